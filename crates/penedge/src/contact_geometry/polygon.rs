//! The face-face contact polygon: the convex hull of the representative points on the
//! contact plane.
//!
//! The representative points are the vertices of A ∩ B (with the gap stubs collapsed), so
//! their hull is the contact polygon. It is computed in 2D coordinates `(u, v)` of the
//! contact plane with `u × v = n`, so counter-clockwise in the plane is counter-clockwise
//! about the normal (Andrew's monotone chain). Points within the length threshold of each
//! other are merged, and a point within it of the chord of its neighbours is dropped: the
//! polygon keeps only corners.

use super::{ContactPlane, ContactPoints, ContactPolygon};
use crate::geometry::DVec3;

type P2 = [f64; 2];

/// The convex polygon of `points` on `plane`; a point or a segment when it collapses below
/// the length threshold `length`.
pub(crate) fn convex_polygon(points: &[DVec3], plane: &ContactPlane, length: f64) -> ContactPoints {
    let n = plane.normal();
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let origin = plane.origin();
    let mut flat: Vec<P2> = points
        .iter()
        .map(|&p| [u.dot(p - origin), v.dot(p - origin)])
        .collect();
    flat.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    let hull = hull_ccw(&flat, length);
    let to_3d = |p: &P2| origin + u * p[0] + v * p[1];
    match hull.as_slice() {
        [] => ContactPoints::Point(origin),
        [p] => ContactPoints::Point(to_3d(p)),
        [p, q] => ContactPoints::Segment([to_3d(p), to_3d(q)]),
        _ => ContactPoints::Polygon(ContactPolygon {
            area: area(&hull),
            vertices: hull.iter().map(to_3d).collect(),
        }),
    }
}

/// `(a - o) × (b - o)`: positive when `o, a, b` turn counter-clockwise.
fn cross(o: P2, a: P2, b: P2) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Plain `sqrt(dx² + dy²)`: coordinates are local to the contact, so no overflow guard
/// (`f64::hypot`, a slow library call) is needed.
fn distance(p: P2, q: P2) -> f64 {
    let (dx, dy) = (p[0] - q[0], p[1] - q[1]);
    (dx * dx + dy * dy).sqrt()
}

/// Whether `a` lies more than `tol` to the left of the line from `o` to `b`.
fn turns_left(o: P2, a: P2, b: P2, tol: f64) -> bool {
    cross(o, a, b) > tol * distance(o, b)
}

/// Convex hull of points sorted by `(x, y)`, counter-clockwise, then points within `tol` of
/// each other or of a hull edge dropped ([`simplify`]).
///
/// The chain itself takes exact turns: a tolerance inside it can pop a true corner. The
/// points of an edge parallel to the sorting axis, a few roundings apart in `x`, come in an
/// order that zigzags in `y` (a corner, a point near the opposite corner, then the other
/// corner); with a tolerance the near-collinear middle test pops the corner for good (a
/// rectangle came out as a triangle, half its area, in the rock-bridge example of
/// docs/generation.md).
fn hull_ccw(sorted: &[P2], tol: f64) -> Vec<P2> {
    let mut hull: Vec<P2> = Vec::with_capacity(sorted.len() + 1);
    for pass in [
        &mut sorted.iter() as &mut dyn Iterator<Item = &P2>,
        &mut sorted.iter().rev(),
    ] {
        let start = hull.len();
        for &p in pass {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop(); // the last point of a chain starts the other one
    }
    if hull.is_empty() {
        hull.extend(sorted.first()); // all points equal
    }
    let mut hull = simplify(hull, tol);
    if let [p, q] = hull[..] {
        if distance(p, q) <= tol {
            hull.truncate(1); // all points within `tol` of each other
        }
    }
    hull
}

/// Drops vertices within `tol` of a neighbour or of the chord of their neighbours, one at a
/// time, the one whose corner holds the least area first (`cross(prev, here, next)`, ties to
/// the first), until none is left to drop. The choice does not depend on where the hull
/// starts or in which order it meets two such vertices: a sweep that dropped the first it
/// met made the polygon of a contact flip between two answers as its blocks moved by
/// roundings (of a true corner and a point of its edge within `tol` of it, the one met first
/// went; the step-path example's unbalanced-force ratio stalled at 5e-4: docs/mechanics.md,
/// "Rock bridges").
fn simplify(mut polygon: Vec<P2>, tol: f64) -> Vec<P2> {
    while polygon.len() >= 3 {
        let len = polygon.len();
        let mut least: Option<(f64, usize)> = None;
        for i in 0..len {
            let (prev, here, next) = (
                polygon[(i + len - 1) % len],
                polygon[i],
                polygon[(i + 1) % len],
            );
            let drops = distance(prev, here) <= tol
                || distance(here, next) <= tol
                || !turns_left(prev, here, next, tol);
            let corner = cross(prev, here, next);
            if drops && least.is_none_or(|(c, _)| corner < c) {
                least = Some((corner, i));
            }
        }
        match least {
            Some((_, i)) => {
                polygon.remove(i);
            }
            None => break,
        }
    }
    polygon
}

/// Area of a counter-clockwise polygon (shoelace, fanned from the first vertex).
fn area(polygon: &[P2]) -> f64 {
    let o = polygon[0];
    let twice: f64 = polygon.windows(2).map(|w| cross(o, w[0], w[1])).sum();
    0.5 * twice
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_drops_inner_duplicate_and_collinear_points() {
        let tol = 1e-9;
        let mut pts: Vec<P2> = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [0.5, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.5, 0.5],
            [1.0 + 1e-12, 1.0],
            [0.0, 0.5 + 1e-13],
        ];
        pts.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
        let hull = hull_ccw(&pts, tol);
        assert_eq!(hull.len(), 4, "{hull:?}");
        assert!((area(&hull) - 1.0).abs() < 1e-12);
        for k in 0..4 {
            assert!(cross(hull[k], hull[(k + 1) % 4], hull[(k + 2) % 4]) > 0.0);
        }
    }

    #[test]
    fn degenerate_hulls_are_short() {
        let tol = 1e-9;
        let one = hull_ccw(&[[0.0, 0.0], [1e-12, 0.0]], tol);
        assert_eq!(one.len(), 1);
        let two = hull_ccw(&[[0.0, 0.0], [0.5, 1e-12], [1.0, 0.0]], tol);
        assert_eq!(two.len(), 2);
    }

    #[test]
    fn a_rectangle_whose_sides_zigzag_in_rounding_keeps_its_corners() {
        // The face of a bridge piece under a sliding block (10 m by 6.1 m), its points as
        // the detection gave them once the simulation had placed the blocks: two columns,
        // x = -10 and x = 0, each within a few roundings, in an order zigzagging in y, with
        // a near-duplicate of two corners (0.015 apart, within the threshold 0.154).
        let pts: Vec<P2> = vec![
            [-10.000000000000004, 10.986971298853108],
            [-10.000000000000002, 4.867663089154262],
            [-10.000000000000002, 4.883098355045824],
            [-10.000000000000002, 10.986971298853105],
            [-1.3833612534343673e-15, 4.867663089154266],
            [-1.232869760325347e-15, 10.986971298853105],
            [5.43487079074903e-16, 10.986971298853106],
            [1.6231606880112627e-15, 4.883098355045822],
        ];
        let hull = hull_ccw(&pts, 0.15435265891560787);
        assert_eq!(hull.len(), 4, "{hull:?}");
        let exact = 10.0 * (10.986971298853106 - 4.867663089154262);
        assert!((area(&hull) - exact).abs() < 0.16 * 10.0, "{}", area(&hull));
    }

    /// A square's corner and a point of its edge 0.02 from it (within the threshold 0.15),
    /// each off the other edge's line by a rounding either way (the face of a block on a
    /// bridge, whose side is in the plane of its neighbours' sides): the polygon keeps the
    /// corner every way. Once the sweep's order decided: with the corner 1e-9 inside and
    /// the point on the line, the corner went (0.1 m² short), and a contact of the
    /// step-path example flipped between the two as its block moved by roundings (its
    /// unbalanced-force ratio stalled at 5e-4).
    #[test]
    fn of_two_points_within_the_threshold_the_corner_stays_whatever_the_rounding() {
        let sides = [-1e-9, 0.0, 1e-9];
        for corner in sides {
            for point in sides {
                let mut pts: Vec<P2> = vec![
                    [0.0, 0.0],
                    [10.0, 0.0],
                    [10.0, 10.0],
                    [corner, 10.0],
                    [point, 9.98],
                ];
                pts.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
                let hull = hull_ccw(&pts, 0.15);
                assert_eq!(hull.len(), 4, "{corner} {point}: {hull:?}");
                assert!(
                    (area(&hull) - 100.0).abs() < 1e-6,
                    "{corner} {point}: {}",
                    area(&hull)
                );
            }
        }
    }
}
