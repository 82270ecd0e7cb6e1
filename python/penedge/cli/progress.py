"""Progress on stderr for long runs: a bar where the work can be counted (cutting by joint
planes, finding contacts), an elapsed-time line where it cannot (reading a file, drawing).

Both stay silent for the first second, so that short runs print nothing, and draw only on
a terminal (:func:`wanted`); ``--quiet`` and ``--json`` turn them off.
"""

from __future__ import annotations

import inspect
import sys
import threading
import time
from collections.abc import Callable
from types import TracebackType
from typing import Any, TextIO


def wanted(quiet: bool, stream: TextIO | None = None) -> bool:
    """Whether to show progress: not `quiet`, and `stream` (default stderr) is a terminal."""
    stream = sys.stderr if stream is None else stream
    isatty = getattr(stream, "isatty", None)
    return not quiet and isatty is not None and bool(isatty())


class ProgressBar:
    """A progress bar redrawn in place (carriage return), shown once a run has lasted
    `delay` seconds, so that short runs print nothing.

    Call it as a ``progress`` callback: ``bar(done, total)``, or ``bar(done, total,
    blocks)`` as :func:`penedge.generate` does; then :meth:`close` it.

    Parameters
    ----------
    stream : text file
        Where to draw (a terminal: stderr).
    label : str
        Text before the bar.
    unit : str, default ""
        What is counted (``"planes"``), written after ``done/total``.
    delay : float, default 1.0
        Seconds before the bar first shows.
    clock : callable, default time.monotonic
        The time in seconds (replaceable in tests).
    width : int, default 30
        Characters of the bar.
    """

    def __init__(
        self,
        stream: TextIO,
        label: str,
        unit: str = "",
        delay: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
        width: int = 30,
    ) -> None:
        self.stream = stream
        self.label = label
        self.unit = unit
        self.delay = delay
        self.clock = clock
        self.width = width
        self.start = clock()
        self.shown = False
        self.length = 0

    def __call__(self, done: int, total: int, blocks: int | None = None) -> None:
        elapsed = self.clock() - self.start
        if elapsed < self.delay:
            return
        fraction = min(done / total, 1.0) if total else 1.0
        filled = round(fraction * self.width)
        bar = "#" * filled + "." * (self.width - filled)
        count = f"{done}/{total} {self.unit}".rstrip()
        if blocks is not None:
            count += f", {blocks} blocks"
        line = f"{self.label} [{bar}] {100 * fraction:3.0f}%  {count}, {elapsed:.0f} s"
        self.length = redraw(self.stream, line, self.length)
        self.shown = True

    def close(self) -> None:
        """Ends the bar's line (when it was shown)."""
        self.shown = end_line(self.stream, self.shown)


def redraw(stream: TextIO, line: str, previous: int) -> int:
    """Draws `line` over the previous one (of length `previous`); returns its length."""
    pad = " " * max(previous - len(line), 0)  # wipe what a longer line left
    stream.write(f"\r{line}{pad}")
    stream.flush()
    return len(line)


def end_line(stream: TextIO, shown: bool) -> bool:
    """Ends a redrawn line if one was `shown`; returns False (nothing shown any more)."""
    if shown:
        stream.write("\n")
        stream.flush()
    return False


class Activity:
    """``label ... 3 s`` on one line, redrawn every `interval` seconds by a background
    thread while a step whose progress cannot be counted runs (reading a large file,
    drawing a picture); shown only once the step has lasted `delay` seconds.

    Use it as a context manager::

        with Activity(sys.stderr, "penedge show: drawing blocks.png"):
            draw()
    """

    def __init__(
        self, stream: TextIO, label: str, delay: float = 1.0, interval: float = 0.5
    ) -> None:
        self.stream = stream
        self.label = label
        self.delay = delay
        self.interval = interval
        self.shown = False
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._start = 0.0

    def _draw(self) -> None:
        elapsed = time.monotonic() - self._start
        self.stream.write(f"\r{self.label} ... {elapsed:.0f} s")
        self.stream.flush()
        self.shown = True

    def _run(self) -> None:
        if not self.shown:  # not drawn on entering: once the step has lasted `delay`
            if self._stop.wait(self.delay):
                return
            self._draw()
        while not self._stop.wait(self.interval):
            self._draw()

    def __enter__(self) -> Activity:
        self._start = time.monotonic()
        if self.delay <= 0:  # at once, before the step can end (not left to the thread)
            self._draw()
        self._thread.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self._stop.set()
        self._thread.join()
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()


class _Silent:
    """An :class:`Activity` that shows nothing."""

    def __enter__(self) -> _Silent:
        return self

    def __exit__(self, *exc: object) -> None:
        return None


def activity(show: bool, label: str) -> Activity | _Silent:
    """An :class:`Activity` on stderr when `show`, else a context that does nothing."""
    return Activity(sys.stderr, label) if show else _Silent()


def accepts_progress(function: Callable[..., Any]) -> bool:
    """Whether `function` takes a ``progress=`` callback (newer bindings of
    :meth:`penedge.BlockSystem.detect` do)."""
    try:
        return "progress" in inspect.signature(function).parameters
    except (TypeError, ValueError):
        return False


def detect(system: Any, show: bool, label: str, **options: Any) -> Any:
    """``system.detect(**options)``, with a progress bar on stderr when `show` (an
    elapsed-time line where the bindings take no ``progress=`` callback)."""
    if not show:
        return system.detect(**options)
    if accepts_progress(system.detect):
        bar = ProgressBar(sys.stderr, label)
        try:
            return system.detect(**options, progress=bar)
        finally:
            bar.close()
    with Activity(sys.stderr, label):
        return system.detect(**options)


class StatusLine:
    """One line of status redrawn in place (carriage return), for runs whose length is not
    known in advance (a simulation solving to equilibrium); shown once the run has lasted
    `delay` seconds, at most every `interval` seconds.

    Call :meth:`show` with the text as often as wanted, then :meth:`close`.
    """

    def __init__(
        self,
        stream: TextIO,
        delay: float = 1.0,
        interval: float = 0.2,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.stream = stream
        self.delay = delay
        self.interval = interval
        self.clock = clock
        self.start = clock()
        self.last = -float("inf")
        self.length = 0
        self.shown = False

    def show(self, text: str, force: bool = False) -> None:
        """Redraws the line with `text` (unless drawn less than `interval` ago)."""
        now = self.clock()
        if now - self.start < self.delay or (now - self.last < self.interval and not force):
            return
        self.last = now
        self.length = redraw(self.stream, text, self.length)
        self.shown = True

    def close(self) -> None:
        """Ends the line (when it was shown)."""
        self.shown = end_line(self.stream, self.shown)
