"""What the subcommands share: the errors that set the exit status, the options every
subcommand spells the same way, and output files.

Output files follow one rule: a file the user named on the command line is replaced
atomically (written to a temporary file beside it, then renamed over it); a file the user
did not name (a default name such as ``example3.png``) is never replaced: the next free
name ``stem-1``, ``stem-2``, ... is taken, unless ``--force`` is given. Named outputs are
checked before any work is done: the right suffix, not a directory, an existing folder
where a file can be made, not an input of the command and not named twice. A command with
several outputs writes them all to temporary files first (:class:`Outputs`) and moves
them into place only when every one is written, all or none: a failed command leaves none
of them, and a move that fails puts back the files already replaced.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import secrets
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import IO, Any

PROG = "penedge"

#: Static picture formats, by file suffix (the interactive view is ``--html``).
PICTURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}


class UsageError(Exception):
    """A bad command line (exit status 2)."""


class CommandError(Exception):
    """Something that went wrong while running (exit status 1)."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C, with what a command had done when it stopped (exit status 130)."""


def output_file(value: str | None, option: str, suffixes: tuple[str, ...]) -> Path | None:
    """The path of an output the user named with `option`, checked; None when not named.

    Raises
    ------
    UsageError
        A suffix not in `suffixes`, no name before the suffix, or a directory.
    CommandError
        Its folder does not exist, or no file can be made there.
    """
    if value is None:
        return None
    path = Path(value)
    if path.name.lower() in suffixes:
        raise UsageError(f"argument {option}: '{value}' has no name before {path.name}")
    if path.suffix.lower() not in suffixes:
        ends = " or ".join(suffixes)
        raise UsageError(f"argument {option}: '{value}' should end in {ends}")
    if path.is_dir():
        raise UsageError(f"argument {option}: '{value}' is a directory")
    folder = path.parent
    if not folder.is_dir():
        raise CommandError(f"cannot write {value}: no directory '{folder}'")
    check_writable(path)
    return path


def check_writable(path: Path) -> None:
    """A file can be made beside `path` (where its temporary file goes), checked by making
    one and removing it, before any work.

    Raises
    ------
    CommandError
        Naming `path` and why (``cannot write out.csv: Permission denied``).
    """
    try:
        fd, probe = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".tmp")
    except OSError as e:
        raise CommandError(f"cannot write {path}: {e.strerror or e}") from None
    os.close(fd)
    Path(probe).unlink(missing_ok=True)


def non_negative_float(text: str) -> float:
    """An argparse type: a finite float >= 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid number: '{text}'") from None
    if not (value >= 0 and value != float("inf")):
        raise argparse.ArgumentTypeError(f"must be a number >= 0, got {text}")
    return value


def explode_factor(text: str) -> float:
    """An argparse type: a number from 0 to ``MAX_EXPLODE`` (what the pictures take:
    :func:`penedge.pictures.scene.check_explode`)."""
    from penedge.pictures.scene import check_explode

    try:
        return check_explode(non_negative_float(text))
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"{e} (beyond, the blocks are specks far apart)") from None


def whole_number(text: str, least: int, words: str) -> int:
    """`text` as a whole number of at least `least` (else the argparse error `words`)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid whole number: '{text}'") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"{words}, got {text}")
    return value


def block_limit(text: str) -> int | None:
    """An argparse type: a whole number >= 0, 0 meaning no limit (None)."""
    return whole_number(text, 0, "must be >= 0 (0: every block)") or None


def positive_int(text: str) -> int:
    """An argparse type: a whole number >= 1."""
    return whole_number(text, 1, "must be 1 or more")


def add_gap(parser: argparse.ArgumentParser) -> None:
    """``--gap G`` or ``--absolute-gap D``: the gap of the detection, relative to the blocks'
    size or a length."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--gap",
        type=float,
        default=1e-12,
        metavar="G",
        help="relative gap: blocks closer than G x block size touch (default 1e-12, rounding only)",
    )
    group.add_argument(
        "--absolute-gap",
        type=float,
        default=None,
        metavar="D",
        help="the gap as a length in the blocks' unit (0.001: 1 mm for blocks in metres), "
        "the same for every pair, instead of --gap",
    )


def gap_options(args: argparse.Namespace) -> dict[str, float]:
    """The gap keyword of ``detect``: ``{"absolute_gap": D}`` or ``{"gap": G}``."""
    if args.absolute_gap is not None:
        return {"absolute_gap": args.absolute_gap}
    return {"gap": args.gap}


def gap_flag(args: argparse.Namespace) -> str:
    """The option that set the gap, for messages."""
    return "--absolute-gap" if args.absolute_gap is not None else "--gap"


def gap_fields(options: dict[str, float] | None) -> dict[str, float | None]:
    """The gap of a summary: ``gap`` (relative) and ``absolute_gap``, one of them None."""
    options = options or {}
    return {"gap": options.get("gap"), "absolute_gap": options.get("absolute_gap")}


def gap_text(summary: dict[str, Any]) -> str:
    """``relative gap G`` or ``absolute gap D``, from a summary's gap fields."""
    if summary.get("absolute_gap") is not None:
        return f"absolute gap {summary['absolute_gap']:g}"
    return f"relative gap {summary['gap']:g}"


def add_picture_options(parser: argparse.ArgumentParser) -> None:
    """``--colour-by``, ``--unit``, ``--explode``, ``--max-blocks``: how blocks are
    drawn."""
    from penedge.pictures.scene import DEFAULT_MAX_BLOCKS

    parser.add_argument(
        "--colour-by",
        "--color-by",
        dest="colour_by",
        choices=("set", "block", "volume"),
        default=None,
        help="colour each block by its joint set (the set of most of its face area; the "
        "default for a system generated with joint sets), its own colour (the default "
        "otherwise), or by its volume with a colour bar",
    )
    parser.add_argument(
        "--unit",
        default=None,
        metavar="U",
        help="the model's length unit, for the axes and the scale bar (default: the spec's "
        "`unit`, kept in the block file, else m)",
    )
    parser.add_argument(
        "--explode",
        type=explode_factor,
        default=0.5,
        metavar="F",
        help="move each block outward by F x its distance from the centre, so that inner "
        "blocks show (default 0.5; 0: as they lie; at most 100)",
    )
    parser.add_argument(
        "--max-blocks",
        type=block_limit,
        default=DEFAULT_MAX_BLOCKS,
        metavar="N",
        help=f"draw at most N blocks (a concave block counts once, drawn whole), those on "
        f"the outside of the rock mass first (default {DEFAULT_MAX_BLOCKS}; 0: every block)",
    )


def add_html(parser: argparse.ArgumentParser, default: str) -> None:
    """``--html`` (a flag: the view at the default name) and ``--html-out FILE`` (the view at
    FILE). ``--html`` takes no value, so ``--html blocks.json`` never takes the block file
    for the HTML file's name."""
    parser.add_argument(
        "--html",
        action="store_true",
        help=f"also write the interactive view (self-contained HTML: rotate, zoom, hide / "
        f"show, hover) to {default}",
    )
    parser.add_argument(
        "--html-out",
        metavar="FILE",
        help="write the interactive view to FILE (.html); implies --html",
    )


def html_file(args: argparse.Namespace) -> tuple[bool, Path | None]:
    """Whether the HTML view is asked for (``--html`` or ``--html-out``), and the file the
    user named (None: the default name)."""
    named = output_file(args.html_out, "--html-out", (".html",))
    return args.html or named is not None, named


def add_output_flags(parser: argparse.ArgumentParser, force: bool) -> None:
    """``--json`` and ``-q/--quiet`` (and ``--force`` where there are default names)."""
    if force:
        parser.add_argument(
            "--force",
            action="store_true",
            help="replace an existing file at a default output name (by default a free "
            "name such as stem-1.png is taken; a file named on the command line is "
            "always replaced)",
        )
    parser.add_argument(
        "--json", action="store_true", help="print the result as JSON on stdout (no progress)"
    )
    parser.add_argument(
        "-q", "--quiet", action="store_true", help="print nothing (no progress, no summary)"
    )


def picture_file(value: str | None, option: str) -> Path | None:
    """A static picture the user named (.png, .svg or .pdf), checked."""
    if value is not None and Path(value).suffix.lower() == ".html":
        raise UsageError(
            f"argument {option}: '{value}' is an HTML file; use --html-out {value} for the "
            "interactive view"
        )
    if value is not None and Path(value).name.lower() in PICTURE_FORMATS:
        raise UsageError(f"argument {option}: '{value}' has no name before {Path(value).name}")
    if value is not None and Path(value).suffix.lower() not in PICTURE_FORMATS:
        known = ", ".join(PICTURE_FORMATS)
        raise UsageError(
            f"argument {option}: cannot tell the picture format of '{value}' "
            f"(use a file name ending in {known})"
        )
    return output_file(value, option, tuple(PICTURE_FORMATS))


class Target:
    """Where an output goes: a path, and whether it may replace an existing file there
    (the user named it, or ``--force``)."""

    def __init__(self, path: Path, replace: bool) -> None:
        self.path = path
        self.replace = replace

    def write(self, write: Callable[[IO[bytes]], None]) -> Path:
        """Writes through a temporary file; returns the path written (another name when
        the path was taken and may not be replaced)."""
        return write_via_temp(self.path, self.replace, write)


def target(named: Path | None, default: Path, force: bool) -> Target:
    """The user's path (replaced if it exists), else the default one (replaced only with
    `force`; its folder checked as a named output's is)."""
    if named is not None:
        return Target(named, True)
    check_writable(default)
    return Target(default, force)


class Outputs:
    """The outputs of one command, written to temporary files beside their targets and moved
    into place together (:meth:`publish`) once every one is written: a command that fails
    half way leaves none of them. Used as a context manager, it removes what was not
    published.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> with Outputs() as outputs:
    ...     a = outputs.staged(Target(folder / "a.txt", True))
    ...     _ = a.write(lambda handle: handle.write(b"a"))
    ...     print(sorted(p.name for p in folder.iterdir() if not p.name.startswith(".")))
    ...     [p.name for p in outputs.publish()]
    []
    ['a.txt']
    """

    def __init__(self) -> None:
        self._staged: list[tuple[Path, Target]] = []

    def __enter__(self) -> Outputs:
        return self

    def __exit__(self, *exc: object) -> None:
        self.discard()

    def staged(self, target: Target) -> Target:
        """A target whose ``write`` writes the temporary file only (and returns the path
        meant); :meth:`publish` moves it into place."""
        outputs = self

        class Staged(Target):
            def write(self, write: Callable[[IO[bytes]], None]) -> Path:
                outputs._staged.append((write_temp(self.path, write), target))
                return self.path

        return Staged(target.path, target.replace)

    def write_named(self, path: Path, write: Callable[[Path], None]) -> None:
        """Writes the output `path` (replaced when published) by ``write(name)``, a writer
        that takes a file name (the library's), into its temporary file."""
        self._staged.append((write_temp(path, write, by_name=True), Target(path, True)))

    def publish(self) -> list[Path]:
        """Moves every file written into place, in the order written, all or none; returns
        the paths written (another name where a default name was taken).

        Every file to be replaced is first set aside under a temporary name beside it (a
        hard link, so that it stays in place until the new file replaces it in one rename;
        where the file system has no hard links, moved there). If any move fails, the files
        already moved in are removed and the old ones put back, and the error is raised:
        no output is changed. Once all are in place, the old files are removed.

        Raises
        ------
        OSError
            Naming the output that could not be moved into place.
        CommandError
            An old file could not be put back after a failure: says where it is kept.
        """
        try:
            return publish_all([(tmp, where.path, where.replace) for tmp, where in self._staged])
        finally:
            self.discard()

    def discard(self) -> None:
        """Removes the temporary files not moved into place."""
        for tmp, _ in self._staged:
            tmp.unlink(missing_ok=True)
        self._staged.clear()


def available(module: str) -> bool:
    """Whether an optional package can be imported."""
    try:
        __import__(module)
    except ImportError:
        return False
    return True


def require(module: str, option: str, extra: str) -> None:
    """Fails early (before a long run) when an output needs an optional package."""
    try:
        __import__(module)
    except ImportError:
        raise CommandError(f"{option} needs {module}: pip install 'penedge[{extra}]'") from None


def check_distinct(inputs: Mapping[str, Path], outputs: Mapping[str, Path | None]) -> None:
    """No output is an input of the command, and no file is named by two outputs.

    Raises
    ------
    UsageError
        Naming the two arguments.
    """
    seen = {_identity(path): f"the input {name}" for name, path in inputs.items()}
    for option, path in outputs.items():
        if path is None:
            continue
        key = _identity(path)
        if key in seen:
            raise UsageError(
                f"argument {option}: '{path}' is also {seen[key]}; refusing to overwrite it"
            )
        seen[key] = f"given to {option}"


def _identity(path: Path) -> tuple[object, ...]:
    """The same key for two names of one file (an existing file: device and inode)."""
    try:
        status = path.stat()
        return ("inode", status.st_dev, status.st_ino)
    except OSError:
        return ("path", os.path.normcase(path.absolute()))


def write_via_temp(path: Path, replace: bool, write: Callable[[IO[bytes]], None]) -> Path:
    """Writes a file through ``write(handle)`` into a temporary file beside `path`, then
    moves it into place: over `path` when `replace`, else to the next free name.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    OSError
        Naming `path` (not the temporary file).
    """
    tmp = write_temp(path, write)
    try:
        return publish(tmp, path, replace)
    finally:
        tmp.unlink(missing_ok=True)


def write_temp(path: Path, write: Callable[[Any], None], *, by_name: bool = False) -> Path:
    """Writes ``write(handle)`` into a new temporary file beside `path`; returns its path
    (removed again if the writing fails). With `by_name`, ``write(tmp)`` writes the file by
    its name instead (the library's writers, which check its suffix: the temporary file
    keeps `path`'s). An OSError names `path`, not the temporary file."""
    directory = path.parent
    if not directory.is_dir():
        raise CommandError(f"cannot write {path}: no directory '{directory}'")
    suffix = path.suffix if by_name else ".tmp"
    try:
        fd, tmp_name = tempfile.mkstemp(dir=directory, prefix=f".{path.stem}.", suffix=suffix)
    except OSError as e:
        raise _naming(e, path) from None
    tmp = Path(tmp_name)
    try:
        if by_name:
            os.close(fd)
            write(tmp)
        else:
            with os.fdopen(fd, "wb") as handle:
                write(handle)
        umask = os.umask(0)
        os.umask(umask)
        tmp.chmod(0o666 & ~umask)  # mkstemp makes it private; an output is an ordinary file
    except OSError as e:
        tmp.unlink(missing_ok=True)
        raise _naming(e, path, tmp) from None
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return tmp


def _naming(e: OSError, path: Path, tmp: Path | None = None) -> OSError:
    """`e` about `path` where it named the temporary file (or no file): the user never saw
    the temporary file's name."""
    if e.filename is not None and tmp is not None and Path(e.filename) != tmp:
        return e  # about another file (one the writer reads, say)
    try:
        return type(e)(e.errno, e.strerror or str(e), str(path))
    except Exception:  # an OSError subclass with another signature
        return OSError(e.errno, e.strerror or str(e), str(path))


def publish_all(staged: list[tuple[Path, Path, bool]]) -> list[Path]:
    """Moves each temporary file `tmp` of `staged` (``(tmp, path, replace)``) into place
    as :func:`publish` does, all or none (:meth:`Outputs.publish`); returns the paths
    written. The temporary files are left to the caller."""
    kept: dict[Path, tuple[Path, bool]] = {}  # target: (its old file set aside, moved away)
    written: list[tuple[Path, Path]] = []  # (path written, target)
    try:
        for _, path, replace in staged:
            if replace and path not in kept and os.path.lexists(path):
                kept[path] = _set_aside(path)
        for tmp, path, replace in staged:
            written.append((publish(tmp, path, replace), path))
    except BaseException as e:
        lost = _roll_back(kept, written)
        if lost:
            where = "; ".join(f"the old {target} is kept as {old}" for target, old in lost)
            raise CommandError(f"{_describe(e)}; could not put back every file: {where}") from e
        raise
    for old, _ in kept.values():
        # Every output is in place; a hidden old file left beside one would be harmless.
        with contextlib.suppress(OSError):
            old.unlink(missing_ok=True)
    return [path for path, _ in written]


def _describe(e: BaseException) -> str:
    """``out.png: Permission denied`` for an OSError naming a file, else the message."""
    if isinstance(e, OSError) and e.filename is not None and e.strerror:
        return f"{e.filename}: {e.strerror}"
    return str(e) or type(e).__name__


def _set_aside(path: Path) -> tuple[Path, bool]:
    """The file at `path` kept under a new temporary name beside it: a hard link where the
    file system has them (the file stays at `path` too), else moved there. Returns the
    name, and whether the file was moved away from `path`. An OSError names `path`."""
    for _ in range(100):
        name = path.with_name(f".{path.stem}.{secrets.token_hex(6)}.old")
        try:
            os.link(path, name, follow_symlinks=False)
            return name, False
        except FileExistsError:
            continue
        except (OSError, NotImplementedError):  # no hard links here: move it aside
            break
    try:
        fd, name_text = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".old")
    except OSError as e:
        raise _naming(e, path) from None
    os.close(fd)
    name = Path(name_text)
    try:
        path.replace(name)
    except OSError as e:
        name.unlink(missing_ok=True)
        raise _naming(e, path, name) from None
    return name, True


def _roll_back(
    kept: dict[Path, tuple[Path, bool]], written: list[tuple[Path, Path]]
) -> list[tuple[Path, Path]]:
    """Undoes a :func:`publish_all` that failed: removes the files moved in and puts the
    old ones back (`kept`: set aside). Returns (target, where its old file is kept) for
    each old file that could not be put back (left where it was set aside)."""
    lost = []
    for path, target in reversed(written):
        if target in kept:
            old, _ = kept.pop(target)
            try:
                old.replace(target)  # over the new file: the old one is back
            except OSError:
                lost.append((target, old))
        else:
            Path(path).unlink(missing_ok=True)  # a file made where there was none
    for target, (old, moved) in kept.items():  # set aside but not replaced
        try:
            if moved:
                old.replace(target)
            else:
                old.unlink()  # a second name of the file still at `target`
        except OSError:
            lost.append((target, old))
    return lost


def publish(tmp: Path, path: Path, replace: bool) -> Path:
    """Moves `tmp` to `path`, or to the next free name when `path` must not be replaced.
    An OSError names `path`."""
    if replace:
        try:
            tmp.replace(path)
        except OSError as e:
            raise _naming(e, path, tmp) from None
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
                try:
                    tmp.replace(candidate)
                except OSError as e:
                    raise _naming(e, candidate, tmp) from None
                return candidate
    raise CommandError(f"no free file name near {path}")


def require_matplotlib(option: str) -> None:
    """Fails early (before a long run) when a picture is asked for without matplotlib."""
    require("matplotlib", option, "plot")


def plural(n: int, word: str) -> str:
    """``1 block``, ``2 blocks``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"
