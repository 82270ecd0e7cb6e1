"""Block systems in an exploded perspective view, like the paper's Figures 9-12.

Each block is moved outward from the system's centroid by ``explode`` times its own
centroid's distance from it, so that inner blocks show; faces are filled with one colour
per block (or a colour for the block's volume, with a colour bar), shaded by their
orientation, and edges are drawn. Given contacts, the blocks are drawn faintly and the
contacts over them (:mod:`penedge.pictures.contacts`).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from penedge.pictures.scene import (
    COLOR_BY,
    DEFAULT_MAX_BLOCKS,
    VOLUME_COLORMAP,
    block_colors,
    build_scene,
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
        system as it is.

    Returns
    -------
    list of (faces, normals, offset)
        Per block: the face polygons (each an (k, 3) array, already moved), the outward
        unit normals (f, 3), and the displacement (3,).
    """
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


def _base_colors(
    volumes: np.ndarray, color_by: str, colors: Sequence[Any] | None
) -> tuple[np.ndarray, Any]:
    """RGB per block, and the norm of the volume scale (None unless coloured by volume)."""
    if colors is not None:
        from matplotlib.colors import to_rgb

        rgb = np.array([to_rgb(c) for c in colors], dtype=float).reshape(-1, 3)
        if len(rgb) != len(volumes):
            raise ValueError(f"colors: {len(rgb)} colours for {len(volumes)} blocks")
        return rgb, None
    if color_by == "block":
        return block_colors(len(volumes)), None
    if color_by == "volume":
        import matplotlib

        norm = volume_norm(volumes)
        cmap = matplotlib.colormaps[VOLUME_COLORMAP]
        clipped = np.clip(volumes, norm.vmin, norm.vmax)
        return np.asarray(cmap(norm(clipped)))[:, :3].reshape(-1, 3), norm
    raise ValueError(f"color_by must be one of {', '.join(COLOR_BY)}, got {color_by!r}")


def plot_system(
    system: BlockSystem | Iterable[Block],
    *,
    ax: Axes | None = None,
    explode: float = 0.5,
    alpha: float = 0.92,
    title: str | None = None,
    labels: bool = False,
    colors: Sequence[Any] | None = None,
    color_by: str = "block",
    colorbar: bool = True,
    contacts: SystemContacts | None = None,
    max_blocks: int | None = DEFAULT_MAX_BLOCKS,
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
        Each block moves by ``explode * (its centroid - the system centroid)``.
    alpha : float, default 0.92
        Face opacity (faces turned away from the viewer are not drawn).
    title : str, optional
        Axes title.
    labels : bool, default False
        Write each block's id at its (moved) centroid.
    colors : sequence of colours, optional
        One matplotlib colour per block (overrides `color_by`).
    color_by : {"block", "volume"}, default "block"
        Each block its own colour, or a colour for its volume (viridis, logarithmic when
        the volumes span more than a factor of 10) with a colour bar.
    colorbar : bool, default True
        Draw the colour bar of ``color_by="volume"``.
    contacts : SystemContacts, optional
        Contacts of `system` found with ``detect(geometry=True)``: drawn coloured by type
        (:func:`penedge.pictures.plot_contacts`) over faint blocks, with a legend.
    max_blocks : int or None, default 20000
        Draw at most this many blocks: those on the outside of the rock mass first, then
        the largest (a note under the picture says so). None: every block.
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
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(7.0, 7.0), layout="constrained").add_subplot(projection="3d")
    scene = build_scene(system, explode, max_blocks)
    base, norm = _base_colors(scene.volumes, color_by, colors)
    if colors is None and color_by == "block":
        base = base[scene.body_first]  # the parts of a concave block in one colour
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
        for part, colors in parts:
            ax.add_collection3d(
                Poly3DCollection(
                    scene.polygons(part),
                    facecolors=colors,
                    edgecolors=(0.35, 0.35, 0.35, 0.35) if ghost else (0.1, 0.1, 0.1, 0.95),
                    linewidths=min(width, 0.5) if ghost else width,
                    zorder=1,
                )
            )
    if scene.n_faces:
        _set_equal_limits(ax, *scene.bounds())
    if labels:
        for i in np.flatnonzero(scene.shown):
            x, y, z = scene.centroids[i]
            ax.text(x, y, z, str(i), fontsize=7, ha="center", va="center", color="0.1", zorder=10)
    if ghost:
        from penedge.pictures.contacts import plot_contacts

        plot_contacts(
            contacts,
            ax=ax,
            block_offsets=scene.offsets,
            shown_blocks=scene.shown,
            view=_view_direction(elev, azim),
        )
    if norm is not None and colorbar:
        _volume_colorbar(ax, norm, bool(scene.volumes.min(initial=np.inf) < norm.vmin))
    note = shown_note(scene)
    if note:
        ax.text2D(0.5, 0.0, note, transform=ax.transAxes, ha="center", va="bottom", fontsize=8)
    ax.set_proj_type("persp", focal_length=2.0)
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=13, pad=0)
    return ax


def _edge_width(n_blocks: int) -> float:
    """Thinner edges for many blocks, so that the faces still show."""
    return 0.8 if n_blocks <= 200 else max(0.15, 0.8 * float(np.sqrt(200 / n_blocks)))


def _volume_colorbar(ax: Any, norm: Any, below: bool) -> None:
    """The colour bar of the volumes; a triangle at the bottom when smaller blocks (slivers)
    share its lowest colour."""
    import matplotlib
    from matplotlib.cm import ScalarMappable

    mappable = ScalarMappable(norm=norm, cmap=matplotlib.colormaps[VOLUME_COLORMAP])
    bar = ax.figure.colorbar(
        mappable, ax=ax, shrink=0.55, pad=0.0, aspect=25, extend="min" if below else "neither"
    )
    label = "block volume (length unit cubed)"
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
    dpi : int, default 150
    format : str, optional
        ``"png"``, ``"svg"``, ``"pdf"``, ... (needed when `path` has no suffix).
    contacts : SystemContacts, optional
        Contacts found with ``detect(geometry=True)``: a second panel draws them, coloured
        by type, over faint blocks.
    **kwargs
        Passed to :func:`plot_system` (``color_by="volume"``, ``max_blocks``, ...).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    panels = 1 if contacts is None else 2
    wide = 1.0 if kwargs.get("color_by", "block") == "volume" else 0.0
    fig = Figure(figsize=(7.0 * panels + wide, 7.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, panels, 1, projection="3d")
    plot_system(system, ax=ax, explode=explode, **kwargs)
    if contacts is not None:
        ax.set_title("blocks", fontsize=11, pad=0)
        right = fig.add_subplot(1, panels, 2, projection="3d")
        plot_system(
            system, ax=right, explode=explode, contacts=contacts, **{**kwargs, "colorbar": False}
        )
        right.set_title("contacts, coloured by type", fontsize=11, pad=0)
    if title:
        if contacts is None:
            ax.set_title(title, fontsize=13, pad=0)
        else:
            fig.suptitle(title, fontsize=13)
    if subtitle:
        fig.text(0.5, 0.015, subtitle, ha="center", va="bottom", fontsize=9, color="0.35")
    fig.savefig(path, dpi=dpi, format=format, facecolor="white")
    return fig
