"""The interactive view: one self-contained HTML file (plotly, with plotly.js inline).

Drag to rotate, scroll to zoom, click a legend entry to hide or show a group of blocks or
a contact type, hover for the block id and volume or the contact type and its two blocks.
Blocks are merged into a few ``Mesh3d`` traces (one per block for small systems, else one
per group of blocks: by id, or by volume class when coloured by volume), with their
numbers stored as binary arrays, so that thousands of blocks still make a file of a few MB.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from penedge.pictures.contacts import CONTACT_COLORS, contact_shapes
from penedge.pictures.scene import (
    DEFAULT_MAX_BLOCKS,
    NO_SET_COLOR,
    SET_COLORS,
    Scene,
    block_colors,
    build_scene,
    check_contacts,
    shown_note,
    volume_scale,
)

if TYPE_CHECKING:
    from penedge._core import Block, BlockSystem, SystemContacts

__all__ = ["HTML_DIV_ID", "html_figure", "write_html"]

#: The id of the plot's ``<div>`` in the page.
HTML_DIV_ID = "penedge-view"

_ONE_TRACE_PER_BLOCK = 30  # up to this many blocks, one legend entry per block
_GROUPS = 20  # else this many groups of blocks
_EDGES_UP_TO = 5000  # draw block edges up to this many blocks (auto)
_VOLUME_CLASSES = 10  # legend entries of blocks coloured by volume
_PALETTE = 64  # block colours repeat with this period in grouped traces
_EDGE_COLOR = "rgb(25,25,25)"


def _rgb(color: np.ndarray) -> str:
    return "rgb({:.0f},{:.0f},{:.0f})".format(*(255 * np.asarray(color)))


def _palette_scale(n: int) -> list[list[Any]]:
    """A stepped colour scale: value k (0..n-1, range -0.5..n-0.5) gets colour k."""
    colors = [_rgb(c) for c in block_colors(n)]
    scale: list[list[Any]] = []
    for k, c in enumerate(colors):
        scale += [[k / n, c], [(k + 1) / n, c]]
    return scale


def _block_groups(scene: Scene, color_by: str) -> list[tuple[str, np.ndarray]]:
    """(legend name, block ids) of each block trace. A concave block (convex parts sharing
    a body id) is one block: its parts are in one group, named and counted once."""
    ids = np.flatnonzero(scene.shown)
    bodies = np.flatnonzero(scene.shown_bodies)
    if color_by == "set":
        from penedge.pictures.blocks import set_name

        groups = []
        for s in np.unique(scene.block_sets[ids]):
            members = ids[scene.block_sets[ids] == s]
            count = len(np.unique(scene.body_index[members]))
            groups.append((f"{set_name(scene, int(s))} ({count})", members))
        return groups
    if len(bodies) <= _ONE_TRACE_PER_BLOCK:
        return [(f"block {scene.body_ids[b]}", _parts(scene, ids, [b])) for b in bodies]
    if color_by == "volume":
        return _volume_classes(scene, ids, bodies)
    return [
        (f"blocks {scene.body_ids[c[0]]} to {scene.body_ids[c[-1]]}", _parts(scene, ids, c))
        for c in np.array_split(bodies, _GROUPS)
        if len(c)
    ]


def _parts(scene: Scene, ids: np.ndarray, bodies: Any) -> np.ndarray:
    """The blocks among `ids` that are parts of `bodies`."""
    return ids[np.isin(scene.body_index[ids], bodies)]


def _volume_classes(
    scene: Scene, ids: np.ndarray, bodies: np.ndarray
) -> list[tuple[str, np.ndarray]]:
    """Blocks in classes of volume (of their whole body), evenly spaced on the colour scale
    (log or linear); the blocks below the scale (slivers) form a class of their own."""
    lo, hi, log = volume_scale(scene.body_volumes)
    bins = _VOLUME_CLASSES + 1
    edges = np.geomspace(lo, hi, bins) if log else np.linspace(lo, hi, bins)
    v = scene.body_volumes[bodies]
    which = np.clip(np.searchsorted(edges, v, side="right") - 1, 0, len(edges) - 2)
    which[v < lo] = -1
    groups = []
    if (which == -1).any():
        below = bodies[which == -1]
        groups.append((f"volume below {lo:.3g} ({len(below)})", _parts(scene, ids, below)))
    for k in range(len(edges) - 1):
        members = bodies[which == k]
        if len(members):
            name = f"volume {edges[k]:.3g} to {edges[k + 1]:.3g} ({len(members)})"
            groups.append((name, _parts(scene, ids, members)))
    return groups


def html_figure(
    system: BlockSystem | Iterable[Block],
    *,
    title: str | None = None,
    explode: float = 0.5,
    contacts: SystemContacts | None = None,
    color_by: str | None = None,
    max_blocks: int | None = DEFAULT_MAX_BLOCKS,
    edges: bool | None = None,
    unit: str | None = None,
) -> Any:
    """The interactive exploded view as a plotly figure (see :func:`write_html`)."""
    import plotly.graph_objects as go

    from penedge.pictures.blocks import length_unit, resolve_color_by

    scene = build_scene(system, explode, max_blocks)
    if contacts is not None:
        check_contacts(contacts, scene.n_blocks)
    color_by = resolve_color_by(color_by, scene)
    unit = length_unit(system, unit)
    if edges is None:
        edges = scene.n_shown <= _EDGES_UP_TO
    lo, hi, log = volume_scale(scene.body_volumes)
    groups = _block_groups(scene, color_by)
    group_of = np.full(scene.n_blocks, -1)
    for g, (_, ids) in enumerate(groups):
        group_of[ids] = g
    face_group = group_of[scene.face_block]
    order = np.argsort(face_group, kind="stable")
    bounds = np.searchsorted(face_group[order], np.arange(len(groups) + 1))
    traces = []
    opacity = 1.0 if contacts is None else 0.3
    for g, (name, _) in enumerate(groups):
        faces = order[bounds[g] : bounds[g + 1]]
        if len(faces) == 0:
            continue
        mesh = _block_mesh(scene, faces, name, color_by, (lo, hi, log), opacity, unit)
        traces.append(mesh)
        if edges:
            traces.append(_block_edges(scene, faces, name, 1.5 if scene.n_shown > 200 else 2.5))
    if contacts is not None:
        traces += _contact_traces(contacts, scene)
    fig = go.Figure(traces)
    notes = ["drag: rotate; scroll: zoom; hover: block or contact; legend click: hide / show"]
    note = shown_note(scene)
    if note:
        notes.append(note)
    if explode:
        notes.append(
            f"exploded view: each block moved out by {explode:g} × its distance from the "
            "centre; the axes show where the blocks really are only without it (explode 0): "
            "hover for the real coordinates"
        )
    axes = _axes(explode, unit)
    fig.update_layout(
        title={"text": title} if title else None,
        scene={
            "aspectmode": "data",
            **axes,
            "camera": {"eye": {"x": 1.5, "y": -1.6, "z": 1.0}},
        },
        legend={
            "title": {"text": "blocks (click: hide / show)"},
            "groupclick": "togglegroup",
            "itemsizing": "constant",
            "y": 0.95,
        },
        legend2={
            "title": {"text": "contacts by type"},
            "groupclick": "togglegroup",
            "itemsizing": "constant",
            "x": 0.0,
            "xanchor": "left",
            "y": 0.95,
            "bgcolor": "rgba(255,255,255,0.8)",
        },
        margin={"l": 0, "r": 0, "t": 50 if title else 10, "b": 10 + 18 * len(notes)},
        paper_bgcolor="white",
        annotations=[
            {
                "text": "<br>".join(notes),
                "xref": "paper",
                "yref": "paper",
                "x": 0,
                "y": 0,
                "yanchor": "top",
                "xanchor": "left",
                "showarrow": False,
                "align": "left",
                "yshift": -4,
                "font": {"size": 11, "color": "rgb(90,90,90)"},
            }
        ],
    )
    if color_by == "volume":
        fig.update_layout(coloraxis=_volume_axis(lo, hi, log))
    return fig


def _axes(explode: float, unit: str) -> dict[str, Any]:
    """The scene's axes: real coordinates with the unit; for an exploded view (whose
    positions are not real) titled so, without numbers."""
    axis = {"showbackground": False, "showspikes": False, "gridcolor": "rgb(225,225,225)"}
    out = {}
    for name, label in (("x", "x, east"), ("y", "y, north"), ("z", "z, up")):
        if explode:
            out[f"{name}axis"] = {
                **axis,
                "title": {"text": f"{label} (exploded)"},
                "showticklabels": False,
            }
        else:
            out[f"{name}axis"] = {**axis, "title": {"text": f"{label} ({unit})"}}
    return out


def _volume_axis(lo: float, hi: float, log: bool) -> dict[str, Any]:
    bar: dict[str, Any] = {
        "title": {"text": "block volume"},
        "len": 0.5,
        "x": 0.0,
        "xanchor": "left",
        "y": 0.05,
        "yanchor": "bottom",
    }
    if log:
        decades = np.arange(np.floor(np.log10(lo)), np.ceil(np.log10(hi)) + 1)
        bar["tickvals"] = decades.tolist()
        bar["ticktext"] = [f"{10**d:g}" for d in decades]
        lo, hi = float(np.log10(lo)), float(np.log10(hi))
    return {"colorscale": "Viridis", "cmin": lo, "cmax": hi, "colorbar": bar}


def _block_mesh(
    scene: Scene,
    faces: np.ndarray,
    name: str,
    color_by: str,
    scale: tuple[float, float, bool],
    opacity: float,
    unit: str,
) -> Any:
    import plotly.graph_objects as go

    tris, tri_face = scene.triangles(faces)
    used, local = np.unique(tris, return_inverse=True)
    local = local.reshape(-1, 3).astype(np.int32)
    xyz = scene.vertices[used].astype(np.float32)
    tri_block = scene.face_block[tri_face]
    vertex_block = np.empty(len(used), dtype=np.int64)
    vertex_block[local.ravel()] = np.repeat(tri_block, 3)
    real = scene.real(scene.vertices[used], vertex_block)
    # A block is named by its body id, with its body's volume (a concave block's parts).
    body = scene.body_index[vertex_block]
    custom = np.column_stack([scene.body_ids[body], scene.body_volumes[body], real])
    custom = custom.astype(np.float32)  # 7 digits: enough to read, half the file
    first = scene.body_first[tri_block]  # a concave block's parts: one colour
    colors: dict[str, Any]
    if color_by == "set":
        s = scene.block_sets[tri_block[0]]
        colors = {"color": NO_SET_COLOR if s < 0 else SET_COLORS[s % len(SET_COLORS)]}
    elif color_by == "volume":
        lo, hi, log = scale
        v = np.clip(scene.block_volumes[tri_block], lo, hi)
        value = np.log10(v) if log else v
        colors = {"intensity": value.astype(np.float32), "coloraxis": "coloraxis"}
    elif len(np.unique(first)) == 1:
        colors = {"color": _rgb(block_colors(first[0] + 1)[-1])}
    else:
        colors = {
            "intensity": (first % _PALETTE).astype(np.float32),
            "colorscale": _palette_scale(_PALETTE),
            "cmin": -0.5,
            "cmax": _PALETTE - 0.5,
            "showscale": False,
        }
    return go.Mesh3d(
        x=xyz[:, 0],
        y=xyz[:, 1],
        z=xyz[:, 2],
        i=local[:, 0],
        j=local[:, 1],
        k=local[:, 2],
        intensitymode="cell",
        flatshading=True,
        opacity=opacity,
        lighting={"ambient": 0.55, "diffuse": 0.6, "specular": 0.05, "roughness": 0.9},
        lightposition={"x": -1000, "y": -2000, "z": 3000},
        name=name,
        legendgroup=name,
        showlegend=True,
        customdata=custom,
        hovertemplate=(
            "block %{customdata[0]}<br>volume %{customdata[1]:.4g} "
            f"{unit}³<br>vertex at x %{{customdata[2]:.6g}}, y %{{customdata[3]:.6g}}, "
            f"z %{{customdata[4]:.6g}} {unit}<extra></extra>"
        ),
        **colors,
    )


def _block_edges(scene: Scene, faces: np.ndarray, name: str, width: float) -> Any:
    import plotly.graph_objects as go

    pairs = scene.edges(faces)
    xyz = _segments(scene.vertices[pairs[:, 0]], scene.vertices[pairs[:, 1]])
    return go.Scatter3d(
        x=xyz[:, 0],
        y=xyz[:, 1],
        z=xyz[:, 2],
        mode="lines",
        line={"color": _EDGE_COLOR, "width": width},
        hoverinfo="skip",
        name=name,
        legendgroup=name,
        showlegend=False,
    )


def _segments(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Points a0, b0, NaN, a1, b1, NaN, ... (NaN breaks the line)."""
    out = np.full((len(a), 3, 3), np.nan, dtype=np.float32)
    out[:, 0], out[:, 1] = a, b
    return out.reshape(-1, 3)


def _contact_traces(contacts: SystemContacts, scene: Scene) -> list[Any]:
    import plotly.graph_objects as go

    from penedge import CONTACT_TYPES

    points, segments, polygons, kinds = contact_shapes(contacts, scene.offsets)
    types = np.asarray(contacts.types)
    pairs = np.asarray(contacts.pairs).reshape(-1, 2)
    drawn = scene.shown[pairs].all(axis=1) if len(pairs) else np.zeros(0, dtype=bool)
    traces = []
    many = drawn.sum() > 2000
    for code, color in CONTACT_COLORS.items():
        name = CONTACT_TYPES[code - 1]
        of_type = (types == code) & drawn
        count = int(of_type.sum())
        if count == 0:
            continue
        group = f"{name} ({count})"
        hover = f"{name}<br>blocks %{{customdata[0]}} and %{{customdata[1]}}<extra></extra>"
        common = {
            "name": group,
            "legendgroup": group,
            "legend": "legend2",
            "hovertemplate": hover,
        }
        shapes = []
        select = of_type[kinds == 3]
        if select.any():
            polys = [p for p, keep in zip(polygons, select, strict=True) if keep]
            shapes.append(_polygon_mesh(polys, pairs[kinds == 3][select], color, common))
        select = of_type[kinds == 2]
        if select.any():
            segs = segments[select]
            xyz = _segments(segs[:, 0], segs[:, 1])
            custom = np.repeat(pairs[kinds == 2][select], 3, axis=0).astype(np.float32)
            shapes.append(
                go.Scatter3d(
                    x=xyz[:, 0],
                    y=xyz[:, 1],
                    z=xyz[:, 2],
                    mode="lines",
                    line={"color": color, "width": 4 if many else 7},
                    customdata=custom,
                    **common,
                )
            )
        select = of_type[kinds == 1]
        if select.any():
            dots = points[select].astype(np.float32)
            shapes.append(
                go.Scatter3d(
                    x=dots[:, 0],
                    y=dots[:, 1],
                    z=dots[:, 2],
                    mode="markers",
                    marker={"color": color, "size": 3 if many else 5, "line": {"width": 0}},
                    customdata=pairs[kinds == 1][select].astype(np.float32),
                    **common,
                )
            )
        for k, trace in enumerate(shapes):
            trace.showlegend = k == 0
        traces += shapes
    return traces


def _polygon_mesh(
    polygons: list[np.ndarray], pairs: np.ndarray, color: str, common: dict[str, Any]
) -> Any:
    import plotly.graph_objects as go

    sizes = np.array([len(p) for p in polygons])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    xyz = np.vstack(polygons).astype(np.float32)
    count = sizes - 2
    first = np.repeat(starts, count)
    step = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    tris = np.column_stack([first, first + 1 + step, first + 2 + step]).astype(np.int32)
    custom = np.repeat(pairs, sizes, axis=0).astype(np.float32)
    return go.Mesh3d(
        x=xyz[:, 0],
        y=xyz[:, 1],
        z=xyz[:, 2],
        i=tris[:, 0],
        j=tris[:, 1],
        k=tris[:, 2],
        color=color,
        opacity=0.85,
        flatshading=True,
        customdata=custom,
        **common,
    )


def write_html(
    system: BlockSystem | Iterable[Block],
    path: Any,
    *,
    title: str | None = None,
    explode: float = 0.5,
    contacts: SystemContacts | None = None,
    color_by: str | None = None,
    max_blocks: int | None = DEFAULT_MAX_BLOCKS,
    edges: bool | None = None,
    include_plotlyjs: bool | str = True,
    unit: str | None = None,
) -> None:
    """Write the interactive exploded view (plotly) to one HTML file.

    Parameters
    ----------
    system : BlockSystem or iterable of Block
    path : str or path-like or text file object
    title : str, optional
    explode : float, default 0.5
        Each block moves by ``explode * (its centroid - the system centroid)``. With 0 the
        axes show the real coordinates; an exploded view hides their numbers (they would
        be the moved positions), and hovering a block gives the real position of the
        vertex nearest the pointer. From 0 to 100: anything else is a ValueError.
    contacts : SystemContacts, optional
        Contacts found with ``detect(geometry=True)``: drawn by type (points, segments,
        polygons), one legend entry per type; the blocks are then drawn translucent.
    color_by : {"set", "block", "volume"}, optional
        The colour of each block's joint set (one legend entry per set), each block its
        own colour, or its volume on a colour scale (with a colour bar); default ``"set"``
        for a system generated with joint sets, else ``"block"``. A concave block (convex
        parts sharing a body id) is one block in each: one colour (its whole body's set,
        colour or volume), one legend entry, named by its body id on hover.
    max_blocks : int or None, default 20000
        Draw at most this many blocks: those on the outside of the rock mass first, then
        the largest (the page says so). A concave block counts once and is drawn whole or
        not at all. None: every block.
    edges : bool, optional
        Draw the block edges; default: up to 5000 blocks.
    include_plotlyjs : bool or str, default True
        True embeds plotly.js, so that the file needs nothing else (works offline, a few
        MB); ``"cdn"`` links it instead.
    unit : str, optional
        The model's length unit, for the axes and the hover text; default the system's
        (``BlockSystem.unit``, from the spec), else ``"m"``.
    """
    fig = html_figure(
        system,
        title=title,
        explode=explode,
        contacts=contacts,
        color_by=color_by,
        max_blocks=max_blocks,
        edges=edges,
        unit=unit,
    )
    fig.write_html(
        path,
        include_plotlyjs=include_plotlyjs,
        full_html=True,
        div_id=HTML_DIV_ID,
        config={"displaylogo": False, "responsive": True},
    )
