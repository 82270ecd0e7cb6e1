"""Rock bridges (docs/generation.md, docs/mechanics.md and docs/models.md, "Rock bridges"):
the faces a finite joint with ``bridge = true`` leaves uncut, the bridge properties of the
engine and of model files, and the step-path example against limit equilibrium computed
here."""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import penedge
import penedge.model as pm
from penedge.model.check import Blocks

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
BRIDGE = 3  # face origin code
STEP_BRIDGE = "[joint_properties.step.bridge]\nfriction = 50\ncohesion = 1e6\n"

needs_engine = pytest.mark.skipif(
    not hasattr(penedge, "Simulation"), reason="this build has no mechanics engine"
)

SPEC = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 10, 10]

[[joints]]
type = "polygon"
name = "step"
vertices = [[2, 2, 5], [8, 2, 5], [8, 8, 5], [2, 8, 5]]
"""


def plane_area(system, code, normal):
    """The area of the faces of origin `code` with outward unit normal `normal`."""
    b = Blocks.of(system)
    on = b.face_normals @ np.asarray(normal) > 1 - 1e-9
    return float(b.face_areas[(b.face_kind == code) & on].sum())


def generated(text):
    system, _ = penedge.generate(tomllib.loads(text))
    return system


def test_the_report_counts_bridged_cuts_apart_from_partial_cuts():
    _, plain = penedge.generate(tomllib.loads(SPEC))
    assert (plain["partial_cuts_skipped"], plain["bridged_cuts"]) == (1, 0)
    _, bridged = penedge.generate(tomllib.loads(SPEC + "bridge = true\n"))
    assert (bridged["partial_cuts_skipped"], bridged["bridged_cuts"]) == (0, 1)


def test_a_square_joint_with_bridges_leaves_the_rest_of_the_plane_as_bridge():
    assert len(generated(SPEC)) == 1  # the joint ends inside the box: left whole
    system = generated(SPEC + "bridge = true\n")
    # 100 m2 of plane in the box, 36 m2 of joint: below the plane, pieces split by the
    # seams (top faces wholly joint or bridge); above it, one piece
    assert plane_area(system, 2, [0, 0, 1]) == pytest.approx(36.0, rel=1e-12)
    assert plane_area(system, BRIDGE, [0, 0, 1]) == pytest.approx(64.0, rel=1e-12)
    assert plane_area(system, 2, [0, 0, -1]) == pytest.approx(100.0, rel=1e-12)
    assert len(system) == 6
    assert Blocks.of(system).volumes.sum() == pytest.approx(1000.0, rel=1e-12)


@needs_engine
def test_simulation_bridge_properties():
    system = generated(SPEC + "bridge = true\n")
    sim = penedge.Simulation(system, density=2600.0)
    sim.set_joint(kn=1e9, ks=1e8, friction=30.0)
    # without its own: the joint's stiffness, a strong rock's strength
    assert sim.bridge(0) == {
        "kn": 1e9,
        "ks": 1e8,
        "friction": 45.0,
        "cohesion": 10e6,
        "tension": 5e6,
        # after failure: friction kept, cohesion lost (the joint law's defaults)
        "residual_friction": 45.0,
        "residual_cohesion": 0.0,
    }
    sim.set_bridge(kn=2e9, ks=2e8, friction=50.0, cohesion=1e6, tension=5e5, set=0)
    assert sim.bridge(0)["cohesion"] == 1e6
    assert sim.bridge(0)["residual_friction"] == 50.0
    sim.set_bridge(
        kn=2e9, ks=2e8, friction=50.0, cohesion=1e6, tension=5e5, set=0, residual_friction=35.0
    )
    assert sim.bridge(0)["residual_friction"] == 35.0
    with pytest.raises(penedge.MechanicsError, match="friction"):
        sim.set_bridge(kn=2e9, ks=2e8, friction=95.0, cohesion=1e6, tension=5e5)
    sim.fix(np.flatnonzero(Blocks.of(system).centroids[:, 2] < 5).tolist())
    sim.step(1)
    contacts = sim.contacts()
    assert contacts["bridges"].any()  # the bridge faces...
    assert not contacts["bridges"].all()  # ...and the joint's


MODEL = (
    SPEC
    + """
[rock]
density = 2600

[joint_properties.default]
kn = 1e9
ks = 1e8
friction = 30

[[boundary]]
region = {type = "face", face = "bottom"}
condition = "fixed"
"""
)


def test_model_file_bridge_table():
    bridged = MODEL.replace('name = "step"', 'name = "step"\nbridge = true')
    m = pm.parse_model(bridged + STEP_BRIDGE + "tension = 2e5\n")
    b = m.bridges["step"]
    assert (b.kn, b.ks, b.friction, b.cohesion, b.tension) == (1e9, 1e8, 50, 1e6, 2e5)
    # the default's bridge table serves every set without its own
    default = "[joint_properties.default.bridge]\nfriction = 40\ncohesion = 1\ntension = 1\n"
    m = pm.parse_model(bridged + default + "kn = 5e9\n")
    assert m.bridges["step"].kn == 5e9


@pytest.mark.parametrize(
    ("text", "field", "words"),
    [
        (
            MODEL.replace('name = "step"', 'name = "step"\nbridge = true'),
            "joint_properties.step.bridge",
            "missing: joints[0] has bridge = true",
        ),
        (
            MODEL + "[joint_properties.step.bridge]\nfriction = 50\ncohesion = 1e6\ntension = 0\n",
            "joint_properties.step.bridge",
            "has no rock bridges",
        ),
        (
            MODEL.replace('name = "step"', 'name = "step"\nbridge = true')
            + "[joint_properties.step.bridge]\nfriction = 50\ncohesion = 1e6\n",
            "joint_properties.step.bridge.tension",
            "",
        ),
        (
            MODEL.replace('name = "step"', 'name = "step"\nbridge = true')
            + STEP_BRIDGE
            + "tension = 0\nresidual_friction = 30\n",
            "joint_properties.step.bridge.residual_friction",
            "unknown field",
        ),
    ],
)
def test_model_file_bridge_errors_name_the_field(text, field, words):
    with pytest.raises(penedge.SpecError) as caught:
        pm.parse_model(text)
    assert caught.value.field == field, str(caught.value)
    assert words in str(caught.value)


def step_path_limit_equilibrium():
    """F of examples/models/slope_step_path.toml: the mass above the bedding in front of the
    crack (x >= 12) slides as one piece on the joint (friction 30) and the bridge (friction
    30, cohesion 50 kPa over 5 / cos 35 by 10 m); the crack opens."""
    dip = math.radians(35)
    bedding = lambda x: 3 + (25 - x) * math.tan(dip)  # noqa: E731
    # x-z section: crack foot, toe, crest, crack top (shoelace)
    section = [(12, bedding(12)), (25, 3), (15, 15), (12, 15)]
    area = 0.5 * abs(
        sum(
            x0 * z1 - x1 * z0
            for (x0, z0), (x1, z1) in zip(section, section[1:] + section[:1], strict=True)
        )
    )
    weight = 2600 * 9.81 * area * 10
    bridge_area = 5 / math.cos(dip) * 10
    resisting = weight * math.cos(dip) * math.tan(math.radians(30)) + 50e3 * bridge_area
    return resisting / (weight * math.sin(dip))


def test_step_path_example_cuts_the_bedding_through():
    setup = pm.prepare(EXAMPLES / "slope_step_path.toml")
    # the crack splits the slope in two; the front is cut through by the bedding, and the
    # piece below the bedding by the seam at the joint's end (x = 17): the sliding mass is
    # one block, on the joint and the bridge
    assert len(setup.system) == 4
    assert (~setup.layout.fixed).sum() == 1
    dip = math.radians(35)
    normal = [math.sin(dip), 0.0, math.cos(dip)]
    assert plane_area(setup.system, BRIDGE, normal) == pytest.approx(50 / math.cos(dip), rel=1e-9)


@needs_engine
def test_step_path_example_factor_of_safety_is_bracketed_by_limit_equilibrium():
    """Without the bridge's cohesion F is the joint's tan 30 / tan 35 (0.82) within the
    bisection's 0.01; with it the slope stands (F > 1) and F is at most the limit equilibrium
    (1.39): the brittle bridge fails corner by corner, below the limit equilibrium, which
    mobilises the whole cohesion at once. (Measured: 1.16.)"""
    text = (EXAMPLES / "slope_step_path.toml").read_text()
    outcome = pm.simulate(text)
    assert outcome.stages[0].converged
    upper = step_path_limit_equilibrium()
    assert upper == pytest.approx(1.39, abs=0.01)
    safety = outcome.safety
    assert safety.stable > 1.05
    assert safety.failing <= upper + 0.01
    assert safety.failing_blocks == np.flatnonzero(~pm.prepare(text).layout.fixed).tolist()
    no_bridge = pm.simulate(text.replace("cohesion = 50e3", "cohesion = 0")).safety
    joint_only = math.tan(math.radians(30)) / math.tan(math.radians(35))
    assert no_bridge.stable < joint_only < no_bridge.failing + 1e-9


@needs_engine
def test_detection_keeps_the_face_of_the_bridge_piece_under_the_sliding_block():
    """A face inside a larger coplanar face, sharing two corners, placed by the simulation
    (coordinates moved by rounding): once a triangle of half the area (the hull's chain popped
    a corner, docs/contact-geometry.md)."""
    setup = pm.prepare(EXAMPLES / "slope_step_path.toml")
    sim = penedge.Simulation(setup.system, density=2600.0)
    placed = list(sim.system())
    sliding = int(np.flatnonzero(~setup.layout.fixed)[0])
    b = Blocks.of(setup.system)
    dip = math.radians(35)
    on = b.face_normals @ np.array([math.sin(dip), 0.0, math.cos(dip)]) > 1 - 1e-9
    bridge_piece = int(b.face_block[(b.face_kind == BRIDGE) & on][0])
    r = penedge.detect_pair(placed[sliding], placed[bridge_piece], gap=1e-3)
    # the bridge piece's top face, 5 / cos 35 by 10 m (the polygon is widened by the gap)
    assert r.area == pytest.approx(50 / math.cos(dip), rel=0.01)


def test_solve_stage_elastic_flag():
    stage = '[[stages]]\ntype = "solve"\nelastic = true\n'
    assert pm.parse_model(MODEL + stage).stages[0].elastic
    assert not pm.parse_model(MODEL + '[[stages]]\ntype = "solve"\n').stages[0].elastic
    with pytest.raises(penedge.SpecError) as caught:
        pm.parse_model(MODEL + stage.replace("true", "1"))
    assert caught.value.field == "stages[0].elastic"


def test_the_pieces_a_bridge_holds_are_one_body_for_the_detection():
    """The box cut through by the square joint is one body of its 6 pieces, and glued to
    nothing else: the same box without the joint (one block) plus a block on top touches it
    in one face-face region of the top's area, as the box alone does."""
    top = '\n[[joints]]\ntype = "plane"\npoint = [0, 0, 8]\ndip = 0\ndip_direction = 0\n'
    system = generated(SPEC + "bridge = true\n" + top)
    ids = system.body_ids
    assert ids.dtype == np.int64
    assert len(ids) == len(system)
    # The plane z = 8 splits the box; the square at z = 5 ends inside the lower block only.
    assert sorted(np.bincount(ids).tolist()) == [1, 6]
    found = system.detect_bodies()
    assert len(found) == 1
    reference = generated(SPEC + top).detect_bodies()  # the rock without the finite joint
    assert len(reference) == 1
    assert found.types.tolist() == reference.types.tolist() == [7]
    assert found.areas[0] == pytest.approx(reference.areas[0], rel=1e-12)
    assert found.areas[0] == pytest.approx(100.0, rel=1e-12)


@needs_engine
def test_block_bodies_maps_the_blocks_to_the_simulation_bodies():
    system = generated(SPEC + "bridge = true\n")
    assert len(set(system.body_ids.tolist())) == 1  # one block for the detection...
    sim = penedge.Simulation(system, density=2600.0)
    # ...six bodies for the mechanics, held by their bridges: one per piece, in block order
    assert len(sim) == 6
    bodies = sim.block_bodies
    assert bodies.dtype == np.int64
    assert bodies.tolist() == list(range(6))
    with pytest.raises(ValueError, match="read-only"):
        bodies[0] = 1
    # A concave block of glued boxes (no bridge) is one body whatever its id.
    a = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    b = penedge.Block.cuboid([1, 0, 0], [2, 1, 1])
    c = penedge.Block.cuboid([0, 0, 1], [1, 1, 2])
    glued = penedge.BlockSystem([a, b, c]).with_bodies([1, 0, 1])
    assert penedge.Simulation(glued).block_bodies.tolist() == [0, 1, 0]
