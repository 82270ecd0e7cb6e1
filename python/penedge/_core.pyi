"""Type stubs of penedge._core (the Rust extension). Keep in step with crates/penedge-py."""

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Final, Literal, Self, TypedDict, final

import numpy as np
import numpy.typing as npt

__version__: Final[str]
"""The version of penedge (``major.minor.patch``)."""

__all__ = [
    "CONTACT_TYPES",
    "EDGE_EDGE",
    "EDGE_EDGE_SUPERPOSITION",
    "EDGE_FACE",
    "FACE_FACE",
    "FEATURE_KINDS",
    "PENETRATING",
    "SEPARATED",
    "VERTEX_EDGE",
    "VERTEX_FACE",
    "VERTEX_VERTEX",
    "Block",
    "BlockArrays",
    "BlockError",
    "BlockSystem",
    "ContactTracker",
    "FileFormatError",
    "InputError",
    "PairContact",
    "PenedgeError",
    "SpecError",
    "SystemContacts",
    "TimeSeries",
    "ToleranceError",
    "__version__",
    "detect_pair",
    "generate",
    "overlap",
    "paper_example",
    "paper_example_planes",
    "paper_table3",
    "write_pvd",
]

_ContactTypeName = Literal[
    "vertex-vertex",
    "vertex-edge",
    "edge-edge",
    "edge-edge-superposition",
    "vertex-face",
    "edge-face",
    "face-face",
]
_Outcome = _ContactTypeName | Literal["separated", "penetrating"]
_FeatureKind = Literal["vertex", "edge", "face"]

CONTACT_TYPES: Final[tuple[_ContactTypeName, ...]]
"""The names of the seven contact types, by type code: ``CONTACT_TYPES[code - 1]``."""
FEATURE_KINDS: Final[tuple[_FeatureKind, _FeatureKind, _FeatureKind]]
"""The feature kinds by code (``SystemContacts.feature_kinds``): 0 vertex, 1 edge, 2 face."""
SEPARATED: Final[int]
"""The type code of a separated pair (``PairContact.type_code``): 0."""
PENETRATING: Final[int]
"""The type code of a pair penetrating beyond the gap (``PairContact.type_code``): -1."""
VERTEX_VERTEX: Final[int]
"""The type code of vertex-vertex contacts: 1 (``SystemContacts.types``)."""
VERTEX_EDGE: Final[int]
"""The type code of vertex-edge contacts: 2."""
EDGE_EDGE: Final[int]
"""The type code of edge-edge contacts: 3."""
EDGE_EDGE_SUPERPOSITION: Final[int]
"""The type code of edge-edge-superposition contacts: 4."""
VERTEX_FACE: Final[int]
"""The type code of vertex-face contacts: 5."""
EDGE_FACE: Final[int]
"""The type code of edge-face contacts: 6."""
FACE_FACE: Final[int]
"""The type code of face-face contacts: 7."""

class PenedgeError(Exception):
    kind: str
    field: str | None  # the bad field of a SpecError (always set) or a FileFormatError

class InputError(PenedgeError, ValueError): ...
class BlockError(PenedgeError, ValueError): ...
class ToleranceError(PenedgeError, ValueError): ...
class SpecError(PenedgeError, ValueError): ...
class FileFormatError(PenedgeError, ValueError): ...

_Path = str | os.PathLike[str]

class _Statistics(TypedDict):
    count: int
    total_volume: float
    min_volume: float
    max_volume: float
    mean_volume: float
    v10: float
    v50: float
    v90: float
    count_percentiles: list[float]

class _SetRecord(TypedDict):
    name: str
    kind: Literal["plane", "set", "disc", "polygon"]

@final
class Block:
    def __new__(cls, vertices: npt.ArrayLike, faces: Sequence[Sequence[int]]) -> Self: ...
    @staticmethod
    def from_planes(normals: npt.ArrayLike, offsets: npt.ArrayLike) -> Block: ...
    @staticmethod
    def cuboid(lo: npt.ArrayLike, hi: npt.ArrayLike) -> Block: ...
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def faces(self) -> list[list[int]]: ...
    @property
    def edges(self) -> npt.NDArray[np.int64]: ...
    @property
    def edge_faces(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_normals(self) -> npt.NDArray[np.float64]: ...
    @property
    def volume(self) -> float: ...
    @property
    def centroid(self) -> npt.NDArray[np.float64]: ...
    @property
    def aabb(self) -> npt.NDArray[np.float64]: ...
    @property
    def size(self) -> float: ...
    def __reduce__(self) -> tuple[Any, ...]: ...

@final
class PairContact:
    @property
    def outcome(self) -> _Outcome: ...
    @property
    def touching(self) -> bool: ...
    @property
    def type_code(self) -> int: ...
    @property
    def feature_a(self) -> tuple[_FeatureKind, int] | None: ...
    @property
    def feature_b(self) -> tuple[_FeatureKind, int] | None: ...
    @property
    def penetration_edges(self) -> np.ndarray[Any, np.dtype[np.void]]: ...
    @property
    def penetration_points(self) -> npt.NDArray[np.float64]: ...
    @property
    def normal(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def distance(self) -> float | None: ...
    @property
    def points(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def area(self) -> float | None: ...
    def table1_counts(self) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]: ...

def detect_pair(
    a: Block, b: Block, gap: float = 1e-12, length: float | None = None
) -> PairContact: ...

class _Overlap(TypedDict):
    normal: npt.NDArray[np.float64]
    depth: float
    min_translation: npt.NDArray[np.float64]
    volume: float
    centroid: npt.NDArray[np.float64]
    points: npt.NDArray[np.float64]
    area: float

def overlap(
    a: Block, b: Block, gap: float = 1e-12, length: float | None = None
) -> _Overlap | None: ...

class _UpdateReport(TypedDict):
    rebuilt: bool
    candidate_pairs: int
    unmoved: int
    certified: int
    queried: int

@final
class ContactTracker:
    def __new__(
        cls,
        system: BlockSystem,
        skin: float = 0.0,
        gap: float = 1e-12,
        length: float | None = None,
    ) -> Self: ...
    @property
    def contacts(self) -> SystemContacts: ...
    def update(self, rotations: npt.ArrayLike, translations: npt.ArrayLike) -> _UpdateReport: ...

@final
class SystemContacts:
    @property
    def pairs(self) -> npt.NDArray[np.int64]: ...
    @property
    def types(self) -> npt.NDArray[np.int8]: ...
    @property
    def feature_kinds(self) -> npt.NDArray[np.int8]: ...
    @property
    def feature_ids(self) -> npt.NDArray[np.int64]: ...
    @property
    def penetrating(self) -> npt.NDArray[np.int64]: ...
    @property
    def normals(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def distances(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def areas(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def point_offsets(self) -> npt.NDArray[np.int64] | None: ...
    @property
    def points(self) -> npt.NDArray[np.float64] | None: ...
    def counts(self) -> dict[_ContactTypeName, int]: ...
    def points_of(self, i: int) -> npt.NDArray[np.float64]: ...
    def write_csv(self, path: _Path) -> None: ...
    def write_vtp(self, path: _Path) -> None: ...
    def __len__(self) -> int: ...

@final
class BlockArrays:
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def vertex_offsets(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_offsets(self) -> npt.NDArray[np.int64]: ...
    @property
    def loop_offsets(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_vertices(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_normals(self) -> npt.NDArray[np.float64]: ...
    @property
    def face_block(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_origin_kind(self) -> npt.NDArray[np.int8]: ...
    @property
    def face_origin_set(self) -> npt.NDArray[np.int64]: ...
    @property
    def face_origin_index(self) -> npt.NDArray[np.int64]: ...
    @property
    def volumes(self) -> npt.NDArray[np.float64]: ...
    @property
    def centroids(self) -> npt.NDArray[np.float64]: ...

@final
class BlockSystem:
    def __new__(cls, blocks: Sequence[Block]) -> Self: ...
    @staticmethod
    def from_box_cut(
        lo: npt.ArrayLike, hi: npt.ArrayLike, normals: npt.ArrayLike, offsets: npt.ArrayLike
    ) -> BlockSystem: ...
    @property
    def blocks(self) -> list[Block]: ...
    @property
    def volumes(self) -> npt.NDArray[np.float64]: ...
    @property
    def centroids(self) -> npt.NDArray[np.float64]: ...
    @property
    def sets(self) -> list[_SetRecord]: ...
    @property
    def domain(self) -> list[Block]: ...
    def detect(
        self,
        gap: float = 1e-12,
        length: float | None = None,
        geometry: bool = False,
        progress: Callable[[int, int], object] | None = None,
        threads: int | None = None,
    ) -> SystemContacts: ...
    def arrays(self) -> BlockArrays: ...
    def statistics(self) -> _Statistics | None: ...
    def volume_curve(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def write_json(self, path: _Path) -> None: ...
    @staticmethod
    def read_json(path: _Path) -> BlockSystem: ...
    def to_json(self) -> str: ...
    @staticmethod
    def from_json(text: str) -> BlockSystem: ...
    def write_vtu(self, path: _Path) -> None: ...
    def write_faces_vtu(self, path: _Path) -> None: ...
    def write_csv(self, path: _Path) -> None: ...
    def __len__(self) -> int: ...
    def __getitem__(self, index: int, /) -> Block: ...
    def __reduce__(self) -> tuple[Any, ...]: ...

@final
class TimeSeries:
    def __new__(cls, folder: _Path, resume: bool = False) -> Self: ...
    def write_step(
        self, time: float, system: BlockSystem, contacts: SystemContacts | None = None
    ) -> int: ...
    @property
    def folder(self) -> Path: ...
    @property
    def blocks_index(self) -> Path: ...
    @property
    def contacts_index(self) -> Path: ...
    @property
    def times(self) -> npt.NDArray[np.float64]: ...
    @property
    def contact_times(self) -> npt.NDArray[np.float64]: ...
    def __len__(self) -> int: ...

def write_pvd(path: _Path, datasets: Sequence[tuple[float, _Path]]) -> None: ...
def generate(
    spec: _Path | Mapping[str, Any],
    progress: Callable[[int, int, int], object] | None = None,
) -> tuple[BlockSystem, dict[str, Any]]: ...
def paper_example(n: int) -> BlockSystem: ...
def paper_example_planes(n: int) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def paper_table3(n: int) -> dict[_ContactTypeName, int]: ...
