//! Building a [`ConvexBlock`] from half-spaces `n · x <= d`.
//!
//! The vertices are the points where three planes meet and no half-space is violated; the
//! faces are the planes that carry three vertices or more. Work grows with the cube of the
//! number of planes, which suits blocks (a few dozen planes), not arbitrary polytopes.

use super::{BlockError, ConvexBlock};
use crate::geometry::{Aabb, DVec3, Plane};
use crate::tolerance::Tolerance;

impl ConvexBlock {
    /// The block `{x : normals[i] · x <= offsets[i] for all i}`, with the default tolerance.
    ///
    /// Normals need not be unit vectors. Redundant half-spaces are allowed (they carry no face).
    /// At most [`super::MAX_HALFSPACES`] half-spaces.
    pub fn from_planes(normals: &[[f64; 3]], offsets: &[f64]) -> Result<ConvexBlock, BlockError> {
        ConvexBlock::from_planes_with_tolerance(normals, offsets, &Tolerance::default())
    }

    /// [`ConvexBlock::from_planes`] with a given tolerance.
    pub fn from_planes_with_tolerance(
        normals: &[[f64; 3]],
        offsets: &[f64],
        tol: &Tolerance,
    ) -> Result<ConvexBlock, BlockError> {
        if normals.len() > super::MAX_HALFSPACES {
            return Err(BlockError::TooManyPlanes {
                count: normals.len(),
                limit: super::MAX_HALFSPACES,
            });
        }
        let planes = unit_planes(normals, offsets)?;
        if planes.len() < 4 {
            return Err(BlockError::Unbounded {
                reason: "fewer than 4 half-spaces",
            });
        }
        let candidates = triple_points(&planes);
        // Feasible corners, within the policy's length threshold of every half-space. The
        // threshold needs the block's size, known only from the corners: a first pass at the
        // magnitude of the planes' offsets (the coordinates' magnitude, never polluted by the
        // far corner of three nearly dependent planes) gives the box, the second the
        // threshold at the block's own scale, the one the block is validated with.
        let magnitude = planes
            .iter()
            .map(|p| p.normal.dot(p.point).abs())
            .fold(0.0, f64::max);
        let rough = tol.at_scale(magnitude, magnitude).length;
        let within = |points: &[DVec3], eps: f64| -> Vec<DVec3> {
            let inside = |p: &&DVec3| planes.iter().all(|pl| pl.distance(**p) <= eps);
            points.iter().filter(inside).copied().collect()
        };
        let near = within(&candidates, rough);
        let feasible = match near.len() {
            0..=3 => near,
            _ => within(&near, tol.for_box(&Aabb::of_points(&near)).length),
        };
        if feasible.len() < 4 {
            return Err(BlockError::Unbounded {
                reason: "the half-spaces meet in fewer than 4 corners",
            });
        }
        let eps = tol.for_box(&Aabb::of_points(&feasible)).length;
        let vertices = dedupe(feasible, eps);
        let faces = face_loops(&planes, &vertices, eps);
        let coords: Vec<[f64; 3]> = vertices.iter().map(|p| p.to_array()).collect();
        ConvexBlock::with_tolerance(&coords, &faces, tol).map_err(|e| match e {
            BlockError::OpenSurface { .. }
            | BlockError::NotASphere { .. }
            | BlockError::TooSmall { .. } => BlockError::Unbounded {
                reason: "the corners found do not close a surface",
            },
            other => other,
        })
    }
}

fn unit_planes(normals: &[[f64; 3]], offsets: &[f64]) -> Result<Vec<Plane>, BlockError> {
    if normals.len() != offsets.len() {
        return Err(BlockError::PlaneCount {
            normals: normals.len(),
            offsets: offsets.len(),
        });
    }
    normals
        .iter()
        .zip(offsets)
        .enumerate()
        .map(|(i, (n, &d))| {
            // Divided by its largest component first, so that the length neither overflows
            // (a normal of 1e200) nor underflows (1e-200): only the direction counts.
            let n = DVec3::from_array(*n);
            let big = n.abs().max_element();
            let len = (n / big).length();
            if !(n.is_finite() && big > 0.0 && d.is_finite()) {
                return Err(BlockError::DegeneratePlane { plane: i });
            }
            let normal = n / big / len;
            Ok(Plane {
                normal,
                point: normal * (d / big / len),
            })
        })
        .collect()
}

fn triple_points(planes: &[Plane]) -> Vec<DVec3> {
    let mut points = Vec::new();
    let m = planes.len();
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                if let Some(p) = meet(&planes[i], &planes[j], &planes[k]) {
                    points.push(p);
                }
            }
        }
    }
    points
}

/// The point where three planes meet, if they are independent.
fn meet(a: &Plane, b: &Plane, c: &Plane) -> Option<DVec3> {
    let (na, nb, nc) = (a.normal, b.normal, c.normal);
    let det = na.dot(nb.cross(nc));
    if det.abs() < 1e-12 {
        return None;
    }
    let (da, db, dc) = (na.dot(a.point), nb.dot(b.point), nc.dot(c.point));
    let p = (nb.cross(nc) * da + nc.cross(na) * db + na.cross(nb) * dc) / det;
    p.is_finite().then_some(p)
}

fn dedupe(points: Vec<DVec3>, eps: f64) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::new();
    for p in points {
        if !out.iter().any(|q| q.distance(p) <= eps) {
            out.push(p);
        }
    }
    out
}

/// For each plane carrying three vertices or more, its vertices counter-clockwise about the
/// outward normal.
fn face_loops(planes: &[Plane], vertices: &[DVec3], eps: f64) -> Vec<Vec<usize>> {
    let mut seen: Vec<Vec<usize>> = Vec::new();
    let mut faces = Vec::new();
    for plane in planes {
        let on: Vec<usize> = (0..vertices.len())
            .filter(|&v| plane.distance(vertices[v]).abs() <= eps)
            .collect();
        // Two half-spaces with the same plane carry one face.
        if on.len() < 3 || seen.contains(&on) {
            continue;
        }
        seen.push(on.clone());
        faces.push(sort_ccw(vertices, on, plane.normal));
    }
    faces
}

/// Sorts points of a convex planar polygon counter-clockwise about `normal`.
fn sort_ccw(vertices: &[DVec3], mut ids: Vec<usize>, normal: DVec3) -> Vec<usize> {
    let centre = ids.iter().map(|&v| vertices[v]).sum::<DVec3>() / ids.len() as f64;
    let u = (vertices[ids[0]] - centre).normalize_or_zero();
    let w = normal.cross(u);
    let angle = |v: usize| {
        let d = vertices[v] - centre;
        d.dot(w).atan2(d.dot(u))
    };
    ids.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    ids
}
