"""The ``penedge`` command line.

* ``penedge example 1|2|3``: one of the paper's examples, its Table 3 and a picture
  (:mod:`penedge.cli.example`);
* ``penedge generate SPEC``: a rock domain cut into blocks, written as a block file and
  ParaView / CSV / PNG files (:mod:`penedge.cli.generate`);
* ``penedge detect BLOCKS``: every contact of a block file, as CSV and ParaView files
  (:mod:`penedge.cli.detect`);
* ``penedge show BLOCKS``: pictures of a block file: exploded view, interactive HTML
  view, volume distribution, contacts by type (:mod:`penedge.cli.show`);
* ``penedge simulate MODEL``: run a model file (docs/models.md) on the rigid-block engine:
  summary, history, pictures, ParaView series (:mod:`penedge.cli.simulate`).

Exit status: 0 success, 1 runtime error (a bad spec or block file, a file that cannot be
read or written, a missing optional dependency), 2 usage error, 130 interrupted (Ctrl-C);
messages go to stderr, without tracebacks.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import NoReturn

import penedge
from penedge.cli import detect, example, generate, show, simulate
from penedge.cli.common import PROG, CommandError, Interrupted, UsageError

__all__ = ["build_parser", "main"]

DESCRIPTION = """\
Contact detection between convex rock blocks by the penetration-edge method
(Chen, Zheng, Cheng, Ge 2004).

Every edge of block A is clipped by the face planes of block B widened by a small gap,
and vice versa; the surviving penetration edges tell whether two blocks touch and which
of seven contact types it is: vertex-vertex, vertex-edge, edge-edge,
edge-edge-superposition, vertex-face, edge-face, face-face."""

EPILOG = """\
worked example:
  $ penedge example 3 --html
  penedge example 3: a 10 m cube cut by x = 5, y = 5, z = 5, x + y = 10, y + z = 10, x + z = 10
  26 blocks, 325 contacts (relative gap 1e-12)

  contact type               penedge  paper
  vertex-vertex                  205    205
  vertex-edge                      0      0
  edge-edge                        0      0
  edge-edge-superposition         78     78
  vertex-face                      0      0
  edge-face                        0      0
  face-face                       42     42
  total                          325    325
  picture: example3.png
  interactive view: example3.html

  The paper's Example 3: the 26 blocks touch at a point 205 times, along an edge 78
  times and face to face 42 times, as in its Table 3. example3.png shows them in an
  exploded view; example3.html turns and zooms in a web browser.

your own rock mass:
  $ penedge generate examples/three_joint_sets.toml -o blocks.json --stats-png volumes.png
  $ penedge detect blocks.json -o contacts.csv --vtp contacts.vtp
  $ penedge show blocks.json --html --colour-by volume

  `penedge COMMAND --help` shows each command's options and a worked example.

options every command spells the same way:
  -o/--output FILE   the main output         --json       the result as JSON on stdout
  -q/--quiet         print nothing           --gap G      the relative contact gap
                                             --absolute-gap D   or the gap as a length
  --force            example, show: replace a file at a default name (exampleN.png);
                     a file named on the command line is always replaced
  --colour-by set|block|volume, --unit U, --explode F, --max-blocks N
                     how pictures draw blocks
                     (generate --max-blocks N: the most blocks a run may make)
  --html             example, show: the interactive view at a default name;
                     --html-out FILE names it

exit status:
  0    success
  1    runtime error: a bad spec or block file, a file that cannot be read or
       written, a missing optional package
  2    usage error: a bad command line (nothing is written)
  130  interrupted (Ctrl-C)"""


class Parser(argparse.ArgumentParser):
    """argparse's parser, with a hint for a file name left over after ``--html`` (which
    takes none since the block file could be taken for it)."""

    def error(self, message: str) -> NoReturn:
        _, _, extra = message.partition("unrecognized arguments: ")
        if any(word.lower().endswith(".html") for word in extra.split()):
            message += " (--html takes no file name: name the view with --html-out FILE)"
        super().error(message)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``penedge`` command."""
    parser = Parser(
        prog=PROG,
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {penedge.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    example.add_parser(commands)
    generate.add_parser(commands)
    detect.add_parser(commands)
    show.add_parser(commands)
    simulate.add_parser(commands)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
    except KeyboardInterrupt:
        print(f"\n{PROG}: interrupted", file=sys.stderr)
        return 130
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        return args.run(args)
    except UsageError as e:
        args.subparser.print_usage(sys.stderr)
        print(f"{args.subparser.prog}: error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # stdout closed early (`penedge example 3 | head -1`): not an error worth a message.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as e:
        print(f"{PROG}: error: {os_message(e)}", file=sys.stderr)
        return 1
    except (CommandError, penedge.PenedgeError) as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 1
    except MemoryError:
        # A run larger than the machine (e.g. the HTML view of a million contacts): a
        # message and status 1, not a traceback; outputs are written whole or not at all.
        print(
            f"{PROG}: error: out of memory: {args.subparser.prog} needs more memory than is "
            "free here; ask for less (--max-blocks for pictures and generation, no "
            "--contacts in pictures of large systems) or use a larger machine",
            file=sys.stderr,
        )
        return 1
    except KeyboardInterrupt as e:
        said = str(e) if isinstance(e, Interrupted) else "interrupted"
        print(f"\n{PROG}: {said}", file=sys.stderr)
        return 130


def os_message(e: OSError) -> str:
    """``blocks.json: No such file or directory`` (not ``[Errno 2] ...``)."""
    if e.filename is not None and e.strerror:
        return f"{e.filename}: {e.strerror}"
    return str(e)
