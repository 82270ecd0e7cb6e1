"""Whole-system detection as DEM codes call it: arrays that match the pair query, threads,
progress reports, and stopping a long run (exception in the callback, Ctrl-C)."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import penedge

from cli_run import default_sigint, stop

SPEC = {
    "domain": {"type": "box", "min": [0, 0, 0], "max": [6, 6, 6]},
    "joints": [
        {"type": "set", "dip": 30, "dip_direction": 40, "spacing": 1.1},
        {"type": "set", "dip": 70, "dip_direction": 150, "spacing": 1.3},
        {"type": "set", "dip": 85, "dip_direction": 280, "spacing": 1.7},
    ],
}


@pytest.fixture(scope="module")
def jointed():
    system, _report = penedge.generate(SPEC)
    return system


def test_named_type_constants_are_the_codes_of_the_types_array():
    names = [name.upper().replace("-", "_") for name in penedge.CONTACT_TYPES]
    assert [getattr(penedge, n) for n in names] == list(range(1, 8))
    found = penedge.paper_example(3).detect()
    assert int(np.sum(found.types == penedge.FACE_FACE)) == 42
    assert int(np.sum(found.types == penedge.VERTEX_VERTEX)) == 205


def test_system_arrays_match_the_pair_query_on_every_pair(jointed):
    """Brute force over all pairs with the pair query: the system's arrays list exactly the
    touching pairs, with the same types, and the penetrating ones."""
    blocks = [jointed[i] for i in range(len(jointed))]
    assert len(blocks) > 60
    found = jointed.detect()
    touching, types, penetrating = [], [], []
    for i in range(len(blocks)):
        for j in range(i + 1, len(blocks)):
            r = penedge.detect_pair(blocks[i], blocks[j])
            if r.touching:
                touching.append((i, j))
                types.append(r.type_code)
            elif r.type_code == penedge.PENETRATING:
                penetrating.append((i, j))
    assert found.pairs.shape == (len(touching), 2)
    assert found.pairs.tolist() == [list(p) for p in touching]
    assert found.types.tolist() == types
    assert found.penetrating.tolist() == [list(p) for p in penetrating]
    assert found.pairs.dtype == np.int64
    assert found.types.dtype == np.int8


@pytest.mark.parametrize("geometry", [False, True])
def test_any_number_of_threads_gives_the_same_arrays(jointed, geometry):
    runs = [jointed.detect(geometry=geometry, threads=t) for t in (1, 2, 3)]
    for other in runs[1:]:
        for name in ("pairs", "types", "feature_kinds", "feature_ids", "penetrating"):
            assert np.array_equal(getattr(runs[0], name), getattr(other, name)), name
        if geometry:
            for name in ("normals", "distances", "areas", "point_offsets", "points"):
                assert np.array_equal(getattr(runs[0], name), getattr(other, name)), name


@pytest.mark.parametrize("threads", [0, -2, 1025])
def test_impossible_thread_counts_are_input_errors(jointed, threads):
    with pytest.raises(penedge.InputError, match="threads must be from 1 to 1024"):
        jointed.detect(threads=threads)


def test_progress_reports_reach_the_total(jointed):
    calls = []
    jointed.detect(progress=lambda done, total: calls.append((done, total)))
    assert calls, "no progress report"
    done, total = calls[-1]
    assert done == total > 0
    assert all(t == total for _, t in calls)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_an_exception_in_the_progress_callback_stops_the_run(jointed):
    class StopError(Exception):
        pass

    def stop(done, total):
        raise StopError(f"{done}/{total}")

    for geometry in (False, True):
        with pytest.raises(StopError):
            jointed.detect(geometry=geometry, progress=stop)


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_long_detection_cleanly():
    """A child times one detection of a 40^3 grid (about a second on one thread), then
    detects it again and again; SIGINT a tenth of a detection into the next one makes it
    raise KeyboardInterrupt within half a detection, not at the end of the call. The
    timing is the child's own, so a fast or a loaded machine changes nothing."""
    script = textwrap.dedent(
        """
        import sys, time
        import penedge
        n = 40
        system = penedge.BlockSystem.from_box_cut(
            [0, 0, 0], [n, n, n],
            [[1, 0, 0]] * (n - 1) + [[0, 1, 0]] * (n - 1) + [[0, 0, 1]] * (n - 1),
            list(range(1, n)) * 3,
        )
        start = time.monotonic()
        system.detect(geometry=True, threads=1)
        print("ready", time.monotonic() - start, flush=True)
        try:
            for _ in range(100):
                system.detect(geometry=True, threads=1)
        except KeyboardInterrupt:
            print("interrupted", time.monotonic(), flush=True)
            sys.exit(0)
        print("completed", flush=True)
        sys.exit(1)
        """
    )
    child = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
        preexec_fn=default_sigint,
    )
    try:
        word, once = child.stdout.readline().split()
        assert word == "ready"
        once = float(once)
        time.sleep(0.1 * once)  # inside the next detection (800,000 pairs)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, err = child.communicate(timeout=60 + 100 * once)
    finally:
        stop(child)
    assert child.returncode == 0, out + err
    stopped = float(out.split()[-1])
    # The binding looks for signals every 0.1 s: within half a run, and never asked below 0.3 s.
    bound = max(0.5 * once, 0.3)
    assert stopped - sent < bound, f"took {stopped - sent:.2f} s to stop ({once:.2f} s a run)"


def rotate(q, v):
    """Rotates rows `v` by unit quaternion `q` = (x, y, z, w)."""
    u, w = np.asarray(q[:3]), q[3]
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def test_contact_tracker_matches_a_full_detection_step_by_step(jointed):
    blocks = [jointed[i] for i in range(len(jointed))]
    tracker = penedge.ContactTracker(jointed, skin=0.2)
    first = jointed.detect()
    assert np.array_equal(tracker.contacts.pairs, first.pairs)
    assert np.array_equal(tracker.contacts.types, first.types)
    rng = np.random.default_rng(3)
    n = len(blocks)
    for step, size in enumerate([1e-3, 1e-6, 1e-6, 0.3]):
        axes = rng.normal(size=(n, 3))
        axes /= np.linalg.norm(axes, axis=1)[:, None]
        half = 0.5 * size * rng.uniform(-1, 1, n)
        rotations = np.column_stack([axes * np.sin(half)[:, None], np.cos(half)])
        translations = size * rng.uniform(-1, 1, (n, 3))
        report = tracker.update(rotations, translations)
        assert report["rebuilt"] == (size > 0.1), (step, report)
        parts = report["unmoved"] + report["certified"] + report["queried"]
        assert parts == report["candidate_pairs"]
        moved = penedge.BlockSystem(
            [
                penedge.Block(rotate(r, b.vertices) + t, b.faces)
                for b, r, t in zip(blocks, rotations, translations, strict=True)
            ]
        )
        expected = moved.detect()
        for name in ("pairs", "types", "penetrating"):
            assert np.array_equal(getattr(tracker.contacts, name), getattr(expected, name)), (
                step,
                name,
            )


def test_contact_tracker_refuses_bad_poses_and_keeps_its_state(jointed):
    tracker = penedge.ContactTracker(jointed, skin=0.1)
    n = len(jointed)
    before = tracker.contacts.pairs.copy()
    identity = np.tile([0.0, 0.0, 0.0, 1.0], (n, 1))
    with pytest.raises(penedge.InputError, match=r"shape \(n, 4\)"):
        tracker.update(np.zeros((n, 3)), np.zeros((n, 3)))
    with pytest.raises(penedge.InputError, match="rotations but"):
        tracker.update(identity[:-1], np.zeros((n, 3)))
    bad = np.zeros((n, 3))
    bad[4, 1] = np.nan
    with pytest.raises(penedge.InputError, match="pose 4"):
        tracker.update(identity, bad)
    zero = identity.copy()
    zero[2] = 0.0
    with pytest.raises(penedge.InputError, match="pose 2"):
        tracker.update(zero, np.zeros((n, 3)))
    with pytest.raises(penedge.InputError, match="skin"):
        penedge.ContactTracker(jointed, skin=-1.0)
    assert np.array_equal(tracker.contacts.pairs, before)
