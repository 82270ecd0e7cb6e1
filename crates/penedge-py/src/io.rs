//! Files (core `io`): the block file (JSON), ParaView files (VTU blocks and faces, VTP
//! contacts, PVD time series: [`TimeSeries`], [`write_pvd`]) and tables (CSV of blocks, CSV
//! of contacts).
//!
//! Every file is written atomically by the core (a temporary file in the same folder, then
//! renamed over the target), without the GIL. A file that cannot be read or written raises
//! the matching `OSError`; a block file that is not valid raises `FileFormatError`.

use crate::arrays;
use crate::errors::{input_error, to_py_err, Error};
use crate::system::{BlockSystem, BodyContacts, SystemContacts};
use numpy::PyArray1;
use penedge::io::pvd::{self, PvdEntry, SeriesError};
use penedge::io::{csv, json, vtp, vtu, IoError};
use pyo3::exceptions::PyFileExistsError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// Runs `work` on a thread of its own while this one, without the GIL, checks Python's
/// signal handlers every 0.1 s: Ctrl-C raises `KeyboardInterrupt` at once, and the work,
/// which has no effect but its result, is left to finish unseen (or to end with the
/// process).
fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(work()));
    py.detach(move || loop {
        match receive.recv_timeout(std::time::Duration::from_millis(100)) {
            Ok(result) => return Ok(result),
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                Python::attach(|py| py.check_signals())?;
            }
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                let message = "the thread reading the file ended without a result";
                return Err(pyo3::exceptions::PyRuntimeError::new_err(message));
            }
        }
    })
}

/// The Python exception of a core file error about `path`.
pub(crate) fn file_error(path: &Path) -> impl Fn(IoError) -> PyErr + '_ {
    move |e| to_py_err(Error::from(e).in_file(path))
}

#[pymethods]
impl BlockSystem {
    /// Writes the system as a JSON block file (``docs/block-file-format.md``), atomically.
    ///
    /// The file keeps everything: blocks, face origins, domain, joint table and spec entries,
    /// bit for bit (:meth:`read_json` gives the same system back).
    ///
    /// Parameters
    /// ----------
    /// path : str or os.PathLike
    fn write_json(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| json::write_json(inner, &path))
            .map_err(file_error(&path))
    }

    /// Reads a JSON block file written by :meth:`write_json` (or ``penedge generate``).
    ///
    /// Parameters
    /// ----------
    /// path : str or os.PathLike
    ///
    /// Returns
    /// -------
    /// BlockSystem
    ///
    /// Raises
    /// ------
    /// FileFormatError
    ///     Not JSON, not a block file of a known version, or a field that is wrong (an invalid
    ///     block: `field` names it).
    /// OSError
    ///     The file cannot be read (``FileNotFoundError``, ...).
    /// KeyboardInterrupt
    ///     Ctrl-C while the file is read: raised at once (within 0.1 s), without waiting for
    ///     the file to be read (a large one takes a second or more, a pipe forever).
    #[staticmethod]
    fn read_json(py: Python<'_>, path: PathBuf) -> PyResult<BlockSystem> {
        let file = path.clone();
        interruptible(py, move || json::read_json(&file))?
            .map(BlockSystem::wrap)
            .map_err(file_error(&path))
    }

    /// The JSON block file as a string.
    fn to_json(&self) -> String {
        json::to_json_string(&self.inner)
    }

    /// The system of a JSON block file's text (as :meth:`read_json`).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &Bound<'_, PyAny>) -> PyResult<BlockSystem> {
        let text = text
            .cast::<pyo3::types::PyString>()
            .map_err(|e| pyo3::exceptions::PyTypeError::new_err(format!("text: {e}")))?
            .to_str()
            .map_err(|e| input_error("text", format!("text is not valid Unicode: {e}")))?;
        py.detach(|| json::from_json_str(text))
            .map(BlockSystem::wrap)
            .map_err(to_py_err)
    }

    /// Writes the blocks as a ParaView file (VTU, one polyhedron cell per block; cell data
    /// ``block_id``, ``volume``, ``n_faces``, ``n_free_faces``), atomically.
    fn write_vtu(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| vtu::write_vtu(inner, &path))
            .map_err(file_error(&path))
    }

    /// Writes the block faces as a ParaView file (VTU, one polygon cell per face; cell data
    /// ``block_id``, ``face``, ``origin`` 0 unknown / 1 boundary / 2 joint / 3 bridge, ``origin_set``,
    /// ``origin_index``), atomically. Colour by ``origin_set`` to see the joint sets.
    fn write_faces_vtu(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| vtu::write_faces_vtu(inner, &path))
            .map_err(file_error(&path))
    }

    /// Writes the block table (CSV: ``id, volume, centroid_x, centroid_y, centroid_z,
    /// n_faces, n_free_faces``), atomically.
    fn write_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| csv::write_block_table(inner, &path))
            .map_err(file_error(&path))
    }
}

#[pymethods]
impl BodyContacts {
    /// Writes the contact regions as a table (CSV), atomically: one row per region, with the
    /// columns ``body_a, body_b, region, type`` (name), ``area, distance, normal_x, normal_y,
    /// normal_z, pieces`` (its number of part contacts).
    fn write_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let found = &self.found;
        py.detach(|| csv::write_body_contacts(found, &path))
            .map_err(file_error(&path))
    }

    /// Writes the contact regions as a ParaView file (VTP), atomically: one cell per part
    /// contact, with cell data ``contact`` (the region's row), ``body_a``, ``body_b``,
    /// ``region``, ``type`` (the region's), ``piece_type``, ``block_a``, ``block_b``,
    /// ``area``, ``distance``, ``normal``.
    fn write_vtp(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let found = &self.found;
        py.detach(|| vtp::write_body_contacts_vtp(found, &path))
            .map_err(file_error(&path))
    }
}

#[pymethods]
impl SystemContacts {
    /// Writes the contacts as a table (CSV), atomically: one row per contact, in the order of
    /// ``pairs``, with the columns ``block_a, block_b, type`` (name), ``type_code`` (1..7),
    /// ``point_x, point_y, point_z`` (the centroid of the contact region: the point, the
    /// segment's midpoint, the polygon's area centroid), ``normal_x, normal_y, normal_z,
    /// distance`` (0 within the pair's rounding tolerance), ``area, n_points`` and ``set_a,
    /// set_b``: where the faces of each block's contact feature come from (the spec entry's
    /// name of a joint, ``boundary`` for the domain's surface; the names of an edge's or a
    /// vertex's faces joined by ``|``; empty when unknown), then ``body_a, body_b``: the
    /// bodies of the two blocks (:attr:`BlockSystem.body_ids`; a concave block's convex
    /// parts share one; a convex block is a body of its own, whose id equals its block id only
    /// in a system without concave blocks). Numbers in the shortest form
    /// that reads back exactly, with an exponent below 1e-4 and from 1e16. See
    /// ``docs/tables.md``.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     The contacts were found without ``geometry=True``.
    fn write_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let (found, geometry) = (&self.found, self.geometry()?);
        let Some((system, tol)) = &self.source else {
            let msg = "the contact table needs contacts found by BlockSystem.detect";
            return Err(input_error("no_system", msg));
        };
        let system = &system.get().inner;
        py.detach(|| csv::write_contact_table(system, found, geometry, tol, &path))
            .map_err(file_error(&path))
    }

    /// Writes the contacts as a ParaView file (VTP), atomically: point contacts as vertex
    /// cells, segments as lines, polygons as polygons; cell data ``contact`` (row in
    /// ``pairs``), ``type``, ``block_a``, ``block_b``, ``area``, ``distance``, ``normal``.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     The contacts were found without ``geometry=True``.
    fn write_vtp(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let (found, geometry) = (&self.found, self.geometry()?);
        py.detach(|| vtp::write_contacts_vtp(found, geometry, &path))
            .map_err(file_error(&path))
    }
}

/// The Python exception of a time-series error: `InputError` (kind ``time``, ``file_name``
/// or ``mismatch``), `OSError` or `FileFormatError`.
fn series_error(e: SeriesError) -> PyErr {
    match e {
        SeriesError::Time(m) => input_error("time", m),
        SeriesError::FileName(m) => input_error("file_name", m),
        SeriesError::Mismatch(m) => input_error("mismatch", m),
        SeriesError::Io(e) => to_py_err(e),
    }
}

/// The Python exception of a series that cannot be started or resumed: a folder that holds
/// a series already is a `FileExistsError` (errno ``EEXIST``, with the core's message).
fn open_error(py: Python<'_>, e: IoError) -> PyErr {
    if let IoError::Io { path, source } = &e {
        if source.kind() == std::io::ErrorKind::AlreadyExists && source.raw_os_error().is_none() {
            let errno = py
                .import("errno")
                .and_then(|m| m.getattr("EEXIST"))
                .and_then(|v| v.extract::<i32>());
            return match errno {
                Ok(errno) => PyFileExistsError::new_err((
                    errno,
                    source.to_string(),
                    path.to_string_lossy().into_owned(),
                )),
                Err(err) => err,
            };
        }
    }
    to_py_err(Error::from(e))
}

/// Writes a ParaView collection (PVD) that lists one dataset file per time step,
/// atomically.
///
/// ParaView opens the ``.pvd`` as one source with a time slider. For blocks and contacts
/// written step after step, :class:`TimeSeries` writes the files and the index together.
///
/// Parameters
/// ----------
/// path : str or os.PathLike
///     The ``.pvd`` file.
/// datasets : sequence of (float, str or os.PathLike)
///     ``(time, file)`` of each step: times finite and strictly increasing, files relative
///     to the folder of `path` (as ParaView reads them) or absolute.
///
/// Raises
/// ------
/// InputError
///     A time that is not finite or not after the one before (``kind == "time"``), or an
///     empty file name (``"file_name"``); nothing is written.
/// OSError
///     The file cannot be written.
///
/// Examples
/// --------
/// >>> import pathlib, shutil, tempfile
/// >>> import penedge
/// >>> folder = pathlib.Path(tempfile.mkdtemp())
/// >>> system = penedge.paper_example(1)
/// >>> for step in (0, 1):  # a simulation would move the blocks in between
/// ...     system.write_vtu(folder / f"step{step}.vtu")
/// >>> penedge.write_pvd(folder / "steps.pvd", [(0.0, "step0.vtu"), (0.5, "step1.vtu")])
/// >>> print((folder / "steps.pvd").read_text().splitlines()[3])
/// <DataSet timestep="0.0" group="" part="0" file="step0.vtu"/>
/// >>> shutil.rmtree(folder)
#[pyfunction]
pub fn write_pvd(
    py: Python<'_>,
    path: PathBuf,
    datasets: Vec<(crate::arrays::Real, PathBuf)>,
) -> PyResult<()> {
    let mut entries = Vec::with_capacity(datasets.len());
    for (k, (time, file)) in datasets.into_iter().enumerate() {
        let time = time.get(&format!("the time of dataset {k}"))?;
        let file = file.into_os_string().into_string().map_err(|f| {
            input_error(
                "file_name",
                format!("dataset {k}: the file name {f:?} is not valid UTF-8"),
            )
        })?;
        entries.push(PvdEntry { time, file });
    }
    py.detach(|| pvd::write_pvd(&path, &entries))
        .map_err(series_error)
}

/// Blocks and contacts step after step, as a ParaView time series in one folder.
///
/// Each :meth:`write_step` writes the blocks as ``blocks_NNNNNN.vtu`` (as
/// :meth:`BlockSystem.write_vtu`) and, when given, the contacts as ``contacts_NNNNNN.vtp``
/// (as :meth:`SystemContacts.write_vtp`), then rewrites the two indexes ``blocks.pvd`` and
/// ``contacts.pvd``. Open them in ParaView (File > Open) to play the steps with the time
/// slider.
///
/// Every file is written atomically, and a step's files before the indexes that list them:
/// ParaView, with the series open while a simulation runs, sees complete steps only; a run
/// that stops leaves a series that ``TimeSeries(folder, resume=True)`` continues.
///
/// Parameters
/// ----------
/// folder : str or os.PathLike
///     Made if missing (with its parents).
/// resume : bool, default False
///     Continue the series already in `folder` after its last step (the files of a step
///     that never reached the index are replaced). Without `resume`, a folder that holds a
///     series is refused.
///
/// Raises
/// ------
/// FileExistsError
///     `folder` already holds a series and `resume` is False.
/// FileNotFoundError
///     `resume` and there is no ``blocks.pvd`` in `folder`.
/// FileFormatError
///     `resume` and an index is not a collection, or its times do not increase.
///
/// Examples
/// --------
/// >>> import pathlib, shutil, tempfile
/// >>> import penedge
/// >>> folder = pathlib.Path(tempfile.mkdtemp())
/// >>> series = penedge.TimeSeries(folder / "series")
/// >>> system = penedge.paper_example(1)
/// >>> for time in (0.0, 0.1, 0.2):  # a simulation would move the blocks in between
/// ...     step = series.write_step(time, system, system.detect(geometry=True))
/// >>> step, len(series), series.times
/// (2, 3, array([0. , 0.1, 0.2]))
/// >>> sorted(p.name for p in series.folder.iterdir())[:4]
/// ['blocks.pvd', 'blocks_000000.vtu', 'blocks_000001.vtu', 'blocks_000002.vtu']
/// >>> penedge.TimeSeries(folder / "series", resume=True).write_step(0.3, system)
/// 3
/// >>> shutil.rmtree(folder)
#[pyclass(module = "penedge", name = "TimeSeries")]
pub struct TimeSeries {
    inner: pvd::TimeSeries,
}

#[pymethods]
impl TimeSeries {
    #[new]
    #[pyo3(signature = (folder, resume = false))]
    fn new(py: Python<'_>, folder: PathBuf, resume: bool) -> PyResult<Self> {
        let made = py.detach(|| {
            if resume {
                pvd::TimeSeries::open(&folder)
            } else {
                pvd::TimeSeries::create(&folder)
            }
        });
        made.map(|inner| TimeSeries { inner })
            .map_err(|e| open_error(py, e))
    }

    /// Writes one step: the blocks, and the contacts when given; returns the step number
    /// (0, 1, 2, ...: the ``NNNNNN`` of the file names).
    ///
    /// Parameters
    /// ----------
    /// time : float
    ///     Finite, after the previous step's time.
    /// system : BlockSystem
    /// contacts : SystemContacts, optional
    ///     The contacts of `system`, found with ``detect(geometry=True)``. Steps without
    ///     contacts are left out of ``contacts.pvd``.
    ///
    /// Returns
    /// -------
    /// int
    ///
    /// Raises
    /// ------
    /// InputError
    ///     A time that is not finite or not after the last step (``kind == "time"``),
    ///     contacts found without ``geometry=True`` (``"no_geometry"``) or naming a block
    ///     `system` does not have (``"mismatch"``); nothing is written.
    /// OSError
    ///     A file cannot be written (the step is not added to the series).
    #[pyo3(signature = (time, system, contacts = None))]
    fn write_step(
        &mut self,
        py: Python<'_>,
        time: crate::arrays::Real,
        system: PyRef<'_, BlockSystem>,
        contacts: Option<PyRef<'_, SystemContacts>>,
    ) -> PyResult<usize> {
        let time = time.get("time")?;
        let contacts = match &contacts {
            Some(c) => Some((&c.found, c.geometry()?)),
            None => None,
        };
        let (inner, system) = (&mut self.inner, &system.inner);
        py.detach(|| inner.write_step(time, system, contacts))
            .map_err(series_error)
    }

    /// The series' folder.
    #[getter]
    fn folder(&self) -> PathBuf {
        self.inner.folder().to_path_buf()
    }

    /// The index of the block files, ``folder / "blocks.pvd"``.
    #[getter]
    fn blocks_index(&self) -> PathBuf {
        self.inner.blocks_index()
    }

    /// The index of the contact files, ``folder / "contacts.pvd"``.
    #[getter]
    fn contacts_index(&self) -> PathBuf {
        self.inner.contacts_index()
    }

    /// The time of each step (float64, increasing).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let times = self.inner.blocks().iter().map(|e| e.time).collect();
        arrays::read_only(arrays::vector(py, times))
    }

    /// The time of each step written with contacts (float64, increasing).
    #[getter]
    fn contact_times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let times = self.inner.contacts().iter().map(|e| e.time).collect();
        arrays::read_only(arrays::vector(py, times))
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "TimeSeries({:?}, {})",
            self.inner.folder().display().to_string(),
            crate::counted(self.inner.len(), "step", "steps")
        )
    }
}
