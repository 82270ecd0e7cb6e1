"""Pictures given text that is not mathtext (a unit, a set name with ``$``), absurd or
impossible ``explode`` factors, contacts of another system, and the caption of a
cut-down system (it overlapped the subtitle)."""

import io
import math

import pytest

import penedge
from penedge import pictures

pytest.importorskip("matplotlib")

# Would not parse as mathtext: matplotlib raised ValueError when drawing it.
BAD_MATH = "$m^{$"

SPEC = {
    "domain": {"type": "box", "min": [0, 0, 0], "max": [4, 4, 4]},
    "joints": [
        {"name": "$J^{$", "type": "set", "dip": 0, "dip_direction": 0, "spacing": 2},
        {"name": "cross", "type": "set", "dip": 90, "dip_direction": 90, "spacing": 2},
    ],
    "unit": BAD_MATH,
}


def drawn(fig):
    """`fig` rendered to PNG (mathtext is parsed when drawn)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return buffer.getvalue()


@pytest.mark.parametrize("explode", [0.0, 0.5])
@pytest.mark.parametrize("color_by", ["set", "volume"])
def test_a_unit_and_set_names_with_dollars_are_drawn_as_they_are(explode, color_by):
    system, _ = penedge.generate(SPEC)
    assert system.unit == BAD_MATH
    fig = pictures.save_picture(
        system, io.BytesIO(), format="png", explode=explode, color_by=color_by
    )
    assert drawn(fig).startswith(b"\x89PNG")
    ax = fig.axes[0]
    if explode == 0:
        assert ax.get_xlabel() == r"x, east (\$m^{\$)"
    else:
        assert r"1 \$m^{\$" in [t.get_text() for t in ax.texts]
    if color_by == "set":
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        assert any(entry.startswith(r"\$J^{\$ (") for entry in legend), legend


def test_the_unit_given_as_an_argument_is_plain_text_too():
    system = penedge.paper_example(1)
    for unit in (BAD_MATH, r"$\foo$"):
        fig = pictures.save_picture(system, io.BytesIO(), format="png", unit=unit, explode=0)
        assert drawn(fig).startswith(b"\x89PNG")


def test_the_volume_distribution_draws_a_unit_with_dollars():
    system, _ = penedge.generate(SPEC)
    fig = pictures.save_volume_distribution(system, io.BytesIO(), format="png")
    assert fig.axes[0].get_xlabel() == r"block volume v (\$m^{\$³)"


@pytest.mark.parametrize("explode", [math.nan, -1.0, math.inf, 1e300, 101.0])
def test_save_picture_refuses_an_impossible_or_absurd_explode(explode):
    with pytest.raises(ValueError, match=r"^explode must be a number from 0 to 100, got "):
        pictures.save_picture(penedge.paper_example(1), io.BytesIO(), format="png", explode=explode)
    with pytest.raises(ValueError, match=r"^explode must be a number from 0 to 100, got "):
        pictures.plot_system(penedge.paper_example(1), explode=explode)
    with pytest.raises(ValueError, match=r"^explode must be a number from 0 to 100, got "):
        pictures.exploded_faces(penedge.paper_example(1), explode=explode)
    # the largest factor taken is drawn
    fig = pictures.save_picture(penedge.paper_example(1), io.BytesIO(), format="png", explode=100)
    assert drawn(fig).startswith(b"\x89PNG")


def test_write_html_refuses_an_impossible_explode():
    pytest.importorskip("plotly")
    for explode in (math.nan, -1.0, 1e300):
        with pytest.raises(ValueError, match=r"^explode must be a number from 0 to 100"):
            pictures.write_html(penedge.paper_example(1), io.StringIO(), explode=explode)


def test_contacts_of_another_system_are_refused_clearly():
    found = penedge.paper_example(3).detect(geometry=True)
    two = penedge.BlockSystem(
        [penedge.Block.cuboid([0, 0, 0], [1, 1, 1]), penedge.Block.cuboid([1, 0, 0], [2, 1, 1])]
    )
    message = r"^contacts: contact \d+ is between blocks \d+ and \d+, but the system has 2 blocks"
    with pytest.raises(ValueError, match=message):
        pictures.save_picture(two, io.BytesIO(), format="png", contacts=found)
    with pytest.raises(ValueError, match=message):
        pictures.plot_system(two, contacts=found)
    pytest.importorskip("plotly")
    with pytest.raises(ValueError, match=message):
        pictures.write_html(two, io.StringIO(), contacts=found)


def test_the_note_of_a_cut_down_system_goes_under_the_picture_once():
    system = penedge.paper_example(1)
    note = "showing 3 of 8 blocks: those on the outside of the rock mass first, then the largest"
    fig = pictures.save_picture(
        system, io.BytesIO(), format="png", subtitle="a caption", max_blocks=3
    )
    assert [t.get_text() for t in fig.texts] == [f"a caption\n{note}"]
    assert not [t for t in fig.axes[0].texts if t.get_text() == note]
    found = system.detect(geometry=True)
    fig = pictures.save_picture(system, io.BytesIO(), format="png", contacts=found, max_blocks=3)
    assert [t.get_text() for t in fig.texts] == [note]
    assert not [t for ax in fig.axes for t in ax.texts if t.get_text() == note]
    # plot_system alone keeps the note in its axes
    ax = pictures.plot_system(system, max_blocks=3)
    assert note in [t.get_text() for t in ax.texts]


def test_the_simulation_pictures_draw_a_title_with_dollars():
    from types import SimpleNamespace

    from penedge.pictures.simulation import save_displacement, save_failing, save_history

    history = SimpleNamespace(
        step=[0, 1, 2],
        ratio=[1.0, 0.1, 0.01],
        kinetic=[1.0, 0.5, 0.2],
        monitors={"$roof^{$": [[0.0] * 6, [0.001] * 6, [0.002] * 6]},
        stage=["start", "s", "s"],
    )
    fig = save_history(history, io.BytesIO(), title=BAD_MATH)
    assert fig.get_suptitle() == r"\$m^{\$"
    system = penedge.paper_example(1)
    fig = save_displacement(system, [[0.0, 0.0, 0.001]] * 8, io.BytesIO(), title=BAD_MATH)
    assert fig.axes[0].get_title() == r"\$m^{\$"
    fig = save_failing(system, [0], io.BytesIO(), title=BAD_MATH)
    assert fig.axes[0].get_title() == r"\$m^{\$"
