//! Hand-made pairs of each of the seven contact types, against the unit cube, checked in both
//! orders, under rotation, translation to mine-grid coordinates and scaling, and moved off
//! contact (apart, and pushed in beyond the gap).

use glam::{DQuat, DVec3};
use penedge::{ContactType, ConvexBlock, Detector, PairResult, Tolerance};
use proptest::prelude::*;

fn cube() -> ConvexBlock {
    ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap()
}

fn tetra(v: [[f64; 3]; 4]) -> ConvexBlock {
    // Orientation fixed by the sign of the volume.
    let (a, b, c, d) = (
        DVec3::from(v[0]),
        DVec3::from(v[1]),
        DVec3::from(v[2]),
        DVec3::from(v[3]),
    );
    let faces: [[usize; 3]; 4] = if (b - a).cross(c - a).dot(d - a) < 0.0 {
        [[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]
    } else {
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    };
    ConvexBlock::new(&v, &faces).unwrap()
}

/// Block B touching the unit cube with the given type, and a unit direction from A to B
/// along which B moves off the contact.
fn touching(kind: ContactType) -> (ConvexBlock, DVec3) {
    let diag = |v: [f64; 3]| DVec3::from(v).normalize();
    match kind {
        ContactType::VertexVertex => (
            ConvexBlock::cuboid([1.0; 3], [2.0; 3]).unwrap(),
            diag([1.0, 1.0, 1.0]),
        ),
        ContactType::VertexEdge => (
            tetra([
                [1.0, 1.0, 0.5],
                [2.0, 3.0, 0.0],
                [3.0, 2.0, 0.2],
                [2.5, 2.5, 2.0],
            ]),
            diag([1.0, 1.0, 0.0]),
        ),
        ContactType::EdgeEdge => (
            tetra([
                [0.5, 0.5, 1.5],
                [1.5, 0.5, 0.5],
                [1.5, 0.0, 1.5],
                [1.5, 1.0, 1.5],
            ]),
            diag([1.0, 0.0, 1.0]),
        ),
        ContactType::EdgeEdgeSuperposition => (
            ConvexBlock::cuboid([1.0, 1.0, 0.5], [2.0, 2.0, 1.5]).unwrap(),
            diag([1.0, 1.0, 0.0]),
        ),
        ContactType::VertexFace => (
            tetra([
                [0.5, 0.5, 1.0],
                [0.0, 0.0, 2.0],
                [1.5, 0.0, 2.0],
                [0.0, 1.5, 2.0],
            ]),
            DVec3::Z,
        ),
        ContactType::EdgeFace => (
            tetra([
                [0.2, 0.5, 1.0],
                [0.8, 0.5, 1.0],
                [0.5, 0.0, 2.0],
                [0.5, 1.0, 2.0],
            ]),
            DVec3::Z,
        ),
        ContactType::FaceFace => (
            ConvexBlock::cuboid([0.5, 0.5, 1.0], [1.5, 1.5, 2.0]).unwrap(),
            DVec3::Z,
        ),
    }
}

fn both_orders(det: &mut Detector, a: &ConvexBlock, b: &ConvexBlock) -> (PairResult, PairResult) {
    (det.detect(a, b), det.detect(b, a))
}

#[test]
fn each_type_in_both_orders() {
    let mut det = Detector::new(Tolerance::default());
    for kind in ContactType::ALL {
        let (b, _) = touching(kind);
        let (ab, ba) = both_orders(&mut det, &cube(), &b);
        assert_eq!(ab.contact_type(), Some(kind), "{kind}: A, B");
        assert_eq!(ba.contact_type(), Some(kind), "{kind}: B, A");
    }
}

#[test]
fn moved_apart_is_separated_and_pushed_in_is_penetrating() {
    let mut det = Detector::new(Tolerance::default());
    let no_turn = DQuat::IDENTITY;
    for kind in ContactType::ALL {
        let (b, off) = touching(kind);
        let apart = b.transformed(no_turn, off * 1e-6, 1.0);
        let pushed = b.transformed(no_turn, -off * 1e-6, 1.0);
        assert_eq!(
            both_orders(&mut det, &cube(), &apart),
            (PairResult::Separated, PairResult::Separated),
            "{kind}"
        );
        assert_eq!(
            both_orders(&mut det, &cube(), &pushed),
            (PairResult::Penetrating, PairResult::Penetrating),
            "{kind}"
        );
    }
}

#[test]
fn the_gap_decides_between_touching_and_separated() {
    let (b, off) = touching(ContactType::FaceFace);
    let apart = b.transformed(DQuat::IDENTITY, off * 1e-4, 1.0);
    // Scale of the pair: the cube's diagonal, sqrt(3).
    let loose = Detector::new(Tolerance::with_gap(1e-4).unwrap()).detect(&cube(), &apart);
    assert_eq!(loose.contact_type(), Some(ContactType::FaceFace));
    let tight = Detector::new(Tolerance::with_gap(1e-5).unwrap()).detect(&cube(), &apart);
    assert_eq!(tight, PairResult::Separated);
}

#[test]
fn table1_counts_of_face_face_cubes() {
    let mut det = Detector::new(Tolerance::default());
    // Shifted by half a side: on each block two face edges cut once by the other block's side
    // faces (type 2) and one vertical stub at the corner inside the other face (type 3).
    let (b, _) = touching(ContactType::FaceFace);
    det.detect(&cube(), &b);
    assert_eq!(
        det.table1_counts(),
        ([[0, 2, 1, 0, 0], [0, 2, 1, 0, 0]], [1, 1])
    );
    // Face to face: the four face edges of each (type 1) and four vertical stubs (type 3).
    let on_top = ConvexBlock::cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]).unwrap();
    det.detect(&cube(), &on_top);
    assert_eq!(
        det.table1_counts(),
        ([[4, 0, 4, 0, 0], [4, 0, 4, 0, 0]], [4, 4])
    );
}

fn arb_rotation() -> impl Strategy<Value = DQuat> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_filter("non-zero", |(w, x, y, z)| {
            w * w + x * x + y * y + z * z > 1e-3
        })
        .prop_map(|(w, x, y, z)| DQuat::from_xyzw(x, y, z, w).normalize())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn types_survive_rigid_motion_and_scaling(
        k in 0usize..7,
        q in arb_rotation(),
        t in prop_oneof![Just(DVec3::ZERO), Just(DVec3::new(5e5, 4e6, 1e3)), (-1e3..1e3f64).prop_map(DVec3::splat)],
        s in prop_oneof![Just(1.0), Just(1e-3), Just(1e3), 0.1..10.0f64],
    ) {
        let kind = ContactType::ALL[k];
        let (b, _) = touching(kind);
        let (a, b) = (cube().transformed(q, t, s), b.transformed(q, t, s));
        let mut det = Detector::new(Tolerance::default());
        let (ab, ba) = both_orders(&mut det, &a, &b);
        prop_assert_eq!(ab.contact_type(), Some(kind));
        prop_assert_eq!(ba.contact_type(), Some(kind));
    }

    #[test]
    fn apart_and_pushed_survive_rigid_motion(k in 0usize..7, q in arb_rotation(), s in 0.01..100.0f64) {
        let kind = ContactType::ALL[k];
        let (b, off) = touching(kind);
        let mut det = Detector::new(Tolerance::default());
        let a = cube().transformed(q, DVec3::ZERO, s);
        let apart = b.transformed(DQuat::IDENTITY, off * 1e-7, 1.0).transformed(q, DVec3::ZERO, s);
        let pushed = b.transformed(DQuat::IDENTITY, -off * 1e-7, 1.0).transformed(q, DVec3::ZERO, s);
        prop_assert_eq!(det.detect(&a, &apart), PairResult::Separated);
        prop_assert_eq!(det.detect(&pushed, &a), PairResult::Penetrating);
    }
}

/// A random convex block: the unit cube's six planes tilted and moved at random.
fn arb_block() -> impl Strategy<Value = ConvexBlock> {
    prop::collection::vec((-0.3..0.3f64, -0.3..0.3f64, 0.5..1.5f64), 6).prop_filter_map(
        "valid",
        |p| {
            let axes = [
                DVec3::X,
                -DVec3::X,
                DVec3::Y,
                -DVec3::Y,
                DVec3::Z,
                -DVec3::Z,
            ];
            let normals: Vec<[f64; 3]> = axes
                .iter()
                .zip(&p)
                .map(|(a, (u, v, _))| {
                    (*a + a.any_orthonormal_pair().0 * *u + a.any_orthonormal_pair().1 * *v)
                        .to_array()
                })
                .collect();
            let offsets: Vec<f64> = p.iter().map(|(_, _, d)| *d).collect();
            ConvexBlock::from_planes(&normals, &offsets).ok()
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Random blocks in random placements: the answer does not depend on the order.
    #[test]
    fn random_pairs_answer_the_same_in_both_orders(
        a in arb_block(),
        b in arb_block(),
        q in arb_rotation(),
        t in (-2.5..2.5f64, -2.5..2.5f64, -2.5..2.5f64),
    ) {
        let b = b.transformed(q, DVec3::new(t.0, t.1, t.2), 1.0);
        let mut det = Detector::new(Tolerance::default());
        let ab = det.detect(&a, &b);
        let ba = det.detect(&b, &a);
        prop_assert_eq!(ab.name(), ba.name());
    }
}

/// A prism on a regular `n`-gon of circumradius 1, z from -1 to 0, from half-spaces.
fn prism(n: usize) -> ConvexBlock {
    let mut normals: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let apothem = (std::f64::consts::PI / n as f64).cos();
    let mut offsets = vec![apothem; n];
    normals.extend([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]);
    offsets.extend([0.0, 1.0]);
    ConvexBlock::from_planes(&normals, &offsets).unwrap()
}

/// Blocks with more than 16 faces are clipped without the per-vertex face masks: the same
/// answers as with them.
#[test]
fn blocks_with_many_faces_use_the_unmasked_path_with_the_same_answers() {
    let mut det = Detector::new(Tolerance::default());
    for n in [10, 14, 15, 30, 70] {
        let base = prism(n);
        assert_eq!(base.n_faces(), n + 2);
        let on_top = ConvexBlock::cuboid([-0.2, -0.2, 0.0], [0.2, 0.2, 0.4]).unwrap();
        let corner = tetra([
            [0.0, 0.0, 0.0],
            [-0.3, -0.3, 0.5],
            [0.3, -0.3, 0.5],
            [0.0, 0.4, 0.5],
        ]);
        let cases = [
            (on_top.clone(), Some(ContactType::FaceFace)),
            (corner, Some(ContactType::VertexFace)),
            (
                on_top.transformed(DQuat::IDENTITY, DVec3::Z * 1e-6, 1.0),
                None,
            ),
        ];
        for (b, kind) in cases {
            let (ab, ba) = both_orders(&mut det, &base, &b);
            assert_eq!(
                (ab.contact_type(), ba.contact_type()),
                (kind, kind),
                "{n} faces"
            );
        }
        let pushed = on_top.transformed(DQuat::IDENTITY, -DVec3::Z * 1e-6, 1.0);
        assert_eq!(
            both_orders(&mut det, &base, &pushed),
            (PairResult::Penetrating, PairResult::Penetrating)
        );
    }
}
