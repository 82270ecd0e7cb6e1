"""``penedge simulate --restart`` refuses a model whose settings or stages up to the save
differ from those of the run that wrote the restart file (docs/models.md, "Restart"), and
a restart whose save stage is not the model's; the stages after the save may change.

The model: a 100 m³ block (2500 kg/m³) on a plane dipping 30° towards the East, the rock
below it fixed; limit equilibrium F = tan φ / tan 30° (dry, no cohesion)."""

import math
from pathlib import Path

import pytest

from penedge import cli

INCLINE = """
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 2, 8]
[[joints]]
type = "plane"
name = "slide"
point = [5, 1, 3]
dip = 30
dip_direction = 90
[rock]
density = 2500
[joint_properties.default]
kn = 1e9
ks = 1e8
friction = 35
[[boundary]]
region = {type = "below", point = [5, 1, 3], dip = 30, dip_direction = 90}
condition = "fixed"
"""

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
