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

use crate::block::ConvexBlock;
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
        let originals = ends
            .iter()
            .filter(|e| matches!(e, EdgeEnd::Vertex(_)))
            .count();
        match (originals, has_length) {
            (2, _) => PenetrationEdgeType::T1,
            (1, true) => PenetrationEdgeType::T2,
            (1, false) => PenetrationEdgeType::T3,
            (_, true) => PenetrationEdgeType::T4,
            (_, false) => PenetrationEdgeType::T5,
        }
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
/// `table[f * n_vertices + v]`, with per-vertex bit masks of the faces that the vertex is
/// outside of (`s > gap`), when the other block has at most 64 faces. The masks reject most
/// edges with one `and` and let the clipping visit only the faces that cut an edge.
#[derive(Default, Clone, Debug)]
pub(crate) struct DistanceTable {
    table: Vec<f64>,
    n_vertices: usize,
    outside: Vec<u64>,
}

/// Faces beyond this count are clipped without masks.
const MASK_FACES: usize = 64;

impl DistanceTable {
    /// Fills the table with the distances of `of`'s vertices to `to`'s planes; returns
    /// `false` as soon as one plane has every vertex farther than `gap` (separation).
    /// The masks are left for [`DistanceTable::build_masks`], once neither table separates.
    pub(crate) fn fill(&mut self, of: &ConvexBlock, to: &ConvexBlock, gap: f64) -> bool {
        let n = of.vertices().len();
        self.n_vertices = n;
        // Coordinates local to one vertex: `n · (v - o) - n · (p - o)` keeps the accuracy of
        // `n · (v - p)` (differences of nearby coordinates) with one dot product per vertex.
        let local = of.local();
        let origin = local.origin;
        self.table.resize(to.n_faces() * n, 0.0);
        let [xs, ys, zs] = &local.xyz;
        let (xs, ys, zs) = (&xs[..n], &ys[..n], &zs[..n]);
        for (plane, row) in to.planes().iter().zip(self.table.chunks_exact_mut(n)) {
            let normal = plane.normal;
            let offset = normal.dot(plane.point - origin);
            // Structure of arrays, so that the loop vectorises.
            let mut separating = true;
            for i in 0..n {
                row[i] = normal.x * xs[i] + normal.y * ys[i] + normal.z * zs[i] - offset;
                separating &= row[i] > gap;
            }
            if separating {
                return false;
            }
        }
        true
    }

    /// Per-vertex masks of the faces a vertex is outside of (`s > gap`); none when the other
    /// block has more than 64 faces.
    pub(crate) fn build_masks(&mut self, n_faces: usize, gap: f64) {
        let n = self.n_vertices;
        self.outside.clear();
        if n_faces > MASK_FACES {
            return;
        }
        self.outside.resize(n, 0);
        let outside = &mut self.outside[..n];
        for (f, row) in self.table.chunks_exact(n).enumerate() {
            for i in 0..n {
                outside[i] |= ((row[i] > gap) as u64) << f;
            }
        }
    }

    #[inline]
    fn get(&self, face: usize, vertex: u32) -> f64 {
        self.table[face * self.n_vertices + vertex as usize]
    }

    /// The parameter interval of edge `(v1, v2)` where `s <= gap` on every face
    /// (`deep == false`), or `s < -gap` (`deep == true`), with the face that cuts each end.
    /// The masks serve the first test; the second runs only on edges that passed it, and
    /// usually stops at the first face.
    #[inline]
    fn clip(&self, n_faces: usize, v1: u32, v2: u32, gap: f64, deep: bool) -> Option<Clipped> {
        if deep {
            return self.clip_faces(0..n_faces, v1, v2, -gap, true);
        }
        if self.outside.is_empty() {
            return self.clip_faces(0..n_faces, v1, v2, gap, false);
        }
        let (m1, m2) = (self.outside[v1 as usize], self.outside[v2 as usize]);
        if m1 & m2 != 0 {
            return None;
        }
        self.clip_crossing(BitIter(m1 | m2), v1, v2, gap)
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
        let Some(c) = table.clip(n_faces, v1, v2, th.gap, false) else {
            continue;
        };
        deep = deep || table.clip(n_faces, v1, v2, th.gap, true).is_some();
        let end = |k: usize, v: u32| c.cut[k].map_or(EdgeEnd::Vertex(v), EdgeEnd::Cut);
        let ends = [end(0, v1), end(1, v2)];
        let edge_vector = of.vertices()[v2 as usize] - of.vertices()[v1 as usize];
        let piece = c.t[1] - c.t[0];
        let has_length = piece * piece * edge_vector.length_squared() > th.length * th.length;
        out.push(PenetrationEdge {
            side,
            edge: e as u32,
            t: c.t,
            ends,
            kind: PenetrationEdgeType::of(ends, has_length),
        });
    }
    deep
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
