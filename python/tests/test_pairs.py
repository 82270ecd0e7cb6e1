"""detect_pair on hand-made pairs: the seven types in both orders, separated, penetrating."""

import numpy as np
import pytest

import penedge

import shapes


@pytest.mark.parametrize("outcome", list(shapes.PAIRS))
@pytest.mark.parametrize("swap", [False, True], ids=["AB", "BA"])
def test_outcome_in_both_orders(outcome, swap):
    a, b = shapes.pair(outcome)
    if swap:
        a, b = b, a
    result = penedge.detect_pair(a, b)
    assert result.outcome == outcome
    assert result.touching == (outcome in penedge.CONTACT_TYPES)


@pytest.mark.parametrize("outcome", shapes.TOUCHING)
def test_type_code_names_the_type(outcome):
    result = penedge.detect_pair(*shapes.pair(outcome))
    assert penedge.CONTACT_TYPES[result.type_code - 1] == outcome


@pytest.mark.parametrize("outcome", shapes.TOUCHING)
def test_features_have_the_expected_kinds_and_swap_with_the_blocks(outcome):
    a, b = shapes.pair(outcome)
    ab, ba = penedge.detect_pair(a, b), penedge.detect_pair(b, a)
    kind_a, kind_b = shapes.FEATURE_KINDS[outcome]
    assert ab.feature_a[0] == kind_a
    assert ab.feature_b[0] == kind_b
    assert (ba.feature_a, ba.feature_b) == (ab.feature_b, ab.feature_a)


def test_features_name_the_touching_elements():
    cube = shapes.cube()
    corner = penedge.detect_pair(cube, penedge.Block.cuboid([1, 1, 1], [2, 2, 2]))
    assert corner.feature_a == ("vertex", 6)
    assert cube.vertices[6].tolist() == [1, 1, 1]
    on_edge = penedge.detect_pair(*shapes.pair("vertex-edge"))
    kind, edge = on_edge.feature_a
    assert kind == "edge"
    assert set(cube.edges[edge].tolist()) == {4, 5}  # (0, 0, 1)-(1, 0, 1)
    on_face = penedge.detect_pair(*shapes.pair("face-face"))
    face = on_face.feature_a[1]
    assert cube.face_normals[face].tolist() == [0, 0, 1]


@pytest.mark.parametrize("outcome", ["separated", "penetrating"])
def test_no_contact_has_no_features(outcome):
    result = penedge.detect_pair(*shapes.pair(outcome))
    assert result.feature_a is None
    assert result.feature_b is None
    assert not result.touching
    expected = penedge.SEPARATED if outcome == "separated" else penedge.PENETRATING
    assert result.type_code == expected


def test_penetration_edges_of_a_face_face_contact():
    # The small box stands on the cube's top face: its four bottom edges lie in the face
    # (Table 1 type 1), its four vertical edges leave it at once (type 3 stubs of the gap).
    result = penedge.detect_pair(*shapes.pair("face-face"))
    edges = result.penetration_edges
    assert edges.dtype.names == (
        "side",
        "edge",
        "t0",
        "t1",
        "end0_kind",
        "end0",
        "end1_kind",
        "end1",
        "type",
    )
    assert set(edges["side"]) == {"B"}
    assert sorted(edges["type"].tolist()) == [1, 1, 1, 1, 3, 3, 3, 3]
    whole = edges[edges["type"] == 1]
    assert np.all(whole["end0_kind"] == "vertex")
    assert np.all(whole["end1_kind"] == "vertex")
    assert np.allclose(whole["t1"] - whole["t0"], 1)
    by_type, originals = result.table1_counts()
    assert by_type.tolist() == [[0, 0, 0, 0, 0], [4, 0, 4, 0, 0]]
    assert originals.tolist() == [0, 4]


def test_penetration_points_lie_on_the_parent_edges():
    a, b = shapes.pair("edge-edge-superposition")
    result = penedge.detect_pair(a, b)
    points = result.penetration_points
    assert points.shape == (len(result.penetration_edges), 2, 3)
    for record, ends in zip(result.penetration_edges, points, strict=True):
        owner = a if record["side"] == "A" else b
        p, q = owner.vertices[owner.edges[record["edge"]]]
        expected = [p + record["t0"] * (q - p), p + record["t1"] * (q - p)]
        assert np.allclose(ends, expected)


def test_separated_by_a_face_plane_has_no_penetration_edges():
    result = penedge.detect_pair(*shapes.pair("separated"))
    assert len(result.penetration_edges) == 0
    assert result.penetration_points.shape == (0, 2, 3)


def test_gap_turns_a_small_distance_into_contact():
    a = shapes.cube()
    b = penedge.Block.cuboid([1.001, 0, 0], [2, 1, 1])
    assert penedge.detect_pair(a, b).outcome == "separated"
    assert penedge.detect_pair(a, b, gap=1e-3).outcome == "face-face"
    assert penedge.detect_pair(a, b, gap=1e-3, length=1e-2).outcome == "face-face"


def test_absolute_gap_is_a_length():
    # 2 mm apart: an absolute gap of 3 mm makes blocks of 1 m and of 10 m touch, 1 mm does
    # not; a relative gap of 1e-3 (of the 1.7 m or 17 m diagonal) only the larger ones.
    for size, relative in ((1.0, "separated"), (10.0, "face-face")):
        a = penedge.Block.cuboid([0, 0, 0], [size, size, size])
        b = penedge.Block.cuboid([size + 0.002, 0, 0], [2 * size, size, size])
        assert penedge.detect_pair(a, b, absolute_gap=0.003).outcome == "face-face"
        assert penedge.detect_pair(a, b, absolute_gap=0.001).outcome == "separated"
        assert penedge.detect_pair(a, b, gap=1e-3).outcome == relative
        system = penedge.BlockSystem([a, b])
        assert len(system.detect(absolute_gap=0.003)) == 1
        assert len(penedge.ContactTracker(system, absolute_gap=0.003).contacts.pairs) == 1


def test_repr_names_outcome_and_features():
    text = repr(penedge.detect_pair(*shapes.pair("vertex-face")))
    assert text.startswith("PairContact('vertex-face', feature_a=('face', 1)")
