"""Pictures for the subcommands: the exploded view (PNG, SVG or PDF), the interactive view
(HTML) and the volume distribution, each written through a temporary file."""

from __future__ import annotations

import io
from pathlib import Path
from typing import IO, Any

from penedge.cli.common import PICTURE_FORMATS, CommandError, Target


def explode_caption(explode: float) -> str:
    """What the exploded view shows, under the picture."""
    if explode == 0:
        return "blocks as they lie (no exploded view)"
    return f"exploded view: each block moved out by {explode:g} × its distance from the centre"


def _missing(e: ImportError, extra: str) -> CommandError:
    return CommandError(
        f"the picture needs {e.name or 'an optional package'}: pip install 'penedge[{extra}]'"
    )


def write_picture(
    system: Any,
    target: Target,
    *,
    title: str,
    explode: float,
    colour_by: str | None,
    unit: str | None,
    max_blocks: int | None,
    contacts: Any = None,
) -> Path:
    """The exploded view (a second panel with the contacts when given); returns the path
    written."""
    fmt = PICTURE_FORMATS[target.path.suffix.lower()]

    def write(handle: IO[bytes]) -> None:
        try:
            from penedge import pictures
            from penedge.pictures.scene import plain_text

            pictures.save_picture(
                system,
                handle,
                title=plain_text(title),  # a file name with $ is no mathtext
                subtitle=explode_caption(explode),
                format=fmt,
                explode=explode,
                contacts=contacts,
                color_by=colour_by,
                unit=unit,
                max_blocks=max_blocks,
            )
        except ImportError as e:
            raise _missing(e, "plot") from None

    return target.write(write)


def write_html(
    system: Any,
    target: Target,
    *,
    title: str,
    explode: float,
    colour_by: str | None,
    unit: str | None,
    max_blocks: int | None,
    contacts: Any = None,
) -> Path:
    """The interactive view, one self-contained HTML file; returns the path written."""

    def write(handle: IO[bytes]) -> None:
        try:
            from penedge import pictures

            text = io.StringIO()
            pictures.write_html(
                system,
                text,
                title=title,
                explode=explode,
                contacts=contacts,
                color_by=colour_by,
                unit=unit,
                max_blocks=max_blocks,
            )
        except ImportError as e:
            raise _missing(e, "html") from None
        handle.write(text.getvalue().encode("utf-8"))

    return target.write(write)


def write_volumes(system: Any, target: Target, title: str | None = None) -> Path:
    """The block volume distribution (cumulative, log volume axis); returns the path."""
    fmt = PICTURE_FORMATS[target.path.suffix.lower()]

    def write(handle: IO[bytes]) -> None:
        try:
            from penedge import pictures

            pictures.save_volume_distribution(system, handle, title=title, format=fmt)
        except ImportError as e:
            raise _missing(e, "plot") from None

    return target.write(write)
