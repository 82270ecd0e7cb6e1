"""A ParaView time series of a simulation: the blocks of each frame as a VTU file (one
polyhedron cell per block) with their displacement, velocity and a moving flag as cell
data, listed by ``blocks.pvd`` (written with :func:`penedge.write_pvd`).

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
    system: Any, displacement: np.ndarray, velocity: np.ndarray, moving: np.ndarray
) -> str:
    """The VTU file of `system` with per-block ``displacement`` (m, vector and
    ``displacement_magnitude``), ``velocity`` (m/s) and ``moving`` (0/1) cell data."""
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
        _array("Float64", "displacement", _floats(displacement), 3),
        _array("Float64", "displacement_magnitude", _floats(magnitude)),
        _array("Float64", "velocity", _floats(velocity), 3),
        _array("UInt8", "moving", _ints(moving.astype(np.uint8))),
    ]
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

    @property
    def index(self) -> Path:
        """The ``.pvd`` file."""
        return self.folder / "blocks.pvd"

    def write(
        self, time: float, system: Any, displacement: np.ndarray, velocity: np.ndarray
    ) -> None:
        """One frame, then the index. A frame at the time of the last one replaces it."""
        import penedge

        if self.entries and time <= self.entries[-1][0]:
            self.entries.pop()
        name = self.folder / f"blocks_{len(self.entries):06d}.vtu"
        moving = np.linalg.norm(velocity, axis=1) > self.speed
        write_text_atomically(name, vtu_text(system, displacement, velocity, moving))
        self.entries.append((time, Path(name.name)))
        penedge.write_pvd(self.index, [(t, str(p)) for t, p in self.entries])
