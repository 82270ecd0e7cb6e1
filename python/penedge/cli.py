"""The ``penedge`` command line.

``penedge example 1|2|3`` builds one of the paper's examples, detects every contact, prints
the counts of each contact type beside the paper's Table 3 and draws the blocks in an
exploded view. Exit status: 0 success, 1 runtime error (a file could not be written, a
missing optional dependency), 2 usage error; messages go to stderr, without tracebacks.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

import penedge

__all__ = ["build_parser", "main"]

PROG = "penedge"
TABLE3_NOTE = "docs/table3.md"
PICTURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf", ".html": "html"}

DESCRIPTION = """\
Contact detection between convex rock blocks by the penetration-edge method
(Chen, Zheng, Cheng, Ge 2004).

Every edge of block A is clipped by the face planes of block B widened by a small gap,
and vice versa; the surviving penetration edges tell whether two blocks touch and which
of seven contact types it is: vertex-vertex, vertex-edge, edge-edge,
edge-edge-superposition, vertex-face, edge-face, face-face."""

EPILOG = """\
worked example:
  $ penedge example 1
  penedge example 1: a 10 m cube cut by x = 5, y = 5, z = 5
  8 blocks, 28 contacts (relative gap 1e-12)

  contact type               penedge  paper
  vertex-vertex                    4      4
  ...
  face-face                       12     12
  total                           28     28
  picture: example1.png

  The eight 5 m cubes touch face to face 12 times, along an edge 12 times
  (edge-edge superposition) and at the centre point 4 times (vertex-vertex).
  `penedge example 3 -o cube.svg` draws Example 3 as SVG; `--json` prints the
  counts as JSON; `penedge example --help` lists every option."""

EXAMPLE_EPILOG = """\
examples:
  penedge example 3                  table and picture example3.png (or example3-1.png ...
                                     if that file exists: an existing file is never replaced)
  penedge example 2 -o ex2.svg       picture as SVG (.png, .svg, .pdf, or .html with plotly)
  penedge example 1 --no-picture     table only
  penedge example 3 --gap 1e-6       with a relative gap of 1e-6 x block size
  penedge example 3 --json           counts as JSON on stdout"""


class UsageError(Exception):
    """A bad command line (exit status 2)."""


class CommandError(Exception):
    """Something that went wrong while running (exit status 1)."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``penedge`` command."""
    parser = argparse.ArgumentParser(
        prog=PROG,
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {penedge.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    example = commands.add_parser(
        "example",
        help="run one of the paper's examples (Table 3 and a picture)",
        description="Cut a 10 m cube as in the paper's Example N, detect every contact, print "
        "the count of each contact type beside the paper's Table 3, and draw the blocks in an "
        "exploded perspective view.",
        epilog=EXAMPLE_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    example.set_defaults(subparser=example)
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
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        return run_example(args)
    except UsageError as e:
        args.subparser.print_usage(sys.stderr)
        print(f"{args.subparser.prog}: error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # stdout closed early (`penedge example 3 | head -1`): not an error worth a message.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (CommandError, penedge.PenedgeError, OSError) as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130


def run_example(args: argparse.Namespace) -> int:
    """``penedge example N``."""
    if not args.explode >= 0:
        raise UsageError(f"argument --explode: must be >= 0, got {args.explode}")
    target = None if args.no_picture else picture_target(args.output, args.number)
    system = penedge.paper_example(args.number)
    try:
        found = system.detect(gap=args.gap)
    except penedge.ToleranceError as e:
        raise UsageError(f"argument --gap: {e}") from None
    result = summarize(args.number, system, found, args.gap)
    notes = []
    if target is not None:
        path, user_named = target
        written = write_picture(system, result, path, user_named, args.explode)
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
    system: Any, result: dict[str, Any], path: Path, replace: bool, explode: float
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
    directory = path.parent
    if not directory.is_dir():
        raise CommandError(f"cannot write the picture: no directory '{directory}'")
    fd, tmp_name = tempfile.mkstemp(dir=directory, prefix=f".{path.stem}.", suffix=".tmp")
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "wb") as handle:
            draw(system, handle, fmt, title, caption, explode)
        umask = os.umask(0)
        os.umask(umask)
        tmp.chmod(0o666 & ~umask)  # mkstemp makes it private; a picture is an ordinary file
        return publish(tmp, path, replace)
    finally:
        tmp.unlink(missing_ok=True)


def draw(system: Any, handle: Any, fmt: str, title: str, caption: str, explode: float) -> None:
    """Writes the picture in format `fmt` to an open binary file."""
    try:
        from penedge import pictures

        if fmt == "html":
            import io

            text = io.StringIO()
            pictures.write_html(system, text, title=f"{title} ({caption})", explode=explode)
            handle.write(text.getvalue().encode("utf-8"))
        else:
            pictures.save_picture(
                system, handle, title=title, subtitle=caption, format=fmt, explode=explode
            )
    except ImportError as e:
        extra = "html" if fmt == "html" else "plot"
        raise CommandError(
            f"the picture needs {e.name or 'an optional package'}: "
            f"pip install 'penedge[{extra}]' (or use --no-picture)"
        ) from None


def publish(tmp: Path, path: Path, replace: bool) -> Path:
    """Moves `tmp` to `path`, or to the next free name when `path` must not be replaced."""
    if replace:
        tmp.replace(path)
        return path
    for k in range(1000):
        candidate = path if k == 0 else path.with_name(f"{path.stem}-{k}{path.suffix}")
        try:
            os.link(tmp, candidate)  # atomic: fails if the name is taken
            return candidate
        except FileExistsError:
            continue
        except OSError:  # no hard links here: check, then rename
            if not candidate.exists():
                tmp.replace(candidate)
                return candidate
    raise CommandError(f"no free file name near {path}")
