"""``penedge detect BLOCKS``: every contact of a block file, with its geometry."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import penedge
from penedge.cli import progress
from penedge.cli.common import (
    PROG,
    CommandError,
    Outputs,
    UsageError,
    add_gap,
    add_output_flags,
    check_distinct,
    gap_fields,
    gap_flag,
    gap_options,
    gap_text,
    output_file,
    plural,
)
from penedge.cli.generate import blocks_of, count_text

EPILOG = """\
worked example:
  $ penedge generate examples/paper_example_3.toml -o blocks.json -q
  $ penedge detect blocks.json -o contacts.csv
  blocks.json: 26 blocks, 325 contacts (relative gap 1e-12)

  code  contact type                count
     1  vertex-vertex                 205
     2  vertex-edge                     0
     ...
     7  face-face                      42
        total                         325

  face-face contact area: 724.264
  written: contacts.csv

more:
  penedge detect blocks.json                       the table of contact counts only
  penedge detect blocks.json -o contacts.csv --vtp contacts.vtp
  penedge detect blocks.json --gap 1e-6 --json     with a relative gap, counts as JSON
  penedge detect blocks.json --absolute-gap 0.001  blocks within 1 mm touch (metres)

contacts.csv has one row per contact (docs/tables.md): block_a, block_b, type,
type_code (1..7), point_x, point_y, point_z (the centroid of the contact region),
normal_x, normal_y, normal_z (unit, from block_a to block_b), distance (gap > 0,
depth < 0; 0 within rounding), area (face-face), n_points, set_a, set_b (the spec
entries the faces of each block's contact feature come from), body_a, body_b (the
blocks the two convex parts belong to; a convex block is a body of its own, numbered in
the order of the bodies' first parts). contacts.vtp
(ParaView) holds the contact points, segments and polygons with the same data.

A block cut into convex parts that stay one block (the rock around an excavation or
under a slope's ground, the pieces held by a finite joint's rock bridges; a `body` id
per part in the block file) is one block: the summary says `16 blocks (39 convex
parts)`, and the contacts are those between parts of different blocks, never the
glue between two parts of one block (block_a, block_b are part ids; as
`BlockSystem.detect` and `ContactTracker`). `BlockSystem.detect_bodies` groups them
into the contact regions of the blocks.

A file named here is replaced if it exists, at once; the input is never overwritten;
both outputs are written, or neither. Pairs of blocks that overlap deeper than the
gap are not contacts: a warning names them on stderr (not with -q, which prints
nothing; --json counts them). A progress bar shows on a terminal when the detection
takes more than a second. Draw the contacts with
`penedge show blocks.json --contacts --html`."""


def add_parser(commands: Any) -> argparse.ArgumentParser:
    """Adds ``detect`` to the subcommands."""
    detect = commands.add_parser(
        "detect",
        help="find every contact of a block file (block file -> contacts)",
        description="Read a block file (from `penedge generate`), find every contact with its\n"
        "type, normal, distance, area and contact points, print the number of contacts\n"
        "of each type and write them.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    detect.set_defaults(subparser=detect, run=run_detect)
    detect.add_argument("blocks", metavar="BLOCKS", help="the block file (.json)")
    detect.add_argument(
        "-o", "--output", metavar="FILE", help="the contacts table (.csv), one row per contact"
    )
    detect.add_argument(
        "--vtp", metavar="FILE", help="the contacts for ParaView (.vtp): points, lines, polygons"
    )
    add_gap(detect)
    add_output_flags(detect, force=False)
    return detect


def run_detect(args: argparse.Namespace) -> int:
    """``penedge detect BLOCKS``."""
    blocks = Path(args.blocks)
    csv = output_file(args.output, "-o/--output", (".csv",))
    vtp = output_file(args.vtp, "--vtp", (".vtp",))
    check_distinct({"BLOCKS": blocks}, {"-o/--output": csv, "--vtp": vtp})
    show = progress.wanted(args.quiet or args.json)
    with Outputs() as staged:
        with progress.activity(show, f"{PROG} detect: reading {blocks}"):
            system = read_blocks(blocks)
        try:
            options = gap_options(args)
            found = progress.detect(system, show, f"{PROG} detect", **options, geometry=True)
        except penedge.ToleranceError as e:
            raise UsageError(f"argument {gap_flag(args)}: {e}") from None
        for path, write in [(csv, found.write_csv), (vtp, found.write_vtp)]:
            if path is not None:
                staged.write_named(path, write)
        written = [str(path) for path in staged.publish()]
    summary = summarize(blocks, system, found, gap_options(args), written)
    if summary["penetrating"] and not args.quiet:
        print(f"{PROG}: warning: {penetration_note(found)}", file=sys.stderr)
    if args.json:
        print(json.dumps(summary, indent=2))
    elif not args.quiet:
        print(format_summary(summary))
    return 0


#: The most bytes of a file that failed to read as a block file looked at for a spec.
SPEC_BYTES = 1 << 20


def read_blocks(path: Path) -> Any:
    """The block file at `path`; a JSON joint spec given instead is named as one (as a
    TOML spec is)."""
    try:
        return penedge.BlockSystem.read_json(path)
    except penedge.PenedgeError:
        if looks_like_json_spec(path):
            raise CommandError(
                f"{path}: this looks like a joint spec (JSON), not a block file: run "
                "`penedge generate` on it first, then give the block file it writes "
                "(-o blocks.json) to this command"
            ) from None
        raise


def looks_like_json_spec(path: Path) -> bool:
    """Whether `path` holds a JSON object with a spec's ``domain`` and no block file's
    ``format`` or ``blocks``, its other keys a spec's (docs/generation.md)."""
    try:
        with path.open("rb") as handle:
            text = handle.read(SPEC_BYTES + 1)
        if len(text) > SPEC_BYTES:
            return False
        value = json.loads(text)
    except (OSError, ValueError):
        return False
    spec_keys = {"domain", "joints", "excavations", "options", "unit"}
    return isinstance(value, dict) and "domain" in value and set(value) <= spec_keys


def summarize(
    blocks: Path, system: Any, found: Any, gap: dict[str, float], written: list[str]
) -> dict[str, Any]:
    """The result as plain data (what ``--json`` prints)."""
    face_face = found.types == penedge.CONTACT_TYPES.index("face-face") + 1
    return {
        "blocks_file": str(blocks),
        "blocks": len(system),
        "bodies": blocks_of(system),
        **gap_fields(gap),
        "contacts": len(found),
        "counts": found.counts(),
        "face_face_area": float(found.areas[face_face].sum()),
        "penetrating": len(found.penetrating),
        "written": written,
    }


def penetration_note(found: Any) -> str:
    """Which pairs overlap deeper than the gap (the first few)."""
    pairs = [f"{a}-{b}" for a, b in found.penetrating[:5].tolist()]
    more = ", ..." if len(found.penetrating) > 5 else ""
    n = len(found.penetrating)
    return (
        f"{plural(n, 'pair')} of blocks overlap deeper than the gap "
        f"({', '.join(pairs)}{more}); they are not contacts"
    )


def format_summary(summary: dict[str, Any]) -> str:
    """The table of counts per contact type."""
    lines = [
        f"{summary['blocks_file']}: {count_text(summary['bodies'], summary['blocks'])}, "
        f"{plural(summary['contacts'], 'contact')} ({gap_text(summary)})",
    ]
    if summary["bodies"] != summary["blocks"]:
        lines.append("(contacts between convex parts of different blocks, typed by the parts)")
    lines += ["", *counts_table(summary["counts"])]
    lines.append("")
    lines.append(f"face-face contact area: {summary['face_face_area']:.6g}")
    if summary["penetrating"]:
        lines.append(f"penetrating pairs: {summary['penetrating']} (not counted above)")
    if summary["written"]:
        lines.append(f"written: {', '.join(summary['written'])}")
    return "\n".join(lines)


def counts_table(counts: dict[str, int]) -> list[str]:
    """The lines of the table of contacts per type: code, type, count, and the total."""
    lines = [f"{'code':>4}  {'contact type':<25}{'count':>8}"]
    for code, (name, count) in enumerate(counts.items(), start=1):
        lines.append(f"{code:>4}  {name:<25}{count:>8}")
    lines.append(f"{'':>4}  {'total':<25}{sum(counts.values()):>8}")
    return lines
