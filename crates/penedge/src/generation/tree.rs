//! The cutting tree: every block ever made, as a binary tree whose leaves are the current
//! blocks. A plane descends only into nodes whose bounding box it crosses, so its cost grows
//! with the blocks it can reach, not with the number of blocks; a node that was split keeps
//! the bounding box of the block it was.

use super::error::GenerationError;
use super::finite::{coverage, Coverage};
use super::record::{JointRecord, JointShape};
use crate::block::{BlockError, ConvexBlock, FaceOrigin};
use crate::cutting::{Side, Splitter};
use crate::geometry::{Aabb, DVec3, Plane};

const LEAF: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Node {
    aabb: Aabb,
    first_child: u32,
    block: u32,
}

/// What the cuts did.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CutCounts {
    /// Blocks split.
    pub(crate) splits: usize,
    /// Finite joints that ended inside a block, which was left whole.
    pub(crate) partial: usize,
    /// Cuts whose pieces did not close with the length threshold and were redone with exact
    /// signs.
    pub(crate) retried: usize,
}

/// How a plane's cut ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cut {
    /// Every block the plane crosses was cut.
    Done,
    /// The tree reached its most blocks and the cut stopped there.
    Full,
}

/// Blocks and the tree over them.
pub(crate) struct CuttingTree {
    nodes: Vec<Node>,
    roots: usize,
    blocks: Vec<ConvexBlock>,
    splitter: Splitter,
    stack: Vec<u32>,
    section: Vec<DVec3>,
    eps: f64,
    max_blocks: usize,
}

impl CuttingTree {
    /// A tree with one root per domain part; `eps` is the absolute length threshold; a cut
    /// stops once there are more than `max_blocks` blocks.
    pub(crate) fn new(parts: &[ConvexBlock], eps: f64, max_blocks: usize) -> Self {
        let nodes = (0..parts.len())
            .map(|i| Node {
                aabb: parts[i].aabb(),
                first_child: LEAF,
                block: i as u32,
            })
            .collect();
        CuttingTree {
            nodes,
            roots: parts.len(),
            blocks: parts.to_vec(),
            splitter: Splitter::default(),
            stack: Vec::new(),
            section: Vec::new(),
            eps,
            max_blocks,
        }
    }

    /// Number of blocks now.
    pub(crate) fn len(&self) -> usize {
        self.blocks.len()
    }

    /// The blocks, in the order they were made.
    pub(crate) fn into_blocks(self) -> Vec<ConvexBlock> {
        self.blocks
    }

    /// Cuts every block the joint crosses (completely, for a finite joint); the new faces
    /// get the origin `Joint { set, joint }`. Stops once there are more blocks than the
    /// tree's most ([`Cut::Full`]).
    pub(crate) fn cut(
        &mut self,
        joint: &JointRecord,
        index: u32,
        counts: &mut CutCounts,
    ) -> Result<Cut, GenerationError> {
        let origin = FaceOrigin::Joint {
            set: joint.set,
            joint: index,
        };
        let reach = reach(joint);
        self.stack.clear();
        self.stack.extend((0..self.roots as u32).rev());
        while let Some(n) = self.stack.pop() {
            let node = self.nodes[n as usize];
            let near = reach.is_none_or(|r| r.overlaps(&node.aabb, self.eps));
            if !near || !crosses(&node.aabb, &joint.plane, self.eps) {
                continue;
            }
            if node.first_child != LEAF {
                self.stack.push(node.first_child + 1);
                self.stack.push(node.first_child);
                continue;
            }
            self.cut_leaf(n, joint, origin, counts)
                .map_err(|source| GenerationError::Cut {
                    set: joint.set,
                    joint: index,
                    source,
                })?;
            if self.blocks.len() > self.max_blocks {
                return Ok(Cut::Full);
            }
        }
        Ok(Cut::Done)
    }

    fn cut_leaf(
        &mut self,
        n: u32,
        joint: &JointRecord,
        origin: FaceOrigin,
        counts: &mut CutCounts,
    ) -> Result<(), BlockError> {
        let slot = self.nodes[n as usize].block as usize;
        let pieces = match self.try_cut(slot, joint, origin, self.eps, counts) {
            Ok(pieces) => pieces,
            Err(_) => {
                counts.retried += 1;
                self.try_cut(slot, joint, origin, 0.0, counts)?
            }
        };
        if let Some([below, above]) = pieces {
            self.replace(n, slot, below, above);
            counts.splits += 1;
        }
        Ok(())
    }

    /// The two pieces, if the joint cuts the block.
    fn try_cut(
        &mut self,
        slot: usize,
        joint: &JointRecord,
        origin: FaceOrigin,
        eps: f64,
        counts: &mut CutCounts,
    ) -> Result<Option<[ConvexBlock; 2]>, BlockError> {
        let block = &self.blocks[slot];
        if self.splitter.prepare(block, &joint.plane, eps)? != Side::Across {
            return Ok(None);
        }
        if joint.is_finite() {
            self.section.clear();
            self.section.extend(self.splitter.section());
            match coverage(&joint.shape, &joint.plane, &self.section, self.eps) {
                Coverage::Whole => {}
                Coverage::Partial => {
                    counts.partial += 1;
                    return Ok(None);
                }
                Coverage::Outside => return Ok(None),
            }
        }
        self.splitter.finish(origin).map(Some)
    }

    /// Leaf `n` becomes a node with two leaves: `below` in its slot, `above` in a new one.
    fn replace(&mut self, n: u32, slot: usize, below: ConvexBlock, above: ConvexBlock) {
        let first = self.nodes.len() as u32;
        for (aabb, block) in [(below.aabb(), slot), (above.aabb(), self.blocks.len())] {
            self.nodes.push(Node {
                aabb,
                first_child: LEAF,
                block: block as u32,
            });
        }
        self.blocks[slot] = below;
        self.blocks.push(above);
        self.nodes[n as usize].first_child = first;
    }
}

/// Whether the plane passes within `eps` of the box.
fn crosses(b: &Aabb, plane: &Plane, eps: f64) -> bool {
    let centre = (b.min + b.max) * 0.5;
    let half = (b.max - b.min) * 0.5;
    plane.distance(centre).abs() <= half.dot(plane.normal.abs()) + eps
}

/// The bounding box of a finite joint (`None` for an infinite one).
fn reach(joint: &JointRecord) -> Option<Aabb> {
    match &joint.shape {
        JointShape::Infinite => None,
        JointShape::Polygon { vertices } => Some(Aabb::of_points(vertices)),
        JointShape::Disc { center, radius } => {
            let n = joint.plane.normal;
            let half = (DVec3::ONE - n * n).max(DVec3::ZERO).map(f64::sqrt) * *radius;
            Some(Aabb {
                min: *center - half,
                max: *center + half,
            })
        }
    }
}
