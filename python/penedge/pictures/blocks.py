"""Block systems in an exploded perspective view, like the paper's Figures 9-12.

Each block is moved outward from the system's centroid by ``explode`` times its own
centroid's distance from it, so that inner blocks show; faces are filled with the colour of
the block's joint set (with a legend), or one colour per block, or a colour for the block's
volume (with a colour bar), shaded by their orientation, and edges are drawn. Blocks as
they lie (``explode=0``) are drawn on axes of their real coordinates, in the model's length
unit; an exploded view, whose positions are not real, gets a scale bar (block sizes are
true) and a north arrow instead. Given contacts, the blocks are drawn faintly and the
contacts over them (:mod:`penedge.pictures.contacts`); :func:`save_picture` draws one
small panel per contact type.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from penedge.pictures.scene import (
    COLOR_BY,
    DEFAULT_MAX_BLOCKS,
    VOLUME_COLORMAP,
    Scene,
    block_colors,
    build_scene,
    check_contacts,
    check_explode,
    padded_polygons,
    plain_text,
    set_colors,
    shown_note,
    volume_scale,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from penedge._core import Block, BlockSystem, SystemContacts

__all__ = ["block_colors", "exploded_faces", "plot_system", "save_picture"]

_GHOST_ALPHA = 0.1  # face opacity of the blocks under the contacts
_ONE_COLLECTION_ABOVE = 1500  # blocks: above, all faces go into one collection

# Light from the viewer's upper left (matplotlib's default view: elev 22, azim -58).
_LIGHT = np.array([-0.35, -0.75, 0.85]) / np.linalg.norm([-0.35, -0.75, 0.85])


def _blocks(system: BlockSystem | Iterable[Block]) -> list[Block]:
    blocks = getattr(system, "blocks", system)
    return list(blocks)


def exploded_faces(
    system: BlockSystem | Iterable[Block], explode: float = 0.5
) -> list[tuple[list[np.ndarray], np.ndarray, np.ndarray]]:
    """The faces of every block, moved outward for an exploded view.

    Parameters
    ----------
    system : BlockSystem or iterable of Block
    explode : float, default 0.5
        Each block moves by ``explode * (its centroid - the system centroid)``; 0 draws the
        system as it is. At most ``MAX_EXPLODE`` (100); a ValueError otherwise.

    Returns
    -------
    list of (faces, normals, offset)
        Per block: the face polygons (each an (k, 3) array, already moved), the outward
        unit normals (f, 3), and the displacement (3,).
    """
    explode = check_explode(explode)
    blocks = _blocks(system)
    if not blocks:
        return []
    volumes = np.array([b.volume for b in blocks])
    centroids = np.array([b.centroid for b in blocks])
    centre = volumes @ centroids / volumes.sum()
    out = []
    for block, c in zip(blocks, centroids, strict=True):
        offset = explode * (c - centre)
        vertices = block.vertices + offset
        faces = [vertices[f] for f in block.faces]
        out.append((faces, block.face_normals, offset))
    return out


def _view_direction(elev: float, azim: float) -> np.ndarray:
    """Unit vector from the scene towards the viewer (matplotlib's elev / azim)."""
    e, a = np.radians(elev), np.radians(azim)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def _set_equal_limits(ax: Any, lo: np.ndarray, hi: np.ndarray) -> None:
    centre, half = (lo + hi) / 2, max((hi - lo).max() / 2 * 1.02, 1e-300)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def volume_norm(volumes: np.ndarray) -> Any:
    """The matplotlib norm of the volume colour scale (logarithmic when the volumes span
    more than a factor of 10)."""
    from matplotlib.colors import LogNorm, Normalize

    lo, hi, log = volume_scale(volumes)
    return LogNorm(lo, hi) if log else Normalize(lo, hi)


def resolve_color_by(color_by: str | None, scene: Scene) -> str:
    """`color_by`, checked; None means ``"set"`` for a system generated with joint sets
    (spec entries of kind ``"set"``), else ``"block"`` (single planes, such as the paper's
    examples, give most blocks several sets of equal area)."""
    if color_by is None:
        has_sets = "set" in scene.set_kinds and (scene.block_sets >= 0).any()
        return "set" if has_sets else "block"
    if color_by not in COLOR_BY:
        raise ValueError(f"color_by must be one of {', '.join(COLOR_BY)}, got {color_by!r}")
    return color_by


def length_unit(system: Any, unit: str | None) -> str:
    """`unit`, else the system's (``BlockSystem.unit``), else ``"m"``."""
    return unit or getattr(system, "unit", None) or "m"


#: The id of the text ``showing N of M blocks`` (:func:`save_picture` moves it under the
#: picture, with the subtitle).
_NOTE_GID = "penedge-shown-note"


def set_name(scene: Scene, index: int) -> str:
    """The name of joint set `index` (``"no joint face"`` for -1)."""
    if index < 0:
        return "no joint face"
    return scene.set_names[index] if index < len(scene.set_names) else f"set {index}"


def _base_colors(
    scene: Scene, color_by: str, colors: Sequence[Any] | None
) -> tuple[np.ndarray, Any]:
    """RGB per block (convex part), and the norm of the volume scale (None unless coloured
    by volume). The parts of a concave block get one colour: its body's set, the colour of
    its first part, or its body's volume; `colors` given are used as they are, per part."""
    n = scene.n_blocks
    if colors is not None:
        from matplotlib.colors import to_rgb

        rgb = np.array([to_rgb(c) for c in colors], dtype=float).reshape(-1, 3)
        if len(rgb) != n:
            raise ValueError(f"colors: {len(rgb)} colours for {n} blocks")
        return rgb, None
    if color_by == "set":
        return set_colors(scene.block_sets), None
    if color_by == "block":
        return block_colors(n)[scene.body_first], None
    import matplotlib

    norm = volume_norm(scene.body_volumes)
    cmap = matplotlib.colormaps[VOLUME_COLORMAP]
    clipped = np.clip(scene.block_volumes, norm.vmin, norm.vmax)
    return np.asarray(cmap(norm(clipped)))[:, :3].reshape(-1, 3), norm


def nice_length(extent: float) -> float:
    """A round length (1, 2 or 5 times a power of ten) of about a fifth of `extent`."""
    if not extent > 0:
        return 1.0
    target = extent / 5
    power = 10.0 ** np.floor(np.log10(target))
    return float(max(m * power for m in (1, 2, 5) if m * power <= target))


def _real_axes(ax: Any, unit: str) -> None:
    """Axes of real coordinates, labelled with the frame and the unit."""
    ax.set_axis_on()
    for name, label in (("x", "x, east"), ("y", "y, north"), ("z", "z, up")):
        getattr(ax, f"set_{name}label")(f"{label} ({unit})", fontsize=9, labelpad=2)
    ax.tick_params(labelsize=7, pad=0)


def _scale_and_north(ax: Any, lo: np.ndarray, hi: np.ndarray, unit: str) -> None:
    """A scale bar along x (east) and a north arrow along y, under the front corner of the
    drawn blocks (an exploded view: sizes are true, positions are not)."""
    extent = float((hi - lo).max())
    length = nice_length(extent)
    gap = 0.06 * extent
    x0, y0, z0 = lo[0], lo[1] - gap, lo[2]
    style = {"color": "0.1", "linewidth": 2.0, "zorder": 20}
    tick = 0.02 * extent
    ax.plot([x0, x0 + length], [y0, y0], [z0, z0], **style)
    for x in (x0, x0 + length):
        ax.plot([x, x], [y0, y0], [z0 - tick, z0 + tick], **style)
    ax.text(
        x0 + length / 2,
        y0 - gap / 2,
        z0,
        f"{length:g} {unit}",
        fontsize=8,
        ha="center",
        va="top",
        zorder=20,
    )
    # The north arrow: a shaft along +y and a head of two short strokes (lines, so that the
    # axes' collections stay the blocks and the contacts).
    nx, head = x0 - gap, 0.3 * length
    tip = y0 + length
    ax.plot([nx, nx], [y0, tip], [z0, z0], **style)
    for side in (-1, 1):
        ax.plot([nx + side * head / 2, nx], [tip - head, tip], [z0, z0], **style)
    ax.text(
        nx,
        tip + 0.15 * length,
        z0,
        "N",
        fontsize=10,
        fontweight="bold",
        ha="center",
        va="center",
        zorder=20,
    )


def _set_legend(ax: Any, scene: Scene) -> None:
    """A legend of the joint sets of the blocks drawn, with their block counts (a concave
    block counts once)."""
    from penedge.pictures.contacts import set_legend

    first = scene.shown & (scene.body_first == np.arange(scene.n_blocks))
    sets = scene.block_sets[first]
    set_legend(ax, sets, scene.set_names, "dominant joint set", noun="block")


def plot_system(
    system: BlockSystem | Iterable[Block],
    *,
    ax: Axes | None = None,
    explode: float = 0.5,
    alpha: float = 0.92,
    title: str | None = None,
    labels: bool = False,
    colors: Sequence[Any] | None = None,
    color_by: str | None = None,
    colorbar: bool = True,
    legend: bool = True,
    contacts: SystemContacts | None = None,
    contact_types: Iterable[int] | None = None,
    max_blocks: int | None = DEFAULT_MAX_BLOCKS,
    unit: str | None = None,
    elev: float = 24.0,
    azim: float = -56.0,
) -> Axes:
    """Draw a block system in an exploded perspective view (matplotlib).

    Parameters
    ----------
    system : BlockSystem or iterable of Block
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional
        Axes to draw into; default a new figure (not registered with pyplot).
    explode : float, default 0.5
        Each block moves by ``explode * (its centroid - the system centroid)``. With 0 the
        blocks lie where they are, on axes of their real coordinates; otherwise the axes
        are hidden (they would show the moved positions) and a scale bar and a north arrow
        (+y) are drawn. From 0 to 100 (``MAX_EXPLODE``): anything else is a ValueError.
    alpha : float, default 0.92
        Face opacity (faces turned away from the viewer are not drawn).
    title : str, optional
        Axes title.
    labels : bool, default False
        Write each block's id at its (moved) centroid: a concave block's body id once, at
        the centroid of the whole body.
    colors : sequence of colours, optional
        One matplotlib colour per block (per convex part of a concave block, used as
        given; overrides `color_by`).
    color_by : {"set", "block", "volume"}, optional
        The colour of a block's joint set (the spec entry holding most of its face area,
        with a legend; grey for blocks with no joint face), each block its own colour, or a
        colour for its volume (viridis, logarithmic when the volumes span more than a
        factor of 10) with a colour bar. Default: ``"set"`` for a system generated with
        joint sets (spec entries of type ``set``), else ``"block"``. A concave block
        (convex parts sharing a body id) is one block in each: the set of most of the
        whole body's face area, one colour, the volume of the whole body.
    colorbar : bool, default True
        Draw the colour bar of ``color_by="volume"``.
    legend : bool, default True
        Draw the legend of the joint sets (``color_by="set"``) or of the contacts.
    contacts : SystemContacts, optional
        Contacts of `system` found with ``detect(geometry=True)``: drawn over faint blocks
        (:func:`penedge.pictures.plot_contacts`): coloured by type, or by the joint set of
        their faces when the blocks are coloured by set. Contacts of another system (a block
        number this one does not have) are a ValueError.
    contact_types : iterable of int, optional
        Draw only the contacts of these type codes (1..7).
    max_blocks : int or None, default 20000
        Draw at most this many blocks: those on the outside of the rock mass first, then
        the largest (a note under the picture says so). A concave block counts once and is
        drawn whole or not at all. None: every block.
    unit : str, optional
        The model's length unit, for the axes and the scale bar; default the system's
        (``BlockSystem.unit``, from the spec), else ``"m"``. Drawn as written (a ``$`` is no
        mathtext).
    elev, azim : float
        View angles in degrees.

    Returns
    -------
    Axes3D
        The axes drawn into (``ax.figure`` is the figure). The faces of each block are
        one ``Poly3DCollection`` (above 1500 blocks, the faces of all blocks are one).

    Examples
    --------
    >>> import penedge
    >>> from penedge.pictures import plot_system
    >>> ax = plot_system(penedge.paper_example(1), title="Example 1")
    >>> len(ax.collections), len(ax.collections[0].get_facecolor())  # 8 cubes, 3 faces seen
    (8, 3)
    >>> ax = plot_system(penedge.paper_example(1), explode=0)
    >>> ax.get_xlabel(), bool(ax.get_xlim()[0] <= 0 and ax.get_xlim()[1] >= 10)
    ('x, east (m)', True)
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(7.0, 7.0), layout="constrained").add_subplot(projection="3d")
    scene = build_scene(system, explode, max_blocks)
    if contacts is not None:
        check_contacts(contacts, scene.n_blocks)
    color_by = resolve_color_by(color_by, scene)
    unit = plain_text(length_unit(system, unit))  # drawn as it is, never as mathtext
    base, norm = _base_colors(scene, color_by, colors)
    ghost = contacts is not None
    if ghost:
        faces = np.arange(scene.n_faces)
    else:
        view = _view_direction(elev, azim)
        faces = np.flatnonzero(scene.face_normals @ view > -0.1)
    if len(faces):
        light = np.clip(scene.face_normals[faces] @ _LIGHT, 0.0, 1.0)
        rgb = np.clip(base[scene.face_block[faces]] * (0.55 + 0.45 * light[:, None]), 0, 1)
        face_alpha = _GHOST_ALPHA if ghost else alpha
        width = _edge_width(scene.n_shown)
        facecolors = np.column_stack([rgb, np.full(len(faces), face_alpha)])
        # matplotlib sorts collections by depth, and the faces inside each: one collection
        # per block paints exploded blocks in the right order; one for all is much faster.
        if scene.n_shown <= _ONE_COLLECTION_ABOVE:
            block = scene.face_block[faces]
            cuts = np.flatnonzero(np.diff(block)) + 1
            parts = zip(np.split(faces, cuts), np.split(facecolors, cuts), strict=True)
        else:
            parts = zip([faces], [facecolors], strict=True)
        for part, part_colors in parts:
            ax.add_collection3d(
                Poly3DCollection(
                    padded_polygons(scene.polygons(part)),
                    facecolors=part_colors,
                    edgecolors=(0.35, 0.35, 0.35, 0.35) if ghost else (0.1, 0.1, 0.1, 0.95),
                    linewidths=min(width, 0.5) if ghost else width,
                    zorder=1,
                )
            )
    if scene.n_faces:
        _set_equal_limits(ax, *scene.bounds())
    if labels:
        for b in np.flatnonzero(scene.shown_bodies):
            x, y, z = scene.body_centroids[b]
            label = str(scene.body_ids[b])
            ax.text(x, y, z, label, fontsize=7, ha="center", va="center", color="0.1", zorder=10)
    if ghost:
        from penedge.pictures.contacts import plot_contacts

        by_set = color_by == "set" and colors is None
        plot_contacts(
            contacts,
            ax=ax,
            block_offsets=scene.offsets,
            shown_blocks=scene.shown,
            view=_view_direction(elev, azim),
            types=contact_types,
            # A panel of one type coloured by type says so in its title: no legend.
            legend=legend and (by_set or contact_types is None),
            sets=scene.contact_sets(contacts) if by_set else None,
            set_names=scene.set_names,
        )
    elif legend and color_by == "set" and colors is None:
        _set_legend(ax, scene)
    if norm is not None and colorbar:
        below = bool(scene.body_volumes.min(initial=np.inf) < norm.vmin)
        _volume_colorbar(ax, norm, below, unit)
    note = shown_note(scene)
    if note:
        ax.text2D(
            0.5,
            0.0,
            note,
            transform=ax.transAxes,
            ha="center",
            va="bottom",
            fontsize=8,
            gid=_NOTE_GID,
        )
    ax.set_proj_type("persp", focal_length=2.0)
    ax.view_init(elev=elev, azim=azim)
    if explode == 0 and scene.n_faces:
        _real_axes(ax, unit)
    else:
        ax.set_axis_off()
        if scene.n_faces:
            _scale_and_north(ax, *scene.bounds(), unit)
    if title:
        ax.set_title(title, fontsize=13, pad=0)
    return ax


def _edge_width(n_blocks: int) -> float:
    """Thinner edges for many blocks, so that the faces still show."""
    return 0.8 if n_blocks <= 200 else max(0.15, 0.8 * float(np.sqrt(200 / n_blocks)))


def _volume_colorbar(ax: Any, norm: Any, below: bool, unit: str) -> None:
    """The colour bar of the volumes; a triangle at the bottom when smaller blocks (slivers)
    share its lowest colour."""
    import matplotlib
    from matplotlib.cm import ScalarMappable

    mappable = ScalarMappable(norm=norm, cmap=matplotlib.colormaps[VOLUME_COLORMAP])
    bar = ax.figure.colorbar(
        mappable, ax=ax, shrink=0.55, pad=0.0, aspect=25, extend="min" if below else "neither"
    )
    label = f"block volume ({unit}³)"
    if below:
        label += "\nsmaller blocks in the lowest colour"
    bar.set_label(label, fontsize=10)


def save_picture(
    system: BlockSystem | Iterable[Block],
    path: Any,
    *,
    title: str | None = None,
    subtitle: str | None = None,
    explode: float = 0.5,
    dpi: int = 150,
    format: str | None = None,
    contacts: SystemContacts | None = None,
    **kwargs: Any,
) -> Figure:
    """Draw a block system (:func:`plot_system`) and save it to a file.

    Uses matplotlib's Agg canvas directly: no window, no pyplot state.

    Parameters
    ----------
    system : BlockSystem or iterable of Block
    path : str or path-like or binary file object
        Where to write; the format comes from `format`, else from the file name.
    title : str, optional
        Title above the picture.
    subtitle : str, optional
        A smaller caption below the picture.
    explode : float, default 0.5
        From 0 to 100, as in :func:`plot_system`.
    dpi : int, default 150
    format : str, optional
        ``"png"``, ``"svg"``, ``"pdf"``, ... (needed when `path` has no suffix).
    contacts : SystemContacts, optional
        Contacts found with ``detect(geometry=True)``: beside the blocks, one small panel
        per contact type present, each with that type's contacts over faint blocks
        (coloured by the joint set of their faces when the blocks are coloured by set), so
        that polygons do not hide points and segments.
    **kwargs
        Passed to :func:`plot_system` (``color_by="volume"``, ``max_blocks``, ``unit``,
        ...).

    Returns
    -------
    matplotlib.figure.Figure
        Its axes: the blocks, then one per contact type.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from penedge import CONTACT_TYPES

    explode = check_explode(explode)
    wide = 1.0 if kwargs.get("color_by") == "volume" else 0.0
    if contacts is None:
        fig = Figure(figsize=(7.0 + wide, 7.0), layout="constrained")
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(projection="3d")
        plot_system(system, ax=ax, explode=explode, **kwargs)
        if title:
            ax.set_title(title, fontsize=13, pad=0)
    else:
        types = np.asarray(contacts.types)
        present = [int(t) for t in np.unique(types)]
        columns = 1 if len(present) <= 1 else 2
        rows = max(1, -(-len(present) // columns))
        fig = Figure(figsize=(7.0 + 3.5 * columns + wide, 7.0), layout="constrained")
        FigureCanvasAgg(fig)
        outer = fig.add_gridspec(1, 2, width_ratios=[7.0 + wide, 3.5 * columns])
        ax = fig.add_subplot(outer[0], projection="3d")
        plot_system(system, ax=ax, explode=explode, **kwargs)
        ax.set_title("blocks", fontsize=11, pad=0)
        grid = outer[1].subgridspec(rows, columns)
        small = {**kwargs, "colorbar": False}
        for k, code in enumerate(present):
            panel = fig.add_subplot(grid[k // columns, k % columns], projection="3d")
            plot_system(
                system,
                ax=panel,
                explode=explode,
                contacts=contacts,
                contact_types=[code],
                **small,
            )
            count = int((types == code).sum())
            panel.set_title(f"{CONTACT_TYPES[code - 1]} ({count})", fontsize=10, pad=0)
        if title:
            fig.suptitle(title, fontsize=13)
    # The note of a cut-down system goes under the picture, after the subtitle, once: at the
    # bottom of the blocks' axes it would overlap the subtitle, in each small panel the
    # panels.
    captions = [subtitle] if subtitle else []
    for panel in fig.axes:
        for note in [t for t in panel.texts if t.get_gid() == _NOTE_GID]:
            if panel is ax:
                captions.append(note.get_text())
            note.remove()
    if captions:
        fig.text(
            0.5, 0.015, "\n".join(captions), ha="center", va="bottom", fontsize=9, color="0.35"
        )
    fig.savefig(path, dpi=dpi, format=format, facecolor="white")
    return fig
