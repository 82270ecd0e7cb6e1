//! Duplicate planes: two infinite joints in the same plane would make no block, only a
//! zero-thickness sliver or nothing at all; the spec is rejected, naming both.

use super::error::{Problem, SpecError};
use super::record::JointRecord;

/// Rejects two infinite planes that are parallel (the sine of their angle at most
/// `sine`) and within `eps` of each other. Planes are sorted by their offset `n · p`, so
/// only planes with nearly equal offsets are compared.
pub(crate) fn check(records: &[JointRecord], sine: f64, eps: f64) -> Result<(), SpecError> {
    let mut order: Vec<(f64, usize)> = records
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.is_finite())
        .map(|(i, r)| (r.plane.normal.dot(r.plane.point), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (k, &(d, i)) in order.iter().enumerate() {
        for &(_, j) in order[k + 1..]
            .iter()
            .take_while(|(e, _)| e - d <= 2.0 * eps)
        {
            if same_plane(&records[i], &records[j], sine, eps) {
                let (first, second) = (i.min(j), i.max(j));
                return Err(duplicate(&records[first], &records[second], eps));
            }
        }
    }
    Ok(())
}

fn same_plane(a: &JointRecord, b: &JointRecord, sine: f64, eps: f64) -> bool {
    let (p, q) = (&a.plane, &b.plane);
    p.normal.cross(q.normal).length() <= sine
        && p.normal.dot(q.normal) > 0.0
        && p.distance(q.point).abs() <= eps
}

fn duplicate(first: &JointRecord, second: &JointRecord, eps: f64) -> SpecError {
    SpecError::new(
        format!("joints[{}]", second.set),
        Problem::Duplicate {
            member: second.member,
            other: format!("joints[{}] plane {}", first.set, first.member),
            distance: eps,
        },
    )
}
