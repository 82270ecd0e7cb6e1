"""``penedge generate SPEC``: cut a rock domain into blocks and write them."""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

import penedge
from penedge.cli import progress
from penedge.cli.common import (
    PROG,
    CommandError,
    Interrupted,
    Outputs,
    add_output_flags,
    check_distinct,
    output_file,
    plural,
    positive_int,
    require_matplotlib,
)
from penedge.cli.progress import ProgressBar

EPILOG = """\
worked example:
  $ penedge generate examples/joint_set_random.toml -o blocks.json --stats-png volumes.png
  penedge generate examples/joint_set_random.toml: 18 blocks in 0.00 s
    joint planes          15 (17 splits)
    block volume          V10 486.6, V50 1395, V90 1584 (min 10.27, max 1584)
    partial cuts skipped  0
    slivers               none (thinner than 4.5e-05 or smaller than 0)
    tiny blocks           none (below 1e-3 of the median volume, 0.6545)
    volume error          1.3e-16 (blocks vs domain)
    written               blocks.json, volumes.png

  Then `penedge detect blocks.json` counts the contacts and `penedge show blocks.json
  --html` draws the blocks.

more:
  penedge generate examples/three_joint_sets.toml -o blocks.json
  penedge generate spec.toml -o blocks.json --vtu blocks.vtu --csv blocks.csv \\
                   --stats-png volumes.png
  penedge generate spec.toml                   check the spec, print the summary, write nothing
  penedge detect blocks.json -o contacts.csv   then the contacts of the blocks
  penedge generate big.toml --max-blocks 50000000
                                               allow more blocks than the memory estimate

A block cut into convex parts that stay one block (the rock around an excavation or
under a slope's ground, the pieces held by a finite joint's rock bridges) counts once:
the summary says `16 blocks (39 convex parts)` and the volumes are those of the blocks
(their parts summed); the block file, the VTU files and the block table (--csv) hold
the parts, each with its block's body id in the block file and the VTU files.

Before cutting, the blocks are estimated from the arrangement of the planes (1 + planes
+ lines + points where they meet; the product of the plane counts for joint sets that
fill the domain). A spec estimated to make more than --max-blocks (default: what half
the memory available holds, at about 4 kB a block) is refused with the estimate, and a
run that makes more stops (an excavation too, once it holds more convex parts). Ctrl-C
stops a run within a second (between two planes, or two cuts of an excavation); nothing
is written then. Every output is written to a temporary file beside it first
and all are moved into place at the end: a run that cannot write one of them (a
folder it may not write to, a full disk) writes none.

The spec (TOML, or JSON when SPEC ends in .json) is described in docs/generation.md;
examples/ has one spec for each feature. A file named here is replaced if it exists, at
once (a reader never sees half a file); an input is never overwritten. A progress bar
shows on a terminal when the run takes more than a second."""

# option -> (destination, suffixes, what it holds)
OUTPUTS = {
    "-o/--output": ("output", (".json",), "the block file (JSON, read by `penedge detect`)"),
    "--vtu": ("vtu", (".vtu",), "the blocks for ParaView (one polyhedron cell per block)"),
    "--faces-vtu": (
        "faces_vtu",
        (".vtu",),
        "the block faces for ParaView, with their origin (boundary or joint set)",
    ),
    "--csv": ("csv", (".csv",), "the block table: id, volume, centroid, faces, free faces"),
    "--stats-png": (
        "stats_png",
        (".png",),
        "the block volume distribution (cumulative volume fraction, V10/V50/V90)",
    ),
}


def add_parser(commands: Any) -> argparse.ArgumentParser:
    """Adds ``generate`` to the subcommands."""
    generate = commands.add_parser(
        "generate",
        help="cut a rock domain into blocks (spec file -> block file)",
        description="Cut the domain of a spec into convex blocks by its joint planes, joint\n"
        "sets and finite joints, print a summary (block count, V10/V50/V90, skipped\n"
        "partial cuts, slivers) and write the blocks.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    generate.set_defaults(subparser=generate, run=run_generate)
    generate.add_argument("spec", metavar="SPEC", help="the spec file (.toml or .json)")
    for option, (dest, _, what) in OUTPUTS.items():
        flags = option.split("/")
        generate.add_argument(*flags, dest=dest, metavar="FILE", help=what)
    generate.add_argument(
        "--max-blocks",
        type=block_count,
        metavar="N",
        help="the most blocks (convex parts) the run may make: a spec estimated to make "
        "more is refused before cutting, and a run that makes more stops (default: what "
        "half the memory available holds, about 4 kB a block; any number above 2^63 - 1 "
        "is taken as 2^63 - 1, no limit in practice)",
    )
    add_output_flags(generate, force=False)
    return generate


#: The largest block limit the library takes (a signed 64-bit count).
MAX_BLOCK_LIMIT = 2**63 - 1


def block_count(text: str) -> int:
    """An argparse type: a whole number >= 1, at most :data:`MAX_BLOCK_LIMIT` (a larger
    limit is no limit either: no run comes near 2^63 blocks)."""
    return min(positive_int(text), MAX_BLOCK_LIMIT)


def run_generate(args: argparse.Namespace) -> int:
    """``penedge generate SPEC``."""
    spec = Path(args.spec)
    outputs = {
        option: output_file(getattr(args, dest), option, suffixes)
        for option, (dest, suffixes, _) in OUTPUTS.items()
    }
    check_distinct({"SPEC": spec}, outputs)
    if outputs["--stats-png"] is not None:
        require_matplotlib("--stats-png")
    show = progress.wanted(args.quiet or args.json)
    # Each output's folder was tried before the run (`output_file`); the outputs are written
    # to temporary files and published together: a run that fails writes none.
    with Outputs() as staged:
        bar = ProgressBar(sys.stderr, f"{PROG} generate", unit="planes") if show else None
        start = time.perf_counter()
        try:
            system, report = penedge.generate(spec, progress=bar, max_blocks=args.max_blocks)
        except KeyboardInterrupt as e:
            notes = " ".join(getattr(e, "__notes__", []))
            found = re.search(r"stopped after (\d+ of \d+ joint planes)", notes)
            where = f" after {found.group(1)}" if found else ""
            raise Interrupted(f"interrupted{where}; nothing written") from None
        finally:
            if bar is not None:
                bar.close()
        seconds = time.perf_counter() - start
        png = outputs["--stats-png"]
        if png is not None and len(system) == 0:
            raise CommandError(f"cannot draw {png}: no blocks left (every block was a sliver)")
        with progress.activity(show, f"{PROG} generate: writing"):
            written = write_outputs(system, outputs, staged)
    summary = summarize(spec, system, report, seconds, written)
    if args.json:
        print(json.dumps(summary, indent=2))
    elif not args.quiet:
        print(format_summary(summary, system))
    return 0


def write_outputs(system: Any, outputs: dict[str, Path | None], staged: Outputs) -> list[str]:
    """Writes every output asked for (`outputs`: per option, its path or None), then moves
    them all into place; returns their names."""
    writers = {
        "-o/--output": system.write_json,
        "--vtu": system.write_vtu,
        "--faces-vtu": system.write_faces_vtu,
        "--csv": system.write_csv,
        "--stats-png": lambda path: write_stats_png(system, path),
    }
    for option, path in outputs.items():
        if path is not None:
            staged.write_named(path, writers[option])
    return [str(path) for path in staged.publish()]


def write_stats_png(system: Any, path: Path) -> None:
    """The volume distribution picture (of the blocks: a concave block's parts summed)."""
    from penedge import pictures

    pictures.save_volume_distribution(system, path, format="png")


def summarize(
    spec: Path, system: Any, report: dict[str, Any], seconds: float, written: list[str]
) -> dict[str, Any]:
    """The result of a run as plain data (what ``--json`` prints)."""
    return {
        "spec": str(spec),
        "blocks": len(system),
        "bodies": blocks_of(system),
        "seconds": seconds,
        "statistics": system.statistics(),
        "report": report,
        "sets": system.sets,
        "written": written,
    }


def blocks_of(system: Any) -> int:
    """The number of blocks: of bodies (a concave block's convex parts are one block)."""
    return len(np.unique(np.asarray(system.body_ids)))


def count_text(blocks: int, parts: int) -> str:
    """``16 blocks (39 convex parts)``; ``26 blocks`` when each block is one part."""
    if blocks == parts:
        return plural(blocks, "block")
    return f"{plural(blocks, 'block')} ({plural(parts, 'convex part')})"


def format_summary(summary: dict[str, Any], system: Any) -> str:
    """The human-readable summary of a run."""
    report, stats = summary["report"], summary["statistics"]
    lines = [
        f"{PROG} generate {summary['spec']}: {count_text(summary['bodies'], summary['blocks'])} "
        f"in {summary['seconds']:.2f} s",
        row("joint planes", f"{report['joint_planes']} ({plural(report['splits'], 'split')})"),
    ]
    if stats is not None:
        lines.append(
            row(
                "block volume",
                f"V10 {stats['v10']:.4g}, V50 {stats['v50']:.4g}, V90 {stats['v90']:.4g} "
                f"(min {stats['min_volume']:.4g}, max {stats['max_volume']:.4g})",
            )
        )
    lines.append(row("partial cuts skipped", partial_cuts(report, summary["sets"])))
    if report.get("bridged_cuts"):
        lines.append(row("bridged cuts", f"{report['bridged_cuts']} (cut through, rock bridges)"))
    lines.append(row("slivers", slivers(report["slivers"])))
    if "tiny" in report:
        # Found among the convex parts, as the slivers, and before the excavations: the
        # blocks the joints cut, as they were before any was excavated (so named).
        excavated = bool(report.get("excavated_volume"))
        plain = summary["bodies"] == summary["blocks"] or excavated
        label = "tiny blocks" if plain else "tiny parts"
        lines.append(row(label, tiny(report["tiny"], before_excavation=excavated)))
    if report.get("excavated_volume") and "excavation_slivers" in report:
        lines.append(
            row(
                "excavation slivers",
                excavation_slivers(report["excavation_slivers"], report["slivers"]),
            )
        )
    if report["set_planes_outside"]:
        lines.append(row("set planes outside", f"{report['set_planes_outside']} (left out)"))
    if report["retried_cuts"]:
        lines.append(row("cuts retried", f"{report['retried_cuts']} (exact signs)"))
    lines.append(row("volume error", f"{report['volume_error']:.1e} (blocks vs domain)"))
    if report.get("excavated_volume"):
        lines.append(row("excavated", f"{report['excavated_volume']:.4g} (volume removed)"))
    if summary["written"]:
        lines.append(row("written", ", ".join(summary["written"])))
    return "\n".join(lines)


def row(label: str, value: str) -> str:
    """One aligned line of the summary."""
    return f"  {label:<22}{value}"


def partial_cuts(report: dict[str, Any], sets: list[dict[str, str]]) -> str:
    """``2 (lens 2)``: finite joints that ended inside a block, by spec entry."""
    total = report["partial_cuts_skipped"]
    by_entry = [
        f"{sets[i]['name']} {n}" for i, n in enumerate(report["partial_cuts_by_entry"]) if n
    ]
    return f"{total} ({', '.join(by_entry)})" if by_entry else str(total)


def tiny(t: dict[str, Any], before_excavation: bool = False) -> str:
    """The blocks far smaller than the typical block (below 1e-3 of the median volume);
    with ``before_excavation``, said to be those the joints cut, before the excavations."""
    limit = f"below 1e-3 of the median volume, {t['threshold']:.4g}"
    if before_excavation:
        limit = f"of the blocks before excavation; {limit}"
    if t["count"] == 0:
        return f"none ({limit})"
    return f"{t['count']} ({limit}; smallest {t['smallest']:.3g})"


def slivers(s: dict[str, Any]) -> str:
    """What happened to the blocks below the minimum thickness or volume."""
    return sliver_summary(s, s, s["kept_ids"], "ids")


def excavation_slivers(s: dict[str, Any], limits: dict[str, Any]) -> str:
    """What happened to the blocks (bodies) left by the excavations below the minimum
    thickness or volume (``limits``: the joints' cut's sliver report, whose limits and
    policy they share)."""
    return sliver_summary(s, limits, s["kept_bodies"], "blocks")


def sliver_summary(s: dict[str, Any], limits: dict[str, Any], kept: list[int], what: str) -> str:
    """``none (...)``, ``2 dropped, volume ... (...)`` or ``2 kept: <what> 3, 9 (...)``."""
    bounds = (
        f"thinner than {limits['min_thickness']:.3g} or smaller than {limits['min_volume']:.3g}"
    )
    if s["count"] == 0:
        return f"none ({bounds})"
    if limits["policy"] == "drop":
        return f"{s['count']} dropped, volume {s['volume']:.3g} ({bounds})"
    ids = ", ".join(str(i) for i in kept[:8])
    more = ", ..." if len(kept) > 8 else ""
    return f"{s['count']} kept: {what} {ids}{more} ({bounds})"
