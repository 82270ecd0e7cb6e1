//! The `gap` and `length` arguments as a core [`Tolerance`].

use crate::errors::to_py_err;
use penedge::Tolerance;
use pyo3::PyResult;

/// `length` `None`: `Tolerance::with_gap(gap)` (length = max(1e-9, 10 gap)); else both given.
pub fn tolerance(gap: f64, length: Option<f64>) -> PyResult<Tolerance> {
    match length {
        None => Tolerance::with_gap(gap).map_err(to_py_err),
        Some(length) => Tolerance::new(gap, length).map_err(to_py_err),
    }
}
