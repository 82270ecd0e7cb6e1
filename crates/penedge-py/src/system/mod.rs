//! `BlockSystem`, its contacts as numpy arrays (`SystemContacts`), and the paper's examples.

use crate::arrays;
use crate::block::{cuboid, Block};
use crate::classify::{contact_type_names, feature_code};
use crate::errors::{input_error, to_py_err};
use crate::tolerance::tolerance;
use numpy::{PyArray1, PyArray2};
use penedge::system::{self, count_types, PaperExample, SystemContacts as CoreContacts};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

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
    inner: system::BlockSystem,
}

/// Every contact of a block system, as numpy arrays (read-only), one row per touching pair.
///
/// Attributes
/// ----------
/// pairs : numpy.ndarray, shape (n, 2), int64
///     Block ids ``i < j`` of each touching pair, sorted.
/// types : numpy.ndarray, shape (n,), int8
///     Contact type codes 1..7 (``CONTACT_TYPES[code - 1]`` is the name).
/// feature_kinds : numpy.ndarray, shape (n, 2), int8
///     The feature of each block holding the contact: 0 vertex, 1 edge, 2 face
///     (``FEATURE_KINDS[k]``).
/// feature_ids : numpy.ndarray, shape (n, 2), int64
///     Index of that feature in its block (vertex, edge or face index).
/// penetrating : numpy.ndarray, shape (m, 2), int64
///     Pairs that overlap deeper than the gap (not in `pairs`).
#[pyclass(module = "penedge", name = "SystemContacts", frozen)]
pub struct SystemContacts {
    #[pyo3(get)]
    pairs: Py<PyArray2<i64>>,
    #[pyo3(get)]
    types: Py<PyArray1<i8>>,
    #[pyo3(get)]
    feature_kinds: Py<PyArray2<i8>>,
    #[pyo3(get)]
    feature_ids: Py<PyArray2<i64>>,
    #[pyo3(get)]
    penetrating: Py<PyArray2<i64>>,
    counts: [usize; 7],
}

impl SystemContacts {
    fn from_core(py: Python<'_>, found: &CoreContacts) -> PyResult<Self> {
        let c = &found.contacts;
        let pair_rows = |p: [u32; 2]| p.map(i64::from);
        let pairs: Vec<[i64; 2]> = c.iter().map(|pc| pair_rows(pc.pair)).collect();
        let features = |pc: &system::PairContact| {
            [
                feature_code(pc.contact.feature_a),
                feature_code(pc.contact.feature_b),
            ]
        };
        let kinds: Vec<[i8; 2]> = c.iter().map(|pc| features(pc).map(|f| f.0)).collect();
        let ids: Vec<[i64; 2]> = c.iter().map(|pc| features(pc).map(|f| f.1)).collect();
        let types: Vec<i8> = c.iter().map(|pc| pc.contact.kind.code() as i8).collect();
        let penetrating: Vec<[i64; 2]> = found.penetrating.iter().map(|&p| pair_rows(p)).collect();
        Ok(SystemContacts {
            pairs: arrays::read_only(arrays::pairs(py, &pairs))?.unbind(),
            types: arrays::read_only(arrays::vector(py, types))?.unbind(),
            feature_kinds: arrays::read_only(arrays::pairs(py, &kinds))?.unbind(),
            feature_ids: arrays::read_only(arrays::pairs(py, &ids))?.unbind(),
            penetrating: arrays::read_only(arrays::pairs(py, &penetrating))?.unbind(),
            counts: count_types(c),
        })
    }
}

fn counts_dict<'py>(py: Python<'py>, counts: &[usize; 7]) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (name, n) in contact_type_names().into_iter().zip(counts) {
        dict.set_item(name, n)?;
    }
    Ok(dict)
}

#[pymethods]
impl SystemContacts {
    /// The number of contacts of each type, ``{name: count}`` for all seven types in code
    /// order (zeros included).
    fn counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        counts_dict(py, &self.counts)
    }

    fn __len__(&self) -> usize {
        self.counts.iter().sum()
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let names = contact_type_names();
        let by_type: Vec<String> = (0..7)
            .filter(|&t| self.counts[t] > 0)
            .map(|t| format!("{} {}", names[t], self.counts[t]))
            .collect();
        format!(
            "SystemContacts({} contacts: {}; {} penetrating)",
            self.__len__(),
            if by_type.is_empty() {
                "none".to_string()
            } else {
                by_type.join(", ")
            },
            self.penetrating.bind(py).len().unwrap_or(0),
        )
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
        let normals = arrays::points(normals, "normals")?;
        let offsets = arrays::numbers(offsets, "offsets")?;
        if normals.len() != offsets.len() {
            let msg = format!(
                "normals and offsets must have the same length, got {} and {}",
                normals.len(),
                offsets.len()
            );
            return Err(input_error("shape", msg));
        }
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
    ///
    /// Returns
    /// -------
    /// SystemContacts
    ///     The touching pairs, their types and features, and the penetrating pairs, as arrays.
    ///
    /// Raises
    /// ------
    /// ToleranceError
    ///     Impossible `gap` or `length`.
    #[pyo3(signature = (gap = 1e-12, length = None))]
    fn detect(&self, py: Python<'_>, gap: f64, length: Option<f64>) -> PyResult<SystemContacts> {
        let tol = tolerance(gap, length)?;
        let inner = &self.inner;
        let found = py.detach(|| inner.detect(&tol));
        SystemContacts::from_core(py, &found)
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

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let args = (slf.get().blocks(),).into_pyobject(py)?;
        PyTuple::new(
            py,
            [py.get_type::<BlockSystem>().into_any(), args.into_any()],
        )
    }
}

fn example(n: i64) -> PyResult<PaperExample> {
    u32::try_from(n)
        .ok()
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
pub fn paper_example(n: i64) -> PyResult<BlockSystem> {
    system::paper_example(example(n)?)
        .map(|inner| BlockSystem { inner })
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
pub fn paper_example_planes(py: Python<'_>, n: i64) -> PyResult<Planes<'_>> {
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
pub fn paper_table3(py: Python<'_>, n: i64) -> PyResult<Bound<'_, PyDict>> {
    counts_dict(py, &system::paper_table3(example(n)?))
}
