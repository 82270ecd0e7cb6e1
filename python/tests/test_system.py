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
