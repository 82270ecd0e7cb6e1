"""The command line and its outputs when something is wrong: a unit with ``$`` (drawn as
text, not a mathtext traceback), an output that cannot be written (refused before any
work, named as the user gave it, not by its temporary file), a failure after one output is
drawn (no output left behind), an empty output name, an absurd ``--explode``."""

import json
from pathlib import Path

import pytest

import penedge
from penedge.cli import common, main, os_message

from cli_run import assert_png

pytest.importorskip("matplotlib")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
BAD_MATH = "$m^{$"


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """The current folder of the runs, with example 1's blocks (blocks.json) and a spec of
    unit ``$m^{$`` (dollars.toml)."""
    monkeypatch.chdir(tmp_path)
    penedge.paper_example(1).write_json(tmp_path / "blocks.json")
    spec = (EXAMPLES / "paper_example_3.toml").read_text(encoding="utf-8")
    (tmp_path / "dollars.toml").write_text(f'unit = "{BAD_MATH}"\n{spec}', encoding="utf-8")
    return tmp_path


def visible(folder):
    return sorted(p.name for p in folder.iterdir())


@pytest.mark.parametrize("unit", [BAD_MATH, r"$\foo$"])
def test_show_and_example_draw_a_unit_with_dollars(folder, unit, capsys):
    assert main(["show", "blocks.json", "-o", "u.png", "--unit", unit, "-q"]) == 0
    assert_png(folder / "u.png")
    assert main(["example", "1", "-o", "e.png", "--unit", unit, "--explode", "0", "-q"]) == 0
    assert_png(folder / "e.png")
    assert capsys.readouterr().err == ""


def test_a_spec_unit_with_dollars_is_drawn_by_generate_and_show(folder, capsys):
    assert main(["generate", "dollars.toml", "-o", "d.json", "--stats-png", "s.png", "-q"]) == 0
    assert_png(folder / "s.png")
    assert penedge.BlockSystem.read_json(folder / "d.json").unit == BAD_MATH
    assert main(["show", "d.json", "-o", "d.png", "--stats-png", "v.png", "-q"]) == 0
    assert_png(folder / "d.png")
    assert_png(folder / "v.png")
    assert capsys.readouterr().err == ""


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc (no files can be made)")
def test_an_output_that_cannot_be_made_is_refused_before_any_work(folder, capsys):
    before = visible(folder)
    args = ["generate", "dollars.toml", "-o", "ok.json", "--csv", "/proc/x.csv", "-q"]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.startswith("penedge: error: cannot write /proc/x.csv: "), err
    assert ".tmp" not in err
    assert visible(folder) == before  # ok.json not written
    args = ["show", "blocks.json", "-o", "ok.png", "--stats-png", "/proc/x.png", "-q"]
    assert main(args) == 1
    assert capsys.readouterr().err.startswith("penedge: error: cannot write /proc/x.png: ")
    assert visible(folder) == before


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc (no files can be made)")
def test_a_write_that_fails_names_the_target_not_its_temporary_file():
    target = Path("/proc/x.png")
    with pytest.raises(FileNotFoundError) as info:
        common.write_via_temp(target, True, lambda handle: handle.write(b"x"))
    assert info.value.filename == str(target)
    assert os_message(info.value).startswith("/proc/x.png: ")


def test_a_failure_after_one_picture_leaves_no_output(folder, monkeypatch):
    from penedge import pictures

    def broken(*args, **kwargs):
        raise RuntimeError("the volume curve failed")

    monkeypatch.setattr(pictures, "save_volume_distribution", broken)
    before = visible(folder)
    args = ["show", "blocks.json", "-o", "ok.png", "--html-out", "ok.html"]
    with pytest.raises(RuntimeError, match="the volume curve failed"):
        main([*args, "--stats-png", "v.png", "-q"])
    assert visible(folder) == before  # neither ok.png nor ok.html, no temporary file


def test_outputs_are_all_published_together(folder):
    with common.Outputs() as outputs:
        for name in ("a.txt", "b.txt"):
            staged = outputs.staged(common.Target(folder / name, True))
            assert staged.write(lambda handle: handle.write(b"x")) == folder / name
        assert not (folder / "a.txt").exists()
        written = outputs.publish()
    assert written == [folder / "a.txt", folder / "b.txt"]
    assert (folder / "b.txt").read_bytes() == b"x"
    with common.Outputs() as outputs:
        outputs.staged(common.Target(folder / "c.txt", True)).write(lambda h: h.write(b"x"))
    assert "c.txt" not in visible(folder)  # not published: removed
    assert not [name for name in visible(folder) if name.endswith(".tmp")]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["generate", "dollars.toml", "-o", ".json"], "'.json' has no name before .json"),
        (["show", "blocks.json", "-o", ".png"], "'.png' has no name before .png"),
        (["show", "blocks.json", "--stats-png", "out/.png"], "'out/.png' has no name before"),
        (["example", "1", "--explode", "1e300"], "must be a number from 0 to 100"),
    ],
)
def test_bad_output_names_and_explode_factors_are_usage_errors(folder, capsys, args, message):
    before = visible(folder)
    with pytest.raises(SystemExit) as info:
        raise SystemExit(main([*args, "-q"]))
    assert info.value.code == 2
    assert message in capsys.readouterr().err
    assert visible(folder) == before
    if "--explode" in args:  # the largest factor taken is drawn
        assert main(["example", "1", "--explode", "100", "-o", "far.png", "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["picture"] == "far.png"
