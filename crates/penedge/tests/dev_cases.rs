//! Every case of `tests/data/dev-cases.json` (contact types computed with exact rational
//! arithmetic) must get the same answer, in both orders.

mod support;

use penedge::{Detector, PairResult, Tolerance};
use support::dev_cases::{block, cases};

#[test]
fn every_dev_case_agrees_in_both_orders() {
    let cases = cases();
    assert!(cases.len() > 200, "expected the full case list");
    let mut det = Detector::new(Tolerance::default());
    let mut failures = Vec::new();
    for case in &cases {
        let (a, b) = (block(&case["a"]), block(&case["b"]));
        let expected = case["expected"].as_str().unwrap();
        let ab = det.detect(&a, &b);
        let ba = det.detect(&b, &a);
        if ab.name() != expected || ba.name() != expected {
            failures.push(format!(
                "{} [{}]: expected {expected}, got {} / {} (swapped)",
                case["id"].as_str().unwrap(),
                case["family"].as_str().unwrap(),
                ab.name(),
                ba.name()
            ));
        }
        if let (PairResult::Contact(x), PairResult::Contact(y)) = (ab, ba) {
            assert_eq!(
                (x.feature_a, x.feature_b),
                (y.feature_b, y.feature_a),
                "features swap with the blocks"
            );
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases disagree:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
