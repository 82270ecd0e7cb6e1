"""Contacts drawn by type: points, segments and polygons, each type in its own colour."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from penedge._core import SystemContacts

__all__ = ["CONTACT_COLORS", "DEFAULT_MAX_CONTACTS", "contact_shapes", "plot_contacts"]

#: The most contacts :func:`plot_contacts` draws by default.
DEFAULT_MAX_CONTACTS = 3000

#: Colour of each contact type, by type code 1..7 (``CONTACT_COLORS[code]``).
CONTACT_COLORS = {
    1: "#d62728",  # vertex-vertex: red
    2: "#ff7f0e",  # vertex-edge: orange
    3: "#9467bd",  # edge-edge: purple
    4: "#1f77b4",  # edge-edge-superposition: blue
    5: "#8c564b",  # vertex-face: brown
    6: "#17becf",  # edge-face: cyan
    7: "#2ca02c",  # face-face: green
}


def contact_shapes(
    contacts: SystemContacts, block_offsets: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, list[np.ndarray], np.ndarray]:
    """The contact points grouped by shape, each contact moved with its blocks.

    Parameters
    ----------
    contacts : SystemContacts
        Found with ``detect(geometry=True)``.
    block_offsets : numpy.ndarray, shape (n_blocks, 3), optional
        A displacement of each block (an exploded view); a contact moves by the mean of its
        two blocks' displacements. Default: none.

    Returns
    -------
    points : numpy.ndarray, shape (p, 3)
        Point contacts.
    segments : numpy.ndarray, shape (s, 2, 3)
        Segment contacts (edge-face, edge-edge superposition).
    polygons : list of numpy.ndarray
        Polygon contacts (face-face), each (k, 3).
    kinds : numpy.ndarray, shape (n,), int
        For each contact: 1 point, 2 segment, 3 polygon; the three groups keep contact order.

    Examples
    --------
    >>> import penedge
    >>> from penedge.pictures import contact_shapes
    >>> found = penedge.paper_example(1).detect(geometry=True)
    >>> points, segments, polygons, kinds = contact_shapes(found)
    >>> len(points), len(segments), len(polygons)
    (4, 12, 12)
    """
    if contacts.points is None or contacts.point_offsets is None:
        raise ValueError("the contacts have no geometry: use detect(geometry=True)")
    offsets = contacts.point_offsets
    sizes = np.diff(offsets)
    points = np.asarray(contacts.points, dtype=float)
    if block_offsets is not None and len(sizes):
        shift = block_offsets[contacts.pairs].mean(axis=1)
        points = points + np.repeat(shift, sizes, axis=0)
    kinds = np.minimum(sizes, 3)
    starts = offsets[:-1]
    single = points[starts[kinds == 1]]
    first = starts[kinds == 2]
    segments = np.stack([points[first], points[first + 1]], axis=1).reshape(-1, 2, 3)
    polygons = [
        points[s : s + k] for s, k in zip(starts[kinds == 3], sizes[kinds == 3], strict=True)
    ]
    return single, segments, polygons, kinds


def plot_contacts(
    contacts: SystemContacts,
    *,
    ax: Axes,
    block_offsets: np.ndarray | None = None,
    shown_blocks: np.ndarray | None = None,
    legend: bool = True,
    max_contacts: int | None = DEFAULT_MAX_CONTACTS,
    view: np.ndarray | None = None,
) -> Axes:
    """Draw contacts into a 3D axes, coloured by type: polygons filled, segments as thick
    lines, points as dots; drawn over what the axes already holds.

    Parameters
    ----------
    contacts : SystemContacts
        Found with ``detect(geometry=True)``.
    ax : Axes3D
    block_offsets : numpy.ndarray, shape (n_blocks, 3), optional
        Displacements of the blocks (see :func:`contact_shapes`).
    shown_blocks : numpy.ndarray, shape (n_blocks,), bool, optional
        Draw only the contacts between these blocks (default: every contact).
    legend : bool, default True
        A legend of the types present, with their counts.
    max_contacts : int or None, default 3000
        Draw at most this many contacts (more make a solid mass): those nearest the
        corner of the system that faces the viewer, with a note saying so. None: all.
    view : numpy.ndarray, shape (3,), optional
        The direction towards the viewer (default: matplotlib's, from the axes).

    Returns
    -------
    Axes3D
    """
    from matplotlib.colors import to_rgba
    from matplotlib.lines import Line2D
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    points, segments, polygons, kinds = contact_shapes(contacts, block_offsets)
    types = np.asarray(contacts.types)
    drawn = np.ones(len(types), dtype=bool)
    if shown_blocks is not None and len(types):
        drawn = np.asarray(shown_blocks, dtype=bool)[contacts.pairs].all(axis=1)
    total = int(drawn.sum())
    counted = types[drawn]
    if max_contacts is not None and total > max_contacts:
        drawn &= _nearest(contacts, block_offsets, drawn, max_contacts, ax, view)
        ax.text2D(
            0.5,
            0.03,
            f"showing {max_contacts} of {total} contacts: those nearest the viewer",
            transform=ax.transAxes,
            ha="center",
            va="bottom",
            fontsize=8,
        )
    many = drawn.sum() > 2000
    ax.computed_zorder = False  # draw the contacts over the blocks
    for code, color in CONTACT_COLORS.items():
        of_type = (types == code) & drawn
        if not of_type.any():
            continue
        polys = [p for p, keep in zip(polygons, of_type[kinds == 3], strict=True) if keep]
        if polys:
            ax.add_collection3d(
                Poly3DCollection(
                    polys,
                    facecolors=to_rgba(color, 0.35),
                    edgecolors=to_rgba(_darker(color), 0.9),
                    linewidths=0.4 if many else 1.0,
                    zorder=2,
                )
            )
        lines = segments[of_type[kinds == 2]]
        if len(lines):
            width = 1.2 if many else 2.5
            ax.add_collection3d(Line3DCollection(lines, colors=color, linewidths=width, zorder=3))
        dots = points[of_type[kinds == 1]]
        if len(dots):
            ax.scatter(
                *dots.T,
                color=color,
                s=6 if many else 18,
                depthshade=False,
                zorder=4,
                edgecolors="0.15",
                linewidths=0 if many else 0.5,
            )
    if legend:
        _legend(ax, counted, Line2D)
    return ax


def _nearest(
    contacts: Any,
    block_offsets: np.ndarray | None,
    drawn: np.ndarray,
    count: int,
    ax: Any,
    view: np.ndarray | None,
) -> np.ndarray:
    """The `count` drawn contacts nearest the corner of their box that faces the viewer."""
    if view is None:
        e, a = np.radians(ax.elev), np.radians(ax.azim)
        view = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    anchors = np.asarray(contacts.points, dtype=float)[contacts.point_offsets[:-1]]
    if block_offsets is not None:
        anchors = anchors + block_offsets[contacts.pairs].mean(axis=1)
    lo, hi = anchors[drawn].min(axis=0), anchors[drawn].max(axis=0)
    corner = (lo + hi) / 2 + (hi - lo) / 2 * np.sign(view)
    distance = np.where(drawn, np.linalg.norm(anchors - corner, axis=1), np.inf)
    keep = np.zeros(len(drawn), dtype=bool)
    keep[np.argsort(distance, kind="stable")[:count]] = True
    return keep


def _darker(color: str) -> tuple[float, float, float]:
    from matplotlib.colors import to_rgb

    return tuple(0.6 * c for c in to_rgb(color))  # type: ignore[return-value]


def _legend(ax: Any, types: np.ndarray, line: Any) -> None:
    from penedge import CONTACT_TYPES

    counts = np.bincount(types.astype(int), minlength=8)
    handles = [
        line([], [], color=CONTACT_COLORS[code], lw=6, label=f"{CONTACT_TYPES[code - 1]} ({n})")
        for code, n in enumerate(counts[1:8], start=1)
        if n
    ]
    if handles:
        ax.legend(handles=handles, loc="upper left", fontsize=9, framealpha=0.9)
