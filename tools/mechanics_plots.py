"""Draw the plots of docs/verification.md into docs/img/ (committed): the mechanics against
the analytic solutions, run through the Python API (the same engine as the Rust tests of
crates/penedge/tests/mechanics.rs, which check the criteria).

* ``mech-slope.png``: a block sliding down three slopes against v1 t + a t^2 / 2;
* ``mech-rotation.png``: free rotation about each principal axis (the intermediate one flips);
* ``mech-contact.png``: the oscillation of a block on a face against 2 pi sqrt(m / (kn A)),
  and the energy of an undamped bounce;
* ``mech-topple.png``: sliding, toppling, stable, and sliding-and-toppling blocks on a 30
  degree slope (rotation and slide), the last against the rigid block.
* ``mech-wedge.png``: a wedge on two planes at its limit-equilibrium friction angle +/- 1;
* ``mech-rocking.png``: the contact force and moment of a block rocking onto its edge and
  back, the contact's changes of type marked;
* ``mech-tension.png``: a bond breaking at T A, a glued slab failing at c A + m g tan phi;
* ``mech-freefall.png``: a thrown block's distance from the parabola.

Run from the repository root, with penedge installed with the ``plot`` extra:

    python3 tools/mechanics_plots.py            # all of them
    python3 tools/mechanics_plots.py topple     # some: slope, rotation, contact, topple, ...
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import matplotlib as mpl

mpl.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import penedge

ROOT = Path(__file__).resolve().parents[1]
IMG = ROOT / "docs" / "img"
G = 9.81


def rot_x(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_z(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def placed(block, matrix):
    return penedge.Block(block.vertices @ matrix.T, block.faces)


def slab_on_slope(theta, size, sink, phi, kn=1e8):
    """A fixed base tilted by `theta` (turned 0.6 rad about z) and a slab on it."""
    frame = rot_z(0.6) @ rot_x(theta)
    lx, ly, h = size
    base = penedge.Block.cuboid([-5, -5, -1], [5, 5, 0])
    slab = penedge.Block.cuboid([-lx / 2, -ly / 2, -sink], [lx / 2, ly / 2, h - sink])
    sim = penedge.Simulation(
        penedge.BlockSystem([placed(base, frame), placed(slab, frame)]), 2500.0
    )
    sim.fix([0])
    sim.set_joint(kn=kn, ks=kn, friction=phi)
    return sim, frame


def slope_plot(ax):
    phi, size = 30.0, (1.0, 0.8, 0.3)
    m, area = 2500 * 0.24, 0.8
    for deg, color in [(33, "C0"), (40, "C1"), (55, "C2")]:
        theta = math.radians(deg)
        sim, frame = slab_on_slope(theta, size, m * G * math.cos(theta) / (1e8 * area), phi)
        down = frame @ np.array([0.0, -1.0, 0.0])
        sim.run_until(0.05)
        before = sim.velocities[1].copy()
        sim.step()
        v1 = ((before + sim.velocities[1]) / 2) @ down
        x1, t1 = sim.positions[1].copy(), sim.time
        ts, xs = [], []
        while sim.time < 0.6:
            sim.step(10)
            ts.append(sim.time - t1)
            xs.append((sim.positions[1] - x1) @ down)
        ts = np.array(ts)
        a = G * (math.sin(theta) - math.cos(theta) * math.tan(math.radians(phi)))
        ax.plot(ts, xs, color=color, lw=2.5, alpha=0.5, label=f"{deg}°, simulated")
        ax.plot(ts, v1 * ts + 0.5 * a * ts**2, "k--", lw=0.8)
    ax.plot([], [], "k--", lw=0.8, label="v₁t + ½g(sinθ − cosθ tanφ)t²")
    ax.set(
        xlabel="t − t₁ (s)",
        ylabel="displacement down the slope (m)",
        title="1. Sliding on slopes steeper than φ = 30°",
    )
    ax.legend(fontsize=8)


def rotation_plot(ax):
    block = penedge.Block.cuboid([0, 0, 0], [1, 2, 3])
    for axis, color in [(0, "C0"), (1, "C1"), (2, "C2")]:
        sim = penedge.Simulation(penedge.BlockSystem([block]), 1000.0)
        sim.set_joint(kn=1e-6, ks=1e-6, friction=30.0)
        sim.gravity = [0.0, 0.0, 0.0]
        spin = np.full(3, 1e-3)
        spin[axis] = 2.0
        q = sim.quaternions[0]
        rotation = quaternion_matrix(q)
        sim.set_velocity(0, [0, 0, 0], rotation @ spin)
        sim.set_timestep(0.005)
        inertia = sim.inertia[0]
        ts, ls = [], []
        for _ in range(800):
            sim.step(10)
            r = quaternion_matrix(sim.quaternions[0])
            body = inertia * (r.T @ sim.spins[0])
            ts.append(sim.time)
            ls.append(body[axis] / np.linalg.norm(body))
        name = ["minor", "intermediate", "major"][axis]
        ax.plot(ts, ls, color=color, label=f"spun about the {name} axis")
    ax.set(
        xlabel="t (s)",
        ylabel="L along the spin axis / |L| (body frame)",
        title="4. Free rotation: the intermediate axis flips",
    )
    ax.legend(fontsize=8)


def quaternion_matrix(q):
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def cube_on_base(drop, kn, gap=1e-3):
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, drop], [0.5, 0.5, 1 + drop])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]), 2500.0, gap=gap)
    sim.fix([0])
    sim.set_joint(kn=kn, ks=kn, friction=30.0)
    return sim


def contact_plots(ax_period, ax_energy):
    kn = 1e8
    period = 2 * math.pi * math.sqrt(2500 / kn)
    sim = cube_on_base(0.0, kn)
    sim.set_timestep(period / 100)
    eq = 0.5 - 2500 * G / kn
    ts, zs = [], []
    while sim.time < 3 * period:
        sim.step()
        ts.append(sim.time / period)
        zs.append((sim.positions[1, 2] - eq) * 1e6)
    ax_period.plot(ts, zs, lw=2.5, alpha=0.5, label="simulated")
    t = np.linspace(0, 3, 300)
    amplitude = 2500 * G / kn * 1e6
    ax_period.plot(
        t,
        amplitude * np.cos(2 * math.pi * t),
        "k--",
        lw=0.8,
        label="δ cos(2π t / T), T = 2π√(m / (kn A))",
    )
    ax_period.set(
        xlabel="t / T",
        ylabel="height − equilibrium (µm)",
        title="5. A block on a face: the contact period",
    )
    ax_period.legend(fontsize=8)

    kn = 1e9
    sim = cube_on_base(0.05, kn, gap=5e-3)
    sim.set_timestep(2 * math.pi * math.sqrt(2500 / kn) / 100)
    e0 = 2500 * G * 0.05
    previous = sim.velocities[1].copy()
    ts, es = [], []
    while sim.time < 0.6:
        z = sim.positions[1, 2] - 0.5
        sim.step()
        v = sim.velocities[1].copy()
        speed = (previous + v) / 2
        previous = v
        overlap = max(-z, 0.0)
        e = 2500 * G * z + 0.5 * 2500 * speed @ speed + 0.5 * kn * overlap**2
        ts.append(sim.time)
        es.append((e - e0) / e0 * 100)
    ax_energy.plot(ts, es)
    ax_energy.set(
        xlabel="t (s)",
        ylabel="energy error (%)",
        title="8. Undamped bounce: total energy",
        ylim=(-1, 1),
    )


def sliding_and_toppling_rigid_block(theta, phi, b, h, ramp, times, dt=1e-5):
    """The rigid block turning by psi about its downhill edge, which slides against mu N
    (the reference of the Rust test, docs/verification.md section 3): the edge's slide and
    psi (radians) at `times`, gravity ramped from 0 to g over `ramp`, by RK4."""
    mu = math.tan(phi)
    inertia = (b * b + h * h) / 12

    def derivative(t, s):
        g = G * min(t / ramp, 1.0)
        psi, w = s[2], s[3]
        rx = -b / 2 * math.cos(psi) + h / 2 * math.sin(psi)
        rz = b / 2 * math.sin(psi) + h / 2 * math.cos(psi)
        arm = rx + mu * rz
        alpha = arm * (g * math.cos(theta) - rz * w * w) / (inertia + rx * arm)
        normal = g * math.cos(theta) - rx * alpha - rz * w * w
        ax = g * math.sin(theta) - mu * normal - rz * alpha + rx * w * w
        return np.array([s[1], ax, s[3], alpha])

    t, s, out = 0.0, np.zeros(4), []
    for end in times:
        while t < end - 1e-12:
            step = min(dt, end - t)
            k1 = derivative(t, s)
            k2 = derivative(t + step / 2, s + step / 2 * k1)
            k3 = derivative(t + step / 2, s + step / 2 * k2)
            k4 = derivative(t + step, s + step * k3)
            s = s + step / 6 * (k1 + 2 * (k2 + k3) + k4)
            t += step
        out.append((s[0], s[2]))
    return np.array(out)


def topple_plot(ax_turn, ax_slide):
    theta = math.radians(30)
    frame = rot_z(0.6) @ rot_x(theta)
    down = frame @ np.array([0.0, -1.0, 0.0])
    for phi, b, label, color in [
        (20, 1.0, "φ = 20°, b/h = 1: slides", "C0"),
        (40, 0.4, "φ = 40°, b/h = 0.4: topples", "C1"),
        (40, 1.0, "φ = 40°, b/h = 1: stays", "C2"),
        (12.5, 0.2, "φ = 12.5°, b/h = 0.2: slides and topples", "C3"),
        (20, 0.4, "φ = 20°, b/h = 0.4 (> tan φ): slides", "C4"),
    ]:
        base = penedge.Block.cuboid([-5, -5, -1], [5, 5, 0])
        block = penedge.Block.cuboid([-0.25, -b / 2, 0], [0.25, b / 2, 1.0])
        sim = penedge.Simulation(
            penedge.BlockSystem([placed(base, frame), placed(block, frame)]), 2500.0
        )
        sim.fix([0])
        sim.set_joint(kn=1e9, ks=1e9, friction=phi)
        q0 = sim.quaternions[1].copy()
        # The downhill bottom edge's midpoint, in the block's frame.
        edge = frame @ np.array([0.0, -b / 2, 0.0])
        local = quaternion_matrix(q0).T @ (edge - sim.positions[1])
        ts, angles, slides = [], [], []
        while sim.time < 0.4:
            sim.gravity = [0, 0, -G * min(sim.time / 0.05, 1.0)]
            sim.step(5)
            ts.append(sim.time)
            angles.append(math.degrees(2 * math.acos(min(abs(q0 @ sim.quaternions[1]), 1.0))))
            moved = sim.positions[1] + quaternion_matrix(sim.quaternions[1]) @ local
            slides.append((moved - edge) @ down)
        # The last block slides as the first: dotted over it.
        style = {"ls": ":", "lw": 2} if b == 0.4 and phi == 20 else {"lw": 2.5, "alpha": 0.5}
        ax_turn.plot(ts, angles, color=color, label=label, **style)
        ax_slide.plot(ts, slides, color=color, label=label, **style)
        if phi == 12.5:
            rigid = sliding_and_toppling_rigid_block(theta, math.radians(phi), b, 1.0, 0.05, ts)
            ax_turn.plot(ts, np.degrees(rigid[:, 1]), "k--", lw=0.8, label="rigid block")
            ax_slide.plot(ts, rigid[:, 0], "k--", lw=0.8, label="rigid block")
    ax_turn.set(xlabel="t (s)", ylabel="rotation (°)", title="3. Blocks on a 30° slope: rotation")
    ax_slide.set(
        xlabel="t (s)",
        ylabel="downhill edge's slide (m)",
        title="3. Blocks on a 30° slope: slide",
    )
    ax_turn.legend(fontsize=7)


def wedge_limit(n1, n2, d):
    """Limit equilibrium of a wedge on two planes (normals n1, n2, out of the rock) sliding
    along their intersection d: W + N1 n1 + N2 n2 - T d = 0 for a unit weight W = (0, 0, -1);
    the critical friction angle atan(T / (N1 + N2)), degrees."""
    normal1, normal2, t = np.linalg.solve(np.column_stack([n1, n2, -d]), [0.0, 0.0, 1.0])
    if min(normal1, normal2, t) <= 0:
        raise ValueError("the wedge does not rest on both planes")
    return math.degrees(math.atan(t / (normal1 + normal2)))


def wedge_sim(n1, n2, d, w, phi):
    """The wedge of the Rust test: two fixed blocks below the planes n_i . x = 0 (boxes of
    half-size 3) and a prism above both, bounded by w . x <= 0.6 and |d . x| <= 0.5."""
    box_normals = [s * a for a in np.eye(3) for s in (1.0, -1.0)]
    blocks = [penedge.Block.from_planes([n, *box_normals], [0.0] + [3.0] * 6) for n in (n1, n2)]
    blocks.append(penedge.Block.from_planes([-n1, -n2, w, d, -d], [0, 0, 0.6, 0.5, 0.5]))
    sim = penedge.Simulation(penedge.BlockSystem(blocks), 2500.0)
    sim.fix([0, 1])
    sim.set_joint(kn=1e9, ks=1e9, friction=phi)
    return sim


def wedge_plot(ax):
    plunge = math.radians(35)
    d = np.array([math.cos(plunge), 0.0, -math.sin(plunge)])  # down the intersection
    w = np.array([math.sin(plunge), 0.0, math.cos(plunge)])  # up, normal to d
    y = np.array([0.0, 1.0, 0.0])
    for (b1, b2), color in [((50, 50), "C0"), ((35, 65), "C1")]:
        b1, b2 = math.radians(b1), math.radians(b2)
        n1 = w * math.cos(b1) + y * math.sin(b1)
        n2 = w * math.cos(b2) - y * math.sin(b2)
        critical = wedge_limit(n1, n2, d)
        for offset, style in [(-1.0, "-"), (1.0, "--")]:
            sim = wedge_sim(n1, n2, d, w, critical + offset)
            start = sim.positions[2].copy()
            ts, slid = [], []
            while sim.time < 0.5:
                sim.gravity = [0, 0, -G * min(sim.time / 0.2, 1.0)]
                sim.step(5)
                ts.append(sim.time)
                slid.append((sim.positions[2] - start) @ d * 1e3)
            label = (
                f"planes at {math.degrees(b1):.0f}° and {math.degrees(b2):.0f}° "
                f"(φc = {critical:.2f}°): φ = φc {offset:+.0f}°"
            )
            # The two geometries give almost the same curves: the first drawn wide.
            width = {"lw": 3, "alpha": 0.4} if color == "C0" else {"lw": 1}
            ax.plot(ts, np.maximum(slid, 1e-3), style, color=color, label=label, **width)
    ax.axvline(0.2, color="gray", lw=0.5)
    ax.set(
        xlabel="t (s; gravity ramped up to 0.2 s)",
        ylabel="slide along the intersection (mm)",
        title="2. A wedge on two planes at its limit-equilibrium φc ± 1°",
        yscale="log",
        ylim=(1e-3, 100),
    )
    ax.legend(fontsize=7)


def sub_contact_moment(sim, body):
    """The contact moment on `body` about its centroid, from the sub-contacts (the forces
    on B of the pair A < B)."""
    c = sim.contacts()
    total = np.zeros(3)
    for i, (a, b) in enumerate(c["pairs"]):
        if body not in (a, b):
            continue
        k = slice(c["sub_offsets"][i], c["sub_offsets"][i + 1])
        force = c["normal_forces"][k, None] * c["normals"][i] + c["shear_forces"][k]
        sign = 1.0 if b == body else -1.0
        total += sign * np.cross(c["points"][k] - sim.positions[body], force).sum(0)
    return total


def rocking_plot(ax, ax_zoom):
    """The block of section 6 rocking onto its downhill edge and back: the total contact
    force and moment, the contact's changes of type marked."""
    names = dict(enumerate(penedge.CONTACT_TYPES, start=1))
    theta, b, h = math.radians(30), 0.8, 1.0
    frame = rot_z(0.6) @ rot_x(theta)
    base = penedge.Block.cuboid([-5, -5, -1], [5, 5, 0])
    block = penedge.Block.cuboid([-0.25, -b / 2, 0], [0.25, b / 2, h])
    sim = penedge.Simulation(
        penedge.BlockSystem([placed(base, frame), placed(block, frame)]), 2500.0
    )
    sim.fix([0])
    sim.set_joint(kn=1e9, ks=1e9, friction=40)
    weight = sim.masses[1] * G
    edge = frame @ np.array([0.0, -b / 2, 0.0])
    spin = frame @ np.array([0.4, 0.0, 0.0])
    ts, forces, moments, switches, shape, kicked = [], [], [], [], None, False
    while sim.time < 0.7:
        sim.gravity = [0, 0, -G * min(sim.time / 0.05, 1.0)]
        if not kicked and sim.time >= 0.1:
            sim.set_velocity(1, np.cross(spin, sim.positions[1] - edge), spin)
            kicked = True
        sim.step()
        c = sim.contacts()
        now = (int(c["types"][0]), int(c["sub_offsets"][1])) if len(c["types"]) else None
        if shape is not None and now is not None and now != shape:
            switches.append(
                (sim.time, f"{names[shape[0]]} ({shape[1]}) → {names[now[0]]} ({now[1]})")
            )
        shape = now
        ts.append(sim.time)
        forces.append(np.linalg.norm(sim.contact_forces[1]) / weight)
        moments.append(np.linalg.norm(sub_contact_moment(sim, 1)) / weight)
    ts, forces, moments = map(np.array, (ts, forces, moments))
    for a in (ax, ax_zoom):
        a.plot(ts, forces, ".-" if a is ax_zoom else "-", ms=3, label="|contact force| / W")
        a.plot(
            ts, moments, ".-" if a is ax_zoom else "-", ms=3, label="|contact moment| / (W × 1 m)"
        )
        for t, _ in switches:
            a.axvline(t, color="gray", ls="--", lw=0.8)
    for t, label in switches:
        ax.annotate(label, (t, 0.5), rotation=90, fontsize=7, ha="right", va="center")
    ax.axvline(0.1, color="C2", lw=0.8)
    ax.annotate("set turning at 0.4 rad/s", (0.1, 0.3), rotation=90, fontsize=7, ha="right")
    ax.set(
        xlabel="t (s)",
        title="6. Rocking onto the downhill edge and back",
        ylim=(0, 1.05 * forces.max()),
    )
    ax.legend(fontsize=7, loc="lower right")
    back = switches[-1][0]
    near = (ts > back - 0.004) & (ts < back + 0.004)
    ax_zoom.set_xlim(back - 0.004, back + 0.004)
    lo = min(forces[near].min(), moments[near].min())
    hi = max(forces[near].max(), moments[near].max())
    ax_zoom.set_ylim(lo - 0.02, hi + 0.02)
    ax_zoom.set(xlabel="t (s)", title="6. Back onto the face: each step (dots)")


def tension_plots(ax_tension, ax_cohesion):
    """Section 7: the bonded hanging block's joint force against the load, to the break at
    T A; the glued slab's failed corners and shear force against the push, to c A + m g tan φ."""
    tension = 1e5
    roof = penedge.Block.cuboid([-2, -2, 0], [2, 2, 1])
    hanging = penedge.Block.cuboid([-0.5, -0.5, -1], [0.5, 0.5, 0])
    sim = penedge.Simulation(penedge.BlockSystem([roof, hanging]), 2500.0)
    sim.fix([0])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0, tension=tension)
    sim.set_damping(local=0.8)
    weight = 2500 * G
    loads, carried = [], []
    while sim.time < 0.25:
        pull = 5e5 * sim.time
        sim.apply_force(1, [0, 0, -pull])
        sim.step()
        c = sim.contacts()
        loads.append(pull + weight)
        # Tension carried by the joint: minus the normal force (compression > 0).
        carried.append(-c["normal_forces"].sum() if len(c["normal_forces"]) else 0.0)
        if len(c["bonded"]) == 0 or not c["bonded"].all():
            broke = pull + weight
            for _ in range(200):
                sim.step()
                c = sim.contacts()
                loads.append(5e5 * sim.time + weight)
                carried.append(-c["normal_forces"].sum() if len(c["normal_forces"]) else 0.0)
            break
    loads, carried = np.array(loads) / 1e3, np.array(carried) / 1e3
    ax_tension.plot(loads, carried, lw=2.5, alpha=0.6, label="joint's tension (simulated)")
    ax_tension.plot(loads, np.minimum(loads, tension / 1e3), "k--", lw=0.8, label="load, up to T A")
    ax_tension.axvline(tension / 1e3, color="gray", lw=0.8)
    note = f"T A = {tension / 1e3:.0f} kN\nbroke at {broke / 1e3:.1f} kN"
    ax_tension.annotate(note, (tension / 1e3, 20), fontsize=8, ha="right")
    ax_tension.set(
        xlabel="load: pull + weight (kN)",
        ylabel="force in the joint (kN)",
        title="7. A hanging block's bond breaks at T A",
    )
    ax_tension.legend(fontsize=7, loc="upper left")

    kn, density, phi, cohesion = 1e9, 25000.0, 15.0, 2e4
    m, area = density * 0.04, 1.0
    sink = m * G / (kn * area)
    base = penedge.Block.cuboid([-3, -3, -1], [3, 3, 0])
    slab = penedge.Block.cuboid([-0.5, -0.5, -sink], [0.5, 0.5, 0.04 - sink])
    sim = penedge.Simulation(penedge.BlockSystem([base, slab]), density)
    sim.fix([0])
    sim.set_joint(kn=kn, ks=kn, friction=phi, cohesion=cohesion)
    sim.set_damping(local=0.8)
    strength = cohesion * area + m * G * math.tan(math.radians(phi))
    push = np.array([0.6, 0.8, 0.0])
    loads, shear, failed = [], [], []
    while sim.time < 0.2:
        load = 2e5 * sim.time
        sim.apply_force(1, push * load)
        sim.step()
        c = sim.contacts()
        loads.append(load)
        shear.append(np.linalg.norm(c["shear_forces"].sum(0)))
        failed.append(int((~c["bonded"]).sum()))
        if load > 1.1 * strength:
            break
    loads, shear = np.array(loads) / 1e3, np.array(shear) / 1e3
    ax_cohesion.plot(loads, shear, lw=2.5, alpha=0.6, label="joint's shear force (simulated)")
    ax_cohesion.axvline(strength / 1e3, color="k", ls="--", lw=0.8, label="c A + m g tan φ")
    friction = m * G * math.tan(math.radians(phi)) / 1e3
    ax_cohesion.axhline(friction, color="k", ls=":", lw=0.8, label="m g tan φ (residual)")
    ax_cohesion.set(
        xlabel="push (kN)",
        ylabel="shear force in the joint (kN)",
        title="7. A glued slab fails at c A + m g tan φ",
    )
    twin = ax_cohesion.twinx()
    twin.plot(loads, failed, color="C3", label="failed corners")
    twin.set_ylabel("failed corners", color="C3")
    twin.set_ylim(-0.2, 4.5)
    ax_cohesion.legend(fontsize=7, loc="upper left")


def free_fall_plot(ax):
    """Section 4: a tilted box thrown with v0, its centroid against x0 + v0 t + g t^2 / 2."""
    c, s = math.cos(0.3), math.sin(0.3)
    tilt = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    block = placed(penedge.Block.cuboid([0, 0, 0], [1, 2, 0.5]), tilt)
    sim = penedge.Simulation(penedge.BlockSystem([block]), 2000.0)
    sim.set_joint(kn=1.0, ks=1.0, friction=30.0)
    sim.set_timestep(1e-3)
    v0 = np.array([1.5, -0.5, 4.0])
    sim.set_velocity(0, v0)
    x0, g = sim.positions[0].copy(), sim.gravity
    ts, errors = [], []
    for _ in range(1000):
        sim.step()
        t = sim.time
        ts.append(t)
        errors.append(np.linalg.norm(sim.positions[0] - (x0 + v0 * t + 0.5 * g * t * t)))
    ax.plot(ts, np.maximum(errors, 1e-17), lw=1)
    ax.axhline(1e-12, color="k", ls="--", lw=0.8, label="the test's bound, 1e-12 m")
    ax.set(
        xlabel="t (s)",
        ylabel="|centroid − (x₀ + v₀t + ½gt²)| (m)",
        title="4. Free fall: distance from the parabola",
        yscale="log",
    )
    ax.legend(fontsize=8)


def draw(name, plot, panels=1):
    """Draws `plot` (a function of its axes) into docs/img/`name`."""
    fig, axes = plt.subplots(1, panels, figsize=(6 if panels == 1 else 11, 4))
    plot(*np.atleast_1d(axes))
    fig.tight_layout()
    fig.savefig(IMG / name, dpi=110)
    plt.close(fig)
    print("wrote", name)


# Each plot: its file, the function drawing it and its number of panels.
PLOTS = {
    "slope": ("mech-slope.png", slope_plot, 1),
    "rotation": ("mech-rotation.png", rotation_plot, 1),
    "contact": ("mech-contact.png", contact_plots, 2),
    "topple": ("mech-topple.png", topple_plot, 2),
    "wedge": ("mech-wedge.png", wedge_plot, 1),
    "rocking": ("mech-rocking.png", rocking_plot, 2),
    "tension": ("mech-tension.png", tension_plots, 2),
    "freefall": ("mech-freefall.png", free_fall_plot, 1),
}


def main(names):
    """Draws the plots named (keys of PLOTS), all of them if none is."""
    unknown = [n for n in names if n not in PLOTS]
    if unknown:
        raise SystemExit(f"unknown plot(s) {unknown}; choose among {list(PLOTS)}")
    IMG.mkdir(parents=True, exist_ok=True)
    for name in names or PLOTS:
        draw(*PLOTS[name])


if __name__ == "__main__":
    main(sys.argv[1:])
