"""Times the Python API's own costs (docs/benchmarks.md, "Python API"):

* ``import``: the time to import ``penedge`` (the extension only), and ``penedge``,
  ``penedge.cli`` and ``penedge.pictures`` (what the command line starts with), each the
  best of `--imports` fresh interpreters, the interpreter's own start left out;
* ``build``: a grid of `--side`^3 unit cubes made into a ``BlockSystem`` two ways: from a
  list of ``Block`` objects (``BlockSystem([Block.cuboid(...) ...])``, one Python object per
  block, the list's own making timed apart) and from flat arrays made with numpy
  (``BlockSystem.from_arrays``, the blocks built in parallel in Rust); then the detection
  of all contacts on one thread and on all, for scale.

Wall-clock seconds (``time.perf_counter``) and CPU seconds of the process, all threads
(``time.process_time``), the median of `--runs` runs (``import``: the best wall-clock).
Run it on a quiet machine after ``pip install -e .`` (a release build)::

    python benches/python/python_api.py               # 100^3 cubes: 10^6 blocks
    python benches/python/python_api.py --side 40     # quicker
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np


def import_seconds(modules: str, runs: int) -> float:
    """The best of `runs` fresh interpreters' time to import `modules`."""
    code = (
        "import time; start = time.perf_counter(); "
        f"import {modules}; "
        "print(time.perf_counter() - start)"
    )
    best = float("inf")
    for _ in range(runs):
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True
        )
        best = min(best, float(out.stdout))
    return best


def grid_arrays(side: int) -> tuple[np.ndarray, ...]:
    """The flat arrays of a side^3 grid of unit cubes (the layout of BlockSystem.arrays)."""
    import penedge

    cube = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    axis = np.arange(side, dtype=float)
    shifts = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    n = len(shifts)
    vertices = (cube.vertices[None] + shifts[:, None]).reshape(-1, 3)
    loops = np.concatenate(cube.faces)
    face_vertices = (loops[None] + 8 * np.arange(n)[:, None]).ravel()
    return (
        vertices,
        np.arange(n + 1) * 8,
        np.arange(n + 1) * 6,
        np.arange(6 * n + 1) * 4,
        face_vertices,
    )


def timed(f, runs: int) -> tuple[tuple[float, float], object]:
    """The median wall-clock and CPU (this process, all threads) times of `runs` calls of
    `f`, and its last result. On a shared machine the CPU time says what the work costs,
    the wall-clock time what a user waits."""
    walls, cpus, result = [], [], None
    for _ in range(runs):
        start, cpu = time.perf_counter(), time.process_time()
        result = f()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    return (statistics.median(walls), statistics.median(cpus)), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=100, help="cubes per side (default 100)")
    parser.add_argument("--runs", type=int, default=3, help="runs of each build (median)")
    parser.add_argument("--imports", type=int, default=7, help="fresh interpreters per import")
    parser.add_argument("--no-detect", action="store_true", help="skip the detection times")
    args = parser.parse_args()

    import penedge

    print(
        f"penedge {penedge.__version__}, Python {platform.python_version()}, "
        f"numpy {np.__version__}, {os.cpu_count()} CPUs, {platform.machine()}"
    )
    print()
    print(f"| import | seconds (best of {args.imports}) |")
    print("|---|---|")
    for modules in ("penedge", "penedge, penedge.cli, penedge.pictures"):
        print(f"| `import {modules}` | {import_seconds(modules, args.imports):.3f} |")
    print()

    side = args.side
    arrays = grid_arrays(side)
    lows = np.stack(
        np.meshgrid(*(np.arange(side, dtype=float),) * 3, indexing="ij"), axis=-1
    ).reshape(-1, 3)
    n = len(lows)
    rows = []
    made, blocks = timed(lambda: [penedge.Block.cuboid(lo, lo + 1) for lo in lows], args.runs)
    rows.append((f"{n:,} `Block.cuboid` objects (the list)", made))
    built, system = timed(lambda: penedge.BlockSystem(blocks), args.runs)
    rows.append(("`BlockSystem(list of Block)`", built))
    rows.append(("list + system: the way through Python objects", tuple(np.add(made, built))))
    flat_time, flat = timed(lambda: penedge.BlockSystem.from_arrays(*arrays), args.runs)
    rows.append(("`BlockSystem.from_arrays` (numpy arrays made beforehand)", flat_time))
    assert len(flat) == len(system) == n
    if not args.no_detect:
        one, found = timed(lambda: flat.detect(threads=1), 1)
        rows.append((f"for scale: `detect(threads=1)`, {len(found):,} contacts", one))
        every, _ = timed(lambda: flat.detect(), 1)
        rows.append((f"for scale: `detect()` on {os.cpu_count()} threads", every))
    print(f"| {side}^3 grid of unit cubes (median of {args.runs}) | wall s | CPU s |")
    print("|---|---|---|")
    for name, (wall, cpu) in rows:
        print(f"| {name} | {wall:.3f} | {cpu:.3f} |")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"\nload average at the end: {load:.2f}")


if __name__ == "__main__":
    main()
