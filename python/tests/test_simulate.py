"""Running a model (penedge.model.run) and ``penedge simulate``, on a stand-in engine.

The stand-in is a block on an incline, solved exactly: the free blocks slide down a slope
of angle theta when tan(phi) < tan(theta), with acceleration g (sin theta - cos theta tan
phi), and come to rest otherwise. Its factor of safety is tan(phi) / tan(theta), so the
strength-reduction search, the stages, the history, Ctrl-C and the command's outputs are
checked against a known answer without the rigid-block engine. (The engine's own checks
against limit equilibrium are in test_simulate_engine.py.)
"""

import copy
import dataclasses
import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import penedge
import penedge.model as pm
from penedge import cli
from penedge.cli import simulate as simulate_command
from penedge.model import engine as engines
from penedge.model.run import Runner

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
WEDGE = EXAMPLES / "wedge_dry.toml"
SLOPE = math.radians(35.0)


class InclineEngine:
    """The Engine interface on an exact block-on-an-incline model."""

    dt = 1e-3
    g = 9.81

    def __init__(self, setup, interrupt_after=None):
        self.setup = setup
        self.system_ = setup.system
        self.start = setup.blocks.centroids.copy()
        self.default = setup.model.default_properties
        self.properties = dict(setup.model.properties)
        self.fixed = setup.layout.fixed.copy()
        self.down = np.array([math.cos(SLOPE), 0.0, -math.sin(SLOPE)])
        self.s = 0.0  # distance slid
        self.v = 0.0
        self.steps = 0
        self.ratio = 1.0
        self.interrupt_after = interrupt_after
        self.cycles = 0

    @property
    def tan_phi(self):
        name = self.setup.model.set_names[0]
        return math.tan(math.radians(self.properties[name].friction))

    def excess(self):
        return math.sin(SLOPE) - math.cos(SLOPE) * self.tan_phi

    def apply_properties(self, properties, factor=1.0):
        # The incline has no rock bridges for `factor` to reduce (Engine.apply_properties).
        self.properties.update(properties)
        self.ratio = max(self.ratio, 0.1)  # a change unbalances the model a little

    def apply_boundary(self, fixed, velocity):
        self.fixed = fixed.copy()

    def set_elastic(self, on):
        """Elastic solves (Engine.set_elastic): the incline has no strength to lift."""

    def set_damping(self, local):
        """A stage's local damping (Engine.set_damping): the incline's motion is exact."""
        previous, self.local = getattr(self, "local", 0.8), local
        return previous

    def copy(self):
        return copy.deepcopy(self)

    def cycle(self, steps):
        self.cycles += 1
        if self.interrupt_after is not None and self.cycles > self.interrupt_after:
            raise KeyboardInterrupt
        for _ in range(steps):
            a = self.g * self.excess()
            if a > 0:
                self.v += a * self.dt
                self.ratio = a / self.g
            else:
                self.v *= 0.5
                self.ratio *= 0.8
            self.s += self.v * self.dt
            self.steps += 1

    @property
    def timestep(self):
        return self.dt

    @property
    def time(self):
        return self.steps * self.dt

    def held(self):
        """The incline holds its block (Engine.held) once it has stepped."""
        return np.full(len(self.start), self.steps > 0)

    def rotations(self):
        """The incline's block slides without turning."""
        n = len(self.start)
        return np.tile([0.0, 0.0, 0.0, 1.0], (n, 1))

    def positions(self):
        p = self.start.copy()
        p[~self.fixed] += self.s * self.down
        return p

    def velocities(self):
        v = np.zeros_like(self.start)
        v[~self.fixed] = self.v * self.down
        return v

    def kinetic_energy(self):
        return 0.5 * 1000.0 * self.v**2

    def system(self):
        return self.system_

    def contacts(self):
        """Two sub-contacts of one contact under the free block, the shape of the engine's."""
        below = self.positions()[~self.fixed][0] - [0, 0, 1]
        return {
            "points": np.array([below, below + np.array([0.5, 0, 0])]),
            "sub_offsets": np.array([0, 2]),
            "normals": np.array([[0.0, 0.0, 1.0]]),
            "normal_forces": np.array([1e3, 2e3]),
            "shear_forces": np.zeros((2, 3)),
            "states": np.array([0, 1], dtype=np.uint8),
            "areas": np.array([0.5, 0.5]),
            "water_forces": np.array([250.0]),
        }

    def bolt_elements(self):
        """The incline has no bolts (Engine.bolt_elements)."""
        return None


def wedge(friction=40.0, stages=None, extra=""):
    text = WEDGE.read_text().replace("friction = 40", f"friction = {friction}")
    if stages is not None:
        text = text[: text.index("[[stages]]")] + stages
    return pm.prepare(pm.parse_model(text + extra))


FOS = '[[stages]]\ntype = "solve"\n[[stages]]\ntype = "factor_of_safety"\nmax_steps = {}\n'


def exact_factor(friction):
    return math.tan(math.radians(friction)) / math.tan(SLOPE)


@pytest.mark.parametrize("friction", [40.0, 30.0, 20.0])
def test_factor_of_safety_brackets_the_exact_answer(friction):
    """The bisection brackets the stand-in's exact factor. At 30 and 20 degrees (F < 1) the
    block slides through the solve (the start is not in equilibrium: unreliable), and a
    trial that holds it stops it only after some decimetres; the stage's `displacement`
    (by default 1 % of the block's size: docs/models.md, "Failure criterion") is raised so
    that the bracket is the search's alone."""
    stages = FOS.format(2000) + ("displacement = 10.0\n" if friction < 40 else "")
    outcome = Runner(wedge(friction, stages), InclineEngine).run()
    f = outcome.safety
    exact = exact_factor(friction)
    assert f.stable < exact <= f.failing
    assert f.failing - f.stable <= 0.01
    assert f.factor == f.stable
    assert f.bounded == "="
    free = int(np.flatnonzero(~outcome_fixed(friction))[0])
    assert f.failing_blocks == [free]
    assert [t.failed for t in f.trials if t.factor == f.failing] == [True]


def outcome_fixed(friction):
    return wedge(friction).layout.fixed


def test_factor_of_safety_does_not_depend_on_the_budget():
    once = Runner(wedge(40.0, FOS.format(1500)), InclineEngine).run().safety
    twice = Runner(wedge(40.0, FOS.format(3000)), InclineEngine).run().safety
    assert (once.stable, once.failing) == (twice.stable, twice.failing)


def test_factor_of_safety_says_when_it_starts_out_of_equilibrium(tmp_path, stand_in, capsys):
    f = Runner(wedge(40.0, FOS.format(1000)), InclineEngine).run().safety
    assert f.in_equilibrium
    stages = '[[stages]]\ntype = "factor_of_safety"\nmax_steps = 1000\n'
    f = Runner(wedge(40.0, stages), InclineEngine).run().safety  # no solve first
    assert not f.in_equilibrium
    model = tmp_path / "wedge.toml"
    text = WEDGE.read_text()
    model.write_text(text[: text.index("[[stages]]")] + stages)
    assert cli.main(["simulate", str(model), "-o", str(tmp_path / "out"), "--no-pictures"]) == 0
    printed = capsys.readouterr().out
    assert "UNRELIABLE: the trials started from a state NOT in equilibrium" in printed


def test_factor_of_safety_outside_the_range():
    stages = FOS.format(1000).rstrip("\n") + "\nhigh = 1.1\n"
    f = Runner(wedge(60.0, stages), InclineEngine).run().safety  # exact 2.47
    assert (f.bounded, f.failing, f.factor) == (">", None, 1.1)


@pytest.mark.parametrize(
    ("friction", "factors", "bound"),
    [
        (89.0, [1, 2, 4, 8, 10], ">"),  # exact 81.8: stable at high = 10 itself
        (2.0, [1, 0.5, 0.25, 0.125, 0.1], "<"),  # exact 0.050: failing at low = 0.1 itself
    ],
)
def test_factor_of_safety_tries_low_and_high_themselves(friction, factors, bound):
    assert (exact_factor(friction) > 10) == (bound == ">")
    f = Runner(wedge(friction, FOS.format(1000)), InclineEngine).run().safety
    assert [t.factor for t in f.trials] == factors
    assert (f.bounded, f.factor) == (bound, factors[-1])


def test_factor_of_safety_refuses_a_tolerance_finer_than_it_can_mean():
    # tolerance = 1e-20 (below the floats' spacing at F = 1) looped for ever: refused, naming
    # the field and the bound (1e-6 x high); 1e-6 x high itself is taken.
    stages = FOS.format(100).rstrip("\n") + "\ntolerance = 1e-20\n"
    with pytest.raises(pm.ModelError, match=r"must be at least 1e-06 x high \(1e-05 here\)") as e:
        wedge(40.0, stages)
    assert e.value.field == "stages[1].tolerance"
    stages = FOS.format(100).rstrip("\n") + "\nhigh = 2\ntolerance = 2e-6\n"
    assert wedge(40.0, stages).model.stages[1].tolerance == 2e-6


def test_factor_of_safety_bisection_ends_at_neighbouring_floats():
    # A tolerance below the floats' spacing, given past the model file's check (a Stage
    # changed in Python): the bisection stops where no factor lies between its two ends
    # (it looped for ever, the midpoint being one of them).
    setup = wedge(40.0, FOS.format(50))
    stages = list(setup.model.stages)
    stages[1] = dataclasses.replace(stages[1], tolerance=1e-300)
    setup = dataclasses.replace(setup, model=dataclasses.replace(setup.model, stages=stages))
    trials = []

    def progress(engine, stage, done, total):
        if stage.kind == "factor_of_safety":
            trials.append(done)
            assert done < 200, "the bisection does not end"

    f = Runner(setup, InclineEngine, progress=progress).run().safety
    assert f.bounded == "="
    assert f.failing == math.nextafter(f.stable, math.inf)
    assert len(f.trials) < 100


def test_factor_of_safety_leaves_the_model_as_it_was():
    setup = wedge(40.0, FOS.format(1000) + '[[stages]]\ntype = "cycle"\nsteps = 30\n')
    runner = Runner(setup, InclineEngine)
    outcome = runner.run()
    assert runner.engine.properties == setup.model.properties  # trials ran on copies
    assert outcome.stable
    assert outcome.moved.tolist() == []


def test_stages_and_history():
    stages = (
        '[[stages]]\ntype = "solve"\n'
        '[[stages]]\ntype = "properties"\nsets = ["A", "B"]\nfriction = 20\n'
        '[[stages]]\ntype = "cycle"\nsteps = 100\n'
        '[[stages]]\ntype = "reset"\n'
        '[[stages]]\ntype = "time"\ntime = 0.05\n'
    )
    setup = wedge(40.0, stages)
    outcome = Runner(setup, InclineEngine).run()
    kinds = [(s.kind, s.steps) for s in outcome.stages]
    assert kinds[0][0] == "solve"
    assert outcome.stages[0].converged
    assert kinds[1:] == [("properties", 0), ("cycle", 100), ("reset", 0), ("time", 50)]
    # The only solve converged, but friction 20 lets the wedge slide: still sliding at the
    # end, so not stable.
    assert not outcome.stable
    assert any("still moving at the end" in p for p in outcome.problems), outcome.problems
    # after the reset, the displacement is the slide of the last 50 steps only:
    # s(t) = a t^2 / 2 from the speed at the reset
    free = np.flatnonzero(~setup.layout.fixed)[0]
    h = outcome.history
    assert h.step[0] == 0
    assert h.step[-1] == outcome.steps
    assert np.all(np.diff(h.step) > 0)
    monitored = np.asarray(h.monitors["wedge"])
    assert np.linalg.norm(monitored[-1, :3]) == pytest.approx(
        np.linalg.norm(outcome.displacement[free])
    )
    assert outcome.moved.tolist() == [free]


def test_properties_stage_without_sets_changes_the_default_too():
    stages = '[[stages]]\ntype = "properties"\nfriction = 20\ncohesion = 5\n'
    runner = Runner(wedge(40.0, stages), InclineEngine)
    runner.run()
    assert (runner.engine.default.friction, runner.engine.default.cohesion) == (20, 5)
    assert runner.engine.properties["A"].friction == 20
    stages = '[[stages]]\ntype = "properties"\nsets = ["B"]\nfriction = 20\n'
    runner = Runner(wedge(40.0, stages), InclineEngine)
    runner.run()
    assert runner.engine.default.friction == 40
    assert (runner.engine.properties["A"].friction, runner.engine.properties["B"].friction) == (
        40,
        20,
    )


def test_boundary_stage_fixes_the_block():
    stages = (
        '[[stages]]\ntype = "properties"\nfriction = 20\n'
        '[[stages]]\ntype = "cycle"\nsteps = 20\n'
        '[[stages]]\ntype = "boundary"\nregion = "wedge"\ncondition = "fixed"\n'
    )
    runner = Runner(wedge(40.0, stages), InclineEngine)
    runner.run()
    assert runner.engine.fixed.all()
    # A stage that steps after it has no free block: refused before any step.
    with pytest.raises(pm.ModelError, match=r"stages\[3\]: stages\[3\] \(cycle\) takes steps"):
        Runner(wedge(40.0, stages + '[[stages]]\ntype = "cycle"\nsteps = 20\n'), InclineEngine)


def test_engine_error_stops_the_run_and_keeps_what_it_did(tmp_path, monkeypatch, capsys):
    class Overlapping(InclineEngine):
        def cycle(self, steps):
            super().cycle(steps)
            if self.steps >= 40:
                raise penedge.InputError("bodies 1 and 3 overlap deeper than the detection gap")

    runner = Runner(wedge(20.0, '[[stages]]\ntype = "cycle"\nsteps = 1000\n'), Overlapping)
    outcome = runner.run()
    assert outcome.error == "bodies 1 and 3 overlap deeper than the detection gap"
    assert not outcome.stable
    assert outcome.steps == 40
    monkeypatch.setattr(engines, "Engine", Overlapping)
    monkeypatch.setattr(engines, "simulation_class", lambda: object)
    out = tmp_path / "out"
    assert cli.main(["simulate", str(WEDGE), "-o", str(out), "--no-pictures"]) == 1
    captured = capsys.readouterr()
    assert "the run stopped at step 40: bodies 1 and 3 overlap" in captured.err
    printed = " ".join(captured.out.split())
    assert "result stopped by an error (below)" in printed
    assert "stages[0] solve: stopped by the engine after 40 steps" in printed
    assert json.loads((out / "summary.json").read_text())["error"].startswith("bodies 1 and 3")


def mechanics_error(kind, message):
    """A :exc:`penedge.MechanicsError` of `kind`, as the engine raises it."""
    error = penedge.MechanicsError(message)
    error.kind = kind
    return error


def test_a_penetration_in_a_trial_is_a_failure():
    class Overlapping(InclineEngine):
        def cycle(self, steps):
            super().cycle(steps)
            if self.v > 0.05:  # sliding far: blocks driven into each other
                raise mechanics_error("penetration", "bodies 0 and 1 overlap deeper")

    f = Runner(wedge(40.0, FOS.format(2000)), Overlapping).run().safety
    exact = exact_factor(40.0)
    assert f.stable < exact <= f.failing


@pytest.mark.parametrize(
    "error",
    [
        mechanics_error("not_finite", "a free body's unbalanced force has a NaN component"),
        penedge.InputError("bad input"),
    ],
)
def test_another_engine_error_in_a_trial_stops_the_run(error):
    # Only a penetration says the reduced strength fails; another error says nothing of
    # the strength: it is the run's error, not a failing trial (which gave a factor).
    class Broken(InclineEngine):
        def cycle(self, steps):
            super().cycle(steps)
            if self.v > 0.05:
                raise error

    outcome = Runner(wedge(40.0, FOS.format(2000)), Broken).run()
    assert outcome.error == str(error)
    assert outcome.safety is None
    assert outcome.stages[-1].stopped == "error"
    assert not outcome.stable


def test_interrupted_run_keeps_what_it_did():
    runner = Runner(wedge(20.0, '[[stages]]\ntype = "cycle"\nsteps = 1000\n'), InclineEngine)
    runner.engine.interrupt_after = 3
    outcome = runner.run()
    assert outcome.interrupted
    assert not outcome.stable
    assert outcome.steps == 30  # three chunks of history_every = 10 steps
    assert outcome.history.stage[-1] == "interrupted"
    assert [(s.name, s.steps, s.stopped) for s in outcome.stages] == [
        ("stages[0]", 30, "interrupted")
    ]


# --- the command ---------------------------------------------------------------------


@pytest.fixture
def stand_in(monkeypatch):
    monkeypatch.setattr(engines, "Engine", InclineEngine)
    monkeypatch.setattr(engines, "simulation_class", lambda: object)


def test_simulate_writes_results(tmp_path, stand_in, capsys):
    model = tmp_path / "wedge.toml"
    model.write_text(WEDGE.read_text().replace("max_steps = 8000", "max_steps = 500"))
    out = tmp_path / "out"
    assert cli.main(["simulate", str(model), "-o", str(out)]) == 0
    printed = capsys.readouterr()
    assert printed.err == ""
    lines = [" ".join(line.split()) for line in printed.out.splitlines()]
    assert lines[0] == f"penedge simulate {model}: Hoek & Bray wedge, dry"
    assert "blocks 4 (3 fixed, 1 free)" in lines
    exact = exact_factor(40.0)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stable"] is True
    assert summary["factor_of_safety"] < exact <= summary["factor_of_safety"] + 0.01
    assert any(
        line.startswith(f"factor of safety = {summary['factor_of_safety']:.2f}") for line in lines
    )
    assert sorted(p.name for p in out.iterdir()) == [
        "displacement.png",
        "failing.png",
        "history.csv",
        "history.png",
        "series",
        "summary.json",
    ]
    header = (out / "history.csv").read_text().splitlines()[0].split(",")
    assert header[:5] == ["step", "time", "stage", "ratio", "kinetic_energy"]
    assert "wedge.dz" in header
    index = ET.parse(out / "series" / "blocks.pvd").getroot()
    files = [d.get("file") for d in index.iter("DataSet")]
    assert files[0] == "blocks_000000.vtu"
    assert len(files) == 2  # the start and the end of the solve (the trials run on copies)
    frame = ET.parse(out / "series" / files[-1]).getroot()
    arrays = {a.get("Name"): a.text.split() for a in frame.iter("DataArray")}
    assert len(arrays["displacement"]) == 4 * 3
    assert len(arrays["moving"]) == 4
    assert arrays["types"] == ["42"] * 4
    index = ET.parse(out / "series" / "subcontacts.pvd").getroot()
    files = [d.get("file") for d in index.iter("DataSet")]
    assert files == ["subcontacts_000000.vtp", "subcontacts_000001.vtp"]
    frame = ET.parse(out / "series" / files[-1]).getroot()
    arrays = {a.get("Name"): a.text.split() for a in frame.iter("DataArray")}
    assert arrays["normal_force"] == ["1000", "2000"]
    assert arrays["state"] == ["0", "1"]
    assert arrays["contact"] == ["0", "0"]
    assert arrays["water_force"] == ["250", "250"]  # the contact's, on each sub-contact
    assert not (out / "series" / "bolts.pvd").exists()  # a model without bolts


def test_simulate_html_plays_the_frames(tmp_path, stand_in):
    pytest.importorskip("plotly")
    out = tmp_path / "out"
    assert cli.main(["simulate", str(WEDGE), "-o", str(out), "--html", "-q", "--no-pictures"]) == 0
    page = (out / "steps.html").read_text()
    assert "Plotly.newPlot" in page
    assert page.count('"name":"t = ') == 2  # the start and the end of the solve
    assert '"label":"play"' in page


def test_simulate_engine_refusal_writes_nothing(tmp_path, monkeypatch, capsys):
    class Refusing(InclineEngine):
        def __init__(self, setup):
            raise penedge.InputError(
                "the time step 1 is not in (0, 0.001] (the critical time step)"
            )

    monkeypatch.setattr(engines, "Engine", Refusing)
    monkeypatch.setattr(engines, "simulation_class", lambda: object)
    out = tmp_path / "out"
    assert cli.main(["simulate", str(WEDGE), "-o", str(out)]) == 1
    assert "the time step 1 is not in" in capsys.readouterr().err
    assert not out.exists()


def test_simulate_check_runs_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    assert (
        cli.main(["simulate", str(EXAMPLES / "wedge_water.toml"), "--check", "-o", str(out)]) == 0
    )
    text = capsys.readouterr().out
    assert "the model is valid" in text
    assert "cannot run yet" not in text  # water runs on the engine
    assert not out.exists()


def test_simulate_refuses_what_the_engine_cannot_run(tmp_path, stand_in, capsys):
    model = tmp_path / "model.toml"
    model.write_text(WEDGE.read_text() + "[joint_properties.A]\nresidual_tension = 1e3\n")
    assert cli.main(["simulate", str(model), "-o", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert err.startswith(
        "penedge: error: joint_properties.A: a residual tensile strength is not supported by "
        "the engine"
    )
    assert not (tmp_path / "out").exists()


def test_simulate_without_engine(tmp_path, monkeypatch, capsys):
    monkeypatch.delattr(penedge, "Simulation", raising=False)
    assert cli.main(["simulate", str(WEDGE), "-o", str(tmp_path / "out")]) == 1
    assert "has no mechanics engine" in capsys.readouterr().err


def test_simulate_bad_model_names_the_field(tmp_path, capsys):
    model = tmp_path / "bad.toml"
    model.write_text(WEDGE.read_text().replace("[regions.wedge]", "[regions.wedge]\nsize = 3"))
    assert cli.main(["simulate", str(model)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("penedge: error: regions.wedge.size: unknown field")
    assert "(in " in err


def test_simulate_usage_errors(tmp_path, capsys):
    assert cli.main(["simulate", str(tmp_path / "model.json")]) == 2
    file = tmp_path / "taken"
    file.write_text("")
    assert cli.main(["simulate", str(WEDGE), "-o", str(file)]) == 2
    assert cli.main(["simulate", str(tmp_path / "missing.toml")]) == 1
    assert "No such file" in capsys.readouterr().err


def test_simulate_interrupted_writes_results(tmp_path, monkeypatch, capsys):
    class Interrupted(InclineEngine):
        def __init__(self, setup):
            super().__init__(setup, interrupt_after=2)

    monkeypatch.setattr(engines, "Engine", Interrupted)
    monkeypatch.setattr(engines, "simulation_class", lambda: object)
    out = tmp_path / "out"
    assert cli.main(["simulate", str(WEDGE), "-o", str(out), "--no-pictures", "--json"]) == 130
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert summary["interrupted"] is True
    assert summary["steps"] == 20
    assert "interrupted" in captured.err
    assert (out / "history.csv").exists()
    assert (out / "series" / "blocks.pvd").exists()


def test_status_line_waits_then_redraws():
    import io

    from penedge.cli.progress import StatusLine

    now = [0.0]
    stream = io.StringIO()
    line = StatusLine(stream, delay=1.0, interval=0.5, clock=lambda: now[0])
    line.show("early")
    now[0] = 1.2
    line.show("step 10, ratio 1e-2")
    now[0] = 1.3
    line.show("too soon")
    now[0] = 2.0
    line.show("step 20")
    line.close()
    assert stream.getvalue() == "\rstep 10, ratio 1e-2\rstep 20            \n"


def test_simulate_refuses_a_density_beyond_any_rock(tmp_path, capsys):
    # density = 1e300 ran to the end with a NaN ratio and infinite displacements, exit 0
    model = tmp_path / "huge.toml"
    text = WEDGE.read_text()
    model.write_text(text.replace("density = 2600", "density = 1e300", 1))
    assert "density = 1e300" in model.read_text()
    out = tmp_path / "out"
    assert cli.main(["simulate", str(model), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(
        "penedge: error: rock.density: 1e+300 kg/m³ is outside the range a model takes, "
        "1 to 100000 kg/m³"
    )
    assert err.rstrip().endswith(f"(in {model})")
    assert not out.exists()


def test_factor_of_safety_says_how_far_each_failing_block_moved_and_turned():
    f = Runner(wedge(40.0, FOS.format(1000)), InclineEngine).run().safety
    failing = next(t for t in f.trials if t.factor == f.failing)
    assert f.failing_blocks == failing.moved
    assert len(f.failing_blocks) > 0
    # The incline's block slides (by the distance its exact model gives) without turning.
    assert f.failing_displacement == failing.displacement
    assert all(d > 1e-3 for d in f.failing_displacement)
    assert f.failing_rotation == [0.0] * len(f.failing_blocks)
    entry = {
        "failing_blocks": f.failing_blocks,
        "failing_displacement": f.failing_displacement,
        "failing_rotation": f.failing_rotation,
    }
    text = simulate_command.failing_text(entry)
    first = f"{f.failing_blocks[0]} ({f.failing_displacement[0]:.2g} m, 0°)"
    assert text.startswith("failing blocks, moved and turned in the first failing trial: ")
    assert first in text
    # A summary written before the rotations were kept: the ids alone.
    old = {"failing_blocks": [3, 4]}
    assert simulate_command.failing_text(old) == "failing blocks: 3, 4"
    assert simulate_command.failing_text({"failing_blocks": []}) == "failing blocks: none"


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-3, 0.5, 30.0, 90.0, 179.0])
def test_rotation_degrees_is_the_angle_between_two_orientations(angle):
    from penedge.model.run import rotation_degrees

    rng = np.random.default_rng(7)
    before = rng.normal(size=(5, 4))
    before /= np.linalg.norm(before, axis=1)[:, None]
    axis = rng.normal(size=(5, 3))
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    half = math.radians(angle) / 2
    turn = np.hstack([axis * math.sin(half), np.full((5, 1), math.cos(half))])

    def times(p, q):  # quaternion products, rows x, y, z, w
        pv, pw, qv, qw = p[:, :3], p[:, 3:], q[:, :3], q[:, 3:]
        v = pw * qv + qw * pv + np.cross(pv, qv)
        w = pw * qw - np.einsum("ij,ij->i", pv, qv)[:, None]
        return np.hstack([v, w])

    after = times(turn, before)
    got = rotation_degrees(before, after)
    assert got == pytest.approx(np.full(5, angle), rel=1e-9, abs=1e-12)
    # -q is the same orientation as q.
    assert rotation_degrees(before, -after) == pytest.approx(got, rel=1e-9, abs=1e-12)
