//! Excavations: tunnels, caverns and shafts, each a union of convex regions (see
//! `docs/generation.md`, "Excavations").
//!
//! An excavation is a prism: a polygonal *profile* (a cross-section) swept along an axis. The
//! profile is decomposed into convex pieces (one piece when it is convex), and each piece
//! swept along the axis is a convex region, a [`ConvexBlock`]: the regions of one excavation
//! share faces and do not overlap, so the excavated volume is the profile's area times the
//! length, exactly. [`crate::BlockSystem::excavate`] removes the rock inside the regions.

use super::check;
use super::error::{Problem, SpecError};
use super::slope::{self, Extent};
use super::topography::{self, Surface};
use crate::block::ConvexBlock;
use crate::geometry::DVec3;

/// One excavation: a name for reports and files, and its shape.
#[derive(Clone, Debug, PartialEq)]
pub struct Excavation {
    /// A name (`"excavations[i]"` when `None`).
    pub name: Option<String>,
    /// What is excavated.
    pub shape: ExcavationShape,
}

/// The shapes of excavation.
#[derive(Clone, Debug, PartialEq)]
pub enum ExcavationShape {
    /// A tunnel: the profile swept from `start` along the axis of the given trend (azimuth,
    /// degrees clockwise from North) and plunge (degrees below the horizontal) for `length`.
    /// The profile's `u` axis is horizontal, to the right looking along the axis; `v` is
    /// perpendicular to the axis, upwards; the axis passes through the profile's origin.
    Tunnel {
        /// The cross-section.
        profile: Profile,
        /// Where the axis starts.
        start: [f64; 3],
        /// Trend of the axis, in [0, 360] degrees.
        trend: f64,
        /// Plunge of the axis, in (-90, 90) degrees (positive: downwards).
        plunge: f64,
        /// Length along the axis (> 0).
        length: f64,
    },
    /// A rectangular cavern: a box of `length` along the horizontal axis of the given trend,
    /// `width` across it and `height`, centred on `center`.
    Cavern {
        /// The centre of the box.
        center: [f64; 3],
        /// Trend of its long axis, in [0, 360] degrees.
        trend: f64,
        /// Along the axis (> 0).
        length: f64,
        /// Across the axis, horizontally (> 0).
        width: f64,
        /// Vertically (> 0).
        height: f64,
    },
    /// A vertical shaft: the profile (`u` East, `v` North, about the shaft's axis) swept
    /// down from `top` by `depth`.
    Shaft {
        /// The cross-section.
        profile: Profile,
        /// The centre of the shaft's top.
        top: [f64; 3],
        /// Depth below `top` (> 0).
        depth: f64,
    },
    /// A slope: the air above a profile (crest, benches, toe) extruded along a horizontal
    /// strike, removed; the rock below the profile is kept. The profile's vertices `(u, v)`
    /// are measured from `origin`: `u` horizontal, to the right looking along the strike,
    /// `v` upwards; `u` must go one way (strictly up or strictly down), and the profile is
    /// extended horizontally from its first and last vertices to the rock's edges.
    Slope {
        /// A point of the strike line: the profile's origin.
        origin: [f64; 3],
        /// Trend of the strike, in [0, 360] degrees.
        trend: f64,
        /// The profile's vertices `(u, v)`, at least 2.
        vertices: Vec<[f64; 2]>,
    },
    /// A topographic surface (a height field: one elevation over each horizontal point of
    /// the rock): the air above it removed, the rock below kept.
    Topography {
        /// The surface's triangles.
        surface: Surface,
    },
}

/// A cross-section, in the profile's own coordinates `(u, v)`.
#[derive(Clone, Debug, PartialEq)]
pub enum Profile {
    /// A regular polygon of `segments` sides with its vertices on the circle of `radius`
    /// about the origin (a flat side at the bottom when `segments` is even).
    Circle {
        /// Radius (> 0).
        radius: f64,
        /// Sides (at least 3).
        segments: u32,
    },
    /// A horseshoe: a flat floor of width `2 radius` at `v = -wall`, vertical walls up to
    /// `v = 0` and a half-circle crown of `radius` about the origin made of `segments` sides.
    Horseshoe {
        /// Radius of the crown (> 0).
        radius: f64,
        /// Height of the walls (>= 0; 0: a half circle on its diameter).
        wall: f64,
        /// Sides of the crown (at least 2).
        segments: u32,
    },
    /// Any simple polygon (vertices in order, either sense); a non-convex one is decomposed
    /// into convex pieces.
    Polygon {
        /// Vertices `(u, v)`.
        vertices: Vec<[f64; 2]>,
    },
}

/// The most sides of a circular or horseshoe profile.
pub const MAX_SEGMENTS: u32 = 1024;

impl Excavation {
    /// An unnamed excavation.
    pub fn new(shape: ExcavationShape) -> Excavation {
        Excavation { name: None, shape }
    }

    /// The same excavation with a name.
    pub fn named(mut self, name: impl Into<String>) -> Excavation {
        self.name = Some(name.into());
        self
    }

    /// The convex regions whose union is excavated (checked: each error names its field
    /// under `excavation`). A slope or a topographic surface is bounded by the rock it cuts:
    /// use [`Excavation::regions_in`].
    pub fn regions(&self) -> Result<Vec<ConvexBlock>, SpecError> {
        self.regions_at("excavation", None)
    }

    /// The convex regions whose union is excavated from `rock` (the blocks or the domain's
    /// parts): a slope's or a topographic surface's air reaches above the rock and past its
    /// sides; the other shapes do not depend on the rock.
    pub fn regions_in(&self, rock: &[ConvexBlock]) -> Result<Vec<ConvexBlock>, SpecError> {
        let extent = Extent::of(rock).ok_or_else(|| no_rock("excavation"))?;
        self.regions_at("excavation", Some(&extent))
    }

    /// The excavated volume, exact: the profile's area times the length (an error for a
    /// slope or a topographic surface, whose volume depends on the rock).
    pub fn volume(&self) -> Result<f64, SpecError> {
        let prism = self.prism("excavation")?;
        let area: f64 = prism.pieces.iter().map(|p| signed_area(p)).sum();
        Ok(area * prism.length)
    }

    /// [`Excavation::regions`], naming fields under `prefix` (`excavations[2]`); a slope or
    /// a topographic surface needs the rock's `extent`.
    pub(crate) fn regions_at(
        &self,
        prefix: &str,
        extent: Option<&Extent>,
    ) -> Result<Vec<ConvexBlock>, SpecError> {
        let open = || {
            extent.ok_or_else(|| {
                let msg = "a slope or a topographic surface is bounded by the rock: its \
                           regions need the rock (`regions_in`)";
                SpecError::new(prefix, Problem::Invalid(msg.to_string()))
            })
        };
        match &self.shape {
            ExcavationShape::Slope {
                origin,
                trend,
                vertices,
            } => {
                let extent = open()?;
                let f = |name: &str| format!("{prefix}.{name}");
                let origin = check::point(&f("origin"), *origin)?;
                let trend = angle(&f("trend"), *trend, 0.0..=360.0, "0 and 360")?.to_radians();
                let d = DVec3::new(trend.sin(), trend.cos(), 0.0);
                let u = DVec3::new(trend.cos(), -trend.sin(), 0.0);
                let field = f("vertices");
                let (start, length, pieces) =
                    slope::pieces(&field, vertices, origin, d, u, extent)?;
                let prism = Prism::new(start, d, u, length, pieces);
                prism.regions(prefix)
            }
            ExcavationShape::Topography { surface } => {
                topography::regions(prefix, surface, open()?)
            }
            _ => {
                let prism = self.prism(prefix)?;
                self.check_sizes(prefix, extent)?;
                prism.regions(prefix)
            }
        }
    }

    /// The sizes of a tunnel, cavern or shaft, by field (checked finite and positive by
    /// [`Excavation::prism`] first): the profile's (radius, wall, width, height, or the
    /// polygon's larger side) and the length (depth).
    fn sizes(&self) -> Vec<(&'static str, f64)> {
        let profile = |p: &Profile| match p {
            Profile::Circle { radius, .. } => vec![("radius", *radius)],
            Profile::Horseshoe { radius, wall, .. } if *wall > 0.0 => {
                vec![("radius", *radius), ("wall", *wall)]
            }
            Profile::Horseshoe { radius, .. } => vec![("radius", *radius)],
            Profile::Polygon { vertices } => {
                let side = |k: usize| {
                    let (lo, hi) = vertices
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                            (lo.min(v[k]), hi.max(v[k]))
                        });
                    hi - lo
                };
                vec![("vertices", side(0).max(side(1)))]
            }
        };
        match &self.shape {
            ExcavationShape::Tunnel {
                profile: p, length, ..
            } => {
                let mut sizes = profile(p);
                sizes.push(("length", *length));
                sizes
            }
            ExcavationShape::Cavern {
                length,
                width,
                height,
                ..
            } => {
                vec![("length", *length), ("width", *width), ("height", *height)]
            }
            ExcavationShape::Shaft {
                profile: p, depth, ..
            } => {
                let mut sizes = profile(p);
                sizes.push(("depth", *depth));
                sizes
            }
            ExcavationShape::Slope { .. } | ExcavationShape::Topography { .. } => Vec::new(),
        }
    }

    /// Sizes that double precision can cut with: each within [`SIZE_RANGE`] times the size
    /// of the rock (the diagonal of its box, when known), and each at least `1 / SIZE_RANGE`
    /// times the opening's largest (a radius of 1e20 or 1e-12 with a length of 12 made a
    /// region whose planes the tolerance could not tell apart, reported as "the half-spaces
    /// do not bound a solid block").
    fn check_sizes(&self, prefix: &str, extent: Option<&Extent>) -> Result<(), SpecError> {
        let sizes = self.sizes();
        let field = |name: &str| format!("{prefix}.{name}");
        if let Some(extent) = extent {
            let rock = extent.aabb.diagonal();
            let (lo, hi) = (rock / SIZE_RANGE, rock * SIZE_RANGE);
            if let Some(&(name, value)) = sizes.iter().find(|(_, v)| !(lo..=hi).contains(v)) {
                let msg = format!(
                    "must be between {} and {} (1e-6 to 1e6 times the size of the rock, whose \
                     box has a diagonal of {}), got {}",
                    readable(lo),
                    readable(hi),
                    readable(rock),
                    readable(value)
                );
                return Err(SpecError::new(field(name), Problem::Invalid(msg)));
            }
        }
        let Some(&(largest, most)) = sizes.iter().max_by(|a, b| a.1.total_cmp(&b.1)) else {
            return Ok(());
        };
        if let Some(&(name, value)) = sizes.iter().find(|(_, v)| *v * SIZE_RANGE < most) {
            let msg = format!(
                "must be at least 1e-6 times the opening's {largest} ({}), got {}",
                readable(most),
                readable(value)
            );
            return Err(SpecError::new(field(name), Problem::Invalid(msg)));
        }
        Ok(())
    }

    /// The checked prism: frame, length and convex pieces of the profile.
    fn prism(&self, prefix: &str) -> Result<Prism, SpecError> {
        let f = |name: &str| format!("{prefix}.{name}");
        match &self.shape {
            ExcavationShape::Tunnel {
                profile,
                start,
                trend,
                plunge,
                length,
            } => {
                let start = check::point(&f("start"), *start)?;
                let trend = angle(&f("trend"), *trend, 0.0..=360.0, "0 and 360")?.to_radians();
                let plunge = finite_in(&f("plunge"), *plunge)?.to_radians();
                let length = check::positive(&f("length"), *length)?;
                let d = DVec3::new(
                    trend.sin() * plunge.cos(),
                    trend.cos() * plunge.cos(),
                    -plunge.sin(),
                );
                let u = DVec3::new(trend.cos(), -trend.sin(), 0.0);
                let pieces = profile.pieces(prefix)?;
                Ok(Prism::new(start, d, u, length, pieces))
            }
            ExcavationShape::Cavern {
                center,
                trend,
                length,
                width,
                height,
            } => {
                let center = check::point(&f("center"), *center)?;
                let trend = angle(&f("trend"), *trend, 0.0..=360.0, "0 and 360")?.to_radians();
                let length = check::positive(&f("length"), *length)?;
                let (w, h) = (
                    check::positive(&f("width"), *width)? / 2.0,
                    check::positive(&f("height"), *height)? / 2.0,
                );
                let d = DVec3::new(trend.sin(), trend.cos(), 0.0);
                let u = DVec3::new(trend.cos(), -trend.sin(), 0.0);
                let rectangle = vec![[-w, -h], [w, -h], [w, h], [-w, h]];
                Ok(Prism::new(
                    center - d * (length / 2.0),
                    d,
                    u,
                    length,
                    vec![rectangle],
                ))
            }
            ExcavationShape::Shaft {
                profile,
                top,
                depth,
            } => {
                let top = check::point(&f("top"), *top)?;
                let depth = check::positive(&f("depth"), *depth)?;
                let pieces = profile.pieces(prefix)?;
                Ok(Prism::new(top, -DVec3::Z, DVec3::X, depth, pieces))
            }
            ExcavationShape::Slope { .. } | ExcavationShape::Topography { .. } => {
                let msg = "a slope or a topographic surface has no volume of its own: what \
                           it removes depends on the rock";
                Err(SpecError::new(prefix, Problem::Invalid(msg.to_string())))
            }
        }
    }
}

/// How many times the size of the rock an opening's size may be, at most (and its
/// inverse, at least); also the largest ratio of an opening's sizes.
const SIZE_RANGE: f64 = 1e6;

/// A number for a message: plain with up to 4 significant digits for magnitudes from 1e-3
/// to below 1e6, with an exponent otherwise (`1.7e7`, `2.5e-5`).
pub(crate) fn readable(x: f64) -> String {
    let m = x.abs();
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if (1e-3..1e6).contains(&m) {
        let digits = (3 - m.log10().floor() as i32).max(0) as usize;
        let text = format!("{x:.digits$}");
        if text.contains('.') {
            return text.trim_end_matches('0').trim_end_matches('.').to_string();
        }
        return text;
    }
    let text = format!("{x:.3e}");
    let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    format!("{mantissa}e{exponent}")
}

/// The error of an excavation applied to no rock at all.
pub(crate) fn no_rock(prefix: &str) -> SpecError {
    let msg = "the excavation removes no rock: there is no rock (no block)";
    SpecError::new(prefix, Problem::Invalid(msg.to_string()))
}

/// An angle within `range` (degrees).
fn angle(
    field: &str,
    value: f64,
    range: std::ops::RangeInclusive<f64>,
    words: &str,
) -> Result<f64, SpecError> {
    if check::finite(field, value)? < *range.start() || value > *range.end() {
        let msg = format!("must be between {words} degrees, got {value}");
        return Err(SpecError::new(field, Problem::Invalid(msg)));
    }
    Ok(value)
}

/// A plunge strictly between -90 and 90 degrees (a vertical opening is a shaft).
fn finite_in(field: &str, value: f64) -> Result<f64, SpecError> {
    if check::finite(field, value)?.abs() >= 90.0 {
        let msg = format!(
            "must be between -90 and 90 degrees (exclusive; a vertical opening is a shaft), \
             got {value}"
        );
        return Err(SpecError::new(field, Problem::Invalid(msg)));
    }
    Ok(value)
}

/// A profile swept along an axis.
pub(super) struct Prism {
    /// Where the axis starts.
    start: DVec3,
    /// The axis (unit).
    d: DVec3,
    /// The profile's `u` and `v` axes (unit, perpendicular to `d`).
    u: DVec3,
    v: DVec3,
    length: f64,
    /// The profile's convex pieces, counter-clockwise in `(u, v)`.
    pieces: Vec<Vec<[f64; 2]>>,
}

impl Prism {
    pub(super) fn new(
        start: DVec3,
        d: DVec3,
        u: DVec3,
        length: f64,
        pieces: Vec<Vec<[f64; 2]>>,
    ) -> Prism {
        Prism {
            start,
            d,
            u,
            v: u.cross(d),
            length,
            pieces,
        }
    }

    /// Every piece swept along the axis; an error names `prefix`.
    fn regions(&self, prefix: &str) -> Result<Vec<ConvexBlock>, SpecError> {
        self.pieces
            .iter()
            .map(|piece| self.region(piece))
            .collect::<Result<_, _>>()
            .map_err(|e| SpecError::new(prefix, Problem::Invalid(e.to_string())))
    }

    /// One convex piece swept along the axis: the two ends and one side per edge of the
    /// piece (its outward normal in the profile's plane). Built from these half-spaces
    /// while they are few enough ([`crate::block::MAX_HALFSPACES`]), else from its
    /// vertices and faces, known exactly (a circle of 1024 segments has 1026 faces).
    fn region(&self, piece: &[[f64; 2]]) -> Result<ConvexBlock, crate::BlockError> {
        let at = |p: [f64; 2]| self.start + self.u * p[0] + self.v * p[1];
        let end = self.start + self.d * self.length;
        if piece.len() + 2 > crate::block::MAX_HALFSPACES {
            return self.column(piece);
        }
        let mut normals = vec![(-self.d).to_array(), self.d.to_array()];
        let mut offsets = vec![-self.d.dot(self.start), self.d.dot(end)];
        for k in 0..piece.len() {
            let (p, q) = (piece[k], piece[(k + 1) % piece.len()]);
            let n = self.u * (q[1] - p[1]) - self.v * (q[0] - p[0]);
            let n = n.normalize();
            normals.push(n.to_array());
            offsets.push(n.dot(at(p)));
        }
        ConvexBlock::from_planes(&normals, &offsets)
    }

    /// [`Prism::region`] from vertices and faces, in the same order of faces: the start
    /// (the piece's vertices at `start`, counter-clockwise seen from behind it: `v = u x
    /// d`), the end, and the side of each edge. A vertex of the piece within a few times
    /// the block's length tolerance of the line through its neighbours is left out, as the
    /// half-spaces would leave it: its two sides would be one face, and it no corner.
    fn column(&self, piece: &[[f64; 2]]) -> Result<ConvexBlock, crate::BlockError> {
        let at = |p: [f64; 2]| self.start + self.u * p[0] + self.v * p[1];
        let along = self.d * self.length;
        let corners: Vec<DVec3> = piece.iter().flat_map(|&p| [at(p), at(p) + along]).collect();
        let size = crate::geometry::Aabb::of_points(&corners);
        let straight = 8.0 * crate::Tolerance::default().for_box(&size).length;
        let mut piece = piece.to_vec();
        loop {
            let before = piece.len();
            let mut k = 0;
            while k < piece.len() && piece.len() > 3 {
                let n = piece.len();
                let (p, q, r) = (piece[(k + n - 1) % n], piece[k], piece[(k + 1) % n]);
                let (a, b) = ([r[0] - p[0], r[1] - p[1]], [q[0] - p[0], q[1] - p[1]]);
                let off = (a[0] * b[1] - a[1] * b[0]).abs() / a[0].hypot(a[1]);
                if off <= straight {
                    piece.remove(k);
                    k = k.saturating_sub(1);
                } else {
                    k += 1;
                }
            }
            if piece.len() == before {
                break;
            }
        }
        let n = piece.len();
        let mut vertices: Vec<[f64; 3]> = piece.iter().map(|&p| at(p).to_array()).collect();
        vertices.extend(piece.iter().map(|&p| (at(p) + along).to_array()));
        let mut faces: Vec<Vec<usize>> = Vec::with_capacity(n + 2);
        faces.push((0..n).collect());
        faces.push((0..n).rev().map(|k| n + k).collect());
        for k in 0..n {
            let l = (k + 1) % n;
            faces.push(vec![k, n + k, n + l, l]);
        }
        ConvexBlock::new(&vertices, &faces)
    }
}

impl Profile {
    /// The vertices, counter-clockwise.
    fn vertices(&self, prefix: &str) -> Result<Vec<[f64; 2]>, SpecError> {
        let f = |name: &str| format!("{prefix}.{name}");
        let segments = |name: &str, n: u32, least: u32| {
            if n < least || n > MAX_SEGMENTS {
                let msg = format!("must be between {least} and {MAX_SEGMENTS}, got {n}");
                return Err(SpecError::new(f(name), Problem::Invalid(msg)));
            }
            Ok(n)
        };
        use std::f64::consts::PI;
        match self {
            Profile::Circle {
                radius,
                segments: n,
            } => {
                let r = check::positive(&f("radius"), *radius)?;
                let n = segments("segments", *n, 3)?;
                Ok((0..n)
                    .map(|k| {
                        let a = -PI / 2.0 + (2 * k + 1) as f64 * PI / n as f64;
                        [r * a.cos(), r * a.sin()]
                    })
                    .collect())
            }
            Profile::Horseshoe {
                radius,
                wall,
                segments: n,
            } => {
                let r = check::positive(&f("radius"), *radius)?;
                let wall = check::non_negative(&f("wall"), *wall)?;
                let n = segments("segments", *n, 2)?;
                let mut v = Vec::with_capacity(n as usize + 3);
                if wall > 0.0 {
                    v.extend([[-r, -wall], [r, -wall]]);
                }
                v.extend((0..=n).map(|k| {
                    let a = k as f64 * PI / n as f64;
                    [r * a.cos(), r * a.sin()]
                }));
                Ok(v)
            }
            Profile::Polygon { vertices } => {
                let field = f("vertices");
                for p in vertices {
                    check::finite(&field, p[0])?;
                    check::finite(&field, p[1])?;
                }
                let mut v = vertices.clone();
                if signed_area(&v) < 0.0 {
                    v.reverse();
                }
                check_simple(&field, &v)?;
                Ok(v)
            }
        }
    }

    /// The convex pieces, counter-clockwise.
    fn pieces(&self, prefix: &str) -> Result<Vec<Vec<[f64; 2]>>, SpecError> {
        let v = self.vertices(prefix)?;
        if is_convex(&v) {
            return Ok(vec![v]);
        }
        Ok(convex_pieces(&v))
    }
}

pub(super) fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// The signed area of a polygon (positive counter-clockwise), by the shoelace.
pub(super) fn signed_area(v: &[[f64; 2]]) -> f64 {
    (0..v.len())
        .map(|k| {
            let (p, q) = (v[k], v[(k + 1) % v.len()]);
            p[0] * q[1] - p[1] * q[0]
        })
        .sum::<f64>()
        / 2.0
}

/// Whether a counter-clockwise polygon is convex (collinear vertices allowed).
pub(super) fn is_convex(v: &[[f64; 2]]) -> bool {
    let n = v.len();
    let scale = v
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    (0..n).all(|k| cross(v[k], v[(k + 1) % n], v[(k + 2) % n]) >= -1e-12 * scale * scale)
}

/// Checks that a counter-clockwise polygon is simple: at least 3 vertices, a positive area,
/// no repeated vertex, no two edges that cross or touch except neighbours at their shared end.
fn check_simple(field: &str, v: &[[f64; 2]]) -> Result<(), SpecError> {
    let bad = |msg: &str| Err(SpecError::new(field, Problem::Invalid(msg.to_string())));
    let n = v.len();
    if n < 3 {
        return bad("a profile needs at least 3 vertices");
    }
    for i in 0..n {
        for j in i + 1..n {
            if v[i] == v[j] {
                return bad(&format!("vertices {i} and {j} are the same point"));
            }
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            let neighbours = j == i + 1 || (i == 0 && j == n - 1);
            let (a, b) = (v[i], v[(i + 1) % n]);
            let (c, d) = (v[j], v[(j + 1) % n]);
            if !neighbours && segments_meet(a, b, c, d) {
                let msg = format!("the profile crosses itself: its edges {i} and {j} meet");
                return bad(&msg);
            }
            // Neighbours folding back on each other (a spike).
            if neighbours {
                let (o, p, q) = if j == i + 1 { (b, a, d) } else { (a, b, c) };
                let (e, g) = ([p[0] - o[0], p[1] - o[1]], [q[0] - o[0], q[1] - o[1]]);
                if cross(o, p, q) == 0.0 && e[0] * g[0] + e[1] * g[1] > 0.0 {
                    let msg = format!("the profile folds back on itself at edges {i} and {j}");
                    return bad(&msg);
                }
            }
        }
    }
    if signed_area(v) <= 0.0 {
        return bad("the profile has no area");
    }
    Ok(())
}

/// Whether segments `ab` and `cd` share a point.
fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (cross(a, b, c), cross(a, b, d));
    let (d3, d4) = (cross(c, d, a), cross(c, d, b));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    (d1 == 0.0 && on(a, b, c))
        || (d2 == 0.0 && on(a, b, d))
        || (d3 == 0.0 && on(c, d, a))
        || (d4 == 0.0 && on(c, d, b))
}

/// A simple counter-clockwise polygon cut into convex pieces: triangles by ear clipping,
/// then neighbouring pieces merged while the union stays convex (Hertel and Mehlhorn: at
/// most four times the fewest pieces possible).
fn convex_pieces(v: &[[f64; 2]]) -> Vec<Vec<[f64; 2]>> {
    let mut pieces: Vec<Vec<usize>> = ear_clip(v);
    let points = |p: &[usize]| p.iter().map(|&k| v[k]).collect::<Vec<_>>();
    'merge: loop {
        for i in 0..pieces.len() {
            for j in i + 1..pieces.len() {
                if let Some(m) = merge(&pieces[i], &pieces[j]) {
                    if is_convex(&points(&m)) {
                        pieces[i] = m;
                        pieces.swap_remove(j);
                        continue 'merge;
                    }
                }
            }
        }
        break;
    }
    pieces.iter().map(|p| points(p)).collect()
}

/// Triangles (vertex indices, counter-clockwise) of a simple counter-clockwise polygon.
fn ear_clip(v: &[[f64; 2]]) -> Vec<Vec<usize>> {
    let mut left: Vec<usize> = (0..v.len()).collect();
    let mut out = Vec::with_capacity(v.len().saturating_sub(2));
    while left.len() > 3 {
        let n = left.len();
        let ear = (0..n).find(|&k| {
            let (a, b, c) = (left[(k + n - 1) % n], left[k], left[(k + 1) % n]);
            cross(v[a], v[b], v[c]) > 0.0
                && left.iter().all(|&p| {
                    p == a || p == b || p == c || !inside_triangle(v[p], v[a], v[b], v[c])
                })
        });
        // A simple polygon always has an ear; rounding aside, clip the most convex vertex.
        let k = ear.unwrap_or_else(|| {
            (0..n)
                .max_by(|&x, &y| {
                    let c = |k: usize| {
                        cross(v[left[(k + n - 1) % n]], v[left[k]], v[left[(k + 1) % n]])
                    };
                    c(x).total_cmp(&c(y))
                })
                .expect("more than 3 vertices")
        });
        let (a, b, c) = (left[(k + n - 1) % n], left[k], left[(k + 1) % n]);
        if cross(v[a], v[b], v[c]) > 0.0 {
            out.push(vec![a, b, c]);
        }
        left.remove(k);
    }
    out.push(left);
    out
}

/// Whether `p` lies in the closed triangle `abc` (counter-clockwise).
fn inside_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0
}

/// Two counter-clockwise pieces sharing an edge, merged into one loop.
fn merge(p: &[usize], q: &[usize]) -> Option<Vec<usize>> {
    let (np, nq) = (p.len(), q.len());
    for i in 0..np {
        let (a, b) = (p[i], p[(i + 1) % np]);
        if let Some(j) = (0..nq).find(|&j| q[j] == b && q[(j + 1) % nq] == a) {
            // p from b round to a, then q from a's successor... q runs b -> a at j, so q from
            // a (j + 1) round to b (j) is [a, .., b]: its inner vertices follow a.
            let mut m: Vec<usize> = (0..np).map(|k| p[(i + 1 + k) % np]).collect();
            m.extend((2..nq).map(|k| q[(j + k) % nq]));
            return Some(m);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(pieces: &[Vec<[f64; 2]>]) -> f64 {
        pieces.iter().map(|p| signed_area(p)).sum()
    }

    #[test]
    fn a_convex_piece_of_many_edges_is_a_column_and_a_vertex_on_its_chord_no_corner() {
        // A regular 300-gon of radius 1 (302 faces swept, more half-spaces than a block
        // from them takes) with a vertex 1e-10 outside the middle of one edge: within the
        // length tolerance (1e-9 of the column's size, some 4 m) of that edge's line, so
        // its two sides are one face and it is no corner; it is left out.
        let n = 300;
        let mut piece: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                [a.cos(), a.sin()]
            })
            .collect();
        let (p, q) = (piece[0], piece[1]);
        let (mid, out) = ([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])], 1e-10);
        let norm = mid[0].hypot(mid[1]);
        piece.insert(
            1,
            [mid[0] * (1.0 + out / norm), mid[1] * (1.0 + out / norm)],
        );
        let prism = Prism::new(DVec3::ZERO, DVec3::Y, DVec3::X, 3.0, vec![piece]);
        let regions = prism.regions("excavation").unwrap();
        assert_eq!(regions.len(), 1);
        assert_eq!(regions[0].n_faces(), n + 2);
        let exact = 0.5 * n as f64 * (std::f64::consts::TAU / n as f64).sin() * 3.0;
        assert!((regions[0].volume() - exact).abs() < 1e-12 * exact);
    }

    #[test]
    fn an_l_profile_is_cut_into_convex_pieces_of_its_area() {
        // An L of area 3 (unit squares), clockwise: reversed, then cut.
        let l = vec![
            [0.0, 0.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
        ];
        let profile = Profile::Polygon { vertices: l };
        let pieces = profile.pieces("p").unwrap();
        assert_eq!(pieces.len(), 2);
        assert!(pieces.iter().all(|p| is_convex(p) && signed_area(p) > 0.0));
        assert!((area(&pieces) - 3.0).abs() < 1e-14);
    }

    #[test]
    fn a_comb_profile_is_cut_into_convex_pieces_of_its_area() {
        // A comb: 3 teeth of 1 x 2 on a 5 x 1 base: area 5 + 3 * 2 = 11.
        let c = vec![
            [0.0, 0.0],
            [5.0, 0.0],
            [5.0, 3.0],
            [4.0, 3.0],
            [4.0, 1.0],
            [3.0, 1.0],
            [3.0, 3.0],
            [2.0, 3.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ];
        let profile = Profile::Polygon { vertices: c };
        let pieces = profile.pieces("p").unwrap();
        assert!(pieces.iter().all(|p| is_convex(p)));
        assert!((area(&pieces) - 11.0).abs() < 1e-12, "{}", area(&pieces));
        assert!(pieces.len() <= 8);
    }

    #[test]
    fn a_circle_and_a_horseshoe_have_the_areas_of_their_polygons() {
        let r = 2.0;
        let n = 16;
        let circle = Profile::Circle {
            radius: r,
            segments: n,
        };
        let a = area(&circle.pieces("p").unwrap());
        let expected = 0.5 * n as f64 * r * r * (2.0 * std::f64::consts::PI / n as f64).sin();
        assert!((a - expected).abs() < 1e-12);
        let shoe = Profile::Horseshoe {
            radius: r,
            wall: 1.5,
            segments: 8,
        };
        let pieces = shoe.pieces("p").unwrap();
        assert_eq!(pieces.len(), 1);
        let half = 0.5 * 8.0 * r * r * (std::f64::consts::PI / 8.0).sin();
        assert!((area(&pieces) - (half + 2.0 * r * 1.5)).abs() < 1e-12);
    }

    #[test]
    fn bad_profiles_name_their_field() {
        let bow = Profile::Polygon {
            vertices: vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]],
        };
        let e = bow.pieces("excavations[0].profile").unwrap_err();
        assert_eq!(e.field, "excavations[0].profile.vertices");
        assert!(e.to_string().contains("crosses itself"), "{e}");
        let e = Profile::Circle {
            radius: 0.0,
            segments: 8,
        }
        .pieces("x")
        .unwrap_err();
        assert_eq!(e.field, "x.radius");
        let e = Profile::Circle {
            radius: f64::NAN,
            segments: 8,
        }
        .pieces("x")
        .unwrap_err();
        assert!(matches!(e.problem, Problem::NotFinite { .. }), "{e}");
        let tunnel = Excavation::new(ExcavationShape::Tunnel {
            profile: Profile::Circle {
                radius: 1.0,
                segments: 8,
            },
            start: [0.0; 3],
            trend: 0.0,
            plunge: 0.0,
            length: 0.0,
        });
        assert_eq!(tunnel.regions().unwrap_err().field, "excavation.length");
    }

    #[test]
    fn a_tunnel_region_has_the_profile_area_times_the_length() {
        let tunnel = Excavation::new(ExcavationShape::Tunnel {
            profile: Profile::Circle {
                radius: 1.5,
                segments: 12,
            },
            start: [1.0, 2.0, 3.0],
            trend: 30.0,
            plunge: 10.0,
            length: 7.0,
        });
        let regions = tunnel.regions().unwrap();
        let v: f64 = regions.iter().map(ConvexBlock::volume).sum();
        let exact = 0.5 * 12.0 * 1.5 * 1.5 * (std::f64::consts::PI / 6.0).sin() * 7.0;
        assert!((v - exact).abs() < 1e-12 * exact);
        assert!((tunnel.volume().unwrap() - exact).abs() < 1e-12 * exact);
        // The far end's centre: 7 m along trend 30, plunge 10 from the start.
        let (t, p) = (30f64.to_radians(), 10f64.to_radians());
        let end = DVec3::new(1.0, 2.0, 3.0)
            + 7.0 * DVec3::new(t.sin() * p.cos(), t.cos() * p.cos(), -p.sin());
        let far = regions[0]
            .vertices()
            .iter()
            .map(|x| (*x - end).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            (far - 1.5).abs() < 1e-12,
            "the far end's vertices lie on the circle"
        );
    }
}
