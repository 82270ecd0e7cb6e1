//! Contact points, on the contact plane.
//!
//! * vertex-vertex: the midpoint of the two vertices; vertex-edge and vertex-face: the
//!   vertex;
//! * edge-edge crossing: the midpoint of the closest points of the two edges' lines;
//! * edge-face and edge-edge superposition: the two extreme representative points along the
//!   edge (A's edge for a superposition);
//! * face-face: the convex hull of the representative points ([`super::polygon`]).
//!
//! Every point is then projected on the contact plane. Representative points closer than
//! the length threshold are one point, so a segment or polygon that collapses below it is
//! given as a point or a segment.

use super::normal::edge_direction;
use super::polygon::convex_polygon;
use super::{ContactPlane, ContactPoints};
use crate::block::ConvexBlock;
use crate::classify::{Contact, ContactType, Feature};
use crate::geometry::DVec3;

/// The contact points of a contact (see the module docs); `length` is the absolute length
/// threshold.
pub(super) fn contact_points(
    a: &ConvexBlock,
    b: &ConvexBlock,
    contact: &Contact,
    representative: &[DVec3],
    plane: &ContactPlane,
    length: f64,
) -> ContactPoints {
    let vertex = |block: &ConvexBlock, v: u32| block.vertices()[v as usize];
    let point = |p: DVec3| ContactPoints::Point(plane.project(p));
    match (contact.feature_a, contact.feature_b) {
        (Feature::Vertex(va), Feature::Vertex(vb)) => point((vertex(a, va) + vertex(b, vb)) * 0.5),
        (Feature::Vertex(v), _) => point(vertex(a, v)),
        (_, Feature::Vertex(v)) => point(vertex(b, v)),
        (Feature::Edge(ea), Feature::Edge(eb)) if contact.kind == ContactType::EdgeEdge => {
            point(crossing_point(a, ea, b, eb).unwrap_or_else(|| centroid(representative)))
        }
        (Feature::Edge(e), _) => segment(representative, a, e, plane, length),
        (_, Feature::Edge(e)) => segment(representative, b, e, plane, length),
        (Feature::Face(_), Feature::Face(_)) => convex_polygon(representative, plane, length),
    }
}

/// The stretch of edge `e` of `block` between the representative points' extremes along it
/// (the plane's origin if there are none), projected on the contact plane; their midpoint
/// when closer than `length`.
///
/// The ends are taken on the edge's line, not at the extreme points themselves: a face-face
/// contact collapsed below the length threshold (two faces overlapping in a strip narrower than
/// it, reported as an edge-edge superposition) has its extreme points on opposite sides of the
/// strip, and the segment between them was the strip's diagonal rather than the edge.
fn segment(
    points: &[DVec3],
    block: &ConvexBlock,
    e: u32,
    plane: &ContactPlane,
    length: f64,
) -> ContactPoints {
    let d = edge_direction(block, e);
    let base = block.vertices()[block.edges()[e as usize].vertices[0] as usize];
    let along = |p: &DVec3| d.dot(*p - base);
    let low = points.iter().map(along).fold(f64::INFINITY, f64::min);
    let high = points.iter().map(along).fold(f64::NEG_INFINITY, f64::max);
    let [p, q] = if points.is_empty() {
        [plane.origin(); 2]
    } else {
        [low, high].map(|t| plane.project(base + d * t))
    };
    if p.distance(q) <= length {
        ContactPoints::Point((p + q) * 0.5)
    } else {
        ContactPoints::Segment([p, q])
    }
}

fn centroid(points: &[DVec3]) -> DVec3 {
    points.iter().fold(DVec3::ZERO, |s, &p| s + p) / points.len().max(1) as f64
}

/// The midpoint of the closest points of the lines of edge `ea` of A and `eb` of B;
/// `None` for parallel lines. When a line's closest point lies beyond its edge (two nearly
/// parallel edges within the gap along a stretch, whose lines come closest far from both:
/// at 2e-3 rad, a metre away), the closest points of the two edges themselves instead, so
/// that the point is on both edges (docs/contact-geometry.md, "Accuracy and deviations").
fn crossing_point(a: &ConvexBlock, ea: u32, b: &ConvexBlock, eb: u32) -> Option<DVec3> {
    let line = |block: &ConvexBlock, e: u32| {
        let [p, q] = block.edges()[e as usize].vertices;
        let start = block.vertices()[p as usize];
        (start, block.vertices()[q as usize] - start)
    };
    let (la, lb) = (line(a, ea), line(b, eb));
    let (s, t) = (closest_parameter(la, lb)?, closest_parameter(lb, la)?);
    let at = |(p, u): (DVec3, DVec3), s: f64| p + u * s;
    let within = |s: f64| (0.0..=1.0).contains(&s);
    if within(s) && within(t) {
        return Some((at(la, s) + at(lb, t)) * 0.5);
    }
    // The closest points of the two segments (Ericson, "Real-Time Collision Detection",
    // 5.1.9): A's parameter clamped, B's nearest to that point, and A's again if B's was
    // clamped.
    let nearest = |(p, u): (DVec3, DVec3), x: DVec3| (x - p).dot(u) / u.length_squared();
    let s = s.clamp(0.0, 1.0);
    let t_free = nearest(lb, at(la, s));
    let t = t_free.clamp(0.0, 1.0);
    let s = if t == t_free {
        s
    } else {
        nearest(la, at(lb, t)).clamp(0.0, 1.0)
    };
    Some((at(la, s) + at(lb, t)) * 0.5)
}

/// The parameter `s` of the point of line `p + s u` closest to line `q + t v`:
/// `s = ((q - p) × v)·(u × v) / |u × v|²`. Written with cross products, which keep their
/// relative accuracy for lines at small angles (`u·u v·v - (u·v)²` would cancel).
fn closest_parameter((p, u): (DVec3, DVec3), (q, v): (DVec3, DVec3)) -> Option<f64> {
    let normal = u.cross(v);
    let det = normal.length_squared();
    if det <= 0.0 {
        return None;
    }
    Some((q - p).cross(v).dot(normal) / det)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    /// The index of the edge of `block` from `p` to `q` (either way).
    fn edge(block: &ConvexBlock, p: DVec3, q: DVec3) -> u32 {
        let v = block.vertices();
        let near = |i: u32, x: DVec3| v[i as usize].distance(x) < 1e-9;
        block
            .edges()
            .iter()
            .position(|e| {
                let [i, j] = e.vertices;
                near(i, p) && near(j, q) || near(i, q) && near(j, p)
            })
            .expect("no such edge") as u32
    }

    /// Two edges that cross inside both keep their lines' closest points; two nearly parallel
    /// edges side by side (B's cube turned by 2e-3 rad about the vertical, its edge 1 mm from
    /// A's along their common stretch), whose lines cross 0.6 m beyond A's edge, get a point
    /// on both edges: the point of the lines, the old answer, was off A's edge by 0.6 m.
    #[test]
    fn a_crossing_point_lies_on_both_edges() {
        let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let ea = edge(&a, DVec3::new(1.0, 0.0, 1.0), DVec3::new(1.0, 1.0, 1.0));
        let on_edge = |block: &ConvexBlock, e: u32, x: DVec3| {
            let [p, q] = block.edges()[e as usize]
                .vertices
                .map(|i| block.vertices()[i as usize]);
            // Within 2 mm of the edge (the segment, not its line).
            let s = ((x - p).dot(q - p) / (q - p).length_squared()).clamp(0.0, 1.0);
            (p + (q - p) * s).distance(x) < 2e-3
        };
        // Crossing: B's top-back edge runs along x above A's top-right edge, 1 mm up.
        let b = ConvexBlock::cuboid([0.5, -0.5, 1.001], [1.5, 0.5, 2.001]).unwrap();
        let eb = edge(&b, DVec3::new(0.5, 0.5, 1.001), DVec3::new(1.5, 0.5, 1.001));
        let x = crossing_point(&a, ea, &b, eb).unwrap();
        assert!(x.distance(DVec3::new(1.0, 0.5, 1.0005)) < 1e-12, "{x}");
        // Nearly parallel: B beside A across its right top edge (x = 1, z = 1), shifted by
        // 0.6 along y and turned by 2e-3 rad about the vertical through (1, 1.6, 1).
        let turn = DQuat::from_rotation_z(2e-3);
        let b = ConvexBlock::cuboid([1.0, 0.6, 1.001], [2.0, 1.6, 2.001])
            .unwrap()
            .rotated(turn, DVec3::new(1.0, 1.6, 1.0));
        let (p, q) = (DVec3::new(1.0, 0.6, 1.001), DVec3::new(1.0, 1.6, 1.001));
        let near = |x: DVec3| {
            *b.vertices()
                .iter()
                .min_by(|u, v| u.distance(x).total_cmp(&v.distance(x)))
                .unwrap()
        };
        let eb = edge(&b, near(p), near(q));
        let x = crossing_point(&a, ea, &b, eb).unwrap();
        assert!(on_edge(&a, ea, x) && on_edge(&b, eb, x), "{x}");
        // The lines alone come closest where B's turned edge meets x = 1: at its far end
        // (y = 1.6), 0.6 beyond A's edge.
        let la = (DVec3::new(1.0, 0.0, 1.0), DVec3::Y);
        let lb = (near(p), near(q) - near(p));
        let s = closest_parameter(la, lb).unwrap();
        assert!((s - 1.6).abs() < 1e-6, "{s}");
    }
}
