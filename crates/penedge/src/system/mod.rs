//! Block systems: a set of blocks with ids, built by cutting a domain with planes (see
//! [`crate::generation`]), and the detection of every contact in it.

mod body_contacts;
mod bridge_bodies;
mod broad_phase;
mod concave;
mod concave_shapes;
#[cfg(test)]
mod concave_tests;
mod detect;
mod examples;
mod excavate;
mod flat;
mod geometry;
#[cfg(test)]
pub(crate) mod test_rng;
mod tracker;

pub use body_contacts::{BodyContact, BodyContacts};
pub use broad_phase::{BroadPhase, WideBoxes};
pub use concave::{ConcaveError, InternalFace};
pub use concave_shapes::BodyShape;
pub use detect::{count_types, Cancelled, DetectProgress, PairContact, SystemContacts};
#[cfg(test)]
pub(crate) use examples::paper_pairs;
pub use examples::{paper_example, paper_spec, paper_table3, PaperExample};
pub use excavate::ExcavationReport;
pub use flat::FlatBlocks;
pub use geometry::ContactGeometries;
pub(crate) use tracker::{
    deadline, edge_certificate, holds, separation, EDGE_CERTIFICATE_STEPS, SIZE_GROWTH,
    TRAVEL_SLACK,
};
pub use tracker::{ContactTracker, TrackerError, UpdateReport};

use crate::block::{BlockError, ConvexBlock};
use crate::generation::{upward, Domain, GenerationError, JointRecord, JointShape};
use crate::generation::{SetKind, SetRecord};
use crate::geometry::{DVec3, Plane};
use crate::tolerance::Tolerance;
use thiserror::Error;

/// A system of blocks; a block's id is its index.
///
/// Each block is a convex part of a body: by default its own body (id = block id); blocks
/// given one body id by [`BlockSystem::with_bodies`] are the parts of one concave block.
///
/// A generated system also carries where it came from: the domain's convex parts, the joint
/// table (every plane applied, in order) and one record per spec entry; each block's
/// [`crate::block::FaceOrigin`]s point into them.
#[derive(Clone, Debug, Default)]
pub struct BlockSystem {
    blocks: Vec<ConvexBlock>,
    domain: Vec<ConvexBlock>,
    joints: Vec<JointRecord>,
    sets: Vec<SetRecord>,
    /// Body ids and internal faces when some block is made of several parts.
    glue: Option<concave::Glue>,
    unit: Option<String>,
}

/// Why a block system cannot be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SystemError {
    /// A cutting plane with a zero, NaN or infinite normal or offset.
    #[error("cutting plane {plane} has a zero, NaN or infinite normal or offset")]
    DegeneratePlane {
        /// Plane index.
        plane: usize,
    },
    /// Cutting planes given with a different number of normals and offsets.
    #[error(
        "{normals} normals but {offsets} offsets: each cutting plane needs one normal and one \
         offset"
    )]
    PlaneCount {
        /// Normals given.
        normals: usize,
        /// Offsets given.
        offsets: usize,
    },
    /// The domain or a piece is not a valid block.
    #[error("invalid block: {0}")]
    Block(#[from] BlockError),
    /// Generation failed.
    #[error("{0}")]
    Generation(#[from] GenerationError),
    /// Flat arrays ([`FlatBlocks`]) whose offsets or indices do not fit together.
    #[error("{message}")]
    Arrays {
        /// What is wrong, naming the array.
        message: String,
    },
    /// Block `block` of flat arrays is not a valid block.
    #[error("block {block}: {source}")]
    InvalidBlock {
        /// The block's id.
        block: usize,
        /// Why.
        source: BlockError,
    },
}

impl BlockSystem {
    /// A system of the given blocks.
    pub fn new(blocks: Vec<ConvexBlock>) -> Self {
        BlockSystem {
            blocks,
            ..BlockSystem::default()
        }
    }

    /// A system with its domain parts, joint table and spec entries.
    pub fn with_provenance(
        blocks: Vec<ConvexBlock>,
        domain: Vec<ConvexBlock>,
        joints: Vec<JointRecord>,
        sets: Vec<SetRecord>,
    ) -> Self {
        BlockSystem {
            blocks,
            domain,
            joints,
            sets,
            glue: None,
            unit: None,
        }
    }

    /// The system with the length unit of its coordinates named (see [`BlockSystem::unit`]).
    pub fn with_unit(mut self, unit: Option<String>) -> Self {
        self.unit = unit;
        self
    }

    /// The length unit of the coordinates, when named (the generation spec's `unit`): a
    /// label for pictures and reports; penedge computes in whatever unit the numbers are.
    pub fn unit(&self) -> Option<&str> {
        self.unit.as_deref()
    }

    /// The blocks, indexed by id.
    pub fn blocks(&self) -> &[ConvexBlock] {
        &self.blocks
    }

    /// The domain's convex parts (empty when not known).
    pub fn domain(&self) -> &[ConvexBlock] {
        &self.domain
    }

    /// The joint table: every joint plane applied, in order.
    pub fn joints(&self) -> &[JointRecord] {
        &self.joints
    }

    /// One record (name, kind) per entry of the generation spec.
    pub fn sets(&self) -> &[SetRecord] {
        &self.sets
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// Whether the system has no block.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// The `domain` cut by infinite planes `normals[i] · x = offsets[i]`: each plane splits
    /// every block it crosses (through the cutting tree). Plane `i` is joint `i` of entry `i`;
    /// planes that miss the domain cut nothing. As many offsets as normals are needed
    /// ([`SystemError::PlaneCount`]).
    pub fn from_domain_cut(
        domain: ConvexBlock,
        normals: &[[f64; 3]],
        offsets: &[f64],
        tol: &Tolerance,
    ) -> Result<Self, SystemError> {
        if normals.len() != offsets.len() {
            return Err(SystemError::PlaneCount {
                normals: normals.len(),
                offsets: offsets.len(),
            });
        }
        let domain = Domain::convex(domain);
        let mut joints = Vec::with_capacity(normals.len());
        for (i, (n, &d)) in normals.iter().zip(offsets).enumerate() {
            // Scaled by the largest component first, so that a normal of 1e200 or 1e-200
            // (with its offset) is neither overflowed nor flushed to zero by the length.
            // `max_element` skips NaN, so finiteness is checked on the normal itself.
            let n = DVec3::from_array(*n);
            let scale = n.abs().max_element();
            if !(n.is_finite() && scale > 0.0 && d.is_finite()) {
                return Err(SystemError::DegeneratePlane { plane: i });
            }
            let (n, d) = (n / scale, d / scale);
            if !d.is_finite() {
                return Err(SystemError::DegeneratePlane { plane: i });
            }
            let len = n.length();
            joints.push(JointRecord {
                set: i as u32,
                member: 0,
                plane: Plane {
                    normal: upward(n / len),
                    point: n * (d / (len * len)),
                },
                shape: JointShape::Infinite,
            });
        }
        let sets = (0..joints.len())
            .map(|i| SetRecord {
                name: format!("plane {i}"),
                kind: SetKind::Plane,
            })
            .collect();
        let eps = tol.for_box(&domain.aabb()).length;
        let blocks = crate::generation::cut_domain(&domain, &joints, eps)?;
        Ok(BlockSystem::with_provenance(
            blocks,
            domain.parts().to_vec(),
            joints,
            sets,
        ))
    }
}

/// A block system as flat arrays (for numpy and other array consumers): block `i` owns
/// vertices `vertex_offsets[i]..vertex_offsets[i + 1]` and faces
/// `face_offsets[i]..face_offsets[i + 1]`; face `f` lists `face_vertices[loop_offsets[f]..
/// loop_offsets[f + 1]]`, indices into the flat vertex array.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SystemArrays {
    /// All vertices, block after block.
    pub vertices: Vec<[f64; 3]>,
    /// Per block, the start of its vertices (length: blocks + 1).
    pub vertex_offsets: Vec<u64>,
    /// Per block, the start of its faces (length: blocks + 1).
    pub face_offsets: Vec<u64>,
    /// Per face, the start of its vertex loop (length: faces + 1).
    pub loop_offsets: Vec<u64>,
    /// Vertex loops of all faces (global vertex indices), counter-clockwise from outside.
    pub face_vertices: Vec<u64>,
    /// Per face, its outward unit normal.
    pub face_normals: Vec<[f64; 3]>,
    /// Per face, [`crate::block::FaceOrigin::code`]: 0 unknown, 1 boundary, 2 joint, 3 bridge.
    pub origin_kind: Vec<u8>,
    /// Per face, the domain part (boundary) or spec entry (joint); -1 when unknown.
    pub origin_set: Vec<i64>,
    /// Per face, the domain face (boundary) or joint id (joint); -1 when unknown.
    pub origin_index: Vec<i64>,
    /// Per block, its volume.
    pub volumes: Vec<f64>,
    /// Per block, its centroid.
    pub centroids: Vec<[f64; 3]>,
    /// Per block, its body id (the concave block it is a part of; its own id by default).
    pub body_ids: Vec<i64>,
    /// Per face, 1 if it lies inside its body (covered entirely by internal faces), else 0.
    pub face_internal: Vec<u8>,
}

impl BlockSystem {
    /// The system as flat arrays.
    pub fn arrays(&self) -> SystemArrays {
        let mut a = SystemArrays {
            vertex_offsets: vec![0],
            face_offsets: vec![0],
            loop_offsets: vec![0],
            ..SystemArrays::default()
        };
        for b in &self.blocks {
            let first = a.vertices.len() as u64;
            a.vertices.extend(b.vertices().iter().map(|v| v.to_array()));
            for (f, face) in b.faces().enumerate() {
                a.face_vertices
                    .extend(face.iter().map(|&v| first + v as u64));
                a.loop_offsets.push(a.face_vertices.len() as u64);
                a.face_normals.push(b.planes()[f].normal.to_array());
                let origin = b.face_origins()[f];
                a.origin_kind.push(origin.code());
                a.origin_set.push(origin.ids().0);
                a.origin_index.push(origin.ids().1);
                a.face_internal
                    .push(self.is_internal_face(a.volumes.len() as u32, f as u32) as u8);
            }
            a.vertex_offsets.push(a.vertices.len() as u64);
            a.face_offsets.push(a.origin_kind.len() as u64);
            a.volumes.push(b.volume());
            a.centroids.push(b.centroid().to_array());
        }
        a.body_ids = self.body_ids().into_iter().map(i64::from).collect();
        a
    }
}

/// Appends `parts` to `out`, in order, each copied by one thread into its own stretch of
/// `out`'s new room: the system output and the broad phase's pairs run to 10^7 entries,
/// whose copy (and fresh pages) from one thread took a fifth of a broad phase and up to
/// 0.9 s of a detection.
fn append_in_parallel<T: Copy + Send + Sync>(out: &mut Vec<T>, parts: &[&[T]]) {
    use rayon::prelude::*;
    let total = parts.iter().map(|p| p.len()).sum();
    out.reserve(total);
    let mut spare = &mut out.spare_capacity_mut()[..total];
    let mut stretches = Vec::with_capacity(parts.len());
    for part in parts {
        let (here, rest) = std::mem::take(&mut spare).split_at_mut(part.len());
        stretches.push(here);
        spare = rest;
    }
    stretches
        .into_par_iter()
        .zip(parts)
        .for_each(|(stretch, part)| {
            for (slot, &x) in stretch.iter_mut().zip(*part) {
                slot.write(x);
            }
        });
    // SAFETY: the stretches have the parts' lengths and together cover the first `total`
    // slots of the new room, each written exactly once above.
    unsafe { out.set_len(out.len() + total) };
}
