"""``penedge example N``: one of the paper's examples, its Table 3, a picture and an
interactive view."""

from __future__ import annotations

import argparse
import json
import sys
import textwrap
from pathlib import Path
from typing import Any

import penedge
from penedge.cli import draw, progress
from penedge.cli.common import (
    PROG,
    Outputs,
    UsageError,
    add_gap,
    add_html,
    add_output_flags,
    add_picture_options,
    available,
    check_distinct,
    gap_fields,
    gap_flag,
    gap_options,
    gap_text,
    html_file,
    picture_file,
    require,
    target,
)

TABLE3_NOTE = "docs/table3.md"

EPILOG = """\
worked example:
  $ penedge example 3 --html
  penedge example 3: a 10 m cube cut by x = 5, y = 5, z = 5, x + y = 10, y + z = 10, x + z = 10
  26 blocks, 325 contacts (relative gap 1e-12)

  contact type               penedge  paper
  vertex-vertex                  205    205
  ...
  face-face                       42     42
  total                          325    325
  picture: example3.png
  interactive view: example3.html

  example3.png shows the 26 blocks in an exploded perspective view; open
  example3.html in a web browser to turn and zoom it (it needs no network).

more:
  penedge example 3 --contacts       a panel per contact type (and the HTML view) with
                                     the contacts
  penedge example 3 --colour-by volume
                                     blocks coloured by volume, with a colour bar
  penedge example 2 -o ex2.svg       the picture as SVG (.png, .svg or .pdf)
  penedge example 1 --no-picture     the table only
  penedge example 3 --gap 1e-6       with a relative gap of 1e-6 x block size
  penedge example 3 --json           the counts as JSON on stdout

Default names (example3.png, example3.html) never replace an existing file: the next
free name (example3-1.png, ...) is taken, unless --force. A file named with -o or
--html-out is replaced. Without matplotlib (the `plot` extra) the table is printed and the
picture left out."""


def add_parser(commands: Any) -> argparse.ArgumentParser:
    """Adds ``example`` to the subcommands."""
    example = commands.add_parser(
        "example",
        help="run one of the paper's examples (Table 3, a picture, an HTML view)",
        description=textwrap.fill(
            "Cut a 10 m cube as in the paper's Example N, detect every contact, print "
            "the count of each contact type beside the paper's Table 3, and draw the blocks in an "
            "exploded perspective view (PNG) and, with --html, an interactive view.",
            88,
        ),
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    example.set_defaults(subparser=example, run=run_example)
    example.add_argument(
        "number",
        type=int,
        choices=(1, 2, 3),
        metavar="N",
        help="1: x, y, z = 5 (8 blocks); 2: x+y, y+z, z+x = 10 (8 blocks); "
        "3: all six planes (26 blocks)",
    )
    pictures = example.add_mutually_exclusive_group()
    pictures.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        help="the picture (.png, .svg or .pdf); default exampleN.png",
    )
    pictures.add_argument("--no-picture", action="store_true", help="draw no picture")
    add_html(example, "exampleN.html")
    example.add_argument(
        "--contacts",
        action="store_true",
        help="draw the contacts too: points, segments, polygons, a panel per type",
    )
    add_gap(example)
    add_picture_options(example)
    add_output_flags(example, force=True)
    return example


def run_example(args: argparse.Namespace) -> int:
    """``penedge example N``."""
    n = args.number
    picture = None
    if not args.no_picture:
        named = picture_file(args.output, "-o/--output")
        picture = target(named, Path(f"example{n}.png"), args.force)
    html = None
    want_html, named_html = html_file(args)
    if want_html:
        html = target(named_html, Path(f"example{n}.html"), args.force)
    if args.contacts and picture is None and html is None:
        raise UsageError("argument --contacts: needs the picture or --html to draw them in")
    check_distinct({}, {"-o/--output": picture and picture.path, "--html-out": html and html.path})
    notes = []
    if picture is not None and args.output is None and not available("matplotlib"):
        # The table is the result; the default picture is a bonus that needs the extra.
        picture = None
        notes.append(
            "no picture: it needs matplotlib (pip install 'penedge[plot]'); the table above "
            "is complete"
        )
    if picture is not None:
        require("matplotlib", "the picture", "plot")
    if html is not None:
        require("plotly", "--html", "html")
    show = progress.wanted(args.quiet or args.json)
    system = penedge.paper_example(n)
    try:
        found = progress.detect(
            system, show, f"{PROG} example {n}", **gap_options(args), geometry=args.contacts
        )
    except penedge.ToleranceError as e:
        raise UsageError(f"argument {gap_flag(args)}: {e}") from None
    result = summarize(n, system, found, gap_options(args))
    title = f"penedge example {n}: {result['blocks']} blocks, {result['total']} contacts"
    options = {
        "title": title,
        "explode": args.explode,
        "colour_by": args.colour_by,
        "unit": args.unit,
        "max_blocks": args.max_blocks,
        "contacts": found if args.contacts else None,
    }
    asked = [
        (key, where, writer)
        for key, where, writer in (
            ("picture", picture, draw.write_picture),
            ("html", html, draw.write_html),
        )
        if where is not None
    ]
    # Both outputs are drawn before either is put in place: a failure leaves neither.
    with Outputs() as outputs:
        for _, where, writer in asked:
            with progress.activity(show, f"{PROG} example {n}: drawing {where.path}"):
                writer(system, outputs.staged(where), **options)
        written_paths = outputs.publish()
    for (key, where, _), written in zip(asked, written_paths, strict=True):
        result[key] = str(written)
        if written != where.path:
            notes.append(f"{where.path} exists and was kept; wrote {written} instead")
    if args.json:
        print(json.dumps(result, indent=2))
        for note in notes:
            print(f"{PROG}: note: {note}", file=sys.stderr)
    elif not args.quiet:
        print(format_report(result))
        for note in notes:
            print(f"note: {note}")
    return 0


def plane_text(normal: Any, offset: float) -> str:
    """``x + y = 10`` for normal (1, 1, 0) and offset 10."""
    terms = []
    for coefficient, name in zip(normal, "xyz", strict=True):
        if coefficient == 0:
            continue
        sign = "-" if coefficient < 0 else "+"
        size = abs(coefficient)
        term = name if size == 1 else f"{size:g}{name}"
        terms.append(f"{sign} {term}")
    text = " ".join(terms).removeprefix("+ ")
    return f"{text} = {offset:g}"


def summarize(number: int, system: Any, found: Any, gap: dict[str, float]) -> dict[str, Any]:
    """The result of an example as plain data (what ``--json`` prints)."""
    normals, offsets = penedge.paper_example_planes(number)
    counts = found.counts()
    paper = penedge.paper_table3(number)
    return {
        "example": number,
        "planes": [plane_text(n, d) for n, d in zip(normals, offsets, strict=True)],
        **gap_fields(gap),
        "blocks": len(system),
        "counts": counts,
        "total": sum(counts.values()),
        "paper": paper,
        "paper_total": sum(paper.values()),
        "differs": [name for name in counts if counts[name] != paper[name]],
        "penetrating": len(found.penetrating),
        "picture": None,
        "html": None,
    }


def format_report(result: dict[str, Any]) -> str:
    """The human-readable report of an example."""
    lines = [
        f"penedge example {result['example']}: a 10 m cube cut by {', '.join(result['planes'])}",
        f"{result['blocks']} blocks, {result['total']} contacts ({gap_text(result)})",
        "",
        f"{'contact type':<25}{'penedge':>9}{'paper':>7}",
    ]
    for name, count in result["counts"].items():
        mark = "  *" if name in result["differs"] else ""
        lines.append(f"{name:<25}{count:>9}{result['paper'][name]:>7}{mark}")
    total_mark = "  *" if result["total"] != result["paper_total"] else ""
    lines.append(f"{'total':<25}{result['total']:>9}{result['paper_total']:>7}{total_mark}")
    if result["penetrating"]:
        lines.append(f"{'penetrating pairs':<25}{result['penetrating']:>9}")
    if result["differs"]:
        lines += [
            "",
            f"* differs from the paper's Table 3; {TABLE3_NOTE} explains why "
            "(an exact count agrees with penedge).",
        ]
    if result["picture"] is not None:
        lines.append(f"picture: {result['picture']}")
    if result["html"] is not None:
        lines.append(f"interactive view: {result['html']}")
    return "\n".join(lines)
