//! Concave blocks (core `system::{with_bodies, detect_bodies}`): body ids, internal faces,
//! body mass properties, and the contacts of bodies as numpy arrays.

use super::{thread_pool, watched, BlockSystem};
use crate::arrays::{self, Count, Real};
use crate::errors::input_error;
use crate::tolerance::tolerance;
use numpy::{PyArray1, PyArray2, PyArray3};
use penedge::system::{BodyContacts as CoreBodyContacts, Cancelled};
use pyo3::prelude::*;
use pyo3::types::PyDict;

#[pymethods]
impl BlockSystem {
    /// This system with a body id per block: blocks that share an id are the convex parts of
    /// one concave block, glued along their common (internal) faces.
    ///
    /// Parameters
    /// ----------
    /// body_ids : sequence of int, length ``len(system)``
    ///     The body of each block (any non-negative ids; by default a block is its own body).
    /// gap, length, absolute_gap : float
    ///     The tolerance at which the parts must touch face to face (as in
    ///     :meth:`BlockSystem.detect`).
    ///
    /// Raises
    /// ------
    /// InputError
    ///     Not one id per block (``kind == "body_ids"``), an id that is negative or not a
    ///     whole number (a float or a bool: ``kind`` ``"negative"`` or ``"dtype"``), parts
    ///     of a body that overlap or are not all glued face to face (``kind == "concave"``,
    ///     the message names the body and the parts).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> c = penedge.Block.cuboid
    /// >>> system = penedge.BlockSystem([c([0, 0, 0], [2, 1, 1]), c([0, 0, 1], [1, 1, 2]),
    /// ...                               c([1, 0, 1], [2, 1, 2])])
    /// >>> l_block = system.with_bodies([0, 0, 1])
    /// >>> l_block.body_ids.tolist(), l_block.internal_faces()["areas"].round(9).tolist()
    /// ([0, 0, 1], [1.0])
    #[pyo3(signature = (body_ids, gap = Real::Value(1e-12), length = None, absolute_gap = None),
        text_signature = "($self, body_ids, gap=1e-12, length=None, absolute_gap=None)")]
    fn with_bodies(
        &self,
        py: Python<'_>,
        body_ids: &Bound<'_, PyAny>,
        gap: Real,
        length: Option<Real>,
        absolute_gap: Option<Real>,
    ) -> PyResult<BlockSystem> {
        let tol = tolerance(gap, length, absolute_gap)?;
        // Whole numbers of any integer dtype, no floats or bools (`arrays::indices`).
        let ids = arrays::indices(body_ids, "body_ids")?
            .iter()
            .map(|&b| u32::try_from(b))
            .collect::<Result<Vec<u32>, _>>()
            .map_err(|_| input_error("body_ids", "body ids must be from 0 to 2^32 - 1"))?;
        let system = self.inner.clone();
        py.detach(|| system.with_bodies(ids, &tol))
            .map(BlockSystem::wrap)
            .map_err(|e| match e {
                penedge::system::ConcaveError::Count { .. } => {
                    input_error("body_ids", e.to_string())
                }
                _ => input_error("concave", e.to_string()),
            })
    }

    /// The body id of each block, shape (n,), int64.
    #[getter]
    fn body_ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let ids = self.inner.body_ids().into_iter().map(i64::from).collect();
        arrays::vector(py, ids)
    }

    /// The rigid body of each block in the mechanics, shape (n,), int64: the parts of a body
    /// joined by rigid glue, numbered in the order of their first block. A body held by rock
    /// bridges (``docs/generation.md``, "Rock bridges") is several rigid bodies, so that the
    /// bridge can break; any other body is one. What :class:`Simulation` makes its bodies of
    /// (its :attr:`Simulation.block_bodies`).
    ///
    /// >>> import penedge
    /// >>> a = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    /// >>> b = penedge.Block.cuboid([1, 0, 0], [2, 1, 1])
    /// >>> penedge.BlockSystem([a, b]).with_bodies([3, 3]).rigid_body_ids.tolist()
    /// [0, 0]
    #[getter]
    fn rigid_body_ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let ids = self
            .inner
            .rigid_body_ids()
            .into_iter()
            .map(i64::from)
            .collect();
        arrays::vector(py, ids)
    }

    /// The internal faces (glue between the parts of concave blocks), as a dict of arrays:
    /// ``parts`` (m, 2) block ids, ``faces`` (m, 2) the face of each, ``areas`` (m,).
    fn internal_faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let glue = self.inner.internal_faces();
        let dict = PyDict::new(py);
        let parts: Vec<[i64; 2]> = glue.iter().map(|g| g.parts.map(i64::from)).collect();
        let faces: Vec<[i64; 2]> = glue.iter().map(|g| g.faces.map(i64::from)).collect();
        dict.set_item("parts", arrays::pairs(py, &parts))?;
        dict.set_item("faces", arrays::pairs(py, &faces))?;
        dict.set_item(
            "areas",
            arrays::vector(py, glue.iter().map(|g| g.area).collect()),
        )?;
        Ok(dict)
    }

    /// Mass properties of each body (per unit density), exact for the union of its parts:
    /// a dict of ``bodies`` (k,) ids ascending, ``volumes`` (k,), ``centroids`` (k, 3) and
    /// ``inertia`` (k, 3, 3) about the centroid.
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> c = penedge.Block.cuboid
    /// >>> system = penedge.BlockSystem([c([0, 0, 0], [2, 1, 1]), c([0, 0, 1], [1, 1, 2])])
    /// >>> m = system.with_bodies([0, 0]).body_mass_properties()
    /// >>> m["volumes"].round(9).tolist(), m["centroids"].round(4).tolist()
    /// ([3.0], [[0.8333, 0.5, 0.8333]])
    fn body_mass_properties<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let inner = &self.inner;
        let all = py.detach(|| inner.body_mass_properties());
        let dict = PyDict::new(py);
        let ids: Vec<i64> = all.iter().map(|(b, _)| i64::from(*b)).collect();
        let centroids: Vec<[f64; 3]> = all.iter().map(|(_, m)| m.centroid.to_array()).collect();
        let inertia: Vec<Vec<Vec<f64>>> = all
            .iter()
            .map(|(_, m)| {
                let t = m.inertia.transpose().to_cols_array_2d();
                t.iter().map(|row| row.to_vec()).collect()
            })
            .collect();
        dict.set_item("bodies", arrays::vector(py, ids))?;
        dict.set_item(
            "volumes",
            arrays::vector(py, all.iter().map(|(_, m)| m.volume).collect()),
        )?;
        dict.set_item("centroids", arrays::rows3(py, &centroids))?;
        dict.set_item("inertia", PyArray3::from_vec3(py, &inertia)?)?;
        Ok(dict)
    }

    /// Every contact of the bodies (concave blocks and convex blocks): the parts are
    /// detected pair by pair, then their contacts are grouped per pair of bodies into
    /// contact regions typed by the bodies' real features (docs/concave-blocks.md).
    ///
    /// Parameters
    /// ----------
    /// gap, length, progress, threads, absolute_gap
    ///     As in :meth:`BlockSystem.detect`.
    ///
    /// Returns
    /// -------
    /// BodyContacts
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> c = penedge.Block.cuboid
    /// >>> u = [c([0, 0, 0], [3, 1, 1]), c([0, 0, 1], [1, 1, 2]), c([2, 0, 1], [3, 1, 2])]
    /// >>> system = penedge.BlockSystem(u + [c([1, 0, 1], [2, 1, 2])])
    /// >>> found = system.with_bodies([0, 0, 0, 1]).detect_bodies()
    /// >>> found.bodies.tolist(), found.regions.tolist(), found.areas.round(9).tolist()
    /// ([[0, 1], [0, 1], [0, 1]], [0, 1, 2], [1.0, 1.0, 1.0])
    #[pyo3(signature = (gap = Real::Value(1e-12), length = None, progress = None, threads = None,
        absolute_gap = None),
        text_signature = "($self, gap=1e-12, length=None, progress=None, threads=None, absolute_gap=None)")]
    fn detect_bodies(
        &self,
        py: Python<'_>,
        gap: Real,
        length: Option<Real>,
        progress: Option<Py<PyAny>>,
        threads: Option<Count>,
        absolute_gap: Option<Real>,
    ) -> PyResult<BodyContacts> {
        let tol = tolerance(gap, length, absolute_gap)?;
        let pool = thread_pool(threads)?;
        let inner = &self.inner;
        let (result, failure) = watched(py, progress.as_ref(), |report| {
            let mut run = || inner.detect_bodies_with_progress(&tol, report);
            match &pool {
                Some(pool) => pool.install(run),
                None => run(),
            }
        });
        match (result, failure) {
            (Ok(found), None) => BodyContacts::from_core(py, found),
            (_, Some(e)) => Err(e),
            (Err(Cancelled), None) => unreachable!("only a failed callback cancels"),
        }
    }
}

/// Every contact region of the bodies of a system, as numpy arrays (read-only), one row per
/// region: two bodies can touch in several separate regions (a block sitting in a notch
/// touches its floor and its walls), numbered 0, 1, ... in `regions`.
///
/// Attributes
/// ----------
/// bodies : numpy.ndarray, shape (n, 2), int64
///     Body ids ``i < j`` of each region, sorted.
/// regions : numpy.ndarray, shape (n,), int64
///     The region's index among the regions of its pair of bodies.
/// types : numpy.ndarray, shape (n,), int8
///     Contact type codes 1..7 by the bodies' real features (a part edge inside a real
///     face of the block is not an edge of the block).
/// normals : numpy.ndarray, shape (n, 3), float64
///     Unit normals from body ``bodies[i, 0]`` to ``bodies[i, 1]``.
/// distances : numpy.ndarray, shape (n,), float64
///     Signed distance along the normal (the smallest of the region's pieces').
/// areas : numpy.ndarray, shape (n,), float64
///     Area of a face-face region (all its pieces together), 0 otherwise.
/// penetrating : numpy.ndarray, shape (m, 2), int64
///     Pairs of bodies with parts that overlap deeper than the gap.
/// piece_offsets : numpy.ndarray, shape (n + 1,), int64
///     Region ``i`` is made of the part contacts ``piece_offsets[i]:piece_offsets[i + 1]``.
/// piece_parts : numpy.ndarray, shape (k, 2), int64
///     The two parts (block ids) of each piece, the part of ``bodies[i, 0]`` first.
/// piece_types : numpy.ndarray, shape (k,), int8
///     The part contact's own type.
/// piece_point_offsets : numpy.ndarray, shape (k + 1,), int64
///     Piece ``p`` has the points ``piece_points[piece_point_offsets[p]:...[p + 1]]``.
/// piece_points : numpy.ndarray, shape (q, 3), float64
///     Contact points of the pieces (a point, a segment's ends or a convex polygon).
#[pyclass(module = "penedge", name = "BodyContacts", frozen)]
pub struct BodyContacts {
    #[pyo3(get)]
    bodies: Py<PyArray2<i64>>,
    #[pyo3(get)]
    regions: Py<PyArray1<i64>>,
    #[pyo3(get)]
    types: Py<PyArray1<i8>>,
    #[pyo3(get)]
    normals: Py<PyArray2<f64>>,
    #[pyo3(get)]
    distances: Py<PyArray1<f64>>,
    #[pyo3(get)]
    areas: Py<PyArray1<f64>>,
    #[pyo3(get)]
    penetrating: Py<PyArray2<i64>>,
    #[pyo3(get)]
    piece_offsets: Py<PyArray1<i64>>,
    #[pyo3(get)]
    piece_parts: Py<PyArray2<i64>>,
    #[pyo3(get)]
    piece_types: Py<PyArray1<i8>>,
    #[pyo3(get)]
    piece_point_offsets: Py<PyArray1<i64>>,
    #[pyo3(get)]
    piece_points: Py<PyArray2<f64>>,
    len: usize,
    /// The core result, kept for the file writers.
    pub found: CoreBodyContacts,
}

impl BodyContacts {
    pub(crate) fn from_core(py: Python<'_>, f: CoreBodyContacts) -> PyResult<Self> {
        let c = &f.contacts;
        let rows = |p: [u32; 2]| p.map(i64::from);
        let offsets = |o: &[u64]| o.iter().map(|&x| x as i64).collect::<Vec<i64>>();
        let bodies: Vec<[i64; 2]> = c.iter().map(|r| rows(r.bodies)).collect();
        let parts: Vec<[i64; 2]> = f.pieces.iter().map(|p| rows(p.pair)).collect();
        let penetrating: Vec<[i64; 2]> = f.penetrating.iter().map(|&p| rows(p)).collect();
        let normals: Vec<[f64; 3]> = c.iter().map(|r| r.normal).collect();
        Ok(BodyContacts {
            len: c.len(),
            bodies: arrays::read_only(arrays::pairs(py, &bodies))?.unbind(),
            regions: arrays::read_only(arrays::vector(
                py,
                c.iter().map(|r| i64::from(r.region)).collect(),
            ))?
            .unbind(),
            types: arrays::read_only(arrays::vector(
                py,
                c.iter().map(|r| r.kind.code() as i8).collect(),
            ))?
            .unbind(),
            normals: arrays::read_only(arrays::rows3(py, &normals))?.unbind(),
            distances: arrays::read_only(arrays::vector(
                py,
                c.iter().map(|r| r.distance).collect(),
            ))?
            .unbind(),
            areas: arrays::read_only(arrays::vector(py, c.iter().map(|r| r.area).collect()))?
                .unbind(),
            penetrating: arrays::read_only(arrays::pairs(py, &penetrating))?.unbind(),
            piece_offsets: arrays::read_only(arrays::vector(py, offsets(&f.piece_offsets)))?
                .unbind(),
            piece_parts: arrays::read_only(arrays::pairs(py, &parts))?.unbind(),
            piece_types: arrays::read_only(arrays::vector(
                py,
                f.pieces
                    .iter()
                    .map(|p| p.contact.kind.code() as i8)
                    .collect(),
            ))?
            .unbind(),
            piece_point_offsets: arrays::read_only(arrays::vector(
                py,
                offsets(&f.piece_point_offsets),
            ))?
            .unbind(),
            piece_points: arrays::read_only(arrays::rows3(py, &f.piece_points))?.unbind(),
            found: f,
        })
    }
}

#[pymethods]
impl BodyContacts {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!("BodyContacts({} regions)", self.len)
    }
}
