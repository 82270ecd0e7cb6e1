//! The cutting tree: every block ever made, as a binary tree whose leaves are the current
//! blocks. A plane descends only into nodes whose bounding box it crosses, so its cost grows
//! with the blocks it can reach, not with the number of blocks; a node that was split keeps
//! the bounding box of the block it was.

use super::error::GenerationError;
use super::finite::{coverage, outline, seams, Coverage};
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
    /// Finite joints with bridges that ended inside a block, which was cut through.
    pub(crate) bridged: usize,
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
    /// get the origin `Joint { set, joint }`. With `bridge`, a finite joint also cuts the
    /// blocks it ends inside, with bridge faces outside its outline (`finite.rs`). Stops
    /// once there are more blocks than the tree's most ([`Cut::Full`]).
    pub(crate) fn cut(
        &mut self,
        joint: &JointRecord,
        index: u32,
        bridge: bool,
        counts: &mut CutCounts,
    ) -> Result<Cut, GenerationError> {
        let origin = FaceOrigin::Joint {
            set: joint.set,
            joint: index,
        };
        let bridged = bridge
            .then(|| outline(&joint.shape, &joint.plane))
            .flatten()
            .map(|vertices| Bridged {
                seams: seams(&vertices, &joint.plane),
                shape: JointShape::Polygon { vertices },
                origin: FaceOrigin::Bridge {
                    set: joint.set,
                    joint: index,
                },
            });
        // A disc's outline reaches a little beyond its radius.
        let reach = match &bridged {
            Some(Bridged {
                shape: JointShape::Polygon { vertices },
                ..
            }) => Some(Aabb::of_points(vertices)),
            _ => reach(joint),
        };
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
            self.cut_leaf(n, joint, origin, bridged.as_ref(), counts)
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
        bridged: Option<&Bridged>,
        counts: &mut CutCounts,
    ) -> Result<(), BlockError> {
        let slot = self.nodes[n as usize].block as usize;
        let shape = bridged.map_or(&joint.shape, |b| &b.shape);
        let pieces = match self.try_cut(slot, joint, shape, origin, self.eps) {
            Ok(pieces) => pieces,
            Err(_) => {
                counts.retried += 1;
                self.try_cut(slot, joint, shape, origin, 0.0)?
            }
        };
        match (pieces, bridged) {
            (Pieces::Two([below, above]), _) => {
                self.replace(n, slot, below, above);
                counts.splits += 1;
            }
            (Pieces::Partial, Some(bridged)) => {
                counts.bridged += 1;
                self.cut_bridged(n, &joint.plane, origin, bridged, counts)?;
            }
            (Pieces::Partial, None) => counts.partial += 1,
            (Pieces::None, _) => {}
        }
        Ok(())
    }

    /// Cuts leaf `n`, which a finite joint ends inside and whose section by the joint's
    /// plane is `self.section`, through: along the plane with joint faces, then the piece
    /// below the plane by each seam whose line crosses what is left of the section, the piece
    /// beyond the seam getting bridge faces (its face on the plane and the seam's). The piece
    /// above stays whole (docs/generation.md, "Rock bridges": why one side only).
    fn cut_bridged(
        &mut self,
        n: u32,
        plane: &Plane,
        origin: FaceOrigin,
        bridged: &Bridged,
        counts: &mut CutCounts,
    ) -> Result<(), BlockError> {
        let mut section = std::mem::take(&mut self.section);
        let Some([mut inside, _above]) = self.split_leaf(n, plane, origin, counts)? else {
            self.section = section;
            return Ok(());
        };
        for seam in &bridged.seams {
            let (mut beyond, mut within) = (false, false);
            for &p in &section {
                let d = seam.distance(p);
                beyond |= d > self.eps;
                within |= d < -self.eps;
            }
            if !(beyond && within) {
                continue;
            }
            if let Some([piece, out]) = self.split_leaf(inside, seam, bridged.origin, counts)? {
                self.retag(out, origin, bridged.origin)?;
                inside = piece;
                section = clip(&section, seam);
            }
        }
        self.section = section;
        Ok(())
    }

    /// The faces of leaf `n` of origin `from` get origin `to`.
    fn retag(&mut self, n: u32, from: FaceOrigin, to: FaceOrigin) -> Result<(), BlockError> {
        let slot = self.nodes[n as usize].block as usize;
        let block = self.blocks[slot].clone();
        let origins = block
            .face_origins()
            .iter()
            .map(|&o| if o == from { to } else { o })
            .collect();
        self.blocks[slot] = block.with_face_origins(origins)?;
        Ok(())
    }

    /// Splits leaf `n` by `plane` (new faces of origin `origin`) if the plane crosses it: the
    /// two new leaves, below and above.
    fn split_leaf(
        &mut self,
        n: u32,
        plane: &Plane,
        origin: FaceOrigin,
        counts: &mut CutCounts,
    ) -> Result<Option<[u32; 2]>, BlockError> {
        let slot = self.nodes[n as usize].block as usize;
        let attempt = |splitter: &mut Splitter, eps: f64| {
            if splitter.prepare(&self.blocks[slot], plane, eps)? != Side::Across {
                return Ok(None);
            }
            splitter.finish(origin).map(Some)
        };
        let mut splitter = std::mem::take(&mut self.splitter);
        let pieces = match attempt(&mut splitter, self.eps) {
            Ok(pieces) => Ok(pieces),
            Err(_) => {
                counts.retried += 1;
                attempt(&mut splitter, 0.0)
            }
        };
        self.splitter = splitter;
        let Some([below, above]) = pieces? else {
            return Ok(None);
        };
        let first = self.nodes.len() as u32;
        self.replace(n, slot, below, above);
        counts.splits += 1;
        Ok(Some([first, first + 1]))
    }

    /// The two pieces, if the joint cuts the block (its extent `shape`).
    fn try_cut(
        &mut self,
        slot: usize,
        joint: &JointRecord,
        shape: &JointShape,
        origin: FaceOrigin,
        eps: f64,
    ) -> Result<Pieces, BlockError> {
        let block = &self.blocks[slot];
        if self.splitter.prepare(block, &joint.plane, eps)? != Side::Across {
            return Ok(Pieces::None);
        }
        if joint.is_finite() {
            self.section.clear();
            self.section.extend(self.splitter.section());
            match coverage(shape, &joint.plane, &self.section, self.eps) {
                Coverage::Whole => {}
                Coverage::Partial => return Ok(Pieces::Partial),
                Coverage::Outside => return Ok(Pieces::None),
            }
        }
        self.splitter.finish(origin).map(Pieces::Two)
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

/// What a joint does to a block. (Returned once per cut and moved at once: no box.)
#[allow(clippy::large_enum_variant)]
enum Pieces {
    /// Nothing: the plane misses the block, or the finite joint its section.
    None,
    /// The finite joint ends inside the block.
    Partial,
    /// The two pieces (below, above).
    Two([ConvexBlock; 2]),
}

/// A finite joint with rock bridges: its outline (as a polygon), seams and bridge origin.
struct Bridged {
    shape: JointShape,
    seams: Vec<Plane>,
    origin: FaceOrigin,
}

/// The part of a convex polygon on the inner side of `plane` (signed distance <= 0).
fn clip(polygon: &[DVec3], plane: &Plane) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for k in 0..polygon.len() {
        let (p, q) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        let (dp, dq) = (plane.distance(p), plane.distance(q));
        if dp <= 0.0 {
            out.push(p);
        }
        if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
            out.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    out
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
