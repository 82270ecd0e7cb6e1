//! `SystemContacts`: every contact of a block system as numpy arrays (core
//! `system::{SystemContacts, ContactGeometries}`).

use crate::arrays;
use crate::classify::{contact_type_names, feature_code};
use numpy::{PyArray1, PyArray2};
use penedge::system::{self, count_types, ContactGeometries, SystemContacts as CoreContacts};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
/// normals : numpy.ndarray, shape (n, 3), float64, or None
///     Unit contact normals, from block ``pairs[i, 0]`` to block ``pairs[i, 1]``.
/// distances : numpy.ndarray, shape (n,), float64, or None
///     Signed distance along the normal: a gap (> 0) or a depth (< 0).
/// areas : numpy.ndarray, shape (n,), float64, or None
///     Contact area of face-face contacts (a polygon); 0 for points and segments.
/// point_offsets : numpy.ndarray, shape (n + 1,), int64, or None
///     Contact ``i`` has the points ``points[point_offsets[i]:point_offsets[i + 1]]``.
/// points : numpy.ndarray, shape (k, 3), float64, or None
///     Contact points of all contacts: one point, the two ends of a segment (edge-face,
///     edge-edge superposition), or a convex polygon counter-clockwise about the normal.
///
/// The geometry attributes (`normals` to `points`) are None unless the contacts were found
/// with ``BlockSystem.detect(geometry=True)``.
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
    #[pyo3(get)]
    normals: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    distances: Option<Py<PyArray1<f64>>>,
    #[pyo3(get)]
    areas: Option<Py<PyArray1<f64>>>,
    #[pyo3(get)]
    point_offsets: Option<Py<PyArray1<i64>>>,
    #[pyo3(get)]
    points: Option<Py<PyArray2<f64>>>,
    counts: [usize; 7],
    /// The core result, kept for the file writers.
    pub found: CoreContacts,
    /// The core geometry, when asked for.
    pub geometry: Option<ContactGeometries>,
    /// The system the contacts were found in and the tolerance used (for the table's joint
    /// sets and its distances within the gap), when found by `BlockSystem.detect`.
    pub source: Option<(Py<super::BlockSystem>, penedge::Tolerance)>,
}

/// The geometry arrays: normals, distances, areas, point offsets, points.
type GeometryArrays = (
    Py<PyArray2<f64>>,
    Py<PyArray1<f64>>,
    Py<PyArray1<f64>>,
    Py<PyArray1<i64>>,
    Py<PyArray2<f64>>,
);

fn geometry_arrays(py: Python<'_>, g: &ContactGeometries) -> PyResult<GeometryArrays> {
    let offsets = g.point_offsets.iter().map(|&o| o as i64).collect();
    Ok((
        arrays::read_only(arrays::rows3(py, &g.normals))?.unbind(),
        arrays::read_only(arrays::vector(py, g.distances.clone()))?.unbind(),
        arrays::read_only(arrays::vector(py, g.areas.clone()))?.unbind(),
        arrays::read_only(arrays::vector(py, offsets))?.unbind(),
        arrays::read_only(arrays::rows3(py, &g.points))?.unbind(),
    ))
}

impl SystemContacts {
    /// The arrays of a core result (and its geometry, when computed).
    pub fn from_core(
        py: Python<'_>,
        found: CoreContacts,
        geometry: Option<ContactGeometries>,
        source: Option<(Py<super::BlockSystem>, penedge::Tolerance)>,
    ) -> PyResult<Self> {
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
        let g = geometry
            .as_ref()
            .map(|g| geometry_arrays(py, g))
            .transpose()?;
        Ok(SystemContacts {
            pairs: arrays::read_only(arrays::pairs(py, &pairs))?.unbind(),
            types: arrays::read_only(arrays::vector(py, types))?.unbind(),
            feature_kinds: arrays::read_only(arrays::pairs(py, &kinds))?.unbind(),
            feature_ids: arrays::read_only(arrays::pairs(py, &ids))?.unbind(),
            penetrating: arrays::read_only(arrays::pairs(py, &penetrating))?.unbind(),
            normals: g.as_ref().map(|g| g.0.clone_ref(py)),
            distances: g.as_ref().map(|g| g.1.clone_ref(py)),
            areas: g.as_ref().map(|g| g.2.clone_ref(py)),
            point_offsets: g.as_ref().map(|g| g.3.clone_ref(py)),
            points: g.map(|g| g.4),
            counts: count_types(c),
            found,
            geometry,
            source,
        })
    }
}

/// ``{name: count}`` for the seven contact types in code order.
pub fn counts_dict<'py>(py: Python<'py>, counts: &[usize; 7]) -> PyResult<Bound<'py, PyDict>> {
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

    /// The contact points of contact `i`, shape (k, 3): one point, a segment's two ends or
    /// a polygon's vertices.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     The contacts were found without geometry.
    /// IndexError
    ///     `i` out of range.
    fn points_of<'py>(
        &self,
        py: Python<'py>,
        i: arrays::Whole,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let g = self.geometry()?;
        let n = g.len();
        let Some(k) = arrays::index_in(&i, n) else {
            let msg = format!("contact index {i} out of range for {n} contacts");
            return Err(PyIndexError::new_err(msg));
        };
        Ok(arrays::rows3(py, g.points_of(k)))
    }

    fn __len__(&self) -> usize {
        self.counts.iter().sum()
    }

    fn __repr__(&self) -> String {
        let names = contact_type_names();
        let by_type: Vec<String> = (0..7)
            .filter(|&t| self.counts[t] > 0)
            .map(|t| format!("{} {}", names[t], self.counts[t]))
            .collect();
        format!(
            "SystemContacts({}: {}; {} penetrating{})",
            crate::counted(self.__len__(), "contact", "contacts"),
            if by_type.is_empty() {
                "none".to_string()
            } else {
                by_type.join(", ")
            },
            self.found.penetrating.len(),
            if self.geometry.is_some() {
                "; with geometry"
            } else {
                ""
            },
        )
    }
}

impl SystemContacts {
    /// The geometry, or an `InputError` saying how to get it.
    pub fn geometry(&self) -> PyResult<&ContactGeometries> {
        self.geometry.as_ref().ok_or_else(|| {
            crate::errors::input_error(
                "no_geometry",
                "these contacts have no geometry: use BlockSystem.detect(geometry=True)",
            )
        })
    }
}
