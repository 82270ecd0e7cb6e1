"""``[mechanics] mass_scaling`` of model files (docs/models.md): the engine's mass scaling
(docs/mechanics.md, "Mass scaling") turned on by the model, checked on ``--restart``.

The model: the incline of incline_model.py (a block on a plane dipping 30° towards the
East, the rock below it fixed; F = tan φ / tan 30°) with a horizontal joint a few
millimetres below its top, which cuts a sliver off the block: a slab riding on it."""

import json
import math
from pathlib import Path

import pytest
from incline_model import incline

import penedge.model as pm
from penedge import cli
from penedge.model.engine import Engine
from penedge.model.fields import ModelError


def sliver(thickness: float = 0.005) -> str:
    """The incline with a slab `thickness` metres thick cut off the top of its block."""
    joint = f"""
[[joints]]
type = "plane"
name = "sliver"
point = [5, 1, {8 - thickness!r}]
dip = 0
dip_direction = 0
"""
    text = incline(35)
    at = text.index("[rock]")
    return text[:at] + joint + text[at:]


def scaled(text: str, on: bool) -> str:
    return text + f"[mechanics]\nmass_scaling = {str(on).lower()}\n"


def test_a_sliver_sets_a_smaller_step_without_mass_scaling_than_with_it():
    setup = pm.prepare(sliver())
    free = ~setup.layout.fixed
    assert free.sum() == 2  # the block and the sliver
    plain = Engine(pm.prepare(scaled(sliver(), False))).timestep
    assert Engine(pm.prepare(sliver())).timestep == plain  # off by default
    faster = Engine(pm.prepare(scaled(sliver(), True))).timestep
    # The slab weighs about 1/1000 of the block; its step is ~1/35 of the block's.
    assert faster > 10 * plain


def test_a_model_run_takes_the_larger_step(tmp_path):
    # summary.json: a cycle stage of 100 steps covers 100 time steps.
    times = {}
    for on in (False, True):
        text = scaled(sliver(), on) + '[[stages]]\ntype = "cycle"\nsteps = 100\n'
        model = tmp_path / f"m{on}.toml"
        model.write_text(text)
        out = tmp_path / f"run{on}"
        rc = cli.main(["simulate", str(model), "-o", str(out), "--no-pictures", "--no-series"])
        assert rc == 0
        summary = json.loads((out / "summary.json").read_text())
        assert summary["steps"] == 100
        times[on] = summary["time"]
    assert times[True] > 10 * times[False]


def test_the_factor_of_safety_is_the_same_with_and_without():
    # A slab 5 cm thick keeps the run without scaling short; mass scaling still raises
    # its step tenfold. The slab rides on the block, which slides at tan 35° / tan 30°.
    fos = '[[stages]]\ntype = "solve"\n[[stages]]\ntype = "factor_of_safety"\nmax_steps = 4000\n'
    text = sliver(0.05)
    assert (
        Engine(pm.prepare(scaled(text, True))).timestep
        > 5 * Engine(pm.prepare(scaled(text, False))).timestep
    )
    exact = math.tan(math.radians(35)) / math.tan(math.radians(30))
    found = {}
    for on in (False, True):
        safety = pm.simulate(scaled(text, on) + fos).safety
        assert safety.stable < exact + 0.01
        assert safety.failing > exact - 0.01
        found[on] = (safety.stable, safety.failing)
    # the same bracket, within the search's resolution
    assert found[True][0] == pytest.approx(found[False][0], abs=0.011)
    assert found[True][1] == pytest.approx(found[False][1], abs=0.011)


@pytest.mark.parametrize("value", ['"yes"', "1", "0.5"])
def test_a_value_other_than_true_or_false_is_refused_naming_the_field(value):
    with pytest.raises(ModelError) as info:
        pm.parse_model(incline() + f"[mechanics]\nmass_scaling = {value}\n")
    assert info.value.field == "mechanics.mass_scaling"
    assert "true or false" in str(info.value)


SOLVE_SAVE = '[[stages]]\ntype = "solve"\n[[stages]]\ntype = "save"\nfile = "settled.json"\n'
AFTER = '[[stages]]\ntype = "cycle"\nsteps = 10\n'


def run(tmp_path: Path, text: str, out: str, *flags: str) -> int:
    model = tmp_path / f"{out}.toml"
    model.write_text(text)
    quiet = ["--no-pictures", "--no-series"]
    return cli.main(["simulate", str(model), "-o", str(tmp_path / out), *quiet, *flags])


@pytest.mark.parametrize("first", [False, True])
def test_a_restart_with_the_other_setting_is_refused(tmp_path, capsys, first):
    text = incline()
    assert run(tmp_path, scaled(text, first) + SOLVE_SAVE + AFTER, "first") == 0
    saved = tmp_path / "first" / "settled.json"
    capsys.readouterr()
    rc = run(
        tmp_path, scaled(text, not first) + SOLVE_SAVE + AFTER, "again", "--restart", str(saved)
    )
    err = capsys.readouterr().err
    assert rc == 1, err
    expected = f"mechanics.mass_scaling: the model says {str(not first).lower()}, the file "
    assert expected + str(first).lower() in err, err
    # The same setting restarts.
    rc = run(tmp_path, scaled(text, first) + SOLVE_SAVE + AFTER, "same", "--restart", str(saved))
    assert rc == 0, capsys.readouterr().err


def test_a_restart_file_from_before_the_setting_had_none(tmp_path, capsys):
    # A note written before mass_scaling was a setting: the run had no mass scaling.
    import penedge

    text = incline() + SOLVE_SAVE + AFTER
    assert run(tmp_path, text, "first") == 0
    sim = penedge.Simulation.load(tmp_path / "first" / "settled.json")
    note = json.loads(sim.note)
    del note["settings"]["mechanics.mass_scaling"]
    older = tmp_path / "older.json"
    sim.save(str(older), note=json.dumps(note))
    capsys.readouterr()
    rc = run(tmp_path, scaled(incline(), True) + SOLVE_SAVE + AFTER, "on", "--restart", str(older))
    err = capsys.readouterr().err
    assert rc == 1, err
    assert "mechanics.mass_scaling: the model says true, the file false" in err, err
    assert run(tmp_path, text, "off", "--restart", str(older)) == 0


#: Excavates the incline's block (its centroid near z = 5.2; the sliver's is at 7.9975, the
#: fixed rock's near 2), leaving the sliver alone free on the rock.
EXCAVATE_THE_BLOCK = """
[[stages]]
type = "excavate"
region = {type = "box", min = [0, 0, 3.5], max = [10, 2, 7.9]}
relax_steps = 1
"""


def test_an_excavate_stage_rescales_from_the_blocks_that_stay():
    # Before, the sliver is scaled up to the block's step (the median of the two free
    # blocks); once the block is excavated the sliver is the only free block, its own step
    # is the median and it is no longer scaled: the time step is the one without mass
    # scaling (the sliver's true one), not the scaled one of before.
    from penedge.model.run import Runner

    steps = {}
    for on in (False, True):
        setup = pm.prepare(scaled(sliver(), on) + EXCAVATE_THE_BLOCK)
        runner = Runner(setup, Engine)
        engine = runner.engine
        before = engine.timestep
        runner.run_stage(0, setup.model.stages[0])
        removed = engine.removed()
        assert removed.sum() == 1
        assert not removed[~setup.layout.fixed].all()  # the sliver stays
        assert engine.sim.mass_scaling == on
        steps[on] = (before, engine.timestep)
    assert steps[True][0] > 10 * steps[False][0]
    assert steps[True][1] == steps[False][1] == steps[False][0]


def test_an_old_restart_file_that_scaled_nothing_is_scaled_again(tmp_path):
    # A restart file from before restart files kept the switch reads as on only if it
    # scaled some body; the incline has one free block, which the median never scales. A
    # model that says mass_scaling = true turns it on again on restoring it.
    import penedge

    text = scaled(incline(), True) + SOLVE_SAVE + AFTER
    assert run(tmp_path, text, "first") == 0
    saved = tmp_path / "first" / "settled.json"
    state = json.loads(saved.read_text())
    assert state["settings"]["mass_scaling"] is True
    del state["settings"]["mass_scaling"]
    older = tmp_path / "older.json"
    older.write_text(json.dumps(state))
    assert not penedge.Simulation.load(older).mass_scaling
    engine = Engine(pm.prepare(text))
    engine.restore(older)
    assert engine.sim.mass_scaling
