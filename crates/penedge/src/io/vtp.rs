//! Contacts as a ParaView file: a VTK XML PolyData file (`.vtp`, ASCII).
//!
//! Each contact is one cell: a point contact a vertex cell (`Verts`), a segment a line cell
//! (`Lines`), a polygon a polygon cell (`Polys`). VTK orders the cells of a PolyData file by
//! section, so the cells are all vertex cells, then all lines, then all polygons, each section
//! in contact order; the cell data array `contact` gives each cell's row in the contact
//! arrays (and in the contacts CSV). Cell data: `contact`, `type` (contact type code 1..7),
//! `block_a`, `block_b` (block ids, `block_a < block_b`), `area` (0 for points and
//! segments), `distance` (gap > 0, depth < 0) and `normal` (unit, from `block_a` to
//! `block_b`). The points are the contact points, contact after contact.

use super::{write_atomic, IoError};
use crate::system::{BodyContacts, ContactGeometries, SystemContacts};
use std::fmt::Display;
use std::io::{self, Write};
use std::path::Path;

/// The three cell sections of a PolyData file, in the order VTK numbers the cells.
const SECTIONS: [&str; 3] = ["Verts", "Lines", "Polys"];

/// The contacts of each section: one point, two points, three or more (in contact order).
fn sections(point_offsets: &[u64]) -> [Vec<usize>; 3] {
    let mut out = [Vec::new(), Vec::new(), Vec::new()];
    for (i, w) in point_offsets.windows(2).enumerate() {
        let n = (w[1] - w[0]).clamp(1, 3);
        out[n as usize - 1].push(i);
    }
    out
}

/// Writes the contacts and their geometry as a VTP file, atomically.
///
/// `geometry` must come with `found` ([`crate::BlockSystem::detect_with_geometry`]); a
/// geometry of another length is refused (`InvalidInput`) and nothing is written.
pub fn write_contacts_vtp(
    found: &SystemContacts,
    geometry: &ContactGeometries,
    path: &Path,
) -> Result<(), IoError> {
    check_lengths(found, geometry).map_err(|e| IoError::io(path, e))?;
    write_atomic(path, |w| write_contacts_vtp_to(found, geometry, w))
}

fn check_lengths(found: &SystemContacts, geometry: &ContactGeometries) -> io::Result<()> {
    if found.contacts.len() == geometry.len() && geometry.point_offsets.len() == geometry.len() + 1
    {
        return Ok(());
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "the geometry has {} rows for {} contacts",
            geometry.len(),
            found.contacts.len()
        ),
    ))
}

/// The VTP file, to any writer.
pub fn write_contacts_vtp_to(
    found: &SystemContacts,
    geometry: &ContactGeometries,
    w: &mut dyn Write,
) -> io::Result<()> {
    check_lengths(found, geometry)?;
    let data = |w: &mut dyn Write, order: &[usize]| cell_data(w, order, found, geometry);
    write_cells(w, &geometry.point_offsets, &geometry.points, data)
}

/// A PolyData file of cells (cell `i` has the points `points[point_offsets[i]..
/// point_offsets[i + 1]]`), with the cell data written by `data` for the cells in file order.
fn write_cells(
    w: &mut dyn Write,
    point_offsets: &[u64],
    points: &[[f64; 3]],
    data: impl FnOnce(&mut dyn Write, &[usize]) -> io::Result<()>,
) -> io::Result<()> {
    let sections = sections(point_offsets);
    header(w, points.len(), &sections)?;
    writeln!(w, "<Points>")?;
    data_array(w, "Float64", "Points", 3, points.iter().flatten())?;
    writeln!(w, "</Points>")?;
    for (name, cells) in SECTIONS.iter().zip(&sections) {
        cell_section(w, name, cells, point_offsets)?;
    }
    data(w, &sections.concat())?;
    writeln!(w, "</Piece>\n</PolyData>\n</VTKFile>")
}

/// The contact regions of bodies as a VTP file: one cell per piece (part contact), cells
/// in the order of [`write_contacts_vtp_to`]. Cell data: `contact` (the region's row in
/// [`BodyContacts::contacts`]), `body_a`, `body_b` (body ids, `body_a < body_b`), `region`
/// (the region's index within its pair of bodies), `type` (the region's type, by the bodies'
/// real features), `piece_type` (the part contact's own type), `block_a`, `block_b` (the
/// parts, `block_a` of `body_a`), `area` (the region's total area), `distance` and `normal`
/// (the region's). Colour by `region` to tell the regions of one pair apart.
pub fn write_body_contacts_vtp_to(found: &BodyContacts, w: &mut dyn Write) -> io::Result<()> {
    let mut region_of = Vec::with_capacity(found.pieces.len());
    for (i, o) in found.piece_offsets.windows(2).enumerate() {
        region_of.extend((o[0]..o[1]).map(|_| i));
    }
    let data = |w: &mut dyn Write, order: &[usize]| {
        let (c, p) = (&found.contacts, &found.pieces);
        let row = |k: &usize| region_of[*k];
        writeln!(w, "<CellData Scalars=\"type\" Normals=\"normal\">")?;
        data_array(w, "Int64", "contact", 1, order.iter().map(row))?;
        for (name, s) in [("body_a", 0), ("body_b", 1)] {
            data_array(
                w,
                "Int64",
                name,
                1,
                order.iter().map(|k| c[row(k)].bodies[s]),
            )?;
        }
        data_array(
            w,
            "Int64",
            "region",
            1,
            order.iter().map(|k| c[row(k)].region),
        )?;
        data_array(
            w,
            "Int8",
            "type",
            1,
            order.iter().map(|k| c[row(k)].kind.code()),
        )?;
        let piece_types = order.iter().map(|&k| p[k].contact.kind.code());
        data_array(w, "Int8", "piece_type", 1, piece_types)?;
        for (name, s) in [("block_a", 0), ("block_b", 1)] {
            data_array(w, "Int64", name, 1, order.iter().map(|&k| p[k].pair[s]))?;
        }
        data_array(
            w,
            "Float64",
            "area",
            1,
            order.iter().map(|k| c[row(k)].area),
        )?;
        let distances = order.iter().map(|k| c[row(k)].distance);
        data_array(w, "Float64", "distance", 1, distances)?;
        let normals = order.iter().flat_map(|k| c[row(k)].normal);
        data_array(w, "Float64", "normal", 3, normals)?;
        writeln!(w, "</CellData>")
    };
    write_cells(w, &found.piece_point_offsets, &found.piece_points, data)
}

/// Writes the contact regions of bodies as a VTP file, atomically
/// ([`write_body_contacts_vtp_to`]).
pub fn write_body_contacts_vtp(found: &BodyContacts, path: &Path) -> Result<(), IoError> {
    write_atomic(path, |w| write_body_contacts_vtp_to(found, w))
}

fn header(w: &mut dyn Write, n_points: usize, sections: &[Vec<usize>; 3]) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "<PolyData>")?;
    let [verts, lines, polys] = sections.each_ref().map(Vec::len);
    writeln!(
        w,
        "<Piece NumberOfPoints=\"{n_points}\" NumberOfVerts=\"{verts}\" NumberOfLines=\"{lines}\" \
         NumberOfStrips=\"0\" NumberOfPolys=\"{polys}\">"
    )
}

/// One cell section (`Verts`, `Lines` or `Polys`): connectivity into the point list and
/// the end offset of each cell. Left out when it has no cell.
fn cell_section(
    w: &mut dyn Write,
    name: &str,
    cells: &[usize],
    point_offsets: &[u64],
) -> io::Result<()> {
    if cells.is_empty() {
        return Ok(());
    }
    let range = |i: usize| point_offsets[i]..point_offsets[i + 1];
    let connectivity = cells.iter().flat_map(|&i| range(i));
    let mut end = 0;
    let offsets = cells.iter().map(|&i| {
        end += range(i).end - range(i).start;
        end
    });
    writeln!(w, "<{name}>")?;
    data_array(w, "Int64", "connectivity", 1, connectivity)?;
    data_array(w, "Int64", "offsets", 1, offsets)?;
    writeln!(w, "</{name}>")
}

/// The cell data, cells in file order (`order[k]` is the contact of cell `k`).
fn cell_data(
    w: &mut dyn Write,
    order: &[usize],
    found: &SystemContacts,
    geometry: &ContactGeometries,
) -> io::Result<()> {
    let c = &found.contacts;
    writeln!(w, "<CellData Scalars=\"type\" Normals=\"normal\">")?;
    data_array(w, "Int64", "contact", 1, order.iter())?;
    let codes = order.iter().map(|&i| c[i].contact.kind.code());
    data_array(w, "Int8", "type", 1, codes)?;
    data_array(
        w,
        "Int64",
        "block_a",
        1,
        order.iter().map(|&i| c[i].pair[0]),
    )?;
    data_array(
        w,
        "Int64",
        "block_b",
        1,
        order.iter().map(|&i| c[i].pair[1]),
    )?;
    data_array(
        w,
        "Float64",
        "area",
        1,
        order.iter().map(|&i| geometry.areas[i]),
    )?;
    let distances = order.iter().map(|&i| geometry.distances[i]);
    data_array(w, "Float64", "distance", 1, distances)?;
    let normals = order.iter().flat_map(|&i| geometry.normals[i]);
    data_array(w, "Float64", "normal", 3, normals)?;
    writeln!(w, "</CellData>")
}

/// One `DataArray`, ten values a line.
fn data_array<T: Display>(
    w: &mut dyn Write,
    kind: &str,
    name: &str,
    components: usize,
    values: impl IntoIterator<Item = T>,
) -> io::Result<()> {
    write!(w, "<DataArray type=\"{kind}\" Name=\"{name}\"")?;
    if components > 1 {
        write!(w, " NumberOfComponents=\"{components}\"")?;
    }
    writeln!(w, " format=\"ascii\">")?;
    for (k, v) in values.into_iter().enumerate() {
        let sep = if k % 10 == 9 { "\n" } else { " " };
        write!(w, "{v}{sep}")?;
    }
    writeln!(w, "\n</DataArray>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{paper_example, PaperExample};
    use crate::{BlockSystem, ConvexBlock, Tolerance};

    fn text(system: &BlockSystem) -> String {
        let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
        let mut out = Vec::new();
        write_contacts_vtp_to(&found, &geometry, &mut out).unwrap();
        String::from_utf8(out).unwrap()
    }

    /// The whitespace-separated values of every `DataArray` named `name`, one after another.
    fn values(text: &str, name: &str) -> Vec<String> {
        let tag = format!("Name=\"{name}\"");
        let mut out = Vec::new();
        for (start, _) in text.match_indices(&tag) {
            let body = &text[start..];
            let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
            out.extend(body.split_whitespace().map(str::to_string));
        }
        out
    }

    #[test]
    fn cells_come_by_section_and_name_their_contact() {
        let cube = |lo: [f64; 3], hi: [f64; 3]| ConvexBlock::cuboid(lo, hi).unwrap();
        let system = BlockSystem::new(vec![
            cube([0.0; 3], [1.0; 3]),
            cube([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]), // 0-1 face-face
            cube([1.0, 1.0, 1.0], [2.0, 2.0, 2.0]), // 0-2 vertex-vertex, 1-2 edge-edge sup.
        ]);
        let t = text(&system);
        assert!(t.contains(
            "NumberOfPoints=\"7\" NumberOfVerts=\"1\" NumberOfLines=\"1\" NumberOfStrips=\"0\" \
             NumberOfPolys=\"1\""
        ));
        assert_eq!(values(&t, "contact"), ["1", "2", "0"]);
        assert_eq!(values(&t, "type"), ["1", "4", "7"]);
        assert_eq!(values(&t, "block_a"), ["0", "1", "0"]);
        assert_eq!(values(&t, "block_b"), ["2", "2", "1"]);
        assert_eq!(
            values(&t, "connectivity"),
            ["4", "5", "6", "0", "1", "2", "3"]
        );
        assert_eq!(values(&t, "offsets"), ["1", "2", "4"]);
        assert_eq!(values(&t, "normal").len(), 9);
        assert_eq!(values(&t, "Points").len(), 21);
    }

    #[test]
    fn empty_sections_are_left_out() {
        let t = text(&paper_example(PaperExample::One).unwrap());
        assert!(t.contains("NumberOfVerts=\"4\" NumberOfLines=\"12\""));
        assert!(t.contains("NumberOfPolys=\"12\""));
        let none = text(&BlockSystem::default());
        assert!(none.contains("NumberOfPoints=\"0\" NumberOfVerts=\"0\""));
        assert!(!none.contains("<Verts>") && !none.contains("<Polys>"));
    }

    #[test]
    fn a_geometry_of_another_system_is_refused_and_nothing_written() {
        let system = paper_example(PaperExample::One).unwrap();
        let (found, _) = system.detect_with_geometry(&Tolerance::default());
        let path = std::env::temp_dir().join(format!("penedge-vtp-{}.vtp", std::process::id()));
        let err = write_contacts_vtp(&found, &ContactGeometries::default(), &path).unwrap_err();
        assert!(err
            .to_string()
            .contains("the geometry has 0 rows for 28 contacts"));
        assert!(!path.exists());
    }
}
