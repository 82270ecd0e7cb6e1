//! Clipping one block's edges by the other block's face planes, read from the distance
//! table: the parameter interval of each edge inside the other block widened by the gap.

use super::table::{DistanceTable, VertexMasks};
use crate::block::{Bits, Edge};

/// The face of an end that no face cuts.
pub(super) const NO_CUT: u32 = u32::MAX;

/// The part `t[0]..=t[1]` of an edge that survives, with the face that cuts each end
/// ([`NO_CUT`]: the end is the edge's own vertex).
pub(super) struct Clipped {
    pub(super) t: [f64; 2],
    pub(super) cut: [u32; 2],
}

/// The edges of a block (at most 64 at a time) that the masks do not reject: bit `k` set
/// where no face has both ends of edge `k` outside. Built without branches, since which
/// edges survive is unpredictable; the survivors are then visited in order.
#[inline]
pub(super) fn survivors(table: &DistanceTable, edges: &[Edge]) -> u64 {
    debug_assert!(edges.len() <= 64);
    let mut bits = 0;
    for (k, edge) in edges.iter().enumerate() {
        let [v1, v2] = edge.vertices;
        let outside = table.vertex_masks(v1).outside & table.vertex_masks(v2).outside;
        bits |= ((outside == 0) as u64) << k;
    }
    bits
}

/// The piece of edge `(v1, v2)` where `s <= gap` on every face, for an edge the masks did
/// not reject: only the faces with one end outside cut it, each once, where
/// `t = |d1| / (|d1| + |d2|)`: the edge enters the other block through the faces `v1` is
/// outside of (the latest entry is kept) and leaves it through those `v2` is outside of
/// (the earliest exit). Fractions are compared by cross-multiplication, with one division
/// per end; which face cuts where is unpredictable, so the choice is made without branches.
#[inline(always)]
pub(super) fn masked(
    table: &DistanceTable,
    [m1, m2]: [VertexMasks; 2],
    v1: u32,
    v2: u32,
    gap: f64,
) -> Option<Clipped> {
    let cut_at = |f: usize| {
        let d1 = table.get(f, v1) - gap;
        let d2 = table.get(f, v2) - gap;
        Fraction {
            num: d1.abs(),
            den: d1.abs() + d2.abs(),
        }
    };
    let (entry, entry_face) = pick(m1.outside, Fraction::ZERO, cut_at, |t, entry| {
        t.above(entry)
    });
    let (exit, exit_face) = pick(m2.outside, Fraction::ONE, cut_at, |t, exit| exit.above(t));
    let t = [entry.value(), exit.value()];
    (t[0] <= t[1]).then_some(Clipped {
        t,
        cut: [entry_face, exit_face],
    })
}

/// The cut `cut_at(f)` of the faces `f` of `mask` that `better` prefers to `start` and to
/// the others, with its face (`NO_CUT`: none, `start` stays); chosen without branches.
#[inline(always)]
fn pick(
    mask: u64,
    start: Fraction,
    cut_at: impl Fn(usize) -> Fraction,
    better: impl Fn(Fraction, Fraction) -> bool,
) -> (Fraction, u32) {
    let (mut best, mut face) = (start, NO_CUT);
    for f in Bits(mask) {
        let t = cut_at(f);
        let wins = better(t, best);
        best = if wins { t } else { best };
        face = if wins { f as u32 } else { face };
    }
    (best, face)
}

/// Whether part of edge `(v1, v2)` has `s < -gap` on every face (deeper than the gap
/// inside the other block). Faces with both ends strictly deeper constrain nothing, so
/// only the others are visited, and a face with both ends not deeper (the usual case for
/// touching blocks) answers at once.
#[inline]
pub(super) fn masked_deep(
    table: &DistanceTable,
    [m1, m2]: [VertexMasks; 2],
    v1: u32,
    v2: u32,
    gap: f64,
) -> bool {
    let (s1, s2) = (m1.shallow, m2.shallow);
    s1 & s2 == 0 && faces(table, Bits(s1 | s2), v1, v2, -gap, true).is_some()
}

/// [`masked`] and [`masked_deep`] for tables without masks: every face is visited.
pub(super) fn unmasked(
    table: &DistanceTable,
    n_faces: usize,
    v1: u32,
    v2: u32,
    gap: f64,
) -> Option<(Clipped, bool)> {
    let clipped = faces(table, 0..n_faces, v1, v2, gap, false)?;
    let deep = faces(table, 0..n_faces, v1, v2, -gap, true).is_some();
    Some((clipped, deep))
}

/// Clips against the given faces only (the others keep both ends inside); `strict` keeps
/// the part with `d < 0` rather than `d <= 0`.
#[inline]
fn faces(
    table: &DistanceTable,
    faces: impl Iterator<Item = usize>,
    v1: u32,
    v2: u32,
    offset: f64,
    strict: bool,
) -> Option<Clipped> {
    let mut c = Clipped {
        t: [0.0, 1.0],
        cut: [NO_CUT; 2],
    };
    for f in faces {
        let d1 = table.get(f, v1) - offset;
        let d2 = table.get(f, v2) - offset;
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
                c.cut[0] = f as u32;
            }
        } else if t < c.t[1] {
            c.t[1] = t;
            c.cut[1] = f as u32;
        }
    }
    let keep = if strict {
        c.t[0] < c.t[1]
    } else {
        c.t[0] <= c.t[1]
    };
    keep.then_some(c)
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
