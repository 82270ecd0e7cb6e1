//! The tolerance policy (docs/tolerance.md), swept: for each of the seven contact types, block B
//! moves from clearly apart, through the edge of the gap, to touching and on to penetrating, and
//! the answer changes exactly where the policy says; then the length threshold: contacts whose
//! extent shrinks below it change type exactly there. Every answer is also checked in the other
//! order (B, A) and through the system detector (broad phase + narrow phase), and the
//! thresholds against the policy's formula.
//!
//! The configurations (A is the unit cube) are built so that the policy's boundaries are known
//! in closed form. B moves by `δ w`: `n · w = 1` for every face normal `n` of A at the contact
//! point `c`, and B has a face normal `m` at `c` with `m · w = -1` (for the vertex-face,
//! edge-face and face-face cases `w` is the face normal and A's edges stay far from B). So
//! B's contact point lies at the signed distance `δ` from every face plane of A through `c`, and
//! A's at `δ` from B's. With the gap `g` of the pair (the paper's widening: every face plane
//! moved out by `g`):
//!
//! * `δ > g`: the plane of A with normal `-m` separates A widened by `g` from B, and A from B
//!   widened: *separated*;
//! * `-g <= δ <= g`: B's contact point lies in A widened, on an edge of B: a contact, of the
//!   type of the configuration;
//! * `δ < -g`: B's contact point, on an edge of B, is deeper than `g` inside A: *penetrating*.

use glam::{DQuat, DVec3};
use penedge::cutting::split_block;
use penedge::geometry::Plane;
use penedge::penetration::{PenetrationEdgeType, Side};
use penedge::system::{BroadPhase, PairContact};
use penedge::tolerance::{Thresholds, ROUNDING_FLOOR};
use penedge::{BlockError, BlockSystem, ContactType, ConvexBlock, Detector, PairResult, Tolerance};

fn cube() -> ConvexBlock {
    ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap()
}

fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
    ConvexBlock::cuboid(lo, hi).unwrap()
}

/// A tetrahedron from four points in any order.
fn tetra(v: [[f64; 3]; 4]) -> ConvexBlock {
    let p = v.map(DVec3::from);
    let faces: [[usize; 3]; 4] = if (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) < 0.0 {
        [[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]
    } else {
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    };
    ConvexBlock::new(&v, &faces).unwrap()
}

/// A wedge along x from `x0` to `x1`: its lower edge at y = 0.5, z = 1, its top face at
/// z = 1.5 from y = 0.2 to 0.8; the end faces are planes x = x0 and x = x1.
fn wedge(x0: f64, x1: f64) -> ConvexBlock {
    let section = [[0.5, 1.0], [0.8, 1.5], [0.2, 1.5]];
    let v: Vec<[f64; 3]> = [x0, x1]
        .iter()
        .flat_map(|&x| section.map(|[y, z]| [x, y, z]))
        .collect();
    let faces: [&[usize]; 5] = [
        &[0, 2, 1],
        &[3, 4, 5],
        &[0, 1, 4, 3],
        &[1, 2, 5, 4],
        &[2, 0, 3, 5],
    ];
    ConvexBlock::new(&v, &faces).unwrap()
}

/// The block rebuilt from its vertices mapped by `f` (planes fitted again, as for any input).
fn rebuilt(b: &ConvexBlock, f: impl Fn(DVec3) -> DVec3) -> ConvexBlock {
    let v: Vec<[f64; 3]> = b.vertices().iter().map(|&p| f(p).to_array()).collect();
    let faces: Vec<Vec<usize>> = b
        .faces()
        .map(|f| f.iter().map(|&i| i as usize).collect())
        .collect();
    ConvexBlock::new(&v, &faces).unwrap()
}

/// The contact point of the edge-edge configuration and the common normal direction.
const CROSSING: [f64; 3] = [0.5, 0.0, 1.0];

/// B of the edge-edge (crossing) configuration: the cube [0, 1] x [-1, 0] x [1, 2], which
/// touches A along A's edge y = 0, z = 1, turned by 90° about the bisector (0, -1, 1) of the
/// two faces at that edge, through (0.5, 0, 1). Its edge now runs along (0, 1, 1) and crosses
/// A's edge at (0.5, 0, 1); its two faces there keep `m · (0, -1, 1) = -1`.
fn crossing_cube(shift_x: f64) -> ConvexBlock {
    let c = DVec3::from(CROSSING);
    let axis = DVec3::new(0.0, -1.0, 1.0).normalize();
    let turn = DQuat::from_axis_angle(axis, std::f64::consts::FRAC_PI_2);
    let moved = c + DVec3::X * shift_x;
    rebuilt(&cuboid([0.0, -1.0, 1.0], [1.0, 0.0, 2.0]), |p| {
        turn * (p - c) + moved
    })
}

/// For each type, B touching the unit cube and the motion `w` per unit of `δ`.
fn configurations() -> Vec<(ContactType, ConvexBlock, DVec3)> {
    let edge_w = DVec3::new(0.0, -1.0, 1.0);
    vec![
        (
            ContactType::VertexVertex,
            cuboid([1.0; 3], [2.0; 3]),
            DVec3::ONE,
        ),
        (
            // B's vertex (0.5, 0, 1) on A's edge y = 0, z = 1; B's bottom face in z = 1.
            ContactType::VertexEdge,
            tetra([
                [0.5, 0.0, 1.0],
                [0.0, -1.0, 1.0],
                [1.0, -1.0, 1.0],
                [0.5, -0.5, 2.0],
            ]),
            edge_w,
        ),
        (ContactType::EdgeEdge, crossing_cube(0.0), edge_w),
        (
            // B's edge y = 0, z = 1 overlaps A's along x in [0.5, 1].
            ContactType::EdgeEdgeSuperposition,
            cuboid([0.5, -1.0, 1.0], [1.5, 0.0, 2.0]),
            edge_w,
        ),
        (
            ContactType::VertexFace,
            tetra([
                [0.5, 0.5, 1.0],
                [0.0, 0.0, 2.0],
                [1.0, 0.0, 2.0],
                [0.5, 1.0, 2.0],
            ]),
            DVec3::Z,
        ),
        (ContactType::EdgeFace, wedge(0.2, 0.8), DVec3::Z),
        (
            ContactType::FaceFace,
            cuboid([0.25, 0.25, 1.0], [0.75, 0.75, 2.0]),
            DVec3::Z,
        ),
        (
            // Face-face with A's top edges crossing B's bottom face.
            ContactType::FaceFace,
            cuboid([0.5, 0.5, 1.0], [1.5, 1.5, 2.0]),
            DVec3::Z,
        ),
    ]
}

/// The thresholds of a pair as docs/tolerance.md states them, computed here from the blocks'
/// bounding boxes.
fn policy(tol: &Tolerance, a: &ConvexBlock, b: &ConvexBlock) -> Thresholds {
    let scale = a.aabb().diagonal().min(b.aabb().diagonal());
    let magnitude = a.aabb().magnitude().max(b.aabb().magnitude());
    let gap = (tol.gap() * scale).max(ROUNDING_FLOOR * magnitude);
    let length = (tol.length() * scale).max(10.0 * gap);
    Thresholds {
        gap,
        length,
        sine: length / scale,
    }
}

/// The answer for (A, B), checked against (B, A) and against the system detector.
fn answer(tol: &Tolerance, a: &ConvexBlock, b: &ConvexBlock, what: &str) -> PairResult {
    let mut det = Detector::new(*tol);
    let ab = det.detect(a, b);
    check_table1(&det, a, b, what);
    let ba = det.detect(b, a);
    let swapped = match ba {
        PairResult::Contact(mut c) => {
            std::mem::swap(&mut c.feature_a, &mut c.feature_b);
            PairResult::Contact(c)
        }
        other => other,
    };
    assert_eq!(ab, swapped, "{what}: (A, B) and (B, A) differ");
    let system = BlockSystem::new(vec![a.clone(), b.clone()]);
    if ab != PairResult::Separated {
        // Every broad phase keeps a pair that the narrow phase finds in contact.
        for method in BroadPhase::ALL {
            let pairs = system.candidate_pairs_by(tol, method);
            assert_eq!(pairs, [[0, 1]], "{what}: broad phase {}", method.name());
        }
    }
    let found = system.detect(tol);
    let (contacts, penetrating): (Vec<PairContact>, Vec<[u32; 2]>) = match ab {
        PairResult::Separated => (vec![], vec![]),
        PairResult::Contact(contact) => (
            vec![PairContact {
                pair: [0, 1],
                contact,
            }],
            vec![],
        ),
        PairResult::Penetrating => (vec![], vec![[0, 1]]),
    };
    assert_eq!(found.contacts, contacts, "{what}: system detection differs");
    assert_eq!(
        found.penetrating, penetrating,
        "{what}: system detection differs"
    );
    ab
}

/// Every penetration edge of the last pair has length (Table 1 types 1, 2, 4) exactly when it
/// is longer than the pair's length threshold.
fn check_table1(det: &Detector, a: &ConvexBlock, b: &ConvexBlock, what: &str) {
    let length = det.thresholds(a, b).length;
    for pe in det.penetration_edges() {
        let owner = if pe.side == Side::A { a } else { b };
        let [p, q] = pe.points(owner);
        let piece = p.distance(q);
        if (piece - length).abs() > 1e-6 * length {
            assert_eq!(
                pe.kind.has_length(),
                piece > length,
                "{what}: a piece {piece:e} long, threshold {length:e}: {:?}",
                pe.kind
            );
        }
    }
}

/// Positions of B, in units of the gap, from clearly apart to penetrating, with the answer
/// the policy gives; `m` is the relative margin either side of a boundary.
fn sweep(m: f64) -> Vec<(f64, Option<bool>)> {
    // None: separated; Some(false): the contact; Some(true): penetrating.
    vec![
        (1e3, None),
        (10.0, None),
        (2.0, None),
        (1.0 + m, None),
        (1.0 - m, Some(false)),
        (0.5, Some(false)),
        (0.0, Some(false)),
        (-0.5, Some(false)),
        (-(1.0 - m), Some(false)),
        (-(1.0 + m), Some(true)),
        (-2.0, Some(true)),
        (-10.0, Some(true)),
    ]
}

fn outcome(expected: Option<bool>, kind: ContactType) -> String {
    match expected {
        None => "separated".into(),
        Some(false) => kind.name().into(),
        Some(true) => "penetrating".into(),
    }
}

/// Runs the sweep of every configuration, with the whole pair mapped by `frame` (a translation
/// or a scaling, applied to every vertex, then the blocks rebuilt), B then moved by `δ w`;
/// `m` is the relative margin.
fn sweep_all(tol: &Tolerance, frame: impl Fn(DVec3) -> DVec3, m: f64, label: &str) {
    let a = rebuilt(&cube(), &frame);
    for (kind, b0, w) in configurations() {
        let b_touching = rebuilt(&b0, &frame);
        let th = Detector::new(*tol).thresholds(&a, &b_touching);
        assert_eq!(
            th,
            policy(tol, &a, &b_touching),
            "{label} {kind}: thresholds"
        );
        assert!(th.length >= 10.0 * th.gap);
        for (units, expected) in sweep(m) {
            let delta = units * th.gap;
            let b = rebuilt(&b0, |p| frame(p) + w * delta);
            let what = format!("{label} {kind}, δ = {units} gap ({delta:e})");
            let got = answer(tol, &a, &b, &what);
            assert_eq!(got.name(), outcome(expected, kind), "{what}");
        }
    }
}

#[test]
fn each_type_separates_beyond_the_gap_and_penetrates_beyond_minus_the_gap() {
    for tol in [
        Tolerance::default(),
        Tolerance::with_gap(1e-6).unwrap(),
        Tolerance::with_gap(1e-3).unwrap(),
        Tolerance::new(1e-4, 1e-2).unwrap(),
    ] {
        // Rounding of coordinates near 1 against the gap: a relative margin of 1e-6 when the
        // gap is large, more at the default gap (2e-12 against rounding of 2e-16).
        let m = (64.0 * f64::EPSILON / (tol.gap() * 3f64.sqrt())).max(1e-6);
        assert!(m < 0.02);
        sweep_all(&tol, |p| p, m, &format!("{tol:?}"));
    }
}

#[test]
fn the_boundaries_scale_with_the_blocks() {
    for s in [1e-3, 1e3] {
        let tol = Tolerance::with_gap(1e-6).unwrap();
        sweep_all(&tol, |p| p * s, 1e-6, &format!("scale {s}"));
    }
}

#[test]
fn in_mine_grid_coordinates_the_gap_is_the_rounding_floor() {
    let far = DVec3::new(5e5, 4e6, 1e3);
    let tol = Tolerance::default();
    let a = rebuilt(&cube(), |p| p + far);
    let th = Detector::new(tol).thresholds(&a, &a);
    // 16 units of rounding of y = 4e6 (about 1.4e-8), far above 1e-12 x sqrt(3).
    assert_eq!(th.gap, ROUNDING_FLOOR * (4e6 + 1.0));
    assert!(th.gap > 1e3 * tol.gap() * a.size());
    // Coordinates near 4e6 are rounded to 4.7e-10, 3% of this gap: margins of 25%.
    sweep_all(&tol, |p| p + far, 0.25, "mine grid");
}

/// The length threshold: a contact whose extent shrinks below it changes type exactly there.
/// Each case gives B for an extent `l`, the type above the threshold and the type below.
#[allow(clippy::type_complexity)]
fn shrinking() -> Vec<(
    &'static str,
    Box<dyn Fn(f64) -> ConvexBlock>,
    ContactType,
    ContactType,
)> {
    use ContactType::*;
    vec![
        (
            // Two collinear edges overlapping by l: a superposition, or a point (the two
            // corners within l of each other: one vertex).
            "edge overlap",
            Box::new(|l| cuboid([1.0 - l, -1.0, 1.0], [2.0 - l, 0.0, 2.0])),
            EdgeEdgeSuperposition,
            VertexVertex,
        ),
        (
            // B's vertex on A's face y = 0, l below A's edge y = 0, z = 1.
            "vertex below an edge",
            Box::new(|l| {
                tetra([
                    [0.5, 0.0, 1.0 - l],
                    [0.0, -1.0, 1.0 - l],
                    [1.0, -1.0, 1.0 - l],
                    [0.5, -0.5, 2.0 - l],
                ])
            }),
            VertexFace,
            VertexEdge,
        ),
        (
            // B's edge crossing A's edge l from A's vertex (1, 0, 1).
            "crossing near a vertex",
            Box::new(|l| crossing_cube(0.5 - l)),
            EdgeEdge,
            VertexEdge,
        ),
        (
            // B's edge lying on A's top face over a length l, then leaving it over A's
            // edge x = 1.
            "edge partly on a face",
            Box::new(|l| wedge(1.0 - l, 1.6 - l)),
            EdgeFace,
            VertexEdge,
        ),
        (
            // B's bottom face overlapping A's top face in a strip of width l.
            "face strip",
            Box::new(|l| cuboid([1.0 - l, 0.25, 1.0], [2.0 - l, 0.75, 2.0])),
            FaceFace,
            EdgeEdgeSuperposition,
        ),
    ]
}

#[test]
fn a_contact_narrower_than_the_length_threshold_changes_type_there() {
    // The gap small against the length threshold, so that the stubs it adds (about a gap
    // long) stay well inside the margin.
    for tol in [Tolerance::new(1e-8, 1e-3).unwrap(), Tolerance::default()] {
        let a = cube();
        for (what, b_of, wide, narrow) in shrinking() {
            let th = Detector::new(tol).thresholds(&a, &b_of(0.1));
            // Margins of 0.1% (10% at the default ratio length / gap = 1000).
            let m = (100.0 * th.gap / th.length).max(1e-3);
            assert!(m <= 0.1, "{what}");
            for (units, kind) in [
                (100.0, wide),
                (1.0 + m, wide),
                (1.0 - m, narrow),
                (0.5, narrow),
            ] {
                let l = units * th.length;
                let b = b_of(l);
                // B's size (the scale when B is the smaller block) moves by rounding only.
                let th_b = Detector::new(tol).thresholds(&a, &b);
                assert!(
                    (th_b.length - th.length).abs() <= 1e-12 * th.length,
                    "{what}"
                );
                let label = format!("{what}, {tol:?}, l = {units} x length");
                let got = answer(&tol, &a, &b, &label);
                if what == "edge overlap" {
                    // A's edge y = 0, z = 1 is in contact over l (and the gap): from its vertex
                    // (1, 0, 1), a piece with length (type 2) or a stub (type 3).
                    let mut det = Detector::new(tol);
                    det.detect(&a, &b);
                    let along_x = |pe: &&penedge::penetration::PenetrationEdge| {
                        let [p, q] = pe.points(&a);
                        pe.side == Side::A && (p - q).normalize().x.abs() > 0.99
                    };
                    let piece = det.penetration_edges().iter().find(along_x).unwrap();
                    let expected = if kind == wide {
                        PenetrationEdgeType::T2
                    } else {
                        PenetrationEdgeType::T3
                    };
                    assert_eq!(piece.kind, expected, "{label}");
                }
                assert_eq!(got.contact_type(), Some(kind), "{label}");
            }
        }
    }
}

#[test]
fn along_a_corner_diagonal_the_widening_reaches_farther_than_the_gap() {
    // The widening moves every face plane out by the gap (it is not a ball of radius gap):
    // corners of the widened cube lie sqrt(3) gaps from the corners of the cube. The
    // vertex-vertex sweep above moves B along (1, 1, 1): at δ = 0.9 gap its corner is
    // 1.56 gaps away, and the pair touches.
    let tol = Tolerance::with_gap(1e-3).unwrap();
    let a = cube();
    let th = Detector::new(tol).thresholds(&a, &a);
    let corner = |d: f64| cuboid([1.0 + d; 3], [2.0 + d; 3]);
    let touching = corner(0.9 * th.gap);
    assert!(touching.vertices()[0].distance(DVec3::ONE) > 1.5 * th.gap);
    assert_eq!(
        answer(&tol, &a, &touching, "diagonal").contact_type(),
        Some(ContactType::VertexVertex)
    );
    // Along a face normal, the boundary is the gap itself.
    let above = |d: f64| cuboid([0.25, 0.25, 1.0 + d], [0.75, 0.75, 2.0 + d]);
    assert_eq!(
        answer(&tol, &a, &above(1.001 * th.gap), "above"),
        PairResult::Separated
    );
}

#[test]
fn blocks_and_cuts_use_the_length_threshold_of_the_policy() {
    // Block validation: a vertex off its face plane by less than the length threshold (at the
    // block's own scale) is on it; by more, the face is not planar.
    let tol = Tolerance::new(1e-6, 1e-4).unwrap();
    let length = tol.for_box(&cube().aabb()).length;
    assert_eq!(length, 1e-4 * 3f64.sqrt());
    let faces = cube().faces().map(|f| f.to_vec()).collect::<Vec<_>>();
    let lifted = |h: f64| {
        let mut v: Vec<[f64; 3]> = cube().vertices().iter().map(|p| p.to_array()).collect();
        v[6][2] += h; // the corner (1, 1, 1), in three faces
        let faces: Vec<Vec<usize>> = faces
            .iter()
            .map(|f| f.iter().map(|&i| i as usize).collect())
            .collect();
        ConvexBlock::with_tolerance(&v, &faces, &tol)
    };
    // Newell's plane of the lifted top face passes a quarter of the lift below the corner.
    assert!(lifted(0.99 * 4.0 * length).is_ok());
    assert!(matches!(
        lifted(1.01 * 4.0 * length),
        Err(BlockError::NonPlanarFace { .. })
    ));
    // Cutting: a plane within the length threshold of the top face does not cut the cube.
    let plane = |z: f64| Plane {
        normal: DVec3::Z,
        point: DVec3::new(0.0, 0.0, z),
    };
    let below = split_block(&cube(), &plane(1.0 - 0.99 * length), &tol).unwrap();
    assert!(below.above.is_none() && below.below.is_some());
    let cut = split_block(&cube(), &plane(1.0 - 1.01 * length), &tol).unwrap();
    assert!(cut.above.is_some() && cut.below.is_some());
}

/// B with its bottom face on the plane through A's edge y = 0, z = 1 at 45° (normal
/// `n = (0, -1, 1) / sqrt 2`), moved out along `n` by `s`: B's bottom face covers A's edge for
/// x in [0.5, 1], and B's edge x = 0.5 runs across it.
fn tilted_box(s: f64) -> ConvexBlock {
    let n = DVec3::new(0.0, -1.0, 1.0) / 2f64.sqrt();
    let t = DVec3::new(0.0, 1.0, 1.0) / 2f64.sqrt();
    let c = DVec3::new(0.0, 0.0, 1.0) + n * s;
    let v: Vec<[f64; 3]> = [0.5, 1.5]
        .iter()
        .flat_map(|&x| {
            [(-0.5, 0.0), (0.5, 0.0), (0.5, 1.0), (-0.5, 1.0)]
                .map(|(a, b)| (c + DVec3::X * x + t * a + n * b).to_array())
        })
        .collect();
    let faces: [&[usize]; 6] = [
        &[0, 1, 5, 4],
        &[3, 7, 6, 2],
        &[0, 3, 2, 1],
        &[4, 5, 6, 7],
        &[0, 4, 7, 3],
        &[1, 2, 6, 5],
    ];
    let b = ConvexBlock::new(&v, &faces).or_else(|_| {
        let flipped: Vec<Vec<usize>> = faces
            .iter()
            .map(|f| f.iter().rev().copied().collect())
            .collect();
        ConvexBlock::new(&v, &flipped)
    });
    b.unwrap()
}

/// The policy's first rule: a face plane of one block with the whole other block farther than
/// the gap separates the pair, even where the other block widened by the gap (the paper's
/// widening, its face planes moved out) would reach an edge of the first. Here A's edge
/// y = 0, z = 1 is 90°, so A widened reaches sqrt(2) gaps along `n`: at s = 1.2 gaps B's
/// edge x = 0.5 still meets widened A (a penetration edge by the paper's rule alone), but B's
/// bottom plane has all of A beyond the gap, and the pair is separated. So along the normal of
/// a face, the boundary is the gap itself, whatever the shape of the other block.
#[test]
fn a_face_plane_farther_than_the_gap_separates() {
    let tol = Tolerance::with_gap(1e-3).unwrap();
    let a = cube();
    let g = Detector::new(tol).thresholds(&a, &tilted_box(0.0)).gap;
    assert_eq!(
        answer(&tol, &a, &tilted_box(0.0), "s = 0").contact_type(),
        Some(ContactType::EdgeFace)
    );
    assert_eq!(
        answer(&tol, &a, &tilted_box(0.99 * g), "s = 0.99 gap").contact_type(),
        Some(ContactType::EdgeFace)
    );
    // B's edge x = 0.5 at s = 1.2 gaps: its point above A's edge is 0.85 gaps from A's
    // faces y = 0 and z = 1, inside A widened.
    let b = tilted_box(1.2 * g);
    let above_edge = DVec3::new(0.5, 0.0, 1.0) + DVec3::new(0.0, -1.0, 1.0) / 2f64.sqrt() * 1.2 * g;
    assert!(-above_edge.y <= g && above_edge.z - 1.0 <= g);
    assert_eq!(answer(&tol, &a, &b, "s = 1.2 gap"), PairResult::Separated);
    assert_eq!(
        answer(&tol, &a, &tilted_box(1.01 * g), "s = 1.01 gap"),
        PairResult::Separated
    );
}

/// A polygonal joint is flat when its vertices lie within the policy's length threshold
/// (relative, here 1e-10) of its plane, scaled by its perimeter: no fixed 1e-9 of its own.
#[test]
fn polygon_joints_are_flat_within_the_policy_length() {
    use penedge::generation::{generate, Discontinuity, Domain, Options, Spec};
    let spec = |tolerance: Tolerance, lift: f64| {
        let square = vec![
            [2.0, 2.0, 5.0],
            [8.0, 2.0, 5.0],
            [8.0, 8.0, 5.0 + lift],
            [2.0, 8.0, 5.0],
        ];
        let mut spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap())
            .with(Discontinuity::polygon(square));
        spec.options = Options {
            tolerance,
            ..Options::default()
        };
        spec
    };
    // Newell's plane of the square passes a quarter of the lift from each corner; the
    // perimeter is 24: flat while lift / 4 <= 24 x length.
    let fine = Tolerance::new(1e-12, 1e-10).unwrap();
    let threshold = 4.0 * 24.0 * 1e-10;
    assert!(generate(&spec(fine, 0.5 * threshold)).is_ok());
    let err = generate(&spec(fine, 2.0 * threshold))
        .unwrap_err()
        .to_string();
    assert!(err.contains("not in one plane"), "{err}");
    assert!(generate(&spec(Tolerance::default(), 2.0 * threshold)).is_ok());
}
