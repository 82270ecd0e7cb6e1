"""The ``excavate`` and ``save`` stages and ``penedge simulate --restart`` (docs/models.md,
"Excavation" and "Restart"), on the rigid-block engine: a resumed run is bit for bit the run
that did not stop; an excavated block's load relaxes and the rock above it falls."""

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

import penedge
import penedge.model as pm
from penedge import cli

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
COLUMN = (EXAMPLES / "block_column.toml").read_text()
BASE = COLUMN[: COLUMN.index("[[stages]]")]
G = 9.81


def column(stages: str, seismic: bool = True) -> str:
    """The block column of examples/models with these stages (blocks 0 to 4, 0 fixed);
    with `seismic`, pushed sideways by 0.05 g so that its joints carry shear forces."""
    push = "[seismic]\ncoefficient = 0.05\nazimuth = 90\n\n[[boundary]]"
    return (BASE.replace("[[boundary]]", push) if seismic else BASE) + stages


SAVE_AND_GO_ON = """
[[stages]]
type = "cycle"
steps = 120
[[stages]]
type = "save"
file = "state.json"
[[stages]]
type = "cycle"
steps = 90
"""


def test_a_restarted_run_is_bit_for_bit_the_run_that_did_not_stop(tmp_path):
    whole = pm.simulate(column(SAVE_AND_GO_ON), folder=tmp_path)
    state = tmp_path / "state.json"
    assert state.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["state.json"]  # no temporary file left
    resumed = pm.simulate(column(SAVE_AND_GO_ON), folder=tmp_path / "again", restart=state)
    # Only the stage after the save ran, from where the save left it.
    assert [s.name for s in resumed.stages] == ["stages[2]"]
    assert resumed.steps == whole.steps == 210
    assert np.array_equal(resumed.displacement, whole.displacement)
    assert np.array_equal(resumed.velocity, whole.velocity)
    assert resumed.time == whole.time
    assert resumed.ratio == whole.ratio
    # The saved state itself: readable by penedge.Simulation.load, with its note.
    sim = penedge.Simulation.load(state)
    assert sim.steps == 120
    assert json.loads(sim.note)["next_stage"] == 2


WET_AND_BOLTED = """
[water]
phreatic = { elevation = 2.5 }

[[bolts]]
name = "top"
point = [0.5, 0.5, 5]
plunge = 90
trend = 0
length = 2.5
capacity = 2e3
stiffness = 1e8
shear_stiffness = 1e7
shear_capacity = 500

[[stages]]"""


def test_a_restarted_run_with_water_and_a_bolt_is_bit_for_bit(tmp_path):
    # The column under a water table (its lower joints wet) and pushed sideways, with a bolt
    # from its top down across two joints; the state of the water and of the bolt's
    # elements (forces, dowel slips) goes through the restart file.
    text = column(SAVE_AND_GO_ON).replace("[[stages]]", WET_AND_BOLTED, 1)
    whole = pm.simulate(text, folder=tmp_path)
    assert len(whole.bolts) == 1
    assert whole.bolts[0]["force"] != 0
    resumed = pm.simulate(text, folder=tmp_path / "again", restart=tmp_path / "state.json")
    assert resumed.steps == whole.steps == 210
    assert np.array_equal(resumed.displacement, whole.displacement)
    assert np.array_equal(resumed.velocity, whole.velocity)
    assert resumed.bolts == whole.bolts
    # The water acts: the same run dry moves otherwise.
    (tmp_path / "dry").mkdir()
    dry = pm.simulate(
        text.replace("[water]\nphreatic = { elevation = 2.5 }\n", ""), folder=tmp_path / "dry"
    )
    assert not np.array_equal(dry.displacement, whole.displacement)


def test_simulate_restart_on_the_command_line(tmp_path, capsys):
    model = tmp_path / "column.toml"
    model.write_text(column(SAVE_AND_GO_ON))
    flags = ["--no-pictures", "--no-series", "--json"]
    assert cli.main(["simulate", str(model), "-o", str(tmp_path / "a"), *flags]) == 0
    first = json.loads(capsys.readouterr().out)
    state = tmp_path / "a" / "state.json"
    again = ["simulate", str(model), "-o", str(tmp_path / "b"), "--restart", str(state)]
    assert cli.main([*again, *flags]) == 0
    second = json.loads(capsys.readouterr().out)
    assert second["max_displacement"] == first["max_displacement"]
    assert second["steps"] == first["steps"] == 210
    # A file that is not a restart file is named, before any step.
    (tmp_path / "blocks.json").write_text(
        penedge.BlockSystem([penedge.Block.cuboid([0, 0, 0], [1, 1, 1])]).to_json()
    )
    bad = ["simulate", str(model), "-o", str(tmp_path / "c"), "--restart"]
    assert cli.main([*bad, str(tmp_path / "blocks.json"), *flags]) == 1
    err = capsys.readouterr().err
    assert "blocks.json" in err, err
    assert "not a restart file" in err, err
    assert not (tmp_path / "c").exists()


EXCAVATE = """
[[stages]]
type = "solve"
ratio = 1e-6
[[stages]]
type = "excavate"
region = {{type = "box", min = [0, 0, 2], max = [1, 1, 3]}}
relax_steps = {relax}
[[stages]]
type = "cycle"
steps = 200
"""


def test_an_excavate_stage_relaxes_the_load_then_the_blocks_above_fall():
    relax = 100
    setup = pm.prepare(column(EXCAVATE.format(relax=relax), seismic=False))
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    runner = Runner(setup, Engine)
    runner.run_stage(0, setup.model.stages[0])
    e = runner.engine
    # Settled (with the model's local damping); undamped from here, so that the fall can be
    # compared with a formula.
    e.sim.set_damping(local=0.0, viscous=0.0)
    z = e.positions()[:, 2]
    middle = int(np.flatnonzero((z > 2) & (z < 3))[0])
    top = np.flatnonzero(z > 3)  # the two blocks above it
    below = np.flatnonzero((z > 1) & (z < 2))
    assert len(top) == 2
    height = e.positions()[top, 2].mean()
    runner.run_stage(1, setup.model.stages[1])
    assert np.flatnonzero(e.removed()).tolist() == [middle]
    assert e.steps == runner.history.step[-1]
    # During the relaxation the two blocks above lose their support linearly: their centre
    # falls by g dt² Σ_j (j - 1) / N over the N steps (the load's share 1 - (j - 1)/N), that
    # is g dt² (N - 1)(N - 2) / (2 N)... summed as the leapfrog does, step by step.
    dt = e.timestep
    v, z = 0.0, 0.0
    for j in range(1, relax + 1):
        v -= G * dt * (j - 1) / relax
        z += v * dt
    drop = e.positions()[top, 2].mean() - height
    assert drop == pytest.approx(z, rel=1e-3)
    # (The cycle stage would set the model's damping: undamped too.)
    runner.run_stage(2, dataclasses.replace(setup.model.stages[2], damping=0.0))
    # Then free fall: 200 steps more at g.
    for _ in range(200):
        v -= G * dt
        z += v * dt
    assert e.positions()[top, 2].mean() - height == pytest.approx(z, rel=1e-3)
    assert abs(e.positions()[below, 2] - 1.5).max() < 1e-3  # the block below stays


def test_an_excavation_with_nothing_left_to_remove_is_refused_before_any_step():
    again = EXCAVATE.format(relax=10)
    again = again[again.index('[[stages]]\ntype = "excavate"') :]  # excavate, then cycle
    text = column(EXCAVATE.format(relax=10) + again)
    with pytest.raises(pm.ModelError, match=r"stages\[3\].region: every block"):
        pm.prepare(text)


@pytest.mark.parametrize("file", ["", "out/"])
def test_a_save_stage_needs_a_file_name(file):
    with pytest.raises(pm.ModelError, match=r"stages\[0\].file"):
        pm.parse_model(column(f'[[stages]]\ntype = "save"\nfile = "{file}"\n'))
    with pytest.raises(pm.ModelError, match=r"stages\[0\].file"):
        pm.parse_model(column('[[stages]]\ntype = "save"\n'))


def joint_set(name: str, dip: int, dip_direction: int, origin: str) -> str:
    """A set of two joints 1 m apart through `origin`."""
    return (
        f'[[joints]]\ntype = "set"\nname = "{name}"\ndip = {dip}\ndip_direction = '
        f"{dip_direction}\nspacing = 1\norigin = {origin}\nnumber = 2\n\n"
    )


BOX = (
    '[domain]\ntype = "box"\nmin = [0, 0, 0]\nmax = [3, 3, 3]\n\n'
    + joint_set("x", 90, 90, "[1, 0, 0]")
    + joint_set("y", 90, 0, "[0, 1, 0]")
    + joint_set("z", 0, 0, "[0, 0, 1]")
    + """[rock]
density = 2500

[mechanics]
gravity = [0, 0, 0]

[joint_properties.default]
kn = 1e9
ks = 1e9
friction = 40

[initial_stress]
type = "uniform"
xx = -2e6
yy = -1e6
zz = -3e6
xy = 0.5e6

[[stages]]
type = "cycle"
steps = 50
"""
)


def test_a_confined_block_under_an_initial_stress_stays_put():
    """A 3 x 3 x 3 box of cubes, the 26 outer ones fixed, the middle one free, gravity off,
    under a uniform stress with shear: the middle block's six faces carry the stress's
    traction (installed as the first step's contact forces), which balance: it stays put."""
    faces = ["bottom", "top", "east", "west", "north", "south"]
    boundary = "".join(
        f'[[boundary]]\nregion = {{type = "face", face = "{f}"}}\ncondition = "fixed"\n'
        for f in faces
    )
    setup = pm.prepare(BOX + boundary)
    assert int((~setup.layout.fixed).sum()) == 1
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    runner = Runner(setup, Engine)
    outcome = runner.run()
    assert np.abs(outcome.displacement).max() < 1e-9
    c = runner.engine.sim.contacts()
    middle = int(np.flatnonzero(~setup.layout.fixed)[0])
    touching = np.flatnonzero((c["pairs"] == middle).any(axis=1))
    assert len(touching) == 26  # faces, edges and corners of its neighbours
    mine = touching[c["types"][touching] == penedge.FACE_FACE]
    assert len(mine) == 6
    corners = touching[c["types"][touching] != penedge.FACE_FACE]
    assert not c["prestresses"][off_of(c, corners)].any()
    # The normal stress of each face: -n.sigma.n, e.g. 3 MPa across the horizontal joints.
    sigma = np.array([[-2e6, 0.5e6, 0], [0.5e6, -1e6, 0], [0, 0, -3e6]])
    off = c["sub_offsets"]
    for k in mine:
        n = c["normals"][k]
        expected = -n @ sigma @ n
        assert np.allclose(c["prestresses"][off[k] : off[k + 1]], expected, rtol=1e-9)


def off_of(c, contacts):
    """The sub-contact indices of `contacts`."""
    off = c["sub_offsets"].astype(np.int64)
    return np.concatenate([np.arange(off[k], off[k + 1]) for k in contacts])


def test_an_overburden_is_the_engine_field_of_the_model():
    from penedge.model.engine import initial_stress_of

    text = BOX.replace(
        'type = "uniform"\nxx = -2e6\nyy = -1e6\nzz = -3e6\nxy = 0.5e6',
        'type = "overburden"\nk0_x = 1.5\nk0_y = 0.5',
    )
    text = text.replace("gravity = [0, 0, 0]", "gravity = [0, 0, -10]")
    boundary = '[[boundary]]\nregion = {type = "face", face = "bottom"}\ncondition = "fixed"\n'
    field = initial_stress_of(pm.prepare(text + boundary))
    assert field["surface"] == 3.0  # the top of the blocks
    assert field["per_depth"] == [-2500 * 10 * 1.5, -2500 * 10 * 0.5, -2500 * 10, 0, 0, 0]


def test_the_outputs_mark_or_leave_out_the_excavated_rock(tmp_path):
    """The ParaView frames after an excavation flag the removed block (cell data
    ``excavated``); the picture of the final state leaves it out."""
    import xml.etree.ElementTree as ET

    from penedge.cli.simulate import without_excavated

    model = tmp_path / "column.toml"
    model.write_text(column(EXCAVATE.format(relax=20), seismic=False))
    out = tmp_path / "out"
    assert cli.main(["simulate", str(model), "-o", str(out), "--no-pictures", "--quiet"]) == 0
    last = sorted((out / "series").glob("blocks_*.vtu"))[-1]
    arrays = {a.get("Name"): a.text for a in ET.parse(last).iter("DataArray")}
    assert [int(v) for v in arrays["excavated"].split()].count(1) == 1
    setup = pm.prepare(model)
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    runner = Runner(setup, Engine)
    outcome = runner.run()
    shown, displacement = without_excavated(
        runner.engine, runner.engine.system(), outcome.displacement
    )
    assert len(shown.blocks) == len(displacement) == 4


def test_the_excavation_example_runs_and_restarts(tmp_path):
    example = EXAMPLES / "column_excavation.toml"
    whole = pm.simulate(example, folder=tmp_path)
    resumed = pm.simulate(example, folder=tmp_path / "again", restart=tmp_path / "settled.json")
    assert [s.kind for s in resumed.stages] == ["excavate", "cycle"]
    assert np.array_equal(resumed.displacement, whole.displacement)
    # The two blocks above the excavated one fell; the one below did not move.
    z = pm.prepare(example).blocks.centroids[:, 2]
    fell = whole.displacement[z > 3, 2]
    assert (fell < -1e-3).all()
    assert abs(whole.displacement[(z > 1) & (z < 2), 2]).max() < 1e-4
