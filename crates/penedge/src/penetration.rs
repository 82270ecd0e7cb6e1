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

use crate::block::{ConvexBlock, Quad};
use crate::tolerance::Thresholds;

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
}

/// Signed distances of one block's vertices to the other block's face planes, face-major:
/// `table[f * stride + v]` (`stride` the vertex count rounded up to 4), with per-vertex bit
/// masks of the faces that the vertex is outside of (`s > gap`) and of the faces it is not
/// deep inside of (`s >= -gap`), when the other block has at most 64 faces. The masks
/// reject most edges with one `and` (for the clipping and for the deeper-than-the-gap test)
/// and let both visit only the faces that cut an edge.
#[derive(Default, Clone, Debug)]
pub(crate) struct DistanceTable {
    table: Vec<f64>,
    stride: usize,
    outside: Vec<u64>,
    shallow: Vec<u64>,
    masked: bool,
}

/// Faces beyond this count are clipped without masks.
const MASK_FACES: usize = 64;

impl DistanceTable {
    /// Fills the table with the distances of `of`'s vertices to `to`'s planes; returns
    /// `false` as soon as one plane has every vertex farther than `gap` (separation). The
    /// masks are left for [`DistanceTable::build_masks`], once neither table separates.
    pub(crate) fn fill(&mut self, of: &ConvexBlock, to: &ConvexBlock, gap: f64) -> bool {
        let local = of.local();
        // Coordinates local to one vertex: `n · (v - o) - n · (p - o)` keeps the accuracy of
        // `n · (v - p)` (differences of nearby coordinates) with one dot product per vertex.
        let origin = local.origin;
        let stride = 4 * local.quads.len();
        self.stride = stride;
        self.table.resize(to.n_faces() * stride, 0.0);
        for (plane, row) in to.planes().iter().zip(self.table.chunks_exact_mut(stride)) {
            let n = plane.normal;
            let plane = [n.x, n.y, n.z, n.dot(plane.point - origin)];
            let mut separating = true;
            for (quad, out) in local.quads.iter().zip(row.chunks_exact_mut(4)) {
                let s = distances(quad, &plane);
                out.copy_from_slice(&s);
                // `&`, not `all`: no branch per vertex.
                separating &= s.iter().fold(true, |all, &s| all & (s > gap));
            }
            if separating {
                return false;
            }
        }
        true
    }

    /// Per-vertex masks of the faces a vertex is outside of (`s > gap`) and of those it is
    /// not deeper than the gap inside of (`s >= -gap`); none when the other block has more
    /// than 64 faces. Four vertices at a time, with the masks in registers, so that the
    /// comparisons vectorise.
    pub(crate) fn build_masks(&mut self, n_faces: usize, gap: f64) {
        self.masked = n_faces <= MASK_FACES;
        if !self.masked {
            return;
        }
        let stride = self.stride;
        self.outside.resize(stride, 0);
        self.shallow.resize(stride, 0);
        let masks = self
            .outside
            .chunks_exact_mut(4)
            .zip(self.shallow.chunks_exact_mut(4));
        for (c, (outside, shallow)) in masks.enumerate() {
            let (mut out, mut sh) = ([0u64; 4], [0u64; 4]);
            for (f, row) in self.table.chunks_exact(stride).enumerate() {
                let s: &[f64; 4] = row[4 * c..][..4].try_into().unwrap();
                let bit = 1u64 << f;
                for k in 0..4 {
                    out[k] |= bit & all_ones(gap < s[k]);
                    sh[k] |= bit & all_ones(s[k] >= -gap);
                }
            }
            outside.copy_from_slice(&out);
            shallow.copy_from_slice(&sh);
        }
    }

    #[inline]
    fn get(&self, face: usize, vertex: u32) -> f64 {
        self.table[face * self.stride + vertex as usize]
    }

    /// The parameter interval of edge `(v1, v2)` where `s <= gap` on every face, with the
    /// face that cuts each end.
    #[inline]
    fn clip(&self, n_faces: usize, v1: u32, v2: u32, gap: f64) -> Option<Clipped> {
        if !self.masked {
            return self.clip_faces(0..n_faces, v1, v2, gap, false);
        }
        let (m1, m2) = (self.outside[v1 as usize], self.outside[v2 as usize]);
        if m1 & m2 != 0 {
            return None;
        }
        self.clip_crossing(BitIter(m1 | m2), v1, v2, gap)
    }

    /// Whether part of edge `(v1, v2)` has `s < -gap` on every face (deeper than the gap
    /// inside the other block). Faces with both ends strictly deeper constrain nothing, so
    /// with masks only the others are visited, and a face with both ends not deeper (the
    /// usual case for touching blocks) answers at once.
    #[inline]
    fn deep(&self, n_faces: usize, v1: u32, v2: u32, gap: f64) -> bool {
        if !self.masked {
            return self.clip_faces(0..n_faces, v1, v2, -gap, true).is_some();
        }
        let (m1, m2) = (self.shallow[v1 as usize], self.shallow[v2 as usize]);
        m1 & m2 == 0
            && self
                .clip_faces(BitIter(m1 | m2), v1, v2, -gap, true)
                .is_some()
    }

    /// Clips against faces that each have exactly one end of the edge outside (as the masks
    /// give them): each cuts the edge once, where `t = |d1| / (|d1| + |d2|)`. The latest entry
    /// and the earliest exit are chosen without branches (fractions compared by
    /// cross-multiplication, one division per end), since which face cuts where is
    /// unpredictable.
    #[inline]
    fn clip_crossing(&self, faces: BitIter, v1: u32, v2: u32, gap: f64) -> Option<Clipped> {
        let (mut entry, mut exit) = (Fraction::ZERO, Fraction::ONE);
        let (mut entry_face, mut exit_face) = (u32::MAX, u32::MAX);
        for f in faces {
            let d1 = self.get(f, v1) - gap;
            let d2 = self.get(f, v2) - gap;
            let t = Fraction {
                num: d1.abs(),
                den: d1.abs() + d2.abs(),
            };
            let entering = d1 > 0.0;
            let take_entry = entering & t.above(entry);
            let take_exit = !entering & exit.above(t);
            entry = if take_entry { t } else { entry };
            entry_face = if take_entry { f as u32 } else { entry_face };
            exit = if take_exit { t } else { exit };
            exit_face = if take_exit { f as u32 } else { exit_face };
        }
        let t = [entry.value(), exit.value()];
        let cut = |f: u32| (f != u32::MAX).then_some(f);
        (t[0] <= t[1]).then_some(Clipped {
            t,
            cut: [cut(entry_face), cut(exit_face)],
        })
    }

    /// Clips against the given faces only (the others keep both ends inside).
    #[inline]
    fn clip_faces(
        &self,
        faces: impl Iterator<Item = usize>,
        v1: u32,
        v2: u32,
        offset: f64,
        strict: bool,
    ) -> Option<Clipped> {
        let mut c = Clipped {
            t: [0.0, 1.0],
            cut: [None, None],
        };
        for f in faces {
            let d1 = self.get(f, v1) - offset;
            let d2 = self.get(f, v2) - offset;
            let (out1, out2) = if strict {
                (d1 >= 0.0, d2 >= 0.0)
            } else {
                (d1 > 0.0, d2 > 0.0)
            };
            if out1 && out2 {
                return None;
            }
            if out1 == out2 {
                continue;
            }
            let t = d1 / (d1 - d2);
            if out1 {
                if t > c.t[0] {
                    c.t[0] = t;
                    c.cut[0] = Some(f as u32);
                }
            } else if t < c.t[1] {
                c.t[1] = t;
                c.cut[1] = Some(f as u32);
            }
        }
        let keep = if strict {
            c.t[0] < c.t[1]
        } else {
            c.t[0] <= c.t[1]
        };
        keep.then_some(c)
    }
}

/// All ones for `true`, zero for `false`: the form of a vector comparison's result, so
/// that the mask updates vectorise.
#[inline]
fn all_ones(b: bool) -> u64 {
    (b as u64).wrapping_neg()
}

/// Signed distances of four vertices to a plane `[normal, offset]`.
#[inline]
fn distances(quad: &Quad, &[nx, ny, nz, offset]: &[f64; 4]) -> [f64; 4] {
    std::array::from_fn(|k| nx * quad.x[k] + ny * quad.y[k] + nz * quad.z[k] - offset)
}

/// The indices of the set bits of a mask, lowest first.
struct BitIter(u64);

impl Iterator for BitIter {
    type Item = usize;
    #[inline]
    fn next(&mut self) -> Option<usize> {
        (self.0 != 0).then(|| {
            let i = self.0.trailing_zeros() as usize;
            self.0 &= self.0 - 1;
            i
        })
    }
}

/// A non-negative fraction with a positive denominator.
#[derive(Clone, Copy)]
struct Fraction {
    num: f64,
    den: f64,
}

impl Fraction {
    const ZERO: Fraction = Fraction { num: 0.0, den: 1.0 };
    const ONE: Fraction = Fraction { num: 1.0, den: 1.0 };

    #[inline]
    fn above(self, other: Fraction) -> bool {
        self.num * other.den > other.num * self.den
    }

    #[inline]
    fn value(self) -> f64 {
        self.num / self.den
    }
}

struct Clipped {
    t: [f64; 2],
    cut: [Option<u32>; 2],
}

/// Appends to `out` the penetration edges of `of`'s edges inside `other` widened by `gap`
/// (`table` holds the distances of `of`'s vertices to `other`'s planes). Returns whether one
/// of them goes deeper than `gap` into `other` (strictly): an edge deeper than the gap is a
/// penetration edge too, so only the surviving edges need that second test.
pub(crate) fn clip_edges(
    of: &ConvexBlock,
    side: Side,
    other: &ConvexBlock,
    table: &DistanceTable,
    th: Thresholds,
    out: &mut Vec<PenetrationEdge>,
) -> bool {
    let n_faces = other.n_faces();
    let mut deep = false;
    for (e, edge) in of.edges().iter().enumerate() {
        let [v1, v2] = edge.vertices;
        let Some(c) = table.clip(n_faces, v1, v2, th.gap) else {
            continue;
        };
        deep = deep || table.deep(n_faces, v1, v2, th.gap);
        out.push(piece(of, side, e, c, th));
    }
    deep
}

/// The penetration edge of `of`'s edge `e` from its clipped interval.
#[inline]
fn piece(of: &ConvexBlock, side: Side, e: usize, c: Clipped, th: Thresholds) -> PenetrationEdge {
    let [v1, v2] = of.edges()[e].vertices;
    let end = |k: usize, v: u32| c.cut[k].map_or(EdgeEnd::Vertex(v), EdgeEnd::Cut);
    let ends = [end(0, v1), end(1, v2)];
    let edge_vector = of.vertices()[v2 as usize] - of.vertices()[v1 as usize];
    let piece = c.t[1] - c.t[0];
    let has_length = piece * piece * edge_vector.length_squared() > th.length * th.length;
    PenetrationEdge {
        side,
        edge: e as u32,
        t: c.t,
        ends,
        kind: PenetrationEdgeType::of(ends, has_length),
    }
}

impl PenetrationEdge {
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
