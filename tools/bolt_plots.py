"""Draw the rock-bolt plot of docs/verification.md ("Rock bolts and applied moments") into
docs/img/mech-bolts.png (committed), through the Python API (the same engine as the Rust
tests of crates/penedge/tests/bolts.rs, which check the criteria):

* left: a cube hanging from a bolt whose capacity is half its weight, undamped: its drop
  against the elastic-then-yielding formula, and the bolt force;
* right: the roof wedge held by a bolt tilted 30 degrees, with capacities around the
  limit-equilibrium force: the wedge's displacement while solving.

Run from the repository root, with penedge installed with the ``plot`` extra:

    python3 tools/bolt_plots.py
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
DENSITY = 2500.0


def yielding_fall(ax):
    k, m = 1e7, DENSITY
    weight = m * G
    capacity = 0.5 * weight
    ceiling = penedge.Block.cuboid([-1, -1, 1.1], [1, 1, 2])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([ceiling, cube]), density=DENSITY)
    sim.fix([0])
    sim.add_bolt([0, 0, 2], [0, 0, -1], 1.5, stiffness=k, capacity=capacity)
    times, drops, forces = [], [], []
    while sim.time < 0.3:
        sim.step(20)
        times.append(sim.time)
        drops.append(0.5 - sim.positions[1, 2])
        forces.append(sim.bolts()["forces"][0])
    omega = math.sqrt(k / m)
    t_y = math.acos(1 - capacity / weight) / omega
    v_y = weight / k * omega * math.sin(omega * t_y)
    a = (weight - capacity) / m
    t = np.array(times)
    formula = np.where(
        t < t_y,
        weight / k * (1 - np.cos(omega * t)),
        capacity / k + v_y * (t - t_y) + 0.5 * a * (t - t_y) ** 2,
    )
    ax.plot(t, np.array(drops) * 1e3, "o", ms=3, label="penedge")
    ax.plot(t, formula * 1e3, "k-", lw=1, label="formula")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("drop (mm)")
    ax.set_title("Bolt of capacity W/2: yields, the cube falls")
    twin = ax.twinx()
    twin.plot(t, np.array(forces) / weight, "C1-", lw=1)
    twin.set_ylabel("bolt force / W", color="C1")
    twin.set_ylim(0, 1)
    ax.legend(loc="upper left")


def roof_wedge(factor):
    a, h, depth, big, top = 1.0, 1.5, 1.0, 3.0, 3.0

    def prism(xz):
        return penedge.Block.from_hull([[x, y, z] for y in (0.0, depth) for x, z in xz])

    wedge = prism([(-a, 0), (a, 0), (0, h)])
    right = prism([(a, 0), (big, 0), (big, top), (0, top), (0, h)])
    left = prism([(-a, 0), (-big, 0), (-big, top), (0, top), (0, h)])
    sim = penedge.Simulation(penedge.BlockSystem([left, right, wedge]), density=DENSITY)
    sim.fix([0, 1])
    phi, beta = 30.0, math.radians(30)
    sim.set_joint(kn=1e10, ks=1e9, friction=phi)
    weight = DENSITY * a * h * depth * G
    tan = math.tan(math.radians(phi))
    sb, cb = math.sin(beta), math.cos(beta)
    required = weight * (h + a * tan) / (tan * (h * sb + a * cb) - a * sb + h * cb)
    collar = [-h / 3 * math.tan(beta), depth / 2, 0.0]
    sim.add_bolt(collar, [sb, 0, cb], 2.5, stiffness=5e7, capacity=factor * required)
    return sim


def wedge_bracket(ax):
    for factor in (0.95, 0.98, 1.02, 1.05):
        sim = roof_wedge(factor)
        start = sim.positions[2].copy()
        steps, moved = [0], [0.0]
        sim.set_damping(local=0.8)
        for _ in range(100):
            sim.step(200)
            steps.append(sim.steps)
            moved.append(float(np.linalg.norm(sim.positions[2] - start)))
        ax.semilogy(steps, np.maximum(moved, 1e-6) * 1e3, label=f"capacity {factor:.2f} T")
    ax.set_xlabel("steps (local damping 0.8)")
    ax.set_ylabel("wedge displacement (mm)")
    ax.set_title("Roof wedge, bolt tilted 30°: T from limit equilibrium")
    ax.legend()


def main():
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5))
    yielding_fall(left)
    wedge_bracket(right)
    fig.tight_layout()
    fig.savefig(IMG / "mech-bolts.png", dpi=110)
    print("wrote", IMG / "mech-bolts.png")


if __name__ == "__main__":
    main()
