//! Representative points as coordinates: the contact geometry builds on them, and the
//! test for two parallel edges needs their extent.

use crate::block::ConvexBlock;
use crate::geometry::DVec3;
use crate::penetration::{EdgeEnd, PenetrationEdge, PenetrationEdgeType, Side};

/// The representative points of one penetration edge (see the module docs): `points[k]`
/// where bit `k` of the mask is set; as the classification reads the edge
/// ([`PenetrationEdge::stands_for`]), or with `widened` by its own type (every stub kept: a
/// face-face contact's polygon). An original vertex comes back once per edge at it:
/// `seen` marks the owner's vertices already given (the first 64), which are left out.
///
/// Both points are computed and the mask says which count, rather than an array filled up
/// to a count: an array indexed by a count lives in memory, and reading back a point just
/// written in two parts stalls the processor (no store-to-load forwarding).
#[inline(always)]
fn representatives(
    pe: &PenetrationEdge,
    owner: &ConvexBlock,
    seen: &mut u64,
    widened: bool,
) -> ([DVec3; 2], u8) {
    let vertices = owner.vertices();
    let [v1, v2] = owner.edges()[pe.edge as usize].vertices;
    let (p, q) = (vertices[v1 as usize], vertices[v2 as usize]);
    let kind = if widened { pe.kind } else { pe.standing.0 };
    let at = |k: usize| match pe.ends[k] {
        EdgeEnd::Vertex(v) => vertices[v as usize],
        EdgeEnd::Cut(_) => p + (q - p) * pe.t[k],
    };
    // Whether end `k` is new: a cut, or a vertex not seen yet (then marked).
    let mut fresh = |k: usize| match pe.ends[k] {
        EdgeEnd::Vertex(v) => {
            let bit = 1u64.checked_shl(v).unwrap_or(0);
            let new = *seen & bit == 0;
            *seen |= bit;
            new as u8
        }
        EdgeEnd::Cut(_) => 1,
    };
    let (ends, mask) = match (kind, pe.ends) {
        (PenetrationEdgeType::T3, [EdgeEnd::Vertex(_), _]) => ([at(0), at(0)], fresh(0)),
        (PenetrationEdgeType::T3, _) => ([at(1), at(1)], fresh(1)),
        (PenetrationEdgeType::T5, _) => {
            let middle = match pe.kind {
                PenetrationEdgeType::T5 => (at(0) + at(1)) * 0.5,
                // A type 4 read as a type 5: the point it stands for.
                _ => p + (q - p) * pe.standing.1,
            };
            ([middle, middle], 1)
        }
        _ => {
            let first = fresh(0);
            ([at(0), at(1)], first | fresh(1) << 1)
        }
    };
    (ends, mask)
}

/// Collects the representative points of the penetration edges (see the module docs); with
/// `widened`, of the pieces as the clipping made them.
pub(crate) fn representative_points(
    a: &ConvexBlock,
    b: &ConvexBlock,
    edges: &[PenetrationEdge],
    widened: bool,
    out: &mut Vec<DVec3>,
) {
    out.clear();
    let mut seen = [0u64; 2];
    for pe in edges {
        let (owner, seen) = side(pe, [a, b], &mut seen);
        // Keep each point once (a cut can fall on a vertex, or two cuts together).
        let ([p, q], mask) = representatives(pe, owner, seen, widened);
        for (k, point) in [p, q].into_iter().enumerate() {
            if mask >> k & 1 != 0 && !out.contains(&point) {
                out.push(point)
            }
        }
    }
}

/// The block that owns a penetration edge, and its entry of `seen`.
#[inline]
fn side<'a, 's>(
    pe: &PenetrationEdge,
    blocks: [&'a ConvexBlock; 2],
    seen: &'s mut [u64; 2],
) -> (&'a ConvexBlock, &'s mut u64) {
    let s = (pe.side == Side::B) as usize;
    (blocks[s], &mut seen[s])
}

/// Whether the representative points of `edges` span more than `length`: some point
/// farther than `length` from the first (the extent of the points above `length`), visited
/// without a list and left at the first such point.
pub(crate) fn spread_exceeds(
    a: &ConvexBlock,
    b: &ConvexBlock,
    edges: &[PenetrationEdge],
    length: f64,
) -> bool {
    let mut seen = [0u64; 2];
    let mut first = None;
    for pe in edges {
        let (owner, seen) = side(pe, [a, b], &mut seen);
        let ([p, q], mask) = representatives(pe, owner, seen, false);
        for (k, point) in [p, q].into_iter().enumerate() {
            if mask >> k & 1 != 0 && point.distance(*first.get_or_insert(point)) > length {
                return true;
            }
        }
    }
    false
}

/// Largest distance of a point from the first one.
#[cfg(test)]
pub(super) fn spread(points: &[DVec3]) -> f64 {
    points
        .iter()
        .map(|p| p.distance(points[0]))
        .fold(0.0, f64::max)
}
