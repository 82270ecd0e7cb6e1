"""Pictures: block systems in an exploded view, their contacts coloured by type, and the
block volume distribution.

* :func:`plot_system`, :func:`save_picture` (:mod:`penedge.pictures.blocks`): an exploded
  perspective view like the paper's Figures 9-12; with ``contacts=`` the contacts are drawn
  too (:func:`plot_contacts`, :mod:`penedge.pictures.contacts`);
* :func:`write_html`: the same view, interactive (plotly);
* :func:`plot_volume_distribution`, :func:`save_volume_distribution`
  (:mod:`penedge.pictures.volumes`): the cumulative volume curve with V10, V50, V90.

matplotlib (``pip install 'penedge[plot]'``) is needed for the pictures, plotly
(``pip install 'penedge[html]'``) for :func:`write_html`; both are imported inside the
functions, so ``import penedge.pictures`` is cheap.
"""

from penedge.pictures.blocks import (
    block_colors,
    exploded_faces,
    plot_system,
    save_picture,
    write_html,
)
from penedge.pictures.contacts import CONTACT_COLORS, contact_shapes, plot_contacts
from penedge.pictures.volumes import (
    passing_volume,
    plot_volume_distribution,
    save_volume_distribution,
)

__all__ = [
    "CONTACT_COLORS",
    "block_colors",
    "contact_shapes",
    "exploded_faces",
    "passing_volume",
    "plot_contacts",
    "plot_system",
    "plot_volume_distribution",
    "save_picture",
    "save_volume_distribution",
    "write_html",
]
