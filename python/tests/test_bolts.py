"""Rock bolts and applied moments through Python (``Simulation.add_bolt``, ``bolts()``,
``apply_moment``, ``apply_force(point=...)``) and in model files (``[[bolts]]``, support
pressures off the centroid). References are formulas computed here."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import penedge
import penedge.model as pm
from penedge.model.engine import Engine, unsupported
from penedge.model.fields import ModelError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
G = 9.81


def hanging_cube(capacity: float = 1e6, rupture_strain: float | None = None):
    """A free 1 m cube 0.1 m under a fixed ceiling, on a bolt from the ceiling's top down
    to the cube's centroid (one 1.5 m element)."""
    ceiling = penedge.Block.cuboid([-1, -1, 1.1], [1, 1, 2])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([ceiling, cube]), density=2500.0)
    sim.fix([0])
    bolt = sim.add_bolt(
        [0, 0, 2], [0, 0, -1], 1.5, stiffness=1e7, capacity=capacity, rupture_strain=rupture_strain
    )
    return sim, bolt


def test_a_hanging_block_stretches_its_bolt_by_w_over_k():
    sim, bolt = hanging_cube()
    assert bolt == 0
    report = sim.solve(ratio=1e-7, max_steps=200_000)
    assert report["converged"]
    weight = 2500.0 * G
    b = sim.bolts()
    assert b["bolt"].tolist() == [0]
    assert b["pairs"].tolist() == [[0, 1]]
    assert b["rest_lengths"][0] == pytest.approx(1.5)
    assert b["forces"][0] == pytest.approx(weight, rel=1e-6)
    assert b["elongations"][0] == pytest.approx(weight / 1e7, rel=1e-6)
    assert b["states"].tolist() == [0]
    assert b["ends"][0] == pytest.approx(sim.positions[1])  # anchored at the centroid
    assert b["starts"][0] == pytest.approx([0, 0, 2])


def test_a_bolt_below_the_weight_yields_and_one_past_its_rupture_strain_breaks():
    weight = 2500.0 * G
    sim, _ = hanging_cube(capacity=0.5 * weight)
    sim.run_until(0.3)
    b = sim.bolts()
    assert b["states"].tolist() == [1]
    assert b["forces"][0] == pytest.approx(0.5 * weight)
    assert sim.positions[1, 2] < 0.5 - 0.1  # falling
    sim, _ = hanging_cube(capacity=0.5 * weight, rupture_strain=0.01)
    sim.run_until(0.3)
    b = sim.bolts()
    assert b["states"].tolist() == [2]
    assert b["forces"][0] == 0.0


def test_bad_bolts_are_refused_with_the_reason():
    sim, _ = hanging_cube()
    with pytest.raises(penedge.MechanicsError, match="outside the rock"):
        sim.add_bolt([5, 5, 0], [0, 0, 1], 1.0, stiffness=1e7, capacity=1e5)
    with pytest.raises(penedge.MechanicsError, match="ties nothing"):
        sim.add_bolt([0, 0, 2], [0, 0, -1], 0.5, stiffness=1e7, capacity=1e5)
    with pytest.raises(penedge.MechanicsError, match="bolt capacity"):
        sim.add_bolt([0, 0, 2], [0, 0, -1], 1.5, stiffness=1e7, capacity=-1.0)


def test_an_applied_moment_and_a_force_at_a_point_turn_a_free_body():
    cube = penedge.Block.cuboid([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5])
    sim = penedge.Simulation(penedge.BlockSystem([cube]), density=10000.0)
    sim.gravity = [0, 0, 0]
    sim.set_timestep(dt=1e-4)
    # A force F at the point p: F / m on the centroid, (p - c) x F / I about it (a cube's
    # principal moments are all m a^2 / 6; the spin is small enough to stay on one axis).
    sim.apply_force(0, [0, 0, 2.0], point=[0.5, 0, 0])
    sim.step(1000)
    t = 999.5e-4  # velocities at the half step: the first kick was a half one
    m, inertia = 10000.0, 10000.0 / 6.0
    assert sim.velocities[0] == pytest.approx([0, 0, 2.0 * t / m], rel=1e-9)
    moment = np.cross([0.5, 0, 0], [0, 0, 2.0])
    assert sim.spins[0] == pytest.approx(moment * t / inertia, rel=1e-9, abs=1e-15)
    sim.apply_moment(0, [0, 0, 0])  # removes it
    with pytest.raises(penedge.MechanicsError):
        sim.apply_moment(3, [1, 0, 0])


def tunnel_text(capacity: float | None) -> str:
    """The tunnel roof example, its bolt with `capacity` (None: no bolt), and a solve with a
    budget that the stable run needs a fraction of."""
    text = (EXAMPLES / "tunnel_roof_bolt.toml").read_text()
    head, bolt = text.split("[[bolts]]")
    bolt, tail = bolt.split("[[monitors]]")
    if capacity is not None:
        bolt = bolt.replace("capacity = 600e3", f"capacity = {capacity}")
        head += "[[bolts]]" + bolt
    return head + "[mechanics]\nmax_steps = 20000\n\n[[monitors]]" + tail


def weight_of_the_wedge() -> float:
    # a pyramid of height 3 on an equilateral triangle of inradius 3 / tan 60
    side = 2 * np.sqrt(3) * 3 / np.tan(np.radians(60))
    return float(np.sqrt(3) / 4 * side**2 * 3 / 3 * 2700 * G)


def solve_tunnel(capacity: float | None) -> tuple[bool, float, list[dict]]:
    """Solves the tunnel model: (converged, the wedge's drop in m, the bolts at the end)."""
    setup = pm.prepare(pm.parse_model(tunnel_text(capacity)))
    engine = Engine(setup)
    wedge = setup.layout.monitors["wedge"]
    z0 = engine.positions()[wedge, 2]
    report = engine.sim.solve(ratio=1e-5, max_steps=20_000)
    return bool(report["converged"]), float(z0 - engine.positions()[wedge, 2]), engine.bolts()


def test_the_tunnel_example_is_no_longer_refused():
    model = pm.read_model(EXAMPLES / "tunnel_roof_bolt.toml")
    assert unsupported(model) == []


def test_the_tunnel_wedge_hangs_on_its_bolt_and_falls_without_it_or_with_a_weak_one():
    weight = weight_of_the_wedge()
    converged, drop, bolts = solve_tunnel(600e3)
    assert converged
    assert bolts[0]["name"] == "crown"
    assert bolts[0]["state"] == "elastic"
    assert bolts[0]["force"] == pytest.approx(weight, rel=1e-3)
    assert drop == pytest.approx(weight / 50e6, rel=0.05)
    for capacity in (None, 250e3):  # no bolt; a bolt below the weight
        converged, drop, bolts = solve_tunnel(capacity)
        assert not converged
        assert drop > 30 * weight / 50e6  # falling out, not hanging
        if capacity is not None:
            assert bolts[0]["state"] == "yielding"


def test_a_bolt_outside_the_rock_is_an_error_naming_its_field():
    text = tunnel_text(600e3).replace(
        "point = [5, 5, 0]         # the collar, on the roof", "point = [50, 5, 0]"
    )
    with pytest.raises(ModelError, match=r"bolts\[0\]\.point: .* outside the rock"):
        pm.prepare(pm.parse_model(text))


def test_a_support_pressure_off_the_centroid_runs_with_its_moment():
    """A pressure on the top face of the Hoek & Bray wedge: that face's centre is not above
    the tetrahedron's centroid, so the resultant has a moment about it. Once refused, the
    model now runs: the pressure pushes the wedge into its joints and it stays."""
    text = (EXAMPLES / "wedge_dry.toml").read_text()
    text = text[: text.index("[[stages]]")]
    text += '[[support]]\nregion = "wedge"\nface = "top"\npressure = 2e4\n'
    text += '[[stages]]\ntype = "solve"\n'
    setup = pm.prepare(pm.parse_model(text))
    wedge = setup.layout.monitors["wedge"]
    assert np.abs(setup.layout.support_moments[wedge]).max() > 1e3  # N m
    outcome = pm.simulate(setup)
    assert outcome.stable
    assert outcome.max_displacement[0] < 0.01


def test_a_dowel_is_both_shear_values_or_neither():
    sim, _ = hanging_cube()
    with pytest.raises(penedge.InputError, match="both shear_stiffness and shear_capacity"):
        sim.add_bolt([0, 0, 2], [0, 0, -1], 1.5, stiffness=1e7, capacity=1e5, shear_stiffness=1e6)
    bolt = sim.add_bolt(
        [0, 0, 2], [0, 0, -1], 1.5, 1e7, 1e5, shear_stiffness=1e6, shear_capacity=1e4
    )
    assert bolt == 1
    assert sim.bolts()["shear_forces"].shape == (2, 3)
    text = tunnel_text(600e3).replace("stiffness = 50e6", "stiffness = 50e6\nshear_stiffness = 1e8")
    with pytest.raises(ModelError, match=r"bolts\[0\]\.shear_capacity: a dowel needs both"):
        pm.parse_model(text)
    model = pm.parse_model(
        text.replace("shear_stiffness = 1e8", "shear_stiffness = 1e8\nshear_capacity = 2e5")
    )
    assert (model.bolts[0].shear_stiffness, model.bolts[0].shear_capacity) == (1e8, 2e5)


def test_a_dowel_holds_a_push_at_push_over_its_stiffness():
    """A cube on a frictionless joint pinned by a bolt with a dowel, pushed sideways at the
    joint's height: it stops at P / k_s (the axial capacity of 1 N leaves the dowel alone)."""
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0)
    sim.fix([0])
    sim.set_joint(kn=1e10, ks=1e9, friction=0.0)
    sim.add_bolt([0, 0, 1], [0, 0, -1], 1.5, 1e7, 1.0, shear_stiffness=1e7, shear_capacity=2e4)
    sim.apply_force(1, [1e4, 0, 0], point=[0, 0, 0])
    assert sim.solve(ratio=1e-7, max_steps=400_000)["converged"]
    assert sim.positions[1, 0] == pytest.approx(1e4 / 1e7, rel=1e-4)
    assert sim.bolts()["shear_forces"][0, 0] == pytest.approx(1e4, rel=1e-5)


def bolted_roof_wedge(capacity_factor: float) -> tuple[str, float]:
    """A model file of a roof wedge (a prism between two joints from the roof z = 0 at
    x = -+a to the apex (0, h)) held by a bolt through its centroid tilted beta = 30 degrees
    towards East, with a capacity `capacity_factor` times the limit-equilibrium force at the
    joints' friction; and the factor of safety by limit equilibrium.

    The bolt presses the wedge onto the East joint (the West one opens); sliding down it is
    resisted when (W + T d).s <= tan(phi) (W + T d).n, n and s the joint's normal and
    downward tangent: T(t) = W (h + a t) / (t (h sin b + a cos b) - a sin b + h cos b) with
    t = tan(phi). Strength reduction divides t by F: at the limit T(t / F) = C, so
    t / F = (W h + C (a sin b - h cos b)) / (C (h sin b + a cos b) - W a).
    """
    a, h, phi, beta, rho = 1.0, 1.5, 30.0, np.radians(30.0), 2500.0
    weight = rho * a * h * 1.0 * G  # the prism: a triangle of area a h, 1 m deep
    t = np.tan(np.radians(phi))
    sb, cb = np.sin(beta), np.cos(beta)
    required = weight * (h + a * t) / (t * (h * sb + a * cb) - a * sb + h * cb)
    c = capacity_factor * required
    t_limit = (weight * h + c * (a * sb - h * cb)) / (c * (h * sb + a * cb) - weight * a)
    dip = np.degrees(np.arctan(h / a))
    joints = "".join(
        f'[[joints]]\ntype = "plane"\nname = "{name}"\npoint = [0, 0.5, {h}]\n'
        f"dip = {dip}\ndip_direction = {direction}\n\n"
        for name, direction in (("East", 90), ("West", 270))
    )
    text = f"""
[domain]
type = "box"
min = [-3, 0, 0]
max = [3, 1, 3]

{joints}
[rock]
density = {rho}

[joint_properties.default]
kn = 1e10
ks = 1e9
friction = {phi}

[regions.wedge]
type = "point"
point = [0, 0.5, 0.3]

[[boundary]]
region = {{type = "all"}}
condition = "fixed"

[[boundary]]
region = "wedge"
condition = "free"

[[bolts]]
point = [{-h / 3 * np.tan(beta)}, 0.5, 0]
direction = [{sb}, 0, {cb}]
length = 2.5
capacity = {c}
stiffness = 5e7

[[stages]]
type = "solve"

[[stages]]
type = "factor_of_safety"
max_steps = 8000
velocity = 2e-5
"""
    return text, float(t / t_limit)


def test_the_factor_of_safety_of_a_bolted_roof_wedge_matches_limit_equilibrium():
    """Strength reduction with a bolt: only the joints are weakened, the bolt keeps its
    capacity (1.2 times the force needed at the joints' friction). Near the limit the wedge
    creeps while the bolt yields (its force a little short of the need, the damped motion
    slow): the stage's `velocity` is lowered to 2e-5 m/s so that such a creep counts as
    failing (with the default 1e-4, F comes out 4 % high; with 2e-5 it does not change when
    the budget is doubled)."""
    text, expected = bolted_roof_wedge(1.2)
    assert 1.5 < expected < 3.0  # the joints' margin, with the bolt as it is
    outcome = pm.simulate(text)
    assert outcome.stages[0].converged
    safety = outcome.safety
    assert safety.factor == pytest.approx(expected, rel=0.02)
    found = np.degrees(np.arctan(np.tan(np.radians(30.0)) / safety.factor))
    exact = np.degrees(np.arctan(np.tan(np.radians(30.0)) / expected))
    assert found == pytest.approx(exact, abs=1.0)  # critical friction, as issue 18 asks
    assert safety.failing - safety.stable <= 0.01 + 1e-12


def test_a_bolt_whose_anchor_rock_is_excavated_is_reported_so_at_the_end():
    """The tunnel roof example with the rock above the wedge excavated after the solve: the
    crown bolt, anchored in that rock, loses its only element (docs/mechanics.md,
    "Excavation"). The run's bolt results said so by raising on the empty element list (no
    summary written); the bolt is now reported as excavated, with no force."""
    text = (EXAMPLES / "tunnel_roof_bolt.toml").read_text()
    text = text[: text.index("[[stages]]")]
    text += '[regions.above]\ntype = "point"\npoint = [5, 5, 4.5]\n\n'
    text += '[[stages]]\ntype = "solve"\n\n'
    text += '[[stages]]\ntype = "excavate"\nregion = "above"\nrelax_steps = 10\n\n'
    text += '[[stages]]\ntype = "cycle"\nsteps = 50\n'
    outcome = pm.simulate(text)
    assert outcome.stages[0].converged
    assert outcome.bolts == [
        {"name": "crown", "force": 0.0, "elongation": 0.0, "state": "excavated"}
    ]
