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


def test_json_round_trip_is_lossless(generated, tmp_path):
    path = tmp_path / "blocks.json"
    generated.write_json(path)
    again = penedge.BlockSystem.read_json(path)
    assert_same_system(again, generated)
    assert again.detect().counts() == generated.detect().counts()
    assert_same_system(penedge.BlockSystem.from_json(generated.to_json()), generated)
    assert [p.name for p in tmp_path.iterdir()] == ["blocks.json"]  # no temporary left


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


def test_contacts_csv(example3, tmp_path):
    _, found = example3
    path = tmp_path / "contacts.csv"
    found.write_csv(path)
    with path.open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == [
        "block_a",
        "block_b",
        "type",
        "type_code",
        "normal_x",
        "normal_y",
        "normal_z",
        "distance",
        "area",
        "n_points",
    ]
    assert len(rows) == len(found) == 325
    column = lambda name, kind=float: np.array([kind(r[name]) for r in rows])  # noqa: E731
    assert np.array_equal(column("block_a", int), found.pairs[:, 0])
    assert np.array_equal(column("type_code", int), found.types)
    assert [r["type"] for r in rows] == [penedge.CONTACT_TYPES[t - 1] for t in found.types]
    assert np.array_equal(column("normal_z"), found.normals[:, 2])  # exact: shortest repr
    assert np.array_equal(column("area"), found.areas)
    assert np.array_equal(column("n_points", int), np.diff(found.point_offsets))


def test_contact_files_need_the_geometry(tmp_path):
    found = penedge.paper_example(1).detect()
    for write in (found.write_csv, found.write_vtp):
        with pytest.raises(penedge.InputError, match="geometry=True") as info:
            write(tmp_path / "contacts.csv")
        assert info.value.kind == "no_geometry"
    assert list(tmp_path.iterdir()) == []
