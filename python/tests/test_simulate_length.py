"""How long a run is (docs/models.md, "How long a run is"): the time step, steps, history
points and frames that ``penedge simulate --check`` states before any step, the stages
refused for taking more than 1e8 steps, the line a long run starts with, the history's
memory per point, and ``Simulation.run_until``'s bound."""

import json
import math
import signal
import tracemalloc
from pathlib import Path

import pytest

import penedge
import penedge.model as pm
from penedge import cli
from penedge.model import engine as engines
from penedge.model.run import Runner

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
COLUMN = (EXAMPLES / "block_column.toml").read_text()
BASE = COLUMN[: COLUMN.index("[[stages]]")]  # history_every = 5, a monitor "top"


def simulate(tmp_path: Path, stages: str, *flags: str, base: str = BASE) -> int:
    """``penedge simulate`` on the block column with these stages, into tmp_path/out."""
    model = tmp_path / "column.toml"
    model.write_text(base + stages)
    return cli.main(["simulate", str(model), "-o", str(tmp_path / "out"), *flags])


def column_timestep() -> float:
    return engines.Engine(pm.prepare(pm.parse_model(COLUMN))).timestep


STAGES = (
    '[[stages]]\ntype = "time"\ntime = 0.5\n'
    '[[stages]]\ntype = "cycle"\nsteps = 1000\n'
    '[[stages]]\ntype = "solve"\n'
    '[[stages]]\ntype = "factor_of_safety"\nmax_steps = 2000\n'
)


def test_check_states_the_time_step_and_what_each_stage_takes(tmp_path, capsys):
    # --check said only "the model is valid": not the time step, not the steps of a
    # time stage (a time = 1e6 s ran 4.6e9 steps, a week), not the history or frames.
    assert simulate(tmp_path, STAGES, "--check") == 0
    lines = [" ".join(line.split()) for line in capsys.readouterr().out.splitlines()]
    dt = column_timestep()
    steps = math.ceil(0.5 / dt - 1e-9)
    assert f"time step {dt:.3g} s (at the start)" in lines, lines
    assert f"steps stages[0] time {steps:,} steps, undamped" in lines, lines
    assert "steps stages[1] cycle 1,000 steps, local damping 0.8" in lines
    assert "steps stages[2] solve at most 100,000 steps" in lines
    # F = 1; 2, 4, 8, 10 (or 0.5 ... 0.1); at most 9 halvings of a bracket of 5 to 0.01
    assert "steps stages[3] factor_of_safety at most 14 trials of at most 2,000 steps" in lines
    points = 1 + math.ceil(steps / 5) + 200 + 20_000
    assert any(line.startswith(f"history at most {points:,} history points") for line in lines)
    frames = 1 + 3  # the start, the end of each stage that steps (frame_every = 0)
    assert f"series at most {frames} ParaView frames ({2 * frames + 2} files)" in lines, lines
    assert not (tmp_path / "out").exists()
    assert simulate(tmp_path, STAGES, "--check", "--json") == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["time_step"] == dt
    assert [(p["kind"], p["steps"], p["exact"]) for p in summary["plan"]] == [
        ("time", steps, True),
        ("cycle", 1000, True),
        ("solve", 100_000, False),
        ("factor_of_safety", 2000, False),
    ]
    assert summary["history_points"] == points


def test_a_time_stage_of_more_than_1e8_steps_is_refused_by_check_and_run(tmp_path, capsys):
    stages = '[[stages]]\ntype = "solve"\n[[stages]]\ntype = "time"\nname = "creep"\ntime = 1e6\n'
    dt = column_timestep()
    steps = math.ceil(1e6 / dt - 1e-9)
    expected = (
        f"penedge: error: stages[1].time: creep (time) runs 1e+06 s, {steps:,} steps of "
        f"{dt:.3g} s: more than 1e+08 (the most steps a stage may take"
    )
    assert simulate(tmp_path, stages, "--check") == 1
    checked = capsys.readouterr()
    assert checked.err.startswith(expected), checked.err
    assert simulate(tmp_path, stages, "--no-pictures") == 1
    assert capsys.readouterr().err == checked.err
    assert not (tmp_path / "out").exists()  # refused before any step
    # just under 1e8 steps is taken (checked only, not run)
    stages = f'[[stages]]\ntype = "time"\ntime = {0.99e8 * dt!r}\n'
    assert simulate(tmp_path, stages, "--check", "-q") == 0


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ('[[stages]]\ntype = "cycle"\nsteps = 1_000_000_000_000\n', "stages[0].steps"),
        ('[[stages]]\ntype = "solve"\nmax_steps = 1_000_000_000_000_000\n', "stages[0].max_steps"),
        ("[mechanics]\nmax_steps = 100_000_001\n", "mechanics.max_steps"),
        (
            '[[stages]]\ntype = "factor_of_safety"\nmax_steps = 200_000_000\n',
            "stages[0].max_steps",
        ),
    ],
)
def test_a_step_count_above_1e8_is_refused(text, field):
    refused = r"must be at most 1e\+08, got .*most steps a stage"
    with pytest.raises(pm.ModelError, match=refused) as e:
        pm.parse_model(BASE + text)
    assert e.value.field == field


def test_a_run_of_many_files_is_warned_of(tmp_path, capsys):
    # frame_every = 1 on 6000 steps: some 12,000 files in the series folder, silently.
    base = BASE.replace("history_every = 5", "history_every = 5\nframe_every = 1")
    stages = '[[stages]]\ntype = "cycle"\nsteps = 6000\n'
    assert simulate(tmp_path, stages, "--check", base=base) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert (
        "warning [results] frame_every = 1 writes up to 6,002 ParaView frames, 12,006 files "
        "in the series folder: raise frame_every"
    ) in out, out
    assert simulate(tmp_path, stages, "--check", "--no-series", base=base) == 0
    assert "warning" not in capsys.readouterr().out


class Idle(engines.Engine):
    """The engine, taking no step (what a long run says at its start, without its steps)."""

    def cycle(self, steps):
        pass


def test_a_long_run_says_at_its_start_what_it_takes(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(engines, "Engine", Idle)
    base = BASE.replace("history_every = 5", "history_every = 500_000")
    stages = '[[stages]]\ntype = "cycle"\nsteps = 2_000_000\n'
    assert simulate(tmp_path, stages, "--no-pictures", "--no-series", base=base) == 0
    err = capsys.readouterr().err
    dt = column_timestep()
    assert err.startswith(
        f"penedge simulate: a long run: time step {dt:.3g} s; stages[0] cycle 2,000,000 steps, "
        "local damping 0.8; "
        "at most 5 history points"
    ), err
    short = '[[stages]]\ntype = "cycle"\nsteps = 1000\n'
    assert simulate(tmp_path, short, "--no-pictures", "--no-series", base=base) == 0
    assert capsys.readouterr().err == ""  # a short run says nothing


def test_the_history_keeps_a_few_bytes_a_point():
    # A list of Python floats and a tuple of numpy scalars per monitored point: some 500
    # bytes a point (a long time stage grew by 0.8 MB/s); numpy columns: 8 a number.
    setup = pm.prepare(
        pm.parse_model(
            BASE.replace("history_every = 5", "history_every = 1")
            + '[[stages]]\ntype = "cycle"\nsteps = 20000\n'
        )
    )
    runner = Runner(setup, Idle)
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        outcome = runner.run()
        after = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    points = len(outcome.history.step)
    assert points == 20_001
    per_point = (after - before) / points
    # 10 numbers (step, time, ratio, kinetic energy, the monitor's 6) and the stage's name,
    # in arrays at most half empty: at most 2 x 88 bytes
    assert per_point < 180, per_point
    rows = outcome.history.rows()
    assert rows[-1]["step"] == 0
    assert set(rows[-1]) >= {"top.dx", "top.vz"}


def test_run_until_refuses_more_steps_than_step_takes():
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0)
    sim.fix([0])
    # A step of 1e-300 is refused since 2026-11-29 (below 2**-52 of the critical step,
    # docs/mechanics.md "The smallest time step"); 1e-19 is taken, and run_until(1.0) would
    # take 1e19 steps.
    with pytest.raises(penedge.MechanicsError, match="2\\^-52 of the undamped") as small:
        sim.set_timestep(1e-300)
    assert small.value.kind == "time_step_too_small"
    sim.set_timestep(1e-19)  # accepted: below the critical step, above its rounding

    def ran_on(signum, frame):  # run_until looks for signals between its chunks
        raise AssertionError("run_until(1.0) took on its 1e19 steps")

    alarm = signal.signal(signal.SIGALRM, ran_on)
    signal.setitimer(signal.ITIMER_REAL, 5.0)
    try:
        refused = r"run_until\(1e0\) takes 1\.000e19 steps"
        with pytest.raises(penedge.InputError, match=refused) as e:
            sim.run_until(1.0)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, alarm)
    assert e.value.kind == "out_of_range"
    assert "more than step(n) takes (2**63 - 1)" in str(e.value)
    assert sim.steps == 0
    sim.set_timestep(1e-4)
    sim.run_until(1.05e-3)  # 11 steps
    assert sim.steps == 11
