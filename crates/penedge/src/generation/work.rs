//! The work of a run, known before cutting: an estimate of the blocks a spec makes, the
//! memory they take, and the limit a run may not pass.
//!
//! A spec of three joint sets at 1 cm spacing in a 100 m box has 30,000 planes (well within
//! [`super::MAX_PLANES`]) but makes about 10^12 blocks: cutting it would fill any memory. The
//! number of planes says little; the arrangement of the planes says it all. In a convex
//! domain, planes in general position make
//!
//! ```text
//! blocks = 1 + planes + lines + points
//! ```
//!
//! where `lines` counts the pairs of planes whose line of intersection crosses the domain and
//! `points` the triples whose common point lies inside it (each plane adds one block, and one
//! more for each line and point it makes with the planes before it). For joint sets that fill
//! the domain this is the product of `(1 + planes)` over the sets when their normals are
//! independent; parallel planes make no line, and planes whose normals lie in one plane (three
//! vertical sets) make no point. [`estimate`] counts this way, by orientation class:
//!
//! * a regular joint set, and single planes parallel to it, form one class: parallel, no line
//!   within the class;
//! * a set with random orientation deviations is a class of its own whose planes also meet
//!   each other: the lines of neighbours that the tilt `2 (dip + dip direction deviation)`
//!   makes meet within the domain's size, and the points of three such planes;
//! * a finite joint (disc, polygon) of weight `w = extent / domain size` (at most 1) meets
//!   about `w` of the infinite planes and holds `w^2` of their lines' points; two finite
//!   joints meet when they are near each other (`(w_a w_b)^1.5`). So a network of many
//!   small discs is not counted as so many infinite planes.
//!
//! Pairs and triples of different classes are all counted as if they met inside the domain,
//! so the estimate is an upper bound for sets that fill a box (exact for orthogonal sets) and
//! errs high for oblique ones; it is an estimate, not a promise, so a run also stops once it
//! makes more blocks than its limit ([`Limits`]).

use super::expand::Plan;
use super::record::JointShape;
use super::spec::{JointKind, Spec};
use crate::geometry::{Aabb, DVec3};

/// Bytes one block takes at the peak of a run, generation and the block file written: the
/// block (vertices, faces, planes, edges, origins), its node in the cutting tree, the copy
/// that becomes the [`crate::system::BlockSystem`] and the JSON written. `penedge generate
/// -o` peaks at 3.1 GB for 10^6 blocks (docs/generation.md), 3.1 kB a block, rounded up.
pub const BYTES_PER_BLOCK: u64 = 4096;

/// The block limit when the memory available cannot be read (not Linux).
pub const FALLBACK_MAX_BLOCKS: u64 = 20_000_000;

/// The share of the available memory a run may plan to use.
const MEMORY_SHARE: f64 = 0.5;

/// What a spec will make, before cutting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Joint planes that cross the domain.
    pub planes: usize,
    /// Lines where two planes meet (counted as above).
    pub lines: f64,
    /// Points where three planes meet.
    pub points: f64,
    /// Blocks: `1 + planes + lines + points` (finite joints weighted).
    pub blocks: f64,
}

impl Estimate {
    /// Bytes the blocks take at the peak of a run ([`BYTES_PER_BLOCK`] each).
    pub fn bytes(&self) -> f64 {
        self.blocks * BYTES_PER_BLOCK as f64
    }
}

/// How much a run may make.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The most blocks: a spec estimated to make more is refused before cutting, and a run
    /// that makes more stops.
    pub max_blocks: u64,
    /// Whether `max_blocks` was set by the caller (rather than from the memory available).
    pub given: bool,
}

impl Limits {
    /// At most `max_blocks` blocks, whatever the memory.
    pub fn blocks(max_blocks: u64) -> Limits {
        Limits {
            max_blocks,
            given: true,
        }
    }

    /// As many blocks as half the memory available now holds ([`BYTES_PER_BLOCK`] each), or
    /// [`FALLBACK_MAX_BLOCKS`] where the memory available cannot be read.
    pub fn from_memory() -> Limits {
        let max_blocks = available_memory().map_or(FALLBACK_MAX_BLOCKS, |bytes| {
            (bytes as f64 * MEMORY_SHARE / BYTES_PER_BLOCK as f64) as u64
        });
        Limits {
            max_blocks: max_blocks.max(1),
            given: false,
        }
    }
}

impl Default for Limits {
    fn default() -> Self {
        Limits::from_memory()
    }
}

/// The memory available to a new allocation, in bytes (`MemAvailable` of `/proc/meminfo`);
/// `None` where it cannot be read.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// One orientation class: planes of (nearly) one normal.
struct Class {
    normal: DVec3,
    /// Planes, finite joints weighted.
    weight: f64,
    /// Lines within the class (a set with orientation deviations).
    lines: f64,
    /// Points within the class.
    points: f64,
}

/// Above this many classes, pairs and triples are counted as in general position (by the
/// elementary symmetric sums), not one by one.
const MAX_CLASSES_ONE_BY_ONE: usize = 200;

/// Two normals are parallel, and three dependent, below this sine (or determinant).
const PARALLEL: f64 = 1e-9;

/// The estimate of a checked and expanded spec.
pub(crate) fn estimate(spec: &Spec, plan: &Plan) -> Estimate {
    let size = spec.domain.size();
    let (classes, finite) = classes(spec, plan, size);
    let single: f64 = classes.iter().map(|c| c.weight).sum();
    let mut lines: f64 = classes.iter().map(|c| c.lines).sum();
    let mut points: f64 = classes.iter().map(|c| c.points).sum();
    // Lines within one class meet the planes of every other class.
    points += classes
        .iter()
        .map(|c| c.lines * (single - c.weight))
        .sum::<f64>();
    if classes.len() <= MAX_CLASSES_ONE_BY_ONE {
        let shape = Shape::of(&spec.domain);
        for (i, a) in classes.iter().enumerate() {
            for (j, b) in classes.iter().enumerate().skip(i + 1) {
                if a.normal.cross(b.normal).length() <= PARALLEL {
                    continue;
                }
                lines += a.weight * b.weight * shape.pair_share(a.normal, b.normal);
                for c in &classes[j + 1..] {
                    let share = shape.triple_share(a.normal, b.normal, c.normal);
                    points += a.weight * b.weight * c.weight * share;
                }
            }
        }
    } else {
        let s1 = single;
        let s2: f64 = classes.iter().map(|c| c.weight.powi(2)).sum();
        let s3: f64 = classes.iter().map(|c| c.weight.powi(3)).sum();
        lines += (s1 * s1 - s2) / 2.0;
        points += (s1.powi(3) - 3.0 * s1 * s2 + 2.0 * s3) / 6.0;
    }
    // A finite joint of weight `w` (its extent over the domain's size) meets about `w` of
    // the infinite planes, holds about `w^2` of their lines' points, and meets another
    // finite joint when both are near each other, about `(w_a w_b)^1.5` (two discs of radius
    // `r` meet where their centres are within `2r`: `(r / size)^3`), in a segment that
    // crosses about `w` of the infinite planes.
    let w1: f64 = finite.iter().sum();
    let w2: f64 = finite.iter().map(|w| w * w).sum();
    let w15: f64 = finite.iter().map(|w| w.powf(1.5)).sum();
    let w3: f64 = finite.iter().map(|w| w.powi(3)).sum();
    let among_finite = (w15 * w15 - w3) / 2.0;
    let typical = if w1 > 0.0 { w2 / w1 } else { 0.0 };
    points += w2 * lines + among_finite * single * typical;
    lines += w1 * single + among_finite;
    // Sums of products of large weights can cancel to a little below zero.
    let at_least_zero = |x: f64| if x < 0.0 { 0.0 } else { x };
    let (lines, points) = (at_least_zero(lines), at_least_zero(points));
    Estimate {
        planes: plan.records.len(),
        lines,
        points,
        blocks: 1.0 + single + w1 + lines + points,
    }
}

/// The domain's vertices and volume: which share of the pairs (triples) of planes of two
/// (three) classes, spread over the domain's extent along their normals, meet inside it.
struct Shape {
    vertices: Vec<Vec<DVec3>>,
    volume: f64,
    all: Vec<DVec3>,
}

impl Shape {
    fn of(domain: &super::Domain) -> Shape {
        let vertices: Vec<Vec<DVec3>> = domain
            .parts()
            .iter()
            .map(|p| p.vertices().to_vec())
            .collect();
        let all = vertices.concat();
        Shape {
            vertices,
            volume: domain.volume(),
            all,
        }
    }

    /// The domain's extent along `n`.
    fn extent(&self, n: DVec3) -> f64 {
        let (lo, hi) = self
            .all
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |r, v| {
                let t = n.dot(*v);
                (r.0.min(t), r.1.max(t))
            });
        (hi - lo).max(0.0)
    }

    /// The share of pairs `(a · x = s, b · x = t)`, `s` and `t` over the domain's extents,
    /// whose line crosses the domain: the area of the domain's image under
    /// `x -> (a · x, b · x)` over the rectangle of the extents.
    fn pair_share(&self, a: DVec3, b: DVec3) -> f64 {
        let rectangle = self.extent(a) * self.extent(b);
        let image: f64 = self
            .vertices
            .iter()
            .map(|part| {
                let points: Vec<[f64; 2]> = part.iter().map(|v| [a.dot(*v), b.dot(*v)]).collect();
                hull_area(points)
            })
            .sum();
        share(image, rectangle)
    }

    /// The share of triples whose point lies inside the domain: the volume of the domain's
    /// image under `x -> (a · x, b · x, c · x)` (`|det| V`) over the box of the extents.
    fn triple_share(&self, a: DVec3, b: DVec3, c: DVec3) -> f64 {
        let det = a.dot(b.cross(c)).abs();
        if det <= PARALLEL {
            return 0.0;
        }
        let product = self.extent(a) * self.extent(b) * self.extent(c);
        share(det * self.volume, product)
    }
}

/// `part / whole`, within [0, 1] (1 for an empty whole).
fn share(part: f64, whole: f64) -> f64 {
    if whole > 0.0 {
        (part / whole).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The area of the convex hull of points in the plane (Andrew's monotone chain).
fn hull_area(mut points: Vec<[f64; 2]>) -> f64 {
    points.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    let turn = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * points.len());
    for pass in [
        &points[..],
        &points.iter().rev().copied().collect::<Vec<_>>()[..],
    ] {
        let start = hull.len();
        for &p in pass {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    let n = hull.len();
    (0..n)
        .map(|i| {
            let (p, q) = (hull[i], hull[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

/// The orientation classes of the plan's infinite joints, and the weights of its finite
/// ones.
fn classes(spec: &Spec, plan: &Plan, size: f64) -> (Vec<Class>, Vec<f64>) {
    let mut classes: Vec<Class> = Vec::new();
    let mut add_parallel = |normal: DVec3, weight: f64| match classes
        .iter_mut()
        .find(|c| c.lines == 0.0 && c.normal.cross(normal).length() <= PARALLEL)
    {
        Some(c) => c.weight += weight,
        None => classes.push(Class {
            normal,
            weight,
            lines: 0.0,
            points: 0.0,
        }),
    };
    let mut deviated = Vec::new();
    let mut finite = Vec::new();
    let mut start = 0;
    while start < plan.records.len() {
        let set = plan.records[start].set;
        let n = plan.records[start..]
            .iter()
            .take_while(|r| r.set == set)
            .count();
        let members = &plan.records[start..start + n];
        start += n;
        let entry = spec.joints.get(set as usize).map(|d| &d.kind);
        if let Some(JointKind::Set(js)) = entry {
            // The typical angle between two planes of the set.
            let tilt = js
                .deviation
                .dip
                .hypot(js.deviation.dip_direction)
                .to_radians();
            let normal = members
                .iter()
                .fold(DVec3::ZERO, |s, r| s + r.plane.normal)
                .normalize_or_zero();
            if tilt > 0.0 && n > 1 {
                // Neighbours within `reach` planes of each other can meet in the domain.
                let sine = tilt.min(std::f64::consts::FRAC_PI_2).sin();
                let reach = (size * sine / js.spacing).min((n - 1) as f64);
                let nf = n as f64;
                let lines = reach * nf - reach * (reach + 1.0) / 2.0;
                deviated.push(Class {
                    normal,
                    weight: nf,
                    lines,
                    points: lines * reach / 3.0,
                });
            } else {
                add_parallel(normal, n as f64);
            }
            continue;
        }
        for r in members {
            let extent = match &r.shape {
                JointShape::Infinite => {
                    add_parallel(r.plane.normal, 1.0);
                    continue;
                }
                JointShape::Disc { radius, .. } => 2.0 * radius,
                JointShape::Polygon { vertices } => Aabb::of_points(vertices).diagonal(),
            };
            finite.push((extent / size).min(1.0));
        }
    }
    classes.extend(deviated);
    (classes, finite)
}
