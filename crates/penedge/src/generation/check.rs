//! Field checks of a spec; each error names the field.

use super::error::{Problem, SpecError};
use super::orientation::Attitude;
use super::record::upward;
use super::spec::{JointSet, Options, Orientation};
use crate::geometry::{newell_normal, DVec3, Plane};

/// A finite number.
pub(crate) fn finite(field: &str, value: f64) -> Result<f64, SpecError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SpecError::new(field, Problem::NotFinite { value }))
    }
}

/// A point with finite coordinates.
pub(crate) fn point(field: &str, p: [f64; 3]) -> Result<DVec3, SpecError> {
    for v in p {
        finite(field, v)?;
    }
    Ok(DVec3::from_array(p))
}

/// A finite number greater than zero.
pub(crate) fn positive(field: &str, value: f64) -> Result<f64, SpecError> {
    if finite(field, value)? > 0.0 {
        Ok(value)
    } else {
        Err(SpecError::new(field, Problem::NotPositive { value }))
    }
}

/// A finite number, zero or more.
pub(crate) fn non_negative(field: &str, value: f64) -> Result<f64, SpecError> {
    if finite(field, value)? >= 0.0 {
        Ok(value)
    } else {
        Err(SpecError::new(field, Problem::Negative { value }))
    }
}

/// A dip in [0, 90] and a dip direction in [0, 360].
pub(crate) fn attitude(prefix: &str, a: Attitude) -> Result<Attitude, SpecError> {
    let dip = finite(&format!("{prefix}.dip"), a.dip)?;
    if !(0.0..=90.0).contains(&dip) {
        return Err(SpecError::new(
            format!("{prefix}.dip"),
            Problem::Dip { value: dip },
        ));
    }
    let field = format!("{prefix}.dip_direction");
    let dd = finite(&field, a.dip_direction)?;
    if !(0.0..=360.0).contains(&dd) {
        return Err(SpecError::new(field, Problem::DipDirection { value: dd }));
    }
    Ok(a)
}

/// The upward unit normal of an orientation.
pub(crate) fn normal(prefix: &str, o: &Orientation) -> Result<DVec3, SpecError> {
    match *o {
        Orientation::Attitude(a) => Ok(attitude(prefix, a)?.normal()),
        Orientation::Normal(n) => {
            let field = format!("{prefix}.normal");
            let n = point(&field, n)?;
            match n.try_normalize() {
                Some(unit) => Ok(upward(unit)),
                None => Err(SpecError::new(field, Problem::ZeroNormal)),
            }
        }
    }
}

/// The attitude of an orientation: for a normal, that of its upward sense, except that a
/// vertical plane's dip direction is taken in [0, 180) (the mean attitude a random set's
/// deviations are drawn about: kept as it was, so that the same spec and seed give the same
/// planes).
pub(crate) fn attitude_of(prefix: &str, o: &Orientation) -> Result<Attitude, SpecError> {
    match *o {
        Orientation::Attitude(a) => attitude(prefix, a),
        Orientation::Normal(_) => {
            let n = normal(prefix, o)?;
            let mut a = Attitude::from_normal(n).expect("unit normal");
            if n.z == 0.0 && a.dip_direction >= 180.0 {
                a.dip_direction -= 180.0;
            }
            Ok(a)
        }
    }
}

/// Spacing, number and deviations of a joint set.
pub(crate) fn joint_set(prefix: &str, set: &JointSet) -> Result<(), SpecError> {
    let spacing = positive(&format!("{prefix}.spacing"), set.spacing)?;
    if set.number == Some(0) {
        let field = format!("{prefix}.number");
        return Err(SpecError::new(field, Problem::NotPositive { value: 0.0 }));
    }
    non_negative(&format!("{prefix}.dip_deviation"), set.deviation.dip)?;
    let field = format!("{prefix}.dip_direction_deviation");
    non_negative(&field, set.deviation.dip_direction)?;
    let field = format!("{prefix}.spacing_deviation");
    let deviation = non_negative(&field, set.deviation.spacing)?;
    if deviation >= spacing {
        let problem = Problem::DeviationTooLarge { deviation, spacing };
        return Err(SpecError::new(field, problem));
    }
    Ok(())
}

/// Minimum volume and thickness.
pub(crate) fn options(o: &Options) -> Result<(), SpecError> {
    non_negative("options.min_volume", o.min_volume)?;
    if let Some(t) = o.min_thickness {
        non_negative("options.min_thickness", t)?;
    }
    Ok(())
}

/// A flat convex polygon: its plane (upward normal, through the centre) and its vertices
/// counter-clockwise about that normal.
pub(crate) fn polygon(
    field: &str,
    vertices: &[[f64; 3]],
    rel: f64,
) -> Result<(Plane, Vec<DVec3>), SpecError> {
    let bad = |reason| SpecError::new(field, Problem::BadPolygon { reason });
    if vertices.len() < 3 {
        return Err(bad("it needs 3 vertices or more"));
    }
    let mut pts = points(field, vertices)?;
    let n = newell_normal(pts.iter().copied());
    let perimeter: f64 = (0..pts.len())
        .map(|k| pts[k].distance(pts[(k + 1) % pts.len()]))
        .sum();
    let Some(unit) = n
        .try_normalize()
        .filter(|_| n.length() > rel * perimeter * perimeter)
    else {
        return Err(bad("its area is zero"));
    };
    if upward(unit) != unit {
        pts.reverse();
    }
    let normal = upward(unit);
    let centre = pts.iter().sum::<DVec3>() / pts.len() as f64;
    let plane = Plane {
        normal,
        point: centre,
    };
    let eps = rel * perimeter;
    if pts.iter().any(|&p| plane.distance(p).abs() > eps) {
        return Err(bad("its vertices are not in one plane"));
    }
    if !turns_left_once(&pts, normal, eps) {
        return Err(bad("it is not convex (or not simple)"));
    }
    Ok((plane, pts))
}

fn points(field: &str, vertices: &[[f64; 3]]) -> Result<Vec<DVec3>, SpecError> {
    vertices.iter().map(|&p| point(field, p)).collect()
}

/// Every corner turns left about `normal` and the turns add up to one full turn.
fn turns_left_once(pts: &[DVec3], normal: DVec3, eps: f64) -> bool {
    let m = pts.len();
    let mut total = 0.0;
    for k in 0..m {
        let (a, b, c) = (pts[k], pts[(k + 1) % m], pts[(k + 2) % m]);
        let (u, v) = (b - a, c - b);
        let Some(dir) = u.try_normalize() else {
            return false;
        };
        if normal.cross(dir).dot(c - b) < -eps {
            return false;
        }
        total += u.cross(v).dot(normal).atan2(u.dot(v));
    }
    (total - std::f64::consts::TAU).abs() < 1e-6
}

/// The separator of the names of a feature's faces in the contact table's `set_a` and
/// `set_b` columns (`J1|J2`): no entry's name may hold it.
pub const NAME_SEPARATOR: char = '|';

/// The label of a domain face in the contact table's `set_a` and `set_b` columns: no
/// entry may be called so.
pub const BOUNDARY_LABEL: &str = "boundary";

/// The start of a rock-bridge face's label in the contact table (`bridge of J1`): no
/// entry's name may start so.
pub const BRIDGE_PREFIX: &str = "bridge of ";

/// Why `name` cannot name an entry because the contact table gives it another meaning
/// (docs/tables.md, `set_a`): empty (no recorded origin), `boundary` (a domain face), or
/// `bridge of ...` (a rock-bridge face).
fn reserved(name: &str) -> Option<String> {
    let why = if name.trim().is_empty() {
        "is empty (or only spaces), as the contact table's set_a and set_b are for a face \
         with no recorded origin"
    } else if name == BOUNDARY_LABEL {
        "is the contact table's label of a face on the domain's surface (set_a, set_b)"
    } else if name.starts_with(BRIDGE_PREFIX) {
        "starts as the contact table's label of a rock-bridge face (`bridge of NAME` in \
         set_a, set_b)"
    } else {
        return None;
    };
    Some(format!(
        "the name {} {why}: choose another, so that the table tells them apart",
        shown(name)
    ))
}

/// The names of a spec's entries (`label[i]` each, in order), checked: none is reserved by
/// the contact table (empty, [`BOUNDARY_LABEL`], starting with [`BRIDGE_PREFIX`]), none holds
/// [`NAME_SEPARATOR`] and none repeats an earlier one, since the contact table names faces by
/// them. The first that fails, as its index and why.
pub(crate) fn entry_names<'a>(
    label: &str,
    names: impl IntoIterator<Item = &'a str>,
) -> Result<(), (usize, String)> {
    entry_names_by(names, |i| format!("{label}[{i}]"))
}

/// [`entry_names`], naming entry `i` as `label(i)` in the message of a repeated name.
pub(crate) fn entry_names_by<'a>(
    names: impl IntoIterator<Item = &'a str>,
    label: impl Fn(usize) -> String,
) -> Result<(), (usize, String)> {
    let mut seen = std::collections::HashMap::new();
    for (i, name) in names.into_iter().enumerate() {
        if let Some(why) = reserved(name) {
            return Err((i, why));
        }
        if name.contains(NAME_SEPARATOR) {
            let why = format!(
                "the name {} holds `{NAME_SEPARATOR}`, which separates the names of a \
                 feature's faces in the contact table (set_a, set_b): choose another",
                shown(name)
            );
            return Err((i, why));
        }
        if let Some(first) = seen.insert(name, i) {
            let why = format!(
                "the name {} is already that of {}: each entry needs its own name (the \
                 contact table names faces by it)",
                shown(name),
                label(first)
            );
            return Err((i, why));
        }
    }
    Ok(())
}

/// The most characters of a length unit's name.
pub const MAX_UNIT_CHARS: usize = 16;

/// A length unit's name: a short label (1 to [`MAX_UNIT_CHARS`] characters once trimmed)
/// without control characters, trimmed; or why not.
pub(crate) fn unit_name(text: &str) -> Result<String, String> {
    let trimmed = text.trim();
    let bad = trimmed.is_empty()
        || trimmed.chars().count() > MAX_UNIT_CHARS
        || trimmed.chars().any(char::is_control);
    if bad {
        return Err(format!(
            "must be a short name of a length unit (1 to {MAX_UNIT_CHARS} printable \
             characters, such as \"m\" or \"ft\"), got {}",
            shown(text)
        ));
    }
    Ok(trimmed.to_string())
}

/// A name as a message shows it: quoted with escapes, and cut after 40 characters (with
/// the count) so that a megabyte of text makes no megabyte of message.
fn shown(text: &str) -> String {
    const SHOWN: usize = 40;
    let count = text.chars().count();
    if count <= SHOWN {
        return format!("{text:?}");
    }
    let start: String = text.chars().take(SHOWN).collect();
    format!("{start:?}... ({count} characters)")
}
