"""What the subcommands share: the errors that set the exit status, and output files.

Output files follow one rule: a file the user named on the command line is replaced
atomically (written to a temporary file beside it, then renamed over it); a file the user
did not name is never replaced (the next free name ``stem-1``, ``stem-2``, ... is taken).
Named outputs are checked before any work is done: the right suffix, not a directory, an
existing folder, not an input of the command and not named twice.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import IO

PROG = "penedge"


class UsageError(Exception):
    """A bad command line (exit status 2)."""


class CommandError(Exception):
    """Something that went wrong while running (exit status 1)."""


def output_file(value: str | None, option: str, suffixes: tuple[str, ...]) -> Path | None:
    """The path of an output the user named with `option`, checked; None when not named.

    Raises
    ------
    UsageError
        A suffix not in `suffixes`, or a directory.
    CommandError
        Its folder does not exist.
    """
    if value is None:
        return None
    path = Path(value)
    if path.suffix.lower() not in suffixes:
        ends = " or ".join(suffixes)
        raise UsageError(f"argument {option}: '{value}' should end in {ends}")
    if path.is_dir():
        raise UsageError(f"argument {option}: '{value}' is a directory")
    folder = path.parent
    if not folder.is_dir():
        raise CommandError(f"cannot write {value}: no directory '{folder}'")
    return path


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
    """
    directory = path.parent
    if not directory.is_dir():
        raise CommandError(f"cannot write {path}: no directory '{directory}'")
    fd, tmp_name = tempfile.mkstemp(dir=directory, prefix=f".{path.stem}.", suffix=".tmp")
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
        umask = os.umask(0)
        os.umask(umask)
        tmp.chmod(0o666 & ~umask)  # mkstemp makes it private; an output is an ordinary file
        return publish(tmp, path, replace)
    finally:
        tmp.unlink(missing_ok=True)


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


def require_matplotlib(option: str) -> None:
    """Fails early (before a long run) when a picture is asked for without matplotlib."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise CommandError(f"{option} needs matplotlib: pip install 'penedge[plot]'") from None


def plural(n: int, word: str) -> str:
    """``1 block``, ``2 blocks``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"
