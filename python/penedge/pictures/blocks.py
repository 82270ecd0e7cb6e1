"""Block systems in an exploded perspective view, like the paper's Figures 9-12.

Each block is moved outward from the system's centroid by ``explode`` times its own
centroid's distance from it, so that inner blocks show; faces are filled with one colour
per block, shaded by their orientation, and edges are drawn. Given contacts, the blocks
are drawn faintly and the contacts over them (:mod:`penedge.pictures.contacts`).
"""

from __future__ import annotations

import colorsys
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from penedge._core import Block, BlockSystem, SystemContacts

__all__ = ["block_colors", "exploded_faces", "plot_system", "save_picture", "write_html"]

_GHOST_ALPHA = 0.1  # face opacity of the blocks under the contacts

# Light from the viewer's upper left (matplotlib's default view: elev 22, azim -58).
_LIGHT = np.array([-0.35, -0.75, 0.85]) / np.linalg.norm([-0.35, -0.75, 0.85])
_GOLDEN_ANGLE = 0.381966  # fraction of a turn between successive block hues


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
    rows = []
    for i in range(n):
        hue = (0.58 + i * _GOLDEN_ANGLE) % 1.0
        saturation = 0.50 if i % 2 else 0.62
        rows.append(colorsys.hsv_to_rgb(hue, saturation, 0.95))
    return np.array(rows, dtype=float).reshape(n, 3)


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


def _shaded(color: np.ndarray, normals: np.ndarray, alpha: float) -> np.ndarray:
    light = np.clip(normals @ _LIGHT, 0.0, 1.0)
    rgb = np.clip(color[None, :] * (0.55 + 0.45 * light[:, None]), 0.0, 1.0)
    return np.column_stack([rgb, np.full(len(normals), alpha)])


def _view_direction(elev: float, azim: float) -> np.ndarray:
    """Unit vector from the scene towards the viewer (matplotlib's elev / azim)."""
    e, a = np.radians(elev), np.radians(azim)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def _set_equal_limits(ax: Any, points: np.ndarray) -> None:
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2 * 1.02
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def plot_system(
    system: BlockSystem | Iterable[Block],
    *,
    ax: Axes | None = None,
    explode: float = 0.5,
    alpha: float = 0.92,
    title: str | None = None,
    labels: bool = False,
    colors: Sequence[Any] | None = None,
    contacts: SystemContacts | None = None,
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
        Outward displacement factor (see :func:`exploded_faces`).
    alpha : float, default 0.92
        Face opacity (faces turned away from the viewer are not drawn).
    title : str, optional
        Axes title.
    labels : bool, default False
        Write each block's id at its (moved) centroid.
    colors : sequence of colours, optional
        One matplotlib colour per block; default :func:`block_colors`.
    contacts : SystemContacts, optional
        Contacts of `system` found with ``detect(geometry=True)``: drawn coloured by type
        (:func:`penedge.pictures.plot_contacts`) over faint blocks, with a legend.
    elev, azim : float
        View angles in degrees.

    Returns
    -------
    Axes3D
        The axes drawn into (``ax.figure`` is the figure).

    Examples
    --------
    >>> import penedge
    >>> from penedge.pictures import plot_system
    >>> ax = plot_system(penedge.paper_example(1), title="Example 1")
    >>> len(ax.collections)  # one per block
    8
    """
    from matplotlib.colors import to_rgb
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(7.0, 7.0), layout="constrained").add_subplot(projection="3d")
    parts = exploded_faces(system, explode)
    palette = block_colors(len(parts)) if colors is None else [to_rgb(c) for c in colors]
    view = _view_direction(elev, azim)
    ghost = contacts is not None
    for (faces, normals, _), color in zip(parts, palette, strict=True):
        front = [k for k in range(len(faces)) if ghost or normals[k] @ view > -0.1]
        shaded = _shaded(np.asarray(color, dtype=float), normals[front], alpha)
        if ghost:
            shaded[:, 3] = _GHOST_ALPHA
        ax.add_collection3d(
            Poly3DCollection(
                [faces[k] for k in front],
                facecolors=shaded,
                edgecolors=(0.35, 0.35, 0.35, 0.35) if ghost else (0.1, 0.1, 0.1, 0.95),
                linewidths=0.5 if ghost else 0.8,
                zorder=1,
            )
        )
    if parts:
        _set_equal_limits(ax, np.vstack([np.vstack(faces) for faces, _, _ in parts]))
    if labels:
        _label_blocks(ax, system, parts)
    if ghost:
        from penedge.pictures.contacts import plot_contacts

        offsets = np.array([offset for _, _, offset in parts]).reshape(-1, 3)
        plot_contacts(contacts, ax=ax, block_offsets=offsets)
    ax.set_proj_type("persp", focal_length=2.0)
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=13, pad=0)
    return ax


def _label_blocks(ax: Any, system: Any, parts: list) -> None:
    for i, (block, (_, _, offset)) in enumerate(zip(_blocks(system), parts, strict=True)):
        x, y, z = block.centroid + offset
        ax.text(x, y, z, str(i), fontsize=7, ha="center", va="center", color="0.1", zorder=10)


def save_picture(
    system: BlockSystem | Iterable[Block],
    path: str,
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
        Passed to :func:`plot_system`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    panels = 1 if contacts is None else 2
    fig = Figure(figsize=(7.0 * panels, 7.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, panels, 1, projection="3d")
    plot_system(system, ax=ax, explode=explode, **kwargs)
    if contacts is not None:
        ax.set_title("blocks", fontsize=11, pad=0)
        right = fig.add_subplot(1, panels, 2, projection="3d")
        plot_system(system, ax=right, explode=explode, contacts=contacts, **kwargs)
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


def write_html(
    system: BlockSystem | Iterable[Block],
    path: str,
    *,
    title: str | None = None,
    explode: float = 0.5,
    include_plotlyjs: bool | str = True,
) -> None:
    """Write an interactive exploded view (plotly) to an HTML file.

    Parameters
    ----------
    system : BlockSystem or iterable of Block
    path : str or path-like
    title : str, optional
    explode : float, default 0.5
    include_plotlyjs : bool or str, default True
        True embeds plotly.js (a self-contained file of a few MB); ``"cdn"`` links it.
    """
    import plotly.graph_objects as go

    parts = exploded_faces(system, explode)
    traces = []
    for i, ((faces, _, _), color) in enumerate(zip(parts, block_colors(len(parts)), strict=True)):
        traces.append(_mesh_trace(faces, color, f"block {i}"))
        traces.append(_edge_trace(faces))
    fig = go.Figure(traces)
    fig.update_layout(
        title=title,
        showlegend=False,
        scene={"aspectmode": "data"},
        margin={"l": 0, "r": 0, "t": 40 if title else 0, "b": 0},
    )
    fig.write_html(path, include_plotlyjs=include_plotlyjs)


def _mesh_trace(faces: list[np.ndarray], color: np.ndarray, name: str) -> Any:
    import plotly.graph_objects as go

    points, triangles = [], []
    for face in faces:
        start = sum(len(f) for f in points)
        points.append(face)
        triangles.extend((start, start + k, start + k + 1) for k in range(1, len(face) - 1))
    xyz = np.vstack(points)
    i, j, k = np.array(triangles).T
    rgb = "rgb({:.0f},{:.0f},{:.0f})".format(*(255 * np.asarray(color)))
    return go.Mesh3d(
        x=xyz[:, 0],
        y=xyz[:, 1],
        z=xyz[:, 2],
        i=i,
        j=j,
        k=k,
        color=rgb,
        opacity=0.9,
        flatshading=True,
        name=name,
        hoverinfo="name",
    )


def _edge_trace(faces: list[np.ndarray]) -> Any:
    import plotly.graph_objects as go

    xs, ys, zs = [], [], []
    for face in faces:
        loop = np.vstack([face, face[:1]])
        xs.extend([*loop[:, 0], None])
        ys.extend([*loop[:, 1], None])
        zs.extend([*loop[:, 2], None])
    return go.Scatter3d(
        x=xs,
        y=ys,
        z=zs,
        mode="lines",
        hoverinfo="skip",
        line={"color": "rgb(30,30,30)", "width": 2},
    )
