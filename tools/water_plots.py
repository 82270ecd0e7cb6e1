"""Draw the water plot of docs/verification.md into docs/img/ (committed): a slab on an
inclined plane under a water table, run through the Python API (the same engine as
crates/penedge/tests/water.rs, which checks the criteria).

* ``mech-water.png``: how far the slab slides in 0.5 s against its friction angle, dry and
  under the water table, with the limit angles of limit equilibrium:
  ``tan(phi) = W sin(theta) / (W cos(theta) - U)``, ``U = gamma_w (h - z_c) A`` (the base is
  all below the table, so the mean pressure is the pressure at its centroid).

Run from the repository root, with penedge installed with the ``plot`` extra:

    python3 tools/water_plots.py
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib as mpl

mpl.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import penedge

ROOT = Path(__file__).resolve().parents[1]
IMG = ROOT / "docs" / "img"
G = 9.81
GAMMA = 9810.0  # unit weight of water, N/m3
THETA = math.radians(25.0)
SIZE = (1.0, 0.8, 1.0)
DENSITY = 3000.0
LEVEL = 0.8  # the water table, m above the base's centroid (all of the base is below)


def frame():
    """The slope: tilted by THETA about x, turned 0.6 rad about z."""
    c, s = math.cos(THETA), math.sin(THETA)
    tilt = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    c, s = math.cos(0.6), math.sin(0.6)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ tilt


def slid(phi, wet):
    """How far the slab moves along the plane in 0.5 s, gravity and water ramped up together
    over 0.3 s (their ratio, hence the limit angle, constant), undamped."""
    f = frame()
    lx, ly, h = SIZE
    base = penedge.Block.cuboid([-5, -5, -1], [5, 5, 0])
    slab = penedge.Block.cuboid([-lx / 2, -ly / 2, 0], [lx / 2, ly / 2, h])
    blocks = [penedge.Block(b.vertices @ f.T, b.faces) for b in (base, slab)]
    sim = penedge.Simulation(penedge.BlockSystem(blocks), DENSITY)
    sim.fix([0])
    sim.set_joint(kn=1e8, ks=1e8, friction=phi)
    start = sim.positions[1].copy()
    while sim.time < 0.5:
        ramp = min(sim.time / 0.3, 1.0)
        sim.gravity = [0.0, 0.0, -G * ramp]
        if wet and ramp > 0:
            sim.set_water(level=LEVEL, unit_weight=GAMMA * ramp)
        sim.step()
    n = f @ np.array([0.0, 0.0, 1.0])
    d = sim.positions[1] - start
    return float(np.linalg.norm(d - n * (d @ n)))


def limit_angles():
    """The limit friction angles (degrees), dry and wet, from limit equilibrium."""
    weight = DENSITY * math.prod(SIZE) * G
    area = SIZE[0] * SIZE[1]
    z_base = 0.0  # the base's centroid is the plane's origin
    uplift = GAMMA * (LEVEL - z_base) * area
    wet = math.atan(weight * math.sin(THETA) / (weight * math.cos(THETA) - uplift))
    return math.degrees(THETA), math.degrees(wet)


def main():
    IMG.mkdir(parents=True, exist_ok=True)
    dry_limit, wet_limit = limit_angles()
    angles = np.arange(20.0, 50.5, 1.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for wet, color, label, limit in [
        (False, "C0", "dry", dry_limit),
        (True, "C1", f"water table {LEVEL} m above the base", wet_limit),
    ]:
        moved = [slid(phi, wet) for phi in angles]
        label = f"{label} (limit {limit:.2f}°)"
        ax.semilogy(angles, moved, "o-", color=color, ms=3, label=label)
        ax.axvline(limit, color=color, ls="--", lw=1)
    ax.set_xlabel("friction angle φ (degrees)")
    ax.set_ylabel("slid in 0.5 s (m)")
    ax.set_title("Slab on a 25° plane: limit equilibrium (dashed) against the engine")
    ax.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(IMG / "mech-water.png", dpi=110)
    print("wrote mech-water.png", f"(limits: dry {dry_limit:.2f}, wet {wet_limit:.2f})")


if __name__ == "__main__":
    main()
