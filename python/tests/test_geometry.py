"""Contact geometry from Python: normal, distance, area and points of a pair, and the same as
flat arrays for a whole system (one run of points per contact, never one object each)."""

import math
from pathlib import Path

import numpy as np
import pytest

import penedge

import shapes

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

# outcome -> (contact points, normal) of the hand-made pairs of shapes.py (A: the unit cube)
EXPECTED = {
    "vertex-vertex": ([[1, 1, 1]], np.ones(3) / math.sqrt(3)),
    "vertex-edge": ([[0.5, 0, 1]], None),
    "edge-edge": ([[0.5, 0, 1]], None),
    "edge-edge-superposition": ([[0.5, 0, 1], [1, 0, 1]], None),
    "vertex-face": ([[0.5, 0.5, 1]], [0, 0, 1]),
    "edge-face": ([[0.2, 0.5, 1], [0.8, 0.5, 1]], [0, 0, 1]),
    "face-face": ([[0.2, 0.2, 1], [0.8, 0.2, 1], [0.8, 0.8, 1], [0.2, 0.8, 1]], [0, 0, 1]),
}


def same_point_set(points, expected):
    """The same points in any order, within 1e-9 (the blocks' size is about 1)."""

    def key(p):
        return tuple(np.round(p, 6))

    got = np.array(sorted(points, key=key))
    want = np.array(sorted(np.asarray(expected, dtype=float), key=key))
    assert got.shape == want.shape
    assert np.allclose(got, want, rtol=0, atol=1e-9)


@pytest.mark.parametrize("outcome", shapes.TOUCHING)
def test_pair_geometry_of_the_hand_made_pairs(outcome):
    a, b = shapes.pair(outcome)
    c = penedge.detect_pair(a, b)
    points, normal = EXPECTED[outcome]
    same_point_set(c.points, points)
    assert c.points.shape == (len(points), 3)
    assert np.linalg.norm(c.normal) == pytest.approx(1, abs=1e-15)
    if normal is not None:
        assert np.allclose(c.normal, normal, atol=1e-15)
    assert c.distance == pytest.approx(0, abs=1e-12)
    assert c.area == pytest.approx(0.36 if outcome == "face-face" else 0, abs=1e-12)
    swapped = penedge.detect_pair(b, a)
    assert np.array_equal(swapped.normal, -c.normal)
    assert swapped.distance == c.distance


def test_the_distance_follows_a_motion_along_the_normal():
    cube = shapes.cube()
    for shift in (0.0005, -0.0005):
        b = penedge.Block.cuboid([0.2, 0.2, 1 + shift], [0.8, 0.8, 2])
        c = penedge.detect_pair(cube, b, gap=1e-3)
        assert c.outcome == "face-face"
        assert c.distance == pytest.approx(shift, abs=1e-12)


@pytest.mark.parametrize("outcome", ["separated", "penetrating"])
def test_no_geometry_without_a_contact(outcome):
    c = penedge.detect_pair(*shapes.pair(outcome))
    assert (c.normal, c.points, c.area, c.distance) == (None, None, None, None)


def test_system_geometry_arrays():
    found = penedge.paper_example(3).detect(geometry=True)
    n = len(found)
    assert found.normals.shape == (n, 3)
    assert found.normals.dtype == np.float64
    assert found.distances.shape == found.areas.shape == (n,)
    assert found.point_offsets.shape == (n + 1,)
    assert found.point_offsets.dtype == np.int64
    assert found.point_offsets[0] == 0
    assert found.point_offsets[-1] == len(found.points)
    assert np.allclose(np.linalg.norm(found.normals, axis=1), 1, atol=1e-15)
    assert np.abs(found.distances).max() < 1e-9
    sizes = np.diff(found.point_offsets)
    for code, size in ((1, 1), (4, 2)):
        assert (sizes[found.types == code] == size).all()
    assert (sizes[found.types == 7] >= 3).all()
    assert (found.areas[found.types != 7] == 0).all()
    with pytest.raises(ValueError, match="read-only"):
        found.normals[0, 0] = 2


def test_without_geometry_the_arrays_are_none():
    found = penedge.paper_example(1).detect()
    assert found.normals is None
    assert found.points is None
    assert found.point_offsets is None
    with pytest.raises(penedge.InputError, match="geometry=True"):
        found.points_of(0)


def test_geometry_keeps_the_contacts_of_detect():
    system, _ = penedge.generate(EXAMPLES / "joint_set_random.toml")
    plain, full = system.detect(), system.detect(geometry=True)
    for name in ("pairs", "types", "feature_kinds", "feature_ids", "penetrating"):
        assert np.array_equal(getattr(plain, name), getattr(full, name)), name


@pytest.mark.parametrize("source", ["example 3", "joint_set_random", "finite_polygon"])
def test_every_row_equals_the_pair_query(source):
    if source == "example 3":
        system = penedge.paper_example(3)
    else:
        system, _ = penedge.generate(EXAMPLES / f"{source}.toml")
    found = system.detect(geometry=True)
    blocks = system.blocks
    for i, (a, b) in enumerate(found.pairs):
        c = penedge.detect_pair(blocks[a], blocks[b])
        assert c.type_code == found.types[i]
        assert np.array_equal(c.normal, found.normals[i])
        assert c.distance == found.distances[i]
        assert c.area == found.areas[i]
        assert np.array_equal(c.points, found.points_of(i))
    start, end = found.point_offsets[-2:]
    assert np.array_equal(found.points_of(-1), found.points[start:end])
    with pytest.raises(IndexError):
        found.points_of(len(found))


@pytest.mark.parametrize(
    ("n", "area"), [(1, 300.0), (2, 300 * math.sqrt(2)), (3, 300 + 300 * math.sqrt(2))]
)
def test_face_face_area_of_the_paper_examples_is_the_area_of_the_cuts(n, area):
    found = penedge.paper_example(n).detect(geometry=True)
    face_face = found.areas[found.types == 7].sum()
    assert face_face == pytest.approx(area, rel=1e-12)


def test_gap_and_geometry_together():
    system = penedge.BlockSystem([shapes.cube(), penedge.Block.cuboid([1.0005, 0, 0], [2, 1, 1])])
    assert len(system.detect(geometry=True)) == 0
    found = system.detect(gap=1e-3, geometry=True)
    assert found.types.tolist() == [7]
    assert found.distances[0] == pytest.approx(0.0005, abs=1e-12)
    assert found.normals.tolist() == [[1, 0, 0]]
    assert found.areas[0] == pytest.approx(1)
