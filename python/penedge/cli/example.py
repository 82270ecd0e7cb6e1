"""``penedge example N``: one of the paper's examples, its Table 3 and a picture."""

from __future__ import annotations

import argparse
import io
import json
import sys
from pathlib import Path
from typing import IO, Any

import penedge
from penedge.cli.common import PROG, CommandError, UsageError, write_via_temp

TABLE3_NOTE = "docs/table3.md"
PICTURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf", ".html": "html"}

EPILOG = """\
examples:
  penedge example 3                  table and picture example3.png (or example3-1.png ...
                                     if that file exists: an existing file is never replaced)
  penedge example 3 --contacts       the picture gets a second panel: the contacts,
                                     coloured by type
  penedge example 2 -o ex2.svg       picture as SVG (.png, .svg, .pdf, or .html with plotly)
  penedge example 1 --no-picture     table only
  penedge example 3 --gap 1e-6       with a relative gap of 1e-6 x block size
  penedge example 3 --json           counts as JSON on stdout"""


def add_parser(commands: Any) -> argparse.ArgumentParser:
    """Adds ``example`` to the subcommands."""
    example = commands.add_parser(
        "example",
        help="run one of the paper's examples (Table 3 and a picture)",
        description="Cut a 10 m cube as in the paper's Example N, detect every contact, print "
        "the count of each contact type beside the paper's Table 3, and draw the blocks in an "
        "exploded perspective view.",
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
        help="picture file (.png, .svg, .pdf or .html); replaced if it "
        "exists. Default: exampleN.png in the current directory, never "
        "replacing an existing file",
    )
    pictures.add_argument("--no-picture", action="store_true", help="do not draw a picture")
    example.add_argument(
        "--contacts",
        action="store_true",
        help="draw the contacts (points, segments, polygons coloured by type) in a second "
        "panel of the picture (.png, .svg or .pdf)",
    )
    example.add_argument(
        "--gap",
        type=float,
        default=1e-12,
        metavar="G",
        help="relative gap: blocks closer than G x block size touch (default 1e-12, rounding only)",
    )
    example.add_argument(
        "--explode",
        type=float,
        default=0.5,
        metavar="F",
        help="move each block outward by F x its distance from the centre "
        "in the picture (default 0.5)",
    )
    example.add_argument(
        "--json", action="store_true", help="print the result as JSON (notes go to stderr)"
    )
    return example


def run_example(args: argparse.Namespace) -> int:
    """``penedge example N``."""
    if not args.explode >= 0:
        raise UsageError(f"argument --explode: must be >= 0, got {args.explode}")
    target = None if args.no_picture else picture_target(args.output, args.number)
    if args.contacts and (target is None or target[0].suffix.lower() == ".html"):
        raise UsageError("argument --contacts: needs a .png, .svg or .pdf picture")
    system = penedge.paper_example(args.number)
    try:
        found = system.detect(gap=args.gap, geometry=args.contacts)
    except penedge.ToleranceError as e:
        raise UsageError(f"argument --gap: {e}") from None
    result = summarize(args.number, system, found, args.gap)
    notes = []
    if target is not None:
        path, user_named = target
        contacts = found if args.contacts else None
        written = write_picture(system, result, path, user_named, args.explode, contacts)
        result["picture"] = str(written)
        if written != path:
            notes.append(f"{path} exists and was kept; the picture went to {written}")
    if args.json:
        print(json.dumps(result, indent=2))
        for note in notes:
            print(f"{PROG}: note: {note}", file=sys.stderr)
    else:
        print(format_report(result, notes))
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


def summarize(number: int, system: Any, found: Any, gap: float) -> dict[str, Any]:
    """The result of an example as plain data (what ``--json`` prints)."""
    normals, offsets = penedge.paper_example_planes(number)
    counts = found.counts()
    paper = penedge.paper_table3(number)
    return {
        "example": number,
        "planes": [plane_text(n, d) for n, d in zip(normals, offsets, strict=True)],
        "gap": gap,
        "blocks": len(system),
        "counts": counts,
        "total": sum(counts.values()),
        "paper": paper,
        "paper_total": sum(paper.values()),
        "differs": [name for name in counts if counts[name] != paper[name]],
        "penetrating": len(found.penetrating),
        "picture": None,
    }


def format_report(result: dict[str, Any], notes: list[str]) -> str:
    """The human-readable report of an example."""
    lines = [
        f"penedge example {result['example']}: a 10 m cube cut by {', '.join(result['planes'])}",
        f"{result['blocks']} blocks, {result['total']} contacts (relative gap {result['gap']:g})",
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
    lines += [f"note: {note}" for note in notes]
    return "\n".join(lines)


def picture_target(output: str | None, number: int) -> tuple[Path, bool]:
    """The picture's path and whether the user named it (then it may be replaced)."""
    if output is None:
        return Path(f"example{number}.png"), False
    path = Path(output)
    if path.suffix.lower() not in PICTURE_FORMATS:
        known = ", ".join(PICTURE_FORMATS)
        raise UsageError(
            f"argument -o/--output: cannot tell the picture format of "
            f"'{output}' (use a file name ending in {known})"
        )
    if path.is_dir():
        raise UsageError(f"argument -o/--output: '{output}' is a directory")
    return path, True


def write_picture(
    system: Any,
    result: dict[str, Any],
    path: Path,
    replace: bool,
    explode: float,
    contacts: Any = None,
) -> Path:
    """Draws the system into a temporary file beside `path`, then moves it into place.

    A file the user did not name is never replaced: the next free name ``stem-1``,
    ``stem-2``, ... is taken instead. Returns the path written.
    """
    fmt = PICTURE_FORMATS[path.suffix.lower()]
    title = (
        f"penedge example {result['example']}: {result['blocks']} blocks, "
        f"{result['total']} contacts"
    )
    caption = f"exploded view: each block moved out by {explode:g} × its distance from the centre"

    def write(handle: IO[bytes]) -> None:
        draw(system, handle, fmt, title, caption, explode, contacts)

    return write_via_temp(path, replace, write)


def draw(
    system: Any,
    handle: IO[bytes],
    fmt: str,
    title: str,
    caption: str,
    explode: float,
    contacts: Any = None,
) -> None:
    """Writes the picture in format `fmt` to an open binary file."""
    try:
        from penedge import pictures

        if fmt == "html":
            text = io.StringIO()
            pictures.write_html(system, text, title=f"{title} ({caption})", explode=explode)
            handle.write(text.getvalue().encode("utf-8"))
        else:
            pictures.save_picture(
                system,
                handle,
                title=title,
                subtitle=caption,
                format=fmt,
                explode=explode,
                contacts=contacts,
            )
    except ImportError as e:
        extra = "html" if fmt == "html" else "plot"
        raise CommandError(
            f"the picture needs {e.name or 'an optional package'}: "
            f"pip install 'penedge[{extra}]' (or use --no-picture)"
        ) from None
