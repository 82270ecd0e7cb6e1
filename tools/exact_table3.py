#!/usr/bin/env python3
"""Exact (rational) count of the contact types of the paper's Table 3.

Independent of the penedge engine: standard library only, every number a
``fractions.Fraction``, no tolerance anywhere.

Conventions
-----------
* A plane is ``(a, b, c, d)`` with rational coefficients: the points with
  ``a x + b y + c z = d``.  A halfspace is the same tuple read as
  ``a x + b y + c z <= d`` (the normal ``(a, b, c)`` points outward).
* The cube is ``[0, 10]^3``.  A block is the set of points of the cube on one
  closed side of every cutting plane; it is named by those sides
  (``x<5,y>5,z+x<10``).
* A polytope is computed as its vertex set: every triple of its distinct
  planes with a unique common point gives a candidate; the candidates that
  satisfy every halfspace are the vertices (each has three independent tight
  constraints, so it is an extreme point).
* A block's faces are its distinct supporting planes whose vertices span a
  plane (affine dimension 2); a plane that only touches it at an edge or a
  vertex is not a face.
* The smallest feature of a block that holds a set S is the intersection of
  the block's faces containing all of S; with r the rank of their normals it
  is a vertex (r = 3), an edge (2), a face (1) or the interior (0).

Usage: ``python3 tools/exact_table3.py`` (report), ``--json`` (counts only),
``--all`` (report plus every pair), ``--dev-cases crates/penedge/tests/data/dev-cases.json``
(the same classifier on the exact dev cases).
"""

from __future__ import annotations

import argparse
import json
import math
from collections import Counter
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cache
from itertools import combinations, product

SIZE = 10

TYPES = (
    "vertex-vertex",
    "vertex-edge",
    "edge-edge",
    "edge-edge-superposition",
    "vertex-face",
    "edge-face",
    "face-face",
)

# The paper's Table 3 (Chen et al. 2004), columns Fig. 9, 10, 11.
PAPER = {
    "example1": (8, (4, 0, 0, 12, 0, 0, 12)),
    "example2": (8, (4, 0, 0, 4, 0, 0, 20)),
    "example3": (26, (205, 0, 0, 78, 0, 0, 42)),
}

# Cutting planes: (label, normal, offset) for the plane normal . p = offset.
AXIS_PLANES = (("x", (1, 0, 0), 5), ("y", (0, 1, 0), 5), ("z", (0, 0, 1), 5))
DIAG_PLANES = (("x+y", (1, 1, 0), 10), ("y+z", (0, 1, 1), 10), ("z+x", (1, 0, 1), 10))
EXAMPLES = {
    "example1": AXIS_PLANES,
    "example2": DIAG_PLANES,
    "example3": AXIS_PLANES + DIAG_PLANES,
}

FEATURE_BY_RANK = {0: "interior", 1: "face", 2: "edge", 3: "vertex"}
FEATURE_ORDER = ("vertex", "edge", "face", "interior")


# ----------------------------------------------------------------- algebra


def det3(r0, r1, r2):
    """Determinant of the 3x3 matrix with rows r0, r1, r2."""
    return (
        r0[0] * (r1[1] * r2[2] - r1[2] * r2[1])
        - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0])
        + r0[2] * (r1[0] * r2[1] - r1[1] * r2[0])
    )


def rank(vectors):
    """Rank of a list of 3-vectors (exact Gaussian elimination)."""
    rows = [[Fraction(x) for x in v] for v in vectors]
    r = 0
    for col in range(3):
        pivot = next((i for i in range(r, len(rows)) if rows[i][col] != 0), None)
        if pivot is None:
            continue
        rows[r], rows[pivot] = rows[pivot], rows[r]
        for i in range(r + 1, len(rows)):
            f = rows[i][col] / rows[r][col]
            rows[i] = [a - f * b for a, b in zip(rows[i], rows[r])]
        r += 1
    return r


def affine_dim(points):
    """Affine dimension of a point set: -1 empty, 0 point, ... 3 solid."""
    pts = list(points)
    if not pts:
        return -1
    p0 = pts[0]
    return rank([tuple(a - b for a, b in zip(p, p0)) for p in pts[1:]])


def dot(n, p):
    return n[0] * p[0] + n[1] * p[1] + n[2] * p[2]


def sub(p, q):
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


@cache
def canonical(h):
    """The plane of halfspace h, scaled so its first nonzero coefficient is 1."""
    lead = next(x for x in h[:3] if x != 0)
    return tuple(Fraction(x) / lead for x in h)


@cache
def solve3(p0, p1, p2):
    """The common point of three canonical planes, or None if not unique."""
    rows = (p0[:3], p1[:3], p2[:3])
    rhs = (p0[3], p1[3], p2[3])
    det = det3(*rows)
    if det == 0:
        return None
    cols = list(zip(*rows))
    point = []
    for k in range(3):
        c = list(cols)
        c[k] = rhs
        point.append(det3(*zip(*c)) / det)
    return tuple(point)


def polytope_vertices(halfspaces):
    """Vertices of the polytope {p : a.p <= d for every (a, b, c, d)}."""
    planes = sorted({canonical(h) for h in halfspaces})
    found = set()
    for triple in combinations(planes, 3):
        p = solve3(*triple)
        if p is not None and all(inside(h, p) for h in halfspaces):
            found.add(p)
    return found


@cache
def inside(h, p):
    """Whether point p satisfies halfspace h (memoised: the pool of both is small)."""
    return dot(h, p) <= h[3]


# ------------------------------------------------------------------ blocks


@dataclass
class Block:
    """A convex cell: its name, halfspaces, vertices and faces."""

    name: str
    halfspaces: list
    vertices: frozenset
    faces: list = field(default_factory=list)  # (outward normal, offset, vertices on it)
    volume: Fraction = Fraction(0)
    centroid: tuple = ()


def cube_halfspaces():
    hs = []
    for axis in range(3):
        e = [0, 0, 0]
        e[axis] = 1
        hs.append((-e[0], -e[1], -e[2], 0))
        hs.append((e[0], e[1], e[2], SIZE))
    return hs


def side_halfspace(normal, offset, below):
    """The closed side n.p <= offset (below) or n.p >= offset."""
    if below:
        return (*normal, offset)
    return (-normal[0], -normal[1], -normal[2], -offset)


def block_faces(halfspaces, vertices):
    """Faces: distinct supporting planes whose vertices span a plane."""
    faces, seen = [], set()
    for h in halfspaces:
        key = canonical(h)
        if key in seen:
            continue
        on = frozenset(v for v in vertices if dot(h, v) == h[3])
        if affine_dim(on) == 2:
            seen.add(key)
            faces.append((h[:3], h[3], on))
    return faces


def volume_and_centroid(vertices, faces):
    """Exact volume and centroid: tetrahedra (inner point, face centre, edge)."""
    p0 = mean(vertices)
    vol, moment = Fraction(0), [Fraction(0)] * 3
    for i, (_, _, on) in enumerate(faces):
        c = mean(on)
        for j, (_, _, other) in enumerate(faces):
            edge = on & other
            if i == j or len(edge) != 2:
                continue
            u, v = tuple(edge)
            t = abs(det3(sub(u, p0), sub(v, p0), sub(c, p0))) / 6
            vol += t
            for k in range(3):
                moment[k] += t * (p0[k] + c[k] + u[k] + v[k]) / 4
    return vol, tuple(m / vol for m in moment)


def mean(points):
    pts = list(points)
    return tuple(sum(p[k] for p in pts) / len(pts) for k in range(3))


def build_blocks(cuts):
    """All solid cells of the cube cut by the planes `cuts`."""
    blocks = []
    for signs in product((True, False), repeat=len(cuts)):
        hs = cube_halfspaces()
        names = []
        for (label, normal, offset), below in zip(cuts, signs):
            hs.append(side_halfspace(normal, offset, below))
            names.append(f"{label}{'<' if below else '>'}{offset}")
        verts = polytope_vertices(hs)
        if affine_dim(verts) < 3:
            continue
        block = Block(",".join(names), hs, frozenset(verts))
        block.faces = block_faces(hs, verts)
        block.volume, block.centroid = volume_and_centroid(verts, block.faces)
        blocks.append(block)
    return blocks


# ---------------------------------------------------------------- contacts


@dataclass
class Contact:
    """The exact intersection of a pair and its contact type."""

    a: int
    b: int
    dim: int
    vertices: list
    features: tuple
    kind: str


def feature(block, points):
    """Smallest feature of `block` holding every point of `points`."""
    normals = [n for n, d, _ in block.faces if all(dot(n, p) == d for p in points)]
    return FEATURE_BY_RANK[min(rank(normals), 3)]


def contact_type(fa, fb, dim):
    """Type from the two features and the dimension of A ∩ B."""
    if dim < 0:
        return "separated"
    if dim == 3:
        return "penetrating"
    pair = tuple(sorted((fa, fb), key=FEATURE_ORDER.index))
    table = {
        ("vertex", "vertex"): "vertex-vertex",
        ("vertex", "edge"): "vertex-edge",
        ("vertex", "face"): "vertex-face",
        ("edge", "face"): "edge-face",
        ("face", "face"): "face-face",
        ("edge", "edge"): "edge-edge" if dim == 0 else "edge-edge-superposition",
    }
    return table.get(pair, f"other({pair[0]},{pair[1]},dim {dim})")


def classify_pair(blocks, i, j):
    a, b = blocks[i], blocks[j]
    verts = sorted(polytope_vertices(a.halfspaces + b.halfspaces))
    dim = affine_dim(verts)
    fa = feature(a, verts) if verts else None
    fb = feature(b, verts) if verts else None
    return Contact(i, j, dim, verts, (fa, fb), contact_type(fa, fb, dim))


def classify_all(blocks):
    return [classify_pair(blocks, i, j) for i, j in combinations(range(len(blocks)), 2)]


def count_types(contacts):
    counts = {t: 0 for t in TYPES}
    for c in contacts:
        counts[c.kind] = counts.get(c.kind, 0) + 1
    return counts


# ---------------------------------------------------------------- symmetry


def rotate(p):
    """The cyclic map x -> y -> z -> x: the point (x, y, z) goes to (z, x, y)."""
    return (p[2], p[0], p[1])


def swap_xy(p):
    """The mirror x <-> y."""
    return (p[1], p[0], p[2])


def invert(p):
    """The point reflection through the cube's centre."""
    return tuple(SIZE - x for x in p)


# Generators: the cyclic group of order 3, and the cube symmetries that keep
# every example (coordinate permutations and the central inversion, order 12).
GROUPS = {
    "cyclic x->y->z->x": (rotate,),
    "permutations + inversion": (rotate, swap_xy, invert),
}


def block_permutation(blocks, f):
    """Index of the image of each block under map f, or None if f is not a symmetry."""
    index = {b.vertices: k for k, b in enumerate(blocks)}
    image = [index.get(frozenset(f(v) for v in b.vertices)) for b in blocks]
    return None if None in image else image


def pair_orbits(contacts, perms):
    """Orbits of pairs under the group generated by `perms`: {type: [orbit sizes]}."""
    by_pair = {(c.a, c.b): c for c in contacts}
    seen, orbits = set(), {}
    for c in contacts:
        if (c.a, c.b) in seen:
            continue
        orbit, todo = {(c.a, c.b)}, [(c.a, c.b)]
        while todo:
            a, b = todo.pop()
            for perm in perms:
                image = tuple(sorted((perm[a], perm[b])))
                if image not in orbit:
                    orbit.add(image)
                    todo.append(image)
        kinds = {by_pair[p].kind for p in orbit}
        assert kinds == {c.kind}, f"type not invariant on orbit {sorted(orbit)}: {kinds}"
        seen |= orbit
        orbits.setdefault(c.kind, []).append(len(orbit))
    return orbits


def symmetry_report(blocks, contacts):
    """For each group: (fixed block names, orbits by type), or None if not a symmetry."""
    out = {}
    for name, gens in GROUPS.items():
        perms = [block_permutation(blocks, f) for f in gens]
        if None in perms:
            out[name] = None
            continue
        fixed = [b.name for k, b in enumerate(blocks) if all(p[k] == k for p in perms)]
        out[name] = (fixed, pair_orbits(contacts, perms))
    return out


# ------------------------------------------------------------------ report


def fmt(x):
    return str(x.numerator) if x.denominator == 1 else f"{x.numerator}/{x.denominator}"


def fmt_point(p):
    return "(" + ", ".join(fmt(Fraction(x)) for x in p) + ")"


def planes_holding(block, points, cuts):
    """Labels of the cutting planes (or cube faces) that are faces holding `points`."""
    labels = []
    for n, d, _ in block.faces:
        if all(dot(n, p) == d for p in points):
            labels.append(plane_label(n, d, cuts))
    return ", ".join(labels)


def plane_label(n, d, cuts):
    for label, normal, offset in cuts:
        if canonical((*n, d)) == canonical((*normal, offset)):
            return f"{label}={offset}"
    axis = "xyz"[[abs(x) for x in n].index(1)]
    return f"{axis}={fmt(Fraction(abs(d)))}"


def wedge_angle(block, points):
    """Interior dihedral angle (degrees, float: display only) of block at the edge
    holding `points`: 180 minus the angle of the two outward face normals."""
    ns = [n for n, d, _ in block.faces if all(dot(n, p) == d for p in points)]
    if len(ns) != 2:
        return None
    n1, n2 = ns
    cos = float(dot(n1, n2)) / math.sqrt(float(dot(n1, n1) * dot(n2, n2)))
    return 180 - math.degrees(math.acos(cos))


def describe_pair(blocks, c, cuts):
    a, b = blocks[c.a], blocks[c.b]
    pts = " ".join(fmt_point(p) for p in c.vertices)
    text = (
        f"    #{c.a} {a.name}  centroid {fmt_point(a.centroid)}\n"
        f"    #{c.b} {b.name}  centroid {fmt_point(b.centroid)}\n"
        f"      A∩B dim {c.dim}, vertices {pts}; features {c.features[0]}/{c.features[1]};"
        f" on {planes_holding(a, c.vertices, cuts) or '-'}"
    )
    if c.kind == "edge-edge-superposition":
        angles = [wedge_angle(blk, c.vertices) for blk in (a, b)]
        text += "; wedge angles " + "/".join("?" if x is None else f"{x:.0f}°" for x in angles)
    return text


def run_example(key):
    cuts = EXAMPLES[key]
    blocks = build_blocks(cuts)
    assert sum(b.volume for b in blocks) == SIZE**3, "blocks do not fill the cube"
    contacts = classify_all(blocks)
    return blocks, contacts, symmetry_report(blocks, contacts)


def summary(blocks, contacts):
    """Counts of one example: the seven types, and any other outcome apart."""
    counts = count_types(contacts)
    return {
        "blocks": len(blocks),
        "counts": {t: counts[t] for t in TYPES},
        "contacts": sum(counts[t] for t in TYPES),
        "penetrating": counts.get("penetrating", 0),
        "separated": counts.get("separated", 0),
        "other": {
            k: v
            for k, v in counts.items()
            if k not in TYPES and k not in ("penetrating", "separated")
        },
    }


def print_symmetry(symmetry):
    for name, result in symmetry.items():
        if result is None:
            print(f"   {name}: not a symmetry of this block set")
            continue
        fixed, orbits = result
        print(f"   {name}: maps the blocks onto themselves; fixed blocks: {fixed or 'none'}")
        for t in TYPES:
            sizes = Counter(orbits.get(t, []))
            if sizes:
                parts = " + ".join(f"{n} of size {size}" for size, n in sorted(sizes.items()))
                print(f"     {t:<26}{sum(orbits[t]):>4} pairs = orbits {parts}")


def print_report(key, blocks, contacts, symmetry, list_all):
    cuts = EXAMPLES[key]
    paper_blocks, paper_counts = PAPER[key]
    s = summary(blocks, contacts)
    planes = ", ".join(f"{label}={offset}" for label, _, offset in cuts)
    print(f"== {key}: cube [0,{SIZE}]^3 cut by {planes}")
    print(
        f"   blocks: {s['blocks']} (paper {paper_blocks}); "
        f"total volume {fmt(sum(b.volume for b in blocks))}"
    )
    print(f"   {'type':<26}{'exact':>6}{'paper':>7}")
    for t, p in zip(TYPES, paper_counts):
        mark = "" if s["counts"][t] == p else "   <-- differs"
        print(f"   {t:<26}{s['counts'][t]:>6}{p:>7}{mark}")
    extra = {k: s[k] for k in ("penetrating", "separated") if s[k]} | s["other"]
    print(f"   {'total contacts':<26}{s['contacts']:>6}{sum(paper_counts):>7}")
    print(f"   other outcomes: {extra or 'none'}")
    print_symmetry(symmetry)
    for t, p in zip(TYPES, paper_counts):
        if list_all or s["counts"][t] != p:
            print(f"   -- {t}: {s['counts'][t]} pairs (paper {p})")
            for c in contacts:
                if c.kind == t:
                    print(describe_pair(blocks, c, cuts))
    print()


def block_from_json(d, name):
    """A block from the dev-case format: vertices, faces counter-clockwise from outside."""
    pts = [tuple(Fraction(x) for x in v) for v in d["vertices"]]
    hs = []
    for f in d["faces"]:
        p0, p1, p2 = pts[f[0]], pts[f[1]], pts[f[2]]
        u, w = sub(p1, p0), sub(p2, p0)
        n = (
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        )
        hs.append((*n, dot(n, p0)))
    verts = polytope_vertices(hs)
    block = Block(name, hs, frozenset(verts))
    block.faces = block_faces(hs, verts)
    return block


def check_dev_cases(path):
    """Classify every pair of a dev-case file; print the disagreements; exit 1 if any."""
    with open(path) as f:
        cases = json.load(f)
    bad = 0
    for case in cases:
        blocks = [block_from_json(case["a"], "a"), block_from_json(case["b"], "b")]
        c = classify_pair(blocks, 0, 1)
        if (c.kind, c.dim) != (case["expected"], case["dim"]):
            bad += 1
            print(
                f"{case['id']}: expected {case['expected']} (dim {case['dim']}),"
                f" got {c.kind} (dim {c.dim})"
            )
    print(f"{len(cases)} cases, {bad} disagreements")
    raise SystemExit(1 if bad else 0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the counts as JSON")
    parser.add_argument("--all", action="store_true", help="list the pairs of every type")
    parser.add_argument(
        "--dev-cases",
        metavar="PATH",
        help="check the classifier on a dev-case file instead",
    )
    args = parser.parse_args()
    if args.dev_cases:
        check_dev_cases(args.dev_cases)
    results = {key: run_example(key) for key in EXAMPLES}
    if args.json:
        out = {key: summary(r[0], r[1]) for key, r in results.items()}
        print(json.dumps(out, indent=2))
        return
    for key, r in results.items():
        print_report(key, *r, list_all=args.all)


if __name__ == "__main__":
    main()
