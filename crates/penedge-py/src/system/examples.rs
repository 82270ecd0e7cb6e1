//! The paper's three examples (core `system::examples`).

use super::contacts::counts_dict;
use super::BlockSystem;
use crate::arrays::{self, Count, Whole};
use crate::errors::{input_error, to_py_err};
use numpy::{PyArray1, PyArray2};
use penedge::system::{self, PaperExample};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Example `n` (1, 2 or 3; a bool is an `InputError`, as [`Count`] says).
fn example(n: Count) -> PyResult<PaperExample> {
    let n: Whole = n.get("n")?;
    n.value()
        .and_then(|n| u32::try_from(n).ok())
        .and_then(PaperExample::from_number)
        .ok_or_else(|| {
            input_error(
                "example",
                format!("the paper's examples are 1, 2 and 3, got {n}"),
            )
        })
}

/// The block system of one of the paper's examples: a 10 m cube cut by planes.
///
/// Example 1: x = 5, y = 5, z = 5 (8 blocks); example 2: x + y = 10, y + z = 10, z + x = 10
/// (8 blocks); example 3: all six planes (26 blocks).
///
/// Parameters
/// ----------
/// n : {1, 2, 3}
///
/// Returns
/// -------
/// BlockSystem
///
/// Examples
/// --------
/// >>> import penedge
/// >>> found = penedge.paper_example(3).detect()
/// >>> len(found), list(found.counts().values())
/// (325, [205, 0, 0, 78, 0, 0, 42])
#[pyfunction]
pub fn paper_example(n: Count) -> PyResult<BlockSystem> {
    system::paper_example(example(n)?)
        .map(BlockSystem::wrap)
        .map_err(to_py_err)
}

/// Plane normals (m, 3) and offsets (m,).
type Planes<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// The cutting planes ``normals[i] . x = offsets[i]`` of one of the paper's examples.
///
/// Returns
/// -------
/// normals : numpy.ndarray, shape (m, 3)
/// offsets : numpy.ndarray, shape (m,)
#[pyfunction]
pub fn paper_example_planes(py: Python<'_>, n: Count) -> PyResult<Planes<'_>> {
    let (normals, offsets) = example(n)?.planes();
    Ok((arrays::rows3(py, &normals), arrays::vector(py, offsets)))
}

/// The contact counts printed in the paper's Table 3 for example `n`.
///
/// Returns
/// -------
/// dict of str to int
///     ``{name: count}`` for the seven types in code order (as ``SystemContacts.counts()``).
///
/// Examples
/// --------
/// >>> import penedge
/// >>> penedge.paper_table3(2)["face-face"]
/// 20
#[pyfunction]
pub fn paper_table3(py: Python<'_>, n: Count) -> PyResult<Bound<'_, PyDict>> {
    counts_dict(py, &system::paper_table3(example(n)?))
}
