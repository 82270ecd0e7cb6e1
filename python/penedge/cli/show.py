"""``penedge show BLOCKS``: pictures of a block file: the exploded view (PNG, SVG, PDF),
the interactive view (HTML) and the volume distribution, with the contacts if asked."""

from __future__ import annotations

import argparse
import json
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np

import penedge
from penedge.cli import draw, progress
from penedge.cli.common import (
    PROG,
    CommandError,
    Outputs,
    Target,
    UsageError,
    add_gap,
    add_html,
    add_output_flags,
    add_picture_options,
    check_distinct,
    gap_fields,
    gap_flag,
    gap_options,
    gap_text,
    html_file,
    output_file,
    picture_file,
    plural,
    require,
    target,
)
from penedge.cli.detect import counts_table, penetration_note
from penedge.cli.generate import blocks_of, count_text

EPILOG = """\
worked example:
  $ penedge generate examples/paper_example_3.toml -o blocks.json -q
  $ penedge show blocks.json --contacts --html
  blocks.json: 26 blocks, 325 contacts (relative gap 1e-12)

  code  contact type                count
     1  vertex-vertex                 205
     ...
     7  face-face                      42
        total                         325

  picture: blocks.png
  interactive view: blocks.html

  blocks.png shows the blocks in an exploded perspective view and, beside them, one
  panel per contact type; open blocks.html in a web browser to turn, zoom, hide
  groups of blocks or contact types, and hover for block ids and contact types.

more:
  penedge show blocks.json                          the picture blocks.png only
  penedge show blocks.json -o rock.svg --colour-by volume
                                                    coloured by volume, as SVG
  penedge show blocks.json --no-picture --html-out view.html --stats-png volumes.png
                                                    the HTML view and the volume curve
  penedge show blocks.json --max-blocks 0 --html    every block, however many

The picture goes to BLOCKS' name with .png in the current folder (blocks.png) unless
-o names it or --no-picture; --html writes blocks.html, --html-out FILE names the
view (--html takes no file name, so `--html blocks.json` reads blocks.json). Default names never
replace an existing file: the next free name (blocks-1.png, ...) is taken, unless
--force. A file named here is replaced. Systems larger than --max-blocks show the
blocks on the outside of the rock mass first."""


def add_parser(commands: Any) -> argparse.ArgumentParser:
    """Adds ``show`` to the subcommands."""
    show = commands.add_parser(
        "show",
        help="draw a block file: picture, interactive HTML view, volume curve",
        description=textwrap.fill(
            "Draw the blocks of a block file (from `penedge generate`) in an exploded "
            "perspective view (PNG, SVG or PDF) and, with --html, as an interactive view in one "
            "self-contained HTML file; with --contacts, find the contacts and draw them "
            "coloured by type.",
            88,
        ),
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    show.set_defaults(subparser=show, run=run_show)
    show.add_argument("blocks", metavar="BLOCKS", help="the block file (.json)")
    pictures = show.add_mutually_exclusive_group()
    pictures.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        help="the picture (.png, .svg or .pdf); default BLOCKS' name with .png",
    )
    pictures.add_argument("--no-picture", action="store_true", help="draw no picture")
    add_html(show, "BLOCKS' name with .html")
    show.add_argument(
        "--stats-png",
        metavar="FILE",
        help="the block volume distribution (cumulative volume fraction, V10/V50/V90)",
    )
    show.add_argument(
        "--contacts",
        action="store_true",
        help="find the contacts and draw them (a small panel per contact type in the "
        "picture; toggleable traces of the HTML view); print their counts",
    )
    add_gap(show)
    add_picture_options(show)
    add_output_flags(show, force=True)
    return show


def _targets(args: argparse.Namespace, blocks: Path) -> dict[str, Target | None]:
    """The outputs asked for: picture, html, stats (None where not asked)."""
    stem = blocks.stem or "blocks"
    named_picture = picture_file(args.output, "-o/--output")
    want_html, named_html = html_file(args)
    stats = output_file(args.stats_png, "--stats-png", (".png",))
    check_distinct(
        {"BLOCKS": blocks},
        {"-o/--output": named_picture, "--html-out": named_html, "--stats-png": stats},
    )
    picture = None
    if not args.no_picture:
        picture = target(named_picture, Path(f"{stem}.png"), args.force)
    html = None
    if want_html:
        html = target(named_html, Path(f"{stem}.html"), args.force)
    return {
        "picture": picture,
        "html": html,
        "stats_png": None if stats is None else Target(stats, True),
    }


def run_show(args: argparse.Namespace) -> int:
    """``penedge show BLOCKS``."""
    blocks = Path(args.blocks)
    targets = _targets(args, blocks)
    if not any(targets.values()):
        raise UsageError("argument --no-picture: nothing to draw (add --html or --stats-png)")
    if args.contacts and targets["picture"] is None and targets["html"] is None:
        raise UsageError("argument --contacts: needs the picture or --html to draw them in")
    if targets["picture"] is not None or targets["stats_png"] is not None:
        require("matplotlib", "the picture", "plot")
    if targets["html"] is not None:
        require("plotly", "--html", "html")
    show = progress.wanted(args.quiet or args.json)
    with progress.activity(show, f"{PROG} show: reading {blocks}"):
        system = penedge.BlockSystem.read_json(blocks)
    if len(system) == 0:
        raise CommandError(f"{blocks} holds no blocks: nothing to draw")
    found = None
    if args.contacts:
        try:
            found = progress.detect(
                system, show, f"{PROG} show", **gap_options(args), geometry=True
            )
        except penedge.ToleranceError as e:
            raise UsageError(f"argument {gap_flag(args)}: {e}") from None
        if len(found.penetrating):
            print(f"{PROG}: warning: {penetration_note(found)}", file=sys.stderr)
    summary = summarize(blocks, system, found, gap_options(args), args.max_blocks)
    title = f"{blocks.name}: {count_text(summary['bodies'], summary['blocks'])}"
    if found is not None:
        title += f", {plural(len(found), 'contact')}"
    options = {
        "title": title,
        "explode": args.explode,
        "colour_by": args.colour_by,
        "unit": args.unit,
        "max_blocks": args.max_blocks,
        "contacts": found,
    }
    notes = []
    asked = {key: where for key, where in targets.items() if where is not None}
    # Every output is drawn before any is put in place: a failure leaves none of them.
    with Outputs() as outputs:
        for key, where in asked.items():
            staged = outputs.staged(where)
            with progress.activity(show, f"{PROG} show: drawing {where.path}"):
                if key == "stats_png":
                    draw.write_volumes(system, staged)
                elif key == "html":
                    draw.write_html(system, staged, **options)
                else:
                    draw.write_picture(system, staged, **options)
        written_paths = outputs.publish()
    for (key, where), written in zip(asked.items(), written_paths, strict=True):
        summary[key] = str(written)
        if written != where.path:
            notes.append(f"{where.path} exists and was kept; wrote {written} instead")
    if summary["shown_bodies"] < summary["bodies"]:
        notes.append(
            f"drew {summary['shown_bodies']} of {summary['bodies']} blocks, those on the "
            "outside of the rock mass first (--max-blocks 0 draws every block)"
        )
    if args.json:
        print(json.dumps(summary, indent=2))
        for note in notes:
            print(f"{PROG}: note: {note}", file=sys.stderr)
    elif not args.quiet:
        print(format_summary(summary))
        for note in notes:
            print(f"note: {note}")
    return 0


def summarize(
    blocks: Path, system: Any, found: Any, gap: dict[str, float], max_blocks: int | None
) -> dict[str, Any]:
    """The result as plain data (what ``--json`` prints): ``blocks`` and ``shown_blocks``
    count convex parts, ``bodies`` and ``shown_bodies`` blocks (a concave block once, as
    ``--max-blocks`` counts them: whole ones are drawn)."""
    n = len(system)
    bodies = blocks_of(system)
    shown_parts, shown_bodies = n, bodies
    if max_blocks is not None and bodies > max_blocks:
        from penedge.pictures.scene import choose_blocks

        shown = choose_blocks(system.arrays(), max_blocks)
        shown_parts = int(shown.sum())
        shown_bodies = len(np.unique(np.asarray(system.body_ids)[shown]))
    return {
        "blocks_file": str(blocks),
        "blocks": n,
        "bodies": bodies,
        "shown_blocks": shown_parts,
        "shown_bodies": shown_bodies,
        **gap_fields(gap if found is not None else None),
        "contacts": None if found is None else len(found),
        "counts": None if found is None else found.counts(),
        "penetrating": None if found is None else len(found.penetrating),
        "picture": None,
        "html": None,
        "stats_png": None,
    }


def format_summary(summary: dict[str, Any]) -> str:
    """What was drawn, with the table of contacts per type when they were found."""
    head = f"{summary['blocks_file']}: {count_text(summary['bodies'], summary['blocks'])}"
    lines = []
    if summary["counts"] is None:
        lines.append(head)
    else:
        lines += [
            f"{head}, {plural(summary['contacts'], 'contact')} ({gap_text(summary)})",
            "",
            *counts_table(summary["counts"]),
            "",
        ]
        if summary["penetrating"]:
            lines.insert(-1, f"penetrating pairs: {summary['penetrating']} (not counted above)")
    for key, label in (
        ("picture", "picture"),
        ("html", "interactive view"),
        ("stats_png", "volume distribution"),
    ):
        if summary[key] is not None:
            lines.append(f"{label}: {summary[key]}")
    return "\n".join(lines)
