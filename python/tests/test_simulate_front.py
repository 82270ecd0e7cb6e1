"""The front end of ``penedge simulate`` (docs/models.md): strict JSON outputs, save files
checked before any step, stages that cannot run refused up front, the factor-of-safety
range and the verdict of a restarted run."""

import json
from pathlib import Path

import pytest

import penedge
import penedge.model as pm
from penedge import cli
from penedge.model.engine import Engine
from penedge.model.run import Runner

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
COLUMN = (EXAMPLES / "block_column.toml").read_text()
BASE = COLUMN[: COLUMN.index("[[stages]]")]
QUIET = ["--no-pictures", "--no-series"]


def strict(text: str) -> dict:
    """`text` read as strict JSON: Infinity and NaN are refused."""

    def refuse(constant: str) -> None:
        raise ValueError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def simulate(tmp_path: Path, stages: str, *flags: str, base: str = BASE) -> int:
    """Runs ``penedge simulate`` on the block column with these stages into tmp_path/out."""
    model = tmp_path / "column.toml"
    model.write_text(base + stages)
    return cli.main(["simulate", str(model), "-o", str(tmp_path / "out"), *QUIET, *flags])


@pytest.mark.parametrize(
    ("stages", "base"),
    [
        ('[[stages]]\ntype = "properties"\nfriction = 20\n', BASE),
        ('[[stages]]\ntype = "reset"\n', BASE),
        # No gravity: nothing pushes the blocks, the ratio has nothing to divide by.
        ('[[stages]]\ntype = "cycle"\nsteps = 10\n', BASE + "[mechanics]\ngravity = [0, 0, 0]\n"),
    ],
)
def test_the_summary_is_strict_json_when_the_ratio_is_not_finite(tmp_path, capsys, stages, base):
    simulate(tmp_path, stages, "--json", base=base)
    printed = strict(capsys.readouterr().out)
    written = strict((tmp_path / "out" / "summary.json").read_text())
    assert printed["ratio"] is None
    assert written["ratio"] is None
    assert written["stages"][0]["ratio"] is None


CYCLE_THEN_SAVE = '[[stages]]\ntype = "cycle"\nsteps = 20\n[[stages]]\ntype = "save"\nfile = "{}"\n'


@pytest.mark.parametrize(
    ("file", "problem"),
    [("nodir/s.json", "no folder"), ("taken", "is a folder"), ("plain/s.json", "not a folder")],
)
def test_a_save_that_cannot_write_is_refused_before_any_step(tmp_path, capsys, file, problem):
    (tmp_path / "out" / "taken").mkdir(parents=True)
    (tmp_path / "out" / "plain").write_text("a file, not a folder")
    assert simulate(tmp_path, CYCLE_THEN_SAVE.format(file)) == 1
    err = capsys.readouterr().err
    assert "stages[1].file: cannot write the restart file" in err, err
    assert problem in err, err
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["plain", "taken"]


def test_a_save_into_the_results_folder_to_be_made_runs(tmp_path, capsys):
    # An absolute path into the results folder, not made yet: the run makes it.
    saved = tmp_path / "out" / "s.json"
    assert simulate(tmp_path, CYCLE_THEN_SAVE.format(saved.as_posix())) == 0, capsys.readouterr()
    assert saved.exists()
    # The Python API with a results folder that does not exist: made for the save.
    folder = tmp_path / "new" / "results"
    pm.simulate(pm.prepare(BASE + CYCLE_THEN_SAVE.format("s.json")), folder=folder)
    assert (folder / "s.json").exists()


def test_check_refuses_a_save_that_cannot_write(tmp_path, capsys):
    assert simulate(tmp_path, CYCLE_THEN_SAVE.format("nodir/s.json"), "--check") == 1
    assert "stages[1].file: cannot write the restart file" in capsys.readouterr().err


def test_a_save_that_fails_during_the_run_keeps_the_results_so_far(tmp_path):
    folder = tmp_path / "results"
    folder.mkdir()
    setup = pm.prepare(BASE + CYCLE_THEN_SAVE.format("s.json"))
    runner = Runner(setup, Engine, folder=folder)
    # Replaced by a file after the checks: the save fails during the run.
    folder.rmdir()
    folder.write_text("not a folder any more")
    outcome = runner.run()
    assert "s.json" in outcome.error
    assert [(s.name, s.steps, s.stopped) for s in outcome.stages] == [
        ("stages[0]", 20, None),
        ("stages[1]", 0, "error"),
    ]
    assert outcome.steps == 20
    assert outcome.history.stage[-1] == "error"


@pytest.mark.parametrize(
    "file",
    ["summary.json", "history.csv", "history.png", "displacement.png", "failing.png",
     "steps.html", "./summary.json", "series", "series/blocks.pvd"],
)  # fmt: skip
def test_a_save_named_like_an_output_is_refused(tmp_path, capsys, file):
    assert simulate(tmp_path, CYCLE_THEN_SAVE.format(file)) == 1
    err = capsys.readouterr().err
    assert "stages[1].file" in err, err
    assert "choose another name" in err, err
    assert not (tmp_path / "out").exists()
    # An absolute path to the same file is the same file.
    absolute = (tmp_path / "out" / file).resolve()
    assert simulate(tmp_path, CYCLE_THEN_SAVE.format(absolute), "--check") == 1
    assert "choose another name" in capsys.readouterr().err


def test_a_save_beside_the_outputs_runs(tmp_path):
    assert simulate(tmp_path, CYCLE_THEN_SAVE.format("summary.json.restart")) == 0
    assert (tmp_path / "out" / "summary.json.restart").exists()
    assert (tmp_path / "out" / "summary.json").exists()


NOTHING_FREE = """
[[stages]]
type = "solve"
[[stages]]
type = "boundary"
region = {type = "all"}
condition = "fixed"
[[stages]]
type = "factor_of_safety"
"""


@pytest.mark.parametrize("check", [[], ["--check"]])
def test_a_factor_of_safety_without_a_free_block_is_refused_before_any_step(
    tmp_path, capsys, check
):
    assert simulate(tmp_path, NOTHING_FREE, *check) == 1
    err = capsys.readouterr().err
    assert "stages[2]: a factor of safety needs a free block" in err, err
    assert not (tmp_path / "out").exists()


def test_a_factor_of_safety_without_a_free_block_stops_at_its_stage():
    # Past the checks (the blocks fixed behind the runner's back), the stage itself says so
    # and the run keeps what the stage before it did.
    stages = '[[stages]]\ntype = "solve"\n[[stages]]\ntype = "factor_of_safety"\n'
    runner = Runner(pm.prepare(BASE + stages), Engine)
    runner.fixed[:] = True
    outcome = runner.run()
    assert outcome.error.startswith("stages[1]: a factor of safety needs a free block")
    assert [(s.kind, s.converged, s.stopped) for s in outcome.stages] == [
        ("solve", True, None),
        ("factor_of_safety", None, "error"),
    ]


SAVE_AND_GO_ON = CYCLE_THEN_SAVE.format("s.json") + '[[stages]]\ntype = "cycle"\nsteps = 20\n'


def test_check_reads_the_restart_file(tmp_path, capsys):
    missing = str(tmp_path / "nonexistent.json")
    assert simulate(tmp_path, SAVE_AND_GO_ON, "--check", "--restart", missing) == 1
    assert "nonexistent.json" in capsys.readouterr().err
    (tmp_path / "other.json").write_text("{}")
    other = str(tmp_path / "other.json")
    assert simulate(tmp_path, SAVE_AND_GO_ON, "--check", "--restart", other) == 1
    assert "other.json" in capsys.readouterr().err
    # A restart file of the model: checked, and the stages it would run are named.
    assert simulate(tmp_path, SAVE_AND_GO_ON) == 0
    saved = str(tmp_path / "out" / "s.json")
    capsys.readouterr()
    assert simulate(tmp_path, SAVE_AND_GO_ON, "--check", "--restart", saved) == 0
    lines = [" ".join(line.split()) for line in capsys.readouterr().out.splitlines()]
    assert f"restart from {saved}: runs stages[2] cycle" in lines
    assert simulate(tmp_path, SAVE_AND_GO_ON, "--check", "--restart", saved, "--json") == 0
    restart = strict(capsys.readouterr().out)["restart"]
    assert restart == {"file": saved, "stages": ["stages[2] cycle"]}


def test_a_restarted_run_gives_the_verdict_of_the_whole_run(tmp_path, capsys):
    # The column settles (a solve), is saved, then its middle block is excavated and the
    # blocks above fall: NOT stable (still moving at the end, though the solve reached
    # equilibrium), the restarted run too, for the same reasons.
    model = str(EXAMPLES / "column_excavation.toml")
    flags = [*QUIET, "--json"]
    assert cli.main(["simulate", model, "-o", str(tmp_path / "a"), *flags]) == 0
    whole = strict(capsys.readouterr().out)
    restart = ["--restart", str(tmp_path / "a" / "settled.json")]
    assert cli.main(["simulate", model, "-o", str(tmp_path / "b"), *restart, *flags]) == 0
    resumed = strict(capsys.readouterr().out)
    assert [s["kind"] for s in resumed["stages"]] == ["excavate", "cycle"]
    assert resumed["max_displacement"] == whole["max_displacement"]
    assert whole["stable"] is False
    assert resumed["stable"] is False
    assert resumed["not_stable_because"] == whole["not_stable_because"]
    assert any("still moving" in why for why in whole["not_stable_because"])


def test_a_solve_that_failed_before_the_restart_still_counts(tmp_path, capsys):
    stages = (
        '[[stages]]\ntype = "solve"\nmax_steps = 5\n'  # far from equilibrium after 5 steps
        '[[stages]]\ntype = "save"\nfile = "s.json"\n'
        '[[stages]]\ntype = "cycle"\nsteps = 5\n'  # no solve after the restart
    )
    assert simulate(tmp_path, stages, "--json") == 0
    whole = strict(capsys.readouterr().out)
    assert [s["converged"] for s in whole["stages"]] == [False, None, None]
    assert whole["stable"] is False
    failed = "stages[0] (the last solve) did not reach equilibrium"
    assert failed in whole["not_stable_because"]
    model, saved = str(tmp_path / "column.toml"), str(tmp_path / "out" / "s.json")
    again = ["simulate", model, "-o", str(tmp_path / "b"), *QUIET, "--json"]
    assert cli.main([*again, "--restart", saved]) == 0
    resumed = strict(capsys.readouterr().out)
    assert resumed["stable"] is False
    assert failed in resumed["not_stable_because"]  # the restart file kept it


def test_a_run_removes_the_results_of_an_earlier_run_and_nothing_else(tmp_path):
    out = tmp_path / "out"

    def run(stages: str, *flags: str, base: str = BASE) -> int:
        (tmp_path / "column.toml").write_text(base + stages)
        return cli.main(["simulate", str(tmp_path / "column.toml"), "-o", str(out), *flags])

    frames = BASE.replace("history_every = 5", "history_every = 5\nframe_every = 5")
    many = '[[stages]]\ntype = "cycle"\nsteps = 40\n'
    assert run(many, "--no-pictures", base=frames) == 0  # with the series
    series = out / "series"
    assert len(list(series.glob("blocks_*.vtu"))) > 2
    # What a run with a factor of safety and --html leaves, and the user's own files.
    for name in ("failing.png", "steps.html", "history.png", "displacement.png"):
        (out / name).write_text("from an earlier run")
    (out / "notes.txt").write_text("mine")
    (series / "mine.vtu").write_text("mine")
    (series / "blocks_7.vtu.keep").write_text("mine")
    (out / "own").mkdir()
    (out / "own" / "blocks_000001.vtu").write_text("mine, not in series/")
    # Now one frame per stage: the start and the end.
    assert run('[[stages]]\ntype = "cycle"\nsteps = 10\n', "--no-pictures") == 0
    assert sorted(p.name for p in series.glob("blocks_*.vtu")) == [
        "blocks_000000.vtu",
        "blocks_000001.vtu",
    ]
    for name in ("failing.png", "steps.html", "history.png", "displacement.png"):
        assert not (out / name).exists(), name
    assert (out / "notes.txt").read_text() == "mine"
    assert (series / "mine.vtu").read_text() == "mine"
    assert (series / "blocks_7.vtu.keep").exists()
    assert (out / "own" / "blocks_000001.vtu").exists()
    # Without a series, the earlier one goes (the folder too, once empty).
    (series / "mine.vtu").unlink()
    (series / "blocks_7.vtu.keep").unlink()
    assert run('[[stages]]\ntype = "cycle"\nsteps = 10\n', *QUIET) == 0
    assert not series.exists()
    assert (out / "summary.json").exists()
    assert (out / "history.csv").exists()


def test_a_time_step_above_the_critical_one_names_its_field(tmp_path, capsys):
    # A 1 m cube of 2500 kg on kn = 1e9 Pa/m oscillates with a period of
    # 2 pi sqrt(m / (kn A)) = 10 ms: a step of 1 s is far above the critical one.
    base = BASE + "[mechanics]\ntime_step = 1\n"
    assert simulate(tmp_path, '[[stages]]\ntype = "cycle"\nsteps = 10\n', base=base) == 1
    err = capsys.readouterr().err
    assert "error: mechanics.time_step: the time step 1 is not in (0, " in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("flags", [[], ["--json"]])
def test_check_refuses_a_time_step_above_the_critical_one_as_the_run_does(tmp_path, capsys, flags):
    # --check builds the engine as the run does before its first step: the engine's
    # refusal comes now, with the run's message and exit status, and nothing is written.
    base = BASE + "[mechanics]\ntime_step = 1\n"
    stages = '[[stages]]\ntype = "cycle"\nsteps = 10\n'
    assert simulate(tmp_path, stages, base=base) == 1
    run = capsys.readouterr()
    assert not (tmp_path / "out").exists()
    assert simulate(tmp_path, stages, "--check", *flags, base=base) == 1
    checked = capsys.readouterr()
    assert checked.out == ""
    assert checked.err == run.err
    assert checked.err.startswith("penedge: error: mechanics.time_step: the time step 1 is "), (
        checked.err
    )
    assert not (tmp_path / "out").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["column.toml"]


def test_a_time_step_a_stiffer_joint_makes_too_large_names_its_field():
    # 0.3 ms is below the critical step with kn = 1e9 (the engine takes it), not with
    # kn = 1e11: the critical step goes as 1 / sqrt(kn), ten times smaller.
    stages = (
        '[mechanics]\ntime_step = 3e-4\n[[stages]]\ntype = "cycle"\nsteps = 10\n'
        '[[stages]]\ntype = "properties"\nkn = 1e11\n[[stages]]\ntype = "cycle"\nsteps = 10\n'
    )
    outcome = Runner(pm.prepare(BASE + stages), Engine).run()
    assert outcome.error.startswith("mechanics.time_step: the time step 0.0003 is not in"), (
        outcome.error
    )
    assert [(s.steps, s.stopped) for s in outcome.stages] == [(10, None), (0, None), (0, "error")]


#: An error of the model of each kind found after reading it: (extra tables, stages, field).
ERRORS_AFTER_READING = [
    # a check that needs the blocks (check.resolve)
    ("[[monitors]]\nname = 'far'\npoint = [9, 9, 9]\n", "", "monitors[1].point"),
    # one of the stages (a region of no block)
    ("", '[[stages]]\ntype = "excavate"\nregion = {type = "blocks", ids = [99]}\n',
     "stages[0].region.ids"),
    # the generation's
    ("[options]\nmin_volume = -1\n", "", "options.min_volume"),
    # the engine's, building it (--check builds it too)
    ("[mechanics]\ntime_step = 1\n", "", "mechanics.time_step"),
    # before any of them (a save named like a result; penedge simulate's own check)
    ("", '[[stages]]\ntype = "save"\nfile = "summary.json"\n', "stages[0].file"),
]  # fmt: skip


@pytest.mark.parametrize(("extra", "stages", "field"), ERRORS_AFTER_READING)
def test_every_error_of_the_model_names_its_file(tmp_path, capsys, extra, stages, field):
    for check in [[], ["--check"]]:
        assert simulate(tmp_path, stages, *check, base=BASE + extra) == 1
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"penedge: error: {field}: "), err
        assert err.endswith(f"(in {tmp_path / 'column.toml'})"), err
        assert err.count("(in ") == 1, err


@pytest.mark.parametrize(("extra", "stages", "field"), ERRORS_AFTER_READING[:-1])
def test_the_python_api_names_the_model_file_as_the_command_does(tmp_path, extra, stages, field):
    model = tmp_path / "column.toml"
    model.write_text(BASE + extra + stages)
    # The engine's refusal comes when the simulation is built: pm.simulate.
    call = pm.simulate if field == "mechanics.time_step" else pm.prepare
    for source in (model, str(model)):
        with pytest.raises(penedge.SpecError) as raised:
            call(source)
        text = str(raised.value)
        assert text.startswith(f"{field}: "), text
        assert text.endswith(f" (in {model})"), text
        assert text.count("(in ") == 1, text
        assert raised.value.field == field
    # the generation's error keeps its class and kind
    if field == "options.min_volume":
        assert type(raised.value) is penedge.SpecError
        assert raised.value.kind == "negative"
    # TOML text names no file
    with pytest.raises(penedge.SpecError) as raised:
        call(BASE + extra + stages)
    assert "(in " not in str(raised.value)


SOLVE = '[[stages]]\ntype = "solve"\n'


def properties(**changes: float) -> str:
    return '[[stages]]\ntype = "properties"\n' + "".join(f"{k} = {v}\n" for k, v in changes.items())


@pytest.mark.parametrize(
    ("stages", "warned"),
    [
        # the column's kn is 1e9 Pa/m
        (SOLVE + properties(kn=1e10), "stages[1] raises kn from 1e+09 to 1e+10 Pa/m"),
        # what is in effect counts: an earlier properties stage set 1e8
        (properties(kn=1e8) + SOLVE + properties(kn=5e8), "from 1e+08 to 5e+08 Pa/m"),
        (properties(kn=1e10) + SOLVE, None),  # before any step: nothing to push
        (SOLVE + properties(kn=1e8), None),  # softer
        (SOLVE + properties(kn=1e9, friction=20), None),  # the same
        (SOLVE + properties(ks=1e10), None),  # shear is incremental: no push now
    ],
)
def test_a_properties_stage_raising_kn_after_steps_is_warned_of(tmp_path, capsys, stages, warned):
    assert simulate(tmp_path, stages, "--check", "-q") == 0
    err = capsys.readouterr().err
    if warned is None:
        assert err == ""
    else:
        assert err.startswith("penedge: warning: stages["), err
        assert warned in err, err
        assert "total overlap" in err
        assert err.count("warning") == 1


def test_the_warning_of_a_stiffer_kn_comes_with_the_run_too(tmp_path, capsys):
    assert simulate(tmp_path, SOLVE + properties(kn=1e10), "--json") == 0
    captured = capsys.readouterr()
    assert "warning: stages[1] raises kn" in captured.err
    strict(captured.out)  # stdout stays JSON


FOS = '[[stages]]\ntype = "factor_of_safety"\n'
FOS_BEDDING = FOS + 'sets = ["bedding"]\n'


@pytest.mark.parametrize(
    ("stages", "warned"),
    [
        # every set and the default properties, brittle (the default residual cohesion, 0)
        (
            properties(cohesion=1e4) + SOLVE + FOS,
            [
                "bedding (cohesion 10000 Pa, residual 0)",
                "the default properties (cohesion 10000 Pa",
            ],
        ),
        # only the sets the stage reduces
        (
            properties(cohesion=1e4) + SOLVE + FOS_BEDDING,
            ["bedding (cohesion 10000 Pa, residual 0)"],
        ),
        # partly ductile is still brittle; wholly ductile is not
        (properties(cohesion=1e4, residual_cohesion=5e3) + SOLVE + FOS, ["residual 5000"]),
        (properties(cohesion=1e4, residual_cohesion=1e4) + SOLVE + FOS, None),
        # what is in effect when the stage runs counts
        (properties(cohesion=1e4) + SOLVE + properties(residual_cohesion=1e4) + FOS, None),
        (properties(cohesion=1e4) + SOLVE + FOS + properties(residual_cohesion=1e4), ["bedding"]),
        # tension is lost where it fails (no residual tension), friction to its residual
        (properties(tension=1e4) + SOLVE + FOS, ["bedding (tension 10000 Pa, residual 0)"]),
        (
            properties(residual_friction=20) + SOLVE + FOS,
            ["bedding (friction 30°, residual 20°)"],
        ),
        (properties(cohesion=1e4) + SOLVE, None),  # no factor of safety
        (SOLVE + FOS, None),  # no cohesion
    ],
)
def test_a_factor_of_safety_reducing_brittle_cohesion_is_warned_of(
    tmp_path, capsys, stages, warned
):
    """The block column's joints with cohesion: a factor_of_safety stage reducing a cohesion
    above its residual value is warned of (docs/models.md, "Brittle cohesion")."""
    assert simulate(tmp_path, stages, "--check", "-q") == 0
    err = capsys.readouterr().err
    if warned is None:
        assert err == ""
        return
    assert err.startswith("penedge: warning: stages["), err
    assert "reduces brittle strength" in err
    assert "residual_cohesion = cohesion" in err
    assert err.count("warning") == 1
    for text in warned:
        assert text in err, err
    if "sets = " in stages:  # the default properties are reduced with every set only
        assert "the default properties" not in err


def test_a_restarted_run_warns_only_of_the_stages_it_runs(tmp_path, capsys):
    """A brittle factor of safety before the save is not run by a run restarted from it,
    and is not warned of; one after it is (with --check too)."""
    save = '[[stages]]\ntype = "save"\nfile = "s.json"\n'
    fos = FOS + "max_steps = 200\n"
    brittle = properties(cohesion=1e4)
    for stages, warned in (
        (brittle + SOLVE + fos + save + SOLVE, False),
        (brittle + SOLVE + save + fos, True),
    ):
        assert simulate(tmp_path, stages) == 0
        assert "reduces brittle strength" in capsys.readouterr().err  # the whole run warns
        saved = str(tmp_path / "out" / "s.json")
        for flags in (("--check",), ()):
            assert simulate(tmp_path, stages, *flags, "--restart", saved) == 0
            err = capsys.readouterr().err
            assert ("reduces brittle strength" in err) == warned, (stages, flags, err)


def test_a_restart_file_of_another_model_is_refused(tmp_path, capsys):
    # The same number of blocks (five), other blocks: the bedding shifted by half a metre.
    assert simulate(tmp_path, SAVE_AND_GO_ON) == 0
    saved = str(tmp_path / "out" / "s.json")
    other = BASE.replace("origin = [0, 0, 1]", "origin = [0, 0, 0.5]")
    assert other != BASE
    capsys.readouterr()
    assert simulate(tmp_path, SAVE_AND_GO_ON, "--restart", saved, base=other) == 1
    err = capsys.readouterr().err
    assert "restart: " in err
    assert "another model" in err
    # The model that wrote it goes on from it.
    assert simulate(tmp_path, SAVE_AND_GO_ON, "--restart", saved) == 0
