"""``import penedge`` stays light: no matplotlib, no plotly. How long it takes is measured by
benches/python/python_api.py (docs/benchmarks.md), not asserted here: a wall-clock limit
fails on a busy machine and says nothing on a fast one."""

import subprocess
import sys


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
