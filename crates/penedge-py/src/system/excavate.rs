//! Excavations (core `BlockSystem::excavate`): tunnels, caverns, shafts, slopes and
//! topographic surfaces removed from a block system, in stages.

use super::BlockSystem;
use crate::arrays::{self, Real};
use crate::errors::{to_py_err, Error};
use crate::generation::{in_dict, toml_text};
use crate::tolerance::tolerance;
use pyo3::prelude::*;

#[pymethods]
impl BlockSystem {
    /// This system with an excavation removed, and what it did.
    ///
    /// The rock inside the excavation is removed; each block its boundary crosses is cut into
    /// convex parts that stay one (concave) block while they are in one piece (see
    /// docs/generation.md, "Excavations"). Excavate again for the next stage.
    ///
    /// Parameters
    /// ----------
    /// excavation : dict
    ///     The fields of a ``[[excavations]]`` entry of a generation spec: ``type``
    ///     (``"tunnel"``, ``"cavern"``, ``"shaft"``, ``"slope"``, ``"topography"``), a
    ///     ``profile`` (``"circle"``, ``"horseshoe"``, ``"polygon"``) with its fields for a
    ///     tunnel or shaft, and the placement (``start``, ``trend``, ``plunge``, ``length``;
    ///     ``center``, ``width``, ``height``; ``top``, ``depth``); for a slope ``origin``,
    ///     ``trend`` (of the strike) and the profile's ``vertices`` ``[[u, v], ...]``; for a
    ///     topographic surface its ``file`` (a grid of elevations ``.xyz``/``.csv``/``.asc``,
    ///     or a ``.obj`` or ``.stl`` mesh; a path relative to the current folder) and an
    ///     optional ``offset`` ``[dx, dy, dz]`` added to its points. The air above a
    ///     slope or a surface is removed, the rock below kept (docs/generation.md, "Slopes
    ///     and topography").
    /// gap, length, absolute_gap : float
    ///     The tolerance of the cuts and of the glue between parts (as in
    ///     :meth:`BlockSystem.detect`).
    ///
    /// Returns
    /// -------
    /// system : BlockSystem
    ///     The blocks left; body ids renumbered from 0.
    /// report : dict
    ///     ``removed_blocks``, ``cut_blocks``, ``parts`` (the cut blocks' convex parts),
    ///     ``volume_removed``.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     `excavation` is not a dict (``kind == "type"``).
    /// SpecError
    ///     A bad field (``field`` names it: ``excavation.radius``), a profile that crosses
    ///     itself, or an excavation that removes no rock (outside the blocks); a surface with
    ///     a hole, a fold or a vertical triangle, a file of the wrong kind, a ground entirely
    ///     above or below the rock, a slope profile that goes back (``excavation.file``,
    ///     ``excavation.vertices``).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> rock = penedge.BlockSystem([penedge.Block.cuboid([0, 0, 0], [10, 10, 10])])
    /// >>> left, report = rock.excavate({"type": "cavern", "center": [5, 5, 5], "trend": 0,
    /// ...                               "length": 20, "width": 2, "height": 3})
    /// >>> round(report["volume_removed"], 9), len(set(left.body_ids.tolist()))
    /// (60.0, 1)
    #[pyo3(signature = (excavation, gap = Real::Value(1e-12), length = None, absolute_gap = None),
        text_signature = "($self, excavation, gap=1e-12, length=None, absolute_gap=None)")]
    fn excavate<'py>(
        &self,
        py: Python<'py>,
        excavation: &Bound<'py, PyAny>,
        gap: Real,
        length: Option<Real>,
        absolute_gap: Option<Real>,
    ) -> PyResult<(BlockSystem, Bound<'py, PyAny>)> {
        let tol = tolerance(gap, length, absolute_gap)?;
        let text = toml_text(excavation, "excavation")?;
        let excavation = penedge::io::spec::parse_excavation_toml(&text)
            .map_err(|e| to_py_err(Error::from(in_dict(&text, e, "excavation"))))?;
        let system = self.inner.clone();
        let (out, report) = py
            .detach(|| system.excavate(&excavation, &tol))
            .map_err(|e| to_py_err(Error::from(e)))?;
        Ok((BlockSystem::wrap(out), arrays::to_python(py, &report)?))
    }
}
