//! Every case of `tests/data/dev-cases.json` (contact types computed with exact rational
//! arithmetic) must get the same answer, in both orders.

use penedge::{ConvexBlock, Detector, PairResult, Tolerance};
use serde_json::Value;
use std::path::PathBuf;

fn cases_path() -> PathBuf {
    if let Ok(dir) = std::env::var("PENEDGE_SHARED") {
        return PathBuf::from(dir).join("cases/dev-cases.json");
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/dev-cases.json")
}

fn block(v: &Value) -> ConvexBlock {
    let vertices: Vec<[f64; 3]> = v["vertices"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let c: Vec<f64> = p
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            [c[0], c[1], c[2]]
        })
        .collect();
    let faces: Vec<Vec<usize>> = v["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            f.as_array()
                .unwrap()
                .iter()
                .map(|i| i.as_u64().unwrap() as usize)
                .collect()
        })
        .collect();
    ConvexBlock::new(&vertices, &faces).unwrap_or_else(|e| panic!("bad block: {e}"))
}

#[test]
fn every_dev_case_agrees_in_both_orders() {
    let path = cases_path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let cases: Vec<Value> = serde_json::from_str(&text).unwrap();
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
