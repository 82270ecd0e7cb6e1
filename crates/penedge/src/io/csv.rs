//! Tables as CSV: the block table (one row per block), the contact table (one row per
//! contact; docs/tables.md describes both) and the contact regions of bodies (concave
//! blocks: one row per region, [`write_body_contacts_to`]).
//!
//! Block table columns: `id, volume, centroid_x, centroid_y, centroid_z, n_faces,
//! n_free_faces` (`n_free_faces`: faces on the domain boundary or made by an excavation). Numbers are written
//! compactly ([`compact`]): the shortest digits that read back to the same `f64`, with an
//! exponent for the very small and the very large.

use super::{write_atomic, IoError};
use crate::block::{ConvexBlock, FaceOrigin};
use crate::classify::Feature;
use crate::contact::Detector;
use crate::system::{BlockSystem, BodyContacts, ContactGeometries, SystemContacts};
use crate::tolerance::Tolerance;
use glam::DVec3;
use std::io::Write;
use std::path::Path;

/// `x` in the shortest digits that read back to the same `f64`: plain for magnitudes from
/// 1e-4 to below 1e16 (`0.25`, `1250`), with an exponent otherwise (`5.551115123125783e-17`
/// rather than 34 digits of zeros); `0` for both zeros; `NaN`, `inf`, `-inf` as Rust writes
/// them.
pub fn compact(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let magnitude = x.abs();
    if !x.is_finite() || (1e-4..1e16).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The header line.
pub const HEADER: &str = "id,volume,centroid_x,centroid_y,centroid_z,n_faces,n_free_faces";

/// Writes the block table to `out`.
pub fn write_block_table_to(system: &BlockSystem, out: &mut dyn Write) -> std::io::Result<()> {
    super::check_finite_io(system)?;
    writeln!(out, "{HEADER}")?;
    for (id, b) in system.blocks().iter().enumerate() {
        let c = b.centroid();
        let free = super::n_free_faces(system, b);
        let n = b.n_faces();
        writeln!(
            out,
            "{id},{},{},{},{},{n},{free}",
            compact(b.volume()),
            compact(c.x),
            compact(c.y),
            compact(c.z)
        )?;
    }
    Ok(())
}

/// Writes the block table to a file, atomically.
pub fn write_block_table(system: &BlockSystem, path: &Path) -> Result<(), IoError> {
    super::check_finite(system)?;
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

/// The header of the contact table.
pub const CONTACT_HEADER: &str = "block_a,block_b,type,type_code,point_x,point_y,point_z,\
normal_x,normal_y,normal_z,distance,area,n_points,set_a,set_b,body_a,body_b";

/// Writes the contact table of `found` (with its `geometry`, found in `system` with `tol`)
/// to `out`: one row per contact, in the order of the contacts. `point_*` is the centroid of
/// the contact region (the point, the segment's midpoint, the polygon's area centroid);
/// a distance within the pair's rounding tolerance is written as 0 (the gap of the default
/// [`Tolerance`] for the two blocks, or the detection's gap when smaller: a larger gap asked
/// for to find near contacts leaves their true distances as they are);
/// `set_a`, `set_b` name where the faces of each block's contact feature come from;
/// `body_a`, `body_b` are the bodies of the two blocks ([`BlockSystem::body_of`]: a concave
/// block's convex parts share one; a convex block is a body of its own, whose id equals its
/// block id only in a system without concave or bridged blocks). The body
/// columns come last, after the columns of older versions, so that a reader of those
/// still reads the table.
pub fn write_contact_table_to(
    system: &BlockSystem,
    found: &SystemContacts,
    geometry: &ContactGeometries,
    tol: &Tolerance,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    writeln!(out, "{CONTACT_HEADER}")?;
    let (detector, rounding) = (Detector::new(*tol), Detector::new(Tolerance::default()));
    let blocks = system.blocks();
    for (i, pc) in found.contacts.iter().enumerate() {
        let [a, b] = pc.pair;
        let (block_a, block_b) = (&blocks[a as usize], &blocks[b as usize]);
        let kind = pc.contact.kind;
        let [nx, ny, nz] = geometry.normals[i].map(compact);
        let points = geometry.points_of(i);
        let [px, py, pz] = region_centroid(points, geometry.normals[i]).map(compact);
        let gap = detector
            .thresholds(block_a, block_b)
            .gap
            .min(rounding.thresholds(block_a, block_b).gap);
        let distance = geometry.distances[i];
        let distance = if distance.abs() <= gap { 0.0 } else { distance };
        writeln!(
            out,
            "{a},{b},{},{},{px},{py},{pz},{nx},{ny},{nz},{},{},{},{},{},{},{}",
            kind.name(),
            kind.code(),
            compact(distance),
            compact(geometry.areas[i]),
            points.len(),
            csv_field(&feature_sets(system, block_a, pc.contact.feature_a)),
            csv_field(&feature_sets(system, block_b, pc.contact.feature_b)),
            system.body_of(a),
            system.body_of(b),
        )?;
    }
    Ok(())
}

/// Writes the contact regions of bodies to a file, atomically.
pub fn write_body_contacts(found: &BodyContacts, path: &Path) -> Result<(), IoError> {
    write_atomic(path, |w| write_body_contacts_to(found, w))
}

/// Writes the contact table to a file, atomically ([`write_contact_table_to`]).
pub fn write_contact_table(
    system: &BlockSystem,
    found: &SystemContacts,
    geometry: &ContactGeometries,
    tol: &Tolerance,
    path: &Path,
) -> Result<(), IoError> {
    write_atomic(path, |w| {
        write_contact_table_to(system, found, geometry, tol, w)
    })
}

/// The centroid of a contact region: the point, the midpoint of a segment, the area centroid
/// of a convex polygon (triangles fanned from its first vertex, weighted by their areas
/// along `normal`).
pub fn region_centroid(points: &[[f64; 3]], normal: [f64; 3]) -> [f64; 3] {
    let p: Vec<DVec3> = points.iter().map(|&q| DVec3::from_array(q)).collect();
    let mean = || p.iter().sum::<DVec3>() / p.len().max(1) as f64;
    if p.len() < 3 {
        return mean().to_array();
    }
    let normal = DVec3::from_array(normal);
    let (mut weighted, mut total) = (DVec3::ZERO, 0.0);
    for k in 1..p.len() - 1 {
        let area = (p[k] - p[0]).cross(p[k + 1] - p[0]).dot(normal).abs();
        weighted += area * (p[0] + p[k] + p[k + 1]) / 3.0;
        total += area;
    }
    if total > 0.0 {
        (weighted / total).to_array()
    } else {
        mean().to_array()
    }
}

/// Where the faces at a feature come from, by name: the spec entry's name of a joint face,
/// `boundary` for a face of the domain's surface, nothing when unknown; the names of the
/// faces at an edge or vertex (each once, in face order) joined by `|`.
pub fn feature_sets(system: &BlockSystem, block: &ConvexBlock, feature: Feature) -> String {
    let mut names: Vec<String> = Vec::new();
    for f in feature_faces(block, feature) {
        let name = match block.face_origins()[f] {
            FaceOrigin::Joint { set, .. } => system
                .sets()
                .get(set as usize)
                .map_or_else(|| format!("set {set}"), |s| s.name.clone()),
            FaceOrigin::Bridge { set, .. } => system.sets().get(set as usize).map_or_else(
                || format!("bridge of set {set}"),
                |s| format!("bridge of {}", s.name),
            ),
            FaceOrigin::Boundary { .. } => "boundary".to_string(),
            FaceOrigin::Unknown => continue,
        };
        if !names.contains(&name) {
            names.push(name);
        }
    }
    names.join("|")
}

/// The faces at a feature: the face itself, an edge's two faces, a vertex's faces.
fn feature_faces(block: &ConvexBlock, feature: Feature) -> Vec<usize> {
    match feature {
        Feature::Face(f) => vec![f as usize],
        Feature::Edge(e) => block.edges()[e as usize].faces.map(|f| f as usize).to_vec(),
        Feature::Vertex(v) => (0..block.n_faces())
            .filter(|&f| block.face(f).contains(&v))
            .collect(),
    }
}

/// A CSV field: as it is, or quoted (with quotes doubled) when it holds a comma, a quote or
/// a line break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compact_and_read_back_exactly() {
        let cases = [
            (0.0, "0"),
            (-0.0, "0"),
            (1250.0, "1250"),
            (0.25, "0.25"),
            (-2f64.powi(-54), "-5.551115123125783e-17"),
            (1e-4, "0.0001"),
            (1e16, "1e16"),
            (0.1 + 0.2, "0.30000000000000004"),
        ];
        for (x, text) in cases {
            assert_eq!(compact(x), text);
            assert_eq!(text.parse::<f64>().unwrap(), x);
        }
    }

    #[test]
    fn region_centroids() {
        let up = [0.0, 0.0, 1.0];
        assert_eq!(region_centroid(&[[1.0, 2.0, 3.0]], up), [1.0, 2.0, 3.0]);
        assert_eq!(
            region_centroid(&[[0.0, 0.0, 0.0], [2.0, 4.0, 0.0]], up),
            [1.0, 2.0, 0.0]
        );
        // The trapezium (0,0), (4,0), (2,2), (0,2):
        // its area centroid, from the rectangle [0,2]^2 (area 4, centre (1,1)) and the
        // triangle (2,0), (4,0), (2,2) (area 2, centre (8/3, 2/3)): (14/9, 8/9).
        let trapezium = [
            [0.0, 0.0, 5.0],
            [4.0, 0.0, 5.0],
            [2.0, 2.0, 5.0],
            [0.0, 2.0, 5.0],
        ];
        let c = region_centroid(&trapezium, up);
        assert!((c[0] - 14.0 / 9.0).abs() < 1e-15 && (c[1] - 8.0 / 9.0).abs() < 1e-15);
        assert_eq!(c[2], 5.0);
    }

    /// The contact table of `system`, as rows of fields by column name.
    fn contact_rows(system: &BlockSystem) -> Vec<std::collections::HashMap<String, String>> {
        let tol = Tolerance::default();
        let (found, geometry) = system.detect_with_geometry(&tol);
        let mut out = Vec::new();
        write_contact_table_to(system, &found, &geometry, &tol, &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        // The columns of older versions first, in their order: the bodies come last.
        let older = "block_a,block_b,type,type_code,point_x,point_y,point_z,normal_x,normal_y,\
                     normal_z,distance,area,n_points,set_a,set_b";
        assert_eq!(header[..15].join(","), older);
        assert_eq!(header[15..], ["body_a", "body_b"]);
        let rows: Vec<_> = lines
            .map(|line| {
                let fields = line.split(',').map(str::to_string);
                header.iter().map(|h| h.to_string()).zip(fields).collect()
            })
            .collect();
        assert_eq!(rows.len(), found.contacts.len());
        rows
    }

    /// Each row's bodies are its blocks' bodies: for a U-block of three parts (body 0) with
    /// a block in its notch (body 1) the parts' rows give body 0, and in a system of convex
    /// blocks each block is its own body.
    #[test]
    fn the_contact_table_names_the_bodies_of_the_blocks() {
        let c = |lo, hi| ConvexBlock::cuboid(lo, hi).unwrap();
        let blocks = vec![
            c([0.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
            c([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            c([2.0, 0.0, 1.0], [3.0, 1.0, 2.0]),
            c([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
        ];
        let convex = BlockSystem::new(blocks.clone());
        let concave = convex
            .clone()
            .with_bodies(vec![0, 0, 0, 1], &Tolerance::default())
            .unwrap();
        for (system, touching) in [(convex, 5), (concave, 3)] {
            let rows = contact_rows(&system);
            assert_eq!(rows.len(), touching);
            for row in rows {
                for (block, body) in [("block_a", "body_a"), ("block_b", "body_b")] {
                    let block: u32 = row[block].parse().unwrap();
                    assert_eq!(row[body], system.body_of(block).to_string(), "{row:?}");
                }
            }
        }
    }

    #[test]
    fn quoted_fields() {
        assert_eq!(csv_field("J1"), "J1");
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }
}
