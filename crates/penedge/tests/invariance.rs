//! The same contacts (pairs, types and features) after moving the whole system: a random
//! rotation, a translation to mine-grid coordinates (x ≈ 5e5, y ≈ 4e6, z ≈ 1e3), scalings by
//! 1e-3 and 1e3, and all of them together; and the same answer for (B, A) as for (A, B) on
//! every candidate pair. On the paper's three examples and on random jointed systems (a few
//! hundred blocks each).

mod support;

use glam::DQuat;
use penedge::generation::rng::SplitMix64;
use penedge::generation::{generate, Discontinuity, Domain, JointSet, Orientation, Spec};
use penedge::geometry::DVec3;
use penedge::system::count_types;
use penedge::system::{paper_example, PaperExample};
use penedge::{BlockSystem, ContactType, ConvexBlock, Detector, Feature, PairResult, Tolerance};
use support::{
    answer, dev_cases, differences, jointed, lies_in_sine, pairs_of_every_type, rebuilt, rotation,
    sheared, transformed,
};

/// A map of every vertex.
type Frame = Box<dyn Fn(DVec3) -> DVec3>;

const MINE_GRID: DVec3 = DVec3::new(5e5, 4e6, 1e3);

/// The motions applied to a system, with a label.
fn motions(seed: u64) -> Vec<(String, DQuat, DVec3, f64)> {
    let mut r = SplitMix64::new(seed);
    let q = rotation(&mut r);
    let id = DQuat::IDENTITY;
    vec![
        ("rotation".into(), q, DVec3::ZERO, 1.0),
        ("mine grid".into(), id, MINE_GRID, 1.0),
        ("scale 1e-3".into(), id, DVec3::ZERO, 1e-3),
        ("scale 1e3".into(), id, DVec3::ZERO, 1e3),
        ("all".into(), rotation(&mut r), MINE_GRID, 1e3),
        ("rotated, small, far".into(), q, MINE_GRID * 1e-3, 1e-3),
    ]
}

/// The contacts of `sys` and of every moved copy are the same.
fn check_motions(sys: &BlockSystem, label: &str, seed: u64) {
    let tol = Tolerance::default();
    let expected = answer(&sys.detect(&tol));
    assert!(!expected.0.is_empty());
    for (what, q, t, s) in motions(seed) {
        let got = answer(&transformed(sys, q, t, s).detect(&tol));
        assert!(
            got == expected,
            "{label}, {what}: {}",
            differences(&expected, &got)
        );
    }
}

/// Every candidate pair answers the same in both orders, features swapped.
fn check_swap(sys: &BlockSystem, label: &str) {
    let mut det = Detector::new(Tolerance::default());
    let blocks = sys.blocks();
    let mut checked = 0;
    for [i, j] in sys.candidate_pairs(&Tolerance::default()) {
        let (a, b) = (&blocks[i as usize], &blocks[j as usize]);
        let ab = det.detect(a, b);
        let ba = match det.detect(b, a) {
            PairResult::Contact(mut c) => {
                std::mem::swap(&mut c.feature_a, &mut c.feature_b);
                PairResult::Contact(c)
            }
            other => other,
        };
        assert_eq!(ab, ba, "{label}: pair {i}, {j}");
        checked += 1;
    }
    assert!(checked > 0);
}

#[test]
fn paper_examples_are_invariant() {
    for (n, example) in [PaperExample::One, PaperExample::Two, PaperExample::Three]
        .into_iter()
        .enumerate()
    {
        let sys = paper_example(example).unwrap();
        check_motions(&sys, &format!("example {}", n + 1), n as u64);
        check_swap(&sys, &format!("example {}", n + 1));
        for (what, q, t, s) in motions(n as u64) {
            check_swap(
                &transformed(&sys, q, t, s),
                &format!("example {}, {what}", n + 1),
            );
        }
    }
}

#[test]
fn random_jointed_systems_are_invariant() {
    for seed in 0..3 {
        let sys = jointed(seed);
        assert!(sys.len() >= 150, "seed {seed}: {} blocks", sys.len());
        check_motions(&sys, &format!("seed {seed}"), 100 + seed);
        check_swap(&sys, &format!("seed {seed}"));
    }
}

#[test]
fn sheared_jointed_systems_are_invariant() {
    for seed in 0..2 {
        let sys = sheared(seed);
        check_motions(&sys, &format!("sheared, seed {seed}"), 200 + seed);
        check_swap(&sys, &format!("sheared, seed {seed}"));
    }
}

#[test]
fn pairs_of_every_type_are_invariant() {
    let sys = pairs_of_every_type();
    let found = sys.detect(&Tolerance::default());
    assert_eq!(count_types(&found.contacts), [6; 7]);
    check_motions(&sys, "pairs", 300);
    check_swap(&sys, "pairs");
}

#[test]
fn moved_systems_answer_the_same_in_both_orders() {
    let sys = jointed(7);
    for (what, q, t, s) in motions(7) {
        check_swap(&transformed(&sys, q, t, s), &format!("seed 7, {what}"));
    }
}

/// Blocks given by their vertices in the new frame (planes fitted again from rounded
/// coordinates, as when a project's blocks are read in mine-grid coordinates) give the same
/// contacts as well.
#[test]
fn blocks_rebuilt_in_the_moved_frame_are_invariant() {
    let tol = Tolerance::default();
    for (label, sys) in [
        ("example 3", paper_example(PaperExample::Three).unwrap()),
        ("seed 3", jointed(3)),
    ] {
        let expected = answer(&sys.detect(&tol));
        let mut r = SplitMix64::new(11);
        let q = rotation(&mut r);
        let frames: [(&str, Frame); 3] = [
            ("mine grid", Box::new(|p| p + MINE_GRID)),
            ("rotated", Box::new(move |p| q * p)),
            (
                "rotated, mine grid, scale 1e-3",
                Box::new(move |p| q * p * 1e-3 + MINE_GRID),
            ),
        ];
        for (what, f) in frames {
            let got = answer(&rebuilt(&sys, f).detect(&tol));
            assert!(
                got == expected,
                "{label}, {what}: {}",
                differences(&expected, &got)
            );
        }
    }
}

/// The sine of the angle between edge `ea` of `a` and edge `eb` of `b`.
fn edges_sine(a: &ConvexBlock, ea: u32, b: &ConvexBlock, eb: u32) -> f64 {
    let direction = |block: &ConvexBlock, e: u32| {
        let [p, q] = block.edges()[e as usize].vertices;
        block.vertices()[q as usize] - block.vertices()[p as usize]
    };
    let (u, v) = (direction(a, ea), direction(b, eb));
    u.cross(v).length() / (u.length() * v.length())
}

/// The exact dev cases that touch, moved by exact translations (every coordinate stays
/// representable, so the geometry is the same) to mine-grid coordinates up to 1e7, at their
/// own size (about 1 to 20 m) and scaled by 2^-6 (2 to 30 cm), grazing families included: the
/// same types and features as at the origin. The one change the rule allows (docs/tolerance.md,
/// "Lies in"): two edges crossing at an angle whose sine is below the rule's sine at the new
/// magnitude (the rounding floor's) lie along each other there, a superposition.
#[test]
fn touching_dev_cases_are_invariant_under_exact_translation() {
    let tol = Tolerance::default();
    let mut det = Detector::new(tol);
    let offsets = [
        DVec3::new(512345.5, 4012345.25, 1234.125),
        DVec3::new(-9999999.5, 9999999.75, 3e6),
        DVec3::new(1e7, 1e7, -1e7),
    ];
    let (mut compared, mut inexact, mut along) = (0, 0, 0);
    for case in dev_cases::cases() {
        let id = case["id"].as_str().unwrap();
        if ["separated", "penetrating"].contains(&case["expected"].as_str().unwrap()) {
            continue;
        }
        for scale in [1.0, 2f64.powi(-6)] {
            let mut at = |offset: DVec3| {
                let exact = [&case["a"], &case["b"]].iter().all(|v| {
                    dev_cases::vertices(v)
                        .iter()
                        .all(|&p| (p * scale + offset) - offset == p * scale)
                });
                exact.then(|| {
                    let f = |p: DVec3| p * scale + offset;
                    let (a, b) = (
                        dev_cases::block_moved(&case["a"], f),
                        dev_cases::block_moved(&case["b"], f),
                    );
                    (det.detect(&a, &b), a, b)
                })
            };
            let (expected, ..) = at(DVec3::ZERO).unwrap();
            assert_eq!(expected.name(), case["expected"].as_str().unwrap(), "{id}");
            for offset in offsets {
                let Some((got, a, b)) = at(offset) else {
                    inexact += 1;
                    continue;
                };
                compared += 1;
                if got == expected {
                    continue;
                }
                // Only a crossing at an angle the rounding floor cannot tell from parallel.
                let (PairResult::Contact(x), PairResult::Contact(y)) = (expected, got) else {
                    panic!("{id} x {scale} at {offset}: {expected:?} became {got:?}");
                };
                let allowed = match (x.kind, x.feature_a, x.feature_b) {
                    (ContactType::EdgeEdge, Feature::Edge(ea), Feature::Edge(eb)) => {
                        y.kind == ContactType::EdgeEdgeSuperposition
                            && (y.feature_a, y.feature_b) == (x.feature_a, x.feature_b)
                            && edges_sine(&a, ea, &b, eb) <= lies_in_sine(&tol, &a, &b)
                    }
                    _ => false,
                };
                assert!(allowed, "{id} x {scale} at {offset}: {x:?} became {y:?}");
                along += 1;
            }
        }
    }
    assert!(
        compared > 500 && along < compared / 50,
        "{compared} compared, {along} along, {inexact} inexact"
    );
}

/// Three joint sets cutting a 20 x 15 x 10 m box with its corner at `corner` (set origins at
/// the same place relative to it).
fn far_spec(corner: DVec3) -> Spec {
    let domain = Domain::cuboid(
        corner.to_array(),
        (corner + DVec3::new(20.0, 15.0, 10.0)).to_array(),
    );
    let mut spec = Spec::new(domain.unwrap());
    for (dip, dip_direction, spacing) in [(60.0, 135.0, 1.7), (80.0, 20.0, 2.3), (10.0, 300.0, 1.1)]
    {
        let mut set = JointSet::new(Orientation::dip(dip, dip_direction), spacing);
        set.origin = (corner + DVec3::new(0.25, 0.5, 0.125)).to_array();
        spec = spec.with(Discontinuity::set(set));
    }
    spec
}

/// A system generated in mine-grid coordinates (the domain and the joint sets placed there,
/// every coordinate of the spec moved exactly) has the same contacts, types and features as
/// the same spec at the origin: the cuts far away keep the accuracy the rounding floor
/// assumes (docs/tolerance.md, "Far from the origin"), with no local origin.
#[test]
fn systems_generated_far_from_the_origin_have_the_same_contacts() {
    let tol = Tolerance::default();
    let at_origin = generate(&far_spec(DVec3::ZERO)).unwrap().system;
    let expected = answer(&at_origin.detect(&tol));
    assert!(at_origin.len() > 500 && expected.0.len() > 5000);
    for corner in [
        DVec3::new(512345.5, 4012345.25, 1234.125),
        DVec3::new(1e7, -1e7, 1e7),
    ] {
        let far = generate(&far_spec(corner)).unwrap().system;
        let got = answer(&far.detect(&tol));
        assert!(
            got == expected,
            "at {corner}: {}",
            differences(&expected, &got)
        );
    }
}
