//! The `gap`, `length` and `absolute_gap` arguments as a core [`Tolerance`].

use crate::arrays::Real;
use crate::errors::to_py_err;
use penedge::tolerance::ToleranceError;
use penedge::Tolerance;
use pyo3::PyResult;

/// `length` `None`: `Tolerance::with_gap(gap)` (length = max(1e-9, 10 gap)); else both given.
/// With `absolute_gap`, the gap is that length instead (`Tolerance::and_absolute_gap`), and the
/// relative `gap` must be left at its default. A bool for any of them is an `InputError`
/// naming it ([`Real`]).
pub fn tolerance(
    gap: Real,
    length: Option<Real>,
    absolute_gap: Option<Real>,
) -> PyResult<Tolerance> {
    let gap = gap.get("gap")?;
    let length = Real::optional(length, "length")?;
    let absolute_gap = Real::optional(absolute_gap, "absolute_gap")?;
    let relative = match length {
        None => Tolerance::with_gap(gap),
        Some(length) => Tolerance::new(gap, length),
    };
    let tol = match absolute_gap {
        None => relative,
        Some(_) if gap != Tolerance::default().gap() => Err(ToleranceError::BothGaps),
        Some(absolute) => relative.and_then(|t| t.and_absolute_gap(absolute)),
    };
    tol.map_err(to_py_err)
}
