//! Finite joints: does a disc or polygon cross a block's section completely, partly, or not?
//!
//! The rule: a finite joint splits a block only where it crosses it completely, that is where
//! the section of the block by the joint's plane (a convex polygon) lies inside the disc or
//! polygon, within the length threshold. A joint that ends inside a block (it covers part of
//! the section) leaves the block whole; such a *partial cut* is counted in the report. The
//! tests run in the plane, in 2D coordinates (u, w) with `w = n × u`.
//!
//! With rock bridges on ([`crate::generation::Discontinuity::bridge`]), a block the joint ends
//! inside is cut through instead, so that each new face lies wholly on the joint or wholly
//! on the bridge (docs/generation.md, "Rock bridges"): the joint's outline is a convex polygon
//! ([`outline`]: a disc is the regular polygon of [`DISC_SEGMENTS`] sides and the disc's
//! area), and the block is first split by the *seams*, the planes through the outline's edges
//! perpendicular to the joint's plane whose lines cross the block's section; each piece
//! outside a seam is then cut along the joint's plane with bridge faces, and the piece inside
//! every seam with joint faces. Seam faces are bridge faces too: they are cut through intact
//! rock.

use super::record::JointShape;
use crate::geometry::{DVec3, Plane};

/// How a finite joint meets a block's section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Coverage {
    /// The joint covers the whole section: cut.
    Whole,
    /// The joint covers part of the section: no cut, counted.
    Partial,
    /// The joint and the section do not overlap (touching at most).
    Outside,
}

/// Coverage of the section (convex, counter-clockwise about the plane's normal).
pub(crate) fn coverage(shape: &JointShape, plane: &Plane, section: &[DVec3], eps: f64) -> Coverage {
    let frame = Frame2::new(plane);
    let s: Vec<[f64; 2]> = section.iter().map(|&p| frame.project(p)).collect();
    match shape {
        JointShape::Infinite => Coverage::Whole,
        JointShape::Disc { center, radius } => disc(frame.project(*center), *radius, &s, eps),
        JointShape::Polygon { vertices } => {
            let p: Vec<[f64; 2]> = vertices.iter().map(|&v| frame.project(v)).collect();
            polygon(&p, &s, eps)
        }
    }
}

/// The sides of the regular polygon that stands for a disc with bridges.
pub(crate) const DISC_SEGMENTS: usize = 32;

/// The outline of a finite joint with bridges, a convex polygon on its plane (`None` for an
/// infinite joint): a polygon's vertices; for a disc of radius `r`, the regular polygon of
/// [`DISC_SEGMENTS`] sides whose area is the disc's, `π r²` (circumradius
/// `r sqrt(2π / (N sin(2π/N)))`), so that the bridge and joint areas are the disc's.
pub(crate) fn outline(shape: &JointShape, plane: &Plane) -> Option<Vec<DVec3>> {
    match shape {
        JointShape::Infinite => None,
        JointShape::Polygon { vertices } => Some(vertices.clone()),
        JointShape::Disc { center, radius } => {
            let frame = Frame2::new(plane);
            let n = DISC_SEGMENTS as f64;
            let step = std::f64::consts::TAU / n;
            let circumradius = radius * (std::f64::consts::TAU / (n * step.sin())).sqrt();
            let vertices = (0..DISC_SEGMENTS)
                .map(|k| {
                    let (s, c) = (k as f64 * step).sin_cos();
                    *center + (frame.u * c + frame.w * s) * circumradius
                })
                .collect();
            Some(vertices)
        }
    }
}

/// The seams of an outline: per edge, the plane through it perpendicular to `plane`, its
/// normal pointing away from the outline.
pub(crate) fn seams(outline: &[DVec3], plane: &Plane) -> Vec<Plane> {
    let centre = outline.iter().fold(DVec3::ZERO, |s, &p| s + p) / outline.len().max(1) as f64;
    (0..outline.len())
        .filter_map(|k| {
            let (a, b) = (outline[k], outline[(k + 1) % outline.len()]);
            let mut normal = (b - a).cross(plane.normal).normalize_or_zero();
            if normal == DVec3::ZERO {
                return None;
            }
            if normal.dot(centre - a) > 0.0 {
                normal = -normal;
            }
            Some(Plane { normal, point: a })
        })
        .collect()
}

struct Frame2 {
    origin: DVec3,
    u: DVec3,
    w: DVec3,
}

impl Frame2 {
    fn new(plane: &Plane) -> Frame2 {
        let u = plane.normal.any_orthonormal_vector();
        Frame2 {
            origin: plane.point,
            u,
            w: plane.normal.cross(u),
        }
    }

    fn project(&self, p: DVec3) -> [f64; 2] {
        let d = p - self.origin;
        [d.dot(self.u), d.dot(self.w)]
    }
}

fn disc(c: [f64; 2], r: f64, section: &[[f64; 2]], eps: f64) -> Coverage {
    if section.iter().all(|&p| dist(p, c) <= r + eps) {
        Coverage::Whole
    } else if distance_to_polygon(c, section) >= r - eps {
        Coverage::Outside
    } else {
        Coverage::Partial
    }
}

fn polygon(joint: &[[f64; 2]], section: &[[f64; 2]], eps: f64) -> Coverage {
    let inside = |p: [f64; 2]| edges(joint).all(|(a, b)| left_distance(a, b, p) >= -eps);
    if section.iter().all(|&p| inside(p)) {
        Coverage::Whole
    } else if separated(joint, section, eps) || separated(section, joint, eps) {
        Coverage::Outside
    } else {
        Coverage::Partial
    }
}

/// Whether an edge line of `a` has all of `b` on its outer side (within `eps`): the
/// separating-axis test for convex polygons, one direction.
fn separated(a: &[[f64; 2]], b: &[[f64; 2]], eps: f64) -> bool {
    edges(a).any(|(p, q)| b.iter().all(|&x| left_distance(p, q, x) <= eps))
}

fn edges(poly: &[[f64; 2]]) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
    (0..poly.len()).map(move |k| (poly[k], poly[(k + 1) % poly.len()]))
}

/// Signed distance of `x` to the line `a -> b`, positive on the left.
fn left_distance(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> f64 {
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let len = ex.hypot(ey);
    if len == 0.0 {
        return 0.0;
    }
    (ex * (x[1] - a[1]) - ey * (x[0] - a[0])) / len
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Distance from `c` to a convex polygon (zero inside).
fn distance_to_polygon(c: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    if edges(poly).all(|(a, b)| left_distance(a, b, c) >= 0.0) {
        return 0.0;
    }
    edges(poly)
        .map(|(a, b)| {
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            let len2 = ex * ex + ey * ey;
            let t = if len2 > 0.0 {
                (((c[0] - a[0]) * ex + (c[1] - a[1]) * ey) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            dist(c, [a[0] + t * ex, a[1] + t * ey])
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(h: f64) -> Vec<DVec3> {
        [[-h, -h], [h, -h], [h, h], [-h, h]]
            .iter()
            .map(|p| DVec3::new(p[0], p[1], 0.0))
            .collect()
    }

    fn horizontal() -> Plane {
        Plane {
            normal: DVec3::Z,
            point: DVec3::ZERO,
        }
    }

    #[test]
    fn disc_coverage() {
        let disc = |r| JointShape::Disc {
            center: DVec3::ZERO,
            radius: r,
        };
        let s = square(1.0);
        assert_eq!(
            coverage(&disc(1.5), &horizontal(), &s, 1e-12),
            Coverage::Whole
        );
        assert_eq!(
            coverage(&disc(2f64.sqrt()), &horizontal(), &s, 1e-12),
            Coverage::Whole
        );
        assert_eq!(
            coverage(&disc(1.0), &horizontal(), &s, 1e-12),
            Coverage::Partial
        );
        let far = JointShape::Disc {
            center: DVec3::new(3.0, 0.0, 0.0),
            radius: 2.0,
        };
        assert_eq!(coverage(&far, &horizontal(), &s, 1e-12), Coverage::Outside);
    }

    #[test]
    fn polygon_coverage() {
        let poly = |h: f64, dx: f64| JointShape::Polygon {
            vertices: square(h).iter().map(|p| *p + DVec3::X * dx).collect(),
        };
        let s = square(1.0);
        assert_eq!(
            coverage(&poly(1.0, 0.0), &horizontal(), &s, 1e-12),
            Coverage::Whole
        );
        assert_eq!(
            coverage(&poly(1.0, 1.0), &horizontal(), &s, 1e-12),
            Coverage::Partial
        );
        assert_eq!(
            coverage(&poly(1.0, 2.0), &horizontal(), &s, 1e-12),
            Coverage::Outside
        );
        assert_eq!(
            coverage(&poly(0.5, 0.0), &horizontal(), &s, 1e-12),
            Coverage::Partial
        );
    }
}
