//! The generation spec file (TOML, or the same structure in JSON): see
//! `docs/generation.md` for every field, and `examples/` for one file per feature.
//!
//! ```toml
//! [domain]
//! type = "box"
//! min = [0, 0, 0]
//! max = [10, 10, 10]
//!
//! [[joints]]
//! type = "set"
//! name = "bedding"
//! dip = 10
//! dip_direction = 135
//! spacing = 2.5
//! ```
//!
//! Parsing checks the shape (known keys, value types, the fields each `type` takes);
//! [`crate::generation::generate`] checks the values. Errors name the field.

use super::strict::{self, Table};
use super::{messages, read_text, surface, IoError};
use crate::generation::MAX_PLANES;
use crate::generation::{Attitude, Deviation, Discontinuity, Domain, JointKind, JointSet};
use crate::generation::{Excavation, ExcavationShape, Profile};
use crate::generation::{Options, Orientation, Problem, SliverPolicy, Spec, SpecError};
use crate::tolerance::Tolerance;
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpec {
    #[serde(deserialize_with = "strict::read")]
    domain: RawDomain,
    #[serde(default, deserialize_with = "strict::read")]
    joints: Vec<RawJoint>,
    #[serde(default, deserialize_with = "strict::read")]
    excavations: Vec<RawExcavation>,
    #[serde(default, deserialize_with = "strict::read")]
    options: RawOptions,
    unit: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDomain {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default, deserialize_with = "strict::read")]
    min: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "strict::read")]
    max: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "strict::read")]
    vertices: Option<Vec<[f64; 3]>>,
    faces: Option<Vec<Vec<usize>>>,
    #[serde(default, deserialize_with = "strict::read")]
    normals: Option<Vec<[f64; 3]>>,
    offsets: Option<Vec<f64>>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawJoint {
    #[serde(rename = "type")]
    kind: String,
    name: Option<String>,
    #[serde(default, deserialize_with = "strict::read")]
    point: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "strict::read")]
    normal: Option<[f64; 3]>,
    dip: Option<f64>,
    dip_direction: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    origin: Option<[f64; 3]>,
    spacing: Option<f64>,
    number: Option<i64>,
    dip_deviation: Option<f64>,
    dip_direction_deviation: Option<f64>,
    spacing_deviation: Option<f64>,
    /// Any whole number from -2^63 to 2^64 - 1 (a negative `s` is the seed `2^64 + s`).
    #[serde(default, deserialize_with = "whole_number")]
    seed: Option<i128>,
    #[serde(default, deserialize_with = "strict::read")]
    center: Option<[f64; 3]>,
    radius: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    vertices: Option<Vec<[f64; 3]>>,
    bridge: Option<bool>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawExcavation {
    #[serde(rename = "type")]
    kind: String,
    name: Option<String>,
    profile: Option<String>,
    radius: Option<f64>,
    segments: Option<i64>,
    wall: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    vertices: Option<Vec<[f64; 2]>>,
    #[serde(default, deserialize_with = "strict::read")]
    start: Option<[f64; 3]>,
    trend: Option<f64>,
    plunge: Option<f64>,
    length: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    center: Option<[f64; 3]>,
    width: Option<f64>,
    height: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    top: Option<[f64; 3]>,
    depth: Option<f64>,
    #[serde(default, deserialize_with = "strict::read")]
    origin: Option<[f64; 3]>,
    file: Option<String>,
    #[serde(default, deserialize_with = "strict::read")]
    offset: Option<[f64; 3]>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawOptions {
    min_volume: Option<f64>,
    min_thickness: Option<f64>,
    slivers: Option<String>,
    gap: Option<f64>,
    length: Option<f64>,
}

strict::tables!(RawSpec, RawDomain, RawJoint, RawExcavation, RawOptions);

/// Parses a TOML spec; a surface file it names is read relative to the current folder.
pub fn parse_toml(text: &str) -> Result<Spec, SpecError> {
    parse_toml_in(text, Path::new(""))
}

/// Parses a TOML spec whose surface files are named relative to `folder` (the spec file's).
pub fn parse_toml_in(text: &str, folder: &Path) -> Result<Spec, SpecError> {
    let Table(raw) = toml::from_str::<Table<RawSpec>>(text).map_err(|e| {
        let message = messages::not_a_spec(text).unwrap_or_else(|| toml_message(text, &e));
        syntax(message)
    })?;
    convert(raw, folder)
}

/// A TOML error on one line: `line L, column C: what` (the parser's own text quotes the
/// whole source line, which can be megabytes long).
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let what = one_line(&messages::plain(e.message()));
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("line {line}, column {column}: {what}")
        }
        None => what,
    }
}

/// A message on one line of at most 300 characters.
fn one_line(message: &str) -> String {
    let joined = message.split_whitespace().collect::<Vec<_>>().join(" ");
    match joined.char_indices().nth(300) {
        Some((cut, _)) => format!("{}...", &joined[..cut]),
        None => joined,
    }
}

/// Parses a JSON spec (the same structure as the TOML file); a surface file it names is
/// read relative to the current folder.
pub fn parse_json(text: &str) -> Result<Spec, SpecError> {
    parse_json_in(text, Path::new(""))
}

/// Parses a JSON spec whose surface files are named relative to `folder`.
pub fn parse_json_in(text: &str, folder: &Path) -> Result<Spec, SpecError> {
    let Table(raw) = serde_json::from_str::<Table<RawSpec>>(text).map_err(|e| {
        let message = messages::not_a_spec(text)
            .unwrap_or_else(|| one_line(&messages::plain(&e.to_string())));
        syntax(message)
    })?;
    convert(raw, folder)
}

/// Reads a spec file: JSON if its name ends in `.json`, TOML otherwise; the surface files
/// it names are relative to its folder.
pub fn read_spec(path: &Path) -> Result<Spec, IoError> {
    let text = read_text(path).map_err(|e| match e {
        IoError::Syntax { message, .. } => IoError::Spec(syntax(message)),
        other => other,
    })?;
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let folder = path.parent().unwrap_or(Path::new(""));
    Ok(if is_json {
        parse_json_in(&text, folder)?
    } else {
        parse_toml_in(&text, folder)?
    })
}

fn syntax(message: String) -> SpecError {
    SpecError::new("spec", Problem::Syntax(message))
}

fn convert(raw: RawSpec, folder: &Path) -> Result<Spec, SpecError> {
    let domain = domain(&raw.domain)?;
    let joints = raw
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| joint(&format!("joints[{i}]"), j))
        .collect::<Result<_, _>>()?;
    let excavations = raw
        .excavations
        .iter()
        .enumerate()
        .map(|(i, e)| excavation(&format!("excavations[{i}]"), e, folder))
        .collect::<Result<_, _>>()?;
    let options = options(&raw.options)?;
    Ok(Spec {
        domain,
        joints,
        excavations,
        options,
        unit: raw.unit.map(unit).transpose()?,
    })
}

/// A length unit's name ([`crate::generation`]'s rule, shared with the block file).
fn unit(text: String) -> Result<String, SpecError> {
    crate::generation::check::unit_name(&text)
        .map_err(|why| SpecError::new("unit", Problem::Invalid(why)))
}

fn need<T: Clone>(field: String, value: &Option<T>) -> Result<T, SpecError> {
    value.clone().ok_or(SpecError::new(field, Problem::Missing))
}

/// The first field given that `allowed` does not list.
fn only(
    prefix: &str,
    kind: &str,
    given: &[(&str, bool)],
    allowed: &[&str],
) -> Result<(), SpecError> {
    match given.iter().find(|(k, set)| *set && !allowed.contains(k)) {
        Some((key, _)) => Err(SpecError::new(
            format!("{prefix}.{key}"),
            Problem::NotAllowed {
                kind: kind.to_string(),
            },
        )),
        None => Ok(()),
    }
}

fn domain(d: &RawDomain) -> Result<Domain, SpecError> {
    let given = [
        ("min", d.min.is_some()),
        ("max", d.max.is_some()),
        ("vertices", d.vertices.is_some()),
        ("faces", d.faces.is_some()),
        ("normals", d.normals.is_some()),
        ("offsets", d.offsets.is_some()),
    ];
    let built = match d.kind.as_str() {
        "box" => {
            only("domain", "box", &given, &["min", "max"])?;
            let (min, max) = (
                need("domain.min".into(), &d.min)?,
                need("domain.max".into(), &d.max)?,
            );
            check_box(min, max)?;
            Domain::cuboid(min, max)
        }
        "polyhedron" => {
            only("domain", "polyhedron", &given, &["vertices", "faces"])?;
            let vertices = need("domain.vertices".into(), &d.vertices)?;
            Domain::from_vertices_faces(&vertices, &need("domain.faces".into(), &d.faces)?)
        }
        "halfspaces" => {
            only("domain", "halfspaces", &given, &["normals", "offsets"])?;
            let normals = need("domain.normals".into(), &d.normals)?;
            Domain::from_halfspaces(&normals, &need("domain.offsets".into(), &d.offsets)?)
        }
        other => {
            return Err(unknown_type(
                "domain.type",
                other,
                "box, polyhedron, halfspaces",
            ))
        }
    };
    built.map_err(|e| SpecError::new("domain", Problem::Domain(e)))
}

fn check_box(min: [f64; 3], max: [f64; 3]) -> Result<(), SpecError> {
    for (field, p) in [("domain.min", min), ("domain.max", max)] {
        for v in p {
            if !v.is_finite() {
                return Err(SpecError::new(field, Problem::NotFinite { value: v }));
            }
        }
    }
    if (0..3).any(|k| max[k] <= min[k]) {
        let msg = "must be greater than `domain.min` in every coordinate".to_string();
        return Err(SpecError::new("domain.max", Problem::Invalid(msg)));
    }
    Ok(())
}

fn unknown_type(field: &str, found: &str, expected: &'static str) -> SpecError {
    let found = found.to_string();
    SpecError::new(field, Problem::UnknownType { found, expected })
}

const PLANE_FIELDS: [&str; 4] = ["point", "normal", "dip", "dip_direction"];
const DISC_FIELDS: [&str; 6] = [
    "center",
    "normal",
    "dip",
    "dip_direction",
    "radius",
    "bridge",
];

fn joint(prefix: &str, j: &RawJoint) -> Result<Discontinuity, SpecError> {
    let given = given_fields(j);
    let kind = match j.kind.as_str() {
        "plane" => {
            only(prefix, "plane", &given, &PLANE_FIELDS)?;
            let point = need(format!("{prefix}.point"), &j.point)?;
            let orientation = orientation(prefix, j)?;
            JointKind::Plane { point, orientation }
        }
        "set" => JointKind::Set(joint_set(prefix, j, &given)?),
        "disc" => {
            only(prefix, "disc", &given, &DISC_FIELDS)?;
            JointKind::Disc {
                center: need(format!("{prefix}.center"), &j.center)?,
                orientation: orientation(prefix, j)?,
                radius: need(format!("{prefix}.radius"), &j.radius)?,
            }
        }
        "polygon" => {
            only(prefix, "polygon", &given, &["vertices", "bridge"])?;
            let vertices = need(format!("{prefix}.vertices"), &j.vertices)?;
            JointKind::Polygon { vertices }
        }
        other => {
            let expected = "plane, set, disc, polygon";
            return Err(unknown_type(&format!("{prefix}.type"), other, expected));
        }
    };
    let name = j.name.clone();
    let bridge = j.bridge.unwrap_or(false);
    Ok(Discontinuity { name, kind, bridge })
}

fn given_fields(j: &RawJoint) -> [(&'static str, bool); 16] {
    [
        ("point", j.point.is_some()),
        ("normal", j.normal.is_some()),
        ("dip", j.dip.is_some()),
        ("dip_direction", j.dip_direction.is_some()),
        ("origin", j.origin.is_some()),
        ("spacing", j.spacing.is_some()),
        ("number", j.number.is_some()),
        ("dip_deviation", j.dip_deviation.is_some()),
        (
            "dip_direction_deviation",
            j.dip_direction_deviation.is_some(),
        ),
        ("spacing_deviation", j.spacing_deviation.is_some()),
        ("seed", j.seed.is_some()),
        ("center", j.center.is_some()),
        ("radius", j.radius.is_some()),
        ("vertices", j.vertices.is_some()),
        ("bridge", j.bridge.is_some()),
        ("name", false),
    ]
}

fn orientation(prefix: &str, j: &RawJoint) -> Result<Orientation, SpecError> {
    match (j.normal, j.dip, j.dip_direction) {
        (Some(n), None, None) => Ok(Orientation::Normal(n)),
        (None, Some(dip), Some(dd)) => Ok(Orientation::Attitude(Attitude::new(dip, dd))),
        (None, Some(_), None) => Err(SpecError::new(
            format!("{prefix}.dip_direction"),
            Problem::Missing,
        )),
        (None, None, Some(_)) => Err(SpecError::new(format!("{prefix}.dip"), Problem::Missing)),
        _ => Err(SpecError::new(prefix, Problem::Orientation)),
    }
}

fn joint_set(prefix: &str, j: &RawJoint, given: &[(&str, bool)]) -> Result<JointSet, SpecError> {
    let allowed = [
        "normal",
        "dip",
        "dip_direction",
        "origin",
        "spacing",
        "number",
        "dip_deviation",
        "dip_direction_deviation",
        "spacing_deviation",
        "seed",
    ];
    only(prefix, "set", given, &allowed)?;
    let number = match j.number {
        None => None,
        Some(n) if n < 1 => {
            let problem = Problem::NotPositive { value: n as f64 };
            return Err(SpecError::new(format!("{prefix}.number"), problem));
        }
        // Every count above the limit is the same error (it was "must be greater than
        // zero" past 2^32 - 1).
        Some(n) if n as u64 > MAX_PLANES => {
            let problem = Problem::TooManyPlanes {
                count: n as u64,
                limit: MAX_PLANES,
                by_number: true,
            };
            return Err(SpecError::new(format!("{prefix}.number"), problem));
        }
        Some(n) => Some(n as u32),
    };
    Ok(JointSet {
        orientation: orientation(prefix, j)?,
        origin: j.origin.unwrap_or([0.0; 3]),
        spacing: need(format!("{prefix}.spacing"), &j.spacing)?,
        number,
        deviation: Deviation {
            dip: j.dip_deviation.unwrap_or(0.0),
            dip_direction: j.dip_direction_deviation.unwrap_or(0.0),
            spacing: j.spacing_deviation.unwrap_or(0.0),
        },
        seed: seed(prefix, j.seed)?,
    })
}

/// A whole number as TOML or JSON has it (a parser that holds a larger one hands it over
/// as 128 bits; the seed's own check then names the field).
fn whole_number<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<i128>, D::Error> {
    struct Whole;
    impl serde::de::Visitor<'_> for Whole {
        type Value = Option<i128>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a whole number")
        }
        fn visit_i64<E>(self, v: i64) -> Result<Self::Value, E> {
            Ok(Some(v.into()))
        }
        fn visit_u64<E>(self, v: u64) -> Result<Self::Value, E> {
            Ok(Some(v.into()))
        }
        fn visit_i128<E>(self, v: i128) -> Result<Self::Value, E> {
            Ok(Some(v))
        }
        fn visit_u128<E: serde::de::Error>(self, v: u128) -> Result<Self::Value, E> {
            // Beyond i128 only far beyond every seed: the seed's check names the field.
            Ok(Some(i128::try_from(v).unwrap_or(i128::MAX)))
        }
        // JSON's `null`: not given, as for the other optional fields.
        fn visit_unit<E>(self) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_none<E>(self) -> Result<Self::Value, E> {
            Ok(None)
        }
    }
    d.deserialize_any(Whole)
}

/// A set's seed: a whole number from -2^63 to 2^64 - 1 (the greatest seed); a negative `s`
/// is the seed `2^64 + s`, as it always was (`-1` is `2^64 - 1`).
fn seed(prefix: &str, given: Option<i128>) -> Result<u64, SpecError> {
    match given {
        None => Ok(0),
        Some(s) if s >= i64::MIN as i128 && s < 0 => Ok(s as i64 as u64),
        Some(s) if s >= 0 && s <= u64::MAX as i128 => Ok(s as u64),
        Some(s) => Err(SpecError::new(
            format!("{prefix}.seed"),
            Problem::Invalid(format!(
                "must be a whole number from -2^63 to 2^64 - 1 (a negative seed s is the seed \
                 2^64 + s), got {s}"
            )),
        )),
    }
}

fn options(o: &RawOptions) -> Result<Options, SpecError> {
    let slivers = match o.slivers.as_deref() {
        None | Some("keep") => SliverPolicy::Keep,
        Some("drop") => SliverPolicy::Drop,
        Some(other) => return Err(unknown_type("options.slivers", other, "keep, drop")),
    };
    let default = Tolerance::default();
    let tolerance = match (o.gap, o.length) {
        (None, None) => default,
        (Some(g), None) => Tolerance::with_gap(g).map_err(tolerance_error("options.gap"))?,
        (g, l) => Tolerance::new(g.unwrap_or(default.gap()), l.unwrap_or(default.length()))
            .map_err(tolerance_error("options.length"))?,
    };
    Ok(Options {
        tolerance,
        min_volume: o.min_volume.unwrap_or(0.0),
        min_thickness: o.min_thickness,
        slivers,
    })
}

fn tolerance_error(field: &'static str) -> impl Fn(crate::tolerance::ToleranceError) -> SpecError {
    move |e| SpecError::new(field, Problem::Invalid(e.to_string()))
}

/// Parses one excavation entry, given as TOML (the fields of an `[[excavations]]` entry);
/// errors name the fields under `excavation`; a surface file is relative to the current
/// folder.
///
/// ```
/// let e = penedge::io::spec::parse_excavation_toml(
///     "type = \"cavern\"\ncenter = [0, 0, 0]\ntrend = 0\nlength = 4\nwidth = 2\nheight = 3",
/// )
/// .unwrap();
/// assert_eq!(e.volume().unwrap(), 24.0);
/// ```
pub fn parse_excavation_toml(text: &str) -> Result<Excavation, SpecError> {
    let Table(raw) = toml::from_str::<Table<RawExcavation>>(text)
        .map_err(|e| SpecError::new("excavation", Problem::Syntax(toml_message(text, &e))))?;
    excavation("excavation", &raw, Path::new(""))
}

/// An excavation entry: `type` (tunnel, cavern, shaft, slope, topography) and, for a tunnel
/// or shaft, a `profile` (circle, horseshoe, polygon) with its fields flat in the entry; a
/// topography's `file` is read relative to `folder`.
fn excavation(prefix: &str, e: &RawExcavation, folder: &Path) -> Result<Excavation, SpecError> {
    let given = [
        ("profile", e.profile.is_some()),
        ("radius", e.radius.is_some()),
        ("segments", e.segments.is_some()),
        ("wall", e.wall.is_some()),
        ("vertices", e.vertices.is_some()),
        ("start", e.start.is_some()),
        ("trend", e.trend.is_some()),
        ("plunge", e.plunge.is_some()),
        ("length", e.length.is_some()),
        ("center", e.center.is_some()),
        ("width", e.width.is_some()),
        ("height", e.height.is_some()),
        ("top", e.top.is_some()),
        ("depth", e.depth.is_some()),
        ("origin", e.origin.is_some()),
        ("file", e.file.is_some()),
        ("offset", e.offset.is_some()),
    ];
    let field = |name: &str| format!("{prefix}.{name}");
    let shape = match e.kind.as_str() {
        "tunnel" => {
            let mut allowed = vec!["start", "trend", "plunge", "length"];
            let profile = profile(prefix, e, &mut allowed)?;
            only(prefix, "tunnel", &given, &allowed)?;
            ExcavationShape::Tunnel {
                profile,
                start: need(field("start"), &e.start)?,
                trend: need(field("trend"), &e.trend)?,
                plunge: e.plunge.unwrap_or(0.0),
                length: need(field("length"), &e.length)?,
            }
        }
        "cavern" => {
            let allowed = ["center", "trend", "length", "width", "height"];
            only(prefix, "cavern", &given, &allowed)?;
            ExcavationShape::Cavern {
                center: need(field("center"), &e.center)?,
                trend: need(field("trend"), &e.trend)?,
                length: need(field("length"), &e.length)?,
                width: need(field("width"), &e.width)?,
                height: need(field("height"), &e.height)?,
            }
        }
        "shaft" => {
            let mut allowed = vec!["top", "depth"];
            let profile = profile(prefix, e, &mut allowed)?;
            only(prefix, "shaft", &given, &allowed)?;
            ExcavationShape::Shaft {
                profile,
                top: need(field("top"), &e.top)?,
                depth: need(field("depth"), &e.depth)?,
            }
        }
        "slope" => {
            only(prefix, "slope", &given, &["origin", "trend", "vertices"])?;
            ExcavationShape::Slope {
                origin: need(field("origin"), &e.origin)?,
                trend: need(field("trend"), &e.trend)?,
                vertices: need(field("vertices"), &e.vertices)?,
            }
        }
        "topography" => {
            only(prefix, "topography", &given, &["file", "offset"])?;
            let offset = e.offset.unwrap_or([0.0; 3]);
            if let Some(&value) = offset.iter().find(|v| !v.is_finite()) {
                return Err(SpecError::new(
                    field("offset"),
                    Problem::NotFinite { value },
                ));
            }
            let name = need(field("file"), &e.file)?;
            let path = folder.join(&name);
            let surface = surface::read_surface(&path).map_err(|err| {
                let why = match err {
                    IoError::Io { source, .. } => format!("{}: {source}", path.display()),
                    other => other.to_string(),
                };
                SpecError::new(field("file"), Problem::Invalid(why))
            })?;
            ExcavationShape::Topography {
                surface: surface.shifted(offset),
            }
        }
        other => {
            let expected = "tunnel, cavern, shaft, slope, topography";
            return Err(unknown_type(&field("type"), other, expected));
        }
    };
    Ok(Excavation {
        name: e.name.clone(),
        shape,
    })
}

/// The profile of a tunnel or shaft; adds the fields it takes to `allowed`.
fn profile(prefix: &str, e: &RawExcavation, allowed: &mut Vec<&str>) -> Result<Profile, SpecError> {
    let field = |name: &str| format!("{prefix}.{name}");
    allowed.push("profile");
    let segments = |default: i64| -> Result<u32, SpecError> {
        let n = e.segments.unwrap_or(default);
        u32::try_from(n).map_err(|_| {
            SpecError::new(field("segments"), Problem::NotPositive { value: n as f64 })
        })
    };
    Ok(match need(field("profile"), &e.profile)?.as_str() {
        "circle" => {
            allowed.extend(["radius", "segments"]);
            Profile::Circle {
                radius: need(field("radius"), &e.radius)?,
                segments: segments(16)?,
            }
        }
        "horseshoe" => {
            allowed.extend(["radius", "segments", "wall"]);
            Profile::Horseshoe {
                radius: need(field("radius"), &e.radius)?,
                wall: need(field("wall"), &e.wall)?,
                segments: segments(8)?,
            }
        }
        "polygon" => {
            allowed.push("vertices");
            Profile::Polygon {
                vertices: need(field("vertices"), &e.vertices)?,
            }
        }
        other => {
            let expected = "circle, horseshoe, polygon";
            return Err(unknown_type(&field("profile"), other, expected));
        }
    })
}
