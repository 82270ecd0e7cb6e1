"""Blocks from numpy arrays, lists, half-spaces and corners; their read-only properties."""

import pickle

import numpy as np
import pytest

import penedge

import shapes


def test_cuboid_properties():
    box = penedge.Block.cuboid([0, 0, 0], [2, 1, 1])
    assert box.vertices.shape == (8, 3)
    assert box.vertices.dtype == np.float64
    assert len(box.faces) == 6
    assert all(len(f) == 4 for f in box.faces)
    assert box.edges.shape == (12, 2)
    assert box.edges.dtype == np.int64
    assert box.edge_faces.shape == (12, 2)
    assert box.face_normals.shape == (6, 3)
    assert np.allclose(np.linalg.norm(box.face_normals, axis=1), 1)
    assert box.volume == pytest.approx(2)
    assert box.centroid.tolist() == pytest.approx([1, 0.5, 0.5])
    assert box.aabb.tolist() == [[0, 0, 0], [2, 1, 1]]
    assert box.size == pytest.approx(np.sqrt(6))


def test_block_from_numpy_and_from_lists_agree():
    points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    from_lists = penedge.Block(points, faces)
    from_numpy = penedge.Block(np.array(points, dtype=np.int32), np.array(faces))
    from_fortran = penedge.Block(np.asfortranarray(np.array(points, dtype=np.float32)), faces)
    for block in (from_numpy, from_fortran):
        assert np.array_equal(block.vertices, from_lists.vertices)
        assert block.faces == from_lists.faces
    assert from_lists.volume == pytest.approx(1 / 6)


def test_normals_point_outward_and_edges_join_their_faces():
    block = shapes.tetra([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    for normal, face in zip(block.face_normals, block.faces, strict=True):
        assert (block.vertices[face] - block.centroid).mean(axis=0) @ normal > 0
    for (p, q), (f, g) in zip(block.edges, block.edge_faces, strict=True):
        assert {p, q} <= set(block.faces[f])
        assert {p, q} <= set(block.faces[g])


def test_from_planes_builds_the_box():
    normals = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 2], [0, 0, -1]]
    block = penedge.Block.from_planes(normals, [1, 0, 1, 0, 2, 0])
    assert block.volume == pytest.approx(1)
    assert block.aabb.tolist() == [[0, 0, 0], [1, 1, 1]]


def test_coplanar_triangles_are_merged_into_one_face():
    v = penedge.Block.cuboid([0, 0, 0], [1, 1, 1]).vertices
    triangles = []
    for face in penedge.Block.cuboid([0, 0, 0], [1, 1, 1]).faces:
        triangles += [[face[0], face[1], face[2]], [face[0], face[2], face[3]]]
    assert len(penedge.Block(v, triangles).faces) == 6


def test_properties_are_copies():
    block = shapes.cube()
    block.vertices[0] = 99
    assert block.vertices[0].tolist() == [0, 0, 0]
    with pytest.raises(AttributeError):
        block.volume = 2


def test_repr_and_pickle():
    block = shapes.cube()
    assert repr(block) == (
        "Block(8 vertices, 6 faces, 12 edges, volume=1.0, centroid=[0.5, 0.5, 0.5])"
    )
    again = pickle.loads(pickle.dumps(block))
    assert np.array_equal(again.vertices, block.vertices)
    assert again.faces == block.faces
