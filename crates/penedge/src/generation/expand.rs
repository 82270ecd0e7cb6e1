//! From a spec to the joint table: every entry checked and expanded into the planes it makes,
//! in order; sets are laid out along their normal, with their random deviations.

use super::check;
use super::domain::Domain;
use super::error::{Problem, SpecError};
use super::finite::{coverage, Coverage};
use super::orientation::Attitude;
use super::record::{JointRecord, JointShape, SetKind, SetRecord};
use super::rng::SplitMix64;
use super::spec::{Discontinuity, JointKind, JointSet, Orientation, Spec, MAX_PLANES};
use crate::cutting::{Side, Splitter};
use crate::geometry::{DVec3, Plane};

/// The joint table of a spec, ready to cut.
#[derive(Clone, Debug, Default)]
pub(crate) struct Plan {
    /// Every plane, in the order applied.
    pub(crate) records: Vec<JointRecord>,
    /// One record per spec entry.
    pub(crate) sets: Vec<SetRecord>,
    /// Planes of joint sets (with a given number) that miss the domain and were left out.
    pub(crate) outside: usize,
    /// The absolute length threshold.
    pub(crate) eps: f64,
}

/// Checks and expands the spec.
pub(crate) fn plan(spec: &Spec) -> Result<Plan, SpecError> {
    check::options(&spec.options)?;
    let names: Vec<String> = spec.joints.iter().enumerate().map(entry_name).collect();
    check::entry_names("joints", names.iter().map(String::as_str))
        .map_err(|(i, why)| SpecError::new(format!("joints[{i}].name"), Problem::Invalid(why)))?;
    let eps = spec.options.tolerance.for_box(&spec.domain.aabb()).length;
    let mut plan = Plan {
        eps,
        ..Plan::default()
    };
    for (i, entry) in spec.joints.iter().enumerate() {
        expand(i, entry, &spec.domain, &mut plan)?;
        if plan.records.len() as u64 > MAX_PLANES {
            let count = plan.records.len() as u64;
            // The spacing hint only when a set fills the domain (not when every set so far
            // gives its `number`).
            let by_number = spec.joints[..=i].iter().all(|d| match &d.kind {
                JointKind::Set(js) => js.number.is_some(),
                _ => true,
            });
            let problem = Problem::TooManyPlanes {
                count,
                limit: MAX_PLANES,
                by_number,
            };
            return Err(SpecError::new(format!("joints[{i}]"), problem));
        }
    }
    super::duplicates::check(&plan.records, spec.options.tolerance.length(), eps)?;
    Ok(plan)
}

/// The name of entry `i`: the one given, or `joints[i]`.
fn entry_name((i, entry): (usize, &Discontinuity)) -> String {
    entry.name.clone().unwrap_or_else(|| format!("joints[{i}]"))
}

fn expand(
    i: usize,
    entry: &Discontinuity,
    domain: &Domain,
    plan: &mut Plan,
) -> Result<(), SpecError> {
    let prefix = format!("joints[{i}]");
    let name = entry_name((i, entry));
    let (kind, what) = match &entry.kind {
        JointKind::Plane { .. } => (SetKind::Plane, "plane"),
        JointKind::Set(_) => (SetKind::Set, "joint set"),
        JointKind::Disc { .. } => (SetKind::Disc, "disc"),
        JointKind::Polygon { .. } => (SetKind::Polygon, "polygon"),
    };
    plan.sets.push(SetRecord { name, kind });
    let before = plan.records.len();
    match &entry.kind {
        JointKind::Set(js) => expand_set(&prefix, i as u32, js, domain, plan)?,
        single => {
            // The policy's length threshold, relative (the domain's, with its rounding floor).
            let rel = plan.eps / domain.size();
            let (plane, shape) = single_joint(&prefix, single, rel)?;
            let record = JointRecord {
                set: i as u32,
                member: 0,
                plane,
                shape,
            };
            push_if_meets(plan, domain, record);
        }
    }
    if plan.records.len() == before {
        return Err(SpecError::new(prefix, Problem::MissesDomain { what }));
    }
    Ok(())
}

/// The plane and shape of a single plane, disc or polygon (`rel`: relative flatness
/// tolerance of a polygon).
fn single_joint(
    prefix: &str,
    kind: &JointKind,
    rel: f64,
) -> Result<(Plane, JointShape), SpecError> {
    Ok(match kind {
        JointKind::Plane { point, orientation } => {
            let plane = plane_of(prefix, "point", *point, orientation)?;
            (plane, JointShape::Infinite)
        }
        JointKind::Disc {
            center,
            orientation,
            radius,
        } => {
            let plane = plane_of(prefix, "center", *center, orientation)?;
            let radius = check::positive(&format!("{prefix}.radius"), *radius)?;
            let center = plane.point;
            (plane, JointShape::Disc { center, radius })
        }
        JointKind::Polygon { vertices } => {
            let (plane, vertices) = check::polygon(&format!("{prefix}.vertices"), vertices, rel)?;
            (plane, JointShape::Polygon { vertices })
        }
        JointKind::Set(_) => unreachable!("sets are expanded by expand_set"),
    })
}

fn plane_of(prefix: &str, key: &str, p: [f64; 3], o: &Orientation) -> Result<Plane, SpecError> {
    let point = check::point(&format!("{prefix}.{key}"), p)?;
    let normal = check::normal(prefix, o)?;
    Ok(Plane { normal, point })
}

/// Adds the joint if it crosses the interior of the domain; returns whether it did.
fn push_if_meets(plan: &mut Plan, domain: &Domain, record: JointRecord) -> bool {
    let meets = meets_domain(domain, &record, plan.eps);
    if meets {
        plan.records.push(record);
    }
    meets
}

/// Whether a joint crosses a part of the domain (a finite joint: overlaps its section).
pub(crate) fn meets_domain(domain: &Domain, record: &JointRecord, eps: f64) -> bool {
    let mut splitter = Splitter::default();
    domain.parts().iter().any(|part| {
        match splitter.prepare(part, &record.plane, eps) {
            Ok(Side::Across) => {
                let section: Vec<DVec3> = splitter.section().collect();
                coverage(&record.shape, &record.plane, &section, eps) != Coverage::Outside
            }
            Ok(_) => false,
            // A section too degenerate to chain: the plane grazes the part.
            Err(_) => false,
        }
    })
}

/// Range of `n · (x - origin)` over the domain's vertices.
fn extent(domain: &Domain, n: DVec3, origin: DVec3) -> (f64, f64) {
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for v in domain.parts().iter().flat_map(|p| p.vertices()) {
        let s = n.dot(*v - origin);
        range = (range.0.min(s), range.1.max(s));
    }
    range
}

fn expand_set(
    prefix: &str,
    set: u32,
    js: &JointSet,
    domain: &Domain,
    plan: &mut Plan,
) -> Result<(), SpecError> {
    check::joint_set(prefix, js)?;
    let origin = check::point(&format!("{prefix}.origin"), js.origin)?;
    let base_normal = check::normal(prefix, &js.orientation)?;
    let base = check::attitude_of(prefix, &js.orientation)?;
    let mut member = 0;
    for (k, t) in positions(prefix, js, base_normal, origin, domain)? {
        let plane = Plane {
            normal: member_normal(js, k, base, base_normal),
            point: origin + base_normal * t,
        };
        let record = JointRecord {
            set,
            member,
            plane,
            shape: JointShape::Infinite,
        };
        if push_if_meets(plan, domain, record) {
            member += 1;
        } else {
            plan.outside += usize::from(js.number.is_some());
        }
    }
    Ok(())
}

/// The normal of plane `k` of a set: the set's own, or deviated by the plane's random
/// draws (its stream's second and third numbers; the first is its gap).
fn member_normal(js: &JointSet, k: i64, base: Attitude, base_normal: DVec3) -> DVec3 {
    if js.deviation.dip == 0.0 && js.deviation.dip_direction == 0.0 {
        return base_normal;
    }
    let mut rng = SplitMix64::for_item(js.seed, k);
    let _gap = rng.unit();
    let d_dip = rng.symmetric(js.deviation.dip);
    let d_dir = rng.symmetric(js.deviation.dip_direction);
    base.deviated(d_dip, d_dir).normal()
}

/// The signed index `k` and position `t` (along the set's normal, from its origin) of each
/// plane, in increasing `t`. The gap between plane `k` and its neighbour towards the origin
/// is drawn from plane `k`'s own random stream, so a plane's position does not depend on the
/// domain's extent.
fn positions(
    prefix: &str,
    js: &JointSet,
    normal: DVec3,
    origin: DVec3,
    domain: &Domain,
) -> Result<Vec<(i64, f64)>, SpecError> {
    let gap = |k: i64| {
        let mut rng = SplitMix64::for_item(js.seed, k);
        js.spacing + js.deviation.spacing * (2.0 * rng.unit() - 1.0)
    };
    let too_many = |count: f64, field: &str| {
        let problem = Problem::TooManyPlanes {
            count: count as u64,
            limit: MAX_PLANES,
            by_number: field == "number",
        };
        Err(SpecError::new(format!("{prefix}.{field}"), problem))
    };
    if let Some(n) = js.number {
        if n as u64 > MAX_PLANES {
            return too_many(n as f64, "number");
        }
        let mut t = 0.0;
        return Ok((0..n as i64)
            .map(|k| {
                t += if k > 0 { gap(k) } else { 0.0 };
                (k, t)
            })
            .collect());
    }
    let (lo, hi) = fill_range(js, normal, origin, domain);
    // Planes inside the range, at most.
    let inside = (hi - lo) / (js.spacing - js.deviation.spacing);
    if inside > MAX_PLANES as f64 {
        return too_many(inside.ceil(), "spacing");
    }
    let far = || {
        let problem = Problem::OriginFar {
            spacings: lo.abs().max(hi.abs()) / js.spacing,
            limit: MAX_WALK,
        };
        SpecError::new(format!("{prefix}.origin"), problem)
    };
    // Hopeless even at the largest gaps: said at once, without walking 10^7 of them.
    let nearest = if lo > 0.0 { lo } else { -hi.min(0.0) };
    if nearest / (js.spacing + js.deviation.spacing) > MAX_WALK as f64 {
        return Err(far());
    }
    fill(lo, hi, gap, MAX_WALK).ok_or_else(far)
}

/// The most gaps walked from a set's origin to place its planes (`Problem::OriginFar`).
const MAX_WALK: u64 = 10 * MAX_PLANES;

/// The range of positions along the set's normal whose planes can meet the domain: its
/// extent, widened for planes tilted by the random deviations.
fn fill_range(js: &JointSet, normal: DVec3, origin: DVec3, domain: &Domain) -> (f64, f64) {
    let (lo, hi) = extent(domain, normal, origin);
    let tilt = (js.deviation.dip + js.deviation.dip_direction).min(90.0);
    let margin = domain.size() * tilt.to_radians().sin();
    (lo - margin, hi + margin)
}

/// Positions from the origin outwards in both directions, kept where in `[lo, hi]`; `None`
/// if the walk would take more than `max_walk` gaps (an origin far from the domain).
fn fill(lo: f64, hi: f64, gap: impl Fn(i64) -> f64, max_walk: u64) -> Option<Vec<(i64, f64)>> {
    let mut below = Vec::new();
    let mut t = 0.0;
    let mut k = 0;
    let mut walked = 0;
    while t >= lo {
        if t <= hi {
            below.push((k, t));
        }
        k -= 1;
        t -= gap(k);
        walked += 1;
        if walked > max_walk {
            return None;
        }
    }
    below.reverse();
    let (mut k, mut t) = (1, gap(1));
    while t <= hi {
        if t >= lo {
            below.push((k, t));
        }
        k += 1;
        t += gap(k);
        walked += 1;
        if walked > max_walk {
            return None;
        }
    }
    Some(below)
}
