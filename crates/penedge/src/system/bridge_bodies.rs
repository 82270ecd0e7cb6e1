//! Rock bridges as concave blocks (docs/generation.md, "Rock bridges"): the pieces of a
//! block that a finite joint with bridges cut through are glued into one body while the
//! bridge holds, so that the detection sees one block; the mechanics keeps them separate
//! rigid bodies held by bonded bridge contacts, so that the bridge can break.
//!
//! Two kinds of glue hold the parts of a body:
//!
//! * **rigid glue**: the parts are one piece of rock for good (the parts an excavation, a
//!   slope or a user's body ids left glued); the mechanics makes them one rigid body;
//! * **breakable glue**: a bridge face on either side (the uncut part of a finite joint's
//!   plane, or a seam), or a face of a finite joint (disc or polygon) on either side (the
//!   crack inside the body: the joint's own faces, glued for the detection since no other
//!   block can reach them). The mechanics keeps the parts apart, held by their contacts.

use super::BlockSystem;
use crate::block::FaceOrigin;
use crate::classify::{Feature, PairResult};
use crate::contact::Detector;
use crate::contact_geometry::ContactGeometry;
use crate::generation::SetKind;
use crate::tolerance::Tolerance;

/// Disjoint sets of `0..n` (union by smaller root, path halving).
pub(super) struct UnionFind(Vec<u32>);

impl UnionFind {
    pub(super) fn new(n: usize) -> Self {
        UnionFind((0..n as u32).collect())
    }

    pub(super) fn find(&mut self, mut k: u32) -> u32 {
        while self.0[k as usize] != k {
            self.0[k as usize] = self.0[self.0[k as usize] as usize];
            k = self.0[k as usize];
        }
        k
    }

    /// Joins the sets of `a` and `b`; whether they were apart.
    pub(super) fn union(&mut self, a: u32, b: u32) -> bool {
        let (a, b) = (self.find(a), self.find(b));
        self.0[a.max(b) as usize] = a.min(b);
        a != b
    }

    /// Per element, its set's number `0..`, sets numbered in the order of their first
    /// element.
    pub(super) fn labels(&mut self) -> Vec<u32> {
        let n = self.0.len();
        let mut label = vec![u32::MAX; n];
        let mut out = Vec::with_capacity(n);
        let mut next = 0;
        for k in 0..n as u32 {
            let r = self.find(k) as usize;
            if label[r] == u32::MAX {
                label[r] = next;
                next += 1;
            }
            out.push(label[r]);
        }
        out
    }
}

impl BlockSystem {
    /// The body ids with the pieces held by rock bridges glued: blocks that touch face to
    /// face (positive area) over a bridge face (origin [`FaceOrigin::Bridge`] on either
    /// side) are one body, transitively, together with the bodies already given (an
    /// excavation's). Ids renumbered `0..` in the order of each body's first part; `None`
    /// when no bridge glues two bodies.
    ///
    /// Found by detecting the pieces, not from the cutting's bookkeeping: the pieces may be
    /// cut again by later planes (a joint set after the finite joint), dropped as slivers or
    /// excavated, and what still touches over a bridge face is what the bridge holds.
    pub(crate) fn bridge_glued_ids(&self, tol: &Tolerance) -> Option<Vec<u32>> {
        let bridged: Vec<bool> = self
            .blocks
            .iter()
            .map(|b| b.face_origins().iter().any(|o| o.is_bridge()))
            .collect();
        if !bridged.contains(&true) {
            return None;
        }
        let mut sets = UnionFind::new(self.len());
        // The bodies given: each part joined to its body's first part.
        let mut first = std::collections::HashMap::<u32, u32>::new();
        for k in 0..self.len() as u32 {
            let head = *first.entry(self.body_of(k)).or_insert(k);
            sets.union(head, k);
        }
        let mut glued = false;
        self.face_face_contacts(
            tol,
            |i, j| bridged[i as usize] || bridged[j as usize],
            |[i, j], [fa, fb], _| {
                let bridge = self.blocks[i as usize].face_origins()[fa as usize].is_bridge()
                    || self.blocks[j as usize].face_origins()[fb as usize].is_bridge();
                if bridge {
                    glued |= sets.union(i, j);
                }
            },
        );
        glued.then(|| sets.labels())
    }

    /// Calls `each(parts, faces, geometry)` for every face-face contact of positive area
    /// between two blocks of a candidate pair that `keep` accepts (the scan both the bridges'
    /// glue and the cracks' measure make: docs/concave-blocks.md).
    pub(super) fn face_face_contacts(
        &self,
        tol: &Tolerance,
        keep: impl Fn(u32, u32) -> bool,
        mut each: impl FnMut([u32; 2], [u32; 2], &ContactGeometry),
    ) {
        let mut det = Detector::new(*tol);
        for [i, j] in self.candidate_pairs(tol) {
            if !keep(i, j) {
                continue;
            }
            let (a, b) = (&self.blocks[i as usize], &self.blocks[j as usize]);
            let (PairResult::Contact(c), Some(g)) = det.detect_with_geometry(a, b) else {
                continue;
            };
            if let (Feature::Face(fa), Feature::Face(fb)) = (c.feature_a, c.feature_b) {
                if g.area() > 0.0 {
                    each([i, j], [fa, fb], &g);
                }
            }
        }
    }

    /// Whether an internal face between two parts is breakable glue (module doc): a bridge
    /// face, or a face of a finite joint, on either side.
    fn is_breakable_glue(&self, parts: [u32; 2], faces: [u32; 2]) -> bool {
        (0..2).any(|s| {
            let origin = self.blocks[parts[s] as usize].face_origins()[faces[s] as usize];
            origin.is_bridge() || self.is_finite_joint(origin)
        })
    }

    /// Whether two faces in contact are a crack: faces of a finite joint with no bridge face
    /// on either side. A crack holds nothing by itself: two pieces of a body touching only
    /// there are held by the bridges beside it, if any are left.
    pub(super) fn is_crack(&self, parts: [u32; 2], faces: [u32; 2]) -> bool {
        let origins =
            [0, 1].map(|s| self.blocks[parts[s] as usize].face_origins()[faces[s] as usize]);
        !origins.iter().any(|o| o.is_bridge()) && origins.iter().any(|&o| self.is_finite_joint(o))
    }

    fn is_finite_joint(&self, origin: FaceOrigin) -> bool {
        match origin {
            FaceOrigin::Joint { set, .. } => self
                .sets
                .get(set as usize)
                .is_some_and(|r| matches!(r.kind, SetKind::Disc | SetKind::Polygon)),
            _ => false,
        }
    }

    /// The rigid bodies of the mechanics, per block: the parts of one body joined by rigid
    /// glue (module doc), numbered `0..` in the order of their first block. A body held by
    /// rock bridges is several rigid bodies, its pieces held by bonded contacts; any other
    /// body is one rigid body. Without concave blocks, each block is its own (`0..n`).
    pub fn rigid_body_ids(&self) -> Vec<u32> {
        let mut sets = UnionFind::new(self.len());
        for g in self.internal_faces() {
            if !self.is_breakable_glue(g.parts, g.faces) {
                sets.union(g.parts[0], g.parts[1]);
            }
        }
        sets.labels()
    }
}
