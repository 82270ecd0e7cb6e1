"""Draw the pictures of the documentation into docs/img/ (committed).

* ``example3.png``: the README's picture, made by the README's first command
  (``penedge example 3 --contacts``);
* ``contact-1-vertex-vertex.png`` ... ``contact-7-face-face.png``: one picture per contact
  type for docs/contact-types.md: two blocks in that configuration, the contact (A ∩ B) in
  the type's colour and the feature of each block that holds it outlined. Each pair goes
  through ``penedge.detect_pair`` first, and the script stops if penedge does not give the
  type the picture is named after: the pictures show what the engine finds.

Run from the repository root, with penedge installed with the ``plot`` extra:

    python3 tools/make_doc_pictures.py            # all pictures
    python3 tools/make_doc_pictures.py --check    # only check the seven pairs' types

The pairs are also checked by the tests (python/tests/test_docs.py).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import penedge

ROOT = Path(__file__).resolve().parents[1]
IMG = ROOT / "docs" / "img"

A_COLOR = (0.55, 0.68, 0.85)  # block A: blue-grey
B_COLOR = (0.90, 0.74, 0.52)  # block B: sand
FEATURE_COLOR = "0.05"


def rotation(axis, degrees):
    """The rotation matrix about `axis` by `degrees` (right-handed)."""
    axis = np.asarray(axis, dtype=float)
    x, y, z = axis / np.linalg.norm(axis)
    t = np.radians(degrees)
    c, s, k = np.cos(t), np.sin(t), 1 - np.cos(t)
    return np.array(
        [
            [c + x * x * k, x * y * k - z * s, x * z * k + y * s],
            [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
            [z * x * k - y * s, z * y * k + x * s, c + z * z * k],
        ]
    )


def box(size, rotate=None, at=(0.0, 0.0, 0.0), anchor=None):
    """A box of `size`, rotated about its centre, then moved so that its vertex `anchor`
    (an index of the box's vertices) lies at `at` (default: its centre at `at`)."""
    half = np.asarray(size, dtype=float) / 2
    cube = penedge.Block.cuboid(-half, half)
    vertices = cube.vertices if rotate is None else cube.vertices @ np.asarray(rotate).T
    ref = vertices.mean(axis=0) if anchor is None else vertices[anchor]
    return penedge.Block(vertices + (np.asarray(at, dtype=float) - ref), cube.faces)


def lowest_vertex(block):
    return int(np.argmin(block.vertices[:, 2]))


# The rotation that stands a cube on a vertex: its body diagonal (1, 1, 1) made vertical.
ON_VERTEX = rotation(np.cross([1, 1, 1], [0, 0, 1]), np.degrees(np.arccos(1 / np.sqrt(3))))


@dataclass
class Pair:
    """Two blocks in one contact configuration."""

    code: int
    a: penedge.Block
    b: penedge.Block
    what: str  # A ∩ B in words
    elev: float = 22.0
    azim: float = -60.0

    @property
    def name(self):
        return penedge.CONTACT_TYPES[self.code - 1]

    @property
    def file(self):
        return f"contact-{self.code}-{self.name}.png"


def pairs():
    """The seven configurations, by type code."""
    unit = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    slab = penedge.Block.cuboid([0, 0, 0], [2, 2, 0.6])
    on_edge_x = rotation([1, 0, 0], 45)  # a box resting on an edge parallel to x
    top = [1.0, 1.0, 0.6]  # the middle of the slab's top face
    stood = box([0.8, 0.8, 0.8], ON_VERTEX)
    return [
        Pair(1, unit, penedge.Block.cuboid([1, 1, 1], [2, 2, 2]), "a point: two vertices"),
        Pair(
            2,
            unit,
            vertex_on_edge(),
            "a point: a vertex on an edge",
            azim=-30,
        ),
        Pair(
            3,
            box([1.6, 1, 1], on_edge_x),  # top edge along x at height sqrt(2) / 2
            box([1, 1.6, 1], rotation([0, 1, 0], 45), [0, 0, np.sqrt(2)]),  # bottom edge along y
            "a point: two edges crossing",
            elev=18,
            azim=-35,
        ),
        Pair(
            4,
            unit,
            penedge.Block.cuboid([1, 1, 0.45], [2, 2, 1.45]),
            "a segment: collinear edges overlapping",
            azim=-25,
        ),
        Pair(
            5,
            slab,
            box([0.8, 0.8, 0.8], ON_VERTEX, top, lowest_vertex(stood)),
            "a point: a vertex in a face",
        ),
        Pair(
            6,
            slab,
            edge_on_face(slab),
            "a segment: an edge in a face",
        ),
        Pair(
            7,
            slab,
            box([1.5, 1.5, 0.7], rotation([0, 0, 1], 30), [1.25, 1.15, 0.95]),
            "a polygon: two faces overlapping",
            elev=48,
        ),
    ]


def vertex_on_edge():
    """A box lying on one of its edges along (1, -1, 0), the middle of that edge on the
    cube's corner (1, 1, 1): the edge leaves the cube's top face at once on both sides."""
    direction = np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
    # A box of length 1.4 along `direction`, square section 0.7 turned 45° about it.
    frame = np.column_stack([direction, [1 / np.sqrt(2), 1 / np.sqrt(2), 0.0], [0, 0, 1.0]])
    turn = rotation([1, 0, 0], 45)
    b = box([1.4, 0.7, 0.7], frame @ turn)
    low = b.vertices[:, 2] < b.vertices[:, 2].min() + 1e-9  # the lowest edge's two ends
    middle = b.vertices[low].mean(axis=0)
    return penedge.Block(b.vertices + (np.array([1.0, 1.0, 1.0]) - middle), b.faces)


def edge_on_face(slab):
    """A box resting on an edge parallel to x in the middle of the slab's top face."""
    b = box([1.2, 0.8, 0.8], rotation([1, 0, 0], 45))
    low = b.vertices[:, 2] < b.vertices[:, 2].min() + 1e-9
    middle = b.vertices[low].mean(axis=0)
    top = np.array([1.0, 1.0, slab.aabb[1, 2]])
    return penedge.Block(b.vertices + (top - middle), b.faces)


def check(pair):
    """penedge's answer for the pair; stops if it is not the pair's type."""
    found = penedge.detect_pair(pair.a, pair.b)
    if found.outcome != pair.name:
        sys.exit(f"{pair.file}: penedge finds {found.outcome}, not {pair.name}")
    swapped = penedge.detect_pair(pair.b, pair.a)
    if swapped.outcome != pair.name:
        sys.exit(f"{pair.file}: with the blocks swapped penedge finds {swapped.outcome}")
    return found


def feature_lines(block, feature):
    """The feature (kind, index) of a block as a list of polylines (a vertex: one point)."""
    kind, index = feature
    v = block.vertices
    if kind == "vertex":
        return [v[[index]]]
    if kind == "edge":
        return [v[block.edges[index]]]
    face = block.faces[index]
    return [v[[*face, face[0]]]]


def draw(pair, found, path):
    """One picture: the two blocks, the features outlined, the contact in its colour."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from penedge.pictures import CONTACT_COLORS
    from penedge.pictures.scene import padded_polygons

    fig = Figure(figsize=(4.2, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    ax.computed_zorder = False
    for block, color in ((pair.a, A_COLOR), (pair.b, B_COLOR)):
        faces = [block.vertices[f] for f in block.faces]
        ax.add_collection3d(
            Poly3DCollection(
                padded_polygons(faces),
                facecolors=(*color, 0.28),
                edgecolors=(0.2, 0.2, 0.2, 0.7),
                linewidths=0.7,
                zorder=1,
            )
        )
    color = CONTACT_COLORS[pair.code]
    points = found.points
    if len(points) >= 3:
        ax.add_collection3d(
            Poly3DCollection([points], facecolors=color, edgecolors=color, alpha=0.9, zorder=3)
        )
    elif len(points) == 2:
        ax.add_collection3d(Line3DCollection([points], colors=color, linewidths=5, zorder=3))
    else:
        ax.scatter(*points.T, color=color, s=90, depthshade=False, zorder=4, edgecolors="0.1")
    for block, feature in ((pair.a, found.feature_a), (pair.b, found.feature_b)):
        for line in feature_lines(block, feature):
            if len(line) == 1:
                ax.scatter(*line.T, color=FEATURE_COLOR, s=14, depthshade=False, zorder=5)
            else:
                ax.plot(*line.T, color=FEATURE_COLOR, lw=1.6, ls="--", zorder=5)
    everything = np.vstack([pair.a.vertices, pair.b.vertices])
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    for set_lim, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
        set_lim(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_proj_type("persp", focal_length=2.0)
    ax.view_init(elev=pair.elev, azim=pair.azim)
    ax.set_axis_off()
    (ka, ia), (kb, ib) = found.feature_a, found.feature_b
    ax.set_title(f"{pair.code}  {pair.name}", fontsize=12, pad=0)
    fig.text(
        0.5,
        0.02,
        f"A: {ka} {ia}, B: {kb} {ib}; A ∩ B: {pair.what}",
        ha="center",
        fontsize=8,
        color="0.3",
    )
    fig.savefig(path, dpi=110, facecolor="white", metadata={"Software": None})


def readme_picture(path):
    """The README's picture: exactly what ``penedge example 3 --contacts`` draws."""
    from penedge.cli import main

    status = main(["example", "3", "--contacts", "-o", str(path)])
    if status != 0:
        sys.exit(f"penedge example 3 failed with status {status}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="check the types, draw nothing")
    args = parser.parse_args(argv)
    checked = [(pair, check(pair)) for pair in pairs()]
    for pair, found in checked:
        print(f"{pair.file}: {found.outcome}, A {found.feature_a}, B {found.feature_b}")
    if args.check:
        return 0
    IMG.mkdir(parents=True, exist_ok=True)
    for pair, found in checked:
        draw(pair, found, IMG / pair.file)
    readme_picture(IMG / "example3.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
