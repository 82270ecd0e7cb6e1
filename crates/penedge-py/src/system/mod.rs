//! `BlockSystem` (core `system`): its blocks, contacts (`contacts.rs`), flat arrays and
//! statistics (`blocks.rs`) and the paper's examples (`examples.rs`); its files are in
//! `crate::io`.

mod blocks;
mod bodies;
mod contacts;
mod examples;
mod excavate;
mod tracker;

pub use blocks::BlockArrays;
pub use bodies::BodyContacts;
pub use contacts::SystemContacts;
pub use examples::{paper_example, paper_example_planes, paper_table3};
pub use tracker::ContactTracker;

use crate::arrays::{self, Count, Real, Whole};
use crate::block::{cuboid, Block};
use crate::errors::{input_error, to_py_err};
use crate::tolerance::tolerance;
use penedge::system::{self, Cancelled, DetectProgress};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

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

    /// A system from flat arrays, as :meth:`arrays` gives them back, without a Python object
    /// per block (the blocks are built and validated in parallel, without the GIL).
    ///
    /// Block ``i`` owns the vertices ``vertices[vertex_offsets[i]:vertex_offsets[i + 1]]``
    /// and the faces ``face_offsets[i]:face_offsets[i + 1]``; face ``f`` is the loop
    /// ``face_vertices[loop_offsets[f]:loop_offsets[f + 1]]`` of indices into `vertices`
    /// (each among its own block's vertices), counter-clockwise seen from outside. Each
    /// block is checked as :class:`Block` checks it.
    ///
    /// Parameters
    /// ----------
    /// vertices : array_like, shape (v, 3)
    /// vertex_offsets : array_like of int, shape (n + 1,)
    /// face_offsets : array_like of int, shape (n + 1,)
    /// loop_offsets : array_like of int, shape (f + 1,)
    /// face_vertices : array_like of int, shape (l,)
    /// face_origin_kind, face_origin_set, face_origin_index : array_like of int, optional
    ///     Shape (f,) each: where each face comes from, as in :class:`BlockArrays` (all three or none); kept
    ///     for the blocks whose faces are kept as given.
    ///
    /// Returns
    /// -------
    /// BlockSystem
    ///
    /// Raises
    /// ------
    /// InputError
    ///     Wrong shapes or dtypes, offsets that do not start at 0, decrease or do not end at
    ///     the length of what they index, or a face that refers to another block's vertex
    ///     (``kind == "arrays"``; the message names the array, face and block).
    /// BlockError
    ///     A block that is not a closed convex polyhedron; the message starts with
    ///     ``block i:`` (the lowest such id).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> a = penedge.paper_example(3).arrays()
    /// >>> system = penedge.BlockSystem.from_arrays(
    /// ...     a.vertices, a.vertex_offsets, a.face_offsets, a.loop_offsets, a.face_vertices)
    /// >>> len(system), system.detect().counts() == penedge.paper_example(3).detect().counts()
    /// (26, True)
    #[staticmethod]
    #[pyo3(signature = (vertices, vertex_offsets, face_offsets, loop_offsets, face_vertices,
                        face_origin_kind=None, face_origin_set=None, face_origin_index=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        vertex_offsets: &Bound<'_, PyAny>,
        face_offsets: &Bound<'_, PyAny>,
        loop_offsets: &Bound<'_, PyAny>,
        face_vertices: &Bound<'_, PyAny>,
        face_origin_kind: Option<&Bound<'_, PyAny>>,
        face_origin_set: Option<&Bound<'_, PyAny>>,
        face_origin_index: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let vertices = arrays::points(vertices, "vertices")?;
        let vertex_offsets = arrays::indices(vertex_offsets, "vertex_offsets")?;
        let face_offsets = arrays::indices(face_offsets, "face_offsets")?;
        let loop_offsets = arrays::indices(loop_offsets, "loop_offsets")?;
        let face_vertices = arrays::indices(face_vertices, "face_vertices")?;
        let origins = match (face_origin_kind, face_origin_set, face_origin_index) {
            (None, None, None) => None,
            (Some(kind), Some(set), Some(index)) => Some(face_origins(kind, set, index)?),
            _ => {
                let msg = "give all three of face_origin_kind, face_origin_set and \
                           face_origin_index, or none";
                return Err(input_error("origins", msg));
            }
        };
        let flat = system::FlatBlocks {
            vertices: &vertices,
            vertex_offsets: &vertex_offsets,
            face_offsets: &face_offsets,
            loop_offsets: &loop_offsets,
            face_vertices: &face_vertices,
            origins: origins.as_deref(),
        };
        let tol = penedge::Tolerance::default();
        py.detach(|| system::BlockSystem::from_arrays(&flat, &tol))
            .map(BlockSystem::wrap)
            .map_err(to_py_err)
    }

    /// The length unit of the coordinates (the generation spec's ``unit``, kept in the
    /// block file), or None when not named. A label for pictures and reports: penedge
    /// computes in whatever unit the numbers are.
    #[getter]
    fn unit(&self) -> Option<String> {
        self.inner.unit().map(str::to_string)
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
    /// In a system with concave blocks (blocks that share a body id,
    /// :meth:`BlockSystem.with_bodies`, or generated around excavations, under slopes or
    /// held by rock bridges), two parts of one body are one block: the glue between them is
    /// never a contact, as in :class:`ContactTracker`. The contacts are those between parts
    /// of different bodies, typed by the parts' features; :meth:`BlockSystem.detect_bodies`
    /// groups them into the contact regions of the bodies.
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
    /// progress : callable, optional
    ///     Called as ``progress(pairs_done, pairs_total)`` at most ten times a second while
    ///     the narrow phase runs (the candidate pairs are known by then), and once at the
    ///     end. An exception it raises stops the detection and propagates.
    /// threads : int, optional
    ///     Number of threads (default: all cores, or ``RAYON_NUM_THREADS``). The result is
    ///     the same for any number.
    /// absolute_gap : float, optional
    ///     The gap as a length (model units) instead of `gap`, as in :func:`detect_pair`.
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
    ///     Impossible `gap`, `length` or `absolute_gap`.
    /// InputError
    ///     `threads` below 1 or above 1024.
    /// KeyboardInterrupt
    ///     Ctrl-C: the detection runs without the GIL and stops within a fraction of a
    ///     second.
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
    #[pyo3(signature = (gap = Real::Value(1e-12), length = None, geometry = false, progress = None,
        threads = None, absolute_gap = None),
        text_signature = "($self, gap=1e-12, length=None, geometry=False, progress=None, threads=None, absolute_gap=None)")]
    #[allow(clippy::too_many_arguments)] // Python's keyword arguments, one per option
    fn detect(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        gap: Real,
        length: Option<Real>,
        geometry: bool,
        progress: Option<Py<PyAny>>,
        threads: Option<Count>,
        absolute_gap: Option<Real>,
    ) -> PyResult<SystemContacts> {
        let tol = tolerance(gap, length, absolute_gap)?;
        let pool = thread_pool(threads)?;
        let inner = &slf.get().inner;
        let run = |report: &mut (dyn FnMut(DetectProgress) -> ControlFlow<()> + Send)| {
            let mut run = || {
                if geometry {
                    inner
                        .detect_with_geometry_and_progress(&tol, report)
                        .map(|(found, g)| (found, Some(g)))
                } else {
                    inner.detect_with_progress(&tol, report).map(|f| (f, None))
                }
            };
            match &pool {
                Some(pool) => pool.install(run),
                None => run(),
            }
        };
        let (result, failure) = watched(py, progress.as_ref(), run);
        match (result, failure) {
            (Ok((found, g)), None) => {
                let source = (slf.clone().unbind(), tol);
                SystemContacts::from_core(py, found, g, Some(source))
            }
            (_, Some(e)) => Err(e),
            (Err(Cancelled), None) => unreachable!("only a failed callback cancels"),
        }
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __getitem__(&self, index: Whole) -> PyResult<Block> {
        let n = self.inner.len();
        let Some(i) = arrays::index_in(&index, n) else {
            let msg = format!("block index {index} out of range for {n} blocks");
            return Err(PyIndexError::new_err(msg));
        };
        Ok(Block::wrap(self.inner.blocks()[i].clone()))
    }

    fn __repr__(&self) -> String {
        format!(
            "BlockSystem({})",
            crate::counted(self.inner.len(), "block", "blocks")
        )
    }

    /// Pickles through the JSON block file (lossless, with the domain and joint table).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let text = penedge::io::json::to_json_string(&slf.get().inner);
        let from_json = py.get_type::<BlockSystem>().getattr("from_json")?;
        PyTuple::new(py, [from_json, (text,).into_pyobject(py)?.into_any()])
    }
}

/// Face origins from the three arrays of :class:`BlockArrays` (kind, set, index).
fn face_origins(
    kind: &Bound<'_, PyAny>,
    set: &Bound<'_, PyAny>,
    index: &Bound<'_, PyAny>,
) -> PyResult<Vec<penedge::block::FaceOrigin>> {
    let whole = |obj: &Bound<'_, PyAny>, name: &str| -> PyResult<Vec<i64>> {
        let values = arrays::numbers(obj, name)?;
        values
            .iter()
            .map(|&x| {
                if x.fract() == 0.0 && x.abs() < 2f64.powi(53) {
                    Ok(x as i64)
                } else {
                    Err(input_error(
                        "dtype",
                        format!("{name} must hold integers, got {x}"),
                    ))
                }
            })
            .collect()
    };
    let (kind, set, index) = (
        whole(kind, "face_origin_kind")?,
        whole(set, "face_origin_set")?,
        whole(index, "face_origin_index")?,
    );
    if kind.len() != set.len() || kind.len() != index.len() {
        let msg = format!(
            "face_origin_kind, face_origin_set and face_origin_index have {}, {} and {} values",
            kind.len(),
            set.len(),
            index.len()
        );
        return Err(input_error("origins", msg));
    }
    (0..kind.len())
        .map(|f| crate::block::face_origin(kind[f], set[f], index[f]))
        .collect()
}

/// The shortest time between two progress reports (and Ctrl-C checks).
const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

/// The most threads a detection may ask for: each is an operating-system thread.
const MAX_THREADS: i64 = 1024;

/// A pool of `threads` threads, or none for rayon's global pool (a bool is an `InputError`,
/// as [`Count`] says).
pub(crate) fn thread_pool(threads: Option<Count>) -> PyResult<Option<rayon::ThreadPool>> {
    let Some(given) = Count::optional(threads, "threads")? else {
        return Ok(None);
    };
    let Some(n) = given.value().filter(|n| (1..=MAX_THREADS).contains(n)) else {
        let msg = format!("threads must be from 1 to {MAX_THREADS}, got {given}");
        return Err(input_error("threads", msg));
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(n as usize)
        .build()
        .map(Some)
        .map_err(|e| input_error("threads", format!("cannot start {n} threads: {e}")))
}

/// Runs `job` on a worker thread without the GIL while this (the calling) thread waits for
/// it, waking every [`PROGRESS_INTERVAL`] to check for Ctrl-C (signals reach Python on the
/// main thread only) and to call `progress(pairs_done, pairs_total)`. A signal or an
/// exception of the callback cancels the job at its next report and is returned.
fn watched<T: Send>(
    py: Python<'_>,
    progress: Option<&Py<PyAny>>,
    job: impl FnOnce(&mut (dyn FnMut(DetectProgress) -> ControlFlow<()> + Send)) -> T + Send,
) -> (T, Option<PyErr>) {
    let cancel = AtomicBool::new(false);
    let mut failure = None;
    let mut latest = None;
    let result = py.detach(|| {
        let (tx, rx) = mpsc::channel::<DetectProgress>();
        let cancel = &cancel;
        std::thread::scope(|scope| {
            let worker = scope.spawn(move || {
                let mut report = |p: DetectProgress| {
                    // The watcher may be gone only once the job is cancelled.
                    let _ = tx.send(p);
                    if cancel.load(Ordering::Relaxed) {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                };
                let out = job(&mut report);
                drop(tx);
                out
            });
            let mut last = Instant::now();
            loop {
                let finished = match rx.recv_timeout(PROGRESS_INTERVAL) {
                    Ok(p) => {
                        latest = Some(p);
                        false
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => false,
                    Err(mpsc::RecvTimeoutError::Disconnected) => true,
                };
                if finished || failure.is_some() || last.elapsed() < PROGRESS_INTERVAL {
                    if finished {
                        break;
                    }
                    continue;
                }
                last = Instant::now();
                let call = Python::attach(|py| {
                    py.check_signals()?;
                    match (progress, latest) {
                        (Some(callback), Some(p)) => {
                            callback.call1(py, (p.pairs_done, p.pairs_total)).map(drop)
                        }
                        _ => Ok(()),
                    }
                });
                if let Err(e) = call {
                    failure = Some(e);
                    cancel.store(true, Ordering::Relaxed);
                }
            }
            worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
    });
    if let (None, Some(callback), Some(p)) = (&failure, progress, latest) {
        // The final report (done == total), after the run.
        if let Err(e) = callback.call1(py, (p.pairs_done, p.pairs_total)) {
            failure = Some(e);
        }
    }
    (result, failure)
}
