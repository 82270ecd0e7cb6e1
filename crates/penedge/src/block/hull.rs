//! A block from the convex hull of points: an incremental hull in triangles, handed to
//! [`ConvexBlock::with_tolerance`], which merges the coplanar triangles into the block's
//! faces and validates the result as it does any vertices and faces.
//!
//! The points are added farthest first from the first tetrahedron's centre, so that the
//! hull's corners come before the points on its edges and faces, which then lie within the
//! length tolerance of a face and are left out (a hull vertex is a corner, never a point
//! in the middle of an edge or face). Work: O(n · f) for n points and f hull triangles.

use super::build::{check_points, check_range};
use super::{BlockError, ConvexBlock};
use crate::geometry::{Aabb, DVec3};
use crate::tolerance::Tolerance;
use std::collections::HashSet;

/// A hull triangle, counter-clockwise seen from outside, with its outward unit normal.
struct Triangle {
    corners: [usize; 3],
    normal: DVec3,
    alive: bool,
}

impl Triangle {
    fn new(points: &[DVec3], corners: [usize; 3]) -> Self {
        let [a, b, c] = corners.map(|i| points[i]);
        Triangle {
            corners,
            normal: (b - a).cross(c - a).normalize_or_zero(),
            alive: true,
        }
    }

    /// The signed distance of `p` from the triangle's plane (positive outside).
    fn height(&self, points: &[DVec3], p: DVec3) -> f64 {
        self.normal.dot(p - points[self.corners[0]])
    }
}

/// The index among `candidates` of the point farthest by `distance`, with that distance.
fn farthest(candidates: &[usize], distance: impl Fn(usize) -> f64) -> (usize, f64) {
    candidates.iter().map(|&i| (i, distance(i))).fold(
        (candidates[0], f64::NEG_INFINITY),
        |best, c| {
            if c.1 > best.1 {
                c
            } else {
                best
            }
        },
    )
}

impl ConvexBlock {
    /// The convex hull of `points` with the default [`Tolerance`]; see
    /// [`ConvexBlock::hull_with_tolerance`].
    pub fn hull(points: &[[f64; 3]]) -> Result<ConvexBlock, BlockError> {
        ConvexBlock::hull_with_tolerance(points, &Tolerance::default())
    }

    /// The convex hull of `points`: its vertices are the corners among them (points inside,
    /// on a face or an edge, or within `tol.length()` x size of another are left out), in the
    /// order given. Fewer than 4 points, or points all within the length tolerance of one
    /// plane, are [`BlockError::TooSmall`] and [`BlockError::ZeroVolume`].
    pub fn hull_with_tolerance(
        points: &[[f64; 3]],
        tol: &Tolerance,
    ) -> Result<ConvexBlock, BlockError> {
        let (p, triangles, _) = incremental_hull(points, tol)?;
        // The corners, in the order given, and the triangles in their numbering.
        let mut used = vec![false; p.len()];
        for t in triangles.iter().filter(|t| t.alive) {
            t.corners.iter().for_each(|&i| used[i] = true);
        }
        let mut new_index = vec![usize::MAX; p.len()];
        let mut vertices = Vec::new();
        for (i, _) in used.iter().enumerate().filter(|(_, u)| **u) {
            new_index[i] = vertices.len();
            vertices.push(points[i]);
        }
        let faces: Vec<[usize; 3]> = triangles
            .iter()
            .filter(|t| t.alive)
            .map(|t| t.corners.map(|i| new_index[i]))
            .collect();
        ConvexBlock::with_tolerance(&vertices, &faces, tol)
    }
}

/// The hull's triangles (alive ones only) of `points` checked, with the points and the
/// first tetrahedron's centre.
fn incremental_hull(
    points: &[[f64; 3]],
    tol: &Tolerance,
) -> Result<(Vec<DVec3>, Vec<Triangle>, DVec3), BlockError> {
    let p = check_points(points)?;
    check_range(&p)?;
    if p.len() < 4 {
        return Err(BlockError::TooSmall {
            vertices: p.len(),
            faces: 0,
        });
    }
    let eps = tol.for_box(&Aabb::of_points(&p)).length;
    let mut triangles = first_tetrahedron(&p, eps)?;
    let centre = triangles
        .iter()
        .flat_map(|t| t.corners)
        .map(|i| p[i])
        .sum::<DVec3>()
        / 12.0;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by(|&a, &b| p[b].distance(centre).total_cmp(&p[a].distance(centre)));
    for i in order {
        add_point(&p, &mut triangles, i, eps);
    }
    Ok((p, triangles, centre))
}

/// The volume and surface area of the convex hull of `points`, summed over the hull's
/// triangles (the incremental hull of [`ConvexBlock::hull_with_tolerance`], points within
/// `tol`'s length threshold of the hull left out). Unlike a hull block, it does not need the
/// hull's vertices to be corners: a point left on an edge or in a face (the parts of a
/// concave block share many) changes neither. Errors as the hull block's, and
/// [`BlockError::OpenSurface`] should the triangles not close (never seen; checked so that
/// a wrong volume is never returned).
pub(crate) fn hull_volume_and_area(
    points: &[[f64; 3]],
    tol: &Tolerance,
) -> Result<(f64, f64), BlockError> {
    let (p, triangles, centre) = incremental_hull(points, tol)?;
    // Closed: each directed edge once, and its reverse once.
    let mut edges = HashSet::new();
    for t in &triangles {
        let [a, b, c] = t.corners;
        for e in [(a, b), (b, c), (c, a)] {
            if !edges.insert(e) {
                return Err(BlockError::NonManifoldEdge {
                    first: e.0,
                    second: e.1,
                });
            }
        }
    }
    // The first open edge in the triangles' order (never the set's, which is random).
    let open = triangles.iter().find_map(|t| {
        let [a, b, c] = t.corners;
        [(a, b), (b, c), (c, a)]
            .into_iter()
            .find(|&(a, b)| !edges.contains(&(b, a)))
    });
    if let Some((first, second)) = open {
        return Err(BlockError::OpenSurface { first, second });
    }
    let (mut volume, mut area) = (0.0, 0.0);
    for t in &triangles {
        let [a, b, c] = t.corners.map(|i| p[i] - centre);
        let n = a.cross(b) + b.cross(c) + c.cross(a);
        volume += a.dot(b.cross(c)) / 6.0;
        area += n.length() / 2.0;
    }
    Ok((volume, area))
}

/// A tetrahedron of four of the points, as far apart as a quick search finds (two extremes
/// along an axis, the farthest from their line, the farthest from their plane), its faces
/// outward.
fn first_tetrahedron(p: &[DVec3], eps: f64) -> Result<Vec<Triangle>, BlockError> {
    let all: Vec<usize> = (0..p.len()).collect();
    // The axis of the bounding box's longest side: its two extreme points.
    let aabb = Aabb::of_points(p);
    let axis = (aabb.max - aabb.min).max_position();
    let (a, _) = farthest(&all, |i| -p[i][axis]);
    let (b, _) = farthest(&all, |i| p[i][axis]);
    let line = (p[b] - p[a]).normalize_or_zero();
    let (c, off_line) = farthest(&all, |i| {
        (p[i] - p[a]).reject_from_normalized(line).length()
    });
    let normal = line.cross(p[c] - p[a]).normalize_or_zero();
    let (d, off_plane) = farthest(&all, |i| normal.dot(p[i] - p[a]).abs());
    if off_line.partial_cmp(&eps) != Some(std::cmp::Ordering::Greater)
        || off_plane.partial_cmp(&eps) != Some(std::cmp::Ordering::Greater)
    {
        return Err(BlockError::ZeroVolume);
    }
    // Faces outward: d is below the face (a, b, c) when the normal points away from it.
    let (b, c) = if normal.dot(p[d] - p[a]) > 0.0 {
        (c, b)
    } else {
        (b, c)
    };
    Ok([[a, b, c], [a, d, b], [b, d, c], [c, d, a]]
        .into_iter()
        .map(|corners| Triangle::new(p, corners))
        .collect())
}

/// Adds point `i` to the hull: the triangles that it sees (more than `eps` above) go, and
/// their horizon (the edges between a seen and an unseen triangle) is joined to it.
fn add_point(p: &[DVec3], triangles: &mut Vec<Triangle>, i: usize, eps: f64) {
    let mut seen_edges: HashSet<(usize, usize)> = HashSet::new();
    let mut seen = Vec::new();
    for (k, t) in triangles.iter().enumerate() {
        if t.alive && t.height(p, p[i]) > eps {
            seen.push(k);
            let [a, b, c] = t.corners;
            seen_edges.extend([(a, b), (b, c), (c, a)]);
        }
    }
    if seen.is_empty() {
        return; // inside, or on the hull within the tolerance
    }
    for &k in &seen {
        triangles[k].alive = false;
    }
    // The horizon in the seen triangles' order and each one's corner order, never in the
    // set's (random, per process and per set) order: the hull is the same, triangle for
    // triangle and bit for bit, at every call.
    let horizon: Vec<(usize, usize)> = seen
        .iter()
        .flat_map(|&k| {
            let [a, b, c] = triangles[k].corners;
            [(a, b), (b, c), (c, a)]
        })
        .filter(|&(a, b)| !seen_edges.contains(&(b, a)))
        .collect();
    for (a, b) in horizon {
        triangles.push(Triangle::new(p, [a, b, i]));
    }
    triangles.retain(|t| t.alive);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible sequence in [0, 1) (a linear congruential generator).
    fn uniform(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn the_hull_of_a_cube_with_inner_edge_and_face_points_is_the_cube() {
        let mut points = Vec::new();
        for k in 0..27 {
            // The 3x3x3 lattice of a 2 m cube: corners, edge midpoints, face centres, centre.
            let (x, y, z) = ((k % 3) as f64, ((k / 3) % 3) as f64, (k / 9) as f64);
            points.push([x, y, z]);
        }
        let cube = ConvexBlock::hull(&points).expect("a cube");
        assert_eq!(cube.vertices().len(), 8);
        assert_eq!(cube.n_faces(), 6);
        assert_eq!(cube.edges().len(), 12);
        assert!((cube.volume() - 8.0).abs() < 1e-12);
        assert!(cube.centroid().distance(DVec3::splat(1.0)) < 1e-12);
        // The corners in the order given: the lattice's corners are points 0, 2, 6, 8, ...
        let corners: Vec<[f64; 3]> = cube.vertices().iter().map(|v| v.to_array()).collect();
        let expected: Vec<[f64; 3]> = [0, 2, 6, 8, 18, 20, 24, 26]
            .iter()
            .map(|&k| points[k])
            .collect();
        assert_eq!(corners, expected);
    }

    #[test]
    fn random_points_on_a_sphere_all_become_vertices_and_the_rest_stay_inside() {
        // Points on the unit sphere are all corners of their hull; points inside it are
        // none. Every hull vertex is one of the points, every point is inside every face
        // plane, and the volume is below the ball's.
        let mut seed = 2004;
        let mut points = Vec::new();
        for _ in 0..200 {
            let z = 2.0 * uniform(&mut seed) - 1.0;
            let phi = std::f64::consts::TAU * uniform(&mut seed);
            let r = (1.0 - z * z).sqrt();
            points.push([r * phi.cos(), r * phi.sin(), z]);
        }
        for _ in 0..300 {
            let v = [0.0; 3].map(|_| 1.1 * uniform(&mut seed) - 0.55);
            points.push(v);
        }
        let ball = ConvexBlock::hull(&points).expect("a hull");
        assert_eq!(ball.vertices().len(), 200);
        for v in ball.vertices() {
            assert!(points[..200].contains(&v.to_array()));
        }
        for q in &points {
            for plane in ball.planes() {
                assert!(plane.distance(DVec3::from_array(*q)) < 1e-9);
            }
        }
        assert!(ball.volume() < 4.0 / 3.0 * std::f64::consts::PI);
        assert!(ball.volume() > 3.5);
        // Each face of a hull of points in general position is a triangle: V - E + F = 2
        // with 3F = 2E.
        assert_eq!(ball.n_faces(), 2 * 200 - 4);
    }

    #[test]
    fn the_hull_volume_of_an_l_shape_with_points_on_its_hull_edges() {
        // The vertices of an L-block's two boxes (the floor [0,3]x[0,1]x[0,1], the column
        // [0,1]x[0,1]x[1,3]): (0,y,1) lies on the hull's edge, (1,y,1) inside. The hull is
        // the 3 x 3 profile less the triangle (1,3) (3,1) (3,3): area 7, 1 deep; its surface
        // 2 x 7 + the profile's perimeter 3 + 1 + 2 sqrt(2) + 1 + 3 (times 1).
        let mut points = Vec::new();
        for (lo, hi) in [
            ([0.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
            ([0.0, 0.0, 1.0], [1.0, 1.0, 3.0]),
        ] {
            for k in 0..8 {
                let pick = |d: usize| if k >> d & 1 == 1 { hi[d] } else { lo[d] };
                points.push([pick(0), pick(1), pick(2)]);
            }
        }
        let (volume, area) = hull_volume_and_area(&points, &Tolerance::default()).unwrap();
        assert!((volume - 7.0).abs() < 1e-12, "{volume}");
        let expected = 14.0 + 8.0 + 2.0 * 2f64.sqrt();
        assert!((area - expected).abs() < 1e-12, "{area}");
    }

    #[test]
    fn the_hull_is_the_same_at_every_call_bit_for_bit() {
        // The horizon was taken in a hash set's order, which differs between two sets of
        // one process: the faces' order and the last bits of the volume changed per call.
        let mut seed = 7;
        for round in 0..10 {
            let points: Vec<[f64; 3]> = (0..40 + 10 * round)
                .map(|_| {
                    let u = [uniform(&mut seed), uniform(&mut seed), uniform(&mut seed)];
                    u.map(|x| 2.0 * x - 1.0)
                })
                .collect();
            let first = ConvexBlock::hull(&points).expect("a hull");
            let tol = Tolerance::default();
            let measures = hull_volume_and_area(&points, &tol).expect("a hull");
            for _ in 0..5 {
                let again = ConvexBlock::hull(&points).expect("a hull");
                assert_eq!(again.vertices(), first.vertices());
                assert!(again.faces().eq(first.faces()));
                assert_eq!(again.volume().to_bits(), first.volume().to_bits());
                assert_eq!(again.centroid(), first.centroid());
                let (volume, area) = hull_volume_and_area(&points, &tol).expect("a hull");
                assert_eq!(
                    (volume.to_bits(), area.to_bits()),
                    (measures.0.to_bits(), measures.1.to_bits())
                );
            }
        }
    }

    #[test]
    fn flat_or_too_few_points_are_errors() {
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(ConvexBlock::hull(&square), Err(BlockError::ZeroVolume));
        let line = [
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0],
            [2.0, 2.0, 2.0],
            [3.0, 3.0, 3.0],
        ];
        assert_eq!(ConvexBlock::hull(&line), Err(BlockError::ZeroVolume));
        assert_eq!(
            ConvexBlock::hull(&square[..3]),
            Err(BlockError::TooSmall {
                vertices: 3,
                faces: 0
            })
        );
        let nan = [
            [f64::NAN, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert_eq!(
            ConvexBlock::hull(&nan),
            Err(BlockError::NonFiniteVertex { vertex: 0 })
        );
    }
}
