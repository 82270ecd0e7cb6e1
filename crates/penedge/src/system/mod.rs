//! Block systems: a set of blocks with ids, built by cutting a box with planes, and the
//! detection of every contact in it.

mod detect;
mod examples;

pub use detect::{count_types, PairContact, SystemContacts};
pub use examples::{paper_example, paper_table3, PaperExample};

use crate::block::{BlockError, ConvexBlock};
use crate::cutting::split_block;
use crate::geometry::{DVec3, Plane};
use crate::tolerance::Tolerance;
use thiserror::Error;

/// A system of blocks; a block's id is its index.
#[derive(Clone, Debug, Default)]
pub struct BlockSystem {
    blocks: Vec<ConvexBlock>,
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
    /// The domain or a piece is not a valid block.
    #[error("invalid block: {0}")]
    Block(#[from] BlockError),
}

impl BlockSystem {
    /// A system of the given blocks.
    pub fn new(blocks: Vec<ConvexBlock>) -> Self {
        BlockSystem { blocks }
    }

    /// The blocks, indexed by id.
    pub fn blocks(&self) -> &[ConvexBlock] {
        &self.blocks
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
    /// every block it crosses (bounding boxes first).
    pub fn from_domain_cut(
        domain: ConvexBlock,
        normals: &[[f64; 3]],
        offsets: &[f64],
        tol: &Tolerance,
    ) -> Result<Self, SystemError> {
        let mut blocks = vec![domain];
        for (i, (n, &d)) in normals.iter().zip(offsets).enumerate() {
            let n = DVec3::from_array(*n);
            let len = n.length();
            if !(len > 0.0 && len.is_finite() && d.is_finite()) {
                return Err(SystemError::DegeneratePlane { plane: i });
            }
            let plane = Plane {
                normal: n / len,
                point: n * (d / (len * len)),
            };
            blocks = cut_all(blocks, &plane, tol)?;
        }
        Ok(BlockSystem { blocks })
    }
}

fn cut_all(
    blocks: Vec<ConvexBlock>,
    plane: &Plane,
    tol: &Tolerance,
) -> Result<Vec<ConvexBlock>, SystemError> {
    let mut out = Vec::with_capacity(blocks.len() * 2);
    for block in blocks {
        if !crosses(&block, plane) {
            out.push(block);
            continue;
        }
        let split = split_block(&block, plane, tol)?;
        out.extend(split.below);
        out.extend(split.above);
    }
    Ok(out)
}

/// Whether the plane can cross the block's bounding box.
fn crosses(block: &ConvexBlock, plane: &Plane) -> bool {
    let b = block.aabb();
    let centre = (b.min + b.max) * 0.5;
    let half = (b.max - b.min) * 0.5;
    plane.distance(centre).abs() <= half.dot(plane.normal.abs())
}
