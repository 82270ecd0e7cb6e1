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


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def assert_png(path):
    """`path` is a PNG picture of more than 500 x 500 pixels that is not blank."""
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    from matplotlib.image import imread

    image = imread(path)
    assert image.shape[0] > 500
    assert image.shape[1] > 500
    assert image[..., :3].std() > 0.05  # not a blank picture


def table_counts(lines):
    """{type name: count} from the rows ``code type count`` of a printed table of contacts
    per type (lines as given by :func:`squeeze`)."""
    import penedge

    counts = {}
    for line in lines:
        words = line.split()
        if len(words) == 3 and words[0].isdigit() and words[1] in penedge.CONTACT_TYPES:
            counts[words[1]] = int(words[2])
    return counts


def default_sigint():
    """For ``Popen(preexec_fn=...)`` of a child that a test interrupts: SIGINT back to its
    default action. A shell that starts a job in the background (``cmd &``, ``nohup``) sets
    SIGINT to ignored, children inherit that, and Python then installs no KeyboardInterrupt
    handler: the child would run on through the test's Ctrl-C."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)


def stop(process):
    """Ends a child a test started (if it still runs) and reaps it: a killed child that is
    never waited for is reported as a ResourceWarning, an error under ``-W error``, on
    whichever test runs when it is collected."""
    if process.poll() is None:
        process.kill()
    process.wait()
