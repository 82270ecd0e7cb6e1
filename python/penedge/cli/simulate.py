"""``penedge simulate MODEL``: generate the blocks of a model file, run its stages on the
rigid-block engine, and write the results (summary, history, pictures, ParaView series)."""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import math
import re
import sys
import time
from pathlib import Path
from typing import IO, Any

from penedge.cli import progress
from penedge.cli.common import (
    PROG,
    CommandError,
    UsageError,
    add_output_flags,
    plural,
    write_via_temp,
)
from penedge.cli.progress import ProgressBar, StatusLine

EPILOG = """\
worked example:
  $ penedge simulate examples/models/block_column.toml --check
  penedge simulate examples/models/block_column.toml: Block column settling: the model is valid
    blocks                5 (1 fixed, 4 free)
    joint sets            bedding
    stages                stages[0] solve
    monitors              top (block 3)

  --check reads the model, generates its blocks, runs every check (regions, boundary
  conditions, monitors, bolts) and builds the engine as the run does (so that a time
  step above the critical one is refused now), and runs no step. Without it, the stages
  run and the results go into a folder:

more:
  penedge simulate examples/models/block_column.toml -o column
      column/summary.json     stable or not, blocks moved, largest displacement, factor
                              of safety (also printed; --json prints it on stdout)
      column/history.csv      step, time, unbalanced-force ratio, kinetic energy, monitors
      column/history.png      the same as curves
      column/displacement.png the final state coloured by displacement
      column/series/blocks.pvd  ParaView time series (displacement, velocity, moving)
      column/series/subcontacts.pvd, bolts.pvd  contact forces (water too), bolts

The model file is described in docs/models.md; examples/models/ has working ones. Ctrl-C
stops the run after the current chunk of steps and still writes the results so far (exit
status 130)."""

OUTPUT_NAMES = {
    "summary": "summary.json",
    "history": "history.csv",
    "history_png": "history.png",
    "picture": "displacement.png",
    "failing": "failing.png",
    "html": "steps.html",
    "series": "series",
}

#: The files penedge simulate writes in the ``series`` folder (:class:`Series`): the indexes
#: and the numbered frames (``blocks_000012.vtu``), and the temporary files of a write that
#: was stopped (``.blocks_000012.x1y2z3.tmp``).
SERIES_FILES = re.compile(
    r"(blocks|subcontacts|bolts)\.pvd|blocks_\d+\.vtu|(subcontacts|bolts)_\d+\.vtp"
    r"|\.(blocks|subcontacts|bolts)(_\d+)?\..+\.tmp"
)


def add_parser(commands: Any) -> argparse.ArgumentParser:
    """Adds ``simulate`` to the subcommands."""
    simulate = commands.add_parser(
        "simulate",
        help="run a model file: stability, displacements, factor of safety",
        description="Generate the blocks of a model file, run its stages (solve to\n"
        "equilibrium, cycles, property changes, factor of safety) on the rigid-block\n"
        "engine, print a summary and write the results into a folder.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    simulate.set_defaults(subparser=simulate, run=run_simulate)
    simulate.add_argument("model", metavar="MODEL", help="the model file (.toml)")
    simulate.add_argument(
        "-o",
        "--output",
        metavar="FOLDER",
        help="the folder of the results (made if needed; the results of an earlier run in "
        "it are removed first, other files are left); default: MODEL's name with _results",
    )
    simulate.add_argument(
        "--restart",
        metavar="FILE",
        help="go on from a restart file written by a `save` stage of this model: the stages "
        "after that one run on the saved state (docs/models.md, Restart)",
    )
    simulate.add_argument(
        "--check",
        action="store_true",
        help="read and check the model and its blocks, build the engine as the run would "
        "(time step, bolts, restart file), print what would run, take no step, write nothing",
    )
    simulate.add_argument(
        "--no-pictures",
        action="store_true",
        help="write no PNG pictures (no matplotlib needed; those of an earlier run in the "
        "results folder are still removed)",
    )
    simulate.add_argument("--no-series", action="store_true", help="write no ParaView time series")
    simulate.add_argument(
        "--html",
        action="store_true",
        help="also write steps.html: an interactive view (plotly) whose frames can be played",
    )
    add_output_flags(simulate, force=False)
    return simulate


def run_simulate(args: argparse.Namespace) -> int:
    """``penedge simulate MODEL``."""
    path = Path(args.model)
    with in_model_file(path):
        return simulate_model(args, path)


def in_model_file(path: Path) -> contextlib.AbstractContextManager[None]:
    """An error of the model found after reading it (the checks that need the blocks, the
    generation's, the engine's refusals of the model's values) says which file, as the
    errors of reading it do: ``regions.top: selects no block ... (in model.toml)``. Not an
    error of the restart file (field ``restart``), which names that file. The Python API
    names the file so too (:func:`penedge.model.naming_file`), and the file once."""
    import penedge.model as pm

    return pm.naming_file(path)


def simulate_model(args: argparse.Namespace, path: Path) -> int:
    """``penedge simulate MODEL`` once the model's `path` is known."""
    import penedge.model as pm
    from penedge.model import engine as engines
    from penedge.model.run import Runner

    if path.suffix.lower() == ".json" or path.is_dir():
        raise UsageError(f"argument MODEL: '{path}' should be a .toml model file")
    folder = Path(args.output) if args.output else Path(f"{path.stem}_results")
    if folder.exists() and not folder.is_dir():
        raise UsageError(f"argument -o/--output: '{folder}' exists and is not a folder")
    if not args.check and not args.no_pictures:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise CommandError(
                "the pictures need matplotlib: pip install 'penedge[plot]' (or --no-pictures)"
            ) from None
    if args.html and not args.check:
        try:
            import plotly  # noqa: F401
        except ImportError:
            raise CommandError("--html needs plotly: pip install 'penedge[html]'") from None
    show = progress.wanted(args.quiet or args.json)
    model = pm.read_model(path)
    refuse_outputs_as_saves(model, folder)
    from penedge.model.run import (
        brittle_warnings,
        input_warnings,
        layout_warnings,
        stiffening_warnings,
    )

    def stage_warnings(first: int) -> None:
        # Of the stages from `first` on: a restarted run runs none before it.
        for warning in stiffening_warnings(model, first) + brittle_warnings(model, first):
            print(f"{PROG}: warning: {warning}", file=sys.stderr)

    if args.restart is None:
        stage_warnings(0)
    for warning in input_warnings(model):
        print(f"{PROG}: warning: {warning}", file=sys.stderr)
    bar = ProgressBar(sys.stderr, f"{PROG} simulate: generating", unit="planes") if show else None
    try:
        setup = pm.prepare(model, progress=bar)
    finally:
        if bar is not None:
            bar.close()
    for warning in layout_warnings(setup):
        print(f"{PROG}: warning: {warning}", file=sys.stderr)
    if args.check:
        with progress.activity(show, f"{PROG} simulate: building the engine"):
            runner = check_run(setup, folder, args.restart)
        if args.restart is not None:
            stage_warnings(0 if runner is None else runner.first)
        summary = check_summary(path, setup)
        summary.update(plan_summary(setup, runner, args.no_series))
        if runner is not None and args.restart is not None:
            stages = model.stages[runner.first :]
            then = [f"{s.name} {s.kind}" for s in stages]
            summary["restart"] = {"file": args.restart, "stages": then}
        print_summary(args, summary, format_check(summary))
        return 0
    engine_factory = engines.Engine
    try:
        engines.refuse_unsupported(model)
        engines.simulation_class()
    except engines.EngineMissingError as e:
        raise CommandError(str(e)) from None
    status = StatusLine(sys.stderr) if show else None
    series: Any = None
    frames: list[tuple[float, Any, Any]] = []

    def frame(engine: Any, displacement: Any) -> None:
        if args.html:
            frames.append((engine.time, engine.system(), displacement))
        if series is not None:
            from penedge.model.run import removed_of

            removed = removed_of(engine)
            series.write(
                engine.time,
                engine.system(),
                displacement,
                engine.velocities(),
                engine.contacts(),
                excavated=removed if removed.any() else None,
                bolts=engine.bolt_elements(),
            )

    def report(engine: Any, stage: Any, done: int, total: int | None) -> None:
        if status is not None:
            status.show(progress_text(engine, stage, done, total))

    start = time.perf_counter()
    # the engine is built (and refuses a bad time step, say) before anything is written
    runner = Runner(
        setup, engine_factory, progress=report, frame=frame, folder=folder, restart=args.restart
    )
    if args.restart is not None:
        stage_warnings(runner.first)
    plan = plan_summary(setup, runner, args.no_series)
    for warning in plan_warnings(plan):
        print(f"{PROG}: warning: {warning}", file=sys.stderr)
    if long_run(plan) and not (args.quiet or args.json):
        print(f"{PROG} simulate: a long run: {plan_text(plan)}", file=sys.stderr)
    folder.mkdir(parents=True, exist_ok=True)
    remove_earlier_results(folder)
    if not args.no_series:
        from penedge.model.series import Series

        series = Series(folder / OUTPUT_NAMES["series"], speed=model.results.moving)
    try:
        outcome = runner.run()
    finally:
        if status is not None:
            status.close()
    seconds = time.perf_counter() - start
    with progress.activity(show, f"{PROG} simulate: writing"):
        written = write_results(folder, setup, runner, outcome, args.no_pictures, series)
        if frames:
            from penedge.pictures.simulation import write_steps_html

            html = folder / OUTPUT_NAMES["html"]
            text = io.StringIO()
            write_steps_html(frames, text, title=model.title or None)
            write_via_temp(html, True, lambda h: h.write(text.getvalue().encode()))
            written.append(str(html))
    summary = run_summary(path, setup, outcome, seconds, written)
    write_summary_json(folder, summary)
    print_summary(args, summary, format_run(summary))
    if outcome.interrupted:
        print(f"{PROG} simulate: interrupted; the results so far are written", file=sys.stderr)
        return 130
    if outcome.error is not None:
        print(
            f"{PROG}: error: the run stopped at step {outcome.steps}: {outcome.error} "
            "(the results so far are written)",
            file=sys.stderr,
        )
        return 1
    return 0


def check_run(setup: Any, folder: Path, restart: str | None) -> Any:
    """``--check``: what the run does before its first step, so that what it would refuse
    is refused now, with the same message and exit status: the engine built from the model
    (a time step above the critical one, a bolt outside the rock), the restart file read
    onto it (refused as the run would refuse it), the excavate, save and factor-of-safety
    stages checked from the stage it would start at. Nothing is written. Returns the
    :class:`~penedge.model.run.Runner`, or None where no engine can be built: a model that
    uses a feature the engine does not run yet (the summary lists it, "cannot run yet")
    or a build of penedge without the engine; then only the checks that need no engine
    run."""
    from penedge.model import engine as engines
    from penedge.model.run import Runner, check_safety_stages, check_saves

    model = setup.model
    try:
        engines.simulation_class()
    except engines.EngineMissingError as e:
        if restart is not None:
            raise CommandError(f"--restart: cannot read the restart file: {e}") from None
        missing = True
    else:
        missing = False
    if restart is None and (missing or engines.unsupported(model)):
        layout = setup.layout
        check_safety_stages(model, layout, layout.fixed, layout.velocity)
        check_saves(model, folder)
        return None
    return Runner(setup, engines.Engine, folder=folder, restart=restart)


def remove_earlier_results(folder: Path) -> None:
    """Removes from `folder` what an earlier run of penedge simulate wrote there (the files
    of :data:`OUTPUT_NAMES`, the series' indexes and frames, then the series folder if that
    leaves it empty), so that no result of that run (a ``failing.png``, extra frames) passes
    for one of this run. Nothing else is touched: a restart file, the user's own files."""
    for name in OUTPUT_NAMES.values():
        path = folder / name
        if name == OUTPUT_NAMES["series"]:
            if path.is_dir() and not path.is_symlink():
                for item in path.iterdir():
                    if SERIES_FILES.fullmatch(item.name) and not item.is_dir():
                        remove_output(item)
                with contextlib.suppress(OSError):
                    path.rmdir()  # only when empty: the user's files stay
        elif not path.is_dir():
            remove_output(path)


def remove_output(path: Path) -> None:
    """Removes one result of an earlier run (nothing when there is none)."""
    try:
        path.unlink(missing_ok=True)
    except OSError as e:
        problem = e.strerror or str(e)
        raise CommandError(f"cannot remove {path}, a result of an earlier run: {problem}") from None


def refuse_outputs_as_saves(model: Any, folder: Path) -> None:
    """A ``save`` stage's file may not be one of the results (``summary.json``, the
    ``series`` folder and what it holds...): the results, written after the run, would
    replace it."""
    import penedge.model as pm
    from penedge.model.run import save_path

    for i, stage in enumerate(model.stages):
        if stage.kind != "save" or stage.file is None:
            continue
        path = save_path(stage.file, folder).resolve()
        for name in OUTPUT_NAMES.values():
            output = (folder / name).resolve()
            if path == output or (name == OUTPUT_NAMES["series"] and output in path.parents):
                raise pm.ModelError(
                    f"stages[{i}].file",
                    f"{stage.file!r} is where penedge simulate writes its {name}, which would "
                    "replace the restart file: choose another name",
                )


def progress_text(engine: Any, stage: Any, done: int, total: int | None) -> str:
    """``stages[0] solve: step 1200, t 0.034 s, ratio 3.2e-04, kinetic energy 12 J``."""
    if stage.kind == "factor_of_safety":
        where = f"trial {done}"
    elif total:
        where = f"{100 * done / total:3.0f}%"
    else:
        where = f"{done} steps"
    return (
        f"{PROG} simulate: {stage.name} {stage.kind} {where}: step {engine.steps}, "
        f"t {engine.time:.4g} s, ratio {engine.ratio:.2e}, "
        f"kinetic energy {engine.kinetic_energy():.3g} J"
    )


def print_summary(args: argparse.Namespace, summary: dict[str, Any], text: str) -> None:
    if args.json:
        print(summary_json(summary))
    elif not args.quiet:
        print(text)


def row(label: str, value: str) -> str:
    """One aligned line of the summary."""
    return f"  {label:<22}{value}"


def check_summary(path: Path, setup: Any) -> dict[str, Any]:
    """What ``--check`` found, as plain data."""
    from penedge.model.engine import unsupported

    layout = setup.layout
    return {
        "model": str(path),
        "title": setup.model.title,
        "blocks": len(setup.system),
        "bodies": len(set(setup.system.body_ids.tolist())),
        "fixed": int(layout.fixed.sum()),
        "driven": int(layout.driven.sum()),
        "free": int((~layout.fixed & ~layout.driven).sum()),
        "sets": setup.model.set_names,
        "monitors": layout.monitors,
        "supports": [
            {"name": s.name, "pressure": s.pressure, "area": area}
            for s, area in zip(setup.model.support, layout.support_areas, strict=True)
        ],
        "bolts": [
            {
                "name": b.name,
                "blocks": path.blocks,
                "length": b.length,
                "in_rock": path.in_rock,
                "capacity": b.capacity,
                "stiffness": b.stiffness,
            }
            for b, path in zip(setup.model.bolts, layout.bolt_paths, strict=True)
        ],
        "stages": [f"{s.name} {s.kind}" for s in setup.model.stages],
        "not_supported": [f"{field}: {message}" for field, message in unsupported(setup.model)],
    }


#: A run that writes more files than this is warned of (``[results].frame_every``).
MANY_FILES = 10_000

#: A run of more steps than this (the stages' known steps, a solve's budget included) says
#: at its start what it will take, on a terminal or not.
LONG_RUN = 1_000_000


def plan_summary(setup: Any, runner: Any, no_series: bool = False) -> dict[str, Any]:
    """What the run will take, before its first step: the time step it starts with, per
    stage that takes steps its steps (``exact`` or at most), history points and frames, a
    factor of safety's trials; in all the history points, its memory, the ParaView frames
    and files (docs/models.md, "How long a run is")."""
    from penedge.model.run import plan_stages

    model = setup.model
    dt = None if runner is None else runner.timestep
    first = 0 if runner is None else runner.first
    plans = plan_stages(model, dt, first)
    monitors = len(setup.layout.monitors)
    points = 1 + sum(p.history for p in plans)
    frames = 1 + sum(p.frames for p in plans)
    per_frame = 2 + bool(model.bolts)  # blocks, subcontacts (and bolts) files
    return {
        "time_step": dt,
        "plan": [p.__dict__ for p in plans],
        "history_points": points,
        # 8 bytes a number (step, time, ratio, kinetic energy, 6 per monitor) and the
        # stage's name, then about as much again for history.csv while it is written
        "history_bytes": points * 8 * (5 + 6 * monitors),
        "frames": 0 if no_series else frames,
        "files": 0 if no_series else frames * per_frame + per_frame,
        "frame_every": model.results.frame_every,
    }


def plan_warnings(plan: dict[str, Any]) -> list[str]:
    """A warning when the series would hold more than :data:`MANY_FILES` files."""
    if plan["files"] <= MANY_FILES:
        return []
    every = plan["frame_every"]
    return [
        f"[results] frame_every = {every} writes up to {plan['frames']:,} ParaView frames, "
        f"{plan['files']:,} files in the series folder: raise frame_every (0: a frame at "
        "the end of each stage only), or run with --no-series"
    ]


def long_run(plan: dict[str, Any]) -> bool:
    """Whether the stages take more than :data:`LONG_RUN` steps (or the series more than
    :data:`MANY_FILES` files)."""
    steps = sum((p["steps"] or 0) * max(1, p["trials"]) for p in plan["plan"])
    return steps > LONG_RUN or plan["files"] > MANY_FILES


def stage_plan_text(p: dict[str, Any]) -> str:
    """``stages[0] time 4,651,163 steps``, ``stages[1] solve at most 100,000 steps``."""
    name = f"{p['name']} {p['kind']}"
    if p["steps"] is None:
        return f"{name} (steps unknown: no time step yet)"
    if p["trials"]:
        return f"{name} at most {p['trials']} trials of at most {p['steps']:,} steps"
    return f"{name} {'' if p['exact'] else 'at most '}{p['steps']:,} steps{damping_text(p)}"


def plan_text(plan: dict[str, Any]) -> str:
    """The plan on one line (the start of a long run)."""
    dt = plan["time_step"]
    parts = [f"time step {dt:.3g} s" if dt is not None else "no time step yet"]
    parts += [stage_plan_text(p) for p in plan["plan"]]
    parts.append(history_text(plan))
    if plan["files"]:
        parts.append(series_text(plan))
    return "; ".join(parts)


def history_text(plan: dict[str, Any]) -> str:
    return f"at most {plan['history_points']:,} history points ({size_text(plan['history_bytes'])})"


def series_text(plan: dict[str, Any]) -> str:
    return f"at most {plan['frames']:,} ParaView frames ({plan['files']:,} files)"


def size_text(n: float) -> str:
    """``12 kB``, ``3.4 MB``, ``1.2 GB``."""
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000 or unit == "GB":
            return f"{n:.3g} {unit}"
        n /= 1000
    return f"{n:.3g} TB"  # pragma: no cover


def format_check(summary: dict[str, Any]) -> str:
    title = f": {summary['title']}" if summary["title"] else ""
    lines = [
        f"{PROG} simulate {summary['model']}{title}: the model is valid",
        row("blocks", blocks_text(summary)),
        row("joint sets", ", ".join(summary["sets"]) or "none"),
        row("stages", ", ".join(summary["stages"])),
    ]
    if "restart" in summary:
        then = ", ".join(summary["restart"]["stages"]) or "no stage"
        lines.append(row("restart", f"from {summary['restart']['file']}: runs {then}"))
    if summary["monitors"]:
        monitors = ", ".join(f"{k} (block {v})" for k, v in summary["monitors"].items())
        lines.append(row("monitors", monitors))
    for support in summary.get("supports", []):
        pushed = f"{support['pressure']:g} Pa on {support['area']:.4g} m² of free faces"
        lines.append(row("support", f"{support['name']}: {pushed}"))
    for bolt in summary.get("bolts", []):
        lines.append(row("bolt", bolt_check_text(bolt)))
    if "plan" in summary:
        dt = summary["time_step"]
        dt_text = f"{dt:.3g} s (at the start)" if dt is not None else "none yet (no engine)"
        lines.append(row("time step", dt_text))
        for p in summary["plan"]:
            lines.append(row("steps", stage_plan_text(p)))
        lines.append(row("history", history_text(summary)))
        if summary["files"]:
            lines.append(row("series", series_text(summary)))
        for warning in plan_warnings(summary):
            lines.append(row("warning", warning))
    for note in summary["not_supported"]:
        lines.append(row("cannot run yet", note))
    return "\n".join(lines)


def bolt_check_text(bolt: dict[str, Any]) -> str:
    """``crown: 5 m, 5 m in rock, through blocks 3, 1; capacity 600 kN, stiffness 5e+07
    N/m`` (``--check``)."""
    import numpy as np

    from penedge.model.check import block_list

    shown = block_list(np.asarray(bolt["blocks"], dtype=np.int64))
    return (
        f"{bolt['name']}: {bolt['length']:.4g} m, {bolt['in_rock']:.4g} m in rock, through "
        f"blocks {shown}; capacity {bolt['capacity'] / 1e3:.4g} kN, stiffness "
        f"{bolt['stiffness']:g} N/m"
    )


def blocks_text(summary: dict[str, Any]) -> str:
    driven = f", {summary['driven']} driven" if summary.get("driven") else ""
    bodies = summary.get("bodies", summary["blocks"])
    parts = f" in {bodies} bodies" if bodies != summary["blocks"] else ""  # concave blocks
    return f"{summary['blocks']}{parts} ({summary['fixed']} fixed{driven}, {summary['free']} free)"


def run_summary(
    path: Path, setup: Any, outcome: Any, seconds: float, written: list[str]
) -> dict[str, Any]:
    """The result of a run as plain data (what ``--json`` prints and summary.json holds)."""
    largest, block = outcome.max_displacement
    summary = check_summary(path, setup)
    del summary["not_supported"]
    stages = []
    for s in outcome.stages:
        entry: dict[str, Any] = {
            "name": s.name,
            "kind": s.kind,
            "steps": s.steps,
            "time": s.time,
            "ratio": s.ratio,
            "converged": s.converged,
            "stopped": s.stopped,
        }
        if s.damping is not None:
            entry["damping"] = s.damping
        if s.safety is not None:
            f = s.safety
            entry["factor_of_safety"] = {
                "factor": f.factor,
                "bound": f.bounded,
                "stable": f.stable,
                "failing": f.failing,
                "failing_blocks": f.failing_blocks,
                "failing_displacement": f.failing_displacement,
                "failing_rotation": f.failing_rotation,
                "unheld_blocks": f.unheld_blocks,
                "moved_before": f.moved_before,
                "moved_before_displacement": f.moved_before_displacement,
                "from_equilibrium": f.in_equilibrium,
                "reliable": f.in_equilibrium,
                "start_ratio": f.start_ratio,
                "trials": [t.__dict__ for t in f.trials],
            }
        stages.append(entry)
    safety = outcome.safety
    summary.update(
        {
            "stages": stages,
            "stable": outcome.stable,
            "verdict": verdict_text(outcome),
            "not_stable_because": outcome.problems,
            "interrupted": outcome.interrupted,
            "error": outcome.error,
            "steps": outcome.steps,
            "time": outcome.time,
            "ratio": outcome.ratio,
            "moved_threshold": outcome.threshold,
            "moved": outcome.moved.tolist(),
            "max_displacement": largest,
            "max_displacement_block": block,
            "factor_of_safety": None if safety is None else safety.factor,
            "factor_of_safety_reliable": None if safety is None else safety.in_equilibrium,
            "seconds": seconds,
            "written": written,
            "bolts": outcome.bolts,
        }
    )
    return summary


def failing_text(f: dict[str, Any], most: int = 12) -> str:
    """The failing blocks of a factor of safety, each with how far it moved and turned in
    the smallest failing trial (``15 (0.21 m, 2°)`` slides, ``8 (0.35 m, 14°)`` turns:
    topples): ``failing blocks, moved and turned in the first failing trial: ...``, or
    ``failing blocks: none``."""
    blocks = f["failing_blocks"]
    if not blocks:
        return "failing blocks: none"
    more = f" and {len(blocks) - most} more" if len(blocks) > most else ""
    moves = f.get("failing_displacement") or []
    turns = f.get("failing_rotation") or []
    if len(moves) != len(blocks) or len(turns) != len(blocks):  # an older summary's
        return "failing blocks: " + ", ".join(map(str, blocks[:most])) + more
    each = ", ".join(
        f"{b} ({m:.2g} m, {angle_text(t)})"
        for b, m, t in zip(blocks[:most], moves, turns, strict=False)
    )
    return f"failing blocks, moved and turned in the first failing trial: {each}{more}"


def angle_text(degrees: float) -> str:
    """``14°``, ``0.031°``; below 0.001° (rounding, for a block that slides) ``0°``."""
    return "0°" if abs(degrees) < 1e-3 else f"{degrees:.2g}°"


def bolts_text(bolts: list[dict[str, Any]]) -> str:
    """The bolts at the end of a run, for the summary: name, axial force, state."""
    return "; ".join(f"{b['name']} {b['force'] / 1e3:.4g} kN ({b['state']})" for b in bolts)


def stage_text(stage: dict[str, Any]) -> str:
    text = f"{stage['name']} {stage['kind']}"
    if stage["stopped"] == "interrupted":
        return f"{text}: interrupted after {stage['steps']:,} steps (ratio {stage['ratio']:.1e})"
    if stage["stopped"] == "error":
        return f"{text}: stopped by the engine after {stage['steps']:,} steps{damping_text(stage)}"
    if stage["kind"] == "solve":
        if stage["converged"]:
            return (
                f"{text}: equilibrium after {stage['steps']:,} steps (ratio {stage['ratio']:.1e})"
            )
        steps, ratio = stage["steps"], stage["ratio"]
        return f"{text}: NOT in equilibrium after {steps:,} steps (ratio {ratio:.1e})"
    if "factor_of_safety" in stage:
        f = stage["factor_of_safety"]
        trials = plural(len(f["trials"]), "trial")
        if not f["reliable"]:
            trials = f"UNRELIABLE, not from equilibrium; {trials}"
        return f"{text}: F {f['bound']} {factor_text(f['factor'])} ({trials})"
    if stage["steps"]:
        return f"{text}: {stage['steps']:,} steps{damping_text(stage)}"
    return text


def damping_text(stage: dict[str, Any]) -> str:
    """``, undamped`` or ``, local damping 0.8`` for a cycle or time stage (a damped
    stage's motion is not physical: docs/models.md, stages); empty for the others."""
    damping = stage.get("damping")
    if damping is None:
        return ""
    return ", undamped" if damping == 0 else f", local damping {damping:g}"


def unreliable_text(start_ratio: float, unheld: list[int] | None = None) -> str:
    """Why a factor of safety is unreliable, and what to do: its trials started from a
    state not in equilibrium. With blocks that no contact held at the start (`unheld`:
    falling freely), which no strength of the joints holds: support, not a higher strength."""
    start = (
        f"UNRELIABLE: the trials started from a state NOT in equilibrium (ratio {start_ratio:.2g}"
    )
    advice = (
        "solve with a higher strength, then a properties stage with the strength to test, "
        "then factor_of_safety (docs/models.md, Factor of safety)"
    )
    if unheld:
        ids = ", ".join(map(str, unheld[:12])) + (", ..." if len(unheld) > 12 else "")
        return (
            f"{start}): blocks {ids} were held by no contact (falling freely), which no "
            "strength of the joints holds: support them (bolts, a boundary) or find why no "
            "joint holds them, then solve and factor_of_safety (docs/models.md, Factor of "
            "safety)"
        )
    return f"{start}: the blocks already moving), which fails them too soon; {advice}"


def moved_before_text(f: dict[str, Any]) -> str:
    """The blocks that had moved farther than five times the trials' displacement limit
    before them: F is that of where they came to rest."""
    pairs = list(zip(f["moved_before"], f["moved_before_displacement"], strict=True))
    ids = ", ".join(f"{b} ({d:.3g} m)" for b, d in pairs[:12]) + (
        ", ..." if len(pairs) > 12 else ""
    )
    return (
        f"CAUTION: blocks {ids} had moved five times farther than a trial may (its "
        "displacement) before the trials began: "
        "F is that of the state they came to rest in, not of the model as built (loads "
        "applied at once can slide a block; solve with a higher strength first: "
        'docs/models.md, "Loads applied at once")'
    )


def factor_text(factor: float) -> str:
    """A factor of safety to 2 decimals, one below 1 with the digits that keep it below 1
    (``0.996``, not ``1.00``: :func:`penedge.model.run.below_one`)."""
    from penedge.model.run import below_one

    return below_one(factor) if factor < 1 else f"{factor:.2f}"


def result_text(summary: dict[str, Any]) -> str:
    """``interrupted``, ``stopped by an error (below)``, or the verdict: ``stable (...)``
    or ``NOT stable: ...``, with what it is based on (:func:`verdict_text`)."""
    if summary["interrupted"]:
        return "interrupted"
    if summary["error"] is not None:
        return "stopped by an error (below)"
    return str(summary["verdict"])


def verdict_text(outcome: Any) -> str:
    """``stable (in equilibrium at the end: ...)`` or ``NOT stable: why; why``: stable
    means that the final state is in equilibrium (its unbalanced-force ratio at most the
    last solve's, no free block faster than ``[results].moving``), the last solve reached
    equilibrium and every factor of safety is reliable and at least 1 (``Outcome.problems``)."""
    problems = outcome.problems
    if problems:
        return "NOT stable: " + "; ".join(problems)
    basis = (
        f"in equilibrium at the end: ratio {outcome.ratio:.2g} <= {outcome.target:.2g}, "
        f"no free block faster than {outcome.moving:g} m/s"
    )
    if outcome.safety is not None:
        basis += ", every factor of safety >= 1"
    if len(outcome.moved):
        largest, _ = outcome.max_displacement
        basis += (
            f"; {plural(len(outcome.moved), 'block')} moved more than "
            f"{outcome.threshold * 1e3:g} mm on the way (up to {largest:.3g} m)"
        )
    return f"stable ({basis})"


def format_run(summary: dict[str, Any]) -> str:
    title = f": {summary['title']}" if summary["title"] else ""
    threshold = summary["moved_threshold"] * 1e3
    moved = summary["moved"]
    moved_text = (
        f"{plural(len(moved), 'block')} more than {threshold:g} mm: "
        + ", ".join(map(str, moved[:12]))
        + (", ..." if len(moved) > 12 else "")
        if moved
        else f"none more than {threshold:g} mm"
    )
    lines = [
        f"{PROG} simulate {summary['model']}{title}",
        row("blocks", blocks_text(summary)),
        row("stages", "; ".join(stage_text(s) for s in summary["stages"])),
        row("result", result_text(summary)),
        row("moved", moved_text),
        row(
            "largest displacement",
            f"{summary['max_displacement'] * 1e3:.3g} mm "
            f"(block {summary['max_displacement_block']})",
        ),
    ]
    if summary["bolts"]:
        lines.append(row("bolts", bolts_text(summary["bolts"])))
    for s in summary["stages"]:
        if "factor_of_safety" in s:
            f = s["factor_of_safety"]
            lines.append(
                row(
                    "factor of safety",
                    f"{f['bound']} {factor_text(f['factor'])}"
                    + ("" if f["reliable"] else " UNRELIABLE")
                    + f" ({failing_text(f)})",
                )
            )
            if not f["reliable"]:
                lines.append(row("", unreliable_text(f["start_ratio"], f.get("unheld_blocks"))))
            if f.get("moved_before"):
                lines.append(row("", moved_before_text(f)))
    if summary["written"]:
        lines.append(row("written", ", ".join(summary["written"])))
    return "\n".join(lines)


def write_results(
    folder: Path, setup: Any, runner: Any, outcome: Any, no_pictures: bool, series: Any
) -> list[str]:
    """summary.json is written by the caller's summary; here the history (CSV, PNG), the
    picture of the final state and the series index. Returns the names written."""
    written: list[str] = []
    rows = outcome.history.each_row()
    buffer = io.StringIO()
    first = next(rows, None)
    if first is not None:
        writer = csv.DictWriter(buffer, fieldnames=list(first))
        writer.writeheader()
        writer.writerow(first)
        writer.writerows(rows)
    history = folder / OUTPUT_NAMES["history"]
    write_via_temp(history, True, lambda h: h.write(buffer.getvalue().encode()))
    written.append(str(history))
    if not no_pictures:
        from penedge.pictures.simulation import save_displacement, save_failing, save_history

        title = setup.model.title or None
        png = folder / OUTPUT_NAMES["history_png"]

        def history_png(handle: IO[bytes]) -> None:
            save_history(outcome.history, handle, title=title)

        write_via_temp(png, True, history_png)
        written.append(str(png))
        picture = folder / OUTPUT_NAMES["picture"]
        final = runner.engine.system()
        present, shown = without_excavated(runner.engine, final, outcome.displacement)

        def displacement_png(handle: IO[bytes]) -> None:
            save_displacement(present, shown, handle, title=title, threshold=outcome.threshold)

        write_via_temp(picture, True, displacement_png)
        written.append(str(picture))
        safety = outcome.safety
        if safety is not None and safety.failing_blocks:
            failing = folder / OUTPUT_NAMES["failing"]
            label = f"failing at F = {safety.failing:.3f} (factor of safety {safety.factor:.2f})"

            def failing_png(handle: IO[bytes]) -> None:
                save_failing(final, safety.failing_blocks, handle, title=label)

            write_via_temp(failing, True, failing_png)
            written.append(str(failing))
    if series is not None and series.entries:
        written.append(str(series.index))
    if series is not None and series.contact_entries:
        written.append(str(series.contacts_index))
    if series is not None and series.bolt_entries:
        written.append(str(series.bolts_index))
    summary_path = folder / OUTPUT_NAMES["summary"]
    written.insert(0, str(summary_path))
    return written


def without_excavated(engine: Any, system: Any, displacement: Any) -> tuple[Any, Any]:
    """The blocks (and their displacements) that an excavate stage has not removed, for the
    picture of the final state: the rock taken out is not drawn."""
    import penedge
    from penedge.model.run import removed_of

    removed = removed_of(engine)
    blocks = system.blocks
    if not removed.any() or len(blocks) != len(removed):
        return system, displacement
    keep = [b for b, gone in zip(blocks, removed, strict=True) if not gone]
    present = penedge.BlockSystem(keep)
    bodies = system.body_ids[~removed]
    if len(set(bodies.tolist())) < len(keep):  # concave blocks (removed whole), drawn as one
        present = present.with_bodies(bodies.tolist())
    return present, displacement[~removed]


def write_summary_json(folder: Path, summary: dict[str, Any]) -> None:
    """summary.json (replaced atomically)."""
    text = summary_json(summary)
    write_via_temp(folder / OUTPUT_NAMES["summary"], True, lambda h: h.write(text.encode()))


def summary_json(summary: dict[str, Any]) -> str:
    """`summary` as strict JSON: a value that is not finite (the unbalanced-force ratio of
    an engine that has taken no step yet, under no gravity, is infinite) is written null,
    since JSON has no Infinity or NaN."""
    return json.dumps(finite(summary), indent=2, allow_nan=False)


def finite(value: Any) -> Any:
    """`value` with every float that is not finite replaced by None, in lists and dicts."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value
