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

/// Signed distances of one block's vertices to the other block's face planes, face-major
/// in groups of four vertices: `table[f * quads + v / 4][v % 4]`, with bit masks of the
/// faces that each vertex is outside of (`s > gap`) and of the faces it is not deep inside
/// of (`s >= -gap`), when the other block has at most [`MASK_FACES`] faces. The masks
/// reject most edges with one `and` (for the clipping and for the deeper-than-the-gap test)
/// and let both visit only the faces that cut an edge.
///
/// The masks are built as one word per group of four vertices, a nibble per face (bit
/// `4 f + k` for vertex `4 c + k` of group `c`): that is the shape in which the comparisons
/// of one face with four vertices come out, so they are built while the distances are
/// computed, with a shift and an `or` per face and group; once no plane separates, each
/// vertex's mask is taken out of its group's word (a shift and an `and`) for the edges.
#[derive(Default, Clone, Debug)]
pub(crate) struct DistanceTable {
    table: Vec<[f64; 4]>,
    quads: usize,
    /// Nibble masks, one word per group of four vertices.
    groups: Vec<[u64; 2]>,
    /// Per-vertex masks `[outside, shallow]`, expanded from the groups' once the table is
    /// known not to separate (each vertex is asked about once per edge at it).
    vertices: Vec<[u64; 2]>,
    masked: bool,
}

/// Faces beyond this count are clipped without masks (a nibble per face in a `u64`).
const MASK_FACES: usize = 16;

/// The bit of vertex 0 of a group in each face's nibble.
const NIBBLE_LOW_BITS: u64 = 0x1111_1111_1111_1111;

impl DistanceTable {
    /// Fills the table with the distances of `of`'s vertices to `to`'s planes, and the
    /// masks; returns `false` as soon as one plane has every vertex farther than `gap`
    /// (separation).
    pub(crate) fn fill(&mut self, of: &ConvexBlock, to: &ConvexBlock, gap: f64) -> bool {
        let local = of.local();
        let quads = local.quads.as_slice();
        let planes = to.planes();
        self.quads = quads.len();
        self.masked = planes.len() <= MASK_FACES;
        let needed = planes.len() * quads.len();
        if self.table.len() < needed {
            self.table.resize(needed, [0.0; 4]);
        }
        if self.groups.len() < quads.len() {
            self.groups.resize(quads.len(), [0; 2]);
            self.vertices.resize(4 * quads.len(), [0; 2]);
        }
        let groups = &mut self.groups[..quads.len()];
        groups.fill([0; 2]);
        // Coordinates local to one vertex: `n · (v - o) - n · (p - o)` keeps the accuracy of
        // `n · (v - p)` (differences of nearby coordinates) with one dot product per vertex.
        let origin = local.origin;
        let rows = self.table[..needed].chunks_exact_mut(quads.len().max(1));
        for (f, (plane, row)) in planes.iter().zip(rows).enumerate() {
            let n = plane.normal;
            let plane = [n.x, n.y, n.z, n.dot(plane.point - origin)];
            // Faces past the mask's width shift out of the word (masks unused then).
            let shift = (4 * f) as u32;
            let mut separating = true;
            for ((quad, out), group) in quads.iter().zip(row.iter_mut()).zip(groups.iter_mut()) {
                let s = distances(quad, &plane);
                *out = s;
                let beyond = above(&s, gap);
                separating &= beyond == 0b1111;
                group[0] |= beyond.checked_shl(shift).unwrap_or(0);
                group[1] |= at_least(&s, -gap).checked_shl(shift).unwrap_or(0);
            }
            if separating {
                return false;
            }
        }
        let vertices = self.vertices.chunks_exact_mut(4).zip(groups.iter());
        for (four, group) in vertices {
            for (k, v) in four.iter_mut().enumerate() {
                *v = group.map(|g| (g >> k) & NIBBLE_LOW_BITS);
            }
        }
        true
    }

    #[inline]
    fn get(&self, face: usize, vertex: u32) -> f64 {
        self.table[face * self.quads + (vertex >> 2) as usize][(vertex & 3) as usize]
    }

    /// The parameter interval of edge `(v1, v2)` where `s <= gap` on every face, with the
    /// face that cuts each end.
    #[inline]
    fn clip(&self, n_faces: usize, v1: u32, v2: u32, gap: f64) -> Option<Clipped> {
        if !self.masked {
            return self.clip_faces(0..n_faces, v1, v2, gap, false);
        }
        let (m1, m2) = (self.vertices[v1 as usize][0], self.vertices[v2 as usize][0]);
        if m1 & m2 != 0 {
            return None;
        }
        self.clip_crossing(FaceBits(m1 | m2), v1, v2, gap)
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
        let (m1, m2) = (self.vertices[v1 as usize][1], self.vertices[v2 as usize][1]);
        m1 & m2 == 0
            && self
                .clip_faces(FaceBits(m1 | m2), v1, v2, -gap, true)
                .is_some()
    }

    /// Clips against faces that each have exactly one end of the edge outside (as the masks
    /// give them): each cuts the edge once, where `t = |d1| / (|d1| + |d2|)`. The latest entry
    /// and the earliest exit are chosen without branches (fractions compared by
    /// cross-multiplication, one division per end), since which face cuts where is
    /// unpredictable.
    #[inline]
    fn clip_crossing(&self, faces: FaceBits, v1: u32, v2: u32, gap: f64) -> Option<Clipped> {
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

/// Bit `k` set where `s[k] > t` (false for NaN).
#[inline]
fn above(s: &[f64; 4], t: f64) -> u64 {
    compare::<false>(s, t)
}

/// Bit `k` set where `s[k] >= t` (false for NaN).
#[inline]
fn at_least(s: &[f64; 4], t: f64) -> u64 {
    compare::<true>(s, t)
}

/// Bit `k` set where `s[k] > t`, or `s[k] >= t` when `EQUAL`.
#[inline]
fn compare<const EQUAL: bool>(s: &[f64; 4], t: f64) -> u64 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
    {
        // Two vector comparisons and their sign masks, where the compiler would otherwise
        // compare and assemble the bits one by one.
        use std::arch::x86_64::*;
        // SAFETY: value-only SSE2 intrinsics (no memory access); SSE2 is enabled (cfg).
        unsafe {
            let t = _mm_set1_pd(t);
            let cmp = |v| {
                if EQUAL {
                    _mm_cmpge_pd(v, t)
                } else {
                    _mm_cmpgt_pd(v, t)
                }
            };
            let lo = _mm_movemask_pd(cmp(_mm_set_pd(s[1], s[0])));
            let hi = _mm_movemask_pd(cmp(_mm_set_pd(s[3], s[2])));
            (lo | hi << 2) as u64
        }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
    {
        nibble(s.map(|s| if EQUAL { s >= t } else { s > t }))
    }
}

/// The four comparisons of a group of vertices as the low four bits of a word.
#[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
#[inline]
fn nibble(b: [bool; 4]) -> u64 {
    b[0] as u64 | (b[1] as u64) << 1 | (b[2] as u64) << 2 | (b[3] as u64) << 3
}

/// Signed distances of four vertices to a plane `[normal, offset]`.
#[inline]
fn distances(quad: &Quad, &[nx, ny, nz, offset]: &[f64; 4]) -> [f64; 4] {
    std::array::from_fn(|k| nx * quad.x[k] + ny * quad.y[k] + nz * quad.z[k] - offset)
}

/// The faces of a vertex mask (bit `4 f` for face `f`), lowest first.
struct FaceBits(u64);

impl Iterator for FaceBits {
    type Item = usize;
    #[inline]
    fn next(&mut self) -> Option<usize> {
        (self.0 != 0).then(|| {
            let i = self.0.trailing_zeros() as usize;
            self.0 &= self.0 - 1;
            i >> 2
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::test_rng::Rng;
    use crate::{Detector, Tolerance};

    /// A random convex block: `n` planes tangent to the unit sphere about `centre`.
    fn polytope(rng: &mut Rng, n: usize, centre: [f64; 3]) -> ConvexBlock {
        loop {
            let normals: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    let v = [rng.signed(), rng.signed(), rng.signed()];
                    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    v.map(|c| c / len)
                })
                .collect();
            let offsets: Vec<f64> = normals
                .iter()
                .map(|m| 1.0 + m[0] * centre[0] + m[1] * centre[1] + m[2] * centre[2])
                .collect();
            if let Ok(block) = ConvexBlock::from_planes(&normals, &offsets) {
                return block;
            }
        }
    }

    /// The penetration edges of `of` in `other` by the clipping of every edge against
    /// every face (no masks), and whether one is deeper than the gap.
    fn unmasked(
        of: &ConvexBlock,
        side: Side,
        other: &ConvexBlock,
        th: Thresholds,
    ) -> Option<(Vec<PenetrationEdge>, bool)> {
        let mut table = DistanceTable::default();
        if !table.fill(of, other, th.gap) {
            return None;
        }
        table.masked = false;
        let mut out = Vec::new();
        let deep = clip_edges(of, side, other, &table, th, &mut out);
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
            let a = polytope(&mut rng, faces, [0.0; 3]);
            let d = 1.2 + 0.6 * rng.unit();
            let centre = [d * rng.signed(), d * rng.signed(), d];
            let b = polytope(&mut rng, faces, centre);
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
