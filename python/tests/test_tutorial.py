"""The README's tutorial runs as written, in a scratch folder: each ``console`` block's
commands through the installed ``penedge`` command (their output compared with the README's,
where ``...`` stands for any lines, or any text within a line), each ``python`` block as a
doctest, and each ``toml NAME`` block saved as the file NAME, all in the README's order.
Only the installation (``pip install``) is left out: the tests run on an installed penedge.

At the end the folder holds what the tutorial promises: the paper's Example 3 picture as PNG
and HTML, the rock mass's block and contact files, its pictures and a ParaView time series.
"""

from __future__ import annotations

import doctest
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
SECTION = "## Tutorial"
NOT_RUN = ("pip install",)  # the installation: done before the tests
FENCE = re.compile(r"^```(\w*)(?:[ \t]+(\S+))?[ \t]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)


def tutorial_text():
    if not README.exists():
        pytest.skip("README.md is not next to the tests (an installed package)")
    text = README.read_text(encoding="utf-8")
    start = text.index(SECTION)
    end = text.find("\n## ", start + len(SECTION))
    return text[start : end if end >= 0 else len(text)], text[:start].count("\n")


def blocks():
    """``(language, name, body, line)`` of each fenced block of the tutorial, in order."""
    text, offset = tutorial_text()
    return [
        (m.group(1), m.group(2), m.group(3), offset + text[: m.start()].count("\n") + 1)
        for m in FENCE.finditer(text)
    ]


def console_steps(body):
    """``(command, expected output lines)`` of a console block."""
    steps = []
    for line in body.splitlines():
        if line.startswith("$ "):
            steps.append((line[2:], []))
        else:
            assert steps, f"output before any command: {line!r}"
            steps[-1][1].append(line)
    return steps


def output_pattern(expected):
    """A regex of the expected lines: a line ``...`` is any lines (none included), ``...``
    within a line any text; everything else literal, up to trailing spaces."""
    parts = []
    for line in expected:
        if line == "...":
            parts.append(r"(?:[^\n]*\n)*?")
        else:
            literal = ".*?".join(re.escape(piece) for piece in line.rstrip().split("..."))
            parts.append(literal + r"[ \t]*\n")
    return re.compile("".join(parts))


def penedge_command():
    """The installed ``penedge`` entry point of this Python."""
    beside = Path(sys.executable).with_name("penedge")
    found = str(beside) if beside.exists() else shutil.which("penedge")
    assert found, "the penedge command is not installed (pip install -e '.[test]')"
    return found


def run_console(body, folder, line):
    ran = []
    for command, expected in console_steps(body):
        if command.startswith(NOT_RUN):
            continue
        argv = shlex.split(command)
        assert argv[0] == "penedge", f"README line {line}: not a penedge command: {command}"
        env = {**os.environ, "PYTHONWARNINGS": "error", "COLUMNS": "100"}
        out = subprocess.run(
            [penedge_command(), *argv[1:]],
            cwd=folder,
            capture_output=True,
            text=True,
            env=env,
            timeout=300,
            check=False,
        )
        where = f"README line {line}: {command}"
        assert out.returncode == 0, f"{where}\n{out.stderr}"
        assert out.stderr == "", f"{where}\n{out.stderr}"
        output = "".join(f"{x.rstrip()}\n" for x in out.stdout.splitlines())
        assert output_pattern(expected).fullmatch(output), f"{where}\n{output}"
        ran.append(command)
    return ran


def run_python(body, folder, line, globs):
    parser = doctest.DocTestParser()
    test = parser.get_doctest(body, globs, f"README.md:{line}", str(README), line)
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    cwd = Path.cwd()
    os.chdir(folder)
    try:
        result = runner.run(test, clear_globs=False)
    finally:
        os.chdir(cwd)
    globs.update(test.globs)  # the next block goes on with these names (DocTest copies)
    assert result.failed == 0, f"README line {line}: {result.failed} failed examples"
    return result.attempted


def test_the_output_pattern_is_strict():
    pattern = output_pattern(["a ... b", "...", "end"])
    assert pattern.fullmatch("a x y b\nend\n")
    assert pattern.fullmatch("a  b\n1\n2\nend\n")
    assert not pattern.fullmatch("a x y c\nend\n")
    assert not pattern.fullmatch("a b\nend\nmore\n")
    assert not output_pattern(["total 1"]).fullmatch("total 12\n")


def test_the_readme_starts_with_the_two_commands():
    text = README.read_text(encoding="utf-8")
    first = FENCE.search(text)
    commands = [line.split("#")[0].strip() for line in first.group(3).splitlines()]
    assert commands == [
        "pip install '.[plot,html]' && penedge example 3 --html",
        "bash scripts/test.sh",
    ]
    assert text.index(first.group(0)) < text.index("\n## ")


def test_the_tutorial_runs_as_written(tmp_path):
    folder = tmp_path / "tutorial"
    folder.mkdir()
    globs = {}
    commands, examples, files = [], 0, []
    for language, name, body, line in blocks():
        if language == "console":
            commands += run_console(body, folder, line)
        elif language == "python":
            examples += run_python(body, folder, line, globs)
        elif language == "toml":
            assert name, f"README line {line}: a toml block needs a file name"
            (folder / name).write_text(body, encoding="utf-8")
            files.append(name)
        else:
            pytest.fail(f"README line {line}: a {language or 'plain'} block in the tutorial")
    assert commands == [
        "penedge example 3 --html",
        "penedge generate rock.toml -o blocks.json --vtu blocks.vtu",
        "penedge detect blocks.json -o contacts.csv --vtp contacts.vtp",
        "penedge show blocks.json --contacts --html",
    ]
    assert files == ["rock.toml"]
    assert examples == 14  # the doctest examples of the two python blocks

    for png in ("example3.png", "blocks.png", "rock.png"):
        assert (folder / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png
    for html in ("example3.html", "blocks.html", "rock.html"):
        page = (folder / html).read_text(encoding="utf-8")
        assert re.match(r"\s*(<!doctype html>\s*)?<html", page, re.IGNORECASE), html
        assert "Plotly.newPlot" in page, html
        assert page.rstrip().endswith("</html>"), html
    for name in ("blocks.json", "blocks.vtu", "contacts.csv", "contacts.vtp"):
        assert (folder / name).stat().st_size > 0, name
    assert (folder / "series" / "blocks.pvd").exists()
    assert (folder / "series" / "contacts_000002.vtp").exists()
