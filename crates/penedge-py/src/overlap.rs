//! `overlap`: normal, depth and region of two penetrating blocks (core [`penedge::overlap`]).

use crate::arrays::{self, Real};
use crate::block::Block;
use crate::tolerance::tolerance;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The overlap of two penetrating blocks, for soft-contact mechanics.
///
/// The normal is the overlap's area vector (minus the gradient of the overlap volume with
/// respect to a translation of `b`): it turns continuously as the blocks move and never
/// switches between the faces of `a` and of `b`. See ``docs/contact-geometry.md``
/// ("Overlapping blocks").
///
/// Parameters
/// ----------
/// a, b : Block
///     The two blocks.
/// gap : float, default 1e-12
///     Relative gap (only the length threshold derived from it is used, to merge the
///     region's points).
/// length : float, optional
///     Relative length threshold (default: ``max(1e-9, 10 * gap)``).
/// absolute_gap : float, optional
///     The gap as a length instead of the relative `gap`, as in :func:`detect_pair`.
///
/// Returns
/// -------
/// dict or None
///     None when the blocks do not overlap (apart or touching); else ``normal`` (unit, from
///     `a` to `b`), ``depth`` (moving `b` by ``depth * normal`` leaves them touching),
///     ``min_translation`` (the shortest translation of `b` that separates them),
///     ``volume`` and ``centroid`` of the intersection, ``points`` (the intersection
///     projected on the plane through its centroid normal to the normal: a convex polygon
///     counter-clockwise about the normal, shape (k, 3)) and its ``area``.
///
/// Examples
/// --------
/// >>> import numpy as np, penedge
/// >>> a = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
/// >>> b = penedge.Block.cuboid([0.25, 0.25, 0.99], [0.75, 0.75, 1.99])
/// >>> o = penedge.overlap(a, b)
/// >>> bool(np.allclose(o["normal"], [0, 0, 1])), round(o["depth"], 12), round(o["area"], 12)
/// (True, 0.01, 0.25)
/// >>> penedge.overlap(a, penedge.Block.cuboid([1, 0, 0], [2, 1, 1])) is None
/// True
#[pyfunction]
#[pyo3(signature = (a, b, gap = Real::Value(1e-12), length = None, absolute_gap = None),
    text_signature = "(a, b, gap=1e-12, length=None, absolute_gap=None)")]
pub fn overlap<'py>(
    py: Python<'py>,
    a: &Bound<'py, Block>,
    b: &Bound<'py, Block>,
    gap: Real,
    length: Option<Real>,
    absolute_gap: Option<Real>,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let tol = tolerance(gap, length, absolute_gap)?;
    let Some(o) = penedge::overlap::overlap(&a.get().inner, &b.get().inner, &tol) else {
        return Ok(None);
    };
    let out = PyDict::new(py);
    out.set_item("normal", arrays::vector(py, o.normal.to_array().to_vec()))?;
    out.set_item("depth", o.depth)?;
    let shift = o.min_translation.to_array().to_vec();
    out.set_item("min_translation", arrays::vector(py, shift))?;
    out.set_item("volume", o.volume)?;
    out.set_item(
        "centroid",
        arrays::vector(py, o.centroid.to_array().to_vec()),
    )?;
    let rows: Vec<[f64; 3]> = o.points().iter().map(|p| p.to_array()).collect();
    out.set_item("points", arrays::rows3(py, &rows))?;
    out.set_item("area", o.area)?;
    Ok(Some(out))
}
