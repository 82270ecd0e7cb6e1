"""Running the ``penedge`` command in a subprocess, for the end-to-end tests."""

from __future__ import annotations

import os
import subprocess
import sys


def run(*args, cwd, command=None, timeout=300):
    """Run ``penedge ARGS`` (``python -m penedge`` unless `command` is given) with warnings
    as errors; returns the completed process."""
    command = command or [sys.executable, "-m", "penedge"]
    env = {**os.environ, "PYTHONWARNINGS": "error"}
    return subprocess.run(
        [*command, *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=timeout,
        check=False,
    )


def squeeze(text):
    """The lines of `text` with runs of spaces collapsed (tables compare as words)."""
    return [" ".join(line.split()) for line in text.splitlines()]
