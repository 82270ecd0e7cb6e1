"""A ParaView time series of a simulation: the blocks of each frame as a VTU file (one
polyhedron cell per block) with their displacement, velocity and a moving flag as cell
data, listed by ``blocks.pvd``; and the sub-contacts of each frame as a VTP file (one
vertex per sub-contact, with its normal and shear force, state and area, and its contact's
water force), listed by ``subcontacts.pvd``; and, for a model with rock bolts, the bolt
elements of each frame as a VTP file (one line per element, with its axial force,
elongation and state), listed by ``bolts.pvd`` (the indexes written with
:func:`penedge.write_pvd`).

Each frame's file is written (atomically) before the index that lists it, so ParaView can
watch a running simulation, and a run stopped with Ctrl-C leaves a series of complete
frames.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

VTK_POLYHEDRON = 42


def _ints(values: np.ndarray) -> str:
    return " ".join(map(str, np.asarray(values, dtype=np.int64).tolist()))


def _floats(values: np.ndarray) -> str:
    return " ".join(f"{v:.9g}" for v in np.asarray(values, dtype=float).ravel().tolist())


def vtu_text(
    system: Any,
    displacement: np.ndarray,
    velocity: np.ndarray,
    moving: np.ndarray,
    excavated: np.ndarray | None = None,
) -> str:
    """The VTU file of `system` with per-block ``block_id``, ``body_id`` (the parts of a
    concave block share one), ``displacement`` (m, vector and ``displacement_magnitude``),
    ``velocity`` (m/s) and ``moving`` (0/1) cell data, and
    ``excavated`` (0/1: removed by an excavate stage; threshold it away in ParaView) when
    given."""
    a = system.arrays()
    vertices = np.asarray(a.vertices)
    vertex_offsets = np.asarray(a.vertex_offsets)
    face_offsets = np.asarray(a.face_offsets)
    loops = np.asarray(a.loop_offsets)
    face_vertices = np.asarray(a.face_vertices)
    n = len(vertex_offsets) - 1
    face_block = np.asarray(a.face_block)
    # the polyhedron faces stream, per cell: n_faces, then per face n_points and its points;
    # placed without a loop: before face f's points come f face headers and b + 1 block
    # headers (b its block) and the points of the faces before it
    n_faces = len(loops) - 1
    corner_face = np.repeat(np.arange(n_faces), np.diff(loops))
    block_start = face_offsets + loops[face_offsets] + np.arange(n + 1)
    faces = np.empty(block_start[-1], dtype=np.int64)
    faces[block_start[:-1]] = np.diff(face_offsets)
    header = loops[:-1] + np.arange(n_faces) + face_block + 1
    faces[header] = np.diff(loops)
    faces[np.arange(len(face_vertices)) + corner_face + face_block[corner_face] + 2] = face_vertices
    stream_offsets = block_start[1:]
    magnitude = np.linalg.norm(displacement, axis=1)
    cells = [
        _array("Int64", "connectivity", _ints(np.arange(len(vertices)))),
        _array("Int64", "offsets", _ints(vertex_offsets[1:])),
        _array("UInt8", "types", _ints(np.full(n, VTK_POLYHEDRON))),
        _array("Int64", "faces", _ints(faces)),
        _array("Int64", "faceoffsets", _ints(np.array(stream_offsets))),
    ]
    data = [
        _array("Int64", "block_id", _ints(np.arange(n))),
        _array("Int64", "body_id", _ints(np.asarray(system.body_ids))),
        _array("Float64", "displacement", _floats(displacement), 3),
        _array("Float64", "displacement_magnitude", _floats(magnitude)),
        _array("Float64", "velocity", _floats(velocity), 3),
        _array("UInt8", "moving", _ints(moving.astype(np.uint8))),
    ]
    if excavated is not None:
        data.append(_array("UInt8", "excavated", _ints(excavated.astype(np.uint8))))
    return "\n".join(
        [
            '<?xml version="1.0"?>',
            '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">',
            "<UnstructuredGrid>",
            f'<Piece NumberOfPoints="{len(vertices)}" NumberOfCells="{n}">',
            "<Points>",
            _array("Float64", "points", _floats(vertices), 3),
            "</Points>",
            "<Cells>",
            *cells,
            "</Cells>",
            '<CellData Scalars="displacement_magnitude" Vectors="displacement">',
            *data,
            "</CellData>",
            "</Piece>",
            "</UnstructuredGrid>",
            "</VTKFile>",
            "",
        ]
    )


#: Sub-contact states, by code (the engine's): elastic, sliding, open.
STATES = ("elastic", "sliding", "open")


def vtp_text(contacts: dict[str, Any]) -> str:
    """The VTP file of the sub-contacts in the engine's `contacts` dict: one vertex per
    sub-contact at its point; point data ``normal_force`` (N, compression positive; the
    joint's effective force, without the water's), ``shear_force`` (N, vector), ``state`` (0
    elastic, 1 sliding, 2 open), ``area`` (m2), ``contact`` (its contact's row), the
    contact's ``normal`` and the contact's ``water_force`` (N, pushing the second block from
    the first along ``normal``; 0 without water). ``normal`` and ``water_force`` belong to
    the contact and are repeated on each of its sub-contacts: the water force is not shared
    out, so sum it over contacts, not over points."""
    points = np.asarray(contacts["points"], dtype=float).reshape(-1, 3)
    k = len(points)
    offsets = np.asarray(contacts["sub_offsets"], dtype=np.int64)
    contact = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    normals = np.asarray(contacts["normals"], dtype=float).reshape(-1, 3)[contact]
    data = [
        _array("Float64", "normal_force", _floats(contacts["normal_forces"])),
        _array("Float64", "shear_force", _floats(contacts["shear_forces"]), 3),
        _array("UInt8", "state", _ints(contacts["states"])),
        _array("Float64", "area", _floats(contacts["areas"])),
        _array("Int64", "contact", _ints(contact)),
        _array("Float64", "normal", _floats(normals), 3),
        _array("Float64", "water_force", _floats(np.asarray(contacts["water_forces"])[contact])),
    ]
    return _polydata_text(
        points,
        cells=("Verts", np.arange(k), np.arange(1, k + 1)),
        data=("PointData", 'Scalars="normal_force" Vectors="shear_force"', data),
    )


#: Bolt element states, by code (the engine's): elastic, yielding, broken.
BOLT_STATES = ("elastic", "yielding", "broken")


def bolts_vtp_text(bolts: dict[str, Any]) -> str:
    """The VTP file of the bolt elements in the engine's `bolts` dict
    (``Simulation.bolts()``): one line per element, from its anchor in its first body to its
    anchor in its second (where they are now); cell data ``bolt`` (the bolt's number, in the
    model's order), ``force`` (N, axial, tension > 0), ``elongation`` (m), ``state`` (0
    elastic, 1 yielding, 2 broken), ``rest_length`` (m) and ``shear_force`` (N, vector: the
    dowel's force on the second body)."""
    starts = np.asarray(bolts["starts"], dtype=float).reshape(-1, 3)
    ends = np.asarray(bolts["ends"], dtype=float).reshape(-1, 3)
    k = len(starts)
    points = np.stack([starts, ends], axis=1).reshape(-1, 3)
    data = [
        _array("Int64", "bolt", _ints(bolts["bolt"])),
        _array("Float64", "force", _floats(bolts["forces"])),
        _array("Float64", "elongation", _floats(bolts["elongations"])),
        _array("UInt8", "state", _ints(bolts["states"])),
        _array("Float64", "rest_length", _floats(bolts["rest_lengths"])),
        _array("Float64", "shear_force", _floats(bolts["shear_forces"]), 3),
    ]
    return _polydata_text(
        points,
        cells=("Lines", np.arange(2 * k), np.arange(2, 2 * k + 1, 2)),
        data=("CellData", 'Scalars="force"', data),
    )


def _polydata_text(
    points: np.ndarray,
    cells: tuple[str, np.ndarray, np.ndarray],
    data: tuple[str, str, list[str]],
) -> str:
    """A VTP file in ASCII: `points` (n, 3), one kind of cells (``"Verts"`` or ``"Lines"``,
    their connectivity and offsets) and the data arrays (``"PointData"`` or ``"CellData"``,
    the element's attributes, the ``<DataArray>`` elements)."""
    kind, connectivity, offsets = cells
    section, attributes, arrays = data
    return "\n".join(
        [
            '<?xml version="1.0"?>',
            '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian">',
            "<PolyData>",
            f'<Piece NumberOfPoints="{len(points)}" NumberOf{kind}="{len(offsets)}">',
            "<Points>",
            _array("Float64", "points", _floats(points), 3),
            "</Points>",
            f"<{kind}>",
            _array("Int64", "connectivity", _ints(connectivity)),
            _array("Int64", "offsets", _ints(offsets)),
            f"</{kind}>",
            f"<{section} {attributes}>",
            *arrays,
            f"</{section}>",
            "</Piece>",
            "</PolyData>",
            "</VTKFile>",
            "",
        ]
    )


def _array(kind: str, name: str, text: str, components: int = 1) -> str:
    """One ``<DataArray>`` element in ASCII."""
    return (
        f'<DataArray type="{kind}" Name="{name}" NumberOfComponents="{components}" '
        f'format="ascii">{text}</DataArray>'
    )


def write_text_atomically(path: Path, text: str) -> None:
    """Writes `text` to a temporary file beside `path`, then renames it over `path`."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        umask = os.umask(0)
        os.umask(umask)
        Path(tmp).chmod(0o666 & ~umask)  # mkstemp makes it private; a frame is an ordinary file
        Path(tmp).replace(path)
    finally:
        Path(tmp).unlink(missing_ok=True)


class Series:
    """Frames of a simulation in `folder` (made if needed): ``blocks_NNNNNN.vtu`` and the
    index ``blocks.pvd``.

    Parameters
    ----------
    folder : path
    speed : float
        A block is *moving* when its speed exceeds this (m/s).
    """

    def __init__(self, folder: Path, speed: float) -> None:
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.speed = speed
        self.entries: list[tuple[float, Path]] = []
        self.contact_entries: list[tuple[float, Path]] = []
        self.bolt_entries: list[tuple[float, Path]] = []

    @property
    def index(self) -> Path:
        """The blocks' ``.pvd`` file."""
        return self.folder / "blocks.pvd"

    @property
    def contacts_index(self) -> Path:
        """The sub-contacts' ``.pvd`` file."""
        return self.folder / "subcontacts.pvd"

    @property
    def bolts_index(self) -> Path:
        """The bolt elements' ``.pvd`` file."""
        return self.folder / "bolts.pvd"

    def write(
        self,
        time: float,
        system: Any,
        displacement: np.ndarray,
        velocity: np.ndarray,
        contacts: dict[str, Any] | None = None,
        excavated: np.ndarray | None = None,
        bolts: dict[str, Any] | None = None,
    ) -> None:
        """One frame, then the indexes. A frame at the time of the last one replaces it.
        The contacts and the bolt elements (the engine's dicts) are written when given."""
        moving = np.linalg.norm(velocity, axis=1) > self.speed
        text = vtu_text(system, displacement, velocity, moving, excavated)
        self._add(self.entries, self.index, "blocks", "vtu", time, text)
        if contacts is not None:
            text = vtp_text(contacts)
            self._add(self.contact_entries, self.contacts_index, "subcontacts", "vtp", time, text)
        if bolts is not None:
            text = bolts_vtp_text(bolts)
            self._add(self.bolt_entries, self.bolts_index, "bolts", "vtp", time, text)

    def _add(
        self,
        entries: list[tuple[float, Path]],
        index: Path,
        stem: str,
        suffix: str,
        time: float,
        text: str,
    ) -> None:
        import penedge

        if entries and time <= entries[-1][0]:
            entries.pop()
        name = self.folder / f"{stem}_{len(entries):06d}.{suffix}"
        write_text_atomically(name, text)
        entries.append((time, Path(name.name)))
        penedge.write_pvd(index, [(t, str(p)) for t, p in entries])
