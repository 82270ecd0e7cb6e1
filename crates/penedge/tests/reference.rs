//! Random convex blocks in random and in constructed touching placements, checked against a
//! slow reference (`support/reference.rs`: A ∩ B by brute-force vertex enumeration of both
//! blocks' half-spaces, nothing of the engine): touching or not, the dimension of the
//! contact (point, segment, polygon) and the feature of each block that holds it, hence the
//! type; and, near contact, the paper's rule (an edge of one block within the other widened by
//! the gap) computed naively.

mod support;

use glam::DVec3;
use penedge::generation::rng::SplitMix64;
use penedge::{ContactType, Detector, Feature, PairResult, Tolerance};
use proptest::prelude::*;
use support::reference::{
    edges_deep, edges_meet, grazing, meet_widened, rotation, same_feature, touch, touching, unit,
    Polytope, TARGETS,
};

fn feature_dim(f: Feature) -> usize {
    match f {
        Feature::Vertex(_) => 0,
        Feature::Edge(_) => 1,
        Feature::Face(_) => 2,
    }
}

/// The engine's answer for (A, B), checked to be the same for (B, A), features swapped.
fn engine(tol: &Tolerance, a: &Polytope, b: &Polytope) -> PairResult {
    let (ba, bb) = (a.block(), b.block());
    let mut det = Detector::new(*tol);
    let ab = det.detect(&ba, &bb);
    let swapped = match det.detect(&bb, &ba) {
        PairResult::Contact(mut c) => {
            std::mem::swap(&mut c.feature_a, &mut c.feature_b);
            PairResult::Contact(c)
        }
        other => other,
    };
    assert_eq!(ab, swapped, "(A, B) and (B, A) differ");
    ab
}

/// The tolerances the properties run with: the default, and a larger gap with the same ratio
/// length / gap = 1000.
fn tolerance(k: usize) -> Tolerance {
    [Tolerance::default(), Tolerance::new(1e-6, 1e-3).unwrap()][k]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Constructed touching placements of every type: the engine finds the contact, with the
    /// type of the reference's dimension and features, and the same features.
    #[test]
    fn touching_placements_have_the_type_of_the_reference(
        seed in any::<u64>(),
        target in 0usize..7,
        swap in any::<bool>(),
        k in 0usize..2,
    ) {
        let mut r = SplitMix64::new(seed);
        let Some((a, b, _)) = touching(&mut r, target) else {
            return Err(TestCaseError::reject("B not clean after the move"));
        };
        let (a, b) = if swap { (b, a) } else { (a, b) };
        let reference = touch(&a, &b).map_err(TestCaseError::reject)?;
        // The construction gives the target type (the reference checks the construction too).
        prop_assert_eq!(reference.kind(), TARGETS[target].0);
        let tol = tolerance(k);
        prop_assume!(!grazing(&a, &b, &reference, 4.0 * tol.length()));
        let PairResult::Contact(c) = engine(&tol, &a, &b) else {
            return Err(TestCaseError::fail(format!(
                "{:?}: not a contact, reference {}",
                engine(&tol, &a, &b),
                reference.kind()
            )));
        };
        prop_assert_eq!(c.kind, reference.kind());
        prop_assert_eq!([feature_dim(c.feature_a), feature_dim(c.feature_b)], reference.feature_dims);
        prop_assert!(same_feature(&a.block(), c.feature_a, &a, &reference.active[0]));
        prop_assert!(same_feature(&b.block(), c.feature_b, &b, &reference.active[1]));
    }

    /// Random placements: clearly apart (A and B widened by the gap do not meet) is
    /// separated; any overlap is not; an overlap deeper than twice the length threshold
    /// (A ∩ B holds a point that deep inside every face plane of both) is penetrating.
    #[test]
    fn random_placements_touch_as_the_reference_says(
        seed in any::<u64>(),
        distance in 0.0..2.5f64,
        k in 0usize..2,
    ) {
        let mut r = SplitMix64::new(seed);
        let a = Polytope::random(&mut r, DVec3::ZERO, 1.0);
        let radius = 0.3 + 1.7 * r.unit();
        let b = Polytope::random(&mut r, DVec3::ZERO, radius);
        let Some(b) = b.moved(rotation(&mut r), unit(&mut r) * distance * (1.0 + radius)) else {
            return Err(TestCaseError::reject("B not clean after the move"));
        };
        let tol = tolerance(k);
        let th = Detector::new(tol).thresholds(&a.block(), &b.block());
        let rounding = 1e-12 * a.size.min(b.size);
        let got = engine(&tol, &a, &b);
        if !meet_widened(&a, &b, th.gap * 1.01 + rounding) {
            prop_assert_eq!(got, PairResult::Separated);
        }
        if meet_widened(&a, &b, -1e3 * rounding) {
            prop_assert_ne!(got, PairResult::Separated);
        }
        if meet_widened(&a, &b, -(2.0 * th.length * 1.01 + rounding)) {
            prop_assert_eq!(got, PairResult::Penetrating);
        }
    }

    /// Touching placements moved along the separating normal by a few gaps: the engine
    /// follows the paper's rule exactly (computed naively here) and, while in contact, keeps
    /// the type of the exact contact. Within a gap of the contact it always touches.
    #[test]
    fn near_touching_placements_follow_the_paper_rule(
        seed in any::<u64>(),
        target in 0usize..7,
        units in prop::sample::select(vec![-3.0, -1.5, -1.0, -0.5, 0.5, 0.99, 1.01, 1.5, 3.0]),
    ) {
        let mut r = SplitMix64::new(seed);
        let Some((a, b0, n)) = touching(&mut r, target) else {
            return Err(TestCaseError::reject("B not clean after the move"));
        };
        let reference = touch(&a, &b0).map_err(TestCaseError::reject)?;
        let tol = tolerance(1);
        prop_assume!(!grazing(&a, &b0, &reference, 4.0 * tol.length()));
        let g = Detector::new(tol).thresholds(&a.block(), &b0.block()).gap;
        let Some(b) = b0.moved(glam::DQuat::IDENTITY, n * units * g) else {
            return Err(TestCaseError::reject("B not clean after the move"));
        };
        // The naive rule at the gap give or take 1e-4: the same answer, or too close to call.
        let m = 1e-4;
        let meets = edges_meet(&a, &b, g * (1.0 + m));
        prop_assume!(meets == edges_meet(&a, &b, g * (1.0 - m)));
        let deep = edges_deep(&a, &b, g * (1.0 - m));
        prop_assume!(deep == edges_deep(&a, &b, g * (1.0 + m)));
        if units.abs() <= 1.0 {
            prop_assert!(meets && !deep, "within the gap, the naive rule must touch");
        }
        let got = engine(&tol, &a, &b);
        match (meets, deep) {
            (false, _) => prop_assert_eq!(got, PairResult::Separated),
            (true, true) => prop_assert_eq!(got, PairResult::Penetrating),
            (true, false) => prop_assert_eq!(got.contact_type(), Some(reference.kind())),
        }
    }
}

/// The constructions reach every type (so that the properties above test all seven), and
/// the reference tells them apart.
#[test]
fn every_target_type_is_constructed() {
    let mut seen = [0usize; 7];
    let mut r = SplitMix64::new(1);
    for _ in 0..20 {
        for (t, count) in seen.iter_mut().enumerate() {
            if let Some((a, b, _)) = touching(&mut r, t) {
                if let Ok(reference) = touch(&a, &b) {
                    assert_eq!(reference.kind(), TARGETS[t].0);
                    *count += 1;
                }
            }
        }
    }
    assert!(seen.iter().all(|&c| c >= 10), "{seen:?}");
    let kinds: Vec<ContactType> = TARGETS.iter().map(|t| t.0).collect();
    assert_eq!(kinds, ContactType::ALL);
}
