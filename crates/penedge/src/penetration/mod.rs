//! Penetration edges of a pair of blocks (paper section 3.3 and Table 1).
//!
//! Every edge of A is clipped by the face planes of B, each moved outwards by a signed
//! offset (the gap), and vice versa. With `s = n · (x - p)` the signed distance of a point
//! outside a face plane of the other block and `d = s - offset`, the part of the edge with
//! `d <= 0` for every face survives. This is the paper's sequential clipping with the signs
//! corrected (method.md), done as an intersection of parameter intervals along the edge,
//! which gives the same piece and needs no new points until the end.
//!
//! The signed distances of each block's vertices to the other block's planes are computed
//! once per pair (`V_B * F_A + V_A * F_B` dot products) and reused by every edge; a face plane
//! with every vertex of the other block beyond the offset separates the pair, which ends the
//! query early.

mod clip;
mod grazing;
mod table;

use crate::block::{Bits, ConvexBlock, Edge};
use crate::tolerance::Thresholds;
use clip::{Clipped, NO_CUT};
pub(crate) use table::{DistanceTable, Kernel, VertexMasks};

/// Which block of the pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Side {
    /// The first block.
    A,
    /// The second block.
    B,
}

/// What ends a penetration edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum EdgeEnd {
    /// An original vertex of the parent edge (index into its block's vertices).
    Vertex(u32),
    /// A cut by a face plane of the other block (index into the other block's faces).
    Cut(u32),
}

/// The five types of penetration edges (paper Table 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum PenetrationEdgeType {
    /// Two original vertices; has length.
    T1 = 1,
    /// One original vertex and one cut point; has length.
    T2 = 2,
    /// One original vertex and one cut point; no length.
    T3 = 3,
    /// Two cut points; has length.
    T4 = 4,
    /// Two cut points; no length.
    T5 = 5,
}

impl PenetrationEdgeType {
    /// The type from the nature of the two ends and whether the piece has length.
    ///
    /// Two original vertices always make a type 1: a block has no edge shorter than the
    /// length threshold (its vertices would be repeated).
    pub fn of(ends: [EdgeEnd; 2], has_length: bool) -> Self {
        use PenetrationEdgeType::*;
        // A table lookup: which type comes out is unpredictable, a branch would often miss.
        const BY_ORIGINALS: [[PenetrationEdgeType; 2]; 3] = [[T5, T4], [T3, T2], [T1, T1]];
        let original = |e: EdgeEnd| matches!(e, EdgeEnd::Vertex(_)) as usize;
        BY_ORIGINALS[original(ends[0]) + original(ends[1])][has_length as usize]
    }

    /// Whether the piece has length (types 1, 2 and 4).
    pub fn has_length(self) -> bool {
        matches!(self, Self::T1 | Self::T2 | Self::T4)
    }
}

/// A penetration edge: the part `t[0]..=t[1]` (0 at `vertices[0]`, 1 at `vertices[1]`) of
/// the parent edge `edge` of block `side` that lies inside the other block widened by the gap.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PenetrationEdge {
    /// The block that owns the parent edge.
    pub side: Side,
    /// The parent edge (index into its block's edges).
    pub edge: u32,
    /// Parameters of the two ends along the parent edge, `t[0] <= t[1]`.
    pub t: [f64; 2],
    /// The nature of each end.
    pub ends: [EdgeEnd; 2],
    /// Table 1 type.
    pub kind: PenetrationEdgeType,
    /// The type the classification reads it as, with the parameter of the point it stands
    /// for when that is a type 5 ([`PenetrationEdge::stands_for`]).
    #[serde(skip)]
    pub(crate) standing: (PenetrationEdgeType, f64),
}

/// A penetration edge as the clipping makes it, for a consumer that reads it at once (the
/// classification): its block, parent edge, Table 1 type, parameters, the face that cuts
/// each end ([`NO_CUT`]: the end is the parent's vertex; a plain number is cheaper to test
/// in the classification's inner loop than an [`EdgeEnd`]), and the faces near each of the
/// parent's two vertices ([`VertexMasks::near`]; zero when the table has no masks).
pub(crate) struct Piece<'a> {
    pub(crate) side: Side,
    pub(crate) parent: &'a Edge,
    pub(crate) kind: PenetrationEdgeType,
    pub(crate) t: [f64; 2],
    cut: [u32; 2],
    pub(crate) near: [u64; 2],
    /// What the classification reads the piece as ([`PenetrationEdge::stands_for`]).
    pub(crate) standing: (PenetrationEdgeType, f64),
}

impl Piece<'_> {
    /// Whether end `k` is a cut (else the parent's vertex `k`).
    #[inline(always)]
    pub(crate) fn is_cut(&self, k: usize) -> bool {
        self.cut[k] != NO_CUT
    }

    /// The nature of each end.
    #[inline(always)]
    fn ends(&self) -> [EdgeEnd; 2] {
        let end = |k: usize| match self.cut[k] {
            NO_CUT => EdgeEnd::Vertex(self.parent.vertices[k]),
            f => EdgeEnd::Cut(f),
        };
        [end(0), end(1)]
    }

    /// The penetration edge, its parent being edge `e` of its block.
    #[inline(always)]
    fn edge(&self, e: usize) -> PenetrationEdge {
        PenetrationEdge {
            side: self.side,
            edge: e as u32,
            t: self.t,
            ends: self.ends(),
            kind: self.kind,
            standing: self.standing,
        }
    }
}

/// What a consumer of the penetration edges of a pair is told as each one is made: the
/// piece, and the distance table of its owner's vertices to the other block's planes. The
/// classification reads them as they come: no second pass, nothing looked up again.
pub(crate) trait EdgeSink {
    /// One penetration edge.
    fn edge(&mut self, piece: &Piece<'_>, table: &DistanceTable);
}

/// No consumer.
impl EdgeSink for () {
    #[inline(always)]
    fn edge(&mut self, _: &Piece<'_>, _: &DistanceTable) {}
}

/// Appends to `out` the penetration edges of `of`'s edges inside `other` widened by `gap`
/// (`table` holds the distances of `of`'s vertices to `other`'s planes), telling `sink` of
/// each until one goes deeper than `gap` into `other` (strictly), which settles the pair.
/// Returns whether one does: an edge deeper than the gap is a penetration edge too, so only
/// the surviving edges need that second test.
#[inline(always)]
pub(crate) fn clip_edges(
    of: &ConvexBlock,
    side: Side,
    other: &ConvexBlock,
    table: &DistanceTable,
    th: Thresholds,
    out: &mut Vec<PenetrationEdge>,
    sink: &mut impl EdgeSink,
) -> bool {
    let edges = of.edges();
    let mut deep = false;
    if !table.masked() {
        for (e, edge) in edges.iter().enumerate() {
            let [v1, v2] = edge.vertices;
            if let Some((c, d)) = clip::unmasked(table, other.n_faces(), v1, v2, th.gap) {
                deep |= d;
                let masks = [VertexMasks::default(); 2];
                keep(of, side, (e, edge), c, masks, th, table, deep, out, sink);
            }
        }
        return deep;
    }
    for (chunk, first) in edges.chunks(64).zip((0..).step_by(64)) {
        for k in Bits(clip::survivors(table, chunk)) {
            let edge = &chunk[k];
            let [v1, v2] = edge.vertices;
            let masks = [table.vertex_masks(v1), table.vertex_masks(v2)];
            if let Some(c) = clip::masked(table, masks, v1, v2, th.gap) {
                deep = deep || clip::masked_deep(table, masks, v1, v2, th.gap);
                keep(
                    of,
                    side,
                    (first + k, edge),
                    c,
                    masks,
                    th,
                    table,
                    deep,
                    out,
                    sink,
                );
            }
        }
    }
    deep
}

/// Stores the penetration edge of edge `e` clipped to `c`, and tells `sink` of it unless a
/// deep edge has settled the pair.
#[allow(clippy::too_many_arguments)] // one call site per path of `clip_edges`, inlined
#[inline(always)]
fn keep(
    of: &ConvexBlock,
    side: Side,
    (e, parent): (usize, &Edge),
    c: Clipped,
    masks: [VertexMasks; 2],
    th: Thresholds,
    table: &DistanceTable,
    deep: bool,
    out: &mut Vec<PenetrationEdge>,
    sink: &mut impl EdgeSink,
) {
    let piece = piece(of, side, parent, c, masks, th, (!deep).then_some(table));
    if !deep {
        sink.edge(&piece, table);
    }
    out.push(piece.edge(e));
}

/// The piece of `parent` left by the clipping `c`.
#[inline(always)]
fn piece<'a>(
    of: &ConvexBlock,
    side: Side,
    parent: &'a Edge,
    c: Clipped,
    masks: [VertexMasks; 2],
    th: Thresholds,
    table: Option<&DistanceTable>,
) -> Piece<'a> {
    // Two original vertices make a type 1 whatever the length; a cut piece well below the
    // threshold at the block's diagonal (no edge is longer: the gap's stubs) has no length,
    // known without the edge's vertices.
    let piece = c.t[1] - c.t[0];
    let (mut length_squared, mut piece_squared) = (0.0, 0.0);
    let has_length = c.cut != [NO_CUT; 2] && 2.0 * piece * of.size() > th.length && {
        let [v1, v2] = parent.vertices;
        let edge_vector = of.vertices()[v2 as usize] - of.vertices()[v1 as usize];
        length_squared = edge_vector.length_squared();
        piece_squared = piece * piece * length_squared;
        piece_squared > th.length * th.length
    };
    let mut piece = Piece {
        side,
        parent,
        kind: PenetrationEdgeType::T1,
        t: c.t,
        cut: c.cut,
        near: masks.map(|m| m.near),
        standing: (PenetrationEdgeType::T1, 0.0),
    };
    piece.kind = PenetrationEdgeType::of(piece.ends(), has_length);
    // A cut piece with length may be no more than the gap's bands at faces its edge crosses
    // (not looked at once an edge deeper than the gap settles the pair: `table` is `None`).
    piece.standing = match table {
        Some(table) if has_length && grazing::may_graze(piece_squared, th) => {
            grazing::standing(table, parent, &c, piece.kind, length_squared, th)
        }
        _ => (piece.kind, 0.5 * (c.t[0] + c.t[1])),
    };
    piece
}

impl PenetrationEdge {
    /// The Table 1 type the classification reads the piece as: its own, except that a piece
    /// with length that the gap's bands at the face planes its edge crosses (rather than lies
    /// in) leave without length reads as a type 3 (its original vertex) or a type 5; with the
    /// parameter of the point a type 5 stands for (the middle of a type 5 piece, the deepest
    /// point between the two cutting planes of a type 4 read so). docs/tolerance.md, "Lies in".
    /// The pieces made after an edge deeper than the gap has settled the pair (penetrating:
    /// no classification) keep their own type.
    pub fn stands_for(&self) -> (PenetrationEdgeType, f64) {
        self.standing
    }

    /// The two end points of the piece.
    pub fn points(&self, owner: &ConvexBlock) -> [crate::geometry::DVec3; 2] {
        let e = owner.edges()[self.edge as usize];
        let (p, q) = (
            owner.vertices()[e.vertices[0] as usize],
            owner.vertices()[e.vertices[1] as usize],
        );
        let at = |k: usize| match self.ends[k] {
            EdgeEnd::Vertex(v) => owner.vertices()[v as usize],
            EdgeEnd::Cut(_) => p + (q - p) * self.t[k],
        };
        [at(0), at(1)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::test_rng::{polytope, Rng};
    use crate::{Detector, Tolerance};

    /// The penetration edges of `of` in `other` by the clipping of every edge against
    /// every face (no masks), and whether one is deeper than the gap.
    fn unmasked(
        of: &ConvexBlock,
        side: Side,
        other: &ConvexBlock,
        th: Thresholds,
    ) -> Option<(Vec<PenetrationEdge>, bool)> {
        let mut table = DistanceTable::default();
        if !table.fill(Kernel::detect(), of, other, th) {
            return None;
        }
        table.unmask();
        let mut out = Vec::new();
        let deep = clip_edges(of, side, other, &table, th, &mut out, &mut ());
        Some((out, deep))
    }

    /// The masks only skip faces that cannot cut an edge: with and without them, the same
    /// penetration edges come out, for blocks under and over the mask's width of faces.
    #[test]
    fn masks_change_no_penetration_edge() {
        let mut rng = Rng(17);
        let mut compared = 0;
        for round in 0..400 {
            let faces = [6, 12, 16, 17, 24][round % 5];
            let a = polytope(&mut rng, faces, [0.0; 3], None);
            let d = 1.2 + 0.6 * rng.unit();
            let centre = [d * rng.signed(), d * rng.signed(), d];
            let b = polytope(&mut rng, faces, centre, None);
            let mut det = Detector::new(Tolerance::default());
            det.detect(&a, &b);
            let th = det.thresholds(&a, &b);
            let (Some((mut edges, _)), Some((of_b, _))) =
                (unmasked(&a, Side::A, &b, th), unmasked(&b, Side::B, &a, th))
            else {
                continue;
            };
            edges.extend(of_b);
            let masked = det.penetration_edges();
            assert_eq!(masked.len(), edges.len(), "round {round}");
            for (m, u) in masked.iter().zip(&edges) {
                assert_eq!(
                    (m.side, m.edge, m.kind),
                    (u.side, u.edge, u.kind),
                    "round {round}"
                );
                assert!((m.t[0] - u.t[0]).abs() < 1e-12 && (m.t[1] - u.t[1]).abs() < 1e-12);
            }
            compared += !edges.is_empty() as usize;
        }
        assert!(
            compared > 50,
            "only {compared} pairs with penetration edges"
        );
    }
}
