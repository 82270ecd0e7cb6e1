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
//!    boundary at a point);
//! 2. the feature of block X holding the contact is found from the faces of X whose planes
//!    pass within the length threshold of every representative point: none means the
//!    contact reaches X's interior (penetrating), one a face, two an edge, three or more a
//!    vertex;
//! 3. the pair of features gives the type: (vertex, vertex) vertex-vertex, (vertex, edge)
//!    vertex-edge, (vertex, face) vertex-face, (edge, face) edge-face, (face, face)
//!    face-face; (edge, edge) is an edge-edge superposition when the two edges are parallel
//!    (the sine of their angle at most the relative length threshold) and the representative
//!    points span more than the length threshold, else an edge-edge crossing. Parallelism is
//!    tested on the edges themselves because two edges crossing at a small angle `θ` stay
//!    within the gap `g` of each other over a length `2g/θ`, which would read as an overlap.
//!
//! Every (feature, feature) combination is thus mapped, in the same way for (A, B) and
//! (B, A). The printed Table 2 counts (N^i, N^orig) are reported by
//! [`crate::Detector::table1_counts`] but not used to decide: several of them are ambiguous
//! or contradict the geometry (a face-face contact of two cubes has eight edges with
//! length, not three; see docs/classification.md).

use crate::block::ConvexBlock;
use crate::geometry::DVec3;
use crate::penetration::{EdgeEnd, PenetrationEdge, PenetrationEdgeType, Side};

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

/// Calls `visit` with the representative points of one penetration edge (see the module
/// docs), one at a time, so that no pair of points is built and read back. An original
/// vertex comes back once per edge at it: `seen` marks the owner's vertices already
/// visited (the first 64), which are skipped.
#[inline]
fn visit_representatives(
    pe: &PenetrationEdge,
    owner: &ConvexBlock,
    seen: &mut u64,
    mut visit: impl FnMut(DVec3),
) {
    let vertices = owner.vertices();
    let [v1, v2] = owner.edges()[pe.edge as usize].vertices;
    let (p, q) = (vertices[v1 as usize], vertices[v2 as usize]);
    let at = |k: usize| match pe.ends[k] {
        EdgeEnd::Vertex(v) => vertices[v as usize],
        EdgeEnd::Cut(_) => p + (q - p) * pe.t[k],
    };
    let mut end = |k: usize| {
        if let EdgeEnd::Vertex(v) = pe.ends[k] {
            let bit = 1u64.checked_shl(v).unwrap_or(0);
            if *seen & bit != 0 {
                return;
            }
            *seen |= bit;
        }
        visit(at(k))
    };
    match (pe.kind, pe.ends) {
        (PenetrationEdgeType::T3, [EdgeEnd::Vertex(_), _]) => end(0),
        (PenetrationEdgeType::T3, _) => end(1),
        (PenetrationEdgeType::T5, _) => visit((at(0) + at(1)) * 0.5),
        _ => {
            end(0);
            end(1);
        }
    }
}

/// Collects the representative points of the penetration edges (see the module docs).
pub(crate) fn representative_points(
    a: &ConvexBlock,
    b: &ConvexBlock,
    edges: &[PenetrationEdge],
    out: &mut Vec<DVec3>,
) {
    out.clear();
    let mut seen = [0u64; 2];
    for pe in edges {
        let (owner, seen) = side(pe, [a, b], &mut seen);
        // Keep each point once (a cut can fall on a vertex, or two cuts together).
        visit_representatives(pe, owner, seen, |p| {
            if !out.contains(&p) {
                out.push(p)
            }
        });
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

/// Classifies a touching pair from its penetration edges (non-empty); `length` is the
/// absolute length threshold, `points` receives the representative points.
pub(crate) fn classify(
    a: &ConvexBlock,
    b: &ConvexBlock,
    edges: &[PenetrationEdge],
    length: f64,
    points: &mut Vec<DVec3>,
) -> PairResult {
    representative_points(a, b, edges, points);
    let (Some(fa), Some(fb)) = (feature_of(a, points, length), feature_of(b, points, length))
    else {
        return PairResult::Penetrating;
    };
    let superposed =
        || edges_parallel(a, b, fa, fb, length / a.size().min(b.size())) && spread(points) > length;
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
        (block.vertices()[q as usize] - block.vertices()[p as usize]).normalize()
    };
    match (fa, fb) {
        (Feature::Edge(ea), Feature::Edge(eb)) => {
            direction(a, ea).cross(direction(b, eb)).length() <= sine
        }
        _ => false,
    }
}

fn contact_type(fa: Feature, fb: Feature, has_length: impl Fn() -> bool) -> ContactType {
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

/// Largest distance of a point from the first one.
fn spread(points: &[DVec3]) -> f64 {
    points
        .iter()
        .map(|p| p.distance(points[0]))
        .fold(0.0, f64::max)
}

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
    match n {
        0 => None,
        1 => Some(Feature::Face(common[0])),
        2 => Some(edge_between(block, common[0], common[1]).unwrap_or(Feature::Face(common[0]))),
        _ => Some(Feature::Vertex(vertex_on(block, &common[..n]))),
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
