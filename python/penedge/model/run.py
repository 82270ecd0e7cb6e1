"""Running a model's stages on an engine: solve, cycle, time, property and boundary
changes, resets, and the factor of safety by strength reduction; the history (step, time,
unbalanced-force ratio, kinetic energy, monitored blocks) and the outcome (stable or not,
blocks that moved, the largest displacement, the factor of safety).

The runner steps in chunks of ``[results].history_every`` steps, so that progress, history
points and Ctrl-C come between chunks: an interrupted run stops after the current chunk
and keeps its outcome so far (``Outcome.interrupted``). A run the engine stops with an
error (two blocks overlapping deeper than the detection gap, a NaN) keeps its outcome so
far too, with the error (``Outcome.error``); in a factor-of-safety trial a penetration
(blocks driven into each other) counts as a failure, any other error stops the run. The
engine is anything with the
interface of :class:`penedge.model.engine.Engine`.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from penedge._core import MechanicsError, PenedgeError
from penedge.model.check import apply_boundary, block_list, partial_body
from penedge.model.fields import MAX_STEPS, MAX_STEPS_WHY, ModelError, point_text
from penedge.model.schema import JointProperties, Model, Stage


class Column:
    """A column of the history that grows: a numpy array filled in place and doubled when
    full (8 bytes a number; a list of Python floats took 32, and a tuple of numpy scalars
    per monitored point some 300). Reads as a sequence (``len``, ``[k]``, ``[-1]``) and as
    an array (``np.asarray``); `width` > 0 makes rows of that many numbers."""

    def __init__(self, width: int = 0, dtype: Any = float) -> None:
        self.width = width
        self.data = np.empty((16, width) if width else 16, dtype=dtype)
        self.size = 0

    def append(self, value: Any) -> None:
        if self.size == len(self.data):
            grown = np.empty((2 * len(self.data), *self.data.shape[1:]), dtype=self.data.dtype)
            grown[: self.size] = self.data
            self.data = grown
        self.data[self.size] = value
        self.size += 1

    @property
    def values(self) -> np.ndarray:
        """The numbers so far (a view: copy it to keep it past the next append)."""
        return self.data[: self.size]

    def tolist(self) -> list[Any]:
        return self.values.tolist()  # type: ignore[no-any-return]

    def __len__(self) -> int:
        return self.size

    def __getitem__(self, k: Any) -> Any:
        return self.values[k]

    def __iter__(self) -> Any:
        return iter(self.values)

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return np.array(self.values, dtype=dtype, copy=True if copy is None else copy)


@dataclass
class History:
    """One row per history point: the step, time, ratio, kinetic energy (numpy-backed
    :class:`Column` s), the stage's name, and per monitor a column of rows
    ``dx dy dz vx vy vz``."""

    step: Column = field(default_factory=lambda: Column(dtype=np.int64))
    time: Column = field(default_factory=Column)
    ratio: Column = field(default_factory=Column)
    kinetic: Column = field(default_factory=Column)
    stage: list[str] = field(default_factory=list)  # the stage's own name: 8 bytes a point
    monitors: dict[str, Column] = field(default_factory=dict)  # dx dy dz vx vy vz

    def rows(self) -> list[dict[str, Any]]:
        """The history as dict rows."""
        return list(self.each_row())

    def each_row(self) -> Iterator[dict[str, Any]]:
        """The history's dict rows one by one (for CSV: not all at once in memory)."""
        step, time = self.step.tolist(), self.time.tolist()
        ratio, kinetic = self.ratio.tolist(), self.kinetic.tolist()
        monitors = {name: values.tolist() for name, values in self.monitors.items()}
        for k in range(len(step)):
            row: dict[str, Any] = {
                "step": step[k],
                "time": time[k],
                "stage": self.stage[k],
                "ratio": ratio[k],
                "kinetic_energy": kinetic[k],
            }
            for name, values in monitors.items():
                for label, v in zip(("dx", "dy", "dz", "vx", "vy", "vz"), values[k], strict=True):
                    row[f"{name}.{label}"] = v
            yield row


@dataclass
class Trial:
    """One trial of a strength reduction."""

    factor: float
    failed: bool
    steps: int
    ratio: float
    speed: float  # m/s, the largest speed of a free block at the end
    moved: list[int]  # free blocks that moved more than the threshold, or still move faster
    # than the stage's velocity, at the end of the trial
    displacement: list[float] = field(default_factory=list)  # m, of each `moved` block
    rotation: list[float] = field(default_factory=list)  # degrees, of each `moved` block
    # free blocks that moved farther than the stage's displacement limit (failing the trial
    # even where they came to rest: a block that slid off its plane onto the rock below)
    beyond: list[int] = field(default_factory=list)


@dataclass
class SafetyFactor:
    """The factor of safety by strength reduction."""

    factor: float  # the largest stable factor found
    stable: float | None  # the bracket: largest stable ...
    failing: float | None  # ... and smallest failing factor
    failing_blocks: list[int]
    trials: list[Trial]
    # of each failing block, in the smallest failing trial: its displacement (m) and
    # rotation (degrees), which tell sliding from toppling
    failing_displacement: list[float] = field(default_factory=list)
    failing_rotation: list[float] = field(default_factory=list)
    # free blocks that no contact held when the trials started (after steps were taken):
    # falling freely, which no strength of the joints can hold
    unheld_blocks: list[int] = field(default_factory=list)
    # free blocks that had moved farther than CAUTION_TIMES the displacement limit before the
    # trials (since the start of the run, or the last reset): F is of where they came to rest
    moved_before: list[int] = field(default_factory=list)
    moved_before_displacement: list[float] = field(default_factory=list)  # m, of each
    start_ratio: float = 0.0  # the unbalanced-force ratio of the state the trials start from
    in_equilibrium: bool = True  # whether that state was below the equilibrium ratio ...
    target: float = 1e-5  # ... the stage's `ratio`

    @property
    def bounded(self) -> str:
        """``"="``, or ``">"`` / ``"<"`` when the search range did not enclose it."""
        if self.failing is None:
            return ">"
        if self.stable is None:
            return "<"
        return "="


@dataclass
class StageResult:
    """What a stage did."""

    name: str
    kind: str
    steps: int
    time: float
    ratio: float
    converged: bool | None = None  # solve stages
    safety: SafetyFactor | None = None
    stopped: str | None = None  # "interrupted" or the engine's error, if the stage was cut short
    index: int | None = None  # the stage's place in the model's stages
    damping: float | None = None  # cycle, time: the local damping it stepped with


@dataclass
class Outcome:
    """The result of a run."""

    stages: list[StageResult]
    history: History
    displacement: np.ndarray  # (n, 3) since the start (or the last reset)
    velocity: np.ndarray  # (n, 3)
    moved: np.ndarray  # ids of the blocks that moved more than the threshold
    interrupted: bool
    threshold: float
    steps: int
    time: float
    ratio: float
    target: float = 1e-5  # the model's equilibrium ratio ([mechanics].ratio)
    error: str | None = None  # the engine's error that stopped the run
    bolts: list[dict[str, Any]] = field(default_factory=list)  # per bolt, at the end
    earlier: list[bool] = field(default_factory=list)  # solves before a restart: converged?

    last_solve: str | None = None  # the last solve stage of the model that ran (or before
    # a restart), whose ratio is the target of the final state
    moving: float = 1e-4  # m/s: [results].moving, a free block faster than it still moves
    free: np.ndarray | None = None  # (n,) bool: the free blocks at the end

    @property
    def problems(self) -> list[str]:
        """Why the run is not stable (empty when it is): the last ``solve`` stage (those
        before a restart included: `earlier`) did not reach its ratio, the final state is
        not in equilibrium (its ratio above the last solve's ratio, or the model's without
        one; or a free block still faster than ``[results].moving``), a factor of safety
        below 1, or one that is unreliable (its trials started from a state above its
        stage's ratio, which may be looser than the last solve's: it does not show the
        model stable); or the run was interrupted or stopped by an error."""
        found = []
        if self.interrupted:
            found.append("interrupted")
        if self.error is not None:
            found.append("stopped by an error")
        solves = self.earlier + [bool(s.converged) for s in self.stages if s.kind == "solve"]
        if solves and not solves[-1]:
            name = self.last_solve or "the last solve stage"
            found.append(f"{name} (the last solve) did not reach equilibrium")
        if not self.ratio <= self.target:  # NaN too
            found.append(
                f"not in equilibrium at the end (unbalanced-force ratio {self.ratio:.2g} > "
                f"{self.target:.2g})"
            )
        speed = self.speed
        if speed > self.moving:
            found.append(
                f"blocks still moving at the end (up to {speed:.2g} m/s > {self.moving:g})"
            )
        for s in self.stages:
            f = s.safety
            if f is None:
                continue
            if f.factor < 1:
                found.append(f"factor of safety {below_one(f.factor)} < 1 ({s.name})")
            if not f.in_equilibrium:
                found.append(
                    f"factor of safety UNRELIABLE ({s.name}: its trials started from a state "
                    f"not in equilibrium, ratio {f.start_ratio:.2g} > {f.target:.2g})"
                )
        return found

    @property
    def stable(self) -> bool:
        """In equilibrium at the end and every factor of safety reliable and at least 1
        (`problems` says what is not)."""
        return not self.problems

    @property
    def speed(self) -> float:
        """The largest speed of a free block at the end (m/s)."""
        speeds = np.linalg.norm(self.velocity, axis=1) if len(self.velocity) else np.zeros(0)
        if self.free is not None:
            speeds = speeds[self.free]
        return float(speeds.max(initial=0.0))

    @property
    def max_displacement(self) -> tuple[float, int]:
        """The largest displacement (m) and its block."""
        d = np.linalg.norm(self.displacement, axis=1)
        if len(d) == 0:
            return 0.0, -1
        i = int(np.argmax(d))
        return float(d[i]), i

    @property
    def safety(self) -> SafetyFactor | None:
        """The last factor of safety computed."""
        found = [s.safety for s in self.stages if s.safety is not None]
        return found[-1] if found else None


Progress = Callable[[Any, Stage, int, int | None], None]


class Runner:
    """Runs the stages of a :class:`~penedge.model.Setup` on an engine.

    Parameters
    ----------
    setup : penedge.model.Setup
    factory : callable
        ``factory(setup)`` builds a fresh engine (:class:`~penedge.model.engine.Engine`).
    progress : callable, optional
        ``progress(engine, stage, done, total)`` after each chunk of steps (`total` None
        when the stage's length is not known, as for a solve).
    frame : callable, optional
        ``frame(engine, displacement)`` when a ParaView frame is due.
    folder : path, optional
        Where a ``save`` stage's relative ``file`` goes (default: the current folder).
    restart : path, optional
        A restart file written by a ``save`` stage of this model: the run goes on from it,
        with the stages after that one (docs/models.md, "Restart").
    """

    def __init__(
        self,
        setup: Any,
        factory: Callable[[Any], Any],
        progress: Progress | None = None,
        frame: Callable[[Any, np.ndarray], None] | None = None,
        folder: str | Path | None = None,
        restart: str | Path | None = None,
    ) -> None:
        self.setup = setup
        self.model = setup.model
        self.factory = factory
        self.progress = progress
        self.frame = frame
        self.engine = factory(setup)
        self.reference = self.engine.positions()
        self.history = History(monitors={name: Column(6) for name in setup.layout.monitors})
        self.fixed = setup.layout.fixed.copy()
        self.velocity = setup.layout.velocity.copy()
        self.last_frame = -1
        self.chunk = self.model.results.history_every
        self.folder = Path(folder) if folder is not None else Path()
        self.first = 0  # the first stage to run (after a restart, the one after the save)
        self.earlier: list[bool] = []  # the verdicts of the solve stages before the restart
        self.solves: list[bool] = []  # ... and of those since: what a save carries on
        check_excavations(self.model, setup.layout.regions, setup.layout.bodies)
        if restart is not None:
            self.restore(Path(restart))
        check_saves(self.model, self.folder, self.first)
        check_safety_stages(
            self.model, setup.layout, self.fixed, self.velocity, removed_of(self.engine), self.first
        )
        #: The time step the engine starts with (None when it has none yet: no free block
        #: until a later stage frees some); the time stages' steps, checked now.
        self.timestep = timestep_of(self.engine)
        check_time_stages(self.model, self.timestep, self.first)

    # --- the run --------------------------------------------------------------------

    def run(self) -> Outcome:
        """Every stage in order; stops cleanly on Ctrl-C (KeyboardInterrupt)."""
        results: list[StageResult] = []
        interrupted = False
        self.record("start")
        self.write_frame()
        error = None
        for index, stage in enumerate(self.model.stages):
            if index < self.first:
                continue
            start = (self.engine.steps, self.engine.time)
            try:
                results.append(dataclasses.replace(self.run_stage(index, stage), index=index))
                self.write_frame()
            except (KeyboardInterrupt, PenedgeError, ModelError, OSError) as e:
                interrupted = isinstance(e, KeyboardInterrupt)
                error = None if interrupted else str(e)
                named = getattr(self.engine, "with_blocks", None)
                if isinstance(e, MechanicsError) and named is not None:
                    error = named(str(e))  # the engine's bodies as the model's blocks
                e_ = self.engine
                results.append(
                    StageResult(
                        stage.name,
                        stage.kind,
                        e_.steps - start[0],
                        e_.time - start[1],
                        e_.ratio,
                        stopped="interrupted" if interrupted else "error",
                        index=index,
                        damping=stage.damping,
                    )
                )
                self.record("interrupted" if interrupted else "error")
                self.write_frame()
                break
        return self.outcome(results, interrupted, error)

    def outcome(
        self, results: list[StageResult], interrupted: bool, error: str | None = None
    ) -> Outcome:
        e = self.engine
        displacement = e.positions() - self.reference
        threshold = self.model.results.moved
        moved = np.flatnonzero(np.linalg.norm(displacement, axis=1) > threshold)
        out = Outcome(
            stages=results,
            history=self.history,
            displacement=displacement,
            velocity=e.velocities(),
            moved=moved,
            interrupted=interrupted,
            threshold=threshold,
            steps=e.steps,
            time=e.time,
            ratio=e.ratio,
            target=self.target(results),
            error=error,
            earlier=list(self.earlier),
            last_solve=self.last_solve(results),
            moving=self.model.results.moving,
            free=free_of(self.fixed, self.velocity, removed_of(e)),
        )
        out.bolts = bolt_results(e)
        return out

    def last_solve_index(self, results: list[StageResult]) -> int | None:
        """The place in the model's stages of the last solve stage that ran (in this run,
        or before its restart): by place, not by name (two stages may share a name)."""
        ran = {r.index for r in results}
        solves = [
            i
            for i, s in enumerate(self.model.stages)
            if s.kind == "solve" and (i < self.first or i in ran)
        ]
        return solves[-1] if solves else None

    def last_solve(self, results: list[StageResult]) -> str | None:
        """The name of the last solve stage that ran (in this run, or before its restart)."""
        i = self.last_solve_index(results)
        return None if i is None else self.model.stages[i].name

    def target(self, results: list[StageResult]) -> float:
        """The ratio of equilibrium of the final state: the last solve's, or the model's."""
        i = self.last_solve_index(results)
        ratio = None if i is None else self.model.stages[i].ratio
        return self.model.mechanics.ratio if ratio is None else ratio

    def record(self, stage: str) -> None:
        """One history point."""
        e = self.engine
        h = self.history
        h.step.append(e.steps)
        h.time.append(e.time)
        h.ratio.append(e.ratio)
        h.kinetic.append(e.kinetic_energy())
        h.stage.append(stage)
        if h.monitors:
            d = e.positions() - self.reference
            v = e.velocities()
            for name, block in self.setup.layout.monitors.items():
                h.monitors[name].append(np.concatenate((d[block], v[block])))

    def write_frame(self) -> None:
        if self.frame is not None and self.engine.steps != self.last_frame:
            self.last_frame = self.engine.steps
            self.frame(self.engine, self.engine.positions() - self.reference)

    def advance(self, stage: Stage, steps: int, total: int | None) -> None:
        """`steps` steps as one chunk, then a history point, progress and maybe a frame."""
        self.engine.cycle(steps)
        self.record(stage.name)
        every = self.model.results.frame_every
        if every and self.engine.steps // every != (self.engine.steps - steps) // every:
            self.write_frame()

    def run_stage(self, index: int, stage: Stage) -> StageResult:
        e = self.engine
        start_steps, start_time = e.steps, e.time
        converged = None
        safety = None
        if stage.kind == "solve":
            assert stage.ratio is not None
            assert stage.max_steps is not None
            e.set_elastic(stage.elastic)
            converged = self.solve(stage, stage.ratio, stage.max_steps)
            e.set_elastic(False)
            self.solves.append(converged)
        elif stage.kind in ("cycle", "time"):
            if stage.kind == "cycle":
                assert stage.steps is not None
                total = stage.steps
            else:
                assert stage.time is not None
                total = time_steps(stage.time, e.timestep)
                refuse_long_time_stage(index, stage, total, e.timestep)
            assert stage.damping is not None
            before = e.set_damping(stage.damping)
            try:
                done = 0
                while done < total:
                    k = min(self.chunk, total - done)
                    self.advance(stage, k, total)
                    done += k
                    self.report(stage, done, total)
            finally:
                e.set_damping(before)
        elif stage.kind in ("properties", "boundary"):
            # The engine's properties (the note's after a restart) and the runner's masks,
            # which the stage changes in place (`StageEffects.apply`, as the replays do).
            effects = StageEffects(
                e.default, dict(e.properties), self.fixed, self.velocity, removed_of(e)
            )
            changed = effects.apply(stage, self.model, self.setup.layout)
            if stage.kind == "properties":
                e.default = effects.default
                e.apply_properties(changed)
            else:
                e.apply_boundary(self.fixed, self.velocity)
        elif stage.kind == "reset":
            self.reference = e.positions()
        elif stage.kind == "excavate":
            self.excavate(stage)
        elif stage.kind == "save":
            self.save(index, stage)
        elif stage.kind == "factor_of_safety":
            safety = self.factor_of_safety(index, stage)
        else:  # pragma: no cover - refused before the run (engine.unsupported)
            raise NotImplementedError(stage.kind)
        return StageResult(
            stage.name,
            stage.kind,
            e.steps - start_steps,
            e.time - start_time,
            e.ratio,
            converged,
            safety,
            damping=stage.damping,
        )

    def report(self, stage: Stage, done: int, total: int | None) -> None:
        if self.progress is not None:
            self.progress(self.engine, stage, done, total)

    def solve(
        self,
        stage: Stage,
        ratio: float,
        max_steps: int,
        engine: Any = None,
        stop: Callable[[Any], bool] | None = None,
    ) -> bool:
        """Steps until the ratio is below `ratio`, at most `max_steps`; whether it got
        there. With `engine` (a trial): on that engine, without history; with `stop`, it
        also ends (not there) once `stop(engine)` holds, checked as the ratio is."""
        e = self.engine if engine is None else engine
        done = 0
        while done < max_steps:
            k = min(self.chunk, max_steps - done)
            if engine is None:
                self.advance(stage, k, None)
            else:
                e.cycle(k)
            done += k
            if engine is None:
                self.report(stage, done, None)
            if e.ratio < ratio:
                return True
            if stop is not None and stop(e):
                return False
        return False

    # --- excavation and restart (docs/models.md) ---------------------------------------

    def excavate(self, stage: Stage) -> None:
        """Removes the blocks of the stage's region (their centroid in it), then steps
        ``relax_steps`` steps while their forces on the rock that stays relax to zero."""
        assert stage.region is not None
        self.engine.excavate(self.setup.layout.regions[stage.region], stage.relax_steps)
        done = 0
        while done < stage.relax_steps:
            k = min(self.chunk, stage.relax_steps - done)
            self.advance(stage, k, stage.relax_steps)
            done += k
            self.report(stage, done, stage.relax_steps)

    def save(self, index: int, stage: Stage) -> None:
        """Writes a restart file: the engine's state, with a note of where the run stands
        (the next stage, the displacement reference, the boundary masks, the joint
        properties of the model's sets, whether each solve stage so far reached
        equilibrium) so that ``--restart`` goes on from here."""
        assert stage.file is not None
        path = save_path(stage.file, self.folder)
        if path.parent.resolve() == self.folder.resolve():
            # The results folder (`check_saves` let it be missing): the command line makes
            # it before the run, a caller of the Python API may not have.
            # (A file by that name: the save below fails, naming its file.)
            with contextlib.suppress(FileExistsError):
                self.folder.mkdir(parents=True, exist_ok=True)
        e = self.engine
        note = {
            "penedge_simulate": RESTART_NOTE_VERSION,
            "title": self.model.title,
            "next_stage": index + 1,
            "stage": stage.name,
            "reference": self.reference.tolist(),
            "fixed": self.fixed.tolist(),
            "velocity": [[None if math.isnan(x) else x for x in row] for row in self.velocity],
            "default": e.default.__dict__,
            "properties": {name: p.__dict__ for name, p in e.properties.items()},
            "solves": self.earlier + self.solves,
            "blocks": blocks_fingerprint(self.setup.blocks),
            "stages_run": [stage_record(s) for s in self.model.stages[: index + 1]],
            "settings": model_settings(self.model, self.setup.layout),
        }
        e.save(path, json.dumps(note))

    def restore(self, path: Path) -> None:
        """Goes on from the restart file `path` (see :meth:`save`)."""
        e = self.engine
        fresh = getattr(e, "sim", None)  # the model's own simulation, before the file's
        text = e.restore(path)
        self.reference = e.positions()
        try:
            note = json.loads(text) if text else None
        except json.JSONDecodeError:
            note = None
        if not (isinstance(note, dict) and note.get("penedge_simulate") == RESTART_NOTE_VERSION):
            return  # a state saved outside a model run: every stage runs on it
        n = len(self.reference)
        written = note.get("blocks")  # none in files written before 2026-11-28
        if written is not None and written != blocks_fingerprint(self.setup.blocks):
            raise ModelError(
                "restart",
                f"{path} was written by a run of another model: its {n} blocks are not this "
                "model's (other joints, domain or options give other blocks; restart a run "
                "with the model file that wrote it)",
            )
        if note["next_stage"] > len(self.model.stages):
            raise ModelError(
                "restart",
                f"{path} was saved after stage {note['next_stage'] - 1} ({note['stage']}), "
                f"but the model has {len(self.model.stages)} stages",
            )
        unknown = set(note["properties"]) - set(self.model.set_names)
        if unknown:
            raise ModelError(
                "restart", f"{path} has joint sets the model has not: {', '.join(sorted(unknown))}"
            )
        check_save_stage(self.model, path, note)
        differences = restart_differences(self.setup, note, fresh, getattr(e, "sim", None))
        differences += excavation_differences(self.setup, note["next_stage"], removed_of(e))
        if differences:
            raise ModelError(
                "restart",
                f"--restart: {path} was saved by a run with other settings than this model's "
                f"up to its save stage {note['stage']}: "
                + "; ".join(differences)
                + ". The settings and the stages up to the save must be those of the run "
                "that wrote the file (only the stages after it may change): run the model "
                "afresh without --restart, or restore the settings",
            )
        self.first = note["next_stage"]
        self.reference = np.array(note["reference"], dtype=float).reshape(n, 3)
        self.fixed = np.array(note["fixed"], dtype=bool)
        self.velocity = np.array(
            [[math.nan if x is None else x for x in row] for row in note["velocity"]], dtype=float
        ).reshape(n, 3)
        e.default = JointProperties(**note["default"])
        e.properties = {k: JointProperties(**v) for k, v in note["properties"].items()}
        self.earlier = [bool(x) for x in note.get("solves", [])]  # none in older files

    # --- factor of safety -----------------------------------------------------------

    def snapshot(self, index: int) -> Any:
        """An engine in the state at the start of stage `index`: a copy of the current one,
        or (when the engine cannot be copied) a fresh one that replays the stages before."""
        try:
            return self.engine.copy()
        except (AttributeError, NotImplementedError):
            replay = Runner(self.setup, self.factory, folder=self.folder)
            for k, stage in enumerate(self.model.stages[:index]):
                if stage.kind != "save":  # written once, by the run itself
                    replay.run_stage(k, stage)
            return replay.engine

    def factor_of_safety(self, index: int, stage: Stage) -> SafetyFactor:
        """Bisection on the strength reduction factor F (docs/models.md)."""
        assert stage.ratio is not None
        assert stage.max_steps is not None
        names = stage.sets or tuple(self.model.set_names)
        reduce_default = not stage.sets
        original = {name: self.engine.properties[name] for name in names}
        default = self.engine.default
        free = free_of(self.fixed, self.velocity, removed_of(self.engine))
        if not free.any():
            raise ModelError(f"stages[{index}]", NO_FREE_BLOCK)
        # Blocks held by no contact at the start (a step taken: before it none has a force).
        unheld: list[int] = []
        if self.engine.steps > 0:
            unheld = np.flatnonzero(free & ~self.engine.held()).tolist()
        threshold = self.model.results.moved
        limit = self.displacement_limit(stage)
        # Blocks that came to rest far from where they started (loads applied at once can
        # slide a block before the trials: docs/models.md, "Loads applied at once").
        # Farther than CAUTION_TIMES a trial's limit: the start's elastic closure and a little
        # slip are not a change of geometry (wedge_water.toml's first solve moves its wedge
        # 47.9 mm, 1.1 % of its size, and its F is limit equilibrium's).
        before_trials = np.linalg.norm(self.engine.positions() - self.reference, axis=1)
        moved_before = np.flatnonzero(free & (before_trials > CAUTION_TIMES * limit))
        trials: list[Trial] = []

        def trial(factor: float) -> Trial:
            e = self.snapshot(index)
            if reduce_default:
                e.default = default.reduced(factor)
            e.apply_properties({n: p.reduced(factor) for n, p in original.items()}, factor)
            before, turned = e.positions(), e.rotations()
            start = e.steps  # the engine's count so far: the trial's own steps are after it

            def gone(e: Any) -> bool:
                # A block beyond the limit has failed the trial: no need to step on.
                far = np.linalg.norm(e.positions() - before, axis=1) > limit
                return bool((free & far).any())

            try:
                converged = self.solve(
                    stage, stage.ratio or 0.0, stage.max_steps or 0, engine=e, stop=gone
                )
                broke = False
            except MechanicsError as error:
                # Blocks driven into each other: the reduced strength is failing. Any other
                # error (a NaN, a bad parameter) is no verdict on the strength: it stops the
                # run as it would any other stage.
                if getattr(error, "kind", None) != "penetration":
                    raise
                converged, broke = False, True
            speeds = np.linalg.norm(e.velocities(), axis=1)
            speed = float(speeds[free].max(initial=0.0))
            distance = np.linalg.norm(e.positions() - before, axis=1)
            # Failing: still moving when the steps ran out, driven into other blocks, or
            # moved farther than the limit, where it may have come to rest (a block that
            # slid off its plane onto the bench below: equilibrium, not stability).
            beyond = np.flatnonzero(free & (distance > limit))
            failed = broke or (not converged and speed > stage.velocity) or beyond.size > 0
            far = distance > np.minimum(limit, threshold)  # the blocks beyond the limit too
            moved = np.flatnonzero(free & (far | (speeds > stage.velocity)))
            angle = rotation_degrees(turned[moved], e.rotations()[moved])
            t = Trial(
                factor,
                failed,
                e.steps - start,
                e.ratio,
                speed,
                moved.tolist(),
                distance[moved].tolist(),
                angle.tolist(),
                beyond.tolist(),
            )
            trials.append(t)
            if self.progress is not None:
                self.progress(e, stage, len(trials), None)
            return t

        stable: Trial | None = None
        failing: Trial | None = None
        t = trial(1.0)
        # Widen by halving or doubling, the last trial at `low` or `high` itself.
        if t.failed:
            failing = t
            f = 1.0
            while f > stage.low:
                f = max(f / 2, stage.low)
                t = trial(f)
                if not t.failed:
                    stable = t
                    break
                failing = t
        else:
            stable = t
            f = 1.0
            while f < stage.high:
                f = min(f * 2, stage.high)
                t = trial(f)
                if t.failed:
                    failing = t
                    break
                stable = t
        if stable is not None and failing is not None:
            while failing.factor - stable.factor > stage.tolerance:
                middle = 0.5 * (stable.factor + failing.factor)
                if not stable.factor < middle < failing.factor:
                    # Two neighbouring floats: no factor lies between them, and the bracket
                    # cannot narrow (a `tolerance` below the floats' spacing, given outside
                    # a model file, which refuses it: MIN_RELATIVE_TOLERANCE).
                    break
                t = trial(middle)
                if t.failed:
                    failing = t
                else:
                    stable = t
        factor = stable.factor if stable is not None else (failing.factor if failing else 1.0)
        return SafetyFactor(
            start_ratio=self.engine.ratio,
            in_equilibrium=bool(self.engine.ratio <= stage.ratio),
            target=stage.ratio,
            factor=factor,
            stable=None if stable is None else stable.factor,
            failing=None if failing is None else failing.factor,
            failing_blocks=[] if failing is None else failing.moved,
            trials=trials,
            failing_displacement=[] if failing is None else failing.displacement,
            failing_rotation=[] if failing is None else failing.rotation,
            unheld_blocks=unheld,
            moved_before=moved_before.tolist(),
            moved_before_displacement=before_trials[moved_before].tolist(),
        )

    def displacement_limit(self, stage: Stage) -> np.ndarray:
        """Per block, how far it may move in a trial of `stage` that does not fail: the
        stage's ``displacement``, else 1 % of the block's size (the cube root of its body's
        volume: a concave block's parts share their body's)."""
        n = len(self.reference)
        if stage.displacement is not None:
            return np.full(n, stage.displacement)
        volumes = np.asarray(self.setup.blocks.volumes, dtype=float)
        bodies = self.setup.layout.bodies
        if bodies is None:  # every block its own body
            return DISPLACEMENT_SHARE * np.cbrt(volumes)
        body = np.asarray(bodies, dtype=np.int64)
        volume = np.bincount(body, volumes, minlength=int(body.max()) + 1)
        return DISPLACEMENT_SHARE * np.cbrt(volume[body])


def rotation_degrees(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """The angle (degrees, 0 to 180) of the rotation from each unit quaternion of
    `before` to the one of `after` (rows ``x, y, z, w``): ``2 atan2(|v|, |w|)`` of
    ``after * conj(before)``, exact for small angles (where ``acos`` of the dot product is
    not)."""
    b, a = np.asarray(before, dtype=float), np.asarray(after, dtype=float)
    bv, bw = -b[:, :3], b[:, 3]  # the conjugate of `before`
    av, aw = a[:, :3], a[:, 3]
    w = aw * bw - np.einsum("ij,ij->i", av, bv)
    v = aw[:, None] * bv + bw[:, None] * av + np.cross(av, bv)
    return np.degrees(2.0 * np.arctan2(np.linalg.norm(v, axis=1), np.abs(w)))


def timestep_of(engine: Any) -> float | None:
    """The engine's time step (s), or None where it has none (no free block yet, or an
    engine without one)."""
    try:
        dt = float(engine.timestep)
    except (AttributeError, PenedgeError):
        return None
    return dt if math.isfinite(dt) and dt > 0 else None


def time_steps(time: float, timestep: float) -> int:
    """The steps a ``time`` stage of `time` seconds takes at `timestep` (at least one)."""
    return max(1, math.ceil(time / timestep - 1e-9))


def refuse_long_time_stage(index: int, stage: Stage, steps: int, timestep: float) -> None:
    """A ``time`` stage of more than :data:`~penedge.model.fields.MAX_STEPS` steps is an
    error naming it, its steps and the time step."""
    if steps <= MAX_STEPS:
        return
    raise ModelError(
        f"stages[{index}].time",
        f"{stage.name} (time) runs {stage.time:g} s, {steps:,} steps of {timestep:.3g} s: "
        f"more than {MAX_STEPS:.0e} ({MAX_STEPS_WHY})",
    )


def check_time_stages(model: Model, timestep: float | None, first: int = 0) -> None:
    """Before any step: no ``time`` stage from stage `first` on takes more than
    :data:`~penedge.model.fields.MAX_STEPS` steps at `timestep`, the time step the engine
    starts with (a stage that changes it, a ``properties`` stage raising kn, is checked
    again when the time stage starts)."""
    if timestep is None:
        return
    for i, stage in enumerate(model.stages):
        if i >= first and stage.kind == "time" and stage.time is not None:
            refuse_long_time_stage(i, stage, time_steps(stage.time, timestep), timestep)


@dataclass
class StagePlan:
    """What a stage will take, before the run (``penedge simulate --check``, and the
    start of a long run): its steps (exact, or at most: a ``solve`` may converge sooner),
    its history points and ParaView frames; a factor of safety's at most `trials` trials of
    at most `steps` steps each (on copies: no history, no frame)."""

    index: int
    name: str
    kind: str
    steps: int | None  # None: a time stage without a known time step
    exact: bool
    history: int = 0
    frames: int = 0
    trials: int = 0
    damping: float | None = None  # cycle, time: the local damping it will step with


def safety_trials(stage: Stage) -> int:
    """The most trials a factor of safety takes: F = 1, the widening to `low` or `high`,
    then the bisection of a bracket of at most half the widest step down to `tolerance`."""
    up = math.ceil(math.log2(stage.high)) if stage.high > 1 else 0
    down = math.ceil(math.log2(1 / stage.low)) if stage.low < 1 else 0
    halvings = max(0, math.ceil(math.log2(max(stage.high / 2, 0.5) / stage.tolerance)))
    return 1 + max(up, down) + halvings


def plan_stages(model: Model, timestep: float | None, first: int = 0) -> list[StagePlan]:
    """Per stage that takes steps, from stage `first` on: its :class:`StagePlan`, with
    `timestep` for the time stages (the engine's at the start)."""
    every = model.results.history_every
    frame_every = model.results.frame_every
    plans = []
    for i, stage in enumerate(model.stages):
        if i < first:
            continue
        trials = 0
        if stage.kind == "cycle":
            steps: int | None = stage.steps
            exact = True
        elif stage.kind == "time":
            assert stage.time is not None
            steps = None if timestep is None else time_steps(stage.time, timestep)
            exact = True
        elif stage.kind == "excavate":
            steps, exact = stage.relax_steps, True
        elif stage.kind == "solve":
            steps, exact = stage.max_steps, False
        elif stage.kind == "factor_of_safety":
            steps, exact, trials = stage.max_steps, False, safety_trials(stage)
        else:
            continue
        plan = StagePlan(
            i, stage.name, stage.kind, steps, exact, trials=trials, damping=stage.damping
        )
        if steps is not None and not trials:
            plan.history = -(-steps // every)
            plan.frames = 1 + (steps // frame_every if frame_every else 0)
        plans.append(plan)
    return plans


def below_one(factor: float) -> str:
    """A factor of safety below 1, with the digits that keep it below 1 when read:
    ``0.80``, ``0.996`` (not ``1.00``), ``0.99999``."""
    for digits in range(2, 10):
        text = f"{factor:.{digits}f}"
        if float(text) < 1:
            return text
    return repr(factor)


#: The version of the note a ``save`` stage keeps in its restart file.
RESTART_NOTE_VERSION = 1

#: The default displacement limit of a factor of safety's trial, as a share of a block's size.
DISPLACEMENT_SHARE = 0.01

#: A free block that moved farther than this many times a trial's displacement limit before
#: the trials is named in a CAUTION: F is that of where it came to rest.
CAUTION_TIMES = 5.0

#: Why a ``factor_of_safety`` stage without a free block cannot run.
NO_FREE_BLOCK = (
    "a factor of safety needs a free block to fail, and every block is fixed, driven or "
    "excavated by this stage (by [[boundary]], boundary and excavate stages)"
)


#: The stages that take steps: after one, the blocks rest on their contacts' overlaps.
STEPPING_STAGES = ("solve", "cycle", "time", "excavate")


def stiffening_warnings(model: Model, first: int = 0) -> list[str]:
    """A warning for each ``properties`` stage that raises ``kn`` (of a set, or the default
    properties) after a stage that took steps. The normal force comes from the blocks'
    total overlap (docs/mechanics.md, "Normal force: total"), so the overlap they settled
    with is pushed harder at once and the blocks move to a new equilibrium: a tenfold kn
    throws them. ``ks`` is not warned of: the shear force is incremental, a stiffer ks
    changes the steps after, not the force now. Only for the stages from `first` on (a run
    restarted there runs none before it)."""
    kn = {name: p.kn for name, p in model.properties.items()}
    default = model.default_properties.kn
    stepped: Stage | None = None
    warnings = []
    for index, stage in enumerate(model.stages):
        if stepped is None and stage.kind in STEPPING_STAGES:
            stepped = stage
        if stage.kind != "properties" or "kn" not in stage.changes:
            continue
        new = stage.changes["kn"]
        names = stage.sets or tuple(model.set_names)
        before = {name: kn[name] for name in names}
        if not stage.sets:  # every set, and the contacts of no set (as the run applies it)
            before["the default properties"] = default
            default = new
        kn.update(dict.fromkeys(names, new))
        raised = [name for name, old in before.items() if new > old]
        if stepped is None or not raised or index < first:
            continue
        old = min(before[name] for name in raised)
        warnings.append(
            f"{stage.name} raises kn from {old:g} to {new:g} Pa/m ({', '.join(raised)}) "
            f"after {stepped.name} ({stepped.kind}) took steps: the normal force comes from "
            f"the blocks' total overlap, so the overlap they settled with is pushed up to "
            f"{new / old:.3g} times harder at once and the blocks are thrown towards a new "
            "equilibrium; give kn before the first solve, or expect a new settlement "
            '(docs/models.md, the "properties" stage)'
        )
    return warnings


def brittle_warnings(model: Model, first: int = 0) -> list[str]:
    """A warning for each ``factor_of_safety`` stage that reduces a brittle strength: a
    joint set (or the default properties, or a set's rock bridges) whose cohesion or tension
    is above its residual value (3DEC's default residual is 0), or whose residual friction
    is below its friction, when the stage runs. A sub-contact that reaches its strength then
    loses it, and the load it sheds can fail the next: F includes that progressive failure,
    and can lie far below limit equilibrium's, which has the whole strength at once
    (docs/models.md, "Brittle cohesion"). Only for the stages from `first` on (a run
    restarted there runs none before it)."""
    properties = dict(model.properties)
    default = model.default_properties
    warnings = []
    for index, stage in enumerate(model.stages):
        if stage.kind == "properties":  # as the run applies it (StageEffects.apply)
            default, changed = properties_changed(stage, model, default, properties)
            properties.update(changed)
            continue
        if stage.kind != "factor_of_safety" or index < first:
            continue
        names = stage.sets or tuple(model.set_names)
        reduced = [(name, properties[name]) for name in names]
        if not stage.sets:
            reduced.append(("the default properties", default))
        reduced += [
            (f"{name}'s rock bridges", model.bridges[name])
            for name in names
            if name in model.bridges
        ]
        brittle = []
        for name, p in reduced:
            if p.cohesion > p.residual_cohesion:
                brittle.append(
                    f"{name} (cohesion {p.cohesion:g} Pa, residual {p.residual_cohesion:g})"
                )
            if p.tension > p.residual_tension:
                brittle.append(
                    f"{name} (tension {p.tension:g} Pa, residual {p.residual_tension:g})"
                )
            residual = p.friction if p.residual_friction is None else p.residual_friction
            if residual < p.friction:
                brittle.append(f"{name} (friction {p.friction:g}°, residual {residual:g}°)")
        if not brittle:
            continue
        warnings.append(
            f"{stage.name} (factor_of_safety) reduces brittle strength: {', '.join(brittle)}. "
            "A joint loses it where it reaches its strength, and the load it sheds can fail "
            "the rest: F includes this progressive failure and can lie well below limit "
            "equilibrium's, which has the whole strength at once (a wedge on joints of 2 and "
            "6 kPa cohesion: 1.15 against 1.47). For limit equilibrium's assumption give "
            "residual_cohesion = cohesion and residual_friction = friction (a tension is "
            'lost whatever: docs/models.md, "Brittle cohesion")'
        )
    return warnings


#: A bolt's ``rupture_strain`` above this is warned of: steel bolts and cables break at a
#: few to some 15 % (0.02 to 0.15); 20 % is more than a steel bar stretches.
RUPTURE_STRAIN_WARNED = 0.2

#: Water lighter than this (kg/m³) is warned of: water is 1000, a brine more; 1 is a
#: density in t/m³ (or g/cm³) typed for kg/m³.
WATER_DENSITY_WARNED = 500.0

#: A bolt whose collar lies farther outside the rock than this share of its length is
#: warned of: its elements (in the rock only) are that much stiffer than `stiffness`.
BOLT_OUTSIDE_WARNED = 0.01


def input_warnings(model: Model) -> list[str]:
    """A warning for each value of the model file that is accepted but likely a mistake
    (docs/models.md, "Warnings"): a bolt's ``rupture_strain`` above
    :data:`RUPTURE_STRAIN_WARNED` (a percent typed), ``[water] density`` below
    :data:`WATER_DENSITY_WARNED` (t/m³ typed for kg/m³), a uniform ``[initial_stress]``
    with a tensile principal stress (compression is negative: a sign missed)."""
    warnings = []
    for i, bolt in enumerate(model.bolts):
        if bolt.rupture_strain is not None and bolt.rupture_strain > RUPTURE_STRAIN_WARNED:
            warnings.append(
                f"bolts[{i}].rupture_strain = {bolt.rupture_strain:g} is a strain of "
                f"{100 * bolt.rupture_strain:g} %: steel bolts break at a few to some 15 % "
                "(0.02 to 0.15); a percent typed? (give 5 % as 0.05)"
            )
    if model.water is not None and model.water.density < WATER_DENSITY_WARNED:
        warnings.append(
            f"water.density = {model.water.density:g} kg/m³: water is 1000 kg/m³; a "
            "density in t/m³ typed? (the joints' water pressure is "
            f"{model.water.density / 1000:.3g} of water's)"
        )
    stress = model.initial_stress
    if stress is not None and stress.kind == "uniform":
        xx, yy, zz, xy, yz, zx = stress.components
        tensor = np.array([[xx, xy, zx], [xy, yy, yz], [zx, yz, zz]])
        largest = float(np.linalg.eigvalsh(tensor).max())
        if largest > 0:
            warnings.append(
                f"initial_stress is tensile in some direction (its largest principal stress "
                f"is +{largest:.4g} Pa; compression is negative, as in 3DEC): joints across "
                "that direction without tensile strength cannot hold it and open at once, "
                "and what they held moves; for a compressive stress give it negative"
            )
    return warnings


def layout_warnings(setup: Any) -> list[str]:
    """A warning for each input that the blocks show to be likely a mistake (docs/models.md,
    "Warnings"): a bolt whose collar lies farther outside the rock than
    :data:`BOLT_OUTSIDE_WARNED` of its length (it is installed from the rock face, and its
    stiffness, ``EA / length`` of the whole bolt, then acts on the part in the rock), and a
    support whose blocks are all fixed or driven (a pressure on them does nothing)."""
    model, layout = setup.model, setup.layout
    warnings = []
    for i, (bolt, path) in enumerate(zip(model.bolts, layout.bolt_paths, strict=True)):
        if path.outside <= BOLT_OUTSIDE_WARNED * bolt.length:
            continue
        warnings.append(
            f"bolts[{i}].point: the collar {point_text(bolt.point)} lies {path.outside:.3g} m "
            f"outside the rock along the bolt: the bolt is installed from where it enters the "
            f"rock (block {path.blocks[0]}), {path.in_rock:.3g} m of its {bolt.length:g} m, "
            f"and as stiffness = {bolt.stiffness:g} N/m is EA / length of the whole "
            f"{bolt.length:g} m, those {path.in_rock:.3g} m are "
            f"{bolt.length / path.in_rock:.3g} times as stiff; put the collar on the rock face "
            "and give the length in the rock"
        )
    held = layout.fixed | layout.driven
    freed = np.zeros(len(held), bool)
    for stage in model.stages:
        b = stage.boundary
        if stage.kind == "boundary" and b is not None and b.condition != "fixed":
            region = layout.regions.get(b.region)
            freed |= True if region is None else region
    for i, (support, blocks) in enumerate(zip(model.support, layout.support_blocks, strict=True)):
        if not held[blocks].all() or freed[blocks].any():
            continue
        warnings.append(
            f"support[{i}].region: every block the support {support.name!r} pushes on "
            f"({block_list(blocks)}) is fixed or driven: a pressure on them does nothing; "
            "give a region of free blocks"
        )
    return warnings


# --- what a restart file must share with the model (docs/models.md, "Restart") --------


def plain(value: Any) -> Any:
    """`value` (dataclasses, tuples, numpy numbers) as the JSON data a restart note keeps,
    so that a value of the model compares equal to the one read back from a note."""

    def data(item: Any) -> Any:
        if dataclasses.is_dataclass(item) and not isinstance(item, type):
            return dataclasses.asdict(item)
        return float(item)

    return json.loads(json.dumps(value, default=data))


def stage_record(stage: Stage) -> dict[str, Any]:
    """A stage's fields as a note keeps them (every stage up to a ``save``)."""
    record: dict[str, Any] = plain(stage)
    return record


def model_settings(model: Model, layout: Any) -> dict[str, Any]:
    """The settings of `model` that act from its first step on, by the field that sets
    them: what a restart file must have been written with (its note keeps them)."""
    m = model.mechanics
    support = []
    for i, s in enumerate(model.support):
        mask = layout.regions.get(s.region)
        blocks = [] if mask is None else np.flatnonzero(mask).tolist()
        area = layout.support_areas[i] if i < len(layout.support_areas) else None
        support.append({**plain(s), "blocks": blocks, "area": area})
    settings: dict[str, Any] = plain(
        {
            "rock.density": m.density,
            "mechanics.gravity": m.gravity,
            "mechanics.damping": m.damping,
            "mechanics.time_step": m.time_step,
            "mechanics.gap": m.gap,
            "mechanics.point_width": m.point_width,
            "mechanics.mass_scaling": m.mass_scaling,
            "seismic": model.seismic,
            "water": model.water,
            "bolts": [plain(b) for b in model.bolts],
            "support": support,
            "initial_stress": model.initial_stress,
            "joint_properties (rock bridges)": {k: plain(v) for k, v in model.bridges.items()},
        }
    )
    return settings


def shown(value: Any) -> str:
    """A setting's value in a message: ``none``, ``35``, ``(0, 0, -9.81)``,
    ``{coefficient 0.05, azimuth 90}``."""
    if value is None or value == [] or value == {}:
        return "none"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float | int):
        return f"{value:g}"
    if isinstance(value, list):
        if all(isinstance(v, float | int) and not isinstance(v, bool) for v in value):
            return "(" + ", ".join(f"{v:g}" for v in value) + ")"
        return "[" + ", ".join(shown(v) for v in value) + "]"
    if isinstance(value, dict):
        items = [f"{k} {shown(v)}" for k, v in value.items() if v not in (None, [], {})]
        return "{" + ", ".join(items) + "}"
    return str(value)


@dataclass
class StageEffects:
    """What the ``properties``, ``boundary`` and ``excavate`` stages leave: the default
    joint properties, those of each set, the boundary masks (per block: `fixed`, and
    `velocity`, NaN where not driven) and the excavated blocks (`removed`). The run and the
    checks before it (`check_safety_stages`, a restart's `resolved_at` and
    `excavation_differences`) apply the stages alike: :meth:`apply`, :func:`replay`."""

    default: JointProperties
    properties: dict[str, JointProperties]
    fixed: np.ndarray
    velocity: np.ndarray
    removed: np.ndarray

    @classmethod
    def initial(cls, model: Model, layout: Any) -> StageEffects:
        """Before the first stage: the model's properties, its ``[[boundary]]`` masks."""
        return cls(
            model.default_properties,
            dict(model.properties),
            layout.fixed.copy(),
            layout.velocity.copy(),
            np.zeros(len(layout.fixed), bool),
        )

    def apply(self, stage: Stage, model: Model, layout: Any) -> dict[str, JointProperties]:
        """The effect of `stage`, in place (the arrays too); for a ``properties`` stage, the
        sets it changes with their new properties (empty for another stage)."""
        if stage.kind == "properties":
            self.default, changed = properties_changed(stage, model, self.default, self.properties)
            self.properties.update(changed)
            return changed
        if stage.kind == "boundary" and stage.boundary is not None:
            b = stage.boundary
            mask = layout.regions[b.region]
            apply_boundary(self.fixed, self.velocity, mask, b.condition, b.velocity, layout.bodies)
        elif stage.kind == "excavate" and stage.region is not None:
            self.removed |= layout.regions[stage.region]
        return {}


def properties_changed(
    stage: Stage,
    model: Model,
    default: JointProperties,
    properties: dict[str, JointProperties],
) -> tuple[JointProperties, dict[str, JointProperties]]:
    """What the ``properties`` stage `stage` makes of the default properties `default` and
    those of the sets (`properties`): the new default (changed only by a stage of every
    set: the contacts of no set too) and the sets it changes with their new properties."""
    names = stage.sets or tuple(model.set_names)
    if not stage.sets:
        default = merge(default, stage.changes)
    return default, {name: merge(properties[name], stage.changes) for name in names}


def replay(model: Model, layout: Any, upto: int) -> StageEffects:
    """The effects of the model's stages before stage `upto`, from its initial state."""
    effects = StageEffects.initial(model, layout)
    for stage in model.stages[:upto]:
        effects.apply(stage, model, layout)
    return effects


def resolved_at(setup: Any, upto: int) -> tuple[Any, dict[str, Any], np.ndarray, np.ndarray]:
    """The default joint properties, those of each set and the boundary masks (fixed,
    velocity) of the model as its stages before stage `upto` leave them (as the run
    applies them: `Runner.run_stage`)."""
    effects = replay(setup.model, setup.layout, upto)
    return effects.default, effects.properties, effects.fixed, effects.velocity


def check_save_stage(model: Model, path: Path, note: dict[str, Any]) -> None:
    """The stage a restart file was saved by is, at its place, a ``save`` stage of the
    model of that name: otherwise the run would go on after another stage (the stages
    before the save were edited: one inserted, removed, or the save itself removed)."""
    k = note["next_stage"] - 1
    there = model.stages[k]
    if there.kind == "save" and there.name == note["stage"]:
        return
    saves = [s.name for s in model.stages if s.kind == "save"]
    has = f"its save stages are {', '.join(saves)}" if saves else "it has no save stage"
    raise ModelError(
        "restart",
        f"--restart: {path} was written by the save stage {note['stage']} (stage {k}; the "
        f"run would go on at stage {k + 1}), but this model's stage {k} is {there.name}, a "
        f"{there.kind} stage ({has}): the stages up to the save must be those of the run "
        "that wrote the file; only the stages after it may change",
    )


def restart_differences(setup: Any, note: dict[str, Any], fresh: Any, loaded: Any) -> list[str]:
    """What differs between the model, as its stages before the save leave it, and the
    run that wrote a restart file's `note`: each as ``field: the model says X, the file
    Y``. The settings of the note (files written since 2026-11-28 night); for an older
    file, the gravity, damping and masses of the `fresh` simulation (the model's) and the
    `loaded` one (the file's) instead."""
    model, layout = setup.model, setup.layout
    upto = note["next_stage"]
    found: list[str] = []

    def differ(name: str, mine: Any, theirs: Any) -> None:
        if mine != theirs:
            found.append(f"{name}: the model says {shown(mine)}, the file {shown(theirs)}")

    records = note.get("stages_run")
    if records is not None:
        for stage, record in zip(model.stages[:upto], records, strict=False):
            mine = stage_record(stage)
            if mine["kind"] != record.get("kind"):
                found.append(
                    f"{stage.name}: a {stage.kind} stage in the model, a {record.get('kind')} "
                    "stage in the file"
                )
                continue
            for key, value in mine.items():
                if key != "file" and key in record:  # a save's file may move
                    differ(f"{stage.name}.{key}", value, record[key])
    settings = note.get("settings")
    if settings is not None:
        for key, value in model_settings(model, layout).items():
            if key in settings:
                differ(key, value, settings[key])
            elif key == "mechanics.mass_scaling":  # a file from before it: none
                differ(key, value, False)
    elif fresh is not None and loaded is not None:
        mine_g = [round(float(x), 12) + 0.0 for x in np.asarray(fresh.gravity)]
        their_g = [round(float(x), 12) + 0.0 for x in np.asarray(loaded.gravity)]
        differ("mechanics.gravity (with [seismic])", mine_g, their_g)
        differ("mechanics.damping", list(fresh.damping), list(loaded.damping))
        differ("mechanics.mass_scaling", model.mechanics.mass_scaling, False)  # none then
        mine_m, their_m = float(np.sum(fresh.masses)), float(np.sum(loaded.masses))
        if not math.isclose(mine_m, their_m, rel_tol=1e-12):
            density = model.mechanics.density
            found.append(
                f"rock.density: the model says {density:g}, the file "
                f"{density * their_m / mine_m:.6g} (its blocks weigh {their_m:.6g} kg, the "
                f"model's {mine_m:.6g} kg)"
            )
    default, properties, fixed, velocity = resolved_at(setup, upto)
    differ_props = [("default", default, note["default"])]
    differ_props += [(name, properties[name], note["properties"].get(name)) for name in properties]
    for name, props, theirs in differ_props:
        if theirs is None:
            continue
        for key, value in plain(props).items():
            if key in theirs:
                differ(f"joint_properties.{name}.{key}", value, theirs[key])
    n = len(fixed)
    their_fixed = np.array(note["fixed"], dtype=bool)
    their_velocity = np.array(
        [[math.nan if x is None else x for x in row] for row in note["velocity"]], dtype=float
    ).reshape(n, 3)
    same_velocity = (velocity == their_velocity) | (np.isnan(velocity) & np.isnan(their_velocity))
    wrong = np.flatnonzero((fixed != their_fixed) | ~same_velocity.all(axis=1))
    if len(wrong):

        def condition(f: np.ndarray, v: np.ndarray, i: int) -> str:
            if f[i]:
                return "fixed"
            if np.isnan(v[i, 0]):
                return "free"
            return "driven at ({:g}, {:g}, {:g}) m/s".format(*v[i])

        some = ", ".join(
            f"block {i} {condition(fixed, velocity, i)} in the model, "
            f"{condition(their_fixed, their_velocity, i)} in the file"
            for i in wrong[:5]
        )
        more = f" and {len(wrong) - 5} more" if len(wrong) > 5 else ""
        found.append(f"the boundary conditions ([[boundary]] and boundary stages): {some}{more}")
    return found


def excavation_differences(setup: Any, upto: int, removed: np.ndarray) -> list[str]:
    """The blocks the model's excavate stages before stage `upto` remove, against those the
    restart file has removed (`removed`), if they differ (an edited region)."""
    expected = replay(setup.model, setup.layout, upto).removed
    if np.array_equal(expected, removed):
        return []
    mine = block_list(np.flatnonzero(expected)) or "none"
    theirs = block_list(np.flatnonzero(removed)) or "none"
    return [f"the excavated blocks: the model's excavate stages remove {mine}, the file {theirs}"]


def free_of(fixed: np.ndarray, velocity: np.ndarray, removed: np.ndarray) -> np.ndarray:
    """The free blocks: not fixed, not driven (a velocity prescribed), not excavated."""
    return ~(fixed | ~np.isnan(velocity[:, 0]) | removed)


def blocks_fingerprint(blocks: Any) -> str:
    """A digest of the model's blocks as generated (their centroids and volumes, relative to
    the model's size, to 6 and 9 digits: another model's blocks change it; a regeneration
    that differs in the last bits changes it only where a value lies at a rounding boundary,
    and the same build regenerates the same bits), kept in a restart file so that a run does
    not go on from another model's state with the same number of blocks."""
    size = blocks.size if blocks.size > 0 else 1.0
    # + 0.0: a negative zero after rounding is the positive one.
    centroids = np.round(np.asarray(blocks.centroids, float) / size, 6) + 0.0
    volumes = np.round(np.asarray(blocks.volumes, float) / size**3, 9) + 0.0
    digest = hashlib.sha256(np.int64(len(volumes)).tobytes())
    digest.update(np.ascontiguousarray(centroids).tobytes())
    digest.update(np.ascontiguousarray(volumes).tobytes())
    return digest.hexdigest()[:32]


def removed_of(engine: Any) -> np.ndarray:
    """The blocks `engine` has excavated (none for an engine that cannot excavate)."""
    removed = getattr(engine, "removed", None)
    n = len(engine.positions())
    return np.zeros(n, bool) if removed is None else np.asarray(removed(), dtype=bool)


def check_safety_stages(
    model: Model,
    layout: Any,
    fixed: np.ndarray,
    velocity: np.ndarray,
    removed: np.ndarray | None = None,
    first: int = 0,
) -> None:
    """Before any step: each stage that takes steps (``solve``, ``cycle``, ``time``,
    ``excavate`` with its relaxation steps, ``factor_of_safety``, whose free blocks must
    fail) from stage `first` on has a free block, given the `fixed` and driven (`velocity`
    not NaN) blocks and the `removed` ones at stage `first`, and the boundary and excavate
    stages before it."""
    effects = StageEffects(
        model.default_properties,
        dict(model.properties),
        fixed.copy(),
        velocity.copy(),
        np.zeros(len(fixed), bool) if removed is None else removed.copy(),
    )
    for i, stage in enumerate(model.stages):
        if i < first:
            continue
        effects.apply(stage, model, layout)
        if stage.kind not in (*STEPPING_STAGES, "factor_of_safety"):
            continue
        if not free_of(effects.fixed, effects.velocity, effects.removed).any():
            if stage.kind == "factor_of_safety":
                raise ModelError(f"stages[{i}]", NO_FREE_BLOCK)
            raise ModelError(
                f"stages[{i}]",
                f"{stage.name} ({stage.kind}) takes steps, but every block is fixed, driven or "
                "excavated by then (by [[boundary]], boundary and excavate stages) and the "
                "engine steps only free blocks: free some before it, or remove the stage",
            )


def check_excavations(
    model: Model, regions: dict[str, np.ndarray], bodies: np.ndarray | None = None
) -> None:
    """Before any step: each ``excavate`` stage has rock left to remove (its region's
    blocks are not all removed by earlier stages) and, with `bodies` (the body id of each
    block), removes whole bodies only: a concave block is one rigid body, so a region that
    holds some of its parts and not others is refused (:func:`partial_body`)."""
    removed: np.ndarray | None = None
    for i, stage in enumerate(model.stages):
        if stage.kind != "excavate" or stage.region is None:
            continue
        mask = regions[stage.region]
        split = partial_body(mask, bodies)
        if split is not None:
            raise ModelError(f"stages[{i}].region", split)
        if removed is None:
            removed = np.zeros(len(mask), bool)
        if not (mask & ~removed).any():
            raise ModelError(
                f"stages[{i}].region",
                "every block of its region was excavated by an earlier stage: "
                "this stage removes nothing",
            )
        removed |= mask


def save_path(file: str, folder: Path) -> Path:
    """Where a ``save`` stage's `file` goes: a relative path is in `folder`."""
    path = Path(file)
    return path if path.is_absolute() else folder / path


def check_saves(model: Model, folder: Path, first: int = 0) -> None:
    """Before any step: each ``save`` stage from stage `first` on can write its file (its
    folder exists, or is `folder`, the results folder, made when needed; the file is not a
    folder), so that a run does not stop at a save after hours of steps."""
    for i, stage in enumerate(model.stages):
        if i < first or stage.kind != "save" or stage.file is None:
            continue
        path = save_path(stage.file, folder)
        parent = path.parent
        if path.is_dir():
            problem = f"{path} is a folder"
        elif parent.is_dir() or (parent.resolve() == folder.resolve() and not parent.exists()):
            continue  # the results folder is made when needed (`Runner.save`)
        elif parent.exists():
            problem = f"{parent} is not a folder"
        else:
            problem = f"no folder {parent} to write {path.name} in"
        raise ModelError(f"stages[{i}].file", f"cannot write the restart file: {problem}")


def merge(props: JointProperties, changes: dict[str, float]) -> JointProperties:
    """`props` with `changes`."""
    return JointProperties(**{**props.__dict__, **changes})


def bolt_results(engine: Any) -> list[dict[str, Any]]:
    """Per bolt at the end of the run: name, force, elongation, state (empty without bolts,
    or with an engine that has none)."""
    bolts = getattr(engine, "bolts", None)
    return bolts() if bolts is not None else []
