"""ParaView files read back by VTK's own readers: the blocks (VTU polyhedra), their faces
(VTU polygons), the contacts (VTP) and time series (PVD, through :class:`TimeSeries` and
:func:`write_pvd`), each compared with the API's arrays.

VTK has no reader of ``.pvd`` collections (ParaView's ``vtkPVDReader`` is not in the ``vtk``
wheel), so the index is parsed with the standard library's XML parser and every file it
lists is read with VTK. The checks of the index itself and of the errors need no VTK.
"""

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import penedge

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
VTK_POLYHEDRON, VTK_POLYGON, VTK_VERTEX, VTK_LINE = 42, 7, 1, 3
# VTK names the polygon cells of poly data by their number of points.
POLY_DATA_CELL = {1: VTK_VERTEX, 2: VTK_LINE, 3: 5, 4: 9}  # 5 triangle, 9 quad


def vtk_modules():
    xml = pytest.importorskip("vtkmodules.vtkIOXML")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    return xml, vtk_to_numpy


def read_vtu(path):
    xml, _ = vtk_modules()
    reader = xml.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    assert reader.GetErrorCode() == 0
    return reader.GetOutput()


def read_vtp(path):
    xml, _ = vtk_modules()
    reader = xml.vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    assert reader.GetErrorCode() == 0
    return reader.GetOutput()


def cell_array(data, name):
    _, vtk_to_numpy = vtk_modules()
    array = data.GetCellData().GetArray(name)
    assert array is not None, f"no cell array {name}"
    return vtk_to_numpy(array)


def face_stream(grid, cell):
    """The faces of polyhedron `cell` as lists of point ids."""
    from vtkmodules.vtkCommonCore import vtkIdList

    ids = vtkIdList()
    grid.GetFaceStream(cell, ids)
    stream = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
    faces, k = [], 1
    for _ in range(stream[0]):
        n = stream[k]
        faces.append(stream[k + 1 : k + 1 + n])
        k += n + 1
    assert k == len(stream)
    return faces


@pytest.fixture(scope="module")
def generated():
    system, _ = penedge.generate(EXAMPLES / "finite_polygon.toml")
    return system


@pytest.fixture(scope="module")
def example3():
    system = penedge.paper_example(3)
    return system, system.detect(geometry=True)


def check_blocks(grid, system):
    """The grid holds `system`: one polyhedron per block, its faces, and its cell data."""
    _, vtk_to_numpy = vtk_modules()
    a = system.arrays()
    assert grid.GetNumberOfCells() == len(system)
    assert grid.GetNumberOfPoints() == len(a.vertices)
    assert np.array_equal(vtk_to_numpy(grid.GetPoints().GetData()), a.vertices)
    assert {grid.GetCellType(i) for i in range(len(system))} == {VTK_POLYHEDRON}
    for i, block in enumerate(system.blocks):
        first = a.vertex_offsets[i]
        faces = [[v - first for v in face] for face in face_stream(grid, i)]
        assert faces == block.faces, i
    assert np.array_equal(cell_array(grid, "block_id"), np.arange(len(system)))
    assert np.array_equal(cell_array(grid, "volume"), system.volumes)
    assert np.array_equal(cell_array(grid, "n_faces"), np.diff(a.face_offsets))
    free = np.bincount(a.face_block[a.face_origin_kind == 1], minlength=len(system))
    assert np.array_equal(cell_array(grid, "n_free_faces"), free)


def check_contacts(poly, found):
    """The poly data holds `found`: a vertex, line or polygon cell per contact (by section),
    each with the contact's points, and the contact arrays in cell order."""
    _, vtk_to_numpy = vtk_modules()
    sizes = np.diff(found.point_offsets)
    counts = (poly.GetNumberOfVerts(), poly.GetNumberOfLines(), poly.GetNumberOfPolys())
    assert counts == ((sizes == 1).sum(), (sizes == 2).sum(), (sizes >= 3).sum())
    assert poly.GetNumberOfCells() == len(found)
    order = cell_array(poly, "contact")
    assert sorted(order.tolist()) == list(range(len(found)))
    assert np.array_equal(np.minimum(sizes[order], 3), np.sort(np.minimum(sizes, 3)))
    points = vtk_to_numpy(poly.GetPoints().GetData()) if len(found) else np.empty((0, 3))
    for cell, contact in enumerate(order):
        ids = poly.GetCell(cell).GetPointIds()
        cell_points = points[[ids.GetId(k) for k in range(ids.GetNumberOfIds())]]
        assert np.array_equal(cell_points, found.points_of(int(contact))), cell
        kind = POLY_DATA_CELL.get(int(sizes[contact]), VTK_POLYGON)
        assert poly.GetCellType(cell) == kind
    assert np.array_equal(cell_array(poly, "type"), found.types[order])
    assert np.array_equal(cell_array(poly, "block_a"), found.pairs[order, 0])
    assert np.array_equal(cell_array(poly, "block_b"), found.pairs[order, 1])
    assert np.array_equal(cell_array(poly, "area"), found.areas[order])
    assert np.array_equal(cell_array(poly, "distance"), found.distances[order])
    assert np.array_equal(cell_array(poly, "normal").reshape(-1, 3), found.normals[order])
    if len(found):
        assert poly.GetCellData().GetNormals().GetName() == "normal"
        assert poly.GetCellData().GetScalars().GetName() == "type"


def test_vtk_reads_the_blocks_as_polyhedra(generated, tmp_path):
    generated.write_vtu(tmp_path / "blocks.vtu")
    grid = read_vtu(tmp_path / "blocks.vtu")
    check_blocks(grid, generated)
    assert grid.GetCellData().GetScalars().GetName() == "block_id"


def test_vtk_computes_the_same_volumes(generated, tmp_path):
    """VTK's own volume of each polyhedron: the faces are closed and outward."""
    _, vtk_to_numpy = vtk_modules()
    verdict = pytest.importorskip("vtkmodules.vtkFiltersVerdict")
    generated.write_vtu(tmp_path / "blocks.vtu")
    sizes = verdict.vtkCellSizeFilter()
    sizes.SetInputData(read_vtu(tmp_path / "blocks.vtu"))
    sizes.ComputeVolumeOn()
    sizes.Update()
    volumes = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
    assert np.allclose(volumes, generated.volumes, rtol=1e-9, atol=0)


def test_vtk_reads_the_faces_with_their_origins(generated, tmp_path):
    _, vtk_to_numpy = vtk_modules()
    generated.write_faces_vtu(tmp_path / "faces.vtu")
    grid = read_vtu(tmp_path / "faces.vtu")
    a = generated.arrays()
    assert grid.GetNumberOfCells() == len(a.face_block)
    assert {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())} == {VTK_POLYGON}
    points = vtk_to_numpy(grid.GetPoints().GetData())
    loops = a.face_vertices
    for face in (0, len(a.face_block) // 2, len(a.face_block) - 1):
        ids = grid.GetCell(face).GetPointIds()
        got = points[[ids.GetId(k) for k in range(ids.GetNumberOfIds())]]
        start, end = a.loop_offsets[face], a.loop_offsets[face + 1]
        assert np.array_equal(got, a.vertices[loops[start:end]]), face
    assert np.array_equal(cell_array(grid, "block_id"), a.face_block)
    assert np.array_equal(cell_array(grid, "origin"), a.face_origin_kind)
    assert np.array_equal(cell_array(grid, "origin_set"), a.face_origin_set)
    assert np.array_equal(cell_array(grid, "origin_index"), a.face_origin_index)
    per_block = np.concatenate([np.arange(n) for n in np.diff(a.face_offsets)])
    assert np.array_equal(cell_array(grid, "face"), per_block)


def test_vtk_reads_the_contacts(example3, tmp_path):
    _, found = example3
    found.write_vtp(tmp_path / "contacts.vtp")
    poly = read_vtp(tmp_path / "contacts.vtp")
    check_contacts(poly, found)
    assert (poly.GetNumberOfVerts(), poly.GetNumberOfLines(), poly.GetNumberOfPolys()) == (
        205,
        78,
        42,
    )
    area = cell_array(poly, "area").sum()
    assert area == pytest.approx(300 + 300 * math.sqrt(2), rel=1e-12)


def pvd_datasets(path):
    """``(time, file)`` of each DataSet of a .pvd, parsed by the standard library."""
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile"
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def moved(system, shift):
    """The system with every block translated by `shift` (a rigid step of a simulation)."""
    return penedge.BlockSystem(
        [penedge.Block(b.vertices + np.asarray(shift), b.faces) for b in system.blocks]
    )


@pytest.fixture(scope="module")
def steps():
    """Three steps of different systems and contact sets: Examples 1 and 2, then
    Example 3 moved away from the origin."""
    systems = [penedge.paper_example(1), penedge.paper_example(2)]
    systems.append(moved(penedge.paper_example(3), [1000.0, -2000.0, 50.0]))
    return [(t, s, s.detect(geometry=True)) for t, s in zip((0.0, 0.25, 0.5), systems, strict=True)]


def test_a_time_series_lists_every_step_and_vtk_reads_each(steps, tmp_path):
    folder = tmp_path / "run" / "series"  # made with its parents
    series = penedge.TimeSeries(folder)
    for k, (time, system, found) in enumerate(steps):
        assert series.write_step(time, system, found) == k
    assert len(series) == 3
    assert np.array_equal(series.times, [0.0, 0.25, 0.5])
    assert np.array_equal(series.contact_times, series.times)
    assert series.folder == folder
    assert series.blocks_index == folder / "blocks.pvd"
    assert series.contacts_index == folder / "contacts.pvd"

    blocks = pvd_datasets(folder / "blocks.pvd")
    contacts = pvd_datasets(folder / "contacts.pvd")
    assert blocks == [(t, f"blocks_{k:06d}.vtu") for k, (t, _, _) in enumerate(steps)]
    assert contacts == [(t, f"contacts_{k:06d}.vtp") for k, (t, _, _) in enumerate(steps)]
    assert sorted(p.name for p in folder.iterdir()) == sorted(
        ["blocks.pvd", "contacts.pvd"] + [f for _, f in blocks] + [f for _, f in contacts]
    )  # no temporary file left

    vtk_modules()
    for (_, blocks_file), (_, contacts_file), (_, system, found) in zip(
        blocks, contacts, steps, strict=True
    ):
        check_blocks(read_vtu(folder / blocks_file), system)
        check_contacts(read_vtp(folder / contacts_file), found)


def test_steps_without_contacts_stay_out_of_the_contact_index(steps, tmp_path):
    series = penedge.TimeSeries(tmp_path)
    (t0, s0, f0), (t1, s1, _), (t2, s2, f2) = steps
    series.write_step(t0, s0, f0)
    series.write_step(t1, s1)
    series.write_step(t2, s2, f2)
    assert pvd_datasets(tmp_path / "contacts.pvd") == [
        (t0, "contacts_000000.vtp"),
        (t2, "contacts_000002.vtp"),
    ]
    assert np.array_equal(series.contact_times, [t0, t2])
    assert not (tmp_path / "contacts_000001.vtp").exists()
    assert len(pvd_datasets(tmp_path / "blocks.pvd")) == 3


def test_a_new_series_has_empty_indexes_and_an_existing_one_is_kept(steps, tmp_path):
    series = penedge.TimeSeries(tmp_path)
    assert len(series) == 0
    assert pvd_datasets(tmp_path / "blocks.pvd") == []
    assert pvd_datasets(tmp_path / "contacts.pvd") == []
    time, system, found = steps[0]
    series.write_step(time, system, found)
    before = (tmp_path / "blocks.pvd").read_bytes()
    with pytest.raises(FileExistsError, match="a time series is already there"):
        penedge.TimeSeries(tmp_path)
    assert (tmp_path / "blocks.pvd").read_bytes() == before


def test_a_series_resumes_after_its_last_step(steps, tmp_path):
    first = penedge.TimeSeries(tmp_path)
    for time, system, found in steps[:2]:
        first.write_step(time, system, found)
    resumed = penedge.TimeSeries(tmp_path, resume=True)
    assert len(resumed) == 2
    assert np.array_equal(resumed.times, [0.0, 0.25])
    with pytest.raises(penedge.InputError) as info:
        resumed.write_step(0.25, steps[2][1])
    assert info.value.kind == "time"
    time, system, found = steps[2]
    assert resumed.write_step(time, system, found) == 2
    assert [t for t, _ in pvd_datasets(tmp_path / "blocks.pvd")] == [0.0, 0.25, 0.5]
    check_contacts(read_vtp(tmp_path / "contacts_000002.vtp"), found)


def test_resuming_needs_a_series(tmp_path):
    with pytest.raises(FileNotFoundError):
        penedge.TimeSeries(tmp_path, resume=True)
    (tmp_path / "blocks.pvd").write_text("<VTKFile type='PolyData'/>", encoding="utf-8")
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.TimeSeries(tmp_path, resume=True)
    assert info.value.field.endswith("VTKFile.type")


@pytest.mark.parametrize("time", [math.nan, math.inf, -0.5, 0.0])
def test_a_time_not_after_the_last_is_refused_and_nothing_written(steps, tmp_path, time):
    series = penedge.TimeSeries(tmp_path)
    series.write_step(0.0, steps[0][1])
    before = sorted(tmp_path.iterdir())
    with pytest.raises(penedge.InputError) as info:
        series.write_step(time, steps[0][1])
    assert info.value.kind == "time"
    assert isinstance(info.value, ValueError)
    assert sorted(tmp_path.iterdir()) == before
    assert len(series) == 1


def test_contacts_must_belong_to_the_system_and_have_geometry(steps, tmp_path):
    series = penedge.TimeSeries(tmp_path)
    small, (_, big, big_found) = steps[0][1], steps[2]
    with pytest.raises(penedge.InputError, match="not of this system") as info:
        series.write_step(0.0, small, big_found)
    assert info.value.kind == "mismatch"
    with pytest.raises(penedge.InputError, match="geometry=True") as info:
        series.write_step(0.0, big, big.detect())
    assert info.value.kind == "no_geometry"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocks.pvd", "contacts.pvd"]
    assert len(series) == 0


def test_write_pvd_indexes_any_files(generated, example3, tmp_path):
    system, found = example3
    generated.write_vtu(tmp_path / "a.vtu")
    system.write_vtu(tmp_path / "b & c.vtu")  # escaped in the XML
    found.write_vtp(tmp_path / "contacts.vtp")
    penedge.write_pvd(tmp_path / "blocks.pvd", [(0, "a.vtu"), (1.5, Path("b & c.vtu"))])
    penedge.write_pvd(tmp_path / "contacts.pvd", [(1e-9, "contacts.vtp")])
    datasets = pvd_datasets(tmp_path / "blocks.pvd")
    assert datasets == [(0.0, "a.vtu"), (1.5, "b & c.vtu")]
    assert pvd_datasets(tmp_path / "contacts.pvd") == [(1e-9, "contacts.vtp")]
    vtk_modules()
    check_blocks(read_vtu(tmp_path / datasets[0][1]), generated)
    check_blocks(read_vtu(tmp_path / datasets[1][1]), system)
    check_contacts(read_vtp(tmp_path / "contacts.vtp"), found)


@pytest.mark.parametrize(
    ("datasets", "kind", "message"),
    [
        ([(1.0, "a.vtu"), (0.5, "b.vtu")], "time", "dataset 1: the times must increase"),
        ([(math.nan, "a.vtu")], "time", "dataset 0: the time must be finite"),
        ([(0.0, "")], "file_name", "dataset 0: empty file name"),
    ],
)
def test_write_pvd_refuses_bad_datasets(tmp_path, datasets, kind, message):
    with pytest.raises(penedge.InputError, match=message) as info:
        penedge.write_pvd(tmp_path / "x.pvd", datasets)
    assert info.value.kind == kind
    assert list(tmp_path.iterdir()) == []


def test_write_pvd_to_a_missing_folder_raises_os_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        penedge.write_pvd(tmp_path / "no" / "x.pvd", [(0.0, "a.vtu")])
