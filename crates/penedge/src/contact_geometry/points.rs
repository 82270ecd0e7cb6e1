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
/// `None` for parallel lines.
fn crossing_point(a: &ConvexBlock, ea: u32, b: &ConvexBlock, eb: u32) -> Option<DVec3> {
    let line = |block: &ConvexBlock, e: u32| {
        let [p, q] = block.edges()[e as usize].vertices;
        let start = block.vertices()[p as usize];
        (start, block.vertices()[q as usize] - start)
    };
    let (la, lb) = (line(a, ea), line(b, eb));
    Some((closest_on_first(la, lb)? + closest_on_first(lb, la)?) * 0.5)
}

/// The point of line `p + s u` closest to line `q + t v`:
/// `s = ((q - p) × v)·(u × v) / |u × v|²`. Written with cross products, which keep their
/// relative accuracy for lines at small angles (`u·u v·v - (u·v)²` would cancel).
fn closest_on_first((p, u): (DVec3, DVec3), (q, v): (DVec3, DVec3)) -> Option<DVec3> {
    let normal = u.cross(v);
    let det = normal.length_squared();
    if det <= 0.0 {
        return None;
    }
    Some(p + u * ((q - p).cross(v).dot(normal) / det))
}
