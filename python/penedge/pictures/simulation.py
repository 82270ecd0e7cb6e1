"""Pictures of a simulation: the history (unbalanced-force ratio, kinetic energy, monitored
displacements against the step), the final state coloured by displacement, and the blocks
that fail in a factor-of-safety search; with axes in metres and a north arrow.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from penedge.pictures.scene import plain_text

DISPLACEMENT_COLORMAP = "plasma"


def save_history(history: Any, path: Any, *, title: str | None = None, dpi: int = 120) -> Any:
    """The history of a run (:class:`penedge.model.run.History`) as a picture: the
    unbalanced-force ratio and the kinetic energy (log scales), and the displacement of each
    monitored block, against the step.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    monitors = history.monitors
    rows = 3 if monitors else 2
    fig = Figure(figsize=(8.0, 2.6 * rows + 0.6), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(rows, 1, sharex=True)
    step = np.asarray(history.step, dtype=float)
    ratio = np.asarray(history.ratio, dtype=float)
    kinetic = np.asarray(history.kinetic, dtype=float)
    positive = ratio > 0
    axes[0].semilogy(step[positive], ratio[positive], color="tab:blue")
    axes[0].set_ylabel("unbalanced-force ratio")
    positive = kinetic > 0
    axes[1].semilogy(step[positive], kinetic[positive], color="tab:red")
    axes[1].set_ylabel("kinetic energy (J)")
    if monitors:
        for name, values in monitors.items():
            v = np.asarray(values, dtype=float).reshape(-1, 6)
            size = np.linalg.norm(v[:, :3], axis=1) * 1e3
            axes[2].plot(step[: len(v)], size, label=plain_text(str(name)))
        axes[2].set_ylabel("displacement (mm)")
        axes[2].legend(fontsize=8, loc="best")
    _stage_marks(axes, history)
    axes[-1].set_xlabel("step")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    if title:
        fig.suptitle(plain_text(title), fontsize=12)  # a model's title: no mathtext
    fig.savefig(path, dpi=dpi, format="png", facecolor="white")
    return fig


def _stage_marks(axes: Any, history: Any) -> None:
    """A faint vertical line where each stage ends."""
    stages = history.stage
    for k in range(1, len(stages)):
        if stages[k] != stages[k - 1] and stages[k - 1] != "start":
            for ax in axes:
                ax.axvline(history.step[k - 1], color="0.6", lw=0.7, ls=":")


def save_displacement(
    system: Any,
    displacement: np.ndarray,
    path: Any,
    *,
    title: str | None = None,
    threshold: float | None = None,
    dpi: int = 120,
) -> Any:
    """The blocks (at their final positions) coloured by the size of their displacement,
    with axes in metres (x East, y North, z up), a colour bar in mm and a north arrow.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    from penedge.pictures.blocks import plot_system

    size = np.linalg.norm(np.asarray(displacement, dtype=float), axis=1) * 1e3
    top = float(size.max(initial=0.0)) or 1.0
    norm = Normalize(0.0, top)
    cmap = matplotlib.colormaps[DISPLACEMENT_COLORMAP]
    colors = cmap(norm(size))[:, :3]
    fig = Figure(figsize=(8.5, 7.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    plot_system(system, ax=ax, explode=0.0, colors=list(colors), max_blocks=None)
    _axes(ax)
    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.6, pad=0.08)
    label = "displacement (mm)"
    if threshold is not None:
        moved = int((size > threshold * 1e3).sum())
        label += f"\n{moved} of {len(size)} blocks moved more than {threshold * 1e3:g} mm"
    bar.set_label(label)
    if title:
        ax.set_title(plain_text(title), fontsize=12)
    fig.savefig(path, dpi=dpi, format="png", facecolor="white")
    return fig


def save_failing(
    system: Any, failing: Any, path: Any, *, title: str | None = None, dpi: int = 120
) -> Any:
    """The blocks that fail at the smallest failing strength reduction factor (red), over
    the others (grey), with axes in metres and a north arrow.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from penedge.pictures.blocks import plot_system

    n = len(system)
    colors = np.tile([0.78, 0.78, 0.78], (n, 1))
    colors[np.asarray(failing, dtype=np.int64)] = [0.85, 0.1, 0.1]
    fig = Figure(figsize=(8.0, 7.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    plot_system(system, ax=ax, explode=0.0, colors=list(colors), max_blocks=None)
    _axes(ax)
    if title:
        ax.set_title(plain_text(title), fontsize=12)
    fig.savefig(path, dpi=dpi, format="png", facecolor="white")
    return fig


def _axes(ax: Any) -> None:
    """Axes in metres, named by direction, and a north arrow."""
    ax.set_axis_on()
    ax.set_xlabel("x, East (m)")
    ax.set_ylabel("y, North (m)")
    ax.set_zlabel("z, up (m)")
    _north_arrow(ax)


def _north_arrow(ax: Any) -> None:
    """An arrow pointing North (+y) at the top corner of the axes, marked N."""
    (x0, x1), (y0, y1), (_, z1) = ax.get_xlim(), ax.get_ylim(), ax.get_zlim()
    length = 0.2 * max(x1 - x0, y1 - y0)
    ax.quiver(x0, y0, z1, 0, length, 0, color="k", linewidth=2, arrow_length_ratio=0.3)
    ax.text(x0, y0 + 1.15 * length, z1, "N", color="k", fontsize=12, fontweight="bold")


#: The interactive view of a run keeps at most this many frames (evenly spread).
MAX_HTML_FRAMES = 200


def steps_figure(frames: list[tuple[float, Any, np.ndarray]], *, title: str | None = None) -> Any:
    """A plotly figure of a run whose steps can be played: one frame per ``(time, system,
    displacement)`` (the blocks at that time, coloured by their displacement in mm), a play
    button and a time slider.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    if len(frames) > MAX_HTML_FRAMES:
        keep = np.unique(np.linspace(0, len(frames) - 1, MAX_HTML_FRAMES).round().astype(int))
        frames = [frames[k] for k in keep]
    top = max(float(np.linalg.norm(d, axis=1).max(initial=0.0)) for _, _, d in frames) * 1e3
    top = top or 1.0
    first = frames[0][1].arrays()
    loops = np.asarray(first.loop_offsets)
    corners = np.asarray(first.face_vertices)
    face_block = np.asarray(first.face_block)
    # a fan of triangles per face: (first, k, k + 1)
    sizes = np.diff(loops)
    tri_face = np.repeat(np.arange(len(sizes)), np.maximum(sizes - 2, 0))
    offset = np.arange(len(tri_face)) - np.repeat(np.cumsum(sizes - 2) - (sizes - 2), sizes - 2)
    i = corners[loops[:-1][tri_face]]
    j = corners[loops[:-1][tri_face] + 1 + offset]
    k = corners[loops[:-1][tri_face] + 2 + offset]
    tri_block = face_block[tri_face]

    def mesh(system: Any, displacement: np.ndarray) -> Any:
        v = np.asarray(system.arrays().vertices)
        size = np.linalg.norm(displacement, axis=1) * 1e3
        return go.Mesh3d(
            x=v[:, 0],
            y=v[:, 1],
            z=v[:, 2],
            i=i,
            j=j,
            k=k,
            intensity=size[tri_block],
            intensitymode="cell",
            cmin=0.0,
            cmax=top,
            colorscale="Plasma",
            colorbar={"title": {"text": "displacement (mm)"}},
            flatshading=True,
            hovertemplate="displacement %{intensity:.3g} mm<extra></extra>",
        )

    labels = [f"t = {t:.4g} s" for t, _, _ in frames]
    fig = go.Figure(
        data=[mesh(frames[0][1], frames[0][2])],
        frames=[
            go.Frame(data=[mesh(s, d)], name=label)
            for label, (_, s, d) in zip(labels, frames, strict=True)
        ],
    )
    step = {"frame": {"duration": 300, "redraw": True}, "mode": "immediate"}
    fig.update_layout(
        title=title,
        scene={
            "aspectmode": "data",
            "xaxis_title": "x, East (m)",
            "yaxis_title": "y, North (m)",
            "zaxis_title": "z, up (m)",
        },
        updatemenus=[
            {
                "type": "buttons",
                "buttons": [
                    {"label": "play", "method": "animate", "args": [None, step]},
                    {
                        "label": "pause",
                        "method": "animate",
                        "args": [[None], {"frame": {"duration": 0}, "mode": "immediate"}],
                    },
                ],
            }
        ],
        sliders=[
            {
                "steps": [
                    {"label": label, "method": "animate", "args": [[label], step]}
                    for label in labels
                ]
            }
        ],
    )
    return fig


def write_steps_html(
    frames: list[tuple[float, Any, np.ndarray]], path: Any, *, title: str | None = None
) -> None:
    """The interactive view of a run (:func:`steps_figure`) as one HTML file (plotly.js
    inline, works offline)."""
    steps_figure(frames, title=title).write_html(
        path, include_plotlyjs=True, full_html=True, config={"displaylogo": False}
    )
