//! Contact types and features as Python values: names, codes and `(kind, index)` tuples.

use penedge::classify::{ContactType, Feature, PairResult};

/// Code of a separated pair (`PairContact.type_code`).
pub const SEPARATED: i8 = 0;
/// Code of a pair penetrating deeper than the gap (`PairContact.type_code`).
pub const PENETRATING: i8 = -1;

/// The feature kinds, indexed by their code.
pub const FEATURE_KINDS: [&str; 3] = ["vertex", "edge", "face"];

/// The seven contact type names in code order (code 1..=7 at index 0..=6).
pub fn contact_type_names() -> Vec<&'static str> {
    ContactType::ALL.iter().map(|t| t.name()).collect()
}

/// 1..=7 for a contact, [`SEPARATED`] or [`PENETRATING`].
pub fn type_code(result: &PairResult) -> i8 {
    match result {
        PairResult::Separated => SEPARATED,
        PairResult::Penetrating => PENETRATING,
        PairResult::Contact(c) => c.kind.code() as i8,
    }
}

/// The kind code (index into [`FEATURE_KINDS`]) and the index of a feature.
pub fn feature_code(f: Feature) -> (i8, i64) {
    match f {
        Feature::Vertex(i) => (0, i64::from(i)),
        Feature::Edge(i) => (1, i64::from(i)),
        Feature::Face(i) => (2, i64::from(i)),
    }
}

/// A feature as `("vertex" | "edge" | "face", index)`.
pub fn feature_tuple(f: Feature) -> (&'static str, i64) {
    let (kind, index) = feature_code(f);
    (FEATURE_KINDS[kind as usize], index)
}
