//! The contact normal, one rule per type (docs/contact-geometry.md).
//!
//! * a face on either side (face-face, vertex-face, edge-face): the face's outward normal,
//!   negated when the face is B's; for two faces `normalize(nA - nB)`, which is symmetric;
//! * edge-edge crossing: the cross product of the two edges, oriented from A's centroid
//!   towards B's (the plane of the two edges is the only plane through the crossing point
//!   that can separate the blocks, and each centroid lies strictly on its block's side);
//! * vertex-vertex, vertex-edge, edge-edge superposition (and a crossing of edges too close
//!   to parallel to give a cross product): the separating normal closest to the bisector of
//!   the features' mean outward normals ([`super::normal::cone`]).
//!
//! Every rule uses directions only (face normals, edge directions, the centroids' offset for
//! a sign), so the normal does not change when B is translated, and each is written so that
//! swapping A and B negates every intermediate vector exactly: the normal of (B, A) is
//! bit for bit the opposite of the normal of (A, B).

mod cone;

pub(super) use cone::most_separating;

use crate::block::ConvexBlock;
use crate::classify::{Contact, ContactType, Feature};
use crate::geometry::DVec3;
use crate::tolerance::Thresholds;

/// The unit contact normal, from A to B. Two edges are parallel when the sine of their
/// angle is at most the relative length threshold (as in [`crate::classify`]); the cone
/// rule allows its constraints an angular slack of the relative gap, which tilts a plane by
/// no more than the gap over the pair's size.
pub(super) fn contact_normal(
    a: &ConvexBlock,
    b: &ConvexBlock,
    contact: &Contact,
    th: Thresholds,
) -> DVec3 {
    let (parallel, slack) = (th.length / scale(a, b), cone_slack(a, b, th.gap));
    let (fa, fb) = (contact.feature_a, contact.feature_b);
    match (fa, fb) {
        (Feature::Face(f), Feature::Face(g)) => (face_normal(a, f) - face_normal(b, g))
            .try_normalize()
            .unwrap_or_else(|| face_normal(a, f)),
        (Feature::Face(f), _) => face_normal(a, f),
        (_, Feature::Face(f)) => -face_normal(b, f),
        (Feature::Edge(ea), Feature::Edge(eb)) if contact.kind == ContactType::EdgeEdge => {
            crossing_normal(a, ea, b, eb, parallel)
                .unwrap_or_else(|| cone::cone_normal(a, fa, b, fb, slack))
        }
        _ => cone::cone_normal(a, fa, b, fb, slack),
    }
}

/// The pair's size: the smaller block's.
fn scale(a: &ConvexBlock, b: &ConvexBlock) -> f64 {
    a.size().min(b.size())
}

/// The cone rule's angular slack for a pair whose gap (absolute) is `gap`: the relative gap.
fn cone_slack(a: &ConvexBlock, b: &ConvexBlock, gap: f64) -> f64 {
    gap / scale(a, b)
}

/// For a contact whose normal is chosen by the cone rule (vertex-vertex, vertex-edge,
/// edge-edge superposition), the other directions of the cone of valid normals among its
/// extreme rays (the face normals at the two features, negated for B, and the cross
/// products of their edge directions), valid within the cone rule's slack (the same as for
/// `normal`); empty for the other types, whose common plane is unique. `gap`: the pair's
/// gap (absolute). Along each, as along the normal, a positive offset of B's feature from
/// A's is a gap between the blocks, to within that slack (docs/mechanics.md, "Gaps of point
/// contacts"): the mechanics measures a point contact's gap as the largest of them.
pub(crate) fn cone_rays(
    a: &ConvexBlock,
    b: &ConvexBlock,
    contact: &Contact,
    normal: DVec3,
    gap: f64,
) -> Vec<DVec3> {
    match contact.kind {
        ContactType::VertexVertex
        | ContactType::VertexEdge
        | ContactType::EdgeEdgeSuperposition => {
            let slack = cone_slack(a, b, gap);
            cone::valid_rays(a, contact.feature_a, b, contact.feature_b, normal, slack)
        }
        _ => Vec::new(),
    }
}

/// Outward unit normal of face `f`.
pub(super) fn face_normal(block: &ConvexBlock, f: u32) -> DVec3 {
    block.planes()[f as usize].normal
}

/// Unit direction of edge `e`, from its first vertex to its second.
pub(super) fn edge_direction(block: &ConvexBlock, e: u32) -> DVec3 {
    let [p, q] = block.edges()[e as usize].vertices;
    (block.vertices()[q as usize] - block.vertices()[p as usize]).normalize()
}

/// `±(dA × dB)` normalised, oriented so that B's centroid is on the positive side of A's;
/// `None` when the edges are parallel within `sine`.
fn crossing_normal(a: &ConvexBlock, ea: u32, b: &ConvexBlock, eb: u32, sine: f64) -> Option<DVec3> {
    let cross = edge_direction(a, ea).cross(edge_direction(b, eb));
    if cross.length() <= sine {
        return None;
    }
    let n = cross.normalize();
    Some(if n.dot(b.centroid() - a.centroid()) < 0.0 {
        -n
    } else {
        n
    })
}
