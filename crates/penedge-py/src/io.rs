//! Files (core `io`): the block file (JSON), ParaView files (VTU blocks and faces, VTP
//! contacts) and tables (CSV of blocks, CSV of contacts).
//!
//! Every file is written atomically by the core (a temporary file in the same folder, then
//! renamed over the target), without the GIL. A file that cannot be read or written raises
//! the matching `OSError`; a block file that is not valid raises `FileFormatError`.

use crate::errors::{to_py_err, Error};
use crate::system::{BlockSystem, SystemContacts};
use penedge::io::{self, csv, json, vtp, vtu, IoError};
use penedge::system::{ContactGeometries, SystemContacts as CoreContacts};
use pyo3::prelude::*;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The Python exception of a core file error about `path`.
fn file_error(path: &Path) -> impl Fn(IoError) -> PyErr + '_ {
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
    #[staticmethod]
    fn read_json(py: Python<'_>, path: PathBuf) -> PyResult<BlockSystem> {
        py.detach(|| json::read_json(&path))
            .map(BlockSystem::wrap)
            .map_err(file_error(&path))
    }

    /// The JSON block file as a string.
    fn to_json(&self) -> String {
        json::to_json_string(&self.inner)
    }

    /// The system of a JSON block file's text (as :meth:`read_json`).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<BlockSystem> {
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
    /// ``block_id``, ``face``, ``origin`` 0 unknown / 1 boundary / 2 joint, ``origin_set``,
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
impl SystemContacts {
    /// Writes the contacts as a table (CSV), atomically: one row per contact, in the order of
    /// ``pairs``, with the columns ``block_a, block_b, type`` (name), ``type_code`` (1..7),
    /// ``normal_x, normal_y, normal_z, distance, area, n_points``.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     The contacts were found without ``geometry=True``.
    fn write_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let (found, geometry) = (&self.found, self.geometry()?);
        py.detach(|| io::write_atomic(&path, |w| write_contacts_csv_to(found, geometry, w)))
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

/// The header of the contacts table.
pub const CONTACTS_CSV_HEADER: &str =
    "block_a,block_b,type,type_code,normal_x,normal_y,normal_z,distance,area,n_points";

/// The contacts table, to any writer (numbers in the shortest form that reads back exactly).
pub fn write_contacts_csv_to(
    found: &CoreContacts,
    geometry: &ContactGeometries,
    w: &mut dyn Write,
) -> std::io::Result<()> {
    writeln!(w, "{CONTACTS_CSV_HEADER}")?;
    for (i, pc) in found.contacts.iter().enumerate() {
        let [a, b] = pc.pair;
        let kind = pc.contact.kind;
        let [nx, ny, nz] = geometry.normals[i];
        let n_points = geometry.points_of(i).len();
        writeln!(
            w,
            "{a},{b},{},{},{nx},{ny},{nz},{},{},{n_points}",
            kind.name(),
            kind.code(),
            geometry.distances[i],
            geometry.areas[i],
        )?;
    }
    Ok(())
}
