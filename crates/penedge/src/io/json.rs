//! The block system as JSON (`docs/block-file-format.md`), versioned and lossless: numbers
//! are written in the shortest form that reads back to the same `f64`, and reading restores
//! each block from its stored vertices, faces, planes and origins without refitting anything
//! (edges, volume and centroid are derived by the same code as when the block was made).
//!
//! A file written by hand needs less: blocks of vertices and faces only (the planes are
//! fitted and checked as [`ConvexBlock::new`] does, the origins are unknown), and no
//! `frame`, `domain`, `sets` or `joints`.

use super::strict::{self, Table};
use super::{messages, read_text, write_atomic, IoError};
use crate::block::{BlockError, ConvexBlock, FaceOrigin};
use crate::generation::check;
use crate::generation::{Attitude, JointRecord, JointShape, SetRecord};
use crate::geometry::{Aabb, DVec3, Plane};
use crate::system::{BlockSystem, InternalFace};
use crate::tolerance::Tolerance;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

/// The value of the `format` field.
pub const FORMAT: &str = "penedge-blocks";
/// The schema version written. Version 2 adds body ids and internal faces (concave blocks);
/// version 1 files are read too, each block its own body.
pub const VERSION: u32 = 2;
/// The value of the `frame` field.
pub const FRAME: &str = "x East, y North, z up";

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SystemFile {
    format: String,
    version: u32,
    #[serde(default)]
    frame: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    length: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    unit: Option<String>,
    #[serde(default, deserialize_with = "strict::read")]
    domain: Vec<BlockFile>,
    #[serde(default, deserialize_with = "strict::read")]
    sets: Vec<SetRecord>,
    #[serde(default, deserialize_with = "strict::read")]
    joints: Vec<JointFile>,
    #[serde(deserialize_with = "strict::read")]
    blocks: Vec<BlockFile>,
    /// Derived from the blocks and their body ids (ignored when reading).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "strict::read"
    )]
    internal_faces: Option<Vec<InternalFace>>,
}

/// A block as stored; written in full, read with only `vertices` and `faces` required.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BlockFile {
    id: Option<u32>,
    /// The body (concave block) the block is a part of; version 2 only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    body: Option<u32>,
    #[serde(deserialize_with = "strict::read")]
    vertices: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
    #[serde(default, deserialize_with = "strict::read")]
    planes: Option<Vec<[f64; 6]>>,
    #[serde(default, deserialize_with = "strict::read")]
    origins: Option<Vec<FaceOrigin>>,
    volume: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    centroid: Option<[f64; 3]>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JointFile {
    id: u32,
    set: u32,
    member: u32,
    #[serde(deserialize_with = "strict::read")]
    normal: [f64; 3],
    #[serde(deserialize_with = "strict::read")]
    point: [f64; 3],
    dip: f64,
    dip_direction: f64,
    #[serde(deserialize_with = "strict::read")]
    shape: ShapeFile,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub(crate) enum ShapeFile {
    Infinite,
    Disc {
        #[serde(deserialize_with = "strict::read")]
        center: [f64; 3],
        radius: f64,
    },
    Polygon {
        #[serde(deserialize_with = "strict::read")]
        vertices: Vec<[f64; 3]>,
    },
}

strict::tables!(SystemFile, BlockFile, JointFile, ShapeFile, InternalFace);

/// The system as a JSON string.
pub fn to_json_string(system: &BlockSystem) -> String {
    serde_json::to_string(&file_of(system)).expect("plain data always serialises")
}

/// The system as a JSON string; an error for a block with a NaN or infinite coordinate
/// (which [`to_json_string`] writes as `null`, and reading refuses).
pub fn try_to_json_string(system: &BlockSystem) -> Result<String, IoError> {
    super::check_finite(system)?;
    Ok(to_json_string(system))
}

/// Writes the system as JSON, atomically; an error, and nothing written, for a block with a
/// NaN or infinite coordinate (JSON has no such numbers).
pub fn write_json(system: &BlockSystem, path: &Path) -> Result<(), IoError> {
    super::check_finite(system)?;
    let file = file_of(system);
    write_atomic(path, |w: &mut dyn Write| {
        serde_json::to_writer(&mut *w, &file).map_err(std::io::Error::other)?;
        w.write_all(b"\n")
    })
}

/// Reads a system written by [`write_json`] (or by hand: see the module's documentation).
///
/// A file that is not a block file at all (a joint spec, a list, a ParaView file) is an
/// [`IoError::Syntax`] that says what it looks like and what to do with it.
pub fn read_json(path: &Path) -> Result<BlockSystem, IoError> {
    let text = read_text(path)?;
    from_json_str(&text).map_err(|e| match e {
        IoError::Syntax { message, .. } => IoError::Syntax {
            path: path.to_path_buf(),
            message,
        },
        other => other,
    })
}

/// Parses a system from a JSON string.
pub fn from_json_str(text: &str) -> Result<BlockSystem, IoError> {
    let Table(file) =
        serde_json::from_str::<Table<SystemFile>>(text).map_err(|e| IoError::Syntax {
            path: "<string>".into(),
            message: messages::not_a_block_file(text)
                .unwrap_or_else(|| messages::plain(&e.to_string())),
        })?;
    if file.format != FORMAT || !(1..=VERSION).contains(&file.version) {
        return Err(format_error(
            "version",
            format!(
                "expected format `{FORMAT}` version 1 to {VERSION}, got `{}` version {}",
                file.format, file.version
            ),
        ));
    }
    let default = Tolerance::default();
    let tol = match file.length {
        None => default,
        Some(length) => Tolerance::new(default.gap(), length)
            .map_err(|e| format_error("length", e.to_string()))?,
    };
    let unit = file
        .unit
        .as_deref()
        .map(check::unit_name)
        .transpose()
        .map_err(|why| format_error("unit", why))?;
    check::entry_names("sets", file.sets.iter().map(|s| s.name.as_str()))
        .map_err(|(i, why)| format_error(format!("sets[{i}].name"), why))?;
    let system = system_box(file.domain.iter().chain(&file.blocks));
    let domain = blocks_of("domain", &file.domain, system.as_ref(), &tol)?;
    let blocks = blocks_of("blocks", &file.blocks, system.as_ref(), &tol)?;
    let joints = file
        .joints
        .into_iter()
        .enumerate()
        .map(|(i, j)| record_of(i, j, file.sets.len()))
        .collect::<Result<Vec<_>, _>>()?;
    check_origins(&blocks, &domain, &joints, file.sets.len())?;
    let bodies = body_ids(file.version, &file.blocks)?;
    let system = BlockSystem::with_provenance(blocks, domain, joints, file.sets).with_unit(unit);
    system
        .with_bodies(bodies, &tol)
        .map_err(|e| format_error("blocks[..].body", e.to_string()))
}

/// The body id of each block: given by every block in version 2, none in version 1 (each
/// block its own body).
fn body_ids(version: u32, blocks: &[BlockFile]) -> Result<Vec<u32>, IoError> {
    let mut ids = Vec::with_capacity(blocks.len());
    for (i, b) in blocks.iter().enumerate() {
        match (version, b.body) {
            (1, None) => ids.push(i as u32),
            (1, Some(_)) => {
                let msg = "body ids need version 2 of the format".to_string();
                return Err(format_error(format!("blocks[{i}].body"), msg));
            }
            (_, Some(body)) => ids.push(body),
            (_, None) => {
                let msg = format!("version {version} needs a body id for every block");
                return Err(format_error(format!("blocks[{i}].body"), msg));
            }
        }
    }
    Ok(ids)
}

/// Every face origin points into the domain parts, joint table and sets that the file has,
/// where it has them: a boundary face to a face of a domain part, a joint or bridge face to
/// a joint of the table that belongs to the same set. A file without a domain or without a
/// joint table (one written from a system built of blocks, whose faces keep the origins they
/// had in the system they came from) keeps the origins that would point into them as
/// written: labels of where the faces came from (the set numbers by which properties are
/// given), which nothing looks up.
fn check_origins(
    blocks: &[ConvexBlock],
    domain: &[ConvexBlock],
    joints: &[JointRecord],
    sets: usize,
) -> Result<(), IoError> {
    let table = !joints.is_empty() || sets > 0;
    for (i, b) in blocks.iter().enumerate() {
        for (f, origin) in b.face_origins().iter().enumerate() {
            if let Some(why) = bad_origin(*origin, domain, joints, sets, table) {
                let written = serde_json::to_string(origin).unwrap_or_default();
                let msg = format!("{written}: {why}");
                return Err(format_error(format!("blocks[{i}].origins[{f}]"), msg));
            }
        }
    }
    Ok(())
}

/// What is wrong with a face origin, in the file's words, or `None`.
fn bad_origin(
    origin: FaceOrigin,
    domain: &[ConvexBlock],
    joints: &[JointRecord],
    sets: usize,
    table: bool,
) -> Option<String> {
    match origin {
        FaceOrigin::Unknown => None,
        FaceOrigin::Boundary { .. } if domain.is_empty() => None,
        FaceOrigin::Boundary { part, face } => match domain.get(part as usize) {
            None => Some(format!(
                "domain part {part} does not exist (the file's domain has {} part(s))",
                domain.len()
            )),
            Some(p) if face as usize >= p.n_faces() => Some(format!(
                "face {face} does not exist (domain part {part} has {} faces)",
                p.n_faces()
            )),
            Some(_) => None,
        },
        FaceOrigin::Joint { .. } | FaceOrigin::Bridge { .. } if !table => None,
        FaceOrigin::Joint { set, joint } | FaceOrigin::Bridge { set, joint } => {
            if set as usize >= sets {
                return Some(format!(
                    "set {set} does not exist (the file has {sets} set(s))"
                ));
            }
            match joints.get(joint as usize) {
                None => Some(format!(
                    "joint {joint} does not exist (the joint table has {} joint(s))",
                    joints.len()
                )),
                Some(record) if record.set != set => Some(format!(
                    "joint {joint} is of set {} in the joint table, not of set {set}",
                    record.set
                )),
                Some(_) => None,
            }
        }
    }
}

fn format_error(field: impl Into<String>, message: String) -> IoError {
    IoError::Format {
        field: field.into(),
        message,
    }
}

fn file_of(system: &BlockSystem) -> SystemFile {
    let domain: Vec<BlockFile> = system.domain().iter().enumerate().map(block_file).collect();
    let bodies = system.body_ids();
    let mut blocks: Vec<BlockFile> = system.blocks().iter().enumerate().map(block_file).collect();
    for (b, body) in blocks.iter_mut().zip(bodies) {
        b.body = Some(body);
    }
    let length = needed_length(system, system_box(domain.iter().chain(&blocks)));
    SystemFile {
        format: FORMAT.to_string(),
        version: VERSION,
        frame: FRAME.to_string(),
        length,
        unit: system.unit().map(str::to_string),
        domain,
        sets: system.sets().to_vec(),
        joints: system.joints().iter().enumerate().map(joint_file).collect(),
        blocks,
        internal_faces: Some(system.internal_faces().to_vec()),
    }
}

/// The relative length threshold with which the blocks read back, when the default is not
/// enough: blocks cut with a coarser tolerance (generation's `options.length`) keep a
/// vertex that was within it of a cutting plane where it is, off the new face's plane by up
/// to that threshold. Twice the largest distance of a face vertex from its plane, or of a
/// vertex outside a plane, over the size of the system's box.
fn needed_length(system: &BlockSystem, scale: Option<Aabb>) -> Option<f64> {
    let scale = scale?;
    let allowed = Tolerance::default().for_box(&scale).length;
    let worst = system
        .domain()
        .iter()
        .chain(system.blocks())
        .map(off_planes)
        .fold(0.0, f64::max);
    (worst > allowed).then(|| 2.0 * worst / scale.diagonal())
}

/// The largest distance of a face vertex from its face's plane, or of a vertex outside a
/// face's plane (what [`ConvexBlock::from_parts_in`] checks).
pub(crate) fn off_planes(b: &ConvexBlock) -> f64 {
    let mut worst = 0.0_f64;
    for (f, plane) in b.planes().iter().enumerate() {
        for &v in b.face(f) {
            worst = worst.max(plane.distance(b.vertices()[v as usize]).abs());
        }
        for &p in b.vertices() {
            worst = worst.max(plane.distance(p));
        }
    }
    worst
}

fn block_file((id, b): (usize, &ConvexBlock)) -> BlockFile {
    BlockFile {
        id: Some(id as u32),
        body: None,
        vertices: b.vertices().iter().map(|v| v.to_array()).collect(),
        faces: b.faces().map(<[u32]>::to_vec).collect(),
        planes: Some(
            b.planes()
                .iter()
                .map(|p| {
                    let (n, q) = (p.normal, p.point);
                    [n.x, n.y, n.z, q.x, q.y, q.z]
                })
                .collect(),
        ),
        origins: Some(b.face_origins().to_vec()),
        volume: Some(b.volume()),
        centroid: Some(b.centroid().to_array()),
    }
}

/// The bounding box of the finite vertices of every block and domain part: the scale of the
/// length threshold with which the blocks are checked, as they were cut
/// ([`ConvexBlock::from_parts_in`]).
fn system_box<'a>(blocks: impl Iterator<Item = &'a BlockFile>) -> Option<Aabb> {
    let points: Vec<DVec3> = blocks
        .flat_map(|b| &b.vertices)
        .map(|v| DVec3::from_array(*v))
        .filter(|p| p.is_finite())
        .collect();
    (!points.is_empty()).then(|| Aabb::of_points(&points))
}

fn blocks_of(
    field: &str,
    files: &[BlockFile],
    system: Option<&Aabb>,
    tol: &Tolerance,
) -> Result<Vec<ConvexBlock>, IoError> {
    files
        .iter()
        .enumerate()
        .map(|(i, f)| {
            if let Some(id) = f.id.filter(|&id| id as usize != i) {
                let msg = format!("ids must run 0, 1, 2, ... in order; found {id}");
                return Err(format_error(format!("{field}[{i}].id"), msg));
            }
            block_of(f, tol, system)
                .map_err(|e| format_error(format!("{field}[{i}]"), e.to_string()))
        })
        .collect()
}

/// A block as stored (planes kept as given, not refitted), or from its vertices and faces
/// alone (planes fitted, origins unknown unless given).
fn block_of(
    f: &BlockFile,
    tol: &Tolerance,
    system: Option<&Aabb>,
) -> Result<ConvexBlock, BlockError> {
    let Some(planes) = &f.planes else {
        let faces: Vec<Vec<usize>> = f
            .faces
            .iter()
            .map(|face| face.iter().map(|&v| v as usize).collect())
            .collect();
        let block = ConvexBlock::with_tolerance(&f.vertices, &faces, tol)?;
        return match &f.origins {
            Some(origins) => block.with_face_origins(origins.clone()),
            None => Ok(block),
        };
    };
    let planes: Vec<Plane> = planes
        .iter()
        .map(|p| Plane {
            normal: DVec3::new(p[0], p[1], p[2]),
            point: DVec3::new(p[3], p[4], p[5]),
        })
        .collect();
    let origins = f
        .origins
        .clone()
        .unwrap_or_else(|| vec![FaceOrigin::Unknown; f.faces.len()]);
    ConvexBlock::from_parts_in(&f.vertices, &f.faces, &planes, &origins, tol, system)
}

pub(crate) fn joint_file((id, r): (usize, &JointRecord)) -> JointFile {
    // A zero or NaN normal (a joint table built by hand) has no attitude: such a joint is
    // written with null angles, and reading the file names it.
    let attitude = r.attitude().unwrap_or(Attitude::new(f64::NAN, f64::NAN));
    JointFile {
        id: id as u32,
        set: r.set,
        member: r.member,
        normal: r.plane.normal.to_array(),
        point: r.plane.point.to_array(),
        dip: attitude.dip,
        dip_direction: attitude.dip_direction,
        shape: match &r.shape {
            JointShape::Infinite => ShapeFile::Infinite,
            JointShape::Disc { center, radius } => ShapeFile::Disc {
                center: center.to_array(),
                radius: *radius,
            },
            JointShape::Polygon { vertices } => ShapeFile::Polygon {
                vertices: vertices.iter().map(|v| v.to_array()).collect(),
            },
        },
    }
}

/// A joint of the file, checked: ids in order, a spec entry that exists, a finite unit
/// normal, finite points, a positive finite radius, a polygon of 3 vertices or more.
pub(crate) fn record_of(i: usize, f: JointFile, sets: usize) -> Result<JointRecord, IoError> {
    let field = |name: &str| format!("joints[{i}].{name}");
    if f.id as usize != i {
        let msg = format!("ids must run 0, 1, 2, ... in order; found {}", f.id);
        return Err(format_error(field("id"), msg));
    }
    if f.set as usize >= sets {
        let msg = format!("refers to spec entry {}, but the file has {sets}", f.set);
        return Err(format_error(field("set"), msg));
    }
    let normal = DVec3::from_array(f.normal);
    if !(normal.is_finite() && (normal.length() - 1.0).abs() <= 1e-9) {
        let msg = format!("must be a finite unit vector, got {:?}", f.normal);
        return Err(format_error(field("normal"), msg));
    }
    let finite = |name: &str, p: &[f64; 3]| {
        if p.iter().all(|c| c.is_finite()) {
            Ok(DVec3::from_array(*p))
        } else {
            let msg = format!("must have finite coordinates, got {p:?}");
            Err(format_error(field(name), msg))
        }
    };
    let point = finite("point", &f.point)?;
    let shape = match f.shape {
        ShapeFile::Infinite => JointShape::Infinite,
        ShapeFile::Disc { center, radius } => {
            if !(radius.is_finite() && radius > 0.0) {
                let msg = format!("must be a finite number greater than zero, got {radius}");
                return Err(format_error(field("shape.radius"), msg));
            }
            JointShape::Disc {
                center: finite("shape.center", &center)?,
                radius,
            }
        }
        ShapeFile::Polygon { vertices } => {
            if vertices.len() < 3 {
                let msg = format!("a polygon needs 3 vertices or more, got {}", vertices.len());
                return Err(format_error(field("shape.vertices"), msg));
            }
            let vertices = vertices
                .iter()
                .map(|v| finite("shape.vertices", v))
                .collect::<Result<_, _>>()?;
            JointShape::Polygon { vertices }
        }
    };
    Ok(JointRecord {
        set: f.set,
        member: f.member,
        plane: Plane { normal, point },
        shape,
    })
}
