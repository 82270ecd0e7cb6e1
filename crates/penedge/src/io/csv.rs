//! The block table as CSV: one row per block.
//!
//! Columns: `id, volume, centroid_x, centroid_y, centroid_z, n_faces, n_free_faces`
//! (`n_free_faces`: faces on the domain boundary). Numbers are written in the shortest form
//! that reads back to the same `f64`.

use super::{write_atomic, IoError};
use crate::system::BlockSystem;
use std::io::Write;
use std::path::Path;

/// The header line.
pub const HEADER: &str = "id,volume,centroid_x,centroid_y,centroid_z,n_faces,n_free_faces";

/// Writes the block table to `out`.
pub fn write_block_table_to(system: &BlockSystem, out: &mut dyn Write) -> std::io::Result<()> {
    writeln!(out, "{HEADER}")?;
    for (id, b) in system.blocks().iter().enumerate() {
        let c = b.centroid();
        let free = b.face_origins().iter().filter(|o| o.is_boundary()).count();
        let n = b.n_faces();
        writeln!(
            out,
            "{id},{},{},{},{},{n},{free}",
            b.volume(),
            c.x,
            c.y,
            c.z
        )?;
    }
    Ok(())
}

/// Writes the block table to a file, atomically.
pub fn write_block_table(system: &BlockSystem, path: &Path) -> Result<(), IoError> {
    write_atomic(path, |w| write_block_table_to(system, w))
}
