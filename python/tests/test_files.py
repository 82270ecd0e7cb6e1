"""Files: the JSON block file reads back bit for bit; VTU, VTP and CSV hold what they should
(read back with VTK's own readers where `vtk` is installed, and always with the standard
library's XML parser); bad files and unwritable paths raise clear errors."""

import csv
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import penedge

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def generated():
    system, _ = penedge.generate(EXAMPLES / "finite_polygon.toml")
    return system


@pytest.fixture(scope="module")
def example3():
    system = penedge.paper_example(3)
    return system, system.detect(geometry=True)


def assert_same_system(a, b):
    x, y = a.arrays(), b.arrays()
    for name in (
        "vertices",
        "vertex_offsets",
        "face_offsets",
        "loop_offsets",
        "face_vertices",
        "face_normals",
        "face_origin_kind",
        "face_origin_set",
        "face_origin_index",
        "volumes",
        "centroids",
    ):
        assert np.array_equal(getattr(x, name), getattr(y, name)), name
    assert a.sets == b.sets
    assert len(a.domain) == len(b.domain)
    assert np.array_equal(x.body_ids, y.body_ids)


def test_json_round_trip_is_lossless(generated, tmp_path):
    path = tmp_path / "blocks.json"
    generated.write_json(path)
    again = penedge.BlockSystem.read_json(path)
    assert_same_system(again, generated)
    assert again.detect().counts() == generated.detect().counts()
    assert_same_system(penedge.BlockSystem.from_json(generated.to_json()), generated)
    assert [p.name for p in tmp_path.iterdir()] == ["blocks.json"]  # no temporary left


# Every block file penedge writes reads back, whichever way the system was built
# (docs/block-file-format.md, "Face origins without a joint table").
JOINT, BRIDGE = 2, 3  # face origin codes


def from_blocks(system):
    """Blocks taken out of a system: their joint faces name sets and joints of a table the
    new system does not have."""
    return penedge.BlockSystem(list(system)[::2])


def from_arrays(system):
    a = system.arrays()
    origins = a.face_origin_kind, a.face_origin_set, a.face_origin_index
    offsets = a.vertex_offsets, a.face_offsets, a.loop_offsets
    return penedge.BlockSystem.from_arrays(
        a.vertices,
        *offsets,
        a.face_vertices,
        face_origin_kind=origins[0],
        face_origin_set=origins[1],
        face_origin_index=origins[2],
    )


def concave(_):
    cuboid = penedge.Block.cuboid
    parts = [
        cuboid([0, 0, 0], [3, 1, 1]),
        cuboid([0, 0, 1], [1, 1, 2]),
        cuboid([2, 0, 1], [3, 1, 2]),
    ]
    return penedge.BlockSystem([*parts, cuboid([1, 0, 1], [2, 1, 2.5])]).with_bodies([0, 0, 0, 1])


def concave_of_taken_blocks(system):
    return penedge.BlockSystem(list(system)[:2]).with_bodies([0, 1])


@pytest.fixture(scope="module")
def bridged():
    """A generated system with rock bridges (the step-path example's)."""
    from penedge.model import prepare

    return prepare(EXAMPLES / "models" / "slope_step_path.toml").system


BUILDS = [
    ("generated", lambda s: s),
    ("from_blocks", from_blocks),
    ("from_arrays", from_arrays),
    ("concave", concave),
    ("concave_of_taken_blocks", concave_of_taken_blocks),
]


@pytest.mark.parametrize("source", ["generated", "bridged"])
@pytest.mark.parametrize("build", [b for _, b in BUILDS], ids=[n for n, _ in BUILDS])
def test_every_block_file_written_reads_back(source, build, request, tmp_path):
    system = build(request.getfixturevalue(source))
    path = tmp_path / "blocks.json"
    system.write_json(path)
    assert_same_system(penedge.BlockSystem.read_json(path), system)
    assert_same_system(penedge.BlockSystem.from_json(system.to_json()), system)
    assert [p.name for p in tmp_path.iterdir()] == ["blocks.json"]


def test_blocks_taken_out_keep_the_origins_of_their_joint_and_bridge_faces(bridged, tmp_path):
    """The defect: a system of generated blocks has joint faces but no joint table; its
    file was refused on reading. The origins read back as written (their set numbers are
    what joint properties are given by)."""
    system = penedge.BlockSystem(list(bridged))
    a = system.arrays()
    assert (a.face_origin_kind == JOINT).any()
    assert (a.face_origin_kind == BRIDGE).any()
    assert system.sets == []
    system.write_json(tmp_path / "b.json")
    back = penedge.BlockSystem.read_json(tmp_path / "b.json").arrays()
    assert np.array_equal(back.face_origin_kind, a.face_origin_kind)
    assert np.array_equal(back.face_origin_set, a.face_origin_set)
    assert np.array_equal(back.face_origin_index, a.face_origin_index)


def test_json_accepts_str_paths_and_replaces_a_file(generated, tmp_path):
    path = tmp_path / "blocks.json"
    path.write_text("old", encoding="utf-8")
    generated.write_json(str(path))
    assert penedge.BlockSystem.read_json(str(path)).volumes.sum() == pytest.approx(1000)


BAD_FILES = {
    "not json": ("{blocks", "syntax", None),
    "empty": ("", "syntax", None),
    "another format": (
        '{"format": "x", "version": 1, "frame": "", "domain": [], "sets": [], "joints": [],'
        ' "blocks": []}',
        "format",
        "version",
    ),
}


@pytest.mark.parametrize("name", list(BAD_FILES))
def test_a_bad_block_file_raises_file_format_error(name, tmp_path):
    text, kind, field = BAD_FILES[name]
    path = tmp_path / "bad.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.read_json(path)
    assert info.value.kind == kind
    assert info.value.field == field
    assert "bad.json" in str(info.value)
    assert isinstance(info.value, ValueError)


def test_a_broken_block_is_named(generated, tmp_path):
    text = generated.to_json().replace('"faces":[[', '"faces":[[0,0,', 1)
    path = tmp_path / "broken.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.read_json(path)
    assert info.value.kind == "format"
    assert info.value.field == "domain[0]"


def test_missing_files_and_folders_raise_os_errors(generated, tmp_path):
    with pytest.raises(FileNotFoundError) as info:
        penedge.BlockSystem.read_json(tmp_path / "none.json")
    assert info.value.filename == str(tmp_path / "none.json")
    with pytest.raises(IsADirectoryError):
        penedge.BlockSystem.read_json(tmp_path)
    for write in (generated.write_json, generated.write_vtu, generated.write_csv):
        with pytest.raises(FileNotFoundError):
            write(tmp_path / "no" / "such" / "folder.out")
    assert list(tmp_path.iterdir()) == []


def xml_arrays(path):
    """The piece's attributes and every DataArray (by section/name) of a VTK XML file."""
    root = ET.parse(path).getroot()
    piece = root.find("./*/Piece")
    arrays = {}
    for section in piece:
        for array in section.iter("DataArray"):
            text = array.text or ""
            kind = float if array.get("type").startswith("Float") else int
            values = np.array([kind(x) for x in text.split()])
            components = int(array.get("NumberOfComponents", "1"))
            arrays[f"{section.tag}/{array.get('Name')}"] = values.reshape(-1, components)
    return piece.attrib, arrays


def test_vtu_of_the_blocks(generated, tmp_path):
    path = tmp_path / "blocks.vtu"
    generated.write_vtu(path)
    piece, arrays = xml_arrays(path)
    a = generated.arrays()
    assert int(piece["NumberOfCells"]) == len(generated)
    assert int(piece["NumberOfPoints"]) == len(a.vertices)
    assert (arrays["Cells/types"] == 42).all()
    assert np.array_equal(arrays["Points/Points"], a.vertices)
    assert np.array_equal(arrays["CellData/volume"].ravel(), a.volumes)
    assert arrays["CellData/block_id"].ravel().tolist() == list(range(len(generated)))


def test_vtu_of_the_faces_with_their_origins(generated, tmp_path):
    path = tmp_path / "faces.vtu"
    generated.write_faces_vtu(path)
    piece, arrays = xml_arrays(path)
    a = generated.arrays()
    assert int(piece["NumberOfCells"]) == len(a.face_block)
    assert np.array_equal(arrays["CellData/origin"].ravel(), a.face_origin_kind)
    assert np.array_equal(arrays["CellData/origin_set"].ravel(), a.face_origin_set)
    assert np.array_equal(arrays["CellData/block_id"].ravel(), a.face_block)


def test_vtp_of_the_contacts(example3, tmp_path):
    _, found = example3
    path = tmp_path / "contacts.vtp"
    found.write_vtp(path)
    piece, arrays = xml_arrays(path)
    sizes = np.diff(found.point_offsets)
    assert int(piece["NumberOfVerts"]) == (sizes == 1).sum() == 205
    assert int(piece["NumberOfLines"]) == (sizes == 2).sum() == 78
    assert int(piece["NumberOfPolys"]) == (sizes >= 3).sum() == 42
    assert int(piece["NumberOfPoints"]) == len(found.points)
    order = arrays["CellData/contact"].ravel()
    assert sorted(order.tolist()) == list(range(len(found)))
    assert np.array_equal(arrays["CellData/type"].ravel(), found.types[order])
    assert np.array_equal(arrays["CellData/block_a"].ravel(), found.pairs[order, 0])
    assert np.array_equal(arrays["CellData/normal"], found.normals[order])
    assert np.array_equal(arrays["CellData/area"].ravel(), found.areas[order])
    assert np.array_equal(arrays["Points/Points"], found.points)
    assert np.array_equal(arrays["Polys/offsets"].ravel(), np.cumsum(sizes[sizes >= 3]))


def test_vtk_reads_the_files_back(generated, example3, tmp_path):
    xml = pytest.importorskip("vtkmodules.vtkIOXML")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    generated.write_vtu(tmp_path / "blocks.vtu")
    reader = xml.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "blocks.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfCells() == len(generated)
    assert grid.GetCell(0).GetNumberOfFaces() == len(generated[0].faces)
    volumes = vtk_to_numpy(grid.GetCellData().GetArray("volume"))
    assert np.array_equal(volumes, generated.volumes)

    _, found = example3
    found.write_vtp(tmp_path / "contacts.vtp")
    reader = xml.vtkXMLPolyDataReader()
    reader.SetFileName(str(tmp_path / "contacts.vtp"))
    reader.Update()
    poly = reader.GetOutput()
    counts = (poly.GetNumberOfVerts(), poly.GetNumberOfLines(), poly.GetNumberOfPolys())
    assert counts == (205, 78, 42)
    data = poly.GetCellData()
    assert data.GetNormals().GetName() == "normal"
    area = vtk_to_numpy(data.GetArray("area")).sum()
    assert area == pytest.approx(300 + 300 * math.sqrt(2), rel=1e-12)


def test_block_table_csv(generated, tmp_path):
    path = tmp_path / "blocks.csv"
    generated.write_csv(path)
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert table.dtype.names == (
        "id",
        "volume",
        "centroid_x",
        "centroid_y",
        "centroid_z",
        "n_faces",
        "n_free_faces",
    )
    assert np.array_equal(table["volume"], generated.volumes)
    assert np.array_equal(table["centroid_y"], generated.centroids[:, 1])
    free = np.bincount(generated.arrays().face_block[generated.arrays().face_origin_kind == 1])
    assert np.array_equal(table["n_free_faces"], free)


def region_centroid(points, normal):
    """The centroid of a point, a segment or a convex polygon (by the shoelace formula in the
    polygon's plane), computed here independently of the writer."""
    if len(points) < 3:
        return points.mean(axis=0)
    u = points[1] - points[0]
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    x, y = (points - points[0]) @ u, (points - points[0]) @ v
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = cross.sum() / 2
    cx = ((x + np.roll(x, -1)) * cross).sum() / (6 * area)
    cy = ((y + np.roll(y, -1)) * cross).sum() / (6 * area)
    return points[0] + cx * u + cy * v


def feature_set_names(system, block, kind, index):
    """The names of where the faces at a contact feature come from (the expected `set_a`)."""
    arrays = system.arrays()
    b = system[block]
    if kind == 2:
        faces = [index]
    elif kind == 1:
        faces = list(b.edge_faces[index])
    else:
        faces = [f for f, loop in enumerate(b.faces) if index in loop]
    names = []
    for f in faces:
        g = arrays.face_offsets[block] + f
        origin = arrays.face_origin_kind[g]
        name = {1: "boundary", 2: system.sets[arrays.face_origin_set[g]]["name"]}.get(origin)
        if name is not None and name not in names:
            names.append(name)
    return "|".join(names)


def test_contacts_csv(example3, tmp_path):
    system, found = example3
    path = tmp_path / "contacts.csv"
    found.write_csv(path)
    with path.open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == [
        "block_a",
        "block_b",
        "type",
        "type_code",
        "point_x",
        "point_y",
        "point_z",
        "normal_x",
        "normal_y",
        "normal_z",
        "distance",
        "area",
        "n_points",
        "set_a",
        "set_b",
        "body_a",
        "body_b",
    ]
    assert len(rows) == len(found) == 325
    column = lambda name, kind=float: np.array([kind(r[name]) for r in rows])  # noqa: E731
    assert np.array_equal(column("block_a", int), found.pairs[:, 0])
    assert np.array_equal(column("type_code", int), found.types)
    assert [r["type"] for r in rows] == [penedge.CONTACT_TYPES[t - 1] for t in found.types]
    assert np.array_equal(column("normal_z"), found.normals[:, 2])  # exact: shortest repr
    assert np.array_equal(column("area"), found.areas)
    assert np.array_equal(column("n_points", int), np.diff(found.point_offsets))
    points = np.column_stack([column(f"point_{k}") for k in "xyz"])
    for i in range(len(found)):
        expected = region_centroid(found.points_of(i), found.normals[i])
        assert np.allclose(points[i], expected, rtol=0, atol=1e-12)
    # Example 3's blocks touch exactly: every distance is rounding noise within the gap.
    assert {r["distance"] for r in rows} == {"0"}
    for r, (a, b), (ka, kb), (ia, ib) in zip(
        rows, found.pairs, found.feature_kinds, found.feature_ids, strict=True
    ):
        assert r["set_a"] == feature_set_names(system, a, ka, ia)
        assert r["set_b"] == feature_set_names(system, b, kb, ib)
    face_face = [r for r in rows if r["type"] == "face-face"]
    assert all(r["set_a"] == r["set_b"] and r["set_a"].startswith("plane ") for r in face_face)


def test_contacts_csv_distances_and_sets_of_a_generated_system(tmp_path):
    # Two cubes 1 mm apart, found with a gap of 0.5 %: the distance (1.001 - 1 in floating
    # point) is written as it is, not snapped to 0 by the large gap; blocks made by hand
    # have no joint sets.
    pair = penedge.BlockSystem(
        [penedge.Block.cuboid([0, 0, 0], [1, 1, 1]), penedge.Block.cuboid([1.001, 0, 0], [2, 1, 1])]
    )
    pair.detect(gap=5e-3, geometry=True).write_csv(tmp_path / "gap.csv")
    with (tmp_path / "gap.csv").open(newline="", encoding="utf-8") as f:
        (row,) = list(csv.DictReader(f))
    assert float(row["distance"]) == pytest.approx(0.001, abs=1e-15)
    # 1e-13 apart, with the default gap (1e-12 x size): rounding, written as 0.
    near = penedge.BlockSystem(
        [
            penedge.Block.cuboid([0, 0, 0], [1, 1, 1]),
            penedge.Block.cuboid([1 + 1e-13, 0, 0], [2, 1, 1]),
        ]
    )
    near.detect(geometry=True).write_csv(tmp_path / "near.csv")
    with (tmp_path / "near.csv").open(newline="", encoding="utf-8") as f:
        (row_near,) = list(csv.DictReader(f))
    assert row_near["distance"] == "0"
    assert (row["set_a"], row["set_b"]) == ("", "")  # blocks made by hand: no provenance
    assert (row["point_y"], row["point_z"]) == ("0.5", "0.5")
    assert 1 <= float(row["point_x"]) <= 1.001


def test_contact_files_need_the_geometry(tmp_path):
    found = penedge.paper_example(1).detect()
    for write in (found.write_csv, found.write_vtp):
        with pytest.raises(penedge.InputError, match="geometry=True") as info:
            write(tmp_path / "contacts.csv")
        assert info.value.kind == "no_geometry"
    assert list(tmp_path.iterdir()) == []
