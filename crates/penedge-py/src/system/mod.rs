//! `BlockSystem` (core `system`): its blocks, contacts (`contacts.rs`), flat arrays and
//! statistics (`blocks.rs`) and the paper's examples (`examples.rs`); its files are in
//! `crate::io`.

mod blocks;
mod contacts;
mod examples;

pub use blocks::BlockArrays;
pub use contacts::SystemContacts;
pub use examples::{paper_example, paper_example_planes, paper_table3};

use crate::arrays;
use crate::block::{cuboid, Block};
use crate::errors::to_py_err;
use crate::tolerance::tolerance;
use penedge::system;
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// A system of convex blocks; a block's id is its index.
///
/// Parameters
/// ----------
/// blocks : sequence of Block
///     The blocks (copied).
///
/// See Also
/// --------
/// BlockSystem.from_box_cut, paper_example
///
/// Examples
/// --------
/// >>> import penedge
/// >>> system = penedge.BlockSystem([penedge.Block.cuboid([0, 0, 0], [1, 1, 1]),
/// ...                               penedge.Block.cuboid([1, 0, 0], [2, 1, 1])])
/// >>> found = system.detect()
/// >>> found.pairs, found.types
/// (array([[0, 1]]), array([7], dtype=int8))
#[pyclass(module = "penedge", name = "BlockSystem", frozen)]
pub struct BlockSystem {
    /// The core system.
    pub inner: system::BlockSystem,
}

impl BlockSystem {
    /// Wraps a core system.
    pub fn wrap(inner: system::BlockSystem) -> Self {
        BlockSystem { inner }
    }
}

#[pymethods]
impl BlockSystem {
    #[new]
    fn new(blocks: Vec<Bound<'_, Block>>) -> Self {
        let blocks = blocks.iter().map(|b| b.get().inner.clone()).collect();
        BlockSystem {
            inner: system::BlockSystem::new(blocks),
        }
    }

    /// The box ``[lo, hi]`` cut by infinite planes ``normals[i] . x = offsets[i]``.
    ///
    /// Each plane splits every block it crosses, in the order given.
    ///
    /// Parameters
    /// ----------
    /// lo, hi : array_like, shape (3,)
    ///     Corners of the box, ``lo < hi``.
    /// normals : array_like, shape (m, 3)
    ///     Plane normals (any length but zero).
    /// offsets : array_like, shape (m,)
    ///     Plane offsets.
    ///
    /// Returns
    /// -------
    /// BlockSystem
    ///
    /// Raises
    /// ------
    /// InputError
    ///     Wrong shapes, ``lo >= hi``, or a zero / NaN plane (``kind == "degenerate_plane"``).
    /// BlockError
    ///     A plane cannot cut a block consistently (the message names the plane).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> system = penedge.BlockSystem.from_box_cut([0, 0, 0], [10, 10, 10],
    /// ...                                           [[1, 0, 0], [0, 1, 0]], [5, 5])
    /// >>> len(system), system.detect().counts()["face-face"]
    /// (4, 4)
    #[staticmethod]
    fn from_box_cut(
        lo: &Bound<'_, PyAny>,
        hi: &Bound<'_, PyAny>,
        normals: &Bound<'_, PyAny>,
        offsets: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let domain = cuboid(lo, hi)?;
        let (normals, offsets) = arrays::planes(normals, offsets)?;
        let tol = penedge::Tolerance::default();
        system::BlockSystem::from_domain_cut(domain, &normals, &offsets, &tol)
            .map(|inner| BlockSystem { inner })
            .map_err(to_py_err)
    }

    /// The blocks, indexed by id (copies).
    #[getter]
    fn blocks(&self) -> Vec<Block> {
        self.inner
            .blocks()
            .iter()
            .cloned()
            .map(Block::wrap)
            .collect()
    }

    /// Detects and classifies every contact of the system (in parallel, without the GIL).
    ///
    /// Parameters
    /// ----------
    /// gap : float, default 1e-12
    ///     Relative gap, as in :func:`detect_pair`.
    /// length : float, optional
    ///     Relative length threshold, as in :func:`detect_pair`.
    /// geometry : bool, default False
    ///     Also compute each contact's normal, signed distance, area and contact points
    ///     (about 50 % more time).
    ///
    /// Returns
    /// -------
    /// SystemContacts
    ///     The touching pairs, their types and features, and the penetrating pairs, as arrays;
    ///     with `geometry`, also ``normals``, ``distances``, ``areas``, ``point_offsets`` and
    ///     ``points``, one row (or one run of points) per contact, in the order of ``pairs``.
    ///
    /// Raises
    /// ------
    /// ToleranceError
    ///     Impossible `gap` or `length`.
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> system = penedge.BlockSystem.from_box_cut([0, 0, 0], [2, 1, 1], [[1, 0, 0]], [1])
    /// >>> found = system.detect(geometry=True)
    /// >>> found.normals, found.areas, found.point_offsets
    /// (array([[1., 0., 0.]]), array([1.]), array([0, 4]))
    /// >>> found.points_of(0).tolist()
    /// [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 1.0], [1.0, 0.0, 1.0]]
    #[pyo3(signature = (gap = 1e-12, length = None, geometry = false))]
    fn detect(
        &self,
        py: Python<'_>,
        gap: f64,
        length: Option<f64>,
        geometry: bool,
    ) -> PyResult<SystemContacts> {
        let tol = tolerance(gap, length)?;
        let inner = &self.inner;
        let (found, g) = if geometry {
            let (found, g) = py.detach(|| inner.detect_with_geometry(&tol));
            (found, Some(g))
        } else {
            (py.detach(|| inner.detect(&tol)), None)
        };
        SystemContacts::from_core(py, found, g)
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __getitem__(&self, index: isize) -> PyResult<Block> {
        let n = self.inner.len() as isize;
        let i = if index < 0 { index + n } else { index };
        if !(0..n).contains(&i) {
            let msg = format!("block index {index} out of range for {n} blocks");
            return Err(PyIndexError::new_err(msg));
        }
        Ok(Block::wrap(self.inner.blocks()[i as usize].clone()))
    }

    fn __repr__(&self) -> String {
        format!("BlockSystem({} blocks)", self.inner.len())
    }

    /// Pickles through the JSON block file (lossless, with the domain and joint table).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let text = penedge::io::json::to_json_string(&slf.get().inner);
        let from_json = py.get_type::<BlockSystem>().getattr("from_json")?;
        PyTuple::new(py, [from_json, (text,).into_pyobject(py)?.into_any()])
    }
}
