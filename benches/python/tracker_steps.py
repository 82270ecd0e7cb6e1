"""Times `penedge.ContactTracker.update` through the Python API (issue 18, "Updating contacts
cheaply"): the situation of the issue's measurements.

    python benches/python/tracker_steps.py [--grid 50] [--gap 1e-3] [--steps 3]

An ``n^3`` grid of unit cubes (default 50: 125,000 blocks) at a relative gap of 1e-3, where
every one of the 1,558,396 candidate pairs touches; a tracker with a skin of 0.05. Three
motions, ``steps`` updates each: every block jittered (a random rotation of up to 1e-5 rad
about its centroid and a shift of up to 1e-5 along each axis), 1 % of the blocks jittered
(drawn anew each step) and the others left, no block moved. Each update is timed
(wall clock, reading ``tracker.contacts`` not included: a DEM step that reads them pays one
conversion), beside ``BlockSystem.detect`` of the grid at its reference poses timed right
after it (built blocks, the same number of touching pairs; their placing not timed). At the
end, the tracker's contacts are checked equal to a full detection of the blocks at their
final poses. Prints a Markdown table (docs/benchmarks.md).
"""

import argparse
import os
import time

import numpy as np

import penedge


def quat_mul(p, q):
    """Hamilton products of quaternion rows (x, y, z, w)."""
    px, py, pz, pw = p.T
    qx, qy, qz, qw = q.T
    return np.column_stack(
        [
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
            pw * qw - px * qx - py * qy - pz * qz,
        ]
    )


def rotate(q, v):
    """Rows of `v` rotated by the quaternion rows `q`."""
    u, w = q[:, :3], q[:, 3:4]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def jitter(rng, rotations, translations, centroids, which, size):
    """Composes a random rigid step about each chosen block's current centroid."""
    k = len(which)
    axes = rng.normal(size=(k, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    half = 0.5 * size * rng.uniform(-1, 1, k)
    step = np.column_stack([axes * np.sin(half)[:, None], np.cos(half)])
    centre = rotate(rotations[which], centroids[which]) + translations[which]
    shift = size * rng.uniform(-1, 1, (k, 3))
    rotations[which] = quat_mul(step, rotations[which])
    translations[which] = rotate(step, translations[which] - centre) + centre + shift


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=50)
    parser.add_argument("--gap", type=float, default=1e-3)
    parser.add_argument("--steps", type=int, default=3)
    args = parser.parse_args()
    n = args.grid
    cubes = [
        penedge.Block.cuboid([x, y, z], [x + 1, y + 1, z + 1])
        for z in range(n)
        for y in range(n)
        for x in range(n)
    ]
    system = penedge.BlockSystem(cubes)
    start = time.perf_counter()
    full = system.detect(gap=args.gap)
    full_s = time.perf_counter() - start
    tracker = penedge.ContactTracker(system, skin=0.05, gap=args.gap)
    count = len(cubes)
    rotations = np.tile([0.0, 0.0, 0.0, 1.0], (count, 1))
    translations = np.zeros((count, 3))
    centroids = system.centroids
    rng = np.random.default_rng(18)
    print(
        f"{n}^3 grid, gap {args.gap:g}; load average at the start "
        f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}; full detection of the grid: "
        f"{full_s:.3f} s ({len(full.pairs)} contacts)\n"
    )
    print("| motion | step | unmoved | certified | queried | update s | full s | update / full |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for motion in ["every block jittered", "1 % of the blocks jittered", "no block moved"]:
        for k in range(1, args.steps + 1):
            if motion == "every block jittered":
                which = np.arange(count)
            elif motion.startswith("1 %"):
                which = rng.choice(count, count // 100, replace=False)
            else:
                which = np.arange(0)
            jitter(rng, rotations, translations, centroids, which, 1e-5)
            start = time.perf_counter()
            report = tracker.update(rotations, translations)
            update_s = time.perf_counter() - start
            start = time.perf_counter()
            system.detect(gap=args.gap)
            full_s = time.perf_counter() - start
            print(
                f"| {motion} | {k} | {report['unmoved']} | {report['certified']} | "
                f"{report['queried']} | {update_s:.3f} | {full_s:.3f} | {update_s / full_s:.2f} |"
            )
    moved = penedge.BlockSystem(
        [
            penedge.Block(rotate(np.tile(r, (8, 1)), b.vertices) + t, b.faces)
            for b, r, t in zip(cubes, rotations, translations, strict=True)
        ]
    )
    final = moved.detect(gap=args.gap)
    assert np.array_equal(tracker.contacts.pairs, final.pairs)
    assert np.array_equal(tracker.contacts.types, final.types)
    print(
        f"\nThe tracker's contacts equal a full detection at the final poses. Load average at "
        f"the end {' '.join(f'{x:.2f}' for x in os.getloadavg())}."
    )


if __name__ == "__main__":
    main()
