"""The checks of a model that need its blocks, and what they resolve: which blocks each
region selects, which blocks are fixed or driven, which block each monitor follows, which
blocks each bolt ties, and the forces of support pressures.

Everything here runs once, after generation and before the first step, on the block
arrays (numpy, no loop over blocks in Python).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from penedge.model.fields import ModelError, point_text
from penedge.model.schema import FACE_DIRECTIONS, STRESS, Model, Region

#: A named domain face is every domain face whose outward normal is within this angle of
#: the named direction.
FACE_ANGLE_DEGREES = 1.0

BOUNDARY_FACE = 1
JOINT_FACE = 2

#: The largest model (the diagonal of its blocks' bounding box, m) whose masses, weights and
#: forces the engine computes: the Earth is 12,742 km across. Beyond it a domain in
#: millimetres, say, would give weights whose squares overflow (docs/models.md, "Ranges").
MAX_SIZE = 1e7

#: Two areas agree when they differ by less than this fraction of the larger (a glue
#: region that is a whole part face).
AREA_MATCH = 1e-6


def polygons(
    corners: np.ndarray, loops: np.ndarray, normals: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Areas and centroids of planar polygons: polygon `i` is the loop of `corners`
    `loops[i]:loops[i + 1]` with unit normal `normals[i]` (a fan from its first corner)."""
    counts = np.diff(loops)
    corner_face = np.repeat(np.arange(len(counts)), counts)
    start = corners[loops[:-1]][corner_face]
    nxt = np.roll(np.arange(len(corners)), -1)
    nxt[loops[1:] - 1] = loops[:-1]
    a_, b_ = corners, corners[nxt]
    cross = np.cross(a_ - start, b_ - start)
    tri_area = 0.5 * np.einsum("ij,ij->i", cross, normals[corner_face])
    areas = np.bincount(corner_face, tri_area, len(counts))
    weighted = (start + a_ + b_) / 3.0 * tri_area[:, None]
    centroid = np.stack(
        [np.bincount(corner_face, weighted[:, k], len(counts)) for k in range(3)], axis=1
    )
    centroid /= np.where(areas != 0, areas, 1.0)[:, None]
    return areas, centroid


@dataclass
class Blocks:
    """The generated blocks as the checks need them (from :meth:`BlockSystem.arrays`)."""

    centroids: np.ndarray  # (n, 3)
    volumes: np.ndarray  # (n,)
    face_block: np.ndarray  # (faces,)
    face_normals: np.ndarray  # (faces, 3), outward
    face_points: np.ndarray  # (faces, 3), a vertex of each face
    face_areas: np.ndarray  # (faces,)
    face_centroids: np.ndarray  # (faces, 3)
    face_kind: np.ndarray  # (faces,) 1 domain boundary, 2 joint
    face_set: np.ndarray  # (faces,) domain part, or joint spec entry
    face_index: np.ndarray  # (faces,) domain face, or joint
    domain_normals: list[np.ndarray]  # per domain part: (faces, 3) outward normals
    size: float  # the diagonal of the blocks' bounding box
    bodies: np.ndarray | None = None  # (n,) the body id of each block (concave blocks)
    sets: list[dict[str, str]] = field(default_factory=list)  # the spec entries (name, kind)
    glue_faces: np.ndarray | None = None  # (m, 2) the two faces of each internal face
    glue_areas: np.ndarray | None = None  # (m,) its area
    system: Any = None  # the penedge.BlockSystem (contact detection, for bare joint faces)
    bare: BareFaces | None = None  # the joint faces an excavation left bare (bare_faces)
    lowest: float | None = None  # the lowest vertex's z (m)

    @classmethod
    def of(cls, system: Any) -> Blocks:
        """The arrays of a :class:`penedge.BlockSystem`."""
        a = system.arrays()
        vertices = np.asarray(a.vertices)
        loops = np.asarray(a.loop_offsets)
        fv = np.asarray(a.face_vertices)
        face_block = np.asarray(a.face_block)
        corners = vertices[fv]  # face_vertices index the system's vertex array
        normals = np.asarray(a.face_normals)
        areas, centroid = polygons(corners, loops, normals)
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        glue = system.internal_faces()
        first_face = np.asarray(a.face_offsets)[:-1]
        glue_faces = first_face[np.asarray(glue["parts"], dtype=np.int64).reshape(-1, 2)]
        glue_faces += np.asarray(glue["faces"], dtype=np.int64).reshape(-1, 2)
        return cls(
            centroids=np.asarray(a.centroids),
            volumes=np.asarray(a.volumes),
            face_block=face_block,
            face_normals=normals,
            face_points=corners[loops[:-1]],
            face_areas=areas,
            face_centroids=centroid,
            face_kind=np.asarray(a.face_origin_kind),
            face_set=np.asarray(a.face_origin_set),
            face_index=np.asarray(a.face_origin_index),
            domain_normals=[np.asarray(part.face_normals) for part in system.domain],
            size=float(np.linalg.norm(hi - lo)),
            bodies=np.asarray(system.rigid_body_ids, dtype=np.int64),
            sets=[dict(entry) for entry in system.sets],
            glue_faces=glue_faces,
            glue_areas=np.asarray(glue["areas"], dtype=float),
            system=system,
            lowest=float(lo[2]),
        )

    def __len__(self) -> int:
        return len(self.centroids)

    def containing(self, point: Any, path: str = "point", what: str = "the point") -> int | None:
        """The block that contains `point`, or None.

        A point on a face (edge, corner) that blocks of two or more bodies share, within
        1e-9 of the model's size, is in each of them: which one it means is a guess (a
        monitor on a sliding plane following the fixed block below it records zeros), so
        it is a :exc:`ModelError` naming `path`, the blocks and where they are. Parts of
        one concave body move as one: a point between two of them is the first part's."""
        p = np.asarray(point, dtype=float)
        outside = np.einsum("ij,ij->i", p - self.face_points, self.face_normals)
        tolerance = 1e-9 * self.size
        bad = np.bincount(self.face_block, outside > tolerance, len(self)).astype(bool)
        inside = np.flatnonzero(~bad)
        if len(inside) == 0:
            return None
        bodies = inside if self.bodies is None else self.bodies[inside]
        if len(np.unique(bodies)) > 1:
            _, first = np.unique(bodies, return_index=True)
            shown = inside[np.sort(first)]
            names = ", ".join(f"{b} (centroid {point_text(self.centroids[b])})" for b in shown[:-1])
            last = shown[-1]
            names += f" and {last} (centroid {point_text(self.centroids[last])})"
            raise ModelError(
                path,
                f"{what} {point_text(p)} lies on the boundary between blocks {names}: it is "
                "in each of them; move it inside the block it means",
            )
        return int(inside[0])


def domain_faces(blocks: Blocks, face: str | int, part: int, path: str) -> set[int]:
    """The domain faces (indices into part `part`, which exists) that `face` (the field
    at `path`) names."""
    normals = blocks.domain_normals[part]
    if isinstance(face, int):
        if face >= len(normals):
            raise ModelError(
                path,
                f"the domain has {len(normals)} faces (0 to {len(normals) - 1}); no face {face}",
            )
        return {face}
    direction = np.asarray(FACE_DIRECTIONS[face])
    cos = np.cos(np.radians(FACE_ANGLE_DEGREES))
    found = set(np.flatnonzero(normals @ direction >= cos).tolist())
    if not found:
        raise ModelError(
            path,
            f"the domain has no face facing {face} (outward normal within "
            f"{FACE_ANGLE_DEGREES:g} degrees of {tuple(direction.tolist())}); give the face's "
            "index instead",
        )
    return found


def on_domain_faces(blocks: Blocks, faces: set[int], part: int) -> np.ndarray:
    """A mask of the block faces that lie on the domain faces `faces` of part `part`."""
    return (
        (blocks.face_kind == BOUNDARY_FACE)
        & (blocks.face_set == part)
        & np.isin(blocks.face_index, list(faces))
    )


def select(region: Region, blocks: Blocks, path: str) -> np.ndarray:
    """The mask of the blocks `region` selects; an error naming `path` when it selects none."""
    n = len(blocks)
    c = blocks.centroids
    if region.kind == "all":
        mask = np.ones(n, bool)
    elif region.kind == "box":
        mask = np.all((c >= region.min) & (c <= region.max), axis=1)
    elif region.kind in ("below", "above"):
        assert region.plane is not None
        h = region.plane.height(c)
        mask = h < 0 if region.kind == "below" else h > 0
    elif region.kind == "face":
        assert region.face is not None
        parts = len(blocks.domain_normals)
        if region.part >= parts:
            raise ModelError(
                f"{path}.part",
                f"the domain has {parts} part(s) (0 to {parts - 1}); no part {region.part}",
            )
        faces = domain_faces(blocks, region.face, region.part, f"{path}.face")
        on = on_domain_faces(blocks, faces, region.part)
        mask = np.zeros(n, bool)
        mask[blocks.face_block[on]] = True
    elif region.kind == "point":
        block = blocks.containing(region.point, f"{path}.point")
        if block is None:
            raise ModelError(
                f"{path}.point", f"no block contains the point {point_text(region.point)}"
            )
        mask = np.zeros(n, bool)
        mask[block] = True
    else:
        ids = np.asarray(region.blocks)
        if ids.max() >= n:
            raise ModelError(
                f"{path}.ids", f"no block {int(ids.max())}: the model has {n} blocks (0 to {n - 1})"
            )
        mask = np.zeros(n, bool)
        mask[ids] = True
    if not mask.any():
        raise ModelError(path, f"selects no block (region {region.name!r}, type {region.kind!r})")
    return mask


@dataclass
class BoltPath:
    """Where a bolt lies in the rock: the blocks its segment passes through, in order from
    the collar, and how much of its length lies before the first of them (in the air in
    front of the rock face, where a collar given off the face puts it)."""

    blocks: list[int]  # the blocks it passes through, from the collar's
    outside: float  # m of its length before the first block (0 for a collar on the face)
    in_rock: float  # m of its length from the first block on (`length` - `outside`)


@dataclass
class Layout:
    """What the checks resolved, in block ids."""

    fixed: np.ndarray  # bool (n,)
    velocity: np.ndarray  # (n, 3) prescribed velocity (NaN where none)
    monitors: dict[str, int]  # monitor name -> block id
    bolts: list[tuple[int, int]] = field(default_factory=list)  # block at the collar, at the end
    bolt_paths: list[BoltPath] = field(default_factory=list)  # per bolt: what it crosses
    support_forces: np.ndarray | None = None  # (n, 3) force of the support pressures (N)
    support_moments: np.ndarray | None = None  # (n, 3) their moment about the centroid (N m)
    support_areas: list[float] = field(default_factory=list)  # per support: area pushed (m²)
    support_blocks: list[np.ndarray] = field(default_factory=list)  # per support: blocks pushed
    regions: dict[str, np.ndarray] = field(default_factory=dict)  # name -> mask
    bodies: np.ndarray | None = None  # (n,) body id per block; a concave block's parts share one

    @property
    def driven(self) -> np.ndarray:
        """Blocks with a prescribed velocity."""
        return ~np.isnan(self.velocity[:, 0])


def region_path(model: Model, name: str) -> str:
    """Where a region is defined in the file: ``regions.NAME`` or the inline field's path
    (``boundary[0].region``: a name with ``[``, which a named region's cannot hold)."""
    return f"regions.{name}" if name in model.regions and "[" not in name else name


def whole_bodies(mask: np.ndarray, bodies: np.ndarray | None) -> np.ndarray:
    """`mask` grown to every part of each body it touches: the blocks of the bodies (body id
    per block, `bodies`; None: every block is its own body) that have a block in `mask`."""
    if bodies is None:
        return mask
    return np.isin(bodies, bodies[mask])


def partial_body(mask: np.ndarray, bodies: np.ndarray | None) -> str | None:
    """Why `mask` cannot be excavated when it holds some parts of a concave block and not
    the others (the first such body; None when it holds whole bodies only)."""
    if bodies is None:
        return None
    inside = np.isin(bodies, bodies[mask])
    split = np.flatnonzero(inside & ~mask)
    if len(split) == 0:
        return None
    body = bodies[split[0]]
    parts = np.flatnonzero(bodies == body)
    taken = parts[mask[parts]]
    left = parts[~mask[parts]]
    return (
        f"the region holds blocks {block_list(taken)} but not blocks {block_list(left)} of "
        f"one concave block (body {int(body)}): a concave block is one rigid body and is "
        "excavated whole or not at all; make the region take all its parts (a region takes a "
        "block when its centroid is inside) or none"
    )


def block_list(ids: np.ndarray) -> str:
    """Block ids as ``1, 4, 7`` (the first 10, then how many more)."""
    shown = ", ".join(map(str, ids[:10].tolist()))
    return shown if len(ids) <= 10 else f"{shown} and {len(ids) - 10} more"


def apply_boundary(
    fixed: np.ndarray,
    velocities: np.ndarray,
    mask: np.ndarray,
    condition: str,
    velocity: Any,
    bodies: np.ndarray | None = None,
) -> None:
    """One boundary condition on the blocks of `mask` (later conditions win): updates the
    `fixed` mask and the prescribed `velocities` (NaN: none) in place. With `bodies` (the
    body id of each block), on whole bodies: a concave block is one rigid body, so a
    condition on one of its parts holds all of them (docs/models.md, "Concave blocks")."""
    mask = whole_bodies(mask, bodies)
    fixed[mask] = condition == "fixed"
    velocities[mask] = np.nan
    if condition == "velocity":
        velocities[mask] = velocity


def resolve(model: Model, blocks: Blocks) -> Layout:
    """Every block-dependent check of `model`; the resolved :class:`Layout`.

    Raises
    ------
    ModelError
        A region that selects no block, every block fixed or none, a monitor or bolt
        outside the rock, a bolt that ties no two blocks, a support with no free face.
    """
    n = len(blocks)
    if n == 0:
        raise ModelError("domain", "the model has no blocks (every block was a sliver)")
    check_scale(model, blocks)
    masks = {
        name: select(region, blocks, region_path(model, name))
        for name, region in model.regions.items()
    }
    layout = Layout(
        fixed=np.zeros(n, bool),
        velocity=np.full((n, 3), np.nan),
        monitors={},
        regions=masks,
        bodies=blocks.bodies,
    )
    for b in model.boundary:
        mask = masks[b.region]
        apply_boundary(layout.fixed, layout.velocity, mask, b.condition, b.velocity, blocks.bodies)
    held = layout.fixed | layout.driven
    if not held.any():
        raise ModelError(
            "boundary",
            "no block is fixed or driven: nothing holds the rock mass (add a [[boundary]] "
            'entry such as {region = {type = "face", face = "bottom"}, condition = "fixed"})',
        )
    if held.all():
        raise ModelError(
            "boundary", f"every block ({n}) is fixed or driven: nothing is free to move"
        )
    for i, monitor in enumerate(model.monitors):
        if monitor.block is not None:
            if monitor.block >= n:
                raise ModelError(
                    f"monitors[{i}].block",
                    f"no block {monitor.block}: the model has {n} blocks (0 to {n - 1})",
                )
            layout.monitors[monitor.name] = monitor.block
        else:
            block = blocks.containing(monitor.point, f"monitors[{i}].point")
            if block is None:
                raise ModelError(
                    f"monitors[{i}].point",
                    f"no block contains the point {point_text(monitor.point)}: "
                    "it is outside the rock",
                )
            layout.monitors[monitor.name] = block
    for i, bolt in enumerate(model.bolts):
        layout.bolts.append(bolt_blocks(blocks, bolt.point, bolt.end, f"bolts[{i}]"))
        layout.bolt_paths.append(bolt_path(blocks, bolt.point, bolt.end))
    if model.support:
        forces = np.zeros((n, 3))
        moments = np.zeros((n, 3))
        for i, s in enumerate(model.support):
            path = f"support[{i}]"
            faces, entries = support_faces(blocks, s.face, f"{path}.face")
            faces &= masks[s.region][blocks.face_block]
            bare = bare_faces(blocks, model.spec.get("excavations", [])) if entries else None
            if bare is not None:
                taken = masks[s.region][blocks.face_block[bare.faces]]
                bare = bare.subset(taken & np.isin(bare.entries, entries))
            if not faces.any() and (bare is None or len(bare.faces) == 0):
                raise ModelError(
                    path,
                    "the region has no free face (a face of the domain's boundary or of an "
                    "excavation's wall) to push on",
                )
            area = pressure_load(blocks, faces, s.pressure, forces, moments, path, bare)
            layout.support_areas.append(area)
            pushed = blocks.face_block[faces]
            if bare is not None:
                pushed = np.concatenate([pushed, blocks.face_block[bare.faces]])
            layout.support_blocks.append(np.unique(pushed))
        layout.support_forces, layout.support_moments = forces, moments
    return layout


def check_scale(model: Model, blocks: Blocks) -> None:
    """The ranges that need the blocks (docs/models.md, "Ranges"): the model's size, and
    the overburden's deepest stress (``[initial_stress]``: density × gravity × depth × k0),
    within :data:`MAX_SIZE` and :data:`penedge.model.schema.STRESS`."""
    if not blocks.size <= MAX_SIZE:
        raise ModelError(
            "domain",
            f"the blocks span {blocks.size:.3g} m (their bounding box's diagonal): above "
            f"{MAX_SIZE:g} m, the range a model takes (the Earth is 12,742 km across): "
            "coordinates in another unit than metres?",
        )
    stress = model.initial_stress
    if stress is None or stress.kind != "overburden":
        return
    m = model.mechanics
    density = m.density if stress.density is None else stress.density
    z = blocks.face_points[:, 2]  # a vertex of each face: the blocks' extent, near enough
    surface = float(z.max()) if stress.surface is None else stress.surface
    lowest = float(z.min()) if blocks.lowest is None else blocks.lowest
    if stress.surface is not None and surface <= lowest:
        raise ModelError(
            "initial_stress.surface",
            f"the ground surface z = {surface:g} m lies below every block (the lowest is at "
            f"z = {lowest:.6g} m): the overburden would be zero everywhere; give the z of the "
            "ground surface above the blocks (or leave surface out: the top of the blocks)",
        )
    depth = max(0.0, surface - float(z.min()))
    deepest = density * float(np.linalg.norm(m.gravity)) * depth * max(1.0, *stress.k0)
    field = "initial_stress.surface" if stress.surface is not None else "initial_stress"
    what = "the overburden's stress at the lowest face (density × gravity × depth × k0), "
    STRESS.check(field, deepest, what=what)


def excavation_entries(blocks: Blocks) -> np.ndarray:
    """The spec entries (indices into ``BlockSystem.sets``) that are excavations, in the
    order of the generation's ``[[excavations]]``."""
    return np.asarray(
        [i for i, entry in enumerate(blocks.sets) if entry.get("kind") == "excavation"],
        dtype=np.int64,
    )


def wall_faces(blocks: Blocks, entries: np.ndarray) -> np.ndarray:
    """A mask of the block faces made by the excavation entries `entries` (its walls, and
    the glue between the parts of the concave blocks it cut)."""
    return (blocks.face_kind == JOINT_FACE) & np.isin(blocks.face_set, entries)


def support_faces(
    blocks: Blocks, face: str | int | None, path: str
) -> tuple[np.ndarray, list[int]]:
    """The faces a support may push on: a mask of faces, and the excavation entries
    (indices into ``BlockSystem.sets``; -1: bared by none known) whose bare joint faces it
    takes too (:func:`bare_faces`). Every free face (the domain's boundary, the
    excavations' walls and every bare joint face) when `face` is None; the faces on a
    domain face (a name such as ``top``, or an index); or the walls of an excavation (its
    name, or ``excavations[i]``, the i-th ``[[excavations]]`` entry)."""
    entries = excavation_entries(blocks)
    if face is None:
        walls = (blocks.face_kind == BOUNDARY_FACE) | wall_faces(blocks, entries)
        return walls, [*entries.tolist(), -1]
    if isinstance(face, int) or face in FACE_DIRECTIONS:
        part = 0
        return on_domain_faces(blocks, domain_faces(blocks, face, part, path), part), []
    names = [str(blocks.sets[e].get("name")) for e in entries]
    chosen = [int(e) for e, name in zip(entries, names, strict=True) if name == face]
    chosen += [int(e) for k, e in enumerate(entries) if face == f"excavations[{k}]"]
    if not chosen:
        known = ", ".join(repr(name) for name in names) if names else "none"
        raise ModelError(
            path,
            f"no domain face or excavation named {face!r} (domain faces: "
            f"{', '.join(FACE_DIRECTIONS)}, or an index; excavations: {known}, or "
            "excavations[i])",
        )
    return wall_faces(blocks, np.asarray(chosen, dtype=np.int64)), chosen


@dataclass
class BareFaces:
    """Joint faces with a part that touches no other block (an excavation took the rock
    beyond): the bare part's area and centroid, and the excavation that bared it."""

    faces: np.ndarray  # (k,) face indices
    areas: np.ndarray  # (k,) the bare part's area
    centroids: np.ndarray  # (k, 3) its centroid
    entries: np.ndarray  # (k,) the excavation entry (index into sets) beyond it; -1 none

    def subset(self, mask: np.ndarray) -> BareFaces:
        return BareFaces(
            self.faces[mask], self.areas[mask], self.centroids[mask], self.entries[mask]
        )


def near_any(points: np.ndarray, others: np.ndarray, distance: float) -> np.ndarray:
    """Per point, whether some point of `others` lies within `distance` (in chunks, so
    that the distance table stays small)."""
    out = np.zeros(len(points), bool)
    if len(others) == 0:
        return out
    for start in range(0, len(points), 1024):
        chunk = points[start : start + 1024]
        gaps = np.linalg.norm(chunk[:, None, :] - others[None, :, :], axis=2)
        out[start : start + 1024] = (gaps <= distance).any(axis=1)
    return out


def bare_faces(blocks: Blocks, excavations: list[dict[str, Any]]) -> BareFaces:
    """The joint faces an excavation left bare, wholly or in part (a face of a block whose
    neighbour across the joint was inside the excavation keeps the joint's origin).

    A face's covered part is the sum of the face-face contacts on it (contact detection
    with geometry; the parts of a concave block touch along their glue, which counts); the
    rest, when more than ``AREA_MATCH`` of the face, is bare, with its centroid by
    subtraction. Which excavation bared it: the one that removes a small probe cube just
    beyond the bare part's centroid (``BlockSystem.excavate`` on the probes, each entry of
    `excavations`, the spec's ``[[excavations]]``, in turn)."""
    import penedge

    if blocks.bare is not None:  # found once, for every support
        return blocks.bare
    n_faces = len(blocks.face_areas)
    entries = excavation_entries(blocks)
    joint = (blocks.face_kind == JOINT_FACE) & ~np.isin(blocks.face_set, entries)
    empty = BareFaces(np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 3)), np.zeros(0, np.int64))
    if blocks.system is None or not joint.any():
        return empty
    # Every pair of parts, the parts of one body too (which `detect` leaves out): their
    # glue covers their faces.
    parts = blocks.system.with_bodies(list(range(len(blocks.system))))
    contacts = parts.detect(geometry=True)
    kinds = np.asarray(contacts.feature_kinds).reshape(-1, 2)
    areas = np.asarray(contacts.areas)
    rows = np.flatnonzero((kinds == 2).all(axis=1) & (areas > 0))
    first_face = np.searchsorted(blocks.face_block, np.arange(len(blocks)))
    pairs = np.asarray(contacts.pairs).reshape(-1, 2)[rows]
    faces = first_face[pairs] + np.asarray(contacts.feature_ids).reshape(-1, 2)[rows]
    offsets = np.asarray(contacts.point_offsets)
    counts = np.diff(offsets)[rows]
    loops = np.concatenate([[0], np.cumsum(counts)])
    within = np.arange(loops[-1]) - np.repeat(loops[:-1], counts)  # corner of its polygon
    points = np.asarray(contacts.points)[np.repeat(offsets[:-1][rows], counts) + within]
    _, centroids = polygons(points, loops, np.asarray(contacts.normals)[rows])
    covered = np.zeros(n_faces)
    moment = np.zeros((n_faces, 3))
    for side in (0, 1):
        covered += np.bincount(faces[:, side], areas[rows], n_faces)
        for k in range(3):
            moment[:, k] += np.bincount(faces[:, side], areas[rows] * centroids[:, k], n_faces)
    bare_area = blocks.face_areas - covered
    bare = np.flatnonzero(joint & (bare_area > AREA_MATCH * blocks.face_areas))
    area = bare_area[bare]
    whole = blocks.face_areas[bare, None] * blocks.face_centroids[bare]
    centroid = (whole - moment[bare]) / area[:, None]
    found = BareFaces(bare, area, centroid, np.full(len(bare), -1, np.int64))
    if len(bare):
        step = 1e-4 * blocks.size
        probes = centroid + 4 * step * blocks.face_normals[bare]
        cubes = [penedge.Block.cuboid(p - step, p + step) for p in probes]
        probe = penedge.BlockSystem(cubes)
        for k, excavation in enumerate(excavations[: len(entries)]):
            try:
                left, _ = probe.excavate(excavation)
                kept = np.asarray(left.centroids).reshape(-1, 3)
            except penedge.PenedgeError:
                continue  # removes none of the probes
            removed = ~near_any(probes, kept, step)
            found.entries[removed & (found.entries < 0)] = entries[k]
    blocks.bare = found
    return found


def pressure_load(
    blocks: Blocks,
    faces: np.ndarray,
    pressure: float,
    forces: np.ndarray,
    moments: np.ndarray,
    path: str,
    bare: BareFaces | None = None,
) -> float:
    """Adds to `forces` and `moments` (per block, about its centroid) the pressure on the
    free part of the faces of `faces`, pushing into the rock; the area pushed on (the
    faces' areas less their glue).

    A part face of a concave block may be glued, wholly or in part, to another part of its
    body (an internal face, docs/concave-blocks.md). Where both sides of a glue are
    pushed on, their pressures cancel in the body's sum (equal areas, opposite normals,
    one centroid), so the whole faces are taken. Where one side only is (a region that
    takes some parts of a concave block), the glue's pressure is taken off that side, at
    the centroid of the glue: the centroid of the face that is glue all over.
    """
    n = len(blocks)
    block = blocks.face_block[faces]
    f = -pressure * blocks.face_areas[faces, None] * blocks.face_normals[faces]
    at = blocks.face_centroids[faces]
    pushed = float(blocks.face_areas[faces].sum())
    if bare is not None and len(bare.faces):  # the bare part of joint faces
        block = np.concatenate([block, blocks.face_block[bare.faces]])
        normals = blocks.face_normals[bare.faces]
        f = np.concatenate([f, -pressure * bare.areas[:, None] * normals])
        at = np.concatenate([at, bare.centroids])
        pushed += float(bare.areas.sum())
    if blocks.glue_faces is not None and len(blocks.glue_faces):
        sides = faces[blocks.glue_faces]
        pushed -= float(sides.sum(axis=1) @ blocks.glue_areas)
        rows = np.flatnonzero(sides[:, 0] != sides[:, 1])
        if len(rows):
            own = np.where(sides[rows, 0], 0, 1)
            mine = blocks.glue_faces[rows, own]
            other = blocks.glue_faces[rows, 1 - own]
            area = blocks.glue_areas[rows]
            whole = [
                np.abs(area - blocks.face_areas[g])
                <= AREA_MATCH * np.maximum(area, blocks.face_areas[g])
                for g in (other, mine)
            ]
            unknown = ~(whole[0] | whole[1])
            if unknown.any():
                k = int(np.flatnonzero(unknown)[0])
                a, b = blocks.face_block[mine[k]], blocks.face_block[other[k]]
                raise ModelError(
                    path,
                    f"the region takes block {a} but not block {b} of one concave block, and "
                    "the pressure cannot tell which part of their glued face is free; make "
                    "the region take all the parts of the concave block or none",
                )
            centroid = np.where(
                whole[0][:, None], blocks.face_centroids[other], blocks.face_centroids[mine]
            )
            block = np.concatenate([block, blocks.face_block[mine]])
            f = np.concatenate([f, pressure * area[:, None] * blocks.face_normals[mine]])
            at = np.concatenate([at, centroid])
    m = np.cross(at - blocks.centroids[block], f)
    for k in range(3):
        forces[:, k] += np.bincount(block, f[:, k], n)
        moments[:, k] += np.bincount(block, m[:, k], n)
    return pushed


def bolt_blocks(blocks: Blocks, start: Any, end: Any, path: str) -> tuple[int, int]:
    """The blocks at the two ends of a bolt; an error when an end is outside the rock or
    both ends are in one block (the bolt would tie nothing)."""
    collar = first_block_along(blocks, np.asarray(start, float), np.asarray(end, float))
    if collar is None:
        raise ModelError(
            f"{path}.point",
            f"the bolt from {point_text(start)} to {point_text(end)} is outside the rock "
            "(it meets no block)",
        )
    anchor = blocks.containing(end, f"{path}.length", "the bolt's far end")
    if anchor is None:
        raise ModelError(
            f"{path}.length",
            f"the bolt's far end {point_text(end)} is outside the rock; a bolt must end in rock",
        )
    if anchor == collar:
        raise ModelError(
            path, f"the bolt lies in one block ({collar}): it crosses no joint and ties nothing"
        )
    return collar, anchor


def first_block_along(blocks: Blocks, start: np.ndarray, end: np.ndarray) -> int | None:
    """The block the segment start -> end enters first (the collar may lie on a free face,
    a hair outside the rock)."""
    crossed, _ = blocks_along(blocks, start, end)
    return crossed[0] if crossed else None


def blocks_along(blocks: Blocks, start: np.ndarray, end: np.ndarray) -> tuple[list[int], float]:
    """The blocks the segment start -> end passes through, in the order it enters them, and
    the fraction of the segment before the first (0 when `start` is in or on it)."""
    d = end - start
    # clip the segment by each block's face planes: t_in = max entering, t_out = min leaving
    dn = blocks.face_normals @ d
    dist = np.einsum("ij,ij->i", start - blocks.face_points, blocks.face_normals)
    n = len(blocks)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -dist / dn
    entering = dn < 0
    leaving = dn > 0
    parallel_out = (dn == 0) & (dist > 1e-9 * blocks.size)
    t_in = np.full(n, 0.0)
    np.maximum.at(t_in, blocks.face_block[entering], t[entering])
    t_out = np.full(n, 1.0)
    np.minimum.at(t_out, blocks.face_block[leaving], t[leaving])
    blocked = np.bincount(blocks.face_block, parallel_out, n).astype(bool)
    crosses = (t_out - t_in > 1e-9) & ~blocked
    if not crosses.any():
        return [], 1.0
    candidates = np.flatnonzero(crosses)
    order = candidates[np.argsort(t_in[candidates], kind="stable")]
    return [int(b) for b in order], float(t_in[order[0]])


def bolt_path(blocks: Blocks, start: Any, end: Any) -> BoltPath:
    """Where the bolt from `start` to `end` lies in the rock (:class:`BoltPath`); call after
    :func:`bolt_blocks` has accepted it."""
    a, b = np.asarray(start, float), np.asarray(end, float)
    crossed, before = blocks_along(blocks, a, b)
    length = float(np.linalg.norm(b - a))
    return BoltPath(crossed, before * length, (1.0 - before) * length)
