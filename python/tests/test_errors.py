"""Every bad input raises a clear Python exception (never a panic, never a crash)."""

import math

import numpy as np
import pytest

import penedge

import shapes

CUBE = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
V, F = CUBE.vertices, CUBE.faces


def test_exception_tree():
    assert issubclass(penedge.PenedgeError, Exception)
    classes = (penedge.InputError, penedge.BlockError, penedge.ToleranceError)
    for cls in (*classes, penedge.SpecError, penedge.FileFormatError, penedge.MechanicsError):
        assert issubclass(cls, penedge.PenedgeError)
        assert issubclass(cls, ValueError)
        assert cls.__module__ == "penedge"
        assert cls.__doc__
        assert cls("message").field is None  # set when the error names a field


BAD_VERTICES = {
    "two columns": (np.zeros((8, 2)), "shape"),
    "one point": ([0.0, 0.0, 0.0], "shape"),
    "three axes": (np.zeros((2, 4, 3)), "shape"),
    "scalar": (3.0, "shape"),
    "ragged": ([[0, 0, 0], [1, 0]], "dtype"),
    "strings": ([["a", "b", "c"]] * 4, "dtype"),
    "complex": (np.zeros((8, 3), dtype=complex), "dtype"),
    "bool": (np.zeros((8, 3), dtype=bool), "dtype"),
    "None": (None, "dtype"),
}


@pytest.mark.parametrize("name", list(BAD_VERTICES))
def test_bad_vertex_arrays(name):
    vertices, kind = BAD_VERTICES[name]
    with pytest.raises(penedge.InputError) as info:
        penedge.Block(vertices, F)
    assert info.value.kind == kind
    assert "vertices" in str(info.value)


@pytest.mark.parametrize(
    "faces",
    [5, "abc", [[0, 1, -2]], [[0.0, 1.0, 2.0]], [[0, 1, None]], [0, 1, 2]],
    ids=["int", "str", "negative", "floats", "None", "flat"],
)
def test_bad_face_lists(faces):
    with pytest.raises(penedge.InputError, match="faces") as info:
        penedge.Block(V, faces)
    assert info.value.kind == "faces"


def with_vertex(i, value):
    v = V.copy()
    v[i] = value
    return v


BAD_BLOCKS = {
    "nan": (with_vertex(3, [np.nan, 1, 0]), F, "non_finite_vertex"),
    "inf": (with_vertex(3, [np.inf, 1, 0]), F, "non_finite_vertex"),
    "index out of range": (V, [*F[:-1], [3, 0, 4, 8]], "vertex_index_out_of_range"),
    "open": (V, F[:-1], "open_surface"),
    "inward": (V, [f[::-1] for f in F], "wrong_orientation"),
    "repeated vertex": (with_vertex(1, [0, 0, 0]), F, "repeated_vertex"),
    "non-planar face": (with_vertex(6, [1.1, 1, 1]), F, "non_planar_face"),
    "too small": (V[:3], [[0, 1, 2]], "too_small"),
    "empty": (np.zeros((0, 3)), [], "too_small"),
    "face listed twice": (V, [[0, 3, 3, 1], *F[1:]], "degenerate_face_list"),
}


@pytest.mark.parametrize("name", list(BAD_BLOCKS))
def test_invalid_blocks(name):
    vertices, faces, kind = BAD_BLOCKS[name]
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block(vertices, faces)
    assert info.value.kind == kind
    assert str(info.value)


BOX_NORMALS = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]


@pytest.mark.parametrize(
    ("normals", "offsets", "error", "kind"),
    [
        (BOX_NORMALS, [1, 0, 1, 0, 1], penedge.InputError, "shape"),
        (BOX_NORMALS, np.ones((6, 1)), penedge.InputError, "shape"),
        ([[0, 0, 0], *BOX_NORMALS[1:]], [1, 0, 1, 0, 1, 0], penedge.BlockError, "degenerate_plane"),
        (
            [[math.nan, 0, 0], *BOX_NORMALS[1:]],
            [1, 0, 1, 0, 1, 0],
            penedge.BlockError,
            "degenerate_plane",
        ),
        (BOX_NORMALS, [1, 0, 1, 0, math.inf, 0], penedge.BlockError, "degenerate_plane"),
        (BOX_NORMALS[:5], [1, 0, 1, 0, 1], penedge.BlockError, "unbounded"),
        (BOX_NORMALS, [1, 0, 1, 0, -1, 0], penedge.BlockError, "unbounded"),
    ],
    ids=["lengths", "offsets 2-D", "zero normal", "nan normal", "inf offset", "open", "empty"],
)
def test_bad_half_spaces(normals, offsets, error, kind):
    with pytest.raises(error) as info:
        penedge.Block.from_planes(normals, offsets)
    assert info.value.kind == kind


@pytest.mark.parametrize(
    ("lo", "hi", "kind"),
    [
        ([0, 0, 0], [0, 1, 1], "corners"),
        ([1, 0, 0], [0, 1, 1], "corners"),
        ([math.nan, 0, 0], [1, 1, 1], "corners"),
        ([0, 0, -math.inf], [1, 1, 1], "corners"),
        ([0, 0], [1, 1, 1], "shape"),
        ("abc", [1, 1, 1], "dtype"),
    ],
)
def test_bad_cuboid_corners(lo, hi, kind):
    with pytest.raises(penedge.InputError) as info:
        penedge.Block.cuboid(lo, hi)
    assert info.value.kind == kind


@pytest.mark.parametrize(
    ("gap", "length", "kind"),
    [
        (-1e-9, None, "out_of_range"),
        (math.nan, None, "out_of_range"),
        (math.inf, None, "out_of_range"),
        (0.5, None, "out_of_range"),
        (1e-6, 1e-6, "length_below_gap"),
        (1e-9, math.nan, "out_of_range"),
        (1e-9, 0.2, "out_of_range"),
        (0.05, None, "out_of_range"),  # the default length 10 x gap would be 0.5
    ],
)
def test_bad_tolerances(gap, length, kind):
    a, b = shapes.pair("face-face")
    with pytest.raises(penedge.ToleranceError) as info:
        penedge.detect_pair(a, b, gap=gap, length=length)
    assert info.value.kind == kind
    with pytest.raises(penedge.ToleranceError):
        penedge.paper_example(1).detect(gap=gap, length=length)


@pytest.mark.parametrize(
    ("options", "kind"),
    [
        ({"absolute_gap": -1e-3}, "absolute_gap"),
        ({"absolute_gap": math.nan}, "absolute_gap"),
        ({"absolute_gap": math.inf}, "absolute_gap"),
        ({"absolute_gap": 1e-3, "gap": 1e-6}, "both_gaps"),
    ],
)
def test_bad_absolute_gaps(options, kind):
    a, b = shapes.pair("face-face")
    with pytest.raises(penedge.ToleranceError) as info:
        penedge.detect_pair(a, b, **options)
    assert info.value.kind == kind
    system = penedge.paper_example(1)
    with pytest.raises(penedge.ToleranceError):
        system.detect(**options)
    with pytest.raises(penedge.ToleranceError):
        penedge.ContactTracker(system, **options)


@pytest.mark.parametrize(
    "call",
    [
        lambda: penedge.detect_pair(CUBE, "block"),
        lambda: penedge.detect_pair(CUBE),
        lambda: penedge.detect_pair(CUBE, CUBE, gap="big"),
        lambda: penedge.BlockSystem([CUBE, 1]),
        lambda: penedge.BlockSystem("blocks"),
        lambda: penedge.paper_example("1"),
    ],
    ids=["not a block", "one block", "gap str", "not blocks", "str", "example str"],
)
def test_wrong_argument_types_raise_type_error(call):
    with pytest.raises(TypeError):
        call()


@pytest.mark.parametrize("n", [0, 4, -1])
def test_unknown_paper_example(n):
    for function in (penedge.paper_example, penedge.paper_table3, penedge.paper_example_planes):
        with pytest.raises(penedge.InputError, match="1, 2 and 3"):
            function(n)


@pytest.mark.parametrize(
    ("normals", "offsets"),
    [([[0, 0, 0]], [1]), ([[1, 0, 0]], [math.nan]), ([[math.inf, 0, 0]], [1])],
)
def test_degenerate_cutting_planes(normals, offsets):
    with pytest.raises(penedge.InputError) as info:
        penedge.BlockSystem.from_box_cut([0, 0, 0], [1, 1, 1], normals, offsets)
    assert info.value.kind == "degenerate_plane"


def test_cutting_planes_shape_mismatch():
    with pytest.raises(penedge.InputError, match="same length"):
        penedge.BlockSystem.from_box_cut([0, 0, 0], [1, 1, 1], [[1, 0, 0]], [0.5, 0.6])
