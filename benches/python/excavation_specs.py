"""Writes the specs of docs/benchmarks.md, "Excavations of big surfaces": a 10 m box cut by
one vertical joint set into 3 blocks, under an ``n x n`` grid of elevations (``topoN.toml``
with ``topoN.csv``) or a zig-zag slope profile of ``n`` vertices (``zigN.toml``).

    python3 benches/python/excavation_specs.py OUTDIR
    /usr/bin/time -f "%e s %M KB" penedge generate OUTDIR/topo200.toml -o topo200.json -q
"""

import math
import random
import sys
from pathlib import Path

BASE = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 10, 10]

[[joints]]
type = "set"
name = "v"
dip = 90
dip_direction = 90
spacing = 5
origin = [2.5, 0, 0]
"""


def topography(folder: Path, n: int) -> None:
    """A bumpy ground at z = 6-8 over x, y in -1..11, n x n nodes (seeded noise)."""
    noise = random.Random(1)
    lines = ["x,y,z"]
    for i in range(n):
        for j in range(n):
            x, y = -1 + 12 * i / (n - 1), -1 + 12 * j / (n - 1)
            lines.append(f"{x:.6f},{y:.6f},{7 + math.sin(x) + 0.1 * noise.random():.6f}")
    (folder / f"topo{n}.csv").write_text("\n".join(lines) + "\n")
    excavation = f'\n[[excavations]]\ntype = "topography"\nfile = "topo{n}.csv"\n'
    (folder / f"topo{n}.toml").write_text(BASE + excavation)


def zig_zag(folder: Path, n: int) -> None:
    """A slope profile v = 5 + 2 sin(3u), every other vertex 1 cm up: a valley per 2."""
    vertices = []
    for i in range(n):
        u = 10.0 * i / (n - 1)
        v = 5 + 2 * math.sin(3 * u) + (0.01 if i % 2 else 0)
        vertices.append(f"[{u:.9f}, {v:.9f}]")
    excavation = (
        '\n[[excavations]]\ntype = "slope"\norigin = [0, 0, 0]\ntrend = 0\n'
        f"vertices = [{', '.join(vertices)}]\n"
    )
    (folder / f"zig{n}.toml").write_text(BASE + excavation)


def main() -> None:
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    folder.mkdir(parents=True, exist_ok=True)
    for n in (50, 100, 200):
        topography(folder, n)
    for n in (4000, 6000):
        zig_zag(folder, n)


if __name__ == "__main__":
    main()
