"""What the pictures draw, as flat numpy arrays: the blocks moved apart for an exploded
view, the faces chosen when a system is too large to draw whole, and block colours.

Everything is built from :meth:`penedge.BlockSystem.arrays` without a Python object per
block, so that systems of 10^5 blocks are prepared in well under a second.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from penedge._core import Block, BlockSystem

__all__ = [
    "COLOR_BY",
    "DEFAULT_MAX_BLOCKS",
    "MAX_EXPLODE",
    "NO_SET_COLOR",
    "SET_COLORS",
    "Scene",
    "block_colors",
    "check_contacts",
    "check_explode",
    "dominant_sets",
    "face_areas",
    "padded_polygons",
    "plain_text",
    "set_colors",
    "volume_scale",
]

#: How blocks can be coloured: by joint set (the set holding most of the block's face area;
#: where no face is a joint, each block its own colour), each block its own colour, or by
#: volume on a colour scale.
COLOR_BY = ("set", "block", "volume")

#: The colours of joint sets (spec entries) in order, repeating after ten (Tableau 10:
#: distinct in print and for the common colour blindnesses).
SET_COLORS = (
    "#4e79a7",
    "#f28e2b",
    "#e15759",
    "#76b7b2",
    "#59a14f",
    "#edc948",
    "#b07aa1",
    "#ff9da7",
    "#9c755f",
    "#79706e",
)
#: The colour of blocks and contacts with no joint face (the domain's surface only, or a
#: contact between vertices and edges).
NO_SET_COLOR = "#c8c8c8"

#: The most blocks a picture draws; beyond, the blocks on the outside of the rock mass
#: (with a face on the domain's boundary) are drawn first, then the largest.
DEFAULT_MAX_BLOCKS = 20_000

#: The largest ``explode`` factor a picture takes (each block moved out by at most this many
#: times its distance from the centre): beyond it the blocks are specks far apart.
MAX_EXPLODE = 100.0

_GOLDEN_ANGLE = 0.381966  # fraction of a turn between successive block hues
VOLUME_COLORMAP = "viridis"
_VOLUME_DECADES = 100.0  # the volume colour scale starts at most this factor below V10


def padded_polygons(polygons: list[np.ndarray]) -> np.ma.MaskedArray:
    """Polygons of different sizes as one masked (n, k, 3) array, for ``Poly3DCollection``.

    Given a ragged list, matplotlib (3.10 and later) pads the shorter polygons with
    uninitialised memory (``np.empty``), and ``add_collection3d`` scales the axes to that
    padding as well: by chance an overflow warning or wrong limits. Here each polygon is
    padded with copies of its own last vertex, and the padding is masked; a matplotlib that
    reads no mask draws the copies as edges of length zero.

    >>> square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    >>> padded = padded_polygons([square, square[:3]])
    >>> padded.shape, padded.mask[1, :, 0].tolist(), padded.data[1, 3].tolist()
    ((2, 4, 3), [False, False, False, True], [1.0, 1.0, 0.0])
    """
    sizes = np.fromiter((len(p) for p in polygons), dtype=np.int64, count=len(polygons))
    if not len(sizes):
        return np.ma.MaskedArray(np.zeros((0, 0, 3)), mask=np.zeros((0, 0, 3), dtype=bool))
    width = int(sizes.max())
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    column = np.arange(width)
    entries = starts[:, None] + np.minimum(column, sizes[:, None] - 1)
    data = np.concatenate(polygons).astype(float, copy=False)[entries]
    mask = np.broadcast_to((column >= sizes[:, None])[:, :, None], data.shape)
    return np.ma.MaskedArray(data, mask=mask.copy())


def plain_text(text: str) -> str:
    """`text` as matplotlib draws it letter for letter: every ``$`` escaped, so that a
    unit, a file name or a set name is never read as mathtext (``$m^{$`` would not
    parse)."""
    return text.replace("$", r"\$")


def check_explode(explode: float) -> float:
    """`explode`, checked: a number from 0 to :data:`MAX_EXPLODE`.

    Raises
    ------
    ValueError
        Negative, larger, not a number (nan), not finite, or a bool.
    """
    if isinstance(explode, (bool, np.bool_)):
        # float(True) is 1.0: a bool is no distance, as it is no number anywhere in penedge.
        raise ValueError(f"explode must be a number, got the bool {explode!r}")
    try:
        value = float(explode)
    except (TypeError, ValueError):
        raise ValueError(f"explode must be a number, got {explode!r}") from None
    if not 0 <= value <= MAX_EXPLODE:
        raise ValueError(f"explode must be a number from 0 to {MAX_EXPLODE:g}, got {explode!r}")
    return value


def check_contacts(contacts: Any, n_blocks: int) -> None:
    """`contacts` refer only to blocks of a system of `n_blocks` blocks.

    Raises
    ------
    ValueError
        A contact names a block the system does not have (contacts of another system).
    """
    pairs = np.asarray(contacts.pairs).reshape(-1, 2)
    if len(pairs) and (pairs.max() >= n_blocks or pairs.min() < 0):
        k = int(np.flatnonzero(((pairs >= n_blocks) | (pairs < 0)).any(axis=1))[0])
        a, b = (int(x) for x in pairs[k])
        raise ValueError(
            f"contacts: contact {k} is between blocks {a} and {b}, but the system has "
            f"{n_blocks} block{'s' if n_blocks != 1 else ''}: contacts of another system?"
        )


def block_colors(n: int) -> np.ndarray:
    """Distinct colours for `n` blocks.

    Parameters
    ----------
    n : int
        Number of blocks.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        RGB in [0, 1]; hues a golden angle apart, so neighbours in id order differ.
    """
    i = np.arange(n)
    hue = (0.58 + i * _GOLDEN_ANGLE) % 1.0
    saturation = np.where(i % 2 == 1, 0.50, 0.62)
    return _hsv_to_rgb(hue, saturation, 0.95)


def set_colors(sets: np.ndarray) -> np.ndarray:
    """RGB in [0, 1] of set indices (``SET_COLORS``, repeating), grey for -1 (no set)."""
    sets = np.asarray(sets, dtype=np.int64)
    table = np.array([_hex_rgb(c) for c in (*SET_COLORS, NO_SET_COLOR)])
    return table[np.where(sets < 0, len(SET_COLORS), sets % len(SET_COLORS))].reshape(-1, 3)


def _hex_rgb(color: str) -> tuple[float, float, float]:
    return tuple(int(color[k : k + 2], 16) / 255 for k in (1, 3, 5))  # type: ignore[return-value]


def face_areas(
    vertices: np.ndarray, face_vertices: np.ndarray, loop_offsets: np.ndarray
) -> np.ndarray:
    """The area of each face (a convex polygon), from its fan of triangles."""
    lo = np.asarray(loop_offsets, dtype=np.int64)
    if len(lo) < 2:
        return np.zeros(0)
    start = lo[:-1]
    count = lo[1:] - start - 2
    first = np.repeat(start, count)
    step = _ranges(np.zeros_like(count), count)
    fv = np.asarray(face_vertices, dtype=np.int64)
    a, b, c = (vertices[fv[first + k]] for k in (0, 1 + step, 2 + step))  # type: ignore[index]
    doubled = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    face = np.repeat(np.arange(len(start)), count)
    return np.bincount(face, weights=doubled, minlength=len(start)) / 2


def dominant_sets(arrays: Any) -> np.ndarray:
    """For each block of :meth:`~penedge.BlockSystem.arrays`, the joint set (spec entry,
    an index into ``BlockSystem.sets``) holding the largest part of its face area; -1 for a
    block with no joint face. Ties go to the first set.

    A concave block (convex parts sharing a body id, ``arrays.body_ids``) is one block: each
    of its parts gets the set holding the largest part of the face area of the whole body
    (the faces of all its parts but the internal ones, ``arrays.face_internal``), so that
    the block is drawn in one colour."""
    n = len(arrays.volumes)
    kind = np.asarray(arrays.face_origin_kind)
    face_block = np.asarray(arrays.face_block)
    internal = np.asarray(getattr(arrays, "face_internal", np.zeros(len(kind))), dtype=bool)
    joint = (kind == 2) & ~internal
    if n == 0 or not joint.any():
        return np.full(n, -1, dtype=np.int64)
    _, body = np.unique(_body_ids(arrays, n), return_inverse=True)
    vertices = np.asarray(arrays.vertices, dtype=float).reshape(-1, 3)
    area = face_areas(vertices, arrays.face_vertices, arrays.loop_offsets)
    sets = np.asarray(arrays.face_origin_set)
    n_sets = int(sets[joint].max()) + 1
    table = np.zeros((int(body.max()) + 1, n_sets))
    np.add.at(table, (body[face_block[joint]], sets[joint]), area[joint])
    best = table.argmax(axis=1)
    return np.where(table.max(axis=1) > 0, best, -1)[body]


def _body_ids(arrays: Any, n: int) -> np.ndarray:
    """The body id of each of the `n` blocks (each block its own body when not given)."""
    ids = getattr(arrays, "body_ids", None)
    return np.arange(n) if ids is None else np.asarray(ids, dtype=np.int64)


def _hsv_to_rgb(h: np.ndarray, s: np.ndarray, v: float) -> np.ndarray:
    """colorsys.hsv_to_rgb on arrays."""
    sector = np.floor(h * 6.0)
    f = h * 6.0 - sector
    p, q, t = v * (1 - s), v * (1 - s * f), v * (1 - s * (1 - f))
    vv = np.full_like(h, v)
    table = np.stack(
        [
            np.column_stack([vv, t, p]),
            np.column_stack([q, vv, p]),
            np.column_stack([p, vv, t]),
            np.column_stack([p, q, vv]),
            np.column_stack([t, p, vv]),
            np.column_stack([vv, p, q]),
        ]
    )
    return table[sector.astype(int) % 6, np.arange(len(h))].reshape(len(h), 3)


def volume_scale(volumes: np.ndarray) -> tuple[float, float, bool]:
    """The range of the volume colour scale, and whether it is logarithmic (when the
    volumes span more than a factor of 10).

    The scale starts at most a factor of 100 below V10 (the volume below which blocks hold
    10 % of the rock): slivers much smaller than that all get its lowest colour, instead of
    squeezing the colours of the blocks that make up the rock into one end of the scale.
    """
    v = np.asarray(volumes, dtype=float)
    positive = np.sort(v[v > 0])
    if len(positive) == 0:
        return 0.0, 1.0, False
    passing = np.cumsum(positive) / positive.sum()
    v10 = positive[min(np.searchsorted(passing, 0.1), len(positive) - 1)]
    lo, hi = max(float(positive[0]), float(v10) / _VOLUME_DECADES), float(positive[-1])
    if hi > 10 * lo:
        return lo, hi, True
    if hi == lo:
        return lo * 0.9, hi * 1.1, False
    return lo, hi, False


@dataclass
class Scene:
    """A block system ready to draw: exploded, possibly cut down to `max_blocks` blocks.

    Attributes
    ----------
    vertices : (V, 3) float array
        Every vertex of the system, moved with its block.
    face_vertices, loop_offsets : int arrays
        The drawn faces: face ``f`` is ``face_vertices[loop_offsets[f]:loop_offsets[f + 1]]``
        (indices into `vertices`, counter-clockwise seen from outside).
    face_normals : (F, 3) float array
        Outward unit normal of each drawn face.
    face_block : (F,) int array
        The block (its id in the system) of each drawn face.
    offsets : (n, 3) float array
        The displacement of every block of the system.
    volumes, centroids : arrays over every block of the system
        Centroids as moved.
    shown : (n,) bool array
        Which blocks are drawn.
    block_sets : (n,) int array
        The dominant joint set of each block (:func:`dominant_sets`), -1 for none.
    set_names, set_kinds : list of str
        The names and kinds of the spec entries (``BlockSystem.sets``); empty when not
        generated.
    face_offsets, face_sets : int arrays over every block and face of the system
        Block ``i`` has the faces ``face_offsets[i]:face_offsets[i + 1]``; the joint set of
        each face, -1 for none (the contacts' sets come from these).
    body_first : (n,) int array
        For each block, the first block (smallest id) of its body: the parts of a concave
        block take its colour, so that the block is drawn as one.
    body_index : (n,) int array
        For each block, its body: an index into `body_ids`, `body_volumes`,
        `body_centroids`.
    body_ids, body_volumes : arrays over every body (ascending body id)
        A concave block (convex parts sharing a body id) is one body, its volume the sum of
        its parts'; each block of a system of convex blocks is its own body.
    body_centroids : (B, 3) float array
        The centroid of each body, as moved.

    A concave block is one block of the picture: `block_sets` and :attr:`block_volumes`
    are its body's, `max_blocks` counts bodies and chooses whole ones (:attr:`n_bodies`,
    :attr:`n_shown_bodies`); the arrays over blocks (`volumes`, `shown`, `face_block`) are
    over its convex parts, as the system stores them.
    """

    vertices: np.ndarray
    face_vertices: np.ndarray
    loop_offsets: np.ndarray
    face_normals: np.ndarray
    face_block: np.ndarray
    offsets: np.ndarray
    volumes: np.ndarray
    centroids: np.ndarray
    shown: np.ndarray
    block_sets: np.ndarray
    set_names: list[str]
    set_kinds: list[str]
    face_offsets: np.ndarray
    face_sets: np.ndarray
    body_first: np.ndarray
    body_index: np.ndarray
    body_ids: np.ndarray
    body_volumes: np.ndarray
    body_centroids: np.ndarray

    @property
    def n_blocks(self) -> int:
        """Blocks (convex parts) in the system."""
        return len(self.volumes)

    @property
    def n_shown(self) -> int:
        """Blocks (convex parts) drawn."""
        return int(self.shown.sum())

    @property
    def n_bodies(self) -> int:
        """Bodies in the system: blocks, a concave block counted once."""
        return len(self.body_ids)

    @property
    def shown_bodies(self) -> np.ndarray:
        """Which bodies are drawn (whole: every part, or none)."""
        out = np.zeros(self.n_bodies, dtype=bool)
        out[self.body_index[self.shown]] = True
        return out

    @property
    def n_shown_bodies(self) -> int:
        """Bodies drawn."""
        return int(self.shown_bodies.sum())

    @property
    def block_volumes(self) -> np.ndarray:
        """The volume of each block's body (a concave block's parts summed), per block:
        what its volume colour shows."""
        return self.body_volumes[self.body_index]

    @property
    def n_faces(self) -> int:
        """Faces drawn."""
        return len(self.face_block)

    def polygons(self, faces: np.ndarray | None = None) -> list[np.ndarray]:
        """The drawn faces (or those of index `faces`) as (k, 3) arrays."""
        lo = self.loop_offsets
        if faces is None:
            faces = np.arange(self.n_faces)
        sizes = lo[faces + 1] - lo[faces]
        entries = self.face_vertices[_ranges(lo[faces], sizes)]
        return np.split(self.vertices[entries], np.cumsum(sizes)[:-1]) if len(faces) else []

    def triangles(self, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Fan triangulation of faces `faces`: (t, 3) vertex indices into `vertices`, and
        the face of each triangle."""
        lo = self.loop_offsets
        start = lo[faces]
        count = lo[faces + 1] - start - 2
        first = np.repeat(start, count)
        step = _ranges(np.zeros_like(count), count)
        fv = self.face_vertices
        tris = np.column_stack([fv[first], fv[first + 1 + step], fv[first + 2 + step]])
        return tris.reshape(-1, 3), np.repeat(faces, count)

    def edges(self, faces: np.ndarray) -> np.ndarray:
        """The edges of faces `faces`, each once: (e, 2) vertex indices into `vertices`."""
        lo = self.loop_offsets
        start = lo[faces]
        sizes = lo[faces + 1] - start
        here = _ranges(start, sizes)
        step = here - np.repeat(start, sizes)
        after = np.repeat(start, sizes) + (step + 1) % np.repeat(sizes, sizes)
        fv = self.face_vertices
        pairs = np.sort(np.column_stack([fv[here], fv[after]]), axis=1)
        return np.unique(pairs, axis=0) if len(pairs) else pairs.reshape(0, 2)

    def contact_sets(self, contacts: Any) -> np.ndarray:
        """The joint set of each contact: that of its face (side A's when both blocks touch
        with a face), -1 when neither block touches with a joint face (vertex-vertex,
        edge-edge, or a face on the domain's surface)."""
        kinds = np.asarray(contacts.feature_kinds).reshape(-1, 2)
        ids = np.asarray(contacts.feature_ids).reshape(-1, 2)
        pairs = np.asarray(contacts.pairs).reshape(-1, 2)
        out = np.full(len(pairs), -1, dtype=np.int64)
        for side in (1, 0):  # side A last: it wins
            face = kinds[:, side] == 2
            index = self.face_offsets[pairs[face, side]] + ids[face, side]
            found = self.face_sets[index]
            out[np.flatnonzero(face)[found >= 0]] = found[found >= 0]
        return out

    def real(self, points: np.ndarray, blocks: np.ndarray) -> np.ndarray:
        """Points of the exploded view back where they really are (`blocks`: the block of
        each point)."""
        return points - self.offsets[blocks]

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The corners of the box around the drawn faces."""
        used = self.vertices[self.face_vertices] if self.n_faces else self.vertices
        if len(used) == 0:
            return np.zeros(3), np.ones(3)
        return used.min(axis=0), used.max(axis=0)


def _ranges(starts: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """``concatenate([arange(s, s + k) for s, k in zip(starts, sizes)])``, vectorized."""
    sizes = np.asarray(sizes, dtype=np.int64)
    total = int(sizes.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    ends = np.cumsum(sizes)
    base = np.repeat(np.asarray(starts, dtype=np.int64) - (ends - sizes), sizes)
    return base + np.arange(total)


def _arrays(system: BlockSystem | Iterable[Block]) -> Any:
    if hasattr(system, "arrays"):
        return system.arrays()
    import penedge

    return penedge.BlockSystem(list(system)).arrays()


def choose_blocks(arrays: Any, max_blocks: int | None) -> np.ndarray:
    """Which blocks to draw: all, or when there are more than `max_blocks` bodies (a
    concave block, convex parts sharing a body id, counts once), whole bodies: those with a
    face on the domain's boundary (what a viewer of the whole mass sees) first, then the
    largest (by the volume of the whole body). Returns a bool per block (convex part)."""
    volumes = np.asarray(arrays.volumes, dtype=float)
    n = len(volumes)
    _, body = np.unique(_body_ids(arrays, n), return_inverse=True)
    n_bodies = int(body.max(initial=-1)) + 1
    if max_blocks is None or n_bodies <= max_blocks:
        return np.ones(n, dtype=bool)
    outside = np.zeros(n_bodies, dtype=bool)
    face_block = np.asarray(arrays.face_block)
    outside[body[face_block[np.asarray(arrays.face_origin_kind) == 1]]] = True
    body_volume = np.bincount(body, weights=volumes, minlength=n_bodies)
    order = np.lexsort((-body_volume, ~outside))
    keep = np.zeros(n_bodies, dtype=bool)
    keep[order[:max_blocks]] = True
    return keep[body]


def build_scene(
    system: BlockSystem | Iterable[Block],
    explode: float = 0.5,
    max_blocks: int | None = DEFAULT_MAX_BLOCKS,
) -> Scene:
    """The system exploded (each block moved by ``explode * (its centroid - the system's
    volume-weighted centroid)``) and cut down to at most `max_blocks` blocks.

    A concave block (parts sharing a body id) is drawn as one block: its parts move together
    (by the centroid of the whole body), its internal faces are left out, and it counts as
    one block of `max_blocks` (whole bodies are drawn or left out)."""
    if isinstance(max_blocks, (bool, np.bool_)):
        raise ValueError(f"max_blocks must be a whole number, got the bool {max_blocks!r}")
    if max_blocks is not None and max_blocks < 1:
        raise ValueError(f"max_blocks must be at least 1, got {max_blocks}")
    explode = check_explode(explode)
    a = _arrays(system)
    volumes = np.asarray(a.volumes, dtype=float)
    centroids = np.asarray(a.centroids, dtype=float).reshape(-1, 3)
    n = len(volumes)
    total = volumes.sum()
    centre = volumes @ centroids / total if n and total > 0 else np.zeros(3)
    body = _body_ids(a, n)
    ids, body_index = np.unique(body, return_inverse=True)
    body_volume = np.bincount(body_index, weights=volumes, minlength=len(ids))
    body_centroid = (
        np.column_stack(
            [
                np.bincount(body_index, weights=volumes * centroids[:, k], minlength=len(ids))
                for k in range(3)
            ]
        )
        / np.where(body_volume > 0, body_volume, 1.0)[:, None]
    )
    offsets = explode * (body_centroid[body_index] - centre) if n else np.zeros((0, 3))
    first = np.full(len(ids), n, dtype=np.int64)
    np.minimum.at(first, body_index, np.arange(n))
    vertex_block = np.repeat(np.arange(n), np.diff(a.vertex_offsets))
    vertices = np.asarray(a.vertices, dtype=float).reshape(-1, 3) + offsets[vertex_block]
    shown = choose_blocks(a, max_blocks)
    face_block = np.asarray(a.face_block)
    loop_offsets = np.asarray(a.loop_offsets)
    face_vertices = np.asarray(a.face_vertices)
    face_normals = np.asarray(a.face_normals, dtype=float).reshape(-1, 3)
    internal = np.asarray(getattr(a, "face_internal", np.zeros(len(face_block))), dtype=bool)
    if not shown.all() or internal.any():
        keep = shown[face_block] & ~internal
        sizes = np.diff(loop_offsets)
        face_vertices = face_vertices[np.repeat(keep, sizes)]
        loop_offsets = np.concatenate([[0], np.cumsum(sizes[keep])])
        face_block, face_normals = face_block[keep], face_normals[keep]
    origin_kind = np.asarray(a.face_origin_kind)
    face_sets = np.where(origin_kind == 2, np.asarray(a.face_origin_set), -1)
    sets = getattr(system, "sets", None) or []
    return Scene(
        block_sets=dominant_sets(a),
        set_names=[s["name"] for s in sets],
        set_kinds=[s["kind"] for s in sets],
        face_offsets=np.asarray(a.face_offsets),
        face_sets=face_sets,
        vertices=vertices,
        face_vertices=face_vertices,
        loop_offsets=loop_offsets,
        face_normals=face_normals,
        face_block=face_block,
        offsets=offsets,
        volumes=volumes,
        centroids=centroids + offsets,
        shown=shown,
        body_first=first[body_index],
        body_index=body_index,
        body_ids=ids,
        body_volumes=body_volume,
        body_centroids=body_centroid + explode * (body_centroid - centre),
    )


def shown_note(scene: Scene) -> str | None:
    """``showing 20000 of 103313 blocks (...)`` when the scene is cut down; blocks are
    bodies (a concave block counts once, as `max_blocks` counts it)."""
    if scene.n_shown == scene.n_blocks:
        return None
    return (
        f"showing {scene.n_shown_bodies} of {scene.n_bodies} blocks: those on the outside of "
        "the rock mass first, then the largest"
    )
