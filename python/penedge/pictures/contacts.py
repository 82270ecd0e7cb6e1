"""Contacts drawn by type: points, segments and polygons, each type in its own colour (or
each joint set in its own colour), polygons translucent under the points and segments."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from penedge.pictures.scene import check_contacts, padded_polygons

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
    if block_offsets is not None:
        check_contacts(contacts, len(block_offsets))
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
    types: Iterable[int] | None = None,
    sets: np.ndarray | None = None,
    set_names: Sequence[str] = (),
) -> Axes:
    """Draw contacts into a 3D axes, coloured by type (or by joint set): polygons filled
    and translucent, segments as thick lines and points as dots drawn over them; all over
    what the axes already holds.

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
        A legend of the types (or sets) present, with their counts.
    max_contacts : int or None, default 3000
        Draw at most this many contacts (more make a solid mass): those nearest the
        corner of the system that faces the viewer, with a note saying so. None: all.
    view : numpy.ndarray, shape (3,), optional
        The direction towards the viewer (default: matplotlib's, from the axes).
    types : iterable of int, optional
        Draw only the contacts of these type codes (1..7).
    sets : numpy.ndarray, shape (n,), int, optional
        The joint set of each contact (-1: none; see ``Scene.contact_sets``): colour the
        contacts by set (``SET_COLORS``, grey for none) instead of by type.
    set_names : sequence of str
        The names of the sets, for the legend.

    Returns
    -------
    Axes3D
    """
    from matplotlib.colors import to_rgba
    from matplotlib.lines import Line2D
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from penedge.pictures.scene import NO_SET_COLOR, SET_COLORS

    if shown_blocks is not None:
        check_contacts(contacts, len(shown_blocks))
    points, segments, polygons, kinds = contact_shapes(contacts, block_offsets)
    codes = np.asarray(contacts.types)
    drawn = np.ones(len(codes), dtype=bool)
    if shown_blocks is not None and len(codes):
        drawn = np.asarray(shown_blocks, dtype=bool)[contacts.pairs].all(axis=1)
    if types is not None:
        drawn &= np.isin(codes, list(types))
    total = int(drawn.sum())
    counted = drawn.copy()  # the legend counts every contact meant, drawn or cut down
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
    if sets is None:
        group_of = codes
        palette = dict(CONTACT_COLORS)
    else:
        sets = np.asarray(sets, dtype=np.int64)
        group_of = sets + 2  # group 1: no set, 2 + s: set s
        palette = {1: NO_SET_COLOR}
        present = np.unique(sets[sets >= 0])
        palette.update({2 + int(s): SET_COLORS[s % len(SET_COLORS)] for s in present})
    groups = np.where(drawn, group_of, 0)
    many = drawn.sum() > 2000
    ax.computed_zorder = False  # draw the contacts over the blocks, points over polygons
    for group, color in palette.items():
        of_group = groups == group
        if not of_group.any():
            continue
        polys = [p for p, keep in zip(polygons, of_group[kinds == 3], strict=True) if keep]
        if polys:
            ax.add_collection3d(
                Poly3DCollection(
                    padded_polygons(polys),
                    facecolors=to_rgba(color, 0.25),
                    edgecolors=to_rgba(_darker(color), 0.8),
                    linewidths=0.4 if many else 0.8,
                    zorder=2,
                )
            )
        lines = segments[of_group[kinds == 2]]
        if len(lines):
            width = 1.2 if many else 2.5
            ax.add_collection3d(Line3DCollection(lines, colors=color, linewidths=width, zorder=3))
        dots = points[of_group[kinds == 1]]
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
        if sets is None:
            _legend(ax, group_of[counted], Line2D)
        else:
            title = "joint set of the contact's face"
            set_legend(ax, sets[counted], set_names, title, noun="")
    return ax


def set_legend(ax: Any, sets: np.ndarray, names: Sequence[str], title: str, noun: str) -> None:
    """A legend of joint sets: one entry per set present in `sets` (indices, -1 for none),
    in set order, with its count of `noun` (``"block"``), then the entry of no set."""
    from matplotlib.patches import Patch

    from penedge.pictures.scene import NO_SET_COLOR, SET_COLORS, plain_text

    sets = np.asarray(sets, dtype=np.int64)
    present, counts = np.unique(sets, return_counts=True)
    order = np.argsort(present < 0, kind="stable")  # the sets, then "no joint face"
    handles = []
    for s, n in zip(present[order], counts[order], strict=True):
        if s < 0:
            name, color = "no joint face", NO_SET_COLOR
        else:
            name = plain_text(names[s]) if s < len(names) else f"set {s}"
            color = SET_COLORS[s % len(SET_COLORS)]
        label = f"{name} ({n}{f' {noun}' + ('s' if n != 1 else '') if noun else ''})"
        handles.append(Patch(facecolor=color, edgecolor="0.2", label=label))
    if handles:
        ax.legend(
            handles=handles,
            loc="upper left",
            fontsize=8,
            framealpha=0.9,
            title=title,
            title_fontsize=8,
        )


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
