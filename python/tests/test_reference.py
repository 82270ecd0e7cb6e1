"""Random convex blocks against a slow reference (hypothesis).

The reference is numpy only: A ∩ B by brute-force vertex enumeration of both blocks'
half-spaces (every triple of planes), its dimension (point, segment, polygon) and the face of
each block that holds it, hence the contact type. Touching placements are constructed: B is
turned so that a normal of a chosen feature of B (vertex, edge or face) points against a normal
of a chosen feature of A, then moved so that a point of B's feature lands on a point of A's;
the plane through it separates the blocks, and A ∩ B is the intersection of the two features.
The engine sees the same half-spaces through ``Block.from_planes``.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import penedge

LOW, HIGH = 1e-8, 1e-3  # relative: below LOW a distance is rounding, above HIGH it is real
FEATURES = ("vertex", "edge", "face")
EPS = np.finfo(float).eps
SETTINGS = settings(
    max_examples=30,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)


def vertices_of(normals: np.ndarray, offsets: np.ndarray, slack: float) -> np.ndarray:
    """The vertices of {x : normals @ x <= offsets}: every triple of planes, kept if feasible."""
    triples = np.array(list(combinations(range(len(offsets)), 3)))
    a, b, c = (normals[triples[:, k]] for k in range(3))
    da, db, dc = (offsets[triples[:, k]][:, None] for k in range(3))
    bc, ca, ab = np.cross(b, c), np.cross(c, a), np.cross(a, b)
    det = np.einsum("ij,ij->i", a, bc)
    keep = np.abs(det) >= 1e-6  # clearly independent planes only
    if not np.any(keep):
        return np.zeros((0, 3))
    points = ((da * bc + db * ca + dc * ab)[keep]) / det[keep][:, None]
    feasible = np.all(points @ normals.T - offsets <= slack, axis=1)
    return points[feasible]


@dataclass
class Polytope:
    """A bounded simple polytope, from its half-spaces, with vertices, edges and faces."""

    normals: np.ndarray
    offsets: np.ndarray
    vertices: np.ndarray
    at: list[tuple[int, int, int]]
    edges: list[tuple[tuple[int, int], tuple[int, int]]]
    faces: list[tuple[int, list[int]]]
    size: float

    def block(self) -> penedge.Block:
        return penedge.Block.from_planes(self.normals, self.offsets)

    def moved(self, rotation: np.ndarray, shift: np.ndarray) -> Polytope | None:
        normals = self.normals @ rotation.T
        return polytope(normals, self.offsets + normals @ shift)


def polytope(normals: np.ndarray, offsets: np.ndarray) -> Polytope | None:
    """The polytope of unit normals and offsets, if bounded, simple and not slender."""
    raw = vertices_of(normals, offsets, 1e-12)
    if len(raw) < 4:
        return None
    size = float(np.linalg.norm(raw.max(axis=0) - raw.min(axis=0)))
    excess = np.abs(raw @ normals.T - offsets)
    at = []
    for k, p in enumerate(raw):
        active = np.flatnonzero(excess[k] <= 1e-9 * size)
        near = np.any((excess[k] > 1e-9 * size) & (excess[k] <= 1e-6 * size))
        close = any(np.linalg.norm(p - raw[j]) <= 1e-6 * size for j in range(k))
        if len(active) != 3 or near or close:
            return None
        at.append(tuple(int(i) for i in active))
    edges = []
    for u, v in combinations(range(len(raw)), 2):
        shared = sorted(set(at[u]) & set(at[v]))
        if len(shared) == 2:
            if np.linalg.norm(raw[u] - raw[v]) < 0.01 * size:
                return None
            edges.append(((u, v), (shared[0], shared[1])))
    faces = []
    for i in range(len(offsets)):
        on = [v for v in range(len(raw)) if i in at[v]]
        if 0 < len(on) < 3:
            return None
        if on:
            faces.append((i, on))
    if len(raw) + len(faces) != len(edges) + 2:
        return None
    return Polytope(normals, offsets, raw, at, edges, faces, size)


# Eight directions around the sphere (an octahedron's face normals), each tilted at random:
# the half-spaces always bound a region.
BASE = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)


@st.composite
def polytopes(draw, radius: float) -> Polytope:
    tilt = np.array(draw(st.lists(st.floats(-0.5, 0.5), min_size=24, max_size=24))).reshape(8, 3)
    extra = draw(st.integers(0, 3))
    more = np.array(draw(st.lists(st.floats(-1, 1), min_size=3 * extra, max_size=3 * extra)))
    normals = np.vstack([BASE + tilt, more.reshape(extra, 3)])
    assume(np.all(np.linalg.norm(normals, axis=1) > 0.3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    k = len(normals)
    spread = np.array(draw(st.lists(st.floats(0, 1), min_size=k, max_size=k)))
    offsets = radius * (0.5 + 0.5 * spread)
    p = polytope(normals, offsets)
    assume(p is not None)
    return p


def rotation_about(axis: np.ndarray, angle: float) -> np.ndarray:
    axis = axis / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def rotation_onto(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A rotation taking unit vector a onto unit vector b."""
    axis = np.cross(a, b)
    if np.linalg.norm(axis) < 1e-9:
        if a @ b > 0:
            return np.eye(3)
        axis = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
        return rotation_about(axis, np.pi)
    return rotation_about(axis, float(np.arctan2(np.linalg.norm(axis), a @ b)))


def feature(draw, p: Polytope, dim: int):
    """A normal strictly inside the normal cone of a feature of dimension dim, a point inside
    the feature, and the edge's ends for an edge."""
    weight = st.floats(0.2, 1.0)
    if dim == 0:
        v = draw(st.integers(0, len(p.vertices) - 1))
        n = sum(p.normals[i] * draw(weight) for i in p.at[v])
        return n / np.linalg.norm(n), p.vertices[v], None
    if dim == 1:
        (u, v), (i, j) = p.edges[draw(st.integers(0, len(p.edges) - 1))]
        n = p.normals[i] * draw(weight) + p.normals[j] * draw(weight)
        a, b = p.vertices[u], p.vertices[v]
        return n / np.linalg.norm(n), a + (b - a) * draw(st.floats(0.25, 0.75)), (a, b)
    plane, on = p.faces[draw(st.integers(0, len(p.faces) - 1))]
    w = np.array([draw(weight) for _ in on])
    return p.normals[plane], (w @ p.vertices[on]) / w.sum(), None


TARGETS = [
    ("vertex-vertex", 0, 0),
    ("vertex-edge", 0, 1),
    ("edge-edge", 1, 1),
    ("edge-edge-superposition", 1, 1),
    ("vertex-face", 0, 2),
    ("edge-face", 1, 2),
    ("face-face", 2, 2),
]


def touching(draw, target: int):
    """A touching placement for a target type: A, B and the separating normal n (A to B)."""
    kind, fa, fb = TARGETS[target]
    a = draw(polytopes(1.0))
    b = draw(polytopes(draw(st.floats(0.3, 2.0))))
    n, pa, ea = feature(draw, a, fa)
    m, pb, eb = feature(draw, b, fb)
    turn = rotation_onto(m, -n)
    spin = draw(st.floats(0, 2 * np.pi))
    if ea is not None and eb is not None and kind.startswith("edge-edge"):
        da = (ea[1] - ea[0]) / np.linalg.norm(ea[1] - ea[0])
        db = turn @ (eb[1] - eb[0]) / np.linalg.norm(eb[1] - eb[0])
        align = float(np.arctan2(np.cross(db, da) @ n, db @ da))
        if kind == "edge-edge":
            spin = align + draw(st.floats(0.35, np.pi - 0.35))
        else:
            spin = align + draw(st.sampled_from([0.0, np.pi]))
            pb = eb[0]  # an end of B's edge on A's edge: they overlap over part of each
    q = rotation_about(n, spin) @ turn
    moved = b.moved(q, pa - q @ pb)
    assume(moved is not None)
    return a, moved, n


def touch(a: Polytope, b: Polytope):
    """Dimension of A ∩ B and of the feature of A and of B holding it; None if too close
    to call (a distance between LOW and HIGH)."""
    scale = min(a.size, b.size)
    low, high = LOW * scale, HIGH * scale
    normals = np.vstack([a.normals, b.normals])
    offsets = np.concatenate([a.offsets, b.offsets])
    assert len(vertices_of(normals, offsets - low, 1e-13 * scale)) == 0, "the blocks overlap"
    points = vertices_of(normals, offsets + 1e-10 * scale, 1e-13 * scale)
    assert len(points) > 0, "the blocks do not touch"
    dim = dimension(points, low, high)
    dims = []
    for p in (a, b):
        far = np.abs(points @ p.normals.T - p.offsets).max(axis=0)
        if np.any((far > low) & (far < high)) or dim is None:
            return None
        active = p.normals[far <= low]
        singular = np.linalg.svd(active, compute_uv=False) if len(active) else np.zeros(0)
        if np.any((singular > 1e-9) & (singular < 1e-4)):
            return None
        rank = int(np.sum(singular >= 1e-4))
        assert rank > 0, "the contact reaches into a block"
        dims.append(3 - rank)
    return dim, dims


def dimension(points: np.ndarray, low: float, high: float) -> int | None:
    """0, 1, 2 or 3 by the extents of the points along their principal axes; None if an
    extent lies between low and high."""
    centred = points - points.mean(axis=0)
    singular = np.concatenate([np.linalg.svd(centred, compute_uv=False), np.zeros(3)])[:3]
    # The largest offset along a principal axis lies between s / sqrt(n) and s.
    root = np.sqrt(len(points))
    if np.any((singular > low) & (singular / root < high)):
        return None
    return int(np.sum(singular / root >= high))


def type_of(dim: int, dims: list[int]) -> str:
    fa, fb = min(dims), max(dims)
    kind = {
        (0, 0): "vertex-vertex",
        (0, 1): "vertex-edge",
        (0, 2): "vertex-face",
        (1, 1): "edge-edge-superposition" if dim == 1 else "edge-edge",
        (1, 2): "edge-face",
        (2, 2): "face-face",
    }[(fa, fb)]
    expected_dim = {"edge-edge-superposition": 1, "edge-face": 1, "face-face": 2}.get(kind, 0)
    assert dim == expected_dim, f"reference: {kind} with a set of dimension {dim}"
    return kind


def grazing(a: Polytope, b: Polytope, sine: float) -> bool:
    """Whether an edge of one block near the contact runs at a grazing angle to a plane of
    the other through it (0 < sin < sine). Below the rule's sine (docs/tolerance.md, "Lies
    in": the relative length threshold, 1e-9 by default) the edge lies in the face, a type one
    rank higher than the exact one; edges within a few times that sine are skipped."""
    scale = min(a.size, b.size)
    normals = np.vstack([a.normals, b.normals])
    offsets = np.concatenate([a.offsets, b.offsets])
    points = vertices_of(normals, offsets + 1e-10 * scale, 1e-13 * scale)
    for x, y in ((a, b), (b, a)):
        far = np.abs(points @ y.normals.T - y.offsets).max(axis=0)
        through = y.normals[far <= LOW * scale]
        for (u, v), _ in x.edges:
            d = x.vertices[v] - x.vertices[u]
            d /= np.linalg.norm(d)
            for s in (through @ d, -(through @ d)):
                if 1e-9 < s.max() < sine and edge_near(x, u, v, y, scale):
                    return True
    return False


def edge_near(x: Polytope, u: int, v: int, y: Polytope, scale: float) -> bool:
    p, q = x.vertices[u], x.vertices[v]
    lo, hi = 0.0, 1.0
    for n, d in zip(y.normals, y.offsets + LOW * scale, strict=True):
        e0, e1 = n @ p - d, n @ q - d
        if e0 > 0 and e1 > 0:
            return False
        if e0 > 0:
            lo = max(lo, e0 / (e0 - e1))
        elif e1 > 0:
            hi = min(hi, e0 / (e0 - e1))
    return lo <= hi


@pytest.mark.parametrize("target", range(7), ids=[t[0] for t in TARGETS])
@SETTINGS
@given(data=st.data())
def test_touching_placements_have_the_reference_type(target, data):
    a, b, _ = touching(data.draw, target)
    if data.draw(st.booleans()):
        a, b = b, a
    reference = touch(a, b)
    assume(reference is not None)
    dim, dims = reference
    kind = type_of(dim, dims)
    assert kind == TARGETS[target][0]  # the construction, checked by the reference
    assume(not grazing(a, b, 4e-9))  # 4 x the default relative length threshold
    found = penedge.detect_pair(a.block(), b.block())
    assert found.outcome == kind
    assert (found.feature_a[0], found.feature_b[0]) == (FEATURES[dims[0]], FEATURES[dims[1]])


def thresholds(a: penedge.Block, b: penedge.Block, gap: float, length: float):
    """The absolute gap and length threshold of a pair, by the policy (docs/tolerance.md)."""
    scale = min(a.size, b.size)
    magnitude = max(np.abs(a.aabb).max(), np.abs(b.aabb).max())
    g = max(gap * scale, 16 * EPS * magnitude)
    return g, max(length * scale, 10 * g)


def meet(a: Polytope, b: Polytope, widen: float) -> bool:
    """Whether A and B, each moved out by widen (in, if negative), meet."""
    normals = np.vstack([a.normals, b.normals])
    offsets = np.concatenate([a.offsets, b.offsets]) + widen
    return len(vertices_of(normals, offsets, 1e-13 * min(a.size, b.size))) > 0


def random_rotation(draw) -> np.ndarray:
    axis = np.array(draw(st.tuples(*[st.floats(-1, 1)] * 3)))
    assume(np.linalg.norm(axis) > 0.2)
    return rotation_about(axis, draw(st.floats(-np.pi, np.pi)))


@settings(SETTINGS, max_examples=100)
@given(data=st.data(), gap=st.sampled_from([1e-12, 1e-6, 1e-3]))
def test_random_placements_touch_as_the_reference_says(data, gap):
    a = data.draw(polytopes(1.0))
    radius = data.draw(st.floats(0.3, 2.0))
    direction = random_rotation(data.draw) @ np.array([1.0, 0, 0])
    distance = data.draw(st.floats(0, 2.5)) * (1 + radius)
    b = data.draw(polytopes(radius)).moved(random_rotation(data.draw), direction * distance)
    assume(b is not None)
    length = max(1e-9, 10 * gap)
    g, big_l = thresholds(a.block(), b.block(), gap, length)
    rounding = 1e-12 * min(a.size, b.size)
    found = penedge.detect_pair(a.block(), b.block(), gap=gap, length=length).outcome
    assert penedge.detect_pair(b.block(), a.block(), gap=gap, length=length).outcome == found
    if not meet(a, b, 1.01 * g + rounding):
        assert found == "separated"
    if meet(a, b, -1e3 * rounding):
        assert found != "separated"
    if meet(a, b, -(2.02 * big_l + rounding)):
        assert found == "penetrating"
