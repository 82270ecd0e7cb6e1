"""``penedge simulate --restart`` refuses a model whose settings or stages up to the save
differ from those of the run that wrote the restart file (docs/models.md, "Restart"), and
a restart whose save stage is not the model's; the stages after the save may change.

The model: a 100 m³ block (2500 kg/m³) on a plane dipping 30° towards the East, the rock
below it fixed; limit equilibrium F = tan φ / tan 30° (dry, no cohesion)."""

import json
import math
from pathlib import Path

import pytest
from incline_model import incline

import penedge
from penedge import cli

INCLINE = incline()

SOLVE_SAVE = """
[[stages]]
type = "solve"
[[stages]]
type = "save"
file = "settled.json"
"""

AFTER = """
[[stages]]
type = "cycle"
steps = 10
"""

QUIET = ["--no-pictures", "--no-series"]


def limit(friction: float) -> float:
    """F of the block on the 30° plane by limit equilibrium (dry, cohesionless)."""
    return math.tan(math.radians(friction)) / math.tan(math.radians(30))


def run(tmp_path: Path, text: str, out: str, *flags: str) -> int:
    model = tmp_path / f"{out}.toml"
    model.write_text(text)
    return cli.main(["simulate", str(model), "-o", str(tmp_path / out), *QUIET, *flags])


@pytest.fixture(scope="module")
def settled(tmp_path_factory) -> Path:
    """The restart file of the incline settled with its own settings."""
    tmp = tmp_path_factory.mktemp("settled")
    assert run(tmp, INCLINE + SOLVE_SAVE + AFTER, "first") == 0
    return tmp / "first" / "settled.json"


def restart(tmp_path: Path, text: str, saved: Path, capsys, *flags: str) -> tuple[int, str]:
    capsys.readouterr()
    rc = run(tmp_path, text, "again", "--restart", str(saved), *flags)
    return rc, capsys.readouterr().err


@pytest.mark.parametrize(
    ("edit", "expected"),
    [
        (
            lambda t: t.replace("friction = 35", "friction = 45"),
            "joint_properties.default.friction: the model says 45, the file 35",
        ),
        (
            lambda t: t + "[seismic]\ncoefficient = 0.05\nazimuth = 90\n",
            "seismic: the model says {coefficient 0.05, azimuth 90, vertical 0}, the file none",
        ),
        (
            lambda t: t + "[water.pressure]\nslide = 10e3\n",
            "water: the model says {density 1000, pressures {slide 10000}}, the file none",
        ),
        (
            lambda t: t.replace("density = 2500", "density = 2600"),
            "rock.density: the model says 2600, the file 2500",
        ),
        (
            lambda t: t + "[mechanics]\ndamping = 0.7\n",
            "mechanics.damping: the model says 0.7, the file 0.8",
        ),
        (
            lambda t: t + "[mechanics]\ngravity = [0, 0, -9.5]\n",
            "mechanics.gravity: the model says (0, 0, -9.5), the file (0, 0, -9.81)",
        ),
        (
            # the block above the plane fixed, the rock below it free
            lambda t: t.replace('region = {type = "below"', 'region = {type = "above"'),
            "fixed in the model, free in the file",
        ),
        (
            lambda t: t.replace('type = "solve"', 'type = "solve"\nratio = 1e-6'),
            "stages[0].ratio: the model says 1e-06, the file 1e-05",
        ),
    ],
)
def test_a_restart_with_other_settings_is_refused_naming_each(
    tmp_path, capsys, settled, edit, expected
):
    # The stages after the save are the same; a setting that acts before it is not.
    rc, err = restart(tmp_path, edit(INCLINE + SOLVE_SAVE) + AFTER, settled, capsys)
    assert rc == 1, err
    assert "--restart" in err, err
    assert expected in err, err
    assert not (tmp_path / "again").exists()  # refused before anything is written
    rc, err = restart(tmp_path, edit(INCLINE + SOLVE_SAVE) + AFTER, settled, capsys, "--check")
    assert rc == 1
    assert expected in err, err


def test_an_older_restart_file_is_checked_on_the_state_it_holds(tmp_path, capsys, settled):
    # A file written before the note kept the settings: the gravity (with [seismic]), the
    # damping and the masses of its simulation are compared with the model's.
    sim = penedge.Simulation.load(settled)
    note = json.loads(sim.note)
    del note["settings"], note["stages_run"]
    older = tmp_path / "older.json"
    sim.save(str(older), note=json.dumps(note))
    quake = INCLINE + "[seismic]\ncoefficient = 0.05\nazimuth = 90\n" + SOLVE_SAVE + AFTER
    rc, err = restart(tmp_path, quake, older, capsys)
    assert rc == 1, err
    assert f"mechanics.gravity (with [seismic]): the model says ({0.05 * 9.81:g}, " in err, err
    assert "-9.81), the file (0, 0, -9.81)" in err, err
    heavier = INCLINE.replace("density = 2500", "density = 2600") + SOLVE_SAVE + AFTER
    rc, err = restart(tmp_path, heavier, older, capsys)
    assert rc == 1, err
    assert "rock.density: the model says 2600, the file 2500" in err, err
    # The same model still restarts from it.
    rc, err = restart(tmp_path, INCLINE + SOLVE_SAVE + AFTER, older, capsys)
    assert rc == 0, err


def test_a_strength_is_refused_before_the_save_and_taken_after_it(tmp_path, capsys, settled):
    # Settle once, then try another strength. In [joint_properties] it would have acted
    # before the save: refused (it was ignored, and F came out tan 35° / tan 30° = 1.21).
    fos = '[[stages]]\ntype = "factor_of_safety"\nmax_steps = 4000\n'
    stronger = INCLINE.replace("friction = 35", "friction = 45")
    rc, err = restart(tmp_path, stronger + SOLVE_SAVE + fos, settled, capsys)
    assert rc == 1, err
    assert "joint_properties.default.friction: the model says 45, the file 35" in err, err
    # A properties stage after the save, then the factor of safety from the saved state:
    # F = tan 45° / tan 30° = 1.732.
    later = '[[stages]]\ntype = "properties"\nfriction = 45\n' + fos
    rc, err = restart(tmp_path, INCLINE + SOLVE_SAVE + later, settled, capsys, "--json")
    assert rc == 0, err
    summary = json.loads((tmp_path / "again" / "summary.json").read_text())
    f = summary["stages"][-1]["factor_of_safety"]
    assert f["stable"] <= limit(45) <= f["failing"] + 1e-9, f


@pytest.mark.parametrize(
    ("stages", "there"),
    [
        # the save stage removed: stages[1] is now the stage after it
        ('[[stages]]\ntype = "solve"\n' + AFTER, "this model's stage 1 is stages[1], a cycle"),
        # a stage inserted before the save: the save is stages[2]
        (
            '[[stages]]\ntype = "solve"\n[[stages]]\ntype = "cycle"\nsteps = 5\n'
            '[[stages]]\ntype = "save"\nfile = "settled.json"\n' + AFTER,
            "this model's stage 1 is stages[1], a cycle stage (its save stages are stages[2])",
        ),
    ],
)
def test_a_restart_whose_save_stage_is_not_the_models_is_refused(
    tmp_path, capsys, settled, stages, there
):
    rc, err = restart(tmp_path, INCLINE + stages, settled, capsys)
    assert rc == 1, err
    assert "--restart" in err, err
    assert "written by the save stage stages[1]" in err, err
    assert there in err, err
