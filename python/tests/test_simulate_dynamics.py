"""``time`` and ``cycle`` stages and their damping (docs/models.md, stages): a ``time``
stage is model time, undamped unless it says otherwise, so that a block sliding down a plane
follows ``x = a t² / 2``; a ``cycle`` stage takes ``[mechanics] damping``; each says what it
stepped with."""

import json
import math
import re

import numpy as np
import pytest

import penedge.model as pm
from penedge import cli
from penedge.model.run import Outcome

SLOPE, FRICTION = 30.0, 20.0
G = 9.81

# A 1 m block on a fixed base, gravity tilted by SLOPE about y (the plane's dip), a fixed
# block beside it on the uphill side: it slides downhill (-x) from rest.
SLIDER = f"""
[domain]
type = "box"
min = [8, 0, 0]
max = [10, 1, 1.25]

[[joints]]
type = "plane"
name = "bed"
point = [0, 0, 1]
dip = 0
dip_direction = 0

[[joints]]
type = "plane"
name = "cut"
point = [9, 0, 0]
dip = 90
dip_direction = 90

[rock]
density = 2500

[mechanics]
gravity = [{-G * math.sin(math.radians(SLOPE))!r}, 0, {-G * math.cos(math.radians(SLOPE))!r}]
{{mechanics}}

[joint_properties.default]
kn = 1e10
ks = 1e10
friction = {FRICTION}

[[boundary]]
region = {{{{type = "below", z = 1}}}}
condition = "fixed"

[[boundary]]
region = {{{{type = "box", min = [9, 0, 1], max = [10, 1, 1.25]}}}}
condition = "fixed"
"""


def run(stages: str, mechanics: str = "") -> tuple[float, Outcome]:
    """The slider's displacement along x at the end of `stages`, and the outcome."""
    outcome = pm.simulate(SLIDER.format(mechanics=mechanics) + stages)
    free = np.flatnonzero(outcome.free)
    assert len(free) == 1
    return float(outcome.displacement[free[0], 0]), outcome


def slide(t: float) -> float:
    """The distance slid in `t` seconds from rest: ``a t² / 2``, ``a = g (sin θ − cos θ
    tan φ)``."""
    theta, phi = math.radians(SLOPE), math.radians(FRICTION)
    return 0.5 * G * (math.sin(theta) - math.cos(theta) * math.tan(phi)) * t * t


def test_a_time_stage_is_undamped_by_default_and_slides_as_the_closed_form():
    t = 0.2
    dx, outcome = run(f'[[stages]]\ntype = "time"\ntime = {t}\n')
    # The stage's model time is t to within a step.
    assert outcome.time == pytest.approx(t, abs=1e-4)
    assert -dx == pytest.approx(slide(outcome.time), rel=0.01)
    assert outcome.stages[0].damping == 0.0


def test_a_time_stage_takes_the_damping_it_is_given():
    t = 0.2
    dx, outcome = run(f'[[stages]]\ntype = "time"\ntime = {t}\ndamping = 0.8\n')
    assert outcome.stages[0].damping == 0.8
    # Local damping 0.8 takes 0.8 of the unbalanced force off while it moves: far short.
    assert 0 < -dx < 0.5 * slide(outcome.time)


def test_a_cycle_stage_takes_the_mechanics_damping_unless_it_says_otherwise():
    stages = '[[stages]]\ntype = "cycle"\nsteps = 2000\n'
    damped, outcome = run(stages)
    assert outcome.stages[0].damping == 0.8
    free, outcome = run(stages + "damping = 0\n")
    assert outcome.stages[0].damping == 0.0
    assert -free == pytest.approx(slide(outcome.time), rel=0.01)
    assert 0 < -damped < 0.5 * -free
    # [mechanics] damping sets it too; the engine's damping is the model's after the stage.
    again, outcome = run(stages, mechanics="damping = 0")
    assert again == free


def simulate(tmp_path, capsys, text: str, *args: str) -> str:
    """``penedge simulate`` on the model `text` (results in tmp_path/out, no pictures, or
    as `args` say): what it printed, on one line."""
    model = tmp_path / "model.toml"
    model.write_text(text, encoding="utf-8")
    options = args or ("-o", str(tmp_path / "out"), "--no-pictures")
    assert cli.main(["simulate", str(model), *options]) == 0
    return " ".join(capsys.readouterr().out.split())


TWO_STAGES = '[[stages]]\ntype = "cycle"\nsteps = 100\n[[stages]]\ntype = "time"\ntime = 0.01\n'


def test_the_summary_says_what_each_stepping_stage_was_damped_with(tmp_path, capsys):
    out = simulate(tmp_path, capsys, SLIDER.format(mechanics="") + TWO_STAGES)
    assert "stages[0] cycle: 100 steps, local damping 0.8" in out
    assert re.search(r"stages\[1\] time: [\d,]+ steps, undamped", out), out


@pytest.mark.parametrize("bad", ["-0.1", "1", "1.5", '"high"'])
def test_a_stage_damping_outside_0_1_is_refused_naming_it(bad):
    text = SLIDER.format(mechanics="") + f'[[stages]]\ntype = "time"\ntime = 0.1\ndamping = {bad}\n'
    with pytest.raises(pm.ModelError) as info:
        pm.parse_model(text)
    assert "stages[0].damping" in str(info.value)


def test_a_factor_of_safety_of_blocks_nothing_holds_says_to_support_them(tmp_path, capsys):
    # The base is left free as well: it falls, and the slider with it (only the uphill
    # block is fixed). A higher strength cannot hold a falling block: the summary said to
    # "solve with a higher strength".
    text = SLIDER.format(mechanics="").replace(
        '[[boundary]]\nregion = {type = "below", z = 1}\ncondition = "fixed"\n', ""
    )
    assert text.count("[[boundary]]") == 1
    stages = (
        '[[stages]]\ntype = "solve"\nmax_steps = 50\n'
        '[[stages]]\ntype = "factor_of_safety"\nmax_steps = 50\n'
    )
    out = simulate(tmp_path, capsys, text + stages)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    f = summary["stages"][1]["factor_of_safety"]
    # Every free block (the two base blocks and the slider) falls: no contact force on any.
    free = np.flatnonzero(~pm.prepare(text + stages).layout.fixed).tolist()
    assert len(free) == 3
    assert f["unheld_blocks"] == free
    ids = ", ".join(map(str, f["unheld_blocks"]))
    assert f"blocks {ids} were held by no contact (falling freely)" in out
    assert "support them (bolts, a boundary)" in out
    assert "solve with a higher strength" not in out


def test_a_block_slides_across_a_joint_of_its_base_as_on_one_plane():
    # The joint x = 8 runs on through the base: the slider's downhill edge starts on it,
    # over the edge of the base block beyond. The two edges lie where the bed and that joint
    # cross: the contact had a nominal strip on the cone rule's 45° normal and pushed the
    # slider back (30 % short at 0.2 s, 7 % at 1 s: a tester's finding); it bears only past
    # half the detection gap now (docs/mechanics.md, "Where joints cross").
    text = SLIDER.format(mechanics="").replace("min = [8, 0, 0]", "min = [0, 0, 0]")
    text += (
        '\n[[joints]]\ntype = "plane"\nname = "cut2"\npoint = [8, 0, 0]\ndip = 90\n'
        "dip_direction = 90\n"
    )
    stages = (
        '[[stages]]\ntype = "excavate"\nregion = {type = "box", min = [0, 0, 1], '
        "max = [8, 1, 1.25]}\nrelax_steps = 1\n"
        '[[stages]]\ntype = "time"\ntime = 0.2\n'
    )
    outcome = pm.simulate(text + stages)
    free = np.flatnonzero(outcome.free)
    assert len(free) == 1
    dx = float(outcome.displacement[free[0], 0])
    assert -dx == pytest.approx(slide(outcome.stages[1].time), rel=0.01)


def test_a_light_block_falling_beside_a_held_heavy_one_is_named_unheld():
    # The base is cut at z = 0.5 (fixed below). The block under the slider is excavated:
    # the slider (625 kg) falls, held by nothing, while the block beside it (1,250 kg)
    # rests on the fixed base. The ratio is the largest unbalanced force over the largest
    # weight of a free block, here about 0.5: the light falling block gave no hint that
    # nothing holds it (a reviewer's case: "solve with a higher strength" again).
    text = SLIDER.format(mechanics="").replace("z = 1}", "z = 0.5}")
    text += (
        '\n[[joints]]\ntype = "plane"\nname = "low"\npoint = [0, 0, 0.5]\ndip = 0\n'
        "dip_direction = 0\n"
    )
    stages = (
        '[[stages]]\ntype = "excavate"\nregion = {type = "box", min = [8, 0, 0.5], '
        "max = [9, 1, 1]}\nrelax_steps = 1\n"
        '[[stages]]\ntype = "solve"\nmax_steps = 50\n'
        '[[stages]]\ntype = "factor_of_safety"\nmax_steps = 50\n'
    )
    setup = pm.prepare(text + stages)
    # The slider: the block above the bed (z = 1) under which the rock is excavated.
    centroids = setup.blocks.centroids
    slider = np.flatnonzero((centroids[:, 2] > 1) & (centroids[:, 0] < 9)).tolist()
    assert len(slider) == 1
    outcome = pm.simulate(setup)
    f = outcome.stages[2].safety
    assert f is not None
    assert not f.in_equilibrium
    assert f.start_ratio < 0.99
    free = np.flatnonzero(outcome.free).tolist()
    assert len(free) == 2  # the slider and the block beside the excavated one
    assert f.unheld_blocks == slider


def test_the_check_and_a_stopped_stage_say_the_damping_too(tmp_path, capsys):
    out = simulate(tmp_path, capsys, SLIDER.format(mechanics="") + TWO_STAGES, "--check")
    assert "stages[0] cycle 100 steps, local damping 0.8" in out
    assert re.search(r"stages\[1\] time [\d,]+ steps, undamped", out), out
    # A stage the engine stopped (its summary entry as run_summary writes it).
    from penedge.cli.simulate import stage_text

    stopped = {"name": "s", "kind": "time", "stopped": "error", "steps": 12, "damping": 0.0}
    assert stage_text(stopped) == "s time: stopped by the engine after 12 steps, undamped"
