//! Placing block B against block A in a chosen way, with a known expected outcome.
//!
//! Every placement starts from a *touching* configuration: a unit direction `u`, a point of A
//! and a point of B (rotated) that are made to coincide, such that A lies in `u · x <= c` and
//! B in `u · x >= c` and each meets the plane `u · x = c` in exactly the chosen feature
//! (`u` strictly inside the feature's normal cone). A ∩ B is then the intersection of the two
//! features, which makes the contact type known in advance. B is then pushed along `u`:
//! away (separated, the plane still separates them) or into A (penetrating).

use crate::rng::SplitMix64;
use glam::{DQuat, DVec3};
use penedge::{ContactType, ConvexBlock, PairResult, Tolerance};
use std::f64::consts::{PI, TAU};

/// How B touches A before it is pushed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Touch {
    /// A face of each, overlapping in a polygon (B turned about the normal, offset a little).
    FaceFace,
    /// A vertex of each (the support vertices in a random direction).
    VertexVertex,
    /// A vertex of B on the interior of an edge of A.
    VertexEdge,
    /// An edge of each, crossing at one point at an angle of at least about 12 degrees.
    EdgeEdge,
    /// An edge of each, parallel and overlapping along a segment.
    EdgeEdgeSuperposition,
    /// A vertex of B on the interior of a face of A.
    VertexFace,
    /// An edge of B lying on a face of A, through the face's middle.
    EdgeFace,
}

impl Touch {
    /// All seven ways.
    pub const ALL: [Touch; 7] = [
        Touch::FaceFace,
        Touch::VertexVertex,
        Touch::VertexEdge,
        Touch::EdgeEdge,
        Touch::EdgeEdgeSuperposition,
        Touch::VertexFace,
        Touch::EdgeFace,
    ];

    /// The ways where an edge or a vertex holds the contact (all but face-face).
    pub const EDGE_OR_VERTEX: [Touch; 6] = [
        Touch::VertexVertex,
        Touch::VertexEdge,
        Touch::EdgeEdge,
        Touch::EdgeEdgeSuperposition,
        Touch::VertexFace,
        Touch::EdgeFace,
    ];

    /// The contact type penedge should report.
    pub fn contact_type(self) -> ContactType {
        match self {
            Touch::FaceFace => ContactType::FaceFace,
            Touch::VertexVertex => ContactType::VertexVertex,
            Touch::VertexEdge => ContactType::VertexEdge,
            Touch::EdgeEdge => ContactType::EdgeEdge,
            Touch::EdgeEdgeSuperposition => ContactType::EdgeEdgeSuperposition,
            Touch::VertexFace => ContactType::VertexFace,
            Touch::EdgeFace => ContactType::EdgeFace,
        }
    }
}

/// Where B goes from the touching configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Push {
    /// Away from A by a random distance in `[SEPARATION_MIN, SEPARATION_MAX]`.
    Apart,
    /// Not at all.
    Touching,
    /// Into A by `PENETRATION`.
    Into,
    /// Into A by `PENETRATION`, with a tolerance whose gap exceeds it ([`WIDE_GAP`]): still
    /// a contact, of the type of the touching configuration.
    IntoWithinGap,
}

impl Push {
    /// The tolerance the pairs are meant for: penedge's default, or a relative gap of
    /// [`WIDE_GAP`] for [`Push::IntoWithinGap`].
    pub fn tolerance(self) -> Tolerance {
        match self {
            Push::IntoWithinGap => Tolerance::with_gap(WIDE_GAP).expect("a valid gap"),
            _ => Tolerance::default(),
        }
    }
}

/// Relative gap of [`Push::IntoWithinGap`] pairs. Blocks are about 1 wide and a block's size
/// (its bounding-box diagonal) is at least about 1.2, so the absolute gap is at least about
/// 1.2e-3, above the penetration of 1e-3; the length threshold is ten times the gap.
pub const WIDE_GAP: f64 = 1e-3;

/// Smallest separation distance (blocks are about 1 wide).
pub const SEPARATION_MIN: f64 = 1e-3;
/// Largest separation distance.
pub const SEPARATION_MAX: f64 = 5e-2;
/// Penetration distance along the contact normal.
pub const PENETRATION: f64 = 1e-3;

/// The outcome a pair should have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expected {
    /// Apart.
    Separated,
    /// Touching with this type.
    Contact(ContactType),
    /// Overlapping deeper than the gap.
    Penetrating,
}

impl Expected {
    /// Whether penedge's answer is the expected one.
    pub fn matches(self, result: &PairResult) -> bool {
        match (self, result) {
            (Expected::Separated, PairResult::Separated) => true,
            (Expected::Penetrating, PairResult::Penetrating) => true,
            (Expected::Contact(kind), PairResult::Contact(c)) => c.kind == kind,
            _ => false,
        }
    }
}

/// Rigid motions of the two reference blocks (rotation about the body origin, then
/// translation) and the expected outcome.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    /// Rotation of A.
    pub rot_a: DQuat,
    /// Translation of A.
    pub pos_a: DVec3,
    /// Rotation of B.
    pub rot_b: DQuat,
    /// Translation of B.
    pub pos_b: DVec3,
    /// What penedge should say.
    pub expected: Expected,
}

/// Places `ref_b` against `ref_a` (both in their body frames): A at a random pose in a
/// 10-wide box, B touching it by `touch`, then pushed by `push`.
pub fn place(
    ref_a: &ConvexBlock,
    ref_b: &ConvexBlock,
    touch: Touch,
    push: Push,
    rng: &mut SplitMix64,
) -> Placement {
    let (rot_a, pos_a) = (rng.rotation(), rng.point_in_cube(5.0));
    let a = ref_a.transformed(rot_a, pos_a, 1.0);
    let t = touching(&a, ref_b, touch, rng);
    let (shift, expected) = match push {
        Push::Apart => (
            rng.range(SEPARATION_MIN, SEPARATION_MAX),
            Expected::Separated,
        ),
        Push::Touching => (0.0, Expected::Contact(touch.contact_type())),
        Push::Into => (-PENETRATION, Expected::Penetrating),
        Push::IntoWithinGap => (-PENETRATION, Expected::Contact(touch.contact_type())),
    };
    Placement {
        rot_a,
        pos_a,
        rot_b: t.rot_b,
        pos_b: t.pos_b + t.normal * shift,
        expected,
    }
}

/// A touching configuration of B against A (A already placed).
struct Touching {
    rot_b: DQuat,
    pos_b: DVec3,
    /// Unit normal from A towards B.
    normal: DVec3,
}

/// Draws touching configurations until one lets B be pushed straight into A (see
/// [`enters`]).
fn touching(a: &ConvexBlock, ref_b: &ConvexBlock, touch: Touch, rng: &mut SplitMix64) -> Touching {
    loop {
        let (normal, rot_b, point_a, point_b) = match touch {
            Touch::FaceFace => face_face(a, ref_b, rng),
            Touch::VertexVertex => vertex_vertex(a, ref_b, rng),
            Touch::VertexEdge => vertex_on_edge(a, ref_b, rng),
            Touch::EdgeEdge => edge_edge(a, ref_b, false, rng),
            Touch::EdgeEdgeSuperposition => edge_edge(a, ref_b, true, rng),
            Touch::VertexFace => vertex_on_face(a, ref_b, rng),
            Touch::EdgeFace => edge_on_face(a, ref_b, rng),
        };
        let b = ref_b.transformed(rot_b, DVec3::ZERO, 1.0);
        if enters(a, point_a, -normal) && enters(&b, point_b, normal) {
            return Touching {
                rot_b,
                pos_b: point_a - point_b,
                normal,
            };
        }
    }
}

/// Whether moving from `point` (on the block's surface) along unit `dir` enters the block
/// at an angle: every face plane through the point has `normal · dir <= -ENTRY`. A support
/// direction in a vertex's normal cone need not point into the block from that vertex when
/// faces meet at an obtuse angle; this excludes such pairs, so that pushing B by
/// `PENETRATION` along `-u` surely makes A and B overlap (by at least about
/// `ENTRY * PENETRATION`).
fn enters(block: &ConvexBlock, point: DVec3, dir: DVec3) -> bool {
    block
        .planes()
        .iter()
        .filter(|pl| pl.distance(point).abs() <= ON_PLANE)
        .all(|pl| pl.normal.dot(dir) <= -ENTRY)
}

/// Smallest cosine between the push and a face plane at the contact point, see [`enters`].
const ENTRY: f64 = 0.05;
/// Distance within which the contact point counts as lying on a face plane.
const ON_PLANE: f64 = 1e-9;

/// `(u, rotation of B, point of A, point of B rotated)`: the pieces of a touching placement.
type Contact = (DVec3, DQuat, DVec3, DVec3);

fn face_face(a: &ConvexBlock, ref_b: &ConvexBlock, rng: &mut SplitMix64) -> Contact {
    let fa = rng.index(a.n_faces());
    let u = a.planes()[fa].normal;
    let fb = rng.index(ref_b.n_faces());
    let rot_b = turned_about(u, rng.range(0.0, TAU)) * aligned(ref_b.planes()[fb].normal, -u);
    let b = ref_b.transformed(rot_b, DVec3::ZERO, 1.0);
    (u, rot_b, face_point(a, fa, rng), face_centre(&b, fb))
}

fn vertex_vertex(a: &ConvexBlock, ref_b: &ConvexBlock, rng: &mut SplitMix64) -> Contact {
    loop {
        let u = rng.direction();
        let (rot_b, point_b) = turned_vertex(ref_b, -u, rng);
        if let Some(point_a) = clear_support(a, u) {
            return (u, rot_b, point_a, point_b);
        }
    }
}

fn vertex_on_edge(a: &ConvexBlock, ref_b: &ConvexBlock, rng: &mut SplitMix64) -> Contact {
    let ea = rng.index(a.edges().len());
    let u = edge_normal(a, ea, rng);
    let (rot_b, point_b) = turned_vertex(ref_b, -u, rng);
    (u, rot_b, edge_point(a, ea, rng.range(0.2, 0.8)), point_b)
}

/// Two edges in the plane normal to `u`: crossing at a random angle, or parallel and
/// overlapping (`parallel`, B's edge centred on a point of A's edge).
fn edge_edge(
    a: &ConvexBlock,
    ref_b: &ConvexBlock,
    parallel: bool,
    rng: &mut SplitMix64,
) -> Contact {
    let ea = rng.index(a.edges().len());
    let u = edge_normal(a, ea, rng);
    let eb = rng.index(ref_b.edges().len());
    let align = aligned(edge_normal(ref_b, eb, rng), -u);
    let (dir_a, dir_b) = (edge_direction(a, ea), align * edge_direction(ref_b, eb));
    let angle = if parallel {
        signed_angle(dir_b, dir_a, u) + if rng.unit() < 0.5 { 0.0 } else { PI }
    } else {
        crossing_angle(dir_a, dir_b, u, rng)
    };
    let rot_b = turned_about(u, angle) * align;
    let b = ref_b.transformed(rot_b, DVec3::ZERO, 1.0);
    let (s_a, s_b) = if parallel {
        (rng.range(0.3, 0.7), 0.5)
    } else {
        (rng.range(0.2, 0.8), rng.range(0.2, 0.8))
    };
    (u, rot_b, edge_point(a, ea, s_a), edge_point(&b, eb, s_b))
}

fn vertex_on_face(a: &ConvexBlock, ref_b: &ConvexBlock, rng: &mut SplitMix64) -> Contact {
    let fa = rng.index(a.n_faces());
    let u = a.planes()[fa].normal;
    let (rot_b, point_b) = turned_vertex(ref_b, -u, rng);
    (u, rot_b, face_point(a, fa, rng), point_b)
}

fn edge_on_face(a: &ConvexBlock, ref_b: &ConvexBlock, rng: &mut SplitMix64) -> Contact {
    let fa = rng.index(a.n_faces());
    let u = a.planes()[fa].normal;
    let eb = rng.index(ref_b.edges().len());
    let align = aligned(edge_normal(ref_b, eb, rng), -u);
    let rot_b = turned_about(u, rng.range(0.0, TAU)) * align;
    let b = ref_b.transformed(rot_b, DVec3::ZERO, 1.0);
    (u, rot_b, face_point(a, fa, rng), edge_point(&b, eb, 0.5))
}

/// The rotation taking unit `from` to unit `to`.
fn aligned(from: DVec3, to: DVec3) -> DQuat {
    DQuat::from_rotation_arc(from, to)
}

fn turned_about(axis: DVec3, angle: f64) -> DQuat {
    DQuat::from_axis_angle(axis, angle)
}

/// The angle that turns `from` onto `to` about `axis` (both normal to it).
fn signed_angle(from: DVec3, to: DVec3, axis: DVec3) -> f64 {
    from.cross(to).dot(axis).atan2(from.dot(to))
}

/// A random turn about `u` after which B's edge crosses A's at a sine of at least 0.2.
fn crossing_angle(dir_a: DVec3, dir_b: DVec3, u: DVec3, rng: &mut SplitMix64) -> f64 {
    loop {
        let angle = rng.range(0.0, TAU);
        if (turned_about(u, angle) * dir_b).cross(dir_a).length() >= 0.2 {
            return angle;
        }
    }
}

/// A random direction strictly inside the normal cone of edge `e` (a positive mix of the
/// normals of its two faces).
fn edge_normal(block: &ConvexBlock, e: usize, rng: &mut SplitMix64) -> DVec3 {
    let [f, g] = block.edges()[e].faces;
    let (nf, ng) = (
        block.planes()[f as usize].normal,
        block.planes()[g as usize].normal,
    );
    (nf * rng.range(0.2, 1.0) + ng * rng.range(0.2, 1.0)).normalize()
}

fn edge_direction(block: &ConvexBlock, e: usize) -> DVec3 {
    let [p, q] = block.edges()[e].vertices;
    (block.vertices()[q as usize] - block.vertices()[p as usize]).normalize()
}

fn edge_point(block: &ConvexBlock, e: usize, s: f64) -> DVec3 {
    let [p, q] = block.edges()[e].vertices;
    let (p, q) = (block.vertices()[p as usize], block.vertices()[q as usize]);
    p + (q - p) * s
}

/// How much lower along the contact normal than the touching vertex every other vertex must
/// be. Blocks are about 1 wide, so the edges at the vertex leave the contact plane at more
/// than about 1 degree: far from grazing, where the gap widening makes a penetration edge
/// long enough to read as an edge (penedge's length threshold is 1000 gaps, an angle of
/// 1e-3 rad).
pub const CLEARANCE: f64 = 0.02;

/// A random rotation of `ref_b` whose farthest vertex along `dir` is clear (see
/// [`CLEARANCE`]), and that vertex, rotated.
fn turned_vertex(ref_b: &ConvexBlock, dir: DVec3, rng: &mut SplitMix64) -> (DQuat, DVec3) {
    loop {
        let rot_b = rng.rotation();
        let b = ref_b.transformed(rot_b, DVec3::ZERO, 1.0);
        if let Some(point_b) = clear_support(&b, dir) {
            return (rot_b, point_b);
        }
    }
}

/// The vertex farthest along unit `dir`, if every other vertex is at least [`CLEARANCE`]
/// behind it.
fn clear_support(block: &ConvexBlock, dir: DVec3) -> Option<DVec3> {
    let mut heights: Vec<(f64, DVec3)> =
        block.vertices().iter().map(|&p| (p.dot(dir), p)).collect();
    heights.sort_by(|x, y| y.0.total_cmp(&x.0));
    (heights[0].0 - heights[1].0 >= CLEARANCE).then_some(heights[0].1)
}

/// The mean of a face's vertices.
fn face_centre(block: &ConvexBlock, f: usize) -> DVec3 {
    let face = block.face(f);
    face.iter()
        .map(|&v| block.vertices()[v as usize])
        .sum::<DVec3>()
        / face.len() as f64
}

/// A point of face `f` near its centre: moved in the face plane by at most 0.15.
fn face_point(block: &ConvexBlock, f: usize, rng: &mut SplitMix64) -> DVec3 {
    let n = block.planes()[f].normal;
    let d = rng.direction();
    let tangent = (d - n * d.dot(n)).normalize_or_zero();
    face_centre(block, f) + tangent * rng.range(0.0, 0.15)
}
