"""The block volume distribution: the cumulative volume curve with V10, V50 and V90."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from penedge.pictures.scene import plain_text

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from penedge._core import BlockSystem

__all__ = ["plot_volume_distribution", "save_volume_distribution"]

_CURVE = "#1f4e79"
_MARKS = {10: "#2ca02c", 50: "#d62728", 90: "#ff7f0e"}
_DECADES_BELOW_V10 = 1e3  # the axis starts at most this factor below V10


def _volumes(system: BlockSystem | Any) -> np.ndarray:
    """The block volumes, ascending: of a system, one per body (a concave block's parts
    summed, as :meth:`penedge.BlockSystem.statistics`); else the numbers given."""
    volumes = np.asarray(getattr(system, "volumes", system), dtype=float).ravel()
    ids = getattr(system, "body_ids", None)
    if ids is not None:
        _, body = np.unique(np.asarray(ids), return_inverse=True)
        if body.max(initial=-1) + 1 < len(volumes):
            volumes = np.bincount(body, weights=volumes)
    return np.sort(volumes)


def passing_volume(volumes: np.ndarray, percent: float) -> float:
    """``VX``: the smallest block volume such that blocks no larger hold `percent` % of the
    total volume (as :meth:`penedge.BlockSystem.statistics`).

    Examples
    --------
    >>> from penedge.pictures import passing_volume
    >>> passing_volume([4, 1, 3, 2], 50)  # cumulative fractions 0.1, 0.3, 0.6, 1.0
    3.0
    """
    v = np.sort(np.asarray(volumes, dtype=float))
    total = np.cumsum(v)
    passing = total / total[-1]  # summed in order, as the core does
    k = np.searchsorted(passing, percent / 100, side="left")
    return float(v[min(k, len(v) - 1)])


def plot_volume_distribution(
    system: BlockSystem | Any, *, ax: Axes | None = None, title: str | None = None
) -> Axes:
    """Draw the cumulative block volume distribution (matplotlib).

    The curve gives, for each block volume ``v`` (log axis), the percentage of the rock
    volume in blocks no larger than ``v`` (a sieve curve); V10, V50 and V90 are marked.
    A fainter curve gives the percentage of blocks by number.

    Parameters
    ----------
    system : BlockSystem or array_like of float
        The blocks (one volume per body: a concave block's parts summed), or their
        volumes.
    ax : matplotlib.axes.Axes, optional
        Default: a new figure (not registered with pyplot).
    title : str, optional
        Default: the number of blocks.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import penedge
    >>> from penedge.pictures import plot_volume_distribution
    >>> ax = plot_volume_distribution(penedge.paper_example(3))
    >>> ax.get_xscale(), ax.get_title()
    ('log', 'Block volume distribution: 26 blocks')
    """
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(8.0, 5.0), layout="constrained").add_subplot()
    v = _volumes(system)
    if len(v) == 0:
        raise ValueError("no blocks: no volume distribution")
    passing = 100 * np.cumsum(v) / v.sum()
    by_count = 100 * np.arange(1, len(v) + 1) / len(v)
    x = np.concatenate([[v[0]], v])
    ax.step(
        x,
        np.concatenate([[0], passing]),
        where="post",
        color=_CURVE,
        lw=2.2,
        label="rock volume in blocks ≤ v",
    )
    ax.step(
        x,
        np.concatenate([[0], by_count]),
        where="post",
        color="0.6",
        lw=1.2,
        ls="--",
        label="number of blocks ≤ v",
    )
    ax.set_xscale("log")
    _set_x_limits(ax, v)
    left = ax.get_xlim()[0]
    _note_hidden(ax, v, left)
    for percent, color in _MARKS.items():
        vx = passing_volume(v, percent)
        ax.plot([left, vx, vx], [percent, percent, 0], color=color, lw=1.2, ls=":")
        ax.plot([vx], [percent], "o", color=color, ms=7, zorder=5, label=f"V{percent} = {vx:.4g}")
    ax.set_ylim(0, 100)
    ax.set_yticks(range(0, 101, 10))
    unit = getattr(system, "unit", None)
    ax.set_xlabel(
        f"block volume v ({plain_text(unit)}³)" if unit else "block volume v (spec unit cubed)"
    )
    ax.set_ylabel("cumulative percentage (%)")
    ax.grid(True, which="major", color="0.88")
    ax.grid(True, which="minor", axis="x", color="0.94")
    ax.legend(loc="upper left", fontsize=9, framealpha=0.95)
    ax.set_title(title or f"Block volume distribution: {len(v)} blocks", fontsize=12)
    return ax


def _set_x_limits(ax: Any, v: np.ndarray) -> None:
    """From the smallest block, or from V10 / 1000 when slivers are much smaller (they hold
    a negligible volume and would squeeze the curve), to the largest block."""
    lo, hi = max(v[0], passing_volume(v, 10) / _DECADES_BELOW_V10), v[-1]
    if hi <= lo * 1.5:  # (nearly) equal volumes: a decade around them
        lo, hi = lo / 3, hi * 3
    ax.set_xlim(lo / 1.25, hi * 1.25)


def _note_hidden(ax: Any, v: np.ndarray, left: float) -> None:
    """Says how many blocks lie left of the axis, and how much volume they hold."""
    hidden = v < left
    if not hidden.any():
        return
    share = 100 * v[hidden].sum() / v.sum()
    text = (
        f"not shown: {hidden.sum()} smaller blocks, down to v = {v[0]:.2g}\n"
        f"({share:.2g} % of the rock volume)"
    )
    ax.text(
        0.015,
        0.70,
        text,
        transform=ax.transAxes,
        ha="left",
        va="top",
        fontsize=8.5,
        color="0.25",
        bbox={"facecolor": "white", "edgecolor": "0.8", "boxstyle": "round,pad=0.4"},
    )


def save_volume_distribution(
    system: BlockSystem | Any,
    path: Any,
    *,
    title: str | None = None,
    dpi: int = 150,
    format: str | None = None,
) -> Figure:
    """Draw the volume distribution (:func:`plot_volume_distribution`) and save it.

    Parameters
    ----------
    system : BlockSystem or array_like of float
    path : str or path-like or binary file object
    title : str, optional
    dpi : int, default 150
    format : str, optional
        ``"png"``, ``"svg"``, ``"pdf"``, ... (needed when `path` has no suffix).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 5.0), layout="constrained")
    FigureCanvasAgg(fig)
    plot_volume_distribution(system, ax=fig.add_subplot(), title=title)
    fig.savefig(path, dpi=dpi, format=format, facecolor="white")
    return fig
