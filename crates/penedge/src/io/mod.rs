//! File formats: the generation spec (TOML or JSON), the block system (JSON, versioned),
//! ParaView files (blocks as VTU, contacts as VTP, time series as PVD) and the block
//! table (CSV).
//!
//! * [`spec`]: the generation spec;
//! * [`surface`]: topographic surfaces (grids of elevations, OBJ, STL);
//! * [`json`]: the block file (lossless);
//! * [`vtu`]: blocks as polyhedron cells, faces as polygon cells;
//! * [`vtp`]: contacts as vertex, line and polygon cells;
//! * [`pvd`]: PVD collections and [`pvd::TimeSeries`], blocks and contacts step after step;
//! * [`csv`]: the block table.
//!
//! Every file is written atomically: to a temporary file in the same folder, flushed to
//! disk, then renamed over the target, so a reader never sees a half-written file and a
//! failed write leaves the old file in place.

pub mod csv;
pub mod json;
mod messages;
pub mod pvd;
pub mod spec;
mod strict;
pub mod surface;
pub mod vtp;
pub mod vtu;

#[cfg(test)]
mod names_tests;

use crate::generation::SpecError;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use thiserror::Error;

/// Why a file could not be read or written.
#[derive(Debug, Error)]
pub enum IoError {
    /// The operating system refused (missing folder, no permission, disk full).
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: io::Error,
    },
    /// The file is not valid JSON, or not of the expected shape.
    #[error("{path}: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// What the parser said (with line and column).
        message: String,
    },
    /// The file parses but a field is wrong (a bad block, an unknown version).
    #[error("{field}: {message}")]
    Format {
        /// The field, as a path (`blocks[3].faces`).
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A generation spec file with a bad field.
    #[error("{0}")]
    Spec(#[from] SpecError),
}

impl IoError {
    pub(crate) fn io(path: &Path, source: io::Error) -> IoError {
        IoError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically through a buffered writer: temporary file, flush, sync, rename.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), IoError> {
    let name = path
        .file_name()
        .ok_or_else(|| IoError::io(path, io::Error::other("not a file name")))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = dir.join(format!(
        ".{}.{}-{unique}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = write_then_rename(&tmp, path, write);
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result.map_err(|source| IoError::io(path, source))
}

fn write_then_rename(
    tmp: &Path,
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let mut out = BufWriter::with_capacity(1 << 16, File::create(tmp)?);
    write(&mut out)?;
    let file = out.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()?;
    drop(file);
    fs::rename(tmp, path)
}

/// The most bytes read from a path that is not a regular file (256 MiB).
pub const MAX_STREAM_BYTES: u64 = 256 << 20;

/// Reads a whole text file.
///
/// A path that is not a regular file (a pipe, a device such as `/dev/zero`) is read up to
/// [`MAX_STREAM_BYTES`], so that an endless stream is an error, not a hang.
pub(crate) fn read_text(path: &Path) -> Result<String, IoError> {
    use std::io::Read;
    let failed = |source| IoError::io(path, source);
    let file = File::open(path).map_err(failed)?;
    let regular = file.metadata().map_err(failed)?.is_file();
    let limit = if regular { u64::MAX } else { MAX_STREAM_BYTES };
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(failed)?;
    if bytes.len() as u64 > limit {
        return Err(IoError::Syntax {
            path: path.to_path_buf(),
            message: format!(
                "not a regular file, and longer than {} MiB: an endless stream?",
                MAX_STREAM_BYTES >> 20
            ),
        });
    }
    String::from_utf8(bytes).map_err(|e| IoError::Syntax {
        path: path.to_path_buf(),
        message: format!(
            "not UTF-8 text (byte {} is not valid UTF-8; a binary file?)",
            e.utf8_error().valid_up_to()
        ),
    })
}

/// Refuses a system with a NaN or infinite coordinate (a block moved beyond the range of
/// double precision by an unchecked [`crate::ConvexBlock::transformed`]): JSON has no such
/// numbers (they were written as `null`, which the reader refuses) and the other formats
/// would write `inf` or `NaN`. The error names the block and the vertex.
pub(crate) fn check_finite(system: &crate::system::BlockSystem) -> Result<(), IoError> {
    let parts = [("domain", system.domain()), ("blocks", system.blocks())];
    for (name, blocks) in parts {
        for (i, b) in blocks.iter().enumerate() {
            let bad = |what: String| IoError::Format {
                field: format!("{name}[{i}]"),
                message: format!(
                    "{what} is NaN or infinite: a block beyond the range of double precision \
                     (moved too far?) cannot be written"
                ),
            };
            if let Some(v) = b.vertices().iter().position(|v| !v.is_finite()) {
                return Err(bad(format!("a coordinate of vertex {v}")));
            }
            if let Some(f) = b
                .planes()
                .iter()
                .position(|p| !(p.normal.is_finite() && p.point.is_finite()))
            {
                return Err(bad(format!("the plane of face {f}")));
            }
            if !(b.volume().is_finite() && b.centroid().is_finite()) {
                return Err(bad("the volume or centroid".into()));
            }
        }
    }
    Ok(())
}

/// [`check_finite`] as an I/O error, for the writers to a stream.
pub(crate) fn check_finite_io(system: &crate::system::BlockSystem) -> io::Result<()> {
    check_finite(system).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string()))
}

/// The free faces of a block of `system`: on the domain's boundary, or made by an
/// excavation (a joint origin of a spec entry of kind `excavation`), both the outside of the
/// rock mass. The `n_free_faces` of the block table and the ParaView file.
pub(crate) fn n_free_faces(
    system: &crate::system::BlockSystem,
    block: &crate::block::ConvexBlock,
) -> usize {
    use crate::block::FaceOrigin;
    use crate::generation::SetKind;
    let sets = system.sets();
    block
        .face_origins()
        .iter()
        .filter(|o| match **o {
            FaceOrigin::Boundary { .. } => true,
            FaceOrigin::Joint { set, .. } => sets
                .get(set as usize)
                .is_some_and(|r| r.kind == SetKind::Excavation),
            _ => false,
        })
        .count()
}
