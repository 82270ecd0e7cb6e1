"""Property tests (hypothesis): rigid motions keep the contact type; no input crashes."""

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import penedge

import shapes

quaternions = st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 4).filter(
    lambda q: np.linalg.norm(q) > 0.1
)
translations = st.tuples(*[st.floats(-1e3, 1e3, allow_nan=False)] * 3)
FAST = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.parametrize("outcome", list(shapes.PAIRS))
@FAST
@given(q=quaternions, t=translations)
def test_rigid_motion_keeps_the_outcome_and_features(outcome, q, t):
    a, b = shapes.pair(outcome)
    before = penedge.detect_pair(a, b)
    rotation, translation = shapes.rotation_from_quaternion(q), np.array(t)
    after = penedge.detect_pair(
        shapes.moved(a, rotation, translation), shapes.moved(b, rotation, translation)
    )
    assert after.outcome == outcome
    assert (after.feature_a, after.feature_b) == (before.feature_a, before.feature_b)


@pytest.mark.parametrize("outcome", shapes.TOUCHING)
@FAST
@given(q=quaternions, t=translations, scale=st.sampled_from([1e-3, 1.0, 1e3]))
def test_system_detection_agrees_with_the_pair_after_motion(outcome, q, t, scale):
    a, b = shapes.pair(outcome)
    rotation, translation = shapes.rotation_from_quaternion(q) * scale, np.array(t)
    system = penedge.BlockSystem(
        [shapes.moved(a, rotation, translation), shapes.moved(b, rotation, translation)]
    )
    found = system.detect()
    assert found.pairs.tolist() == [[0, 1]]
    assert penedge.CONTACT_TYPES[found.types[0] - 1] == outcome


coordinates = st.floats(allow_nan=True, allow_infinity=True, width=64)


@settings(max_examples=300, deadline=None)
@given(
    vertices=hnp.arrays(np.float64, st.tuples(st.integers(0, 9), st.just(3)), elements=coordinates),
    faces=st.lists(st.lists(st.integers(0, 10), max_size=6), max_size=8),
)
def test_any_vertices_and_faces_give_a_block_or_a_penedge_error(vertices, faces):
    try:
        block, error = penedge.Block(vertices, faces), None
    except penedge.PenedgeError as e:
        block, error = None, e
    if error is not None:
        assert isinstance(error, ValueError)
        assert error.kind
    else:
        assert block.volume > 0


@settings(max_examples=200, deadline=None)
@given(
    normals=hnp.arrays(
        np.float64, st.tuples(st.integers(0, 10), st.just(3)), elements=st.floats(-2, 2)
    ),
    offsets=hnp.arrays(np.float64, st.integers(0, 10), elements=st.floats(-2, 2)),
)
def test_any_half_spaces_give_a_block_or_a_penedge_error(normals, offsets):
    try:
        block = penedge.Block.from_planes(normals, offsets)
    except penedge.PenedgeError:
        return
    assert block.volume > 0


def random_block(draw_points):
    """The convex hull of points, as half-spaces through the points' extreme directions."""
    directions = np.array(
        [
            [1, 0, 0],
            [-1, 0, 0],
            [0, 1, 0],
            [0, -1, 0],
            [0, 0, 1],
            [0, 0, -1],
            [1, 1, 1],
            [-1, -1, 1],
            [1, -1, -1],
            [-1, 1, -1],
        ],
        dtype=float,
    )
    offsets = (draw_points @ directions.T).max(axis=0)
    return penedge.Block.from_planes(directions, offsets)


@settings(max_examples=150, deadline=None)
@given(
    p=hnp.arrays(np.float64, (6, 3), elements=st.floats(-1, 1)),
    q=hnp.arrays(np.float64, (6, 3), elements=st.floats(-1, 1)),
    shift=st.tuples(*[st.floats(-2, 2)] * 3),
)
def test_random_pairs_answer_the_same_in_both_orders(p, q, shift):
    try:
        a, b = random_block(p), random_block(q + np.array(shift))
    except penedge.BlockError:
        assume(False)
    ab, ba = penedge.detect_pair(a, b), penedge.detect_pair(b, a)
    assert ab.outcome == ba.outcome
    assert ab.outcome in (*penedge.CONTACT_TYPES, "separated", "penetrating")
    assert (ab.feature_a, ab.feature_b) == (ba.feature_b, ba.feature_a)
