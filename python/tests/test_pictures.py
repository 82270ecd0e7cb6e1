"""Pictures: the exploded view (matplotlib, headless) and the HTML view (plotly)."""

import io

import numpy as np
import pytest

import penedge
from penedge import pictures

import shapes

pytest.importorskip("matplotlib")


def test_exploded_faces_move_blocks_away_from_the_centre():
    system = penedge.paper_example(1)
    parts = pictures.exploded_faces(system, explode=0.5)
    assert len(parts) == 8
    for block, (faces, normals, offset) in zip(system.blocks, parts, strict=True):
        assert np.allclose(offset, 0.5 * (block.centroid - [5, 5, 5]))
        assert len(faces) == len(block.faces) == len(normals)
        assert np.allclose(faces[0], block.vertices[block.faces[0]] + offset)
    still = pictures.exploded_faces(system, explode=0.0)
    assert all(np.allclose(offset, 0) for _, _, offset in still)


def test_block_colors_are_distinct():
    colors = pictures.block_colors(26)
    assert colors.shape == (26, 3)
    assert ((colors >= 0) & (colors <= 1)).all()
    assert len({tuple(np.round(c, 3)) for c in colors}) == 26


def test_plot_system_draws_one_collection_per_block():
    ax = pictures.plot_system(penedge.paper_example(3), title="Example 3")
    assert len(ax.collections) == 26
    assert ax.get_title() == "Example 3"


def test_plot_accepts_a_list_of_blocks_and_colours():
    ax = pictures.plot_system([shapes.cube()], colors=["red"], labels=True)
    assert len(ax.collections) == 1
    assert len(ax.texts) == 1


def test_save_picture_png_to_a_file_object():
    buffer = io.BytesIO()
    pictures.save_picture(penedge.paper_example(2), buffer, format="png", title="Example 2")
    assert buffer.getvalue().startswith(b"\x89PNG\r\n\x1a\n")


def test_save_picture_to_a_path(tmp_path):
    path = tmp_path / "ex.svg"
    pictures.save_picture(penedge.paper_example(1), path)
    assert path.read_text(encoding="utf-8").lstrip().startswith("<?xml")


def test_empty_system_draws_nothing():
    ax = pictures.plot_system(penedge.BlockSystem([]))
    assert len(ax.collections) == 0


def test_write_html(tmp_path):
    pytest.importorskip("plotly")
    path = tmp_path / "ex.html"
    pictures.write_html(penedge.paper_example(1), path, title="Example 1", include_plotlyjs="cdn")
    text = path.read_text(encoding="utf-8")
    assert "Example 1" in text
    assert text.count('"name":"block ') == 8


def test_contact_shapes_group_the_contacts_and_follow_the_blocks():
    system = penedge.paper_example(3)
    found = system.detect(geometry=True)
    points, segments, polygons, kinds = pictures.contact_shapes(found)
    assert points.shape == (205, 3)
    assert segments.shape == (78, 2, 3)
    assert len(polygons) == 42
    assert all(p.shape[1] == 3 and len(p) >= 3 for p in polygons)
    assert np.bincount(kinds).tolist() == [0, 205, 78, 42]
    offsets = np.zeros((len(system), 3))
    offsets[:, 2] = np.arange(len(system))  # block i moved up by i
    moved, _, _, _ = pictures.contact_shapes(found, block_offsets=offsets)
    a, b = found.pairs[found.types == 1][0]
    assert moved[0] - points[0] == pytest.approx([0, 0, (a + b) / 2])


def test_contact_shapes_need_the_geometry():
    with pytest.raises(ValueError, match="geometry=True"):
        pictures.contact_shapes(penedge.paper_example(1).detect())


def test_plot_system_with_contacts_draws_them_over_faint_blocks():
    system = penedge.paper_example(1)
    ax = pictures.plot_system(system, contacts=system.detect(geometry=True))
    # 8 blocks, then face-face polygons, edge-edge superposition lines, vertex-vertex dots
    assert len(ax.collections) == 8 + 3
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == [
        "vertex-vertex (4)",
        "edge-edge-superposition (12)",
        "face-face (12)",
    ]
    assert ax.collections[0].get_facecolor()[:, 3].max() < 0.2


def test_save_picture_with_contacts_has_two_panels():
    system = penedge.paper_example(2)
    figure = pictures.save_picture(
        system,
        io.BytesIO(),
        format="png",
        title="Example 2",
        contacts=system.detect(geometry=True),
    )
    assert len(figure.axes) == 2
    assert figure.get_suptitle() == "Example 2"


def test_volume_distribution_marks_v10_v50_v90():
    system = penedge.paper_example(3)
    ax = pictures.plot_volume_distribution(system)
    assert ax.get_xscale() == "log"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[2:] == ["V10 = 20.83", "V50 = 41.67", "V90 = 125"]
    stats = system.statistics()
    assert [pictures.passing_volume(system.volumes, x) for x in (10, 50, 90)] == [
        stats["v10"],
        stats["v50"],
        stats["v90"],
    ]


def test_volume_distribution_leaves_out_tiny_slivers_and_says_so():
    volumes = np.concatenate([np.full(100, 10.0), [1e-12, 1e-9]])
    ax = pictures.plot_volume_distribution(volumes)
    assert ax.get_xlim()[0] > 1e-3
    notes = [t.get_text() for t in ax.texts]
    assert len(notes) == 1
    assert notes[0].startswith("not shown: 2 smaller blocks, down to v = 1e-12")


def test_volume_distribution_of_equal_blocks_and_of_none():
    ax = pictures.plot_volume_distribution(np.full(8, 125.0))
    lo, hi = ax.get_xlim()
    assert lo < 125 < hi
    assert hi / lo > 5
    with pytest.raises(ValueError, match="no blocks"):
        pictures.plot_volume_distribution(penedge.BlockSystem([]))


def test_save_volume_distribution_png():
    buffer = io.BytesIO()
    figure = pictures.save_volume_distribution(penedge.paper_example(2), buffer, format="png")
    assert buffer.getvalue().startswith(b"\x89PNG\r\n\x1a\n")
    assert figure.axes[0].get_title() == "Block volume distribution: 8 blocks"
