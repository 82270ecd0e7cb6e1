"""The command line end to end, through ``python -m penedge`` and the console script."""

import json
import re
import shutil
import sys
from pathlib import Path

import pytest

from cli_run import assert_png, run, squeeze

COUNTS = {
    1: ["vertex-vertex 4 4", "edge-edge-superposition 12 12", "face-face 12 12", "total 28 28"],
    2: ["vertex-vertex 4 4", "edge-edge-superposition 12 4 *", "face-face 12 20 *", "total 28 28"],
    3: [
        "vertex-vertex 205 205",
        "edge-edge-superposition 78 78",
        "face-face 42 42",
        "total 325 325",
    ],
}
BLOCKS = {1: 8, 2: 8, 3: 26}


def console_script():
    found = shutil.which("penedge", path=str(Path(sys.executable).parent)) or shutil.which(
        "penedge"
    )
    if found is None:
        pytest.skip("the console script `penedge` is not installed (pip install -e .)")
    return [found]


@pytest.mark.parametrize("n", [1, 2, 3])
def test_example_prints_counts_and_writes_png(n, tmp_path):
    result = run("example", str(n), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert f"{BLOCKS[n]} blocks" in result.stdout
    for row in COUNTS[n]:
        assert row in lines
    assert (n == 2) == ("docs/table3.md" in result.stdout)
    assert f"picture: example{n}.png" in lines
    assert_png(tmp_path / f"example{n}.png")
    assert [p.name for p in tmp_path.iterdir()] == [f"example{n}.png"]  # no temporary left


def test_console_script(tmp_path):
    result = run("example", "1", "--no-picture", cwd=tmp_path, command=console_script())
    assert result.returncode == 0, result.stderr
    assert "total 28 28" in squeeze(result.stdout)
    assert list(tmp_path.iterdir()) == []


def test_never_replaces_an_existing_default_picture(tmp_path):
    (tmp_path / "example1.png").write_bytes(b"mine")
    (tmp_path / "example1-1.png").write_bytes(b"mine too")
    result = run("example", "1", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "example1.png").read_bytes() == b"mine"
    assert (tmp_path / "example1-1.png").read_bytes() == b"mine too"
    assert_png(tmp_path / "example1-2.png")
    assert "note: example1.png exists and was kept; wrote example1-2.png instead" in squeeze(
        result.stdout
    )


def test_output_file_named_by_the_user_is_written(tmp_path):
    target = tmp_path / "cube.png"
    target.write_bytes(b"old")
    result = run("example", "3", "-o", str(target), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert_png(target)


@pytest.mark.parametrize(("suffix", "start"), [(".svg", b"<?xml"), (".pdf", b"%PDF")])
def test_other_picture_formats(tmp_path, suffix, start):
    result = run("example", "2", "-o", f"ex{suffix}", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / f"ex{suffix}").read_bytes().startswith(start)


def test_html_view(tmp_path):
    pytest.importorskip("plotly")
    result = run("example", "1", "--html-out", "ex.html", "--no-picture", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "interactive view: ex.html" in squeeze(result.stdout)
    text = (tmp_path / "ex.html").read_text(encoding="utf-8")
    assert "<html>" in text
    assert text.count('"hovertemplate":"block %{customdata[0]}') == 8  # a mesh per block
    assert not re.search(r"<script[^>]+src=", text)  # self-contained: plotly.js inline
    assert [p.name for p in tmp_path.iterdir()] == ["ex.html"]


def test_html_view_at_the_default_name_never_replaces_a_file(tmp_path):
    pytest.importorskip("plotly")
    (tmp_path / "example3.html").write_text("mine", encoding="utf-8")
    result = run("example", "3", "--contacts", "--html", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert "picture: example3.png" in lines
    assert "interactive view: example3-1.html" in lines
    assert "note: example3.html exists and was kept; wrote example3-1.html instead" in lines
    assert (tmp_path / "example3.html").read_text(encoding="utf-8") == "mine"
    text = (tmp_path / "example3-1.html").read_text(encoding="utf-8")
    assert '"name":"face-face (42)"' in text
    assert_png(tmp_path / "example3.png")


def test_force_replaces_files_at_default_names(tmp_path):
    (tmp_path / "example1.png").write_bytes(b"mine")
    result = run("example", "1", "--force", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "picture: example1.png" in squeeze(result.stdout)
    assert_png(tmp_path / "example1.png")
    assert [p.name for p in tmp_path.iterdir()] == ["example1.png"]


def test_quiet_prints_nothing_and_still_writes(tmp_path):
    (tmp_path / "example2.png").write_bytes(b"mine")
    result = run("example", "2", "-q", cwd=tmp_path)
    assert (result.returncode, result.stdout, result.stderr) == (0, "", "")
    assert (tmp_path / "example2.png").read_bytes() == b"mine"
    assert_png(tmp_path / "example2-1.png")


def test_colour_by_volume(tmp_path):
    result = run("example", "3", "--colour-by", "volume", "-o", "v.png", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert_png(tmp_path / "v.png")
    same = run("example", "3", "--color-by", "volume", "-o", "w.png", cwd=tmp_path)
    assert same.returncode == 0, same.stderr
    assert (tmp_path / "v.png").read_bytes() == (tmp_path / "w.png").read_bytes()
    blocks = run("example", "3", "-o", "b.png", cwd=tmp_path)
    assert blocks.returncode == 0, blocks.stderr
    assert (tmp_path / "b.png").read_bytes() != (tmp_path / "v.png").read_bytes()


def test_json(tmp_path):
    result = run("example", "2", "--json", "--no-picture", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["blocks"] == 8
    assert list(data["counts"].values()) == [4, 0, 0, 12, 0, 0, 12]
    assert list(data["paper"].values()) == [4, 0, 0, 4, 0, 0, 20]
    assert data["differs"] == ["edge-edge-superposition", "face-face"]
    assert data["total"] == data["paper_total"] == 28
    assert data["picture"] is None


def test_json_with_picture_keeps_notes_off_stdout(tmp_path):
    (tmp_path / "example1.png").write_bytes(b"mine")
    result = run("example", "1", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["picture"] == "example1-1.png"
    assert "exists and was kept" in result.stderr


def test_gap_option(tmp_path):
    result = run("example", "1", "--gap", "1e-6", "--no-picture", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "relative gap 1e-06" in result.stdout


def test_absolute_gap_option(tmp_path):
    result = run("example", "1", "--absolute-gap", "0.001", "--no-picture", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "absolute gap 0.001" in result.stdout
    result = run("example", "1", "--absolute-gap", "0.001", "--no-picture", "--json", cwd=tmp_path)
    summary = json.loads(result.stdout)
    assert (summary["gap"], summary["absolute_gap"]) == (None, 0.001)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "usage: penedge"),
        (["example"], "the following arguments are required"),
        (["example", "4"], "invalid choice"),
        (["example", "one"], "invalid int value"),
        (["example", "1", "--gap", "-1"], "argument --gap"),
        (["example", "1", "--gap", "nan"], "argument --gap"),
        (["example", "1", "--gap", "abc"], "invalid float value"),
        (["example", "1", "--absolute-gap", "-1"], "argument --absolute-gap"),
        (["example", "1", "--gap", "1e-6", "--absolute-gap", "1e-3"], "not allowed with"),
        (["example", "1", "-o", "x.jpg"], "picture format"),
        (["example", "1", "-o", "x.html"], "use --html-out x.html for the interactive view"),
        (["example", "1", "--html-out", "x.png"], "should end in .html"),
        (["example", "1", "--html", "x.html"], "name the view with --html-out FILE"),
        (["example", "1", "--no-picture", "--contacts"], "argument --contacts"),
        (["example", "1", "--colour-by", "size"], "invalid choice"),
        (["example", "1", "--max-blocks", "-3"], "argument --max-blocks"),
        (["example", "1", "-o", "same.png", "--html-out", "same.png"], "should end in .html"),
        (["example", "1", "-o", "x.png", "--no-picture"], "not allowed with"),
        (["example", "1", "--explode", "-1"], "argument --explode"),
        (["example", "1", "--explode", "inf"], "argument --explode"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_usage_errors_exit_2_without_traceback(args, message, tmp_path):
    result = run(*args, cwd=tmp_path)
    assert result.returncode == 2
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_runtime_error_exits_1_without_traceback(tmp_path):
    result = run("example", "1", "-o", str(tmp_path / "missing" / "x.png"), cwd=tmp_path)
    assert result.returncode == 1
    assert "penedge: error:" in result.stderr
    assert "Traceback" not in result.stderr


def test_output_to_a_directory_is_refused(tmp_path):
    (tmp_path / "pics.png").mkdir()
    result = run("example", "1", "-o", "pics.png", cwd=tmp_path)
    assert result.returncode == 2
    assert "is a directory" in result.stderr


def test_version(tmp_path):
    import penedge

    result = run("--version", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stdout.strip() == f"penedge {penedge.__version__}"


def test_example_without_matplotlib_prints_the_table_and_says_what_the_picture_needs(tmp_path):
    # matplotlib made unimportable (None in sys.modules), as where the `plot` extra is not
    # installed: the table is the result, the default picture a bonus.
    code = (
        "import sys; sys.modules['matplotlib'] = None; "
        "from penedge.cli import main; sys.exit(main(sys.argv[1:]))"
    )
    result = run("example", "1", cwd=tmp_path, command=[sys.executable, "-c", code])
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert "total 28 28" in lines
    assert (
        "note: no picture: it needs matplotlib (pip install 'penedge[plot]'); the table above "
        "is complete"
    ) in lines
    assert list(tmp_path.iterdir()) == []
    # A picture named on the command line is an error still.
    result = run("example", "1", "-o", "x.png", cwd=tmp_path, command=[sys.executable, "-c", code])
    assert result.returncode == 1
    assert "pip install 'penedge[plot]'" in result.stderr
