"""Block systems: the contact arrays, the paper's examples, threads."""

import pickle
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import penedge

import shapes

EXPECTED = {
    1: (8, [4, 0, 0, 12, 0, 0, 12]),
    2: (8, [4, 0, 0, 12, 0, 0, 12]),
    3: (26, [205, 0, 0, 78, 0, 0, 42]),
}
PAPER = {
    1: [4, 0, 0, 12, 0, 0, 12],
    2: [4, 0, 0, 4, 0, 0, 20],
    3: [205, 0, 0, 78, 0, 0, 42],
}


@pytest.mark.parametrize("n", [1, 2, 3])
def test_paper_examples(n):
    blocks, counts = EXPECTED[n]
    system = penedge.paper_example(n)
    found = system.detect()
    assert len(system) == blocks
    assert list(found.counts()) == list(penedge.CONTACT_TYPES)
    assert list(found.counts().values()) == counts
    assert len(found) == sum(counts)
    assert len(found.penetrating) == 0
    assert np.bincount(found.types, minlength=8)[1:].tolist() == counts


@pytest.mark.parametrize("n", [1, 2, 3])
def test_paper_table3_is_the_printed_table(n):
    assert list(penedge.paper_table3(n).values()) == PAPER[n]
    assert list(penedge.paper_table3(n)) == list(penedge.CONTACT_TYPES)


def test_paper_example_planes():
    normals, offsets = penedge.paper_example_planes(2)
    assert normals.tolist() == [[1, 1, 0], [0, 1, 1], [1, 0, 1]]
    assert offsets.tolist() == [10, 10, 10]


def test_arrays_of_a_small_system():
    cube = shapes.cube()
    system = penedge.BlockSystem(
        [
            cube,
            penedge.Block.cuboid([1, 0, 0], [2, 1, 1]),  # 0-1 face-face
            penedge.Block.cuboid([1, 1, 1], [2, 2, 2]),  # 0-2 vertex-vertex, 1-2 edge-edge sup.
            penedge.Block.cuboid([5, 5, 5], [6, 6, 6]),  # alone
            penedge.Block.cuboid([0.5, 0.5, -0.5], [1.5, 1.5, 0.5]),  # penetrates 0 and 1
        ]
    )
    found = system.detect()
    assert found.pairs.dtype == np.int64
    assert found.types.dtype == np.int8
    assert found.pairs.tolist() == [[0, 1], [0, 2], [1, 2]]
    assert found.types.tolist() == [7, 1, 4]
    assert found.penetrating.tolist() == [[0, 4], [1, 4]]
    assert found.feature_kinds.dtype == np.int8
    assert found.feature_kinds.tolist() == [[2, 2], [0, 0], [1, 1]]
    vertex_of_0 = found.feature_ids[1, 0]
    assert system[0].vertices[vertex_of_0].tolist() == [1, 1, 1]
    assert found.counts()["face-face"] == 1


def test_arrays_are_read_only():
    found = penedge.paper_example(1).detect()
    with pytest.raises(ValueError, match="read-only"):
        found.pairs[0, 0] = 5


def test_empty_system():
    found = penedge.BlockSystem([]).detect()
    assert found.pairs.shape == (0, 2)
    assert found.types.shape == (0,)
    assert found.penetrating.shape == (0, 2)
    assert sum(found.counts().values()) == 0


def test_from_box_cut_matches_paper_example():
    normals, offsets = penedge.paper_example_planes(3)
    system = penedge.BlockSystem.from_box_cut([0, 0, 0], [10, 10, 10], normals, offsets)
    assert len(system) == 26
    assert system.detect().counts() == penedge.paper_example(3).detect().counts()


def test_blocks_getitem_and_repr():
    system = penedge.paper_example(1)
    assert len(system.blocks) == 8
    assert system[-1].volume == pytest.approx(125)
    assert np.array_equal(system[7].vertices, system.blocks[7].vertices)
    with pytest.raises(IndexError):
        system[8]
    assert repr(system) == "BlockSystem(8 blocks)"
    assert repr(system.detect()).startswith("SystemContacts(28 contacts: vertex-vertex 4")


def test_reprs_say_one_in_the_singular():
    pair = penedge.BlockSystem([shapes.cube(), penedge.Block.cuboid([1, 0, 0], [2, 1, 1])])
    assert repr(pair.detect()) == "SystemContacts(1 contact: face-face 1; 0 penetrating)"
    assert repr(penedge.ContactTracker(pair)) == "ContactTracker(2 blocks, 1 contact)"
    assert repr(penedge.BlockSystem([shapes.cube()])) == "BlockSystem(1 block)"
    assert repr(penedge.BlockSystem([shapes.cube()]).arrays()) == "BlockArrays(1 block, 6 faces)"


def test_gap_is_passed_through():
    system = penedge.BlockSystem([shapes.cube(), penedge.Block.cuboid([1.001, 0, 0], [2, 1, 1])])
    assert len(system.detect()) == 0
    assert system.detect(gap=1e-3).types.tolist() == [7]


def test_pickle_round_trip():
    system = pickle.loads(pickle.dumps(penedge.paper_example(2)))
    assert list(system.detect().counts().values()) == EXPECTED[2][1]


def test_detect_from_many_threads_gives_one_answer():
    system = penedge.paper_example(3)
    expected = system.detect().pairs
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(lambda _: system.detect(), range(8)))
    for found in results:
        assert np.array_equal(found.pairs, expected)


def flat(arrays):
    return (
        arrays.vertices,
        arrays.vertex_offsets,
        arrays.face_offsets,
        arrays.loop_offsets,
        arrays.face_vertices,
    )


def test_system_from_flat_arrays_round_trip():
    system = penedge.paper_example(3)
    a = system.arrays()
    back = penedge.BlockSystem.from_arrays(*flat(a))
    assert len(back) == 26
    assert all(x == y for x, y in zip(back.blocks, system.blocks, strict=True))
    assert back.detect().counts() == system.detect().counts()
    assert np.array_equal(back.arrays().face_origin_kind, np.zeros(len(a.face_block)))
    with_origins = penedge.BlockSystem.from_arrays(
        *flat(a), a.face_origin_kind, a.face_origin_set, a.face_origin_index
    )
    for name in ("face_origin_kind", "face_origin_set", "face_origin_index"):
        assert np.array_equal(getattr(with_origins.arrays(), name), getattr(a, name))


def test_system_from_flat_arrays_of_a_grid_built_with_numpy():
    # A 3 x 2 x 1 grid of unit cubes from arrays made here: 7 face-face contacts
    # (4 along x, 3 along y), as a DEM code would hand its blocks over.
    cube = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    loops = np.concatenate(cube.faces)
    shifts = np.array([[i, j, 0] for i in range(3) for j in range(2)], dtype=float)
    vertices = (cube.vertices[None] + shifts[:, None]).reshape(-1, 3)
    n = len(shifts)
    system = penedge.BlockSystem.from_arrays(
        vertices,
        np.arange(n + 1) * 8,
        np.arange(n + 1) * 6,
        np.arange(6 * n + 1) * 4,
        (loops[None] + 8 * np.arange(n)[:, None]).ravel(),
    )
    assert len(system) == 6
    assert system.detect().counts()["face-face"] == 7


def test_system_from_flat_arrays_names_what_is_wrong():
    a = penedge.paper_example(1).arrays()
    args = list(flat(a))
    bad = list(args)
    bad[1] = a.vertex_offsets[:-1]
    with pytest.raises(penedge.InputError, match="vertex_offsets ends at 56, but vertices has 64"):
        penedge.BlockSystem.from_arrays(*bad)
    bad = list(args)
    bad[4] = a.face_vertices.astype(float)
    with pytest.raises(penedge.InputError, match="face_vertices must hold integers"):
        penedge.BlockSystem.from_arrays(*bad)
    bad = list(args)
    loops = a.face_vertices.copy()
    loops[a.loop_offsets[a.face_offsets[3]]] = 0
    bad[4] = loops
    with pytest.raises(penedge.InputError, match=r"\(of block 3\) refers to vertex 0"):
        penedge.BlockSystem.from_arrays(*bad)
    bad = list(args)
    flipped = a.vertices.copy()
    flipped[a.vertex_offsets[5] : a.vertex_offsets[6], 2] *= -1  # block 5 mirrored
    bad[0] = flipped
    with pytest.raises(penedge.BlockError, match=r"^block 5: ") as info:
        penedge.BlockSystem.from_arrays(*bad)
    assert info.value.kind == "wrong_orientation"
    with pytest.raises(penedge.InputError, match="all three"):
        penedge.BlockSystem.from_arrays(*args, a.face_origin_kind)
