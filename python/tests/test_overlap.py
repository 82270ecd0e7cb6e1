"""penedge.overlap: normal, depth and region of two penetrating blocks, checked against
values worked out by hand and against detect_pair after moving a block by the depth."""

import numpy as np
import pytest

import penedge


def cube(lo, hi):
    return penedge.Block.cuboid(lo, hi)


def moved(block, shift):
    return penedge.Block(block.vertices + np.asarray(shift), block.faces)


def test_a_block_sunk_into_a_larger_one():
    a = cube([0, 0, 0], [1, 1, 1])
    b = cube([0.25, 0.25, 0.99], [0.75, 0.75, 1.99])
    o = penedge.overlap(a, b)
    # B's bottom (0.5 x 0.5) lies 0.01 inside A's top face, within it.
    np.testing.assert_allclose(o["normal"], [0, 0, 1], atol=1e-12)
    assert o["depth"] == pytest.approx(0.01, abs=1e-12)
    np.testing.assert_allclose(o["min_translation"], [0, 0, 0.01], atol=1e-12)
    assert o["volume"] == pytest.approx(0.5 * 0.5 * 0.01, abs=1e-12)
    np.testing.assert_allclose(o["centroid"], [0.5, 0.5, 0.995], atol=1e-12)
    assert o["area"] == pytest.approx(0.25, abs=1e-12)
    assert o["points"].shape == (4, 3)
    np.testing.assert_allclose(o["points"][:, 2], 0.995, atol=1e-12)


def test_moving_by_the_depth_along_the_normal_leaves_the_blocks_touching():
    a = cube([0, 0, 0], [1, 1, 1])
    # A corner of B sunk into A's edge region: a tilted, generic overlap.
    b = penedge.Block.from_planes(
        [[1, 1, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]], [3.9, -0.9, -0.8, -0.85]
    )
    assert penedge.detect_pair(a, b).outcome == "penetrating"
    o = penedge.overlap(a, b)
    shift = o["normal"] * o["depth"]
    assert penedge.detect_pair(a, moved(b, shift), gap=1e-9).touching
    assert penedge.detect_pair(a, moved(b, 0.9 * shift)).outcome == "penetrating"
    # The minimum over all directions is no longer than the depth along the normal.
    assert np.linalg.norm(o["min_translation"]) <= o["depth"] + 1e-12


def test_swapping_negates_the_normal():
    a = cube([0, 0, 0], [1, 1, 1])
    b = cube([0.5, 0.6, 0.97], [1.5, 1.6, 1.97])
    ab, ba = penedge.overlap(a, b), penedge.overlap(b, a)
    np.testing.assert_allclose(ab["normal"], -ba["normal"], atol=1e-12)
    assert ab["depth"] == pytest.approx(ba["depth"], abs=1e-12)
    assert ab["volume"] == pytest.approx(ba["volume"], abs=1e-12)


@pytest.mark.parametrize("lo", [[1, 0, 0], [1, 1, 1], [1.5, 0, 0]])
def test_touching_or_apart_blocks_have_none(lo):
    a = cube([0, 0, 0], [1, 1, 1])
    assert penedge.overlap(a, cube(lo, np.add(lo, 1))) is None


def test_a_bad_gap_is_an_error():
    a = cube([0, 0, 0], [1, 1, 1])
    with pytest.raises(penedge.ToleranceError):
        penedge.overlap(a, a, gap=-1.0)
