//! The block table as CSV: one row per block; the contact regions of bodies (concave
//! blocks) as CSV: one row per region ([`write_body_contacts_to`]).
//!
//! Columns: `id, volume, centroid_x, centroid_y, centroid_z, n_faces, n_free_faces`
//! (`n_free_faces`: faces on the domain boundary). Numbers are written in the shortest form
//! that reads back to the same `f64`.

use super::{write_atomic, IoError};
use crate::system::{BlockSystem, BodyContacts};
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

/// The header line of the contact regions of bodies.
pub const BODY_CONTACTS_HEADER: &str =
    "body_a,body_b,region,type,area,distance,normal_x,normal_y,normal_z,pieces";

/// Writes the contact regions of bodies ([`crate::BlockSystem::detect_bodies`]) to `out`,
/// one row per region: the two bodies (`body_a < body_b`), the region's index within the
/// pair (two bodies can touch in several regions), its type by name, total area, distance,
/// normal (from `body_a` to `body_b`) and its number of part contacts.
pub fn write_body_contacts_to(found: &BodyContacts, out: &mut dyn Write) -> std::io::Result<()> {
    writeln!(out, "{BODY_CONTACTS_HEADER}")?;
    for (i, c) in found.contacts.iter().enumerate() {
        let [a, b] = c.bodies;
        let [x, y, z] = c.normal;
        let pieces = found.piece_offsets[i + 1] - found.piece_offsets[i];
        writeln!(
            out,
            "{a},{b},{},{},{},{},{x},{y},{z},{pieces}",
            c.region, c.kind, c.area, c.distance
        )?;
    }
    Ok(())
}

/// Writes the contact regions of bodies to a file, atomically.
pub fn write_body_contacts(found: &BodyContacts, path: &Path) -> Result<(), IoError> {
    write_atomic(path, |w| write_body_contacts_to(found, w))
}
