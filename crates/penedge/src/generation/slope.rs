//! Slopes: the air above a profile (crest, benches, toe) extruded along a horizontal strike
//! (see `docs/generation.md`, "Slopes and topography").
//!
//! The air above a polyline `v(u)` is a union of convex pieces: above each segment, the
//! column up to a level above the rock is a convex quadrilateral, and neighbouring columns
//! are merged while their union stays convex (across a valley of the profile, not across a
//! crest). Each piece swept along the strike, past the rock at both ends, is a convex
//! region; the regions share their vertical sides and do not overlap, so the rock left is
//! exactly the rock below the profile.
//!
//! A slope and a topographic surface are bounded by the rock they cut (the air must reach
//! above it and past its sides): [`Extent`] is what they need of it.

use super::error::{Problem, SpecError};
use super::excavation::cross;
use crate::block::ConvexBlock;
use crate::geometry::{Aabb, DVec3};

/// The most vertices of a slope's profile.
pub const MAX_PROFILE_VERTICES: usize = 100_000;

/// What a slope or a topographic surface needs of the rock: its bounding box and its
/// horizontal footprint (the convex hull of its vertices seen from above, counter-clockwise).
#[derive(Clone, Debug)]
pub(crate) struct Extent {
    pub(crate) aabb: Aabb,
    pub(crate) footprint: Vec<[f64; 2]>,
}

impl Extent {
    /// The extent of some blocks (`None` when there are none).
    pub(crate) fn of(blocks: &[ConvexBlock]) -> Option<Extent> {
        let points: Vec<DVec3> = blocks
            .iter()
            .flat_map(|b| b.vertices().iter().copied())
            .collect();
        if points.is_empty() {
            return None;
        }
        let aabb = Aabb::of_points(&points);
        let flat: Vec<[f64; 2]> = points.iter().map(|p| [p.x, p.y]).collect();
        Some(Extent {
            aabb,
            footprint: convex_hull(flat),
        })
    }

    /// A length beyond which the air reaches past the rock: 1 % of its size.
    pub(crate) fn margin(&self) -> f64 {
        0.01 * self.aabb.diagonal().max(f64::MIN_POSITIVE)
    }
}

/// The convex hull of points in the plane, counter-clockwise, without collinear vertices
/// (Andrew's monotone chain).
pub(crate) fn convex_hull(mut p: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let points: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in points {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// Where a sweep along the strike starts, its length, and the convex pieces swept.
pub(super) type Sweep = (DVec3, f64, Vec<Vec<[f64; 2]>>);

/// A slope's convex pieces in the profile's `(u, v)` (counter-clockwise), and where the
/// sweep along the strike `d` starts and how long it is, for the rock's `extent`.
/// `origin` is the profile's origin; `u` its horizontal axis. Errors name `field` (the
/// profile's vertices).
pub(super) fn pieces(
    field: &str,
    vertices: &[[f64; 2]],
    origin: DVec3,
    d: DVec3,
    u: DVec3,
    extent: &Extent,
) -> Result<Sweep, SpecError> {
    let bad = |msg: String| SpecError::new(field, Problem::Invalid(msg));
    let profile = monotone(field, vertices)?;
    // The rock's range along u, v (= z) and the strike, from its box's corners.
    let corners: Vec<DVec3> = (0..8)
        .map(|k| {
            let pick = |bit: usize, lo: f64, hi: f64| if k >> bit & 1 == 0 { lo } else { hi };
            let (lo, hi) = (extent.aabb.min, extent.aabb.max);
            DVec3::new(
                pick(0, lo.x, hi.x),
                pick(1, lo.y, hi.y),
                pick(2, lo.z, hi.z),
            )
        })
        .collect();
    let range = |axis: DVec3| {
        corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                let t = axis.dot(*c - origin);
                (a.min(t), b.max(t))
            })
    };
    let (u_lo, u_hi) = range(u);
    let (t_lo, t_hi) = range(d);
    let (bottom, top) = (extent.aabb.min.z - origin.z, extent.aabb.max.z - origin.z);
    let margin = extent.margin();
    // Extended horizontally to the rock's edges.
    let mut line = Vec::with_capacity(profile.len() + 2);
    if profile[0][0] > u_lo - margin {
        line.push([u_lo - margin, profile[0][1]]);
    }
    line.extend_from_slice(&profile);
    let last = profile[profile.len() - 1];
    if last[0] < u_hi + margin {
        line.push([u_hi + margin, last[1]]);
    }
    // The profile's lowest and highest points over the rock.
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..line.len() - 1 {
        let (p, q) = (line[k], line[k + 1]);
        let (a, b) = (p[0].max(u_lo), q[0].min(u_hi));
        if a > b {
            continue;
        }
        let at = |x: f64| p[1] + (q[1] - p[1]) * (x - p[0]) / (q[0] - p[0]);
        for v in [at(a), at(b)] {
            low = low.min(v);
            high = high.max(v);
        }
    }
    if low >= top {
        return Err(bad(format!(
            "the profile lies entirely above the rock (its lowest point over the rock is at \
             z = {}, the rock's top at z = {}): it removes nothing",
            low + origin.z,
            top + origin.z
        )));
    }
    if high <= bottom {
        return Err(bad(format!(
            "the profile lies entirely below the rock (its highest point over the rock is at \
             z = {}, the rock's bottom at z = {}): it would remove all of it",
            high + origin.z,
            bottom + origin.z
        )));
    }
    let lid = top.max(line.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p[1]))) + margin;
    let pieces = columns(&line, lid);
    let start = origin + d * (t_lo - margin);
    Ok((start, t_hi - t_lo + 2.0 * margin, pieces))
}

/// The profile's vertices, checked (finite, at least 2, `u` strictly one way), in order
/// of increasing `u`.
fn monotone(field: &str, vertices: &[[f64; 2]]) -> Result<Vec<[f64; 2]>, SpecError> {
    let bad = |msg: String| Err(SpecError::new(field, Problem::Invalid(msg)));
    if vertices.len() < 2 {
        return bad(format!(
            "a slope's profile needs at least 2 vertices, got {}",
            vertices.len()
        ));
    }
    if vertices.len() > MAX_PROFILE_VERTICES {
        return bad(format!(
            "a slope's profile may have at most {MAX_PROFILE_VERTICES} vertices, got {}",
            vertices.len()
        ));
    }
    for p in vertices {
        for x in p {
            super::check::finite(field, *x)?;
        }
    }
    let sense = if vertices[1][0] < vertices[0][0] {
        -1.0
    } else {
        1.0
    };
    for k in 1..vertices.len() {
        let (p, q) = (vertices[k - 1], vertices[k]);
        if (q[0] - p[0]) * sense <= 0.0 {
            return bad(format!(
                "the profile must go one way along u (the horizontal coordinate across the \
                 strike), as the ground seen in section does: vertex {k} at u = {} is not \
                 past vertex {} at u = {} (an overhang or a vertical step: make a vertical \
                 face slightly inclined)",
                q[0],
                k - 1,
                p[0]
            ));
        }
    }
    let mut v = vertices.to_vec();
    if sense < 0.0 {
        v.reverse();
    }
    Ok(v)
}

/// The air above a polyline `line` (increasing `u`) up to `v = lid`, as convex pieces: the
/// column above each run of segments that turns left (a valley) or goes straight; a crest
/// (a right turn) starts a new column.
fn columns(line: &[[f64; 2]], lid: f64) -> Vec<Vec<[f64; 2]>> {
    let scale = line
        .iter()
        .fold(lid.abs(), |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let close = |chain: Vec<[f64; 2]>| {
        let (first, last) = (chain[0], chain[chain.len() - 1]);
        let mut piece = chain;
        piece.extend([[last[0], lid], [first[0], lid]]);
        piece
    };
    let mut pieces = Vec::new();
    let mut chain = vec![line[0], line[1]];
    for &q in &line[2..] {
        let n = chain.len();
        let turn = cross(chain[n - 2], chain[n - 1], q);
        if turn.abs() <= 1e-12 * scale * scale {
            chain[n - 1] = q; // straight on: one edge, not two on one line
        } else if turn > 0.0 {
            chain.push(q);
        } else {
            let next = vec![chain[n - 1], q];
            pieces.push(close(std::mem::replace(&mut chain, next)));
        }
    }
    pieces.push(close(chain));
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generation::excavation::signed_area;

    #[test]
    fn the_columns_of_a_benched_profile_fill_the_air_above_it() {
        // Crest at v = 10 up to u = 0, face down to a bench at v = 5 (u = 5..8), face down
        // to the toe at v = 0 from u = 13.
        let line = [
            [-5.0, 10.0],
            [0.0, 10.0],
            [5.0, 5.0],
            [8.0, 5.0],
            [13.0, 0.0],
            [20.0, 0.0],
        ];
        let pieces = columns(&line, 12.0);
        // Crests at u = 0 and u = 8 split; the valleys at u = 5 and 13 merge.
        assert_eq!(pieces.len(), 3);
        assert!(pieces
            .iter()
            .all(|p| super::super::excavation::is_convex(p)));
        // Exact air: 25 x 12 minus the rock below the line (trapezoids).
        let rock = 5.0 * 10.0 + 5.0 * 7.5 + 3.0 * 5.0 + 5.0 * 2.5 + 7.0 * 0.0;
        let air: f64 = pieces.iter().map(|p| signed_area(p)).sum();
        assert!((air - (25.0 * 12.0 - rock)).abs() < 1e-12, "{air}");
    }

    #[test]
    fn a_profile_that_goes_back_is_an_error_naming_the_vertex() {
        let e = monotone("s.vertices", &[[0.0, 1.0], [2.0, 1.0], [1.0, 0.0]]).unwrap_err();
        assert_eq!(e.field, "s.vertices");
        assert!(e.to_string().contains("vertex 2 at u = 1"), "{e}");
        // Given in decreasing u: the same check, the index as given.
        let e = monotone("s", &[[3.0, 1.0], [2.0, 1.0], [2.0, 0.0]]).unwrap_err();
        assert!(e.to_string().contains("vertex 2 at u = 2"), "{e}");
        assert!(monotone("s", &[[1.0, 0.0]]).is_err());
        assert!(monotone("s", &[[1.0, 0.0], [f64::NAN, 1.0]]).is_err());
        assert_eq!(
            monotone("s", &[[2.0, 0.0], [1.0, 1.0]]).unwrap(),
            vec![[1.0, 1.0], [2.0, 0.0]]
        );
    }

    #[test]
    fn the_hull_of_a_square_with_inner_and_edge_points_is_its_corners() {
        let p = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [1.0, 1.0],
            [0.0, 2.0],
            [0.0, 2.0],
        ];
        let h = convex_hull(p);
        assert_eq!(h, vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
    }
}
