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
from penedge.model.engine import Engine
from penedge.model.run import Runner

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
BRIDGE = 3  # face origin code
STEP_BRIDGE = "[joint_properties.step.bridge]\nfriction = 50\ncohesion = 1e6\n"

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
    assert b.residual_cohesion == 0  # brittle unless told
    m = pm.parse_model(bridged + STEP_BRIDGE + "tension = 2e5\nresidual_cohesion = 1e6\n")
    assert m.bridges["step"].residual_cohesion == 1e6  # ductile
    assert m.bridges["step"].reduced(2.0).residual_cohesion == 5e5
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
        (
            MODEL.replace('name = "step"', 'name = "step"\nbridge = true')
            + STEP_BRIDGE
            + "tension = 0\nresidual_cohesion = 2e6\n",
            "joint_properties.step.bridge.residual_cohesion",
            "above the cohesion",
        ),
    ],
)
def test_model_file_bridge_errors_name_the_field(text, field, words):
    with pytest.raises(penedge.SpecError) as caught:
        pm.parse_model(text)
    assert caught.value.field == field, str(caught.value)
    assert words in str(caught.value)


class StepPath:
    """The statics of examples/models/slope_step_path.toml, computed here: the mass above the
    bedding in front of the crack (x >= 12, weight W) on its base, the bridge (x from 12 to
    17, friction 30, cohesion 50 kPa) and the joint (x from 17 to 25, friction 30), the crack
    open. Along x on the base the normal stress is linear (a rigid block on springs of one
    stiffness) with its resultant W cos 35 on the weight's line of action (x of the section's
    centroid: the shear forces, in the base plane, have no moment about a line in it); each
    rectangle's area is shared by its four corners (the engine's sub-contacts,
    docs/mechanics.md)."""

    dip = math.radians(35)
    tan_phi = math.tan(math.radians(30))
    cohesion = 50e3
    # each rectangle's length along the dip by 10 m across
    bridge_area = 5 / math.cos(dip) * 10
    joint_area = 8 / math.cos(dip) * 10

    def __init__(self):
        bedding = lambda x: 3 + (25 - x) * math.tan(self.dip)  # noqa: E731
        # x-z section: crack foot, toe, crest, crack top (shoelace, centroid)
        section = [(12, bedding(12)), (25, 3), (15, 15), (12, 15)]
        edges = list(zip(section, section[1:] + section[:1], strict=True))
        cross = [x0 * z1 - x1 * z0 for (x0, z0), (x1, z1) in edges]
        area = 0.5 * sum(cross)
        moment = sum((x0 + x1) * w for ((x0, _), (x1, _)), w in zip(edges, cross, strict=True))
        self.centroid_x = moment / (6 * area)
        self.weight = 2600 * 9.81 * abs(area) * 10
        # corners (x, area share of the two corners at x): sigma = a + b x with
        # sum(share sigma) = W cos 35 and sum(share sigma (x - x_G)) = 0
        corners = [
            (12, self.bridge_area / 2),
            (17, self.bridge_area / 2),
            (17, self.joint_area / 2),
            (25, self.joint_area / 2),
        ]
        s0, s1, s2 = (sum(w * x**k for x, w in corners) for k in range(3))
        xg, normal = self.centroid_x, self.weight * math.cos(self.dip)
        a, b = np.linalg.solve([[s0, s1], [s1 - xg * s0, s2 - xg * s1]], [normal, 0.0])
        self.stress = lambda x: a + b * x

    def corner_force(self, x, area):
        """The normal force of a corner at `x` of a rectangle of `area`."""
        return self.stress(x) * area / 4

    def limit_equilibrium(self):
        """F with the whole cohesion mobilised at once: (N tan 30 + c A) / (W sin 35)."""
        n = self.weight * math.cos(self.dip)
        resisting = n * self.tan_phi + self.cohesion * self.bridge_area
        return resisting / (self.weight * math.sin(self.dip))

    def first_corner_failure(self):
        """F at which the first bridge corners break (brittle): the joint's corners slide
        (friction only: N tan 30 / F), the bridge's four share the rest of W sin 35 equally
        (one shear displacement, one stiffness), and those at the joint's end (x = 17),
        pressed least, reach (c A / 4 + N tan 30) / F first."""
        joint = 2 * sum(self.corner_force(x, self.joint_area) for x in (17, 25))
        front = self.corner_force(17, self.bridge_area)
        resisting = self.cohesion * self.bridge_area + (4 * front + joint) * self.tan_phi
        return resisting / (self.weight * math.sin(self.dip))


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


def ductile(text):
    """The step-path model with a ductile bridge: its cohesion kept after failure."""
    return text.replace("tension = 100e3", "tension = 100e3\nresidual_cohesion = 50e3")


def test_step_path_example_factor_of_safety_against_its_statics():
    """Friction only, F is the joint's tan 30 / tan 35 (0.82). With the bridge: a ductile
    bridge (residual cohesion = cohesion) gives the limit equilibrium (1.391) within the
    bisection; the brittle one (the example's) fails with its first corners (1.331, computed
    here) within the bisection (a trial loads it at once: a slightly dynamic load), not at
    the limit equilibrium, which mobilises the whole cohesion at once."""
    statics = StepPath()
    upper = statics.limit_equilibrium()
    first = statics.first_corner_failure()
    assert (upper, first) == (pytest.approx(1.391, abs=1e-3), pytest.approx(1.331, abs=1e-3))
    text = (EXAMPLES / "slope_step_path.toml").read_text()
    outcome = pm.simulate(text)
    assert outcome.stages[0].converged
    brittle = outcome.safety  # measured: stable 1.3203, failing 1.3281
    assert first - 0.02 <= brittle.stable < brittle.failing <= first + 0.01
    assert brittle.failing_blocks == np.flatnonzero(~pm.prepare(text).layout.fixed).tolist()
    ductile_run = pm.simulate(ductile(text)).safety  # measured: 1.3906, 1.3984
    assert ductile_run.stable - 0.01 <= upper <= ductile_run.failing + 0.01
    assert abs(ductile_run.factor - upper) <= 0.02
    no_bridge = pm.simulate(text.replace("cohesion = 50e3", "cohesion = 0")).safety
    joint_only = math.tan(math.radians(30)) / math.tan(math.radians(35))
    assert no_bridge.stable < joint_only < no_bridge.failing + 1e-9


def bridge_corners(contacts):
    """Per sub-contact of the bridge contact: x, normal force, bonded."""
    (i,) = np.flatnonzero(contacts["bridges"])
    a, b = contacts["sub_offsets"][i : i + 2]
    x = contacts["points"][a:b, 0]
    return x, contacts["normal_forces"][a:b], contacts["bonded"][a:b]


def test_step_path_bridge_breaks_from_the_joints_end():
    """The mechanism: at rest the corners carry the normal forces of the statics (the
    block's weight acts behind the middle of its base: the bridge's back corners are pressed
    most); reduced by F between the first corners' failure and the limit equilibrium, the
    corners at the joint's end reach their strength first: the brittle bridge then breaks
    whole, the ductile one holds."""
    statics = StepPath()
    f = 0.5 * (statics.first_corner_failure() + statics.limit_equilibrium())  # 1.36
    outcomes = {}
    text = (EXAMPLES / "slope_step_path.toml").read_text()
    for name in ("brittle", "ductile"):
        setup = pm.prepare(text if name == "brittle" else ductile(text))
        runner = Runner(setup, Engine)
        runner.run_stage(0, setup.model.stages[0])
        e = runner.engine
        x, normal, bonded = bridge_corners(e.sim.contacts())
        assert bonded.all()
        for xi, n in zip(x, normal, strict=True):
            expected = statics.corner_force(round(xi), statics.bridge_area)
            assert n == pytest.approx(expected, rel=0.01), xi
        e.default = e.default.reduced(f)
        e.apply_properties({k: p.reduced(f) for k, p in dict(e.properties).items()}, f)
        broken_at = {}
        for step in range(0, 3000, 20):
            e.cycle(20)
            x, _, bonded = bridge_corners(e.sim.contacts())
            for xi, b in zip(x, bonded, strict=True):
                if not b:
                    broken_at.setdefault(round(xi), step)
        free = ~setup.layout.fixed
        outcomes[name] = (broken_at, float(np.linalg.norm(e.velocities()[free], axis=1).max()))
    # ductile: the corners at the joint's end reach the strength and slide, keeping their
    # cohesion; the back ones hold and the block stays
    ductile_broken, ductile_speed = outcomes["ductile"]
    assert set(ductile_broken) <= {17}
    assert ductile_speed < 1e-4
    # brittle: those corners lose their cohesion, the back ones then break and the block slides
    brittle, brittle_speed = outcomes["brittle"]
    assert set(brittle) == {12, 17}, brittle
    assert brittle_speed > 1e-2
    assert brittle[17] < brittle[12]


def test_an_elastic_solve_glues_no_joint_that_has_no_bond():
    """``elastic = true`` makes the bonds unbreakable, not new ones: the step-path block
    settles on the bedding and the bridge, the tension crack (friction only) open behind
    it. (Once every model's tension was raised, the crack's included: it held the block
    with 2.9 MN of tension, a third of its weight, let go at once when the stage ended; the
    shock broke the brittle bridge at F = 1.16 instead of 1.32.)"""
    setup = pm.prepare(EXAMPLES / "slope_step_path.toml")
    runner = Runner(setup, Engine)
    assert runner.run_stage(0, setup.model.stages[0]).converged
    c = runner.engine.sim.contacts()
    counts = np.diff(c["sub_offsets"].astype(np.int64))
    per_sub = np.repeat(c["bridges"], counts)
    assert c["bonded"][per_sub].all()  # the bridge holds, bonded
    assert (c["normal_forces"][~per_sub] >= 0).all()  # no joint in tension
    # the crack's contact (vertical normal) is open
    crack = np.abs(c["normals"][:, 0]) > 0.99
    assert crack.sum() == 1
    assert (c["states"][np.repeat(crack, counts)] == 2).all()


def test_the_step_path_block_settles_to_roundings_with_a_cohesive_bridge():
    """Friction 40 on the joint and the bridge (the block stands on friction alone, every
    sub-contact elastic), the bridge bonded with its cohesion: the unbalanced-force ratio
    falls below 1e-8. It stalled at 5e-4: the polygon of the joint's contact had a corner at
    the joint's end and a point 1.9 cm from it (the gap's widening), and which of the two it
    kept depended on the roundings of the block's pose, so the corner jumped at the re-queries
    and the forces with it (contact_geometry/polygon.rs, docs/mechanics.md)."""
    text = (
        (EXAMPLES / "slope_step_path.toml").read_text().replace("friction = 30 ", "friction = 40 ")
    )
    setup = pm.prepare(text)
    runner = Runner(setup, Engine)
    runner.run_stage(0, setup.model.stages[0])
    e = runner.engine
    for _ in range(40):
        e.cycle(250)
        if e.ratio < 1e-8:
            break
    assert e.ratio < 1e-8
    c = e.sim.contacts()
    per_sub = np.repeat(c["bridges"], np.diff(c["sub_offsets"].astype(np.int64)))
    assert c["bonded"][per_sub].all()
    assert (c["states"] != 1).all()  # none sliding


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
