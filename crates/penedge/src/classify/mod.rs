//! The contact decision and the seven contact types (paper sections 3.1 and 3.4).
//!
//! # Rule
//! The types are defined by geometry: the dimension of A ∩ B and the smallest feature
//! (vertex, edge, face) of each block that holds it. penedge reads both from the
//! penetration edges, whose end points are the vertices of the penetration body A ∩ B:
//!
//! 1. each penetration edge stands for its *representative points*: both ends if it has
//!    length (Table 1 types 1, 2, 4); its original vertex if it is a type 3 (no length, one
//!    original vertex: the gap widening cut a stub off an edge at a vertex in contact); its
//!    middle if it is a type 5 (no length, two cuts: an edge crossing the other block's
//!    boundary at a point); a piece with length that the gap's bands at the face planes its
//!    edge crosses (rather than lies in) leave without length is read as a type 3 or 5
//!    ([`crate::penetration::PenetrationEdge::stands_for`], docs/tolerance.md "Lies in");
//! 2. the feature of block X holding the contact is found from the faces of X whose planes
//!    pass within the length threshold of every representative point: none means the
//!    contact reaches X's interior (penetrating), one a face, two an edge, three or more a
//!    vertex (how it is done without computing the points: `classify/faces.rs` and
//!    docs/classification.md);
//! 3. the pair of features gives the type: (vertex, vertex) vertex-vertex, (vertex, edge)
//!    vertex-edge, (vertex, face) vertex-face, (edge, face) edge-face, (face, face)
//!    face-face; (edge, edge) is an edge-edge superposition when the two edges are parallel
//!    (lie along each other: the sine of their angle at most the length threshold over the
//!    pair's scale, [`crate::tolerance::Thresholds::sine`]) and the representative
//!    points span more than the length threshold, else an edge-edge crossing. Parallelism is
//!    tested on the edges themselves because two edges crossing at a small angle `θ` stay
//!    within the gap `g` of each other over a length `2g/θ`, which would read as an overlap.
//!
//! Every (feature, feature) combination is thus mapped, in the same way for (A, B) and
//! (B, A). The printed Table 2 counts (N^i, N^orig) are reported by
//! [`crate::Detector::table1_counts`] but not used to decide: several of them are ambiguous
//! or contradict the geometry (a face-face contact of two cubes has eight edges with
//! length, not three; see docs/classification.md).

mod faces;
mod points;

pub(crate) use faces::{FaceLists, FaceMasks, HeldFaces};
pub(crate) use points::{representative_points, spread_exceeds};

use crate::block::ConvexBlock;
use crate::geometry::DVec3;
use crate::tolerance::Thresholds;

/// The seven contact types of two touching convex blocks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[repr(u8)]
pub enum ContactType {
    /// A vertex of each block at one point.
    VertexVertex = 1,
    /// A vertex of one block on an edge (interior) of the other.
    VertexEdge = 2,
    /// Two edges crossing at one point.
    EdgeEdge = 3,
    /// Two collinear edges overlapping along a segment.
    EdgeEdgeSuperposition = 4,
    /// A vertex of one block in the interior of a face of the other.
    VertexFace = 5,
    /// An edge (or part of it) of one block lying in a face of the other.
    EdgeFace = 6,
    /// Two faces overlapping in a polygon.
    FaceFace = 7,
}

impl ContactType {
    /// All seven, in the paper's order.
    pub const ALL: [ContactType; 7] = [
        ContactType::VertexVertex,
        ContactType::VertexEdge,
        ContactType::EdgeEdge,
        ContactType::EdgeEdgeSuperposition,
        ContactType::VertexFace,
        ContactType::EdgeFace,
        ContactType::FaceFace,
    ];

    /// The name used in files and on the command line (`vertex-face`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ContactType::VertexVertex => "vertex-vertex",
            ContactType::VertexEdge => "vertex-edge",
            ContactType::EdgeEdge => "edge-edge",
            ContactType::EdgeEdgeSuperposition => "edge-edge-superposition",
            ContactType::VertexFace => "vertex-face",
            ContactType::EdgeFace => "edge-face",
            ContactType::FaceFace => "face-face",
        }
    }

    /// The type with code 1..=7, as in [`ContactType::code`].
    pub fn from_code(code: u8) -> Option<ContactType> {
        ContactType::ALL
            .get((code as usize).wrapping_sub(1))
            .copied()
    }

    /// The code 1..=7 (the paper's order).
    pub fn code(self) -> u8 {
        self as u8
    }
}

impl std::fmt::Display for ContactType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The smallest feature of a block that holds the contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Feature {
    /// A vertex (index into the block's vertices).
    Vertex(u32),
    /// An edge (index into the block's edges).
    Edge(u32),
    /// A face (index into the block's faces).
    Face(u32),
}

impl Feature {
    fn rank(self) -> u8 {
        match self {
            Feature::Vertex(_) => 0,
            Feature::Edge(_) => 1,
            Feature::Face(_) => 2,
        }
    }
}

/// A contact between two touching blocks.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Contact {
    /// The contact type.
    pub kind: ContactType,
    /// The feature of A that holds the contact.
    pub feature_a: Feature,
    /// The feature of B that holds the contact.
    pub feature_b: Feature,
}

/// The answer for a pair of blocks.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum PairResult {
    /// Farther apart than the gap.
    Separated,
    /// Touching within the tolerance, with the contact type.
    Contact(Contact),
    /// Overlapping deeper than the gap.
    Penetrating,
}

impl PairResult {
    /// The contact type, if the blocks touch.
    pub fn contact_type(&self) -> Option<ContactType> {
        match self {
            PairResult::Contact(c) => Some(c.kind),
            _ => None,
        }
    }

    /// The name of the outcome: a contact type's name, `separated` or `penetrating`.
    pub fn name(&self) -> &'static str {
        match self {
            PairResult::Separated => "separated",
            PairResult::Penetrating => "penetrating",
            PairResult::Contact(c) => c.kind.name(),
        }
    }
}
/// The contact from the features of both blocks (`None`: the points reach the block's
/// interior); `spread_exceeds(length)` tells whether the representative points span more
/// than `length`, asked only for two parallel edges (`th.sine`, the one sine of "lies
/// along" and "lies in": docs/tolerance.md).
pub(crate) fn decide(
    a: &ConvexBlock,
    b: &ConvexBlock,
    features: (Option<Feature>, Option<Feature>),
    th: Thresholds,
    spread_exceeds: impl FnOnce(f64) -> bool,
) -> PairResult {
    let (Some(fa), Some(fb)) = features else {
        return PairResult::Penetrating;
    };
    let superposed = || edges_parallel(a, b, fa, fb, th.sine) && spread_exceeds(th.length);
    let kind = contact_type(fa, fb, superposed);
    PairResult::Contact(Contact {
        kind,
        feature_a: fa,
        feature_b: fb,
    })
}
/// Whether two edges are parallel: the sine of their angle at most `sine` (the relative
/// length threshold, so that over a block's size the edges stay within the length threshold
/// of each other). Edges crossing at a small angle have a long stretch within the gap of each
/// other, which alone would read as an overlap.
fn edges_parallel(a: &ConvexBlock, b: &ConvexBlock, fa: Feature, fb: Feature, sine: f64) -> bool {
    let direction = |block: &ConvexBlock, e: u32| {
        let [p, q] = block.edges()[e as usize].vertices;
        block.vertices()[q as usize] - block.vertices()[p as usize]
    };
    match (fa, fb) {
        (Feature::Edge(ea), Feature::Edge(eb)) => {
            // |u × v| <= sine |u| |v|, squared: no square root or division.
            let (u, v) = (direction(a, ea), direction(b, eb));
            u.cross(v).length_squared() <= sine * sine * u.length_squared() * v.length_squared()
        }
        _ => false,
    }
}

pub(crate) fn contact_type(
    fa: Feature,
    fb: Feature,
    has_length: impl FnOnce() -> bool,
) -> ContactType {
    match (fa.rank().min(fb.rank()), fa.rank().max(fb.rank())) {
        (0, 0) => ContactType::VertexVertex,
        (0, 1) => ContactType::VertexEdge,
        (0, _) => ContactType::VertexFace,
        (1, 1) if has_length() => ContactType::EdgeEdgeSuperposition,
        (1, 1) => ContactType::EdgeEdge,
        (1, _) => ContactType::EdgeFace,
        _ => ContactType::FaceFace,
    }
}
/// The smallest feature of `block` with exactly the faces `common` (in increasing order):
/// none, a face, the edge between two faces, or the vertex on three or more.
fn feature_from(block: &ConvexBlock, common: &[u32]) -> Option<Feature> {
    match *common {
        [] => None,
        [f] => Some(Feature::Face(f)),
        [f, g] => Some(edge_between(block, f, g).unwrap_or(Feature::Face(f))),
        _ => Some(Feature::Vertex(vertex_on(block, common))),
    }
}

fn edge_between(block: &ConvexBlock, f: u32, g: u32) -> Option<Feature> {
    block
        .edges()
        .iter()
        .position(|e| e.faces == [f, g] || e.faces == [g, f])
        .map(|e| Feature::Edge(e as u32))
}

/// The vertex shared by the given faces (by incidence), or else the vertex closest to all
/// their planes.
fn vertex_on(block: &ConvexBlock, faces: &[u32]) -> u32 {
    let shared = block.face(faces[0] as usize).iter().find(|v| {
        faces[1..]
            .iter()
            .all(|&f| block.face(f as usize).contains(v))
    });
    if let Some(&v) = shared {
        return v;
    }
    let off = |v: &DVec3| {
        faces
            .iter()
            .map(|&f| block.planes()[f as usize].distance(*v).abs())
            .fold(0.0, f64::max)
    };
    let best = block
        .vertices()
        .iter()
        .enumerate()
        .min_by(|(_, p), (_, q)| off(p).total_cmp(&off(q)))
        .map_or(0, |(i, _)| i);
    best as u32
}
#[cfg(test)]
mod tests {
    use super::points::spread;
    use super::*;
    use crate::penetration::PenetrationEdge;

    /// The smallest feature of `block` whose faces all pass within `length` of every point;
    /// `None` when no face does (the points reach the block's interior).
    fn feature_of(block: &ConvexBlock, points: &[DVec3], length: f64) -> Option<Feature> {
        let planes = block.planes();
        let mut common = [0u32; 16];
        let mut n = 0;
        for (f, plane) in planes.iter().enumerate() {
            if points.iter().all(|&p| plane.distance(p).abs() <= length) {
                if n == common.len() {
                    break;
                }
                common[n] = f as u32;
                n += 1;
            }
        }
        feature_from(block, &common[..n])
    }

    use crate::system::test_rng::Rng;
    use crate::{Detector, Tolerance};
    use glam::DQuat;

    /// The rule of the module docs applied as written: the representative points collected
    /// (duplicates removed), then every face tested against every point.
    fn by_points(
        a: &ConvexBlock,
        b: &ConvexBlock,
        edges: &[PenetrationEdge],
        th: Thresholds,
    ) -> PairResult {
        let mut points = Vec::new();
        representative_points(a, b, edges, false, &mut points);
        let features = (
            feature_of(a, &points, th.length),
            feature_of(b, &points, th.length),
        );
        decide(a, b, features, th, |l| spread(&points) > l)
    }

    /// A unit cube turned by `rotation` and moved so that its lowest feature (vertex, edge
    /// or face: the middle of its lowest vertices) is at `target`.
    fn resting_on(rotation: DQuat, target: [f64; 3]) -> ConvexBlock {
        let cube = ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).unwrap();
        let turned = cube.transformed(rotation, glam::DVec3::ZERO, 1.0);
        let low = turned
            .vertices()
            .iter()
            .map(|v| v.z)
            .fold(f64::INFINITY, f64::min);
        let lowest: Vec<_> = turned
            .vertices()
            .iter()
            .filter(|v| v.z < low + 1e-9)
            .collect();
        let middle = lowest.iter().copied().sum::<glam::DVec3>() / lowest.len() as f64;
        turned.transformed(DQuat::IDENTITY, glam::DVec3::from(target) - middle, 1.0)
    }

    /// Pairs with every contact type: the paper's three examples (all pairs of blocks) and
    /// a unit cube with a cube resting on its top face by a vertex, an edge or a face, on the
    /// face, on an edge or at a corner; two cubes resting on each other's edges, crossed.
    fn pairs() -> Vec<(ConvexBlock, ConvexBlock)> {
        let mut pairs = crate::system::paper_pairs();
        let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        // A vertex down: the cube's diagonal turned onto the vertical.
        let diagonal = glam::DVec3::ONE.normalize();
        let vertex_down = DQuat::from_rotation_arc(diagonal, glam::DVec3::Z);
        let edge_down_x = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_4);
        let edge_down_y = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_4);
        let face_down = DQuat::from_rotation_z(0.3);
        for (rotation, target) in [
            (vertex_down, [0.5, 0.5, 1.0]), // vertex-face
            (vertex_down, [0.5, 1.0, 1.0]), // vertex-edge
            (vertex_down, [1.0, 1.0, 1.0]), // vertex-vertex
            (edge_down_x, [0.5, 0.5, 1.0]), // edge-face
            (edge_down_x, [0.5, 1.0, 1.0]), // edge-edge superposition
            (face_down, [0.6, 0.4, 1.0]),   // face-face
        ] {
            pairs.push((a.clone(), resting_on(rotation, target)));
        }
        // Edge-edge: two ridges across each other (one cube on an edge along x, the other
        // on its top edge by an edge along y).
        let ridge = resting_on(edge_down_x, [0.0; 3]);
        let top = std::f64::consts::SQRT_2;
        pairs.push((ridge, resting_on(edge_down_y, [0.0, 0.0, top])));
        pairs
    }

    /// The shrinking face masks give the same features and type as the rule applied to
    /// every point, for pairs with every contact type (and separated ones), turned, moved,
    /// scaled and pushed slightly together, in both orders.
    #[test]
    fn face_masks_classify_as_every_point_does() {
        let mut rng = Rng(23);
        let mut contacts = [0usize; 8];
        let pairs = pairs();
        for round in 0..4 {
            let axis = glam::DVec3::new(rng.signed(), rng.signed(), rng.signed() + 2.0);
            let rotation = DQuat::from_axis_angle(axis.normalize(), 3.0 * rng.signed());
            let shift = glam::DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 1e3;
            let scale = 0.01 + rng.unit();
            for (a, b) in &pairs {
                let a = a.transformed(rotation, shift, scale);
                let mut b = b.transformed(rotation, shift, scale);
                if round == 3 {
                    // Pushed together by a fraction of the gap.
                    let towards = (a.centroid() - b.centroid()).normalize();
                    b = b.transformed(DQuat::IDENTITY, towards * 1e-5 * scale, 1.0);
                }
                for (a, b) in [(&a, &b), (&b, &a)] {
                    let mut det = Detector::new(Tolerance::default());
                    let result = det.detect(a, b);
                    let edges = det.penetration_edges();
                    if edges.is_empty() || result == PairResult::Penetrating {
                        continue;
                    }
                    let th = det.thresholds(a, b);
                    assert_eq!(result, by_points(a, b, edges, th), "round {round}");
                    contacts[result.contact_type().map_or(0, |t| t.code() as usize)] += 1;
                }
            }
        }
        assert!(
            contacts[1..].iter().all(|&n| n > 0),
            "types met: {contacts:?}"
        );
    }
}
