"""Hand-made pairs of blocks, one per outcome, with literal coordinates checkable by hand.

Block A is always the unit cube [0, 1]^3 (``Block.cuboid``: vertex 4 = (0, 0, 1),
vertex 5 = (1, 0, 1), vertex 6 = (1, 1, 1); its top face z = 1 is face 1). Most B blocks
are tetrahedra in the half-space z - y >= 1 (which meets the cube only along its edge
y = 0, z = 1) or z >= 1 (which meets it only in its top face): B's feature on the boundary
plane then decides the type.
"""

from __future__ import annotations

import numpy as np

import penedge

UNIT_CUBE = ([0, 0, 0], [1, 1, 1])


def tetra(points) -> penedge.Block:
    """A tetrahedron from four points in any order (faces oriented outward here)."""
    p = np.asarray(points, dtype=float)
    if np.linalg.det(np.array([p[1] - p[0], p[2] - p[0], p[3] - p[0]])) < 0:
        p = p[[0, 2, 1, 3]]
    return penedge.Block(p, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def cube() -> penedge.Block:
    return penedge.Block.cuboid(*UNIT_CUBE)


# outcome -> (B, expected feature of A as (kind, vertex set or face index), feature kind of B)
PAIRS = {
    "vertex-vertex": lambda: penedge.Block.cuboid([1, 1, 1], [2, 2, 2]),
    # B's vertex (0.5, 0, 1) in the middle of the cube's edge (0, 0, 1)-(1, 0, 1)
    "vertex-edge": lambda: tetra([[0.5, 0, 1], [0, -1, 2], [1, -1, 2], [0.5, 0.5, 2.5]]),
    # B's edge (0.5, -1, 0)-(0.5, 1, 2) crosses the cube's edge at (0.5, 0, 1)
    "edge-edge": lambda: tetra([[0.5, -1, 0], [0.5, 1, 2], [0, -1, 2], [1, -1, 2]]),
    # B's edge (0.5, 0, 1)-(2, 0, 1) overlaps the cube's edge along x in [0.5, 1]
    "edge-edge-superposition": lambda: tetra([[0.5, 0, 1], [2, 0, 1], [1, -1, 2], [1.2, 0.3, 2.5]]),
    # B's vertex at the centre of the top face
    "vertex-face": lambda: tetra([[0.5, 0.5, 1], [0, 0, 2], [1, 0, 2], [0.5, 1, 2]]),
    # B's edge (0.2, 0.5, 1)-(0.8, 0.5, 1) lies in the top face
    "edge-face": lambda: tetra([[0.2, 0.5, 1], [0.8, 0.5, 1], [0.5, 0, 2], [0.5, 1, 2]]),
    "face-face": lambda: penedge.Block.cuboid([0.2, 0.2, 1], [0.8, 0.8, 2]),
    "separated": lambda: penedge.Block.cuboid([1.5, 0, 0], [2.5, 1, 1]),
    "penetrating": lambda: penedge.Block.cuboid([0.5, 0.5, 0.5], [1.5, 1.5, 1.5]),
}

# The feature kinds (A, B) of each touching pair above.
FEATURE_KINDS = {
    "vertex-vertex": ("vertex", "vertex"),
    "vertex-edge": ("edge", "vertex"),
    "edge-edge": ("edge", "edge"),
    "edge-edge-superposition": ("edge", "edge"),
    "vertex-face": ("face", "vertex"),
    "edge-face": ("face", "edge"),
    "face-face": ("face", "face"),
}

TOUCHING = list(FEATURE_KINDS)


def pair(outcome: str) -> tuple[penedge.Block, penedge.Block]:
    """Blocks A (the unit cube) and B of the hand-made pair with this outcome."""
    return cube(), PAIRS[outcome]()


def moved(block: penedge.Block, rotation: np.ndarray, translation: np.ndarray) -> penedge.Block:
    """The block rotated about the origin, then translated (same vertex and face ids)."""
    return penedge.Block(block.vertices @ rotation.T + translation, block.faces)


def rotation_from_quaternion(q) -> np.ndarray:
    """The rotation matrix of a (not necessarily unit, non-zero) quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
