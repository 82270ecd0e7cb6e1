"""``penedge generate`` and ``penedge detect`` end to end: files, summaries, exit codes,
outputs that must not be overwritten, --quiet, the progress bar."""

import csv
import functools
import inspect
import io
import json
import re
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import penedge
from penedge import cli
from penedge.cli import generate as generate_command
from penedge.cli import progress
from penedge.cli.progress import ProgressBar

from cli_run import default_sigint, run, squeeze, stop, table_counts

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CUBE = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 10, 10]
"""


def plane(point, dip):
    """A ``[[joints]]`` entry of a plane through `point`, dipping `dip` to the north."""
    return f"""
[[joints]]
type = "plane"
point = {list(point)}
dip = {dip}
dip_direction = 0
"""


BAD_SPEC = CUBE + plane([5, 5, 5], 120)

# Three sets at 1 cm in a 100 m box: 30,000 planes, about 10^12 blocks.
RUNAWAY_SPEC = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [100, 100, 100]
"""
RUNAWAY_SPEC += "".join(
    f"""
[[joints]]
type = "set"
dip = {dip}
dip_direction = {direction}
spacing = 0.01
"""
    for dip, direction in ((0, 0), (90, 0), (90, 90))
)


def test_generate_then_detect(tmp_path):
    spec = EXAMPLES / "paper_example_3.toml"
    made = run(
        "generate",
        spec,
        "-o",
        "blocks.json",
        "--vtu",
        "blocks.vtu",
        "--csv",
        "blocks.csv",
        "--faces-vtu",
        "faces.vtu",
        cwd=tmp_path,
    )
    assert made.returncode == 0, made.stderr
    assert made.stderr == ""
    lines = squeeze(made.stdout)
    assert lines[0].startswith(f"penedge generate {spec}: 26 blocks in")
    assert "block volume V10 20.83, V50 41.67, V90 125 (min 20.83, max 125)" in lines
    assert "partial cuts skipped 0" in lines
    assert "written blocks.json, blocks.vtu, faces.vtu, blocks.csv" in lines
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "blocks.csv",
        "blocks.json",
        "blocks.vtu",
        "faces.vtu",
    ]
    assert len(penedge.BlockSystem.read_json(tmp_path / "blocks.json")) == 26

    found = run(
        "detect", "blocks.json", "-o", "contacts.csv", "--vtp", "contacts.vtp", cwd=tmp_path
    )
    assert found.returncode == 0, found.stderr
    lines = squeeze(found.stdout)
    assert lines[0] == "blocks.json: 26 blocks, 325 contacts (relative gap 1e-12)"
    for row in (
        "1 vertex-vertex 205",
        "4 edge-edge-superposition 78",
        "7 face-face 42",
        "total 325",
        "face-face contact area: 724.264",
    ):
        assert row in lines
    with (tmp_path / "contacts.csv").open(newline="", encoding="utf-8") as f:
        assert len(list(csv.DictReader(f))) == 325
    assert (tmp_path / "contacts.vtp").read_text(encoding="utf-8").startswith("<?xml")


def test_json_summaries(tmp_path):
    made = run("generate", EXAMPLES / "finite_disc.toml", "--json", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    summary = json.loads(made.stdout)
    assert summary["blocks"] == 5
    assert summary["report"]["partial_cuts_by_entry"] == [0, 2]
    assert summary["statistics"]["count"] == 5
    assert summary["written"] == []
    assert list(tmp_path.iterdir()) == []  # nothing asked, nothing written
    penedge.paper_example(1).write_json(tmp_path / "ex1.json")
    found = run("detect", "ex1.json", "--json", "--gap", "1e-6", cwd=tmp_path)
    summary = json.loads(found.stdout)
    assert summary["contacts"] == 28
    assert summary["gap"] == 1e-6
    assert summary["counts"]["face-face"] == 12
    assert summary["face_face_area"] == pytest.approx(300)


def test_summary_names_partial_cuts_and_slivers(tmp_path):
    disc = squeeze(run("generate", EXAMPLES / "finite_disc.toml", cwd=tmp_path).stdout)
    assert "partial cuts skipped 2 (lens 2)" in disc
    slivers = squeeze(run("generate", EXAMPLES / "slivers.toml", cwd=tmp_path).stdout)
    assert any(line.startswith("slivers 4 dropped, volume 0.1") for line in slivers)


def test_quiet_prints_nothing(tmp_path):
    made = run("generate", EXAMPLES / "joint_set_fill.toml", "-o", "b.json", "-q", cwd=tmp_path)
    assert (made.returncode, made.stdout, made.stderr) == (0, "", "")
    found = run("detect", "b.json", "-o", "c.csv", "--quiet", cwd=tmp_path)
    assert (found.returncode, found.stdout, found.stderr) == (0, "", "")
    assert (tmp_path / "c.csv").exists()


def test_a_named_output_is_replaced(tmp_path):
    (tmp_path / "blocks.json").write_text("old", encoding="utf-8")
    made = run("generate", EXAMPLES / "plane_dip.toml", "-o", "blocks.json", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    assert len(penedge.BlockSystem.read_json(tmp_path / "blocks.json")) == 2
    assert [p.name for p in tmp_path.iterdir()] == ["blocks.json"]  # no temporary left


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["generate", "spec.json", "-o", "spec.json"], "is also the input SPEC; refusing"),
        (
            ["generate", "spec.json", "--vtu", "a.vtu", "--faces-vtu", "a.vtu"],
            "is also given to --vtu; refusing",
        ),
        (["detect", "blocks.json", "-o", "c.csv", "--vtp", "c.csv"], "should end in .vtp"),
        (["generate", "spec.json", "-o", "blocks.csv"], "should end in .json"),
        (["generate", "spec.json", "--stats-png", "v.svg"], "should end in .png"),
        (["detect", "blocks.json", "-o", "contacts.json"], "should end in .csv"),
        (["detect", "blocks.json", "-o", "folder.csv"], "is a directory"),
        (["detect", "blocks.json", "--gap", "0.5"], "argument --gap"),
        (["generate"], "the following arguments are required: SPEC"),
        (["detect"], "the following arguments are required: BLOCKS"),
    ],
)
def test_usage_errors_exit_2_and_touch_nothing(args, message, tmp_path):
    spec = tmp_path / "spec.json"
    spec.write_text('{"domain": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}}')
    penedge.paper_example(1).write_json(tmp_path / "blocks.json")
    (tmp_path / "folder.csv").mkdir()
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    result = run(*args, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    assert after == before


def test_an_input_named_through_another_path_is_not_overwritten(tmp_path):
    (tmp_path / "sub").mkdir()
    penedge.paper_example(1).write_json(tmp_path / "blocks.json")
    before = (tmp_path / "blocks.json").read_bytes()
    result = run(
        "generate",
        EXAMPLES / "plane_dip.toml",
        "-o",
        "sub/../blocks.json",
        "--vtu",
        "x.vtu",
        cwd=tmp_path,
    )
    assert result.returncode == 0  # an output, not an input: replaced as asked
    (tmp_path / "spec.toml").write_text((EXAMPLES / "plane_dip.toml").read_text())
    (tmp_path / "link.json").symlink_to(tmp_path / "spec.toml")
    result = run("generate", "spec.toml", "-o", "link.json", cwd=tmp_path)
    assert result.returncode == 2
    assert "refusing to overwrite" in result.stderr
    assert before != (tmp_path / "blocks.json").read_bytes()


@pytest.mark.parametrize(
    ("setup", "args", "message"),
    [
        (
            "bad",
            ["generate", "bad.toml", "-o", "out.json"],
            "penedge: error: bad.toml: joints[0].dip: dip must be between 0 and 90 degrees",
        ),
        (None, ["generate", "none.toml"], "penedge: error: none.toml: No such file or directory"),
        (None, ["detect", "none.json"], "penedge: error: none.json: No such file or directory"),
        (
            "bad",
            ["detect", "bad.toml"],
            "penedge: error: bad.toml: this looks like a joint spec (TOML), not a block file: "
            "run `penedge generate` on it first",
        ),
        (
            "numbers",
            ["detect", "numbers.json"],
            "penedge: error: numbers.json: this is a JSON list, not a block file: a block file "
            'is one JSON object, {"format": "penedge-blocks"',
        ),
        (
            "runaway",
            ["generate", "runaway.toml", "-o", "out.json"],
            "penedge: error: runaway.toml: the spec would make about 1.0e12 blocks",
        ),
        (
            None,
            ["generate", str(EXAMPLES / "plane_dip.toml"), "-o", "no/dir/b.json"],
            "penedge: error: cannot write no/dir/b.json: no directory 'no/dir'",
        ),
    ],
)
def test_runtime_errors_exit_1_without_traceback(setup, args, message, tmp_path):
    if setup == "bad":
        (tmp_path / "bad.toml").write_text(BAD_SPEC, encoding="utf-8")
    if setup == "numbers":
        (tmp_path / "numbers.json").write_text("[1, 2, 3]", encoding="utf-8")
    if setup == "runaway":
        (tmp_path / "runaway.toml").write_text(RUNAWAY_SPEC, encoding="utf-8")
    result = run(*args, cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr.splitlines()[0].startswith(message), result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""
    assert not (tmp_path / "out.json").exists()


def test_penetrating_pairs_are_a_warning(tmp_path):
    system = penedge.BlockSystem(
        [penedge.Block.cuboid([0, 0, 0], [1, 1, 1]), penedge.Block.cuboid([0.5, 0, 0], [2, 1, 1])]
    )
    system.write_json(tmp_path / "overlap.json")
    result = run("detect", "overlap.json", "-o", "c.csv", cwd=tmp_path)
    assert result.returncode == 0
    assert "penedge: warning: 1 pair of blocks overlap deeper than the gap (0-1)" in result.stderr
    assert "penetrating pairs: 1" in result.stdout


def test_stats_png(tmp_path):
    pytest.importorskip("matplotlib")
    from matplotlib.image import imread

    result = run(
        "generate", EXAMPLES / "joint_set_random.toml", "--stats-png", "v.png", cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr
    image = imread(tmp_path / "v.png")
    assert image.shape[0] > 500
    assert image.shape[1] > 800
    assert image[..., :3].std() > 0.05
    assert [p.name for p in tmp_path.iterdir()] == ["v.png"]


def test_example_with_contacts(tmp_path):
    pytest.importorskip("matplotlib")
    result = run("example", "1", "--contacts", "-o", "ex.png", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "ex.png").read_bytes().startswith(b"\x89PNG")
    refused = run("example", "1", "--contacts", "--no-picture", cwd=tmp_path)
    assert refused.returncode == 2
    assert "argument --contacts" in refused.stderr


class FakeClock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def test_progress_bar_waits_then_draws_in_place():
    stream, clock = io.StringIO(), FakeClock()
    bar = ProgressBar(stream, "gen", unit="planes", delay=1.0, clock=clock, width=10)
    bar(1, 4, 2)
    assert stream.getvalue() == ""  # a short run prints nothing
    clock.now = 1.5
    bar(2, 4, 3)
    clock.now = 2.5
    bar(4, 4, 5)
    bar.close()
    assert stream.getvalue() == (
        "\rgen [#####.....]  50%  2/4 planes, 3 blocks, 2 s"
        "\rgen [##########] 100%  4/4 planes, 5 blocks, 2 s\n"
    )


def test_progress_bar_shows_on_a_terminal(monkeypatch, capsys):
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(generate_command, "ProgressBar", functools.partial(ProgressBar, delay=0.0))
    assert cli.main(["generate", str(EXAMPLES / "joint_set_random.toml")]) == 0
    assert "] 100%  15/15 planes, 18 blocks" in terminal.getvalue()
    assert terminal.getvalue().endswith("\n")
    assert "18 blocks" in capsys.readouterr().out
    terminal.truncate(0)
    assert cli.main(["generate", str(EXAMPLES / "joint_set_random.toml"), "-q"]) == 0
    assert terminal.getvalue() == ""


def test_no_block_left_is_an_error_before_anything_is_written(tmp_path):
    (tmp_path / "all.toml").write_text(
        '[domain]\ntype = "box"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n\n'
        '[options]\nmin_volume = 5\nslivers = "drop"\n',
        encoding="utf-8",
    )
    result = run("generate", "all.toml", "-o", "b.json", "--stats-png", "v.png", cwd=tmp_path)
    assert result.returncode == 1
    assert "no blocks left" in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["all.toml"]


def test_progress_bar_counts_without_a_unit_and_wipes_longer_lines():
    stream, clock = io.StringIO(), FakeClock()
    bar = ProgressBar(stream, "d", delay=0.0, clock=clock, width=4)
    bar(10, 100, 12345)
    bar(2, 4)
    bar.close()
    first = "\rd [....]  10%  10/100, 12345 blocks, 0 s"
    second = "\rd [##..]  50%  2/4, 0 s"
    assert stream.getvalue() == first + second + " " * (len(first) - len(second)) + "\n"


def test_activity_shows_elapsed_time_only_for_long_steps():
    slow = io.StringIO()
    with progress.Activity(slow, "drawing x.png", delay=0.0, interval=0.01):
        time.sleep(0.1)
    assert slow.getvalue().startswith("\rdrawing x.png ... 0 s")
    assert slow.getvalue().endswith("\n")
    quick = io.StringIO()
    with progress.Activity(quick, "drawing x.png", delay=5.0):
        pass
    assert quick.getvalue() == ""


def test_activity_without_delay_shows_even_a_step_that_ends_before_its_thread_runs(monkeypatch):
    # With no delay the line is drawn on entering, not left to the thread: a step that
    # ended before the thread was scheduled showed nothing (seen in 3 of 5,000 runs).
    monkeypatch.setattr(progress.Activity, "_run", lambda self: None)  # a thread never run
    stream = io.StringIO()
    with progress.Activity(stream, "penedge detect", delay=0.0):
        pass
    assert stream.getvalue() == "\rpenedge detect ... 0 s\n"


class FakeSystem:
    """A system whose detect takes, or not, a progress callback."""

    def __init__(self, takes_progress):
        self.calls = []
        if takes_progress:
            self.detect = self.detect_with_progress

    def detect(self, gap=1e-12, geometry=False):
        self.calls.append((gap, geometry))
        return "found"

    def detect_with_progress(self, gap=1e-12, geometry=False, progress=None):
        self.calls.append((gap, geometry))
        for done in range(5):
            if progress is not None:
                progress(done + 1, 5)
        return "found"


@pytest.mark.parametrize("takes_progress", [True, False])
def test_detection_shows_a_bar_when_the_bindings_take_a_callback(takes_progress, monkeypatch):
    terminal = io.StringIO()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(progress, "ProgressBar", functools.partial(ProgressBar, delay=0.0))
    monkeypatch.setattr(
        progress, "Activity", functools.partial(progress.Activity, delay=0.0, interval=0.01)
    )
    system = FakeSystem(takes_progress)
    assert progress.accepts_progress(system.detect) == takes_progress
    assert progress.detect(system, True, "penedge detect", gap=1e-6, geometry=True) == "found"
    assert system.calls == [(1e-6, True)]
    if takes_progress:
        assert "\rpenedge detect [" in terminal.getvalue()
        assert "] 100%  5/5, " in terminal.getvalue()
    else:
        assert terminal.getvalue().startswith("\rpenedge detect ... 0 s")
    terminal.truncate(0)
    terminal.seek(0)
    assert progress.detect(system, False, "penedge detect") == "found"
    assert terminal.getvalue() == ""


def test_the_real_bindings_are_asked_whether_they_take_a_callback():
    system = penedge.paper_example(1)
    takes = progress.accepts_progress(system.detect)
    assert takes == ("progress" in inspect.signature(system.detect).parameters)
    assert progress.accepts_progress(len) is False  # no keyword progress


def test_wanted_only_on_a_terminal_and_not_quiet():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    assert progress.wanted(False, Terminal())
    assert not progress.wanted(True, Terminal())
    assert not progress.wanted(False, io.StringIO())


def test_detect_progress_on_a_terminal(monkeypatch, capsys, tmp_path):
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    penedge.paper_example(3).write_json(tmp_path / "b.json")
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(progress, "ProgressBar", functools.partial(ProgressBar, delay=0.0))
    monkeypatch.setattr(
        progress, "Activity", functools.partial(progress.Activity, delay=0.0, interval=0.01)
    )
    assert cli.main(["detect", str(tmp_path / "b.json")]) == 0
    assert "\rpenedge detect" in terminal.getvalue()
    assert terminal.getvalue().endswith("\n")
    assert "total 325" in squeeze(capsys.readouterr().out)
    terminal.truncate(0)
    terminal.seek(0)
    assert cli.main(["detect", str(tmp_path / "b.json"), "--quiet"]) == 0
    assert terminal.getvalue() == ""
    assert capsys.readouterr().out == ""


@pytest.mark.parametrize("spec", ["joint_set_random.toml", "finite_polygon.toml"])
def test_the_summary_table_is_the_apis_count(spec, tmp_path):
    made = run("generate", EXAMPLES / spec, "-o", "b.json", "-q", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    system = penedge.BlockSystem.read_json(tmp_path / "b.json")
    expected = system.detect().counts()
    found = run("detect", "b.json", cwd=tmp_path)
    assert found.returncode == 0, found.stderr
    lines = squeeze(found.stdout)
    assert table_counts(lines) == expected
    assert f"total {sum(expected.values())}" in lines
    assert sum(n > 0 for n in expected.values()) >= 2  # a table with several types


def test_a_runaway_spec_says_how_to_proceed(tmp_path):
    (tmp_path / "runaway.toml").write_text(RUNAWAY_SPEC, encoding="utf-8")
    result = run("generate", "runaway.toml", "-o", "out.json", cwd=tmp_path)
    assert result.returncode == 1
    message = " ".join(result.stderr.split())
    for words in ("about 1.0e12 blocks", "larger spacing", "sub-domain", "--max-blocks"):
        assert words in message
    assert [p.name for p in tmp_path.iterdir()] == ["runaway.toml"]


def test_max_blocks(tmp_path):
    spec = EXAMPLES / "paper_example_3.toml"  # 26 blocks
    result = run("generate", spec, "--max-blocks", "20", "-o", "b.json", cwd=tmp_path)
    assert result.returncode == 1
    assert "the limit is 20 blocks (given)" in " ".join(result.stderr.split())
    assert not (tmp_path / "b.json").exists()
    result = run("generate", spec, "--max-blocks", "26", "-o", "b.json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    for bad in ("0", "-3", "many"):
        result = run("generate", spec, "--max-blocks", bad, cwd=tmp_path)
        assert result.returncode == 2
        assert "argument --max-blocks" in result.stderr


THIN_LAYER = CUBE + plane([0, 0, 5], 0) + plane([0, 0, 5.001], 0)


def test_the_summary_flags_tiny_blocks(tmp_path):
    # Blocks of 500, 0.1 and 499.9 m^3: the 1 mm layer is no sliver (thicker than 1e-6 of
    # the 17.3 m diagonal) but 1/4999 of the median block.
    (tmp_path / "thin.toml").write_text(THIN_LAYER, encoding="utf-8")
    result = run("generate", "thin.toml", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert "slivers none (thinner than 1.73e-05 or smaller than 0)" in lines
    assert "tiny blocks 1 (below 1e-3 of the median volume, 0.4999; smallest 0.1)" in lines


def test_ctrl_c_stops_generate_where_it_is_and_writes_nothing(tmp_path):
    # 100^3 = 10^6 blocks: several seconds. Ctrl-C is sent once the progress bar shows (on
    # a terminal, after 1 s), so it reaches the run, not the start-up. The run stops there
    # and says how far it got (it used to go on to the end, then stop).
    pty = pytest.importorskip("pty")
    import os
    import select
    import signal
    import subprocess

    spec = tmp_path / "million.toml"
    spec.write_text(RUNAWAY_SPEC.replace("spacing = 0.01", "spacing = 1"), encoding="utf-8")
    controller, terminal = pty.openpty()
    process = subprocess.Popen(
        [sys.executable, "-m", "penedge", "generate", "million.toml", "-o", "blocks.json"],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=terminal,
        preexec_fn=default_sigint,
    )
    os.close(terminal)
    seen = b""
    try:
        while b"planes" not in seen:
            ready, _, _ = select.select([controller], [], [], 120)
            assert ready, f"no progress bar: {seen!r}"
            seen += os.read(controller, 4096)
        process.send_signal(signal.SIGINT)
        assert process.wait(timeout=300) == 130
        while select.select([controller], [], [], 1)[0]:
            try:
                chunk = os.read(controller, 4096)
            except OSError:  # the terminal closed with the process
                break
            if not chunk:
                break
            seen += chunk
    finally:
        stop(process)
        os.close(controller)
    text = seen.decode(errors="replace")
    found = re.search(
        r"penedge: interrupted after (\d+) of (\d+) joint planes; nothing written", text
    )
    assert found, text
    done, total = map(int, found.groups())
    assert done < total == 297
    assert [p.name for p in tmp_path.iterdir()] == ["million.toml"]


def test_detect_reads_a_block_file_written_by_hand(tmp_path):
    # Vertices and faces only (docs/block-file-format.md): two unit cubes side by side
    # touch face to face over 1 m^2.
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]

    def cube(x):
        corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
        vertices = [[x + a, b, z] for z in (0, 1) for a, b, _ in corners]
        return {"vertices": vertices, "faces": faces}

    text = json.dumps({"format": "penedge-blocks", "version": 1, "blocks": [cube(0), cube(1)]})
    (tmp_path / "hand.json").write_text(text, encoding="utf-8")
    result = run("detect", "hand.json", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert (summary["blocks"], summary["contacts"]) == (2, 1)
    assert summary["counts"]["face-face"] == 1
    assert summary["face_face_area"] == pytest.approx(1.0)


def test_ctrl_c_while_a_block_file_is_read_stops_at_once(tmp_path):
    # A named pipe that nobody writes to: reading it never ends, as reading a huge block file
    # takes long. Ctrl-C is sent once the command has opened the pipe (it then opens for
    # writing); the command used to take it only after the read.
    import errno
    import os
    import signal
    import subprocess

    if not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes here")
    pipe = tmp_path / "pipe.json"
    os.mkfifo(pipe)
    process = subprocess.Popen(
        [sys.executable, "-m", "penedge", "detect", "pipe.json"],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=default_sigint,
    )
    writer = None
    try:
        deadline = time.monotonic() + 120
        while writer is None:
            try:
                writer = os.open(pipe, os.O_WRONLY | os.O_NONBLOCK)
            except OSError as e:  # ENXIO: no reader yet
                if e.errno != errno.ENXIO:
                    raise
                assert process.poll() is None, process.communicate()
                assert time.monotonic() < deadline, "the command never opened the pipe"
                time.sleep(0.05)
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=60)
    finally:
        stop(process)
        if writer is not None:
            os.close(writer)
    assert process.returncode == 130, err
    assert err.splitlines()[-1] == "penedge: interrupted"
    assert "Traceback" not in err


ALL_GONE = (
    CUBE
    + """
[[joints]]
type = "set"
dip = 0
dip_direction = 0
spacing = 3

[[excavations]]
type = "tunnel"
profile = "circle"
radius = 100
start = [5, -10, 5]
trend = 0
length = 100
"""
)


def test_an_excavation_of_all_the_rock_is_an_error_before_anything_is_written(tmp_path):
    # It was "0 blocks", exit 0 and empty files (with --stats-png: "every block was a sliver").
    (tmp_path / "gone.toml").write_text(ALL_GONE, encoding="utf-8")
    args = ["-o", "b.json", "--vtu", "b.vtu", "--csv", "b.csv", "--stats-png", "v.png"]
    result = run("generate", "gone.toml", *args, cwd=tmp_path)
    assert result.returncode == 1
    assert "excavations[0]: the excavation would remove all of the rock" in result.stderr
    assert "sliver" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gone.toml"]


def test_the_summary_says_its_tiny_blocks_are_those_before_excavation(tmp_path):
    spec = CUBE + plane([5, 5, 5], 0) + plane([5, 5, 5.001], 0)
    spec += """
[[excavations]]
type = "cavern"
center = [5, 5, 8]
trend = 0
length = 100
width = 2
height = 2
"""
    (tmp_path / "thin.toml").write_text(spec, encoding="utf-8")
    result = run("generate", "thin.toml", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    # The three blocks before excavation (500, 0.1, 499.9), not the parts after it.
    want = (
        "tiny blocks 1 (of the blocks before excavation; below 1e-3 of the median volume, "
        "0.4999; smallest 0.1)"
    )
    assert want in lines, lines


def thin_slab(thin, policy):
    """A 10 m box split by the joint y = 5, and an opening that removes y from 2 to
    ``5 - thin`` right through: a slab ``thin`` thick left against the joint."""
    width = 3 - thin
    return (
        CUBE
        + f'\n[options]\nslivers = "{policy}"\n'
        + plane([0, 5, 0], 90)
        + f"""
[[excavations]]
type = "cavern"
center = [5, {2 + width / 2!r}, 5]
trend = 90
length = 20
width = {width!r}
height = 20
"""
    )


@pytest.mark.parametrize("policy", ["keep", "drop"])
def test_the_summary_reports_the_slivers_an_excavation_leaves(tmp_path, policy):
    # The 2e-6 m slab is below the default minimum thickness (1e-6 of the 17.3 m
    # diagonal); the joints' cut alone made no sliver. It was a block of its own, in no
    # report, whatever the policy.
    thin = 2e-6
    (tmp_path / "slab.toml").write_text(thin_slab(thin, policy), encoding="utf-8")
    result = run("generate", "slab.toml", "-o", "b.json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert "slivers none (thinner than 1.73e-05 or smaller than 0)" in lines
    volume = thin * 10 * 10
    assert f"{3 if policy == 'keep' else 2} blocks in" in lines[0]
    system, report = penedge.generate(str(tmp_path / "slab.toml"))
    slivers = report["excavation_slivers"]
    assert slivers["count"] == 1
    assert slivers["volume"] == pytest.approx(volume, rel=1e-6)
    centroids = system.centroids
    ids = np.asarray(system.body_ids)
    on_joint = (centroids[:, 1] > 5 - thin) & (centroids[:, 1] < 5)
    if policy == "keep":
        assert slivers["kept_bodies"] == sorted(set(ids[on_joint].tolist()))
        assert on_joint.sum() == 1
        body = slivers["kept_bodies"][0]
        want = f"excavation slivers 1 kept: blocks {body} (thinner than 1.73e-05"
    else:
        assert slivers["kept_bodies"] == []
        assert not on_joint.any()
        assert float(np.sum(system.volumes)) == pytest.approx(700.0, rel=1e-12)
        want = f"excavation slivers 1 dropped, volume {volume:.3g}"
    assert any(line.startswith(want) for line in lines), lines
