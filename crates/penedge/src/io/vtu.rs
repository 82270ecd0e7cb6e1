//! ParaView files: VTK XML unstructured grids (`.vtu`, ASCII).
//!
//! * [`write_vtu`]: one polyhedron cell (VTK type 42) per block (a convex part), with cell
//!   data `block_id`, `body_id` (the concave block it is a part of: colour by it to see each
//!   concave block in one colour), `volume`, `n_faces` and `n_free_faces` (faces on the
//!   domain boundary or made by an excavation: the outside of the rock mass);
//! * [`write_faces_vtu`]: one polygon cell (VTK type 7) per block face, with cell data
//!   `block_id`, `body_id`, `face`, `internal` (1 for a face inside its concave block, glued
//!   to other parts: threshold it away to draw concave blocks without their internal faces),
//!   `origin` (0 unknown, 1 domain boundary, 2 joint, 3 bridge), `origin_set`
//!   (domain part, or spec entry of the joint) and `origin_index` (boundary face, or joint
//!   id): colour by `origin` to see free faces, by `origin_set` to see joint sets.
//!
//! Blocks do not share points (each block lists its own vertices), so blocks can be shrunk
//! or exploded independently in ParaView.

use super::{write_atomic, IoError};
use crate::block::ConvexBlock;
use crate::system::BlockSystem;
use std::io::{self, Write};
use std::path::Path;

const POLYHEDRON: u8 = 42;
const POLYGON: u8 = 7;

/// Writes the blocks as polyhedron cells, atomically.
pub fn write_vtu(system: &BlockSystem, path: &Path) -> Result<(), IoError> {
    super::check_finite(system)?;
    write_atomic(path, |w| write_blocks_to(system, w))
}

/// Writes the block faces as polygon cells with their origins, atomically.
pub fn write_faces_vtu(system: &BlockSystem, path: &Path) -> Result<(), IoError> {
    super::check_finite(system)?;
    write_atomic(path, |w| write_faces_to(system, w))
}

/// The polyhedron file, to any writer.
pub fn write_blocks_to(system: &BlockSystem, w: &mut dyn Write) -> io::Result<()> {
    super::check_finite_io(system)?;
    let blocks = system.blocks();
    let n_points: usize = blocks.iter().map(|b| b.vertices().len()).sum();
    header(w, n_points, blocks.len())?;
    points(w, blocks)?;
    writeln!(w, "<Cells>")?;
    polyhedron_cells(w, blocks)?;
    polyhedron_faces(w, blocks)?;
    writeln!(w, "</Cells>\n<CellData Scalars=\"block_id\">")?;
    array(w, "Int64", "block_id", 0..blocks.len())?;
    array(w, "Int64", "body_id", system.body_ids())?;
    array(
        w,
        "Float64",
        "volume",
        blocks.iter().map(ConvexBlock::volume),
    )?;
    array(
        w,
        "Int32",
        "n_faces",
        blocks.iter().map(ConvexBlock::n_faces),
    )?;
    let free = |b: &ConvexBlock| super::n_free_faces(system, b);
    array(w, "Int32", "n_free_faces", blocks.iter().map(free))?;
    writeln!(w, "</CellData>")?;
    footer(w)
}

/// Connectivity (each block's own points), offsets and cell types of the polyhedra.
fn polyhedron_cells(w: &mut dyn Write, blocks: &[ConvexBlock]) -> io::Result<()> {
    let n_points: usize = blocks.iter().map(|b| b.vertices().len()).sum();
    array(w, "Int64", "connectivity", 0..n_points)?;
    let mut end = 0;
    let ends = blocks.iter().map(|b| {
        end += b.vertices().len();
        end
    });
    array(w, "Int64", "offsets", ends)?;
    array(w, "UInt8", "types", blocks.iter().map(|_| POLYHEDRON))
}

/// The `faces` stream of each polyhedron (`n_faces, n, ids..., n, ids...`, point ids
/// global) and the end offset of each cell's stream.
fn polyhedron_faces(w: &mut dyn Write, blocks: &[ConvexBlock]) -> io::Result<()> {
    let mut stream = Vec::new();
    let mut ends = Vec::with_capacity(blocks.len());
    let mut first = 0u64;
    for b in blocks {
        stream.push(b.n_faces() as u64);
        for face in b.faces() {
            stream.push(face.len() as u64);
            stream.extend(face.iter().map(|&v| first + v as u64));
        }
        ends.push(stream.len());
        first += b.vertices().len() as u64;
    }
    array(w, "Int64", "faces", stream)?;
    array(w, "Int64", "faceoffsets", ends)
}

/// The faces file, to any writer.
pub fn write_faces_to(system: &BlockSystem, w: &mut dyn Write) -> io::Result<()> {
    super::check_finite_io(system)?;
    let blocks = system.blocks();
    let n_points: usize = blocks.iter().map(|b| b.vertices().len()).sum();
    let n_faces: usize = blocks.iter().map(ConvexBlock::n_faces).sum();
    header(w, n_points, n_faces)?;
    points(w, blocks)?;
    writeln!(w, "<Cells>")?;
    let mut first = 0u64;
    let mut connectivity = Vec::new();
    let mut offsets = Vec::with_capacity(n_faces);
    for b in blocks {
        for face in b.faces() {
            connectivity.extend(face.iter().map(|&v| first + v as u64));
            offsets.push(connectivity.len());
        }
        first += b.vertices().len() as u64;
    }
    array(w, "Int64", "connectivity", connectivity)?;
    array(w, "Int64", "offsets", offsets)?;
    array(w, "UInt8", "types", (0..n_faces).map(|_| POLYGON))?;
    writeln!(w, "</Cells>\n<CellData Scalars=\"origin\">")?;
    face_data(w, system)?;
    writeln!(w, "</CellData>")?;
    footer(w)
}

fn face_data(w: &mut dyn Write, system: &BlockSystem) -> io::Result<()> {
    let blocks = system.blocks();
    let per_face = || {
        blocks.iter().enumerate().flat_map(|(id, b)| {
            b.face_origins()
                .iter()
                .enumerate()
                .map(move |(f, o)| (id, f, *o))
        })
    };
    array(w, "Int64", "block_id", per_face().map(|(id, _, _)| id))?;
    let bodies = system.body_ids();
    array(
        w,
        "Int64",
        "body_id",
        per_face().map(|(id, _, _)| bodies[id]),
    )?;
    array(w, "Int32", "face", per_face().map(|(_, f, _)| f))?;
    let internal = |(id, f, _): (usize, usize, _)| system.is_internal_face(id as u32, f as u32);
    array(
        w,
        "UInt8",
        "internal",
        per_face().map(|x| internal(x) as u8),
    )?;
    array(w, "Int32", "origin", per_face().map(|(_, _, o)| o.code()))?;
    array(
        w,
        "Int64",
        "origin_set",
        per_face().map(|(_, _, o)| o.ids().0),
    )?;
    array(
        w,
        "Int64",
        "origin_index",
        per_face().map(|(_, _, o)| o.ids().1),
    )
}

fn header(w: &mut dyn Write, n_points: usize, n_cells: usize) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    writeln!(
        w,
        "<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
    )
}

fn points(w: &mut dyn Write, blocks: &[ConvexBlock]) -> io::Result<()> {
    writeln!(w, "<Points>")?;
    let coords = blocks
        .iter()
        .flat_map(|b| b.vertices().iter().flat_map(|v| v.to_array()));
    write_array(w, "Float64", "Points", " NumberOfComponents=\"3\"", coords)?;
    writeln!(w, "</Points>")
}

fn footer(w: &mut dyn Write) -> io::Result<()> {
    writeln!(w, "</Piece>\n</UnstructuredGrid>\n</VTKFile>")
}

fn array<T: std::fmt::Display>(
    w: &mut dyn Write,
    kind: &str,
    name: &str,
    values: impl IntoIterator<Item = T>,
) -> io::Result<()> {
    write_array(w, kind, name, "", values)
}

/// One `DataArray`, ten values a line.
fn write_array<T: std::fmt::Display>(
    w: &mut dyn Write,
    kind: &str,
    name: &str,
    extra: &str,
    values: impl IntoIterator<Item = T>,
) -> io::Result<()> {
    writeln!(
        w,
        "<DataArray type=\"{kind}\" Name=\"{name}\"{extra} format=\"ascii\">"
    )?;
    for (k, v) in values.into_iter().enumerate() {
        let sep = if k % 10 == 9 { "\n" } else { " " };
        write!(w, "{v}{sep}")?;
    }
    writeln!(w, "\n</DataArray>")
}
