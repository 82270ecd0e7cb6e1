"""``penedge --help`` and each command's ``--help``: a worked example that is true (the
tests run it and compare its output), the options spelled alike, the exit statuses; and
the exit statuses themselves, Ctrl-C included."""

import shlex
from pathlib import Path

import pytest

import penedge
from penedge import cli

from cli_run import default_sigint, run, squeeze, stop

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
COMMANDS = ["example", "generate", "detect", "show", "simulate"]


def help_text(*args, cwd):
    result = run(*args, "--help", cwd=cwd)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""
    return result.stdout


def worked_example(text):
    """The commands (after ``$``) and the printed lines of the help's worked example."""
    lines = text.split("worked example:\n", 1)[1].splitlines()
    commands, shown = [], []
    for line in lines:
        if line and not line.startswith(" "):  # the next section
            break
        stripped = line.strip()
        if stripped.startswith("$ "):
            commands.append(stripped[2:])
            shown = []
        else:
            shown.append(" ".join(stripped.split()))
    return commands, shown


def varies(line):
    """Lines of a worked example that differ from run to run or platform to platform."""
    return line == "..." or line.endswith(" s") or line.startswith("volume error")


def test_the_top_level_help_lists_every_command_and_the_exit_statuses(tmp_path):
    text = help_text(cwd=tmp_path)
    for command in COMMANDS:
        assert f"\n    {command} " in text, command
    statuses = text.split("exit status:\n", 1)[1].splitlines()
    codes = [
        line.split()[0] for line in statuses if line.startswith("  ") and line.split()[0].isdigit()
    ]
    assert codes == ["0", "1", "2", "130"]
    assert "130  interrupted (Ctrl-C)" in text


@pytest.mark.parametrize("command", COMMANDS)
def test_each_command_spells_the_shared_options_alike(command, tmp_path):
    text = help_text(command, cwd=tmp_path)
    assert f"usage: penedge {command}" in text
    name = "FOLDER" if command == "simulate" else "FILE"
    for option in ("-q, --quiet", "--json"):
        assert option in text, option
    # Python 3.13's argparse names the value once: "-o, --output FILE".
    assert f"-o {name}, --output {name}" in text or f"-o, --output {name}" in text
    drawing = command in ("example", "show")
    for option in ("--force", "--colour-by {set,block,volume}", "--unit U", "--explode F"):
        assert (option in text) == drawing, option
    # The most blocks drawn (example, show) or made (generate).
    assert ("--max-blocks N" in text) == (command not in ("detect", "simulate"))
    assert ("--gap G" in text) == (command not in ("generate", "simulate"))


@pytest.mark.parametrize("args", [[], *([c] for c in COMMANDS)])
def test_every_worked_example_in_the_help_is_what_penedge_prints(args, tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("plotly")
    commands, shown = worked_example(help_text(*args, cwd=tmp_path))
    assert commands, "no worked example"
    assert all(c.startswith("penedge ") for c in commands)
    (tmp_path / "examples").symlink_to(EXAMPLES)
    for command in commands:
        result = run(*shlex.split(command)[1:], cwd=tmp_path)
        assert result.returncode == 0, (command, result.stderr)
    printed = squeeze(result.stdout)
    matched = [bool(line) and line in printed for line in shown]
    last = max(k for k, hit in enumerate(matched) if hit)  # then prose about the output
    missing = [
        line
        for line, hit in zip(shown[:last], matched[:last], strict=True)
        if not hit and line and not varies(line)
    ]
    assert missing == [], f"{commands[-1]} does not print: {missing}"
    assert sum(matched) >= 5


def test_no_command_is_a_usage_error(tmp_path):
    result = run(cwd=tmp_path)
    assert result.returncode == 2
    assert "usage: penedge" in result.stderr
    assert result.stdout == ""


def test_ctrl_c_exits_130_with_a_word_and_no_traceback(monkeypatch, capsys, tmp_path):
    def interrupted(n):
        raise KeyboardInterrupt

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(penedge, "paper_example", interrupted)
    assert cli.main(["example", "1"]) == 130
    out, err = capsys.readouterr()
    assert out == ""
    assert err == "\npenedge: interrupted\n"
    assert list(tmp_path.iterdir()) == []


def test_out_of_memory_is_an_error_with_advice_and_leaves_no_file(monkeypatch, capsys, tmp_path):
    # The HTML view of a million contacts ran out of memory in plotly with a traceback.
    pytest.importorskip("plotly")
    import plotly.graph_objects as go

    def too_large(self, *args, **kwargs):
        raise MemoryError

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(go.Figure, "write_html", too_large)
    assert cli.main(["example", "1", "--html"]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert err.startswith("penedge: error: out of memory: penedge example needs more memory")
    assert "--max-blocks" in err
    assert not list(tmp_path.glob("*.html"))


def test_a_signal_before_the_command_runs_exits_130_without_a_traceback(monkeypatch, capsys):
    def interrupted():
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", interrupted)
    assert cli.main(["example", "1"]) == 130
    assert capsys.readouterr().err == "\npenedge: interrupted\n"


def test_a_signal_during_a_run_exits_130_and_leaves_no_temporary_file(tmp_path):
    import os
    import signal
    import subprocess
    import sys
    import time

    # A run long enough to be interrupted: the 10^5 blocks of three_joint_sets, written.
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "penedge",
            "generate",
            str(EXAMPLES / "three_joint_sets.toml"),
            "-o",
            "blocks.json",
        ],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=default_sigint,
    )
    # The signal once the child has run 0.8 s of CPU (its imports take about 0.3): during the
    # cutting, whatever the load on the machine (a fixed wall-clock wait came, on a loaded
    # machine, as the run ended, and on a quiet one after it).
    ticks = os.sysconf("SC_CLK_TCK")
    started = time.monotonic()
    try:
        while process.poll() is None and time.monotonic() - started < 60:
            fields = Path(f"/proc/{process.pid}/stat").read_text().rsplit(")", 1)[1].split()
            if (int(fields[11]) + int(fields[12])) / ticks >= 0.8:
                break
            time.sleep(0.01)
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=120)
    finally:
        stop(process)
    if process.returncode == 0:
        pytest.skip("the run ended before the signal came (a very fast machine)")
    assert process.returncode == 130, err
    # "interrupted", and during the cutting "interrupted after k of N joint planes; ..."
    assert err.splitlines()[-1].startswith("penedge: interrupted")
    assert "Traceback" not in err
    left = [p.name for p in tmp_path.iterdir()]
    assert [name for name in left if name != "blocks.json"] == []  # no temporary file
    if left:  # the signal came after the file was written: it is whole, never half
        assert len(penedge.BlockSystem.read_json(tmp_path / "blocks.json")) > 10**5


@pytest.mark.parametrize("command", ["example", "show"])
def test_html_takes_no_file_name_so_the_block_file_is_never_taken_for_it(command):
    first = "3" if command == "example" else "blocks.json"
    parse = cli.build_parser().parse_args
    # The bug: `penedge show --html blocks.json` took blocks.json for the HTML file.
    args = parse([command, "--html", first])
    assert (args.html, args.html_out) == (True, None)
    assert str(args.number if command == "example" else args.blocks) == first
    args = parse([command, first, "--html-out", "view.html"])
    assert (args.html, args.html_out) == (False, "view.html")
    args = parse([command, "--html-out", "view.html", first, "--html"])
    assert (args.html, args.html_out) == (True, "view.html")
