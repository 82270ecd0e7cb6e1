"""Pictures: block systems in an exploded view, their contacts by type, and the
block volume distribution.

* :func:`plot_system`, :func:`save_picture` (:mod:`penedge.pictures.blocks`): an exploded
  perspective view like the paper's Figures 9-12 (with a scale bar and a north arrow; as
  they lie, ``explode=0``, on axes of real coordinates), blocks coloured by joint set
  (with a legend), each its own colour, or by volume (``color_by="volume"``, with a colour
  bar); with ``contacts=`` the contacts are drawn too, coloured by type or joint set, one
  small panel per type (:func:`plot_contacts`, :mod:`penedge.pictures.contacts`);
* :func:`write_html` (:mod:`penedge.pictures.html`): the same view, interactive, as one
  self-contained HTML file (plotly): rotate, zoom, hide or show groups of blocks and
  contact types, hover for block ids and contact types;
* :func:`plot_volume_distribution`, :func:`save_volume_distribution`
  (:mod:`penedge.pictures.volumes`): the cumulative volume curve with V10, V50, V90.

matplotlib (``pip install 'penedge[plot]'``) is needed for the pictures, plotly
(``pip install 'penedge[html]'``) for :func:`write_html`; both are imported inside the
functions, so ``import penedge.pictures`` is cheap.
"""

from penedge.pictures.blocks import exploded_faces, plot_system, save_picture
from penedge.pictures.contacts import CONTACT_COLORS, contact_shapes, plot_contacts
from penedge.pictures.html import HTML_DIV_ID, html_figure, write_html
from penedge.pictures.scene import (
    COLOR_BY,
    DEFAULT_MAX_BLOCKS,
    SET_COLORS,
    block_colors,
    dominant_sets,
)
from penedge.pictures.volumes import (
    passing_volume,
    plot_volume_distribution,
    save_volume_distribution,
)

__all__ = [
    "COLOR_BY",
    "CONTACT_COLORS",
    "DEFAULT_MAX_BLOCKS",
    "HTML_DIV_ID",
    "SET_COLORS",
    "block_colors",
    "contact_shapes",
    "dominant_sets",
    "exploded_faces",
    "html_figure",
    "passing_volume",
    "plot_contacts",
    "plot_system",
    "plot_volume_distribution",
    "save_picture",
    "save_volume_distribution",
    "write_html",
]
