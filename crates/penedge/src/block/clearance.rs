//! How a block's own face planes pass its vertices: within rounding of the faces at each
//! vertex, and well clear of the others. The classification asks which faces of a block
//! pass within the length threshold of a point on its boundary; where the threshold lies
//! between these two bounds, the faces at a vertex (and along an edge) are the answer, read
//! from the topology with no distance computed ([`crate::classify`]).

use super::{DVec3, Plane};

/// Bounds of the distances of a block's vertices to its own face planes, as the
/// classification computes them for points on the block's edges: at most `on` to the plane
/// of a face at the vertex, more than `off` to any other, rounding included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Clearance {
    on: f64,
    off: f64,
}

impl Clearance {
    /// Not known (a block placed by a pose): every test computes its distance.
    pub(crate) const UNKNOWN: Clearance = Clearance {
        on: f64::INFINITY,
        off: 0.0,
    };

    /// The bounds of a block with these vertices, planes and faces at each vertex (bit `f`
    /// of `vertex_faces[v]`; empty: unknown).
    ///
    /// A point along an edge is computed as `p + (q - p) t` and its distance as
    /// `n · (x - c)`: each rounds by a few units of the last place of the coordinates and
    /// of the plane points, so both bounds are widened by 64 such units; between them the
    /// exact distance of a point on an edge is affine in `t`, so it stays within `on` of
    /// the edge's own faces and beyond `off` of the faces at neither end.
    pub(crate) fn of(vertices: &[DVec3], planes: &[Plane], vertex_faces: &[u64]) -> Clearance {
        if vertex_faces.len() != vertices.len() {
            return Clearance::UNKNOWN;
        }
        let (mut on, mut off) = (0.0f64, f64::INFINITY);
        let mut magnitude = 0.0f64;
        for (&v, &at) in vertices.iter().zip(vertex_faces) {
            magnitude = magnitude.max(v.abs().max_element());
            for (f, plane) in planes.iter().enumerate() {
                let d = plane.distance(v).abs();
                if at >> f & 1 == 1 {
                    on = on.max(d);
                } else {
                    off = off.min(d);
                }
            }
        }
        for plane in planes {
            magnitude = magnitude.max(plane.point.abs().max_element());
        }
        let rounding = 64.0 * f64::EPSILON * 2.0 * magnitude;
        let bounds = Clearance {
            on: on + rounding,
            off: off - rounding,
        };
        // NaN (never for a valid block) leaves the bounds unknown.
        if bounds.on.is_nan() || bounds.off.is_nan() {
            Clearance::UNKNOWN
        } else {
            bounds
        }
    }

    /// Whether, at the length threshold `length`, a face of the block passes within
    /// `length` of a vertex exactly when it is a face at that vertex (and of a point along an
    /// edge when it is one of the edge's faces, or a face at one end within `length`).
    #[inline]
    pub(crate) fn decides(&self, length: f64) -> bool {
        self.on <= length && length < self.off
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ConvexBlock;

    #[test]
    fn a_cube_is_decided_between_rounding_and_its_side() {
        let cube = ConvexBlock::cuboid([0.0; 3], [2.0, 1.0, 3.0]).unwrap();
        let c = cube.clearance();
        assert!(c.on < 1e-12 && (c.off - 1.0).abs() < 1e-12, "{c:?}");
        assert!(c.decides(1e-9) && c.decides(0.5) && !c.decides(1.0));
        let far = cube.transformed(glam::DQuat::from_rotation_z(0.3), DVec3::splat(4e6), 1.0);
        let c = far.clearance();
        assert!(c.on < 1e-6 && c.off > 0.999, "{c:?}");
        assert!(!Clearance::UNKNOWN.decides(1e-9));
    }

    #[test]
    fn a_sliver_is_not_decided_at_a_wide_threshold() {
        // A wedge 1e-4 thick at one end: the vertices of that end lie 1e-4 from the plane
        // of the bottom face, which they are not on.
        let wedge = ConvexBlock::from_planes(
            &[
                [0.0, 0.0, -1.0],
                [0.0, -1.0, 0.0],
                [0.0, 1.0, 0.0],
                [-1.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1e-4, 0.0, 1.0],
            ],
            &[0.0, 0.0, 1.0, 0.0, 1.0, 1e-4],
        )
        .unwrap();
        let c = wedge.clearance();
        assert!(c.decides(1e-9), "{c:?}");
        assert!(!c.decides(1e-3), "{c:?}");
    }
}
