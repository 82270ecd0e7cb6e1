"""A one-line progress bar on stderr for long runs."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TextIO


class ProgressBar:
    """A progress bar redrawn in place (carriage return), shown once a run has lasted
    `delay` seconds, so that short runs print nothing.

    Call it as the ``progress`` callback of :func:`penedge.generate`
    (``bar(planes_done, planes_total, blocks)``), then :meth:`close` it.

    Parameters
    ----------
    stream : text file
        Where to draw (a terminal: stderr).
    label : str
        Text before the bar.
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
        delay: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
        width: int = 30,
    ) -> None:
        self.stream = stream
        self.label = label
        self.delay = delay
        self.clock = clock
        self.width = width
        self.start = clock()
        self.shown = False

    def __call__(self, done: int, total: int, blocks: int) -> None:
        elapsed = self.clock() - self.start
        if elapsed < self.delay:
            return
        fraction = done / total if total else 1.0
        filled = round(fraction * self.width)
        bar = "#" * filled + "." * (self.width - filled)
        line = (
            f"\r{self.label} [{bar}] {100 * fraction:3.0f}%  "
            f"{done}/{total} planes, {blocks} blocks, {elapsed:.0f} s"
        )
        self.stream.write(line)
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        """Ends the bar's line (when it was shown)."""
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()
            self.shown = False
