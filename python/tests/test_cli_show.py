"""``penedge show BLOCKS`` end to end: the picture, the HTML view and the volume curve of
a block file, the contacts and their table, default names that never replace a file,
--force, --quiet, --json and the exit statuses."""

import json
import re
from pathlib import Path

import pytest

import penedge

from cli_run import assert_png, run, squeeze, table_counts

pytest.importorskip("matplotlib")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture
def blocks(tmp_path):
    """Example 3's blocks as a block file in `tmp_path` (the current folder of the runs)."""
    made = run(
        "generate", EXAMPLES / "paper_example_3.toml", "-o", "blocks.json", "-q", cwd=tmp_path
    )
    assert made.returncode == 0, made.stderr
    return tmp_path / "blocks.json"


def names(folder):
    return sorted(p.name for p in folder.iterdir())


def test_show_draws_the_picture_at_the_default_name(blocks):
    folder = blocks.parent
    result = run("show", "blocks.json", cwd=folder)
    assert result.returncode == 0, result.stderr
    assert squeeze(result.stdout) == ["blocks.json: 26 blocks", "picture: blocks.png"]
    assert result.stderr == ""
    assert_png(folder / "blocks.png")
    assert names(folder) == ["blocks.json", "blocks.png"]


def test_show_with_contacts_prints_the_apis_table_and_draws_them(blocks):
    pytest.importorskip("plotly")
    folder = blocks.parent
    result = run("show", "blocks.json", "--contacts", "--html", cwd=folder)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert lines[0] == "blocks.json: 26 blocks, 325 contacts (relative gap 1e-12)"
    expected = penedge.BlockSystem.read_json(blocks).detect().counts()
    assert table_counts(lines) == expected
    assert "total 325" in lines
    assert lines[-2:] == ["picture: blocks.png", "interactive view: blocks.html"]
    assert_png(folder / "blocks.png")
    text = (folder / "blocks.html").read_text(encoding="utf-8")
    for name, n in expected.items():
        assert (f'"name":"{name} ({n})"' in text) == (n > 0), name
    assert not re.search(r"<script[^>]+src=", text)  # self-contained
    assert names(folder) == ["blocks.html", "blocks.json", "blocks.png"]


def test_default_names_are_never_replaced_but_named_files_and_force_replace(blocks):
    folder = blocks.parent
    (folder / "blocks.png").write_bytes(b"mine")
    kept = run("show", "blocks.json", cwd=folder)
    assert kept.returncode == 0, kept.stderr
    assert squeeze(kept.stdout)[1:] == [
        "picture: blocks-1.png",
        "note: blocks.png exists and was kept; wrote blocks-1.png instead",
    ]
    assert (folder / "blocks.png").read_bytes() == b"mine"
    assert_png(folder / "blocks-1.png")
    forced = run("show", "blocks.json", "--force", cwd=folder)
    assert forced.returncode == 0, forced.stderr
    assert squeeze(forced.stdout)[1:] == ["picture: blocks.png"]
    assert_png(folder / "blocks.png")
    (folder / "mine.png").write_bytes(b"old")
    named = run("show", "blocks.json", "-o", "mine.png", cwd=folder)
    assert named.returncode == 0, named.stderr
    assert_png(folder / "mine.png")
    assert names(folder) == ["blocks-1.png", "blocks.json", "blocks.png", "mine.png"]


def test_html_and_volume_curve_without_the_picture(blocks):
    pytest.importorskip("plotly")
    folder = blocks.parent
    result = run(
        "show",
        "blocks.json",
        "--no-picture",
        "--html-out",
        "v.html",
        "--stats-png",
        "v.png",
        "--colour-by",
        "volume",
        cwd=folder,
    )
    assert result.returncode == 0, result.stderr
    assert squeeze(result.stdout)[1:] == ["interactive view: v.html", "volume distribution: v.png"]
    assert_png(folder / "v.png")
    text = (folder / "v.html").read_text(encoding="utf-8")
    assert '"coloraxis":"coloraxis"' in text
    assert names(folder) == ["blocks.json", "v.html", "v.png"]


def test_quiet_and_json(blocks):
    folder = blocks.parent
    quiet = run("show", "blocks.json", "-q", "--contacts", cwd=folder)
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (0, "", "")
    assert_png(folder / "blocks.png")
    data = run("show", "blocks.json", "--json", "--contacts", "-o", "x.svg", cwd=folder)
    assert data.returncode == 0, data.stderr
    summary = json.loads(data.stdout)
    assert summary["blocks"] == summary["shown_blocks"] == 26
    assert summary["contacts"] == 325
    assert summary["counts"] == penedge.paper_table3(3)
    assert summary["picture"] == "x.svg"
    assert summary["html"] is None
    assert (folder / "x.svg").read_bytes().startswith(b"<?xml")


def test_a_large_system_is_cut_down_and_says_so(blocks):
    folder = blocks.parent
    result = run("show", "blocks.json", "--max-blocks", "10", "-o", "ten.png", cwd=folder)
    assert result.returncode == 0, result.stderr
    assert (
        "note: drew 10 of 26 blocks, those on the outside of the rock mass first "
        "(--max-blocks 0 draws every block)"
    ) in squeeze(result.stdout)
    assert_png(folder / "ten.png")
    every = run("show", "blocks.json", "--max-blocks", "0", "--json", "-o", "all.png", cwd=folder)
    assert json.loads(every.stdout)["shown_blocks"] == 26


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["show"], "the following arguments are required: BLOCKS"),
        (["show", "blocks.json", "-o", "x.html"], "use --html-out x.html for the interactive view"),
        (["show", "blocks.json", "-o", "x.jpg"], "picture format"),
        (["show", "blocks.json", "--html-out", "x.htm"], "should end in .html"),
        (["show", "blocks.json", "--html", "v.html"], "name the view with --html-out FILE"),
        (["show", "blocks.json", "--stats-png", "x.svg"], "should end in .png"),
        (["show", "blocks.json", "--no-picture"], "nothing to draw"),
        (
            ["show", "blocks.json", "--no-picture", "--contacts", "--stats-png", "v.png"],
            "argument --contacts",
        ),
        (["show", "blocks.json", "-o", "a.png", "--no-picture"], "not allowed with"),
        (["show", "blocks.json", "--contacts", "--gap", "0.5"], "argument --gap"),
        (["show", "blocks.json", "--explode", "-0.5"], "argument --explode"),
        (["show", "blocks.json", "--max-blocks", "many"], "argument --max-blocks"),
        (["show", "blocks.json", "--colour-by", "age"], "invalid choice"),
        (
            ["show", "blocks.json", "--html-out", "v.html", "--stats-png", "v.html"],
            "should end in .png",
        ),
    ],
)
def test_usage_errors_exit_2_and_write_nothing(args, message, blocks):
    folder = blocks.parent
    result = run(*args, cwd=folder)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""
    assert names(folder) == ["blocks.json"]


@pytest.mark.parametrize(
    ("setup", "message"),
    [
        ("missing", "penedge: error: none.json: No such file or directory"),
        ("bad", "penedge: error: none.json: this is not a block file (JSON): a block file is one"),
        ("empty", "penedge: error: none.json holds no blocks: nothing to draw"),
    ],
)
def test_runtime_errors_exit_1_and_write_nothing(setup, message, tmp_path):
    if setup == "bad":
        (tmp_path / "none.json").write_text("nonsense", encoding="utf-8")
    elif setup == "empty":
        penedge.BlockSystem([]).write_json(tmp_path / "none.json")
    result = run("show", "none.json", cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr.splitlines()[0].startswith(message), result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""
    assert names(tmp_path) == ([] if setup == "missing" else ["none.json"])
