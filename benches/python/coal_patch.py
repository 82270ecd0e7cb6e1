"""Times coal's contact patch on the pairs of penedge's geometry benchmark.

The Rust bench writes the pairs (each block's body-frame vertices and faces, and its pose,
the same poses parry gets)::

    cargo run --release -p penedge-bench -- geometry --export pairs.json
    pip install coal            # coal 3 (the FCL successor), with numpy
    python benches/python/coal_patch.py pairs.json

Per pair, coal gets the same two blocks as `coal.Convex` shapes (body-frame vertices, faces
fanned into triangles) with `coal.Transform3s` poses, and runs:

* ``collide``: `coal.collide(geom_a, tf_a, geom_b, tf_b, request, result)` with
  `security_margin` set to penedge's absolute gap for the pair (so touching blocks collide) and
  one contact asked for;
* ``collide + patch``: the same, then `coal.computeContactPatch(geom_a, tf_a, geom_b, tf_b,
  result, patch_request, patch_result)` with coal's default `ContactPatchRequest` (one patch,
  patch tolerance 1e-3). The patch needs the collision's contact (its normal and point), so this
  is the cost of a contact patch for a pair, and the patch alone is the difference;
* the same two through the functors `coal.ComputeCollision` and `coal.ComputeContactPatch`,
  built once per pair before timing. A functor keeps its GJK solver, whose support function coal
  warm-starts from its previous call (here: the previous round on the same pair);
* one trivial bound call per pair (`result.isCollision()`): the floor that the Python loop and
  one Boost.Python call add to every row, which a C++ caller does not pay.

Times are CPU time of this thread (`time.thread_time_ns`), median of interleaved rounds,
with the same cold (every pair once per round) and hot (the first `hot` pairs, warmed up and
looped) windows as the Rust bench. Prints Markdown tables (see docs/benchmarks.md).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

try:
    import coal
except ImportError:  # pragma: no cover - reported to the user
    sys.exit("coal is not installed: pip install coal")

NORMAL_AGREE = 1e-6  # two unit normals closer than this agree
TOUCH = 1e-9  # a distance within this of 0 is touching
AREA_AGREE = 1e-9  # relative difference of two areas that agree


def rotation_matrix(q: list[float]) -> np.ndarray:
    """The rotation matrix of the unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def convex(block: dict) -> coal.Convex:
    """The block as a coal convex shape in its body frame, faces fanned into triangles."""
    points = coal.StdVec_Vec3s()
    for v in block["vertices"]:
        points.append(np.array(v, dtype=float))
    triangles = coal.StdVec_Triangle()
    for face in block["faces"]:
        for k in range(1, len(face) - 1):
            triangles.append(coal.Triangle(face[0], face[k], face[k + 1]))
    return coal.Convex(points, triangles)


def transform(block: dict) -> coal.Transform3s:
    return coal.Transform3s(
        rotation_matrix(block["rotation"]), np.array(block["translation"], dtype=float)
    )


class Pair:
    """One pair, ready for coal: shapes, poses, requests, results and functors."""

    def __init__(self, pair: dict, patch_tolerance: float):
        self.data = pair
        self.a, self.b = convex(pair["a"]), convex(pair["b"])
        self.tf_a, self.tf_b = transform(pair["a"]), transform(pair["b"])
        self.request = coal.CollisionRequest()
        self.request.security_margin = pair["gap"]
        self.result = coal.CollisionResult()
        self.patch_request = coal.ContactPatchRequest()
        self.patch_request.setPatchTolerance(patch_tolerance)
        self.patch_result = coal.ContactPatchResult(self.patch_request)
        self.collide = coal.ComputeCollision(self.a, self.b)
        self.patch = coal.ComputeContactPatch(self.a, self.b)


def call_floor(pairs: list[Pair]) -> None:
    for p in pairs:
        p.result.isCollision()


def collide_free(pairs: list[Pair]) -> None:
    for p in pairs:
        coal.collide(p.a, p.tf_a, p.b, p.tf_b, p.request, p.result)


def collide_patch_free(pairs: list[Pair]) -> None:
    for p in pairs:
        coal.collide(p.a, p.tf_a, p.b, p.tf_b, p.request, p.result)
        coal.computeContactPatch(
            p.a, p.tf_a, p.b, p.tf_b, p.result, p.patch_request, p.patch_result
        )


def collide_functor(pairs: list[Pair]) -> None:
    for p in pairs:
        p.collide(p.tf_a, p.tf_b, p.request, p.result)


def collide_patch_functor(pairs: list[Pair]) -> None:
    for p in pairs:
        p.collide(p.tf_a, p.tf_b, p.request, p.result)
        p.patch(p.tf_a, p.tf_b, p.result, p.patch_request, p.patch_result)


ENGINES = [call_floor, collide_free, collide_patch_free, collide_functor, collide_patch_functor]


def polygon_area(points: list[np.ndarray], normal: np.ndarray) -> float:
    """Area of a planar polygon (vertices in order) with unit normal `normal`."""
    total = np.zeros(3)
    for i, p in enumerate(points):
        total += np.cross(p, points[(i + 1) % len(points)])
    return 0.5 * abs(float(np.dot(total, normal)))


def distance_ok(situation: str, d: float, penetration: float) -> bool:
    if "penetrating" in situation:
        return TOUCH < abs(d) <= penetration + TOUCH
    return abs(d) <= TOUCH


def check(situation: str, pairs: list[Pair], penetration: float) -> dict:
    """Runs collide + patch once on every pair and compares with penedge's geometry."""
    c = dict(collision=0, patch=0, points=0, normal=0, distance=0, area=0, faces=0, worst=0.0)
    for p in pairs:
        coal.collide(p.a, p.tf_a, p.b, p.tf_b, p.request, p.result)
        if not p.result.isCollision():
            continue
        c["collision"] += 1
        contact = p.result.getContact(0)
        c["distance"] += distance_ok(situation, contact.penetration_depth, penetration)
        coal.computeContactPatch(
            p.a, p.tf_a, p.b, p.tf_b, p.result, p.patch_request, p.patch_result
        )
        if p.patch_result.numContactPatches() == 0:
            continue
        patch = p.patch_result.getContactPatch(0)
        c["patch"] += 1
        c["points"] += patch.size()
        mine = p.data["penedge"]
        if "normal" not in mine:
            continue
        normal = np.asarray(patch.getNormal())
        c["normal"] += float(np.linalg.norm(normal - np.array(mine["normal"]))) <= NORMAL_AGREE
        if mine["type"] == "face-face" and patch.size() >= 3:
            c["faces"] += 1
            points = [np.asarray(patch.getPoint(i)) for i in range(patch.size())]
            difference = abs(polygon_area(points, normal) - mine["area"]) / mine["area"]
            c["area"] += difference <= AREA_AGREE
            c["worst"] = max(c["worst"], difference)
    return c


def timed(pass_fn, window: list[Pair], loops: int, warm: bool) -> float:
    if warm:
        pass_fn(window)
    start = time.thread_time_ns()
    for _ in range(loops):
        pass_fn(window)
    return (time.thread_time_ns() - start) / (len(window) * loops)


def measure(jobs: list[tuple[list[Pair], int, bool]], reps: int) -> list[list[float]]:
    """Median ns per pair of each engine on each job (window, loops, warm)."""
    samples = [[[] for _ in ENGINES] for _ in jobs]
    for rep in range(reps + 1):
        for job, s in zip(jobs, samples, strict=True):
            for engine, column in zip(ENGINES, s, strict=True):
                t = timed(engine, *job)
                if rep > 0:
                    column.append(t)
    return [[statistics.median(column) for column in s] for s in samples]


def load() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "unknown"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pairs", help="JSON file from `penedge-bench geometry --export`")
    parser.add_argument("--reps", type=int, default=21)
    parser.add_argument("--hot", type=int, help="hot window (default: the file's)")
    parser.add_argument("--limit", type=int, help="use only the first N pairs of each set")
    parser.add_argument(
        "--patch-tolerance", type=float, default=1e-3, help="coal's patch tolerance"
    )
    args = parser.parse_args()

    data = json.loads(Path(args.pairs).read_text())
    if data.get("format") != "penedge-bench pairs 1":
        sys.exit(f"{args.pairs}: not a penedge-bench pairs file")
    hot = args.hot or data["hot"]
    penetration = data["penetration"]
    sets = []
    for s in data["sets"]:
        raw = s["pairs"][: args.limit] if args.limit else s["pairs"]
        sets.append((s, [Pair(p, args.patch_tolerance) for p in raw]))

    n = len(sets[0][1])
    print("## coal contact patch (Python bindings)\n")
    print(
        f"coal {coal.__version__}, Python {platform.python_version()}, numpy {np.__version__}; "
        f"{n} pairs per row from {Path(args.pairs).name} (seed {data['seed']}); "
        f"{os.cpu_count()} logical CPUs; patch tolerance {args.patch_tolerance:g}."
    )
    print(f"Times are CPU time of this thread. Load average at the start: {load()}.\n")

    print("### Answers\n")
    print(
        "| situation | family | pairs | collision | coal distance as expected | patch "
        "| same normal as penedge (1e-6) | face-face area as penedge (1e-9 rel.) "
        "| largest relative area difference | patch points/pair |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for s, pairs in sets:
        c = check(s["situation"], pairs, penetration)
        area = f"{c['area']} of {c['faces']}" if c["faces"] else "n/a"
        worst = f"{c['worst']:.1e}" if c["faces"] else "n/a"
        print(
            f"| {s['situation']} | {s['family']} | {len(pairs)} | {c['collision']} "
            f"| {c['distance']} | {c['patch']} | {c['normal']} | {area} | {worst} "
            f"| {c['points'] / len(pairs):.2f} |"
        )

    modes = [
        ("cold: all pairs once per round", lambda ps: (ps, 1, False)),
        (
            f"hot: the first {hot} pairs, warmed up and looped",
            lambda ps: (ps[:hot], math.ceil(len(ps) / min(hot, len(ps))), True),
        ),
    ]
    jobs = [make(pairs) for _, make in modes for _, pairs in sets]
    medians = measure(jobs, args.reps)
    for k, (caption, _) in enumerate(modes):
        print(f"\n### ns per pair, median of {args.reps} rounds ({caption})\n")
        print(
            "| situation | family | one bound call (floor) | `collide` "
            "| `collide` + `computeContactPatch` | patch (difference) "
            "| functors: `collide` | functors: `collide` + patch | functors: patch (difference) |"
        )
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
        rows = medians[k * len(sets) : (k + 1) * len(sets)]
        for (s, _), (floor, collide, both, f_collide, f_both) in zip(sets, rows, strict=True):
            print(
                f"| {s['situation']} | {s['family']} | {floor:.0f} | {collide:.0f} "
                f"| {both:.0f} | {both - collide:.0f} | {f_collide:.0f} | {f_both:.0f} "
                f"| {f_both - f_collide:.0f} |"
            )
    print(f"\nLoad average at the end: {load()}.")


if __name__ == "__main__":
    main()
