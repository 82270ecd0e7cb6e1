"""Contact detection between convex rock blocks by the penetration-edge method.

penedge implements Chen, Zheng, Cheng and Ge (2004): every edge of block A is clipped
by the face planes of block B widened by a gap, and vice versa; the surviving
*penetration edges* tell whether the blocks touch and which of seven contact types it is
(:data:`CONTACT_TYPES`; the codes 1..7 are also named :data:`VERTEX_VERTEX` ...
:data:`FACE_FACE`). The engine is Rust (``penedge._core``); this package re-exports
it, and adds a command line (``penedge example 3``) and pictures
(:mod:`penedge.pictures`, needs matplotlib).

Blocks
    :class:`Block` -- a convex polyhedron from vertices + faces, half-spaces
    (:meth:`Block.from_planes`) or corners (:meth:`Block.cuboid`).
Pairs
    :func:`detect_pair` -- the contact of two blocks, a :class:`PairContact`;
    :func:`overlap` -- normal, depth and region of two penetrating blocks (soft contact).
Systems
    :class:`BlockSystem` -- many blocks; :meth:`BlockSystem.detect` returns every
    contact as numpy arrays (:class:`SystemContacts`), with ``geometry=True`` also normals,
    distances, areas and contact points. :func:`paper_example` builds the paper's three
    examples, :func:`paper_table3` gives its printed counts.
Time stepping
    :class:`ContactTracker` -- the contacts of moving blocks, step after step, reusing
    the broad phase within a skin and skipping pairs whose blocks did not move or that are
    clearly apart or overlapping.
Mechanics
    :class:`Simulation` -- rigid-block DEM (3DEC-style) on a block system: gravity,
    joint properties per set (Mohr-Coulomb with tension and cohesion), fixed and prescribed
    blocks, damping, ``step`` / ``solve`` / ``run_until``, the state and the contact and
    sub-contact forces as numpy arrays (``docs/mechanics.md``).
Generation
    :func:`generate` -- a rock domain cut by joint planes, joint sets and finite joints
    (a spec file, TOML text or a dict) into a :class:`BlockSystem`; its blocks as flat
    arrays (:meth:`BlockSystem.arrays`), volume statistics, and files (JSON, VTU, CSV).
Files
    :meth:`BlockSystem.write_json` / :meth:`BlockSystem.read_json` (lossless),
    :meth:`BlockSystem.write_vtu` and :meth:`SystemContacts.write_vtp` (ParaView),
    :class:`TimeSeries` -- blocks and contacts step after step as a ParaView time series
    (``.pvd``), :func:`write_pvd` -- a time series index of any files.
Errors
    :exc:`PenedgeError` and its subclasses :exc:`InputError`, :exc:`BlockError`,
    :exc:`ToleranceError`, :exc:`SpecError`, :exc:`FileFormatError`,
    :exc:`MechanicsError` (all also
    ``ValueError``); files that cannot be read or written raise ``OSError``.

Conventions: right-handed frame; faces counter-clockwise seen from outside, normals
outward; tolerances (`gap`, `length`) are relative to the smaller block's size.

Examples
--------
>>> import penedge
>>> a = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
>>> b = penedge.Block.cuboid([1, 1, 0], [2, 2, 1])
>>> penedge.detect_pair(a, b).outcome
'edge-edge-superposition'
>>> found = penedge.paper_example(1).detect()
>>> found.counts() == penedge.paper_table3(1)
True
"""

from penedge._core import (
    CONTACT_TYPES,
    EDGE_EDGE,
    EDGE_EDGE_SUPERPOSITION,
    EDGE_FACE,
    FACE_FACE,
    FEATURE_KINDS,
    PENETRATING,
    SEPARATED,
    VERTEX_EDGE,
    VERTEX_FACE,
    VERTEX_VERTEX,
    Block,
    BlockArrays,
    BlockError,
    BlockSystem,
    BodyContacts,
    ContactTracker,
    FileFormatError,
    InputError,
    MechanicsError,
    PairContact,
    PenedgeError,
    Simulation,
    SpecError,
    SystemContacts,
    TimeSeries,
    ToleranceError,
    __version__,
    detect_pair,
    generate,
    overlap,
    paper_example,
    paper_example_planes,
    paper_table3,
    write_pvd,
)

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
    "BodyContacts",
    "ContactTracker",
    "FileFormatError",
    "InputError",
    "MechanicsError",
    "PairContact",
    "PenedgeError",
    "Simulation",
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
