"""``import penedge`` stays light: no matplotlib, no plotly, and well under a second."""

import subprocess
import sys

import pytest


def test_import_does_not_load_plotting_libraries():
    code = (
        "import sys, penedge, penedge.cli, penedge.pictures; "
        "print(sorted(m for m in ('matplotlib', 'plotly') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_version_is_a_string():
    import penedge

    assert isinstance(penedge.__version__, str)
    assert penedge.__version__.count(".") == 2


def import_seconds(modules):
    """The best of three fresh interpreters' time to import `modules` (the interpreter's own
    start left out): the least disturbed by other work on the machine."""
    code = (
        "import time; start = time.perf_counter(); "
        f"import {modules}; "
        "print(time.perf_counter() - start)"
    )
    runs = []
    for _ in range(3):
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True
        )
        runs.append(float(out.stdout))
    return min(runs)


@pytest.mark.parametrize(
    ("modules", "limit"),
    [
        ("penedge", 0.5),  # the package: the extension only (numpy loads on first use)
        ("penedge, penedge.cli, penedge.pictures", 1.0),  # the command's start, with numpy
    ],
)
def test_import_is_fast(modules, limit):
    assert import_seconds(modules) < limit
