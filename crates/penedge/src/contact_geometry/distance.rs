//! The contact plane and the signed distance along the normal.

use crate::block::ConvexBlock;
use crate::geometry::DVec3;

/// The plane normal to the contact normal `n`, halfway between the two blocks along `n`,
/// with the signed distance between them.
///
/// With `hA = max n·x` over A's vertices and `hB = min n·y` over B's, the distance is
/// `hB - hA` and the plane is `n·x = (hA + hB) / 2`. Moving B by `t n` moves every
/// vertex of B by `t` along `n`, so the distance grows by exactly `t`. Values are taken
/// relative to a reference point near both blocks, so that distances keep their accuracy
/// far from the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPlane {
    normal: DVec3,
    reference: DVec3,
    offset: f64,
    distance: f64,
}

impl ContactPlane {
    /// The contact plane of `a` and `b` for the unit normal `normal` (from A to B).
    pub fn between(a: &ConvexBlock, b: &ConvexBlock, normal: DVec3) -> ContactPlane {
        let reference = reference(a, b);
        let (_, top_a) = extent(a, normal, reference);
        let (bottom_b, _) = extent(b, normal, reference);
        ContactPlane {
            normal,
            reference,
            offset: (top_a + bottom_b) * 0.5,
            distance: bottom_b - top_a,
        }
    }

    /// The plane through `point` with unit normal `normal`, the blocks `distance` apart
    /// along it (the overlap's common plane, [`crate::overlap`]).
    pub(crate) fn through(point: DVec3, normal: DVec3, distance: f64) -> ContactPlane {
        ContactPlane {
            normal,
            reference: point,
            offset: 0.0,
            distance,
        }
    }

    /// Unit normal from A to B.
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// Signed distance from A to B along the normal: gap (> 0) or depth (< 0).
    pub fn distance(&self) -> f64 {
        self.distance
    }

    /// A point of the plane.
    pub fn origin(&self) -> DVec3 {
        self.reference + self.normal * self.offset
    }

    /// The orthogonal projection of `p` on the plane.
    pub fn project(&self, p: DVec3) -> DVec3 {
        p + self.normal * (self.offset - self.normal.dot(p - self.reference))
    }
}

/// The signed distance from A to B along the unit vector `n`: `min_B n·y - max_A n·x`.
/// Exactly the same for `(a, b, n)` and `(b, a, -n)`.
pub(in crate::contact_geometry) fn separation(a: &ConvexBlock, b: &ConvexBlock, n: DVec3) -> f64 {
    let r = reference(a, b);
    extent(b, n, r).0 - extent(a, n, r).1
}

/// A point near both blocks, the same for `(a, b)` and `(b, a)` (`x + y == y + x`).
fn reference(a: &ConvexBlock, b: &ConvexBlock) -> DVec3 {
    (a.vertices()[0] + b.vertices()[0]) * 0.5
}

/// Smallest and largest `n·(x - r)` over the block's vertices.
pub(crate) fn extent(block: &ConvexBlock, n: DVec3, r: DVec3) -> (f64, f64) {
    block
        .vertices()
        .iter()
        .map(|&x| n.dot(x - r))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
            (lo.min(h), hi.max(h))
        })
}
