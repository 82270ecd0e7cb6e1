//! The faces of each block whose planes pass within the length threshold of every
//! representative point (step 2 of the rule in the module docs), gathered edge by edge
//! while the penetration edges are made, without computing the points.
//!
//! A representative point lies on an edge of its *owner* (the block whose edge was
//! clipped) and near the *other* block's boundary:
//!
//! * the other block's faces: their distances are read from the pair's distance table. The
//!   distance of a vertex is in it (its `near` mask has the faces within the threshold), and
//!   along an edge the distance is affine, so that of a point at `t` is `d1 + t (d2 - d1)`
//!   from the two ends': the faces near both ends hold every point between them, and only
//!   the others are interpolated;
//! * the owner's faces: a vertex lies on the faces at that vertex and a point along an edge
//!   on the edge's two faces (and on a face at one end within the threshold). Where the
//!   block's [`crate::block::Clearance`] decides at the pair's threshold (every vertex within
//!   it of its own faces' planes and beyond it from the others, rounding included), this
//!   topology *is* the distance rule, and no distance is computed; elsewhere the point's
//!   distances to the owner's planes are.
//!
//! [`FaceMasks`] keeps both sets as bit masks that only shrink (blocks of at most 64 faces);
//! once they hold only the faces along the contact, a penetration edge changes them by two
//! `and`s. [`FaceLists`] applies the same tests face by face, for larger blocks.

use super::{feature_from, Feature};
use crate::block::{Bits, ConvexBlock, Edge, MASK_FACES};
use crate::geometry::DVec3;
use crate::penetration::{DistanceTable, EdgeSink, PenetrationEdgeType, Piece};

/// The faces of each block that hold the representative points, gathered from the
/// penetration edges as they come, and the features they give.
pub(crate) trait HeldFaces: EdgeSink {
    /// The feature of each block that holds the contact.
    fn features(&self) -> (Option<Feature>, Option<Feature>);
}

/// A representative point (module docs of [`crate::classify`]), by where it lies on its
/// owner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Representative {
    /// An original vertex of the owner.
    Vertex(u32),
    /// The point at parameter `t` along an edge of the owner (0 at its first vertex).
    OnEdge(f64),
}

/// The representative points of a penetration edge, as the classification reads it
/// (`Piece::standing`): both ends if it has length, its original vertex if it is a stub
/// (type 3), its middle if it is a crossing point (type 5).
#[inline]
fn representatives(piece: &Piece<'_>) -> ([Representative; 2], usize) {
    let vertex = |k: usize| Representative::Vertex(piece.parent.vertices[k]);
    let (kind, point) = piece.standing;
    match kind {
        PenetrationEdgeType::T3 => ([vertex(piece.is_cut(0) as usize); 2], 1),
        PenetrationEdgeType::T5 => ([Representative::OnEdge(point); 2], 1),
        _ => {
            let end = |k: usize| match piece.is_cut(k) {
                true => Representative::OnEdge(piece.t[k]),
                false => vertex(k),
            };
            ([end(0), end(1)], 2)
        }
    }
}

/// The point at `t` along `edge` (as the penetration edges' points are computed).
#[inline]
fn point_on(owner: &ConvexBlock, edge: &Edge, t: f64) -> DVec3 {
    let [v1, v2] = edge.vertices;
    let (p, q) = (owner.vertices()[v1 as usize], owner.vertices()[v2 as usize]);
    p + (q - p) * t
}

/// The distance to the other block's face `f` of a representative point of the owner's edge
/// `(v1, v2)`, from the distance table of the owner's vertices.
#[inline]
fn other_distance(table: &DistanceTable, f: usize, rep: Representative, [v1, v2]: [u32; 2]) -> f64 {
    match rep {
        Representative::Vertex(v) => table.get(f, v),
        Representative::OnEdge(t) => {
            let (d1, d2) = (table.get(f, v1), table.get(f, v2));
            d1 + (d2 - d1) * t
        }
    }
}

/// The faces along `edge` (its two), as a mask.
#[inline(always)]
fn edge_faces(edge: &Edge) -> u64 {
    1u64 << edge.faces[0] | 1u64 << edge.faces[1]
}

/// The faces of `mask` (bit `f` for face `f`) for which `keep` holds.
#[inline(always)]
fn retain(mask: u64, mut keep: impl FnMut(usize) -> bool) -> u64 {
    let mut kept = mask;
    for f in Bits(mask) {
        kept &= !((!keep(f) as u64) << f);
    }
    kept
}

/// The faces of each block (at most 64) that hold every representative point given so far,
/// as bit masks (bit `f` for face `f`, as in the block's vertex-face masks and the distance
/// tables' masks).
///
/// The other block's faces come from the distance table: for a vertex, its `near` mask;
/// along an edge, the faces near both ends hold every point between them (the distance is
/// affine along the edge), and only the others are tested, at `d1 + t (d2 - d1)`. The
/// owner's faces come from its topology where its [`crate::block::Clearance`] decides at the
/// length threshold, else from the distances of the point to its planes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceMasks<'a> {
    blocks: [&'a ConvexBlock; 2],
    masks: [u64; 2],
    decided: [bool; 2],
    length: f64,
}

impl<'a> FaceMasks<'a> {
    /// Every face of both blocks; `None` when one has more than 64 faces.
    #[inline]
    pub(crate) fn new(a: &'a ConvexBlock, b: &'a ConvexBlock, length: f64) -> Option<Self> {
        let all = |block: &ConvexBlock| match block.n_faces() {
            n if n > MASK_FACES => None,
            n => Some(u64::MAX >> (64 - n)),
        };
        Some(FaceMasks {
            blocks: [a, b],
            masks: [all(a)?, all(b)?],
            decided: [a, b].map(|x| x.clearance().decides(length)),
            length,
        })
    }

    /// A representative point at vertex `v` of block `side`.
    #[inline(always)]
    fn vertex(&mut self, side: usize, v: u32, table: &DistanceTable) {
        let owner = self.blocks[side];
        self.masks[side] = if self.decided[side] {
            self.masks[side] & owner.vertex_faces()[v as usize]
        } else {
            self.within(side, owner.vertices()[v as usize])
        };
        let other = 1 - side;
        self.masks[other] = if table.masked() {
            self.masks[other] & table.vertex_masks(v).near
        } else {
            let length = self.length;
            retain(self.masks[other], |f| table.get(f, v).abs() <= length)
        };
    }

    /// A representative point at `t` along edge `edge` of block `side`; `near` the masks of
    /// its vertices.
    #[inline(always)]
    fn along(&mut self, side: usize, edge: &Edge, near: [u64; 2], t: f64, table: &DistanceTable) {
        let owner = self.blocks[side];
        let [v1, v2] = edge.vertices;
        let length = self.length;
        self.masks[side] = if self.decided[side] {
            let along = edge_faces(edge);
            let at = owner.vertex_faces();
            let near_end = (at[v1 as usize] | at[v2 as usize]) & !along & self.masks[side];
            let ends = if near_end == 0 {
                0
            } else {
                let p = point_on(owner, edge, t);
                retain(near_end, |f| owner.planes()[f].distance(p).abs() <= length)
            };
            self.masks[side] & (along | ends)
        } else {
            self.within(side, point_on(owner, edge, t))
        };
        let other = 1 - side;
        let lerp = |f: usize| {
            other_distance(table, f, Representative::OnEdge(t), [v1, v2]).abs() <= length
        };
        self.masks[other] = if table.masked() {
            let both = near[0] & near[1];
            let rest = self.masks[other] & !both;
            let tested = if rest == 0 { 0 } else { retain(rest, lerp) };
            self.masks[other] & (both | tested)
        } else {
            retain(self.masks[other], lerp)
        };
    }

    /// The faces of block `side` in its mask whose planes pass within the length threshold
    /// of `p`.
    #[inline]
    fn within(&self, side: usize, p: DVec3) -> u64 {
        let (planes, length) = (self.blocks[side].planes(), self.length);
        retain(self.masks[side], |f| planes[f].distance(p).abs() <= length)
    }

    /// The same masks with every owner's face tested by distance (tests: the clearance
    /// shortcut must change nothing).
    #[cfg(test)]
    pub(crate) fn without_clearance(mut self) -> Self {
        self.decided = [false; 2];
        self
    }
}

impl EdgeSink for FaceMasks<'_> {
    /// Keeps the faces that hold the representative points of `piece`; `table` holds the
    /// distances of its owner's vertices to the other block's planes.
    ///
    /// Once the masks have shrunk to the faces along the contact (after a point or two),
    /// a penetration edge changes them by two `and`s: every point along an edge is held by
    /// the edge's two faces, and by the other block's faces near both of its vertices; only
    /// faces still in a mask and not settled so are tested point by point.
    #[inline(always)]
    fn edge(&mut self, piece: &Piece<'_>, table: &DistanceTable) {
        let side = piece.side as usize;
        let other = 1 - side;
        let parent = piece.parent;
        let (kind, point) = piece.standing;
        if kind == PenetrationEdgeType::T3 {
            // The stub's original vertex.
            let v = parent.vertices[piece.is_cut(0) as usize];
            return self.vertex(side, v, table);
        }
        if self.decided[side] && table.masked() {
            let along = edge_faces(parent);
            let at = self.blocks[side].vertex_faces();
            let [v1, v2] = parent.vertices.map(|v| at[v as usize]);
            let both = piece.near[0] & piece.near[1];
            let open_own = (v1 | v2) & !along & self.masks[side];
            let open_other = self.masks[other] & !both;
            if open_own | open_other == 0 {
                self.masks[side] &= along;
                self.masks[other] &= both;
                return;
            }
        }
        if kind == PenetrationEdgeType::T5 {
            return self.along(side, parent, piece.near, point, table);
        }
        // The two ends written out rather than looped over by index: an indexed piece
        // stays in memory, and the caller's copy of its parameters into the penetration
        // edge then reads two narrow stores with one wide load, which the processor cannot
        // forward (about 5 % of the 100^3 grid's detection).
        let [t0, t1] = piece.t;
        let [v1, v2] = parent.vertices;
        if piece.is_cut(0) {
            self.along(side, parent, piece.near, t0, table);
        } else {
            self.vertex(side, v1, table);
        }
        if piece.is_cut(1) {
            self.along(side, parent, piece.near, t1, table);
        } else {
            self.vertex(side, v2, table);
        }
    }
}

impl HeldFaces for FaceMasks<'_> {
    fn features(&self) -> (Option<Feature>, Option<Feature>) {
        let feature = |k: usize| feature_of_mask(self.blocks[k], self.masks[k]);
        (feature(0), feature(1))
    }
}

/// The smallest feature of `block` with exactly the faces of `mask`.
fn feature_of_mask(block: &ConvexBlock, mask: u64) -> Option<Feature> {
    match mask.count_ones() {
        0 => None,
        1 => Some(Feature::Face(mask.trailing_zeros())),
        2 => {
            let (f, g) = (mask.trailing_zeros(), (mask & (mask - 1)).trailing_zeros());
            feature_from(block, &[f, g])
        }
        _ => match block.vertex_faces().iter().position(|&m| m & mask == mask) {
            Some(v) => Some(Feature::Vertex(v as u32)),
            None => {
                let faces: Vec<u32> = Bits(mask).map(|f| f as u32).collect();
                feature_from(block, &faces)
            }
        },
    }
}

/// [`FaceMasks`] for blocks of any number of faces (their clearance is not kept): the same
/// tests, face by face over lists of the faces still held, the owner's by the distances of
/// the points to its planes.
pub(crate) struct FaceLists<'a> {
    blocks: [&'a ConvexBlock; 2],
    held: [Vec<u32>; 2],
    length: f64,
}

impl<'a> FaceLists<'a> {
    /// Every face of both blocks.
    pub(crate) fn new(a: &'a ConvexBlock, b: &'a ConvexBlock, length: f64) -> Self {
        let all = |block: &ConvexBlock| (0..block.n_faces() as u32).collect();
        FaceLists {
            blocks: [a, b],
            held: [all(a), all(b)],
            length,
        }
    }
}

impl EdgeSink for FaceLists<'_> {
    /// The tests of [`FaceMasks`], face by face.
    fn edge(&mut self, piece: &Piece<'_>, table: &DistanceTable) {
        let (reps, n) = representatives(piece);
        let side = piece.side as usize;
        let owner = self.blocks[side];
        let edge = *piece.parent;
        let length = self.length;
        for &rep in &reps[..n] {
            let p = match rep {
                Representative::Vertex(v) => owner.vertices()[v as usize],
                Representative::OnEdge(t) => point_on(owner, &edge, t),
            };
            let planes = owner.planes();
            self.held[side].retain(|&f| planes[f as usize].distance(p).abs() <= length);
            self.held[1 - side]
                .retain(|&f| other_distance(table, f as usize, rep, edge.vertices).abs() <= length);
        }
    }
}

impl HeldFaces for FaceLists<'_> {
    fn features(&self) -> (Option<Feature>, Option<Feature>) {
        let feature = |k: usize| feature_from(self.blocks[k], &self.held[k]);
        (feature(0), feature(1))
    }
}
