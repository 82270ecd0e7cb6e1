"""Model files with concave blocks (docs/models.md, "Concave blocks"): the tunnel example
of examples/models runs through ``penedge simulate``; a concave block is one rigid body whose
mass is that of the union of its parts (a square minus a quarter of the tunnel's polygon,
computed here), the fixed rock carries the free rock's weight at equilibrium, boundary
conditions and excavations go by whole bodies, and per-block results are the body's."""

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import penedge
import penedge.model as pm
from penedge import cli

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
TUNNEL = EXAMPLES / "tunnel_concave.toml"
TEXT = TUNNEL.read_text()
BASE = TEXT[: TEXT.index("[[stages]]")]
DENSITY, G = 2700.0, 9.81
# The example's geometry: joints every 2.5 m in x and z, a slice 2 m long in y, a 16-gon of
# radius 2 m centred on the joints' intersection x = z = 5.
SPACING, SLICE, RADIUS, SEGMENTS = 2.5, 2.0, 2.0, 16


def concave_volume():
    """A block around the tunnel: the 2.5 m square minus a quarter of the regular 16-gon
    (area N r² sin(2π/N) / 2; its quarters are equal, the polygon being symmetric about the
    two joints through its centre), times the slice's length."""
    polygon = SEGMENTS * RADIUS**2 * math.sin(2 * math.pi / SEGMENTS) / 2
    return (SPACING**2 - polygon / 4) * SLICE


def bodies_of(setup):
    """Body id per block, and the bodies of several parts."""
    ids = np.asarray(setup.system.body_ids)
    values, counts = np.unique(ids, return_counts=True)
    return ids, values[counts > 1]


def test_the_example_has_concave_blocks_held_as_whole_bodies():
    setup = pm.prepare(TUNNEL)
    ids, concave = bodies_of(setup)
    assert len(concave) == 8  # four around the tunnel in each of the two slices
    fixed = setup.layout.fixed
    for body in concave:
        parts = ids == body
        assert len(set(fixed[parts].tolist())) == 1  # a body is fixed or free as a whole
        # each concave block is the square minus a quarter polygon, whatever its parts
        assert setup.blocks.volumes[parts].sum() == pytest.approx(concave_volume(), rel=1e-9)
    free_bodies = set(ids[~fixed].tolist())
    assert set(concave.tolist()) <= free_bodies
    assert len(free_bodies) == 12  # two middle columns, three rows above the floor, 2 slices


def test_the_example_runs_and_the_fixed_rock_carries_the_weight_of_the_free_rock():
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    setup = pm.prepare(TUNNEL)
    runner = Runner(setup, Engine)
    outcome = runner.run()
    assert outcome.stable
    e = runner.engine
    ids, concave = bodies_of(setup)
    body = e.body
    assert len(e.sim) == len(np.unique(ids))
    # one body per concave block, with the mass of the union of its parts
    masses = np.asarray(e.sim.masses)
    for b in concave:
        assert masses[body[ids == b][0]] == pytest.approx(DENSITY * concave_volume(), rel=1e-9)
    # At equilibrium the contact forces on the fixed bodies add up to the free rock's
    # weight, the density times the free blocks' volumes (from the generation, not the
    # engine's masses); fixed-fixed contacts cancel in the sum.
    fixed = setup.layout.fixed
    weight = DENSITY * G * setup.blocks.volumes[~fixed].sum()
    fixed_bodies = np.unique(body[fixed])
    reaction = -np.asarray(e.sim.contact_forces)[fixed_bodies].sum(axis=0)
    assert reaction[2] == pytest.approx(weight, rel=0.01)
    assert abs(reaction[:2]).max() < 0.01 * weight
    # per block results are the body's: the parts of a concave block move together
    for b in concave:
        parts = np.flatnonzero(ids == b)
        assert (outcome.displacement[parts] == outcome.displacement[parts[0]]).all()
    # the geometry at the end is in the model's block order, with the bodies
    final = e.system()
    assert np.asarray(final.body_ids).tolist() == body.tolist()
    moved = np.linalg.norm(np.asarray(final.arrays().centroids) - setup.blocks.centroids, axis=1)
    assert moved.max() < 0.01  # held by cohesive joints: millimetres at most


def cells(path):
    """The cell data of a VTU file, by name."""
    root = ET.parse(path).getroot()
    return {
        a.get("Name"): np.array(a.text.split(), dtype=float)
        for a in root.iter("DataArray")
        if a.get("Name") in ("block_id", "body_id", "displacement")
    }


def test_penedge_simulate_runs_the_concave_example(tmp_path):
    out = tmp_path / "out"
    assert cli.main(["simulate", str(TUNNEL), "-o", str(out), "-q"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stable"]
    assert (out / "displacement.png").stat().st_size > 0
    setup = pm.prepare(TUNNEL)
    pvd = ET.parse(out / "series" / "blocks.pvd").getroot()
    last = [d.get("file") for d in pvd.iter("DataSet")][-1]
    data = cells(out / "series" / last)
    assert data["block_id"].tolist() == list(range(len(setup.system)))
    assert data["body_id"].tolist() == np.asarray(setup.system.body_ids).tolist()
    displacement = data["displacement"].reshape(-1, 3)
    ids = data["body_id"]
    for b in np.unique(ids):
        parts = ids == b
        assert (displacement[parts] == displacement[parts][0]).all()


def test_a_condition_on_one_part_holds_the_whole_concave_block():
    # the point lies in one part of the concave block above the tunnel, West of the crown
    text = BASE.replace(
        "[[monitors]]",
        '[[boundary]]\nregion = {type = "point", point = [4.5, 1, 7.2]}\n'
        'condition = "velocity"\nvelocity = [0, 0, 0.01]\n\n[[monitors]]',
    )
    setup = pm.prepare(text + '[[stages]]\ntype = "solve"\n')
    ids, _ = bodies_of(setup)
    block = setup.layout.monitors["crown"]
    parts = ids == ids[block]
    assert parts.sum() > 1
    assert np.array_equal(setup.layout.driven, parts)
    assert (setup.layout.velocity[parts] == [0, 0, 0.01]).all()


def excavating(region):
    return pm.prepare(BASE + f'[[stages]]\ntype = "excavate"\nregion = {region}\n')


def test_an_excavation_that_splits_a_concave_block_is_refused_before_any_step():
    # x < 4.5 takes the parts of the blocks West of the crown whose centroid is there,
    # not all of them
    region = '{type = "box", min = [2.6, 0, 5.1], max = [4.0, 4, 7.4]}'
    with pytest.raises(pm.ModelError, match=r"stages\[0\].region: the region holds blocks"):
        excavating(region)


def test_an_excavation_removes_whole_concave_blocks():
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    setup = excavating('{type = "box", min = [2.5, 0, 5], max = [5, 4, 7.5]}')
    runner = Runner(setup, Engine)
    runner.run_stage(0, setup.model.stages[0])
    ids, _ = bodies_of(setup)
    removed = runner.engine.removed()
    block = setup.layout.monitors["crown"]
    assert removed[ids == ids[block]].all()
    assert removed.sum() == (np.isin(ids, ids[removed])).sum()
    assert np.asarray(runner.engine.sim.removed).sum() == 2  # one concave block per slice


def test_the_engine_refuses_parts_of_one_body_given_different_conditions():
    from penedge.model.engine import Engine

    setup = pm.prepare(TUNNEL)
    e = Engine(setup)
    ids, concave = bodies_of(setup)
    parts = np.flatnonzero(ids == concave[0])
    fixed = setup.layout.fixed.copy()
    fixed[parts[0]] = True
    with pytest.raises(pm.ModelError, match=r"boundary: blocks \d+ and \d+ are parts of one"):
        e.apply_boundary(fixed, setup.layout.velocity)


def test_a_bolt_within_one_concave_block_is_refused():
    # from the West wall of the block above the tunnel towards the opening, at z = 6.5:
    # through two of its parts, both ends in rock, and no other body on the way
    bolt = (
        "[[bolts]]\npoint = [2.6, 1, 6.5]\ntrend = 90\nplunge = 0\nlength = 1\n"
        "capacity = 1e5\nstiffness = 1e7\n"
    )
    setup = pm.prepare(BASE + bolt)
    ids, _ = bodies_of(setup)
    collar, anchor = setup.layout.bolts[0]
    assert collar != anchor
    assert ids[collar] == ids[anchor]
    from penedge.model.engine import Engine

    with pytest.raises(pm.ModelError, match=r"bolts\[0\]: .*ties nothing"):
        Engine(setup)


class Recorder:
    """Stands in for the simulation in Engine.apply_support: records the loads per body."""

    def __init__(self, sim):
        self.n = len(sim)
        self.positions = np.asarray(sim.positions)
        self.forces = np.zeros((self.n, 3))
        self.moments = np.zeros((self.n, 3))

    def __len__(self):
        return self.n

    def apply_force(self, i, force):
        self.forces[i] += force

    def apply_moment(self, i, moment):
        self.moments[i] += moment


def test_support_forces_on_parts_add_up_on_the_body_with_their_moments_about_its_centroid():
    from penedge.model.engine import Engine

    setup = pm.prepare(TUNNEL)
    e = Engine(setup)
    e.sim = Recorder(e.sim)
    n = len(setup.system)
    rng = np.random.default_rng(7)
    forces = rng.normal(size=(n, 3)) * 1e3
    moments = rng.normal(size=(n, 3)) * 1e2
    e.apply_support(forces, moments)
    ids, concave = bodies_of(setup)
    volumes, centroids = setup.blocks.volumes, setup.blocks.centroids
    for b in concave:
        parts = np.flatnonzero(ids == b)
        # the body's centroid from its parts' volumes and centroids (not the engine's)
        centre = volumes[parts] @ centroids[parts] / volumes[parts].sum()
        expected = moments[parts].sum(0) + np.cross(centroids[parts] - centre, forces[parts]).sum(0)
        row = e.body[parts[0]]
        assert np.allclose(e.sim.forces[row], forces[parts].sum(0), rtol=1e-12, atol=1e-9)
        assert np.allclose(e.sim.moments[row], expected, rtol=1e-9, atol=1e-6)
    for k in np.flatnonzero(~np.isin(ids, concave)):  # a convex block keeps its own loads
        assert np.array_equal(e.sim.forces[e.body[k]], forces[k])
        assert np.array_equal(e.sim.moments[e.body[k]], moments[k])


def test_a_restarted_concave_model_is_bit_for_bit_the_run_that_did_not_stop(tmp_path):
    stages = (
        '[[stages]]\ntype = "cycle"\nsteps = 60\n[[stages]]\ntype = "save"\n'
        'file = "state.json"\n[[stages]]\ntype = "cycle"\nsteps = 40\n'
    )
    whole = pm.simulate(BASE + stages, folder=tmp_path)
    resumed = pm.simulate(BASE + stages, folder=tmp_path / "again", restart=tmp_path / "state.json")
    assert [s.name for s in resumed.stages] == ["stages[2]"]
    assert resumed.steps == whole.steps == 100
    assert np.array_equal(resumed.displacement, whole.displacement)
    assert np.array_equal(resumed.velocity, whole.velocity)
    # the file holds the bodies, one per concave block: the parts' map is the model's
    sim = penedge.Simulation.load(tmp_path / "state.json")
    ids, _ = bodies_of(pm.prepare(TUNNEL))
    assert len(sim) == len(np.unique(ids))


def test_the_picture_after_an_excavation_keeps_the_concave_blocks_whole():
    from penedge.cli.simulate import without_excavated
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    setup = excavating('{type = "box", min = [2.5, 0, 5], max = [5, 4, 7.5]}')
    runner = Runner(setup, Engine)
    runner.run_stage(0, setup.model.stages[0])
    e = runner.engine
    shown, displacement = without_excavated(e, e.system(), np.zeros((len(setup.system), 3)))
    kept = ~e.removed()
    assert len(shown) == len(displacement) == kept.sum()
    assert np.asarray(shown.body_ids).tolist() == e.body[kept].tolist()


def test_a_point_between_two_parts_of_a_concave_block_is_that_block():
    # the parts of one body move as one: a point on their glue face is not ambiguous (as a
    # point on a face between two bodies is: docs/models.md, "[[monitors]]")
    setup = pm.prepare(TUNNEL)
    blocks = setup.blocks
    ids = np.asarray(setup.system.body_ids)
    glue = blocks.glue_faces[0]
    a, b = blocks.face_block[glue]
    assert a != b
    assert ids[a] == ids[b]
    assert blocks.containing(blocks.face_centroids[glue[0]]) in (a, b)
    # a joint face between two bodies is
    joint = np.flatnonzero(blocks.face_kind == 2)
    centre = blocks.face_centroids[joint]
    for point in centre:
        others = np.flatnonzero(np.all(np.isclose(centre, point), axis=1))
        owners = blocks.face_block[joint[others]]
        if len(set(ids[owners].tolist())) > 1:
            break
    else:
        pytest.fail("no joint face between two bodies")
    with pytest.raises(pm.ModelError, match="lies on the boundary between blocks") as caught:
        blocks.containing(point)
    assert all(f" {b} (centroid" in str(caught.value) for b in owners)


def test_an_engine_error_naming_two_bodies_names_their_blocks(monkeypatch):
    # The engine's penetration error names its bodies, rows a model's user never sees: in a
    # model with concave blocks body i is not block i. The run's error names the blocks
    # each body is made of (docs/models.md, "Concave blocks").
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    setup = pm.prepare(BASE + '[[stages]]\ntype = "cycle"\nsteps = 10\n')
    runner = Runner(setup, Engine)
    body = runner.engine.body
    ids, concave = bodies_of(setup)
    a = int(body[ids == concave[0]][0])  # a concave block's body
    b = int(np.flatnonzero(np.bincount(body) == 1)[-1])  # a convex block's body
    assert not np.array_equal(body, np.arange(len(body)))
    message = f"bodies {a} and {b} overlap by 0.1, deeper than the detection gap (0.001), at step 3"

    def penetrate(steps):
        raise penedge.MechanicsError(message)

    monkeypatch.setattr(runner.engine, "cycle", penetrate)
    outcome = runner.run()
    parts = ", ".join(str(k) for k in np.flatnonzero(body == a))
    (block,) = np.flatnonzero(body == b)
    assert outcome.error == (
        f"bodies {a} and {b} (the concave block made of blocks {parts}; block {block}) "
        "overlap by 0.1, deeper than the detection gap (0.001), at step 3"
    )
    # Where every body is its own block, the message is left as it is.
    column = (EXAMPLES / "block_column.toml").read_text()
    plain = Runner(pm.prepare(column), Engine)
    assert plain.engine.with_blocks(message) == message
