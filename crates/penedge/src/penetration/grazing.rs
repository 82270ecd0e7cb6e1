//! What a penetration edge stands for in the classification: one point when what is left of
//! it without the gap's band at the face planes that its edge crosses has no length
//! (docs/tolerance.md, "Lies in").
//!
//! The gap widens the other block by a band `[-g, g]` about each face plane (touching, not
//! penetrating). An edge that crosses a face's plane at an angle `θ` spends `2g / sin θ` of its
//! length in that band, which is the gap's doing, not a contact along the edge: an edge
//! leaving a vertex in contact at a shallow angle keeps a stub that long. An edge *lies in*
//! the face when the sine of its angle to the plane is at most [`Thresholds::sine`] (the
//! length threshold over the pair's scale); then the band is the contact. Otherwise the end
//! that the face's widened plane cuts is moved back to where the edge is the gap inside that
//! plane; when nothing longer than the length threshold is left, the piece stands for one
//! point: its original vertex (type 2 read as a type 3), or, for two cuts, the point where the
//! edge is equally far from both cutting planes, the deepest point between them (type 4 read
//! as a type 5 at that point). Otherwise it stands for its two ends as clipped, like every
//! piece with length.

use super::clip::{Clipped, NO_CUT};
use super::table::DistanceTable;
use super::PenetrationEdgeType;
use crate::block::Edge;
use crate::tolerance::Thresholds;

/// Whether a piece `piece_length_squared` long (squared) can be reduced to a point by the
/// gap's bands: each end moves back by less than `2g / sine`, so a piece longer than
/// `length + 4g / sine` keeps its length whatever its angles (tested as
/// `(L sine)^2 <= (length sine + 4g)^2`, without a division or a square root).
#[inline(always)]
pub(super) fn may_graze(piece_length_squared: f64, th: Thresholds) -> bool {
    let reach = th.length * th.sine + 4.0 * th.gap;
    piece_length_squared * th.sine * th.sine <= reach * reach
}

/// The type the piece `c` of `parent` (of Table 1 type 2 or 4 `kind`, parent's squared length
/// `length_squared`) is read as, with the parameter of the point it stands for when a type 5
/// (module docs): `kind` itself unless the gap's bands leave it without length.
#[cold]
pub(super) fn standing(
    table: &DistanceTable,
    parent: &Edge,
    c: &Clipped,
    kind: PenetrationEdgeType,
    length_squared: f64,
    th: Thresholds,
) -> (PenetrationEdgeType, f64) {
    let [v1, v2] = parent.vertices;
    let distances = |f: u32| (table.get(f as usize, v1), table.get(f as usize, v2));
    let mut t = c.t;
    let mut moved = false;
    for (k, &f) in c.cut.iter().enumerate() {
        if f == NO_CUT {
            continue;
        }
        let (d1, d2) = distances(f);
        // n · (v2 - v1) = d2 - d1: the sine of the edge's angle to the plane is its ratio to
        // the edge's length.
        let rise = d2 - d1;
        if rise * rise <= th.sine * th.sine * length_squared {
            continue;
        }
        // Where the edge is the gap inside the plane.
        t[k] = (d1 + th.gap) / (d1 - d2);
        moved = true;
    }
    let left = t[1] - t[0];
    if !moved || left > 0.0 && left * left * length_squared > th.length * th.length {
        return (kind, 0.0);
    }
    match c.cut {
        [NO_CUT, _] | [_, NO_CUT] => (PenetrationEdgeType::T3, 0.0),
        [entry, exit] => {
            // The deepest point between the two cutting planes: d_entry(t) = d_exit(t).
            let (a1, a2) = distances(entry);
            let (b1, b2) = distances(exit);
            let slopes = (a2 - a1) - (b2 - b1);
            let t = if slopes != 0.0 {
                ((b1 - a1) / slopes).clamp(c.t[0], c.t[1])
            } else {
                0.5 * (c.t[0] + c.t[1])
            };
            (PenetrationEdgeType::T5, t)
        }
    }
}
