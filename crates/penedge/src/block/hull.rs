//! A block from the convex hull of points: an incremental hull in triangles, handed to
//! [`ConvexBlock::with_tolerance`], which merges the coplanar triangles into the block's
//! faces and validates the result as it does any vertices and faces.
//!
//! Two questions, two rules. *Which points become vertices* is a question of the tolerance:
//! a point is added only when it lies more than the length threshold above a triangle of
//! the hull so far, so that points on (or within the threshold of) a face, an edge or another
//! point are left out, and the points are added farthest first from the first
//! tetrahedron's centre, so that the hull's corners come before the points on its edges and
//! faces. *Which triangles a point added replaces* is exact: all the triangles whose plane
//! has the point strictly above it (Shewchuk's adaptive `orient3d`, the `robust` crate),
//! found by walking from the one it was found above. The triangles are then exactly the
//! convex hull of the vertices chosen: every vertex is on or below every triangle's plane,
//! however dense the cloud. (Until 2026-11-29 the replaced triangles were those the point
//! was more than the threshold above: a point within it of a neighbouring triangle left a
//! fold of up to the threshold there, such folds added up over thousands of points, and
//! some 6,400 random points on a sphere were refused as "not convex" by 5e-9.)
//!
//! Each point waits in the list of one triangle it is above (a conflict list); when that
//! triangle goes, its points move to the new triangles (or to the horizon's neighbours),
//! or are dropped as within the threshold of the hull. Work: about O(n log n) for n points
//! in general position (each addition touches the triangles it replaces and their points).

use super::build::{check_points, check_range};
use super::{BlockError, ConvexBlock};
use crate::geometry::{Aabb, DVec3};
use crate::tolerance::Tolerance;
use std::collections::{HashMap, HashSet};

/// No triangle (a point inside the hull, or one already added).
const NONE: usize = usize::MAX;

/// A hull triangle, counter-clockwise seen from outside, with its outward unit normal.
struct Triangle {
    corners: [usize; 3],
    normal: DVec3,
    /// The triangle across each edge (`corners[k]`, `corners[k + 1]`).
    neighbours: [usize; 3],
    /// The points waiting to be added that lie more than the threshold above it.
    outside: Vec<usize>,
    alive: bool,
}

impl Triangle {
    fn new(points: &[DVec3], corners: [usize; 3], neighbours: [usize; 3]) -> Self {
        let [a, b, c] = corners.map(|i| points[i]);
        Triangle {
            corners,
            normal: (b - a).cross(c - a).normalize_or_zero(),
            neighbours,
            outside: Vec::new(),
            alive: true,
        }
    }

    /// The signed distance of `p` from the triangle's plane (positive outside).
    fn height(&self, points: &[DVec3], p: DVec3) -> f64 {
        self.normal.dot(p - points[self.corners[0]])
    }

    /// Whether `p` is strictly above (outside) the triangle's plane, exactly.
    fn sees(&self, points: &[DVec3], p: DVec3) -> bool {
        orient(points, self.corners, p) < 0.0
    }
}

/// Shewchuk's exact orientation of `p` against the plane of the triangle `corners`: negative
/// above it (the corners counter-clockwise seen from there), positive below, 0 in it.
fn orient(points: &[DVec3], corners: [usize; 3], p: DVec3) -> f64 {
    let c = |v: DVec3| robust::Coord3D {
        x: v.x,
        y: v.y,
        z: v.z,
    };
    let [a, b, d] = corners.map(|i| c(points[i]));
    robust::orient3d(a, b, d, c(p))
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
        // A vertex that is no corner at the tolerance (one whose triangles make fewer than
        // three faces: a point added before the corners that then put it in a face, within
        // the threshold of it) is left out and the hull made again without it. Each round
        // leaves out at least one point, so this ends; one round is the rule.
        let mut left_out = vec![false; points.len()];
        let (p, triangles) = loop {
            let (p, triangles, _) = incremental_hull_without(points, tol, &left_out)?;
            let eps = tol.for_box(&Aabb::of_points(&p)).length;
            let not_corners = not_corners(&p, &triangles, eps);
            if not_corners.is_empty() {
                break (p, triangles);
            }
            not_corners.into_iter().for_each(|v| left_out[v] = true);
        };
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
    incremental_hull_without(points, tol, &[])
}

/// Vertices of the hull `triangles` (alive ones) in fewer than three faces, the triangles
/// around each grouped as [`ConvexBlock::with_tolerance`] merges them (two triangles across
/// an edge are one face when each one's corners lie within `eps` of the other's plane); no
/// two of them neighbours (each is judged with its neighbours in place).
fn not_corners(p: &[DVec3], triangles: &[Triangle], eps: f64) -> Vec<usize> {
    let mut across: HashMap<(usize, usize), usize> = HashMap::with_capacity(3 * triangles.len());
    let mut fan: Vec<Vec<(usize, usize)>> = vec![Vec::new(); p.len()];
    for (t, triangle) in triangles.iter().enumerate() {
        let c = triangle.corners;
        for k in 0..3 {
            across.insert((c[k], c[(k + 1) % 3]), t);
            fan[c[k]].push((t, c[(k + 1) % 3]));
        }
    }
    let planes: Vec<(DVec3, DVec3)> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.corners.map(|i| p[i]);
            ((b - a).cross(c - a).normalize_or_zero(), (a + b + c) / 3.0)
        })
        .collect();
    let within = |t: usize, u: usize| {
        let (n, centre) = planes[t];
        triangles[u]
            .corners
            .iter()
            .all(|&i| n.dot(p[i] - centre).abs() <= eps)
    };
    let mut taken = vec![false; p.len()];
    let mut found = Vec::new();
    for v in 0..p.len() {
        if fan[v].is_empty() {
            continue;
        }
        // The edges from v across which the face changes.
        let breaks = fan[v]
            .iter()
            .filter(|&&(t, x)| {
                let u = across.get(&(x, v)).copied().unwrap_or(t);
                !(planes[t].0.dot(planes[u].0) > 0.0 && within(t, u) && within(u, t))
            })
            .count();
        if breaks < 3 && fan[v].iter().all(|&(_, x)| !taken[x]) {
            taken[v] = true;
            found.push(v);
        }
    }
    found
}

/// [`incremental_hull`] of the points not `left_out` (all when it is empty).
fn incremental_hull_without(
    points: &[[f64; 3]],
    tol: &Tolerance,
    left_out: &[bool],
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
    let kept = |i: usize| !left_out.get(i).copied().unwrap_or(false);
    let candidates: Vec<usize> = (0..p.len()).filter(|&i| kept(i)).collect();
    if candidates.len() < 4 {
        return Err(BlockError::TooSmall {
            vertices: candidates.len(),
            faces: 0,
        });
    }
    let triangles = first_tetrahedron(&p, &candidates, eps)?;
    let centre = triangles
        .iter()
        .flat_map(|t| t.corners)
        .map(|i| p[i])
        .sum::<DVec3>()
        / 12.0;
    let mut hull = Hull {
        p: &p,
        eps,
        triangles,
        waiting_on: vec![NONE; p.len()],
        seen_by: Vec::new(),
    };
    for &i in &candidates {
        hull.assign(i, &[0, 1, 2, 3]);
    }
    // The triangles in the order made, each until it goes or has no point above it: the
    // next point is the one most above it (new triangles come last, so this ends).
    let mut k = 0;
    while k < hull.triangles.len() {
        while hull.triangles[k].alive {
            let Some(i) = hull.take_farthest(k) else {
                break;
            };
            hull.add_point(i);
        }
        k += 1;
    }
    let mut triangles = hull.triangles;
    triangles.retain(|t| t.alive);
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
/// outward, each with its neighbours.
fn first_tetrahedron(p: &[DVec3], all: &[usize], eps: f64) -> Result<Vec<Triangle>, BlockError> {
    // The axis of the bounding box's longest side: its two extreme points.
    let aabb = Aabb::of_points(p);
    let axis = (aabb.max - aabb.min).max_position();
    let (a, _) = farthest(all, |i| -p[i][axis]);
    let (b, _) = farthest(all, |i| p[i][axis]);
    let line = (p[b] - p[a]).normalize_or_zero();
    let (c, off_line) = farthest(all, |i| (p[i] - p[a]).reject_from_normalized(line).length());
    let normal = line.cross(p[c] - p[a]).normalize_or_zero();
    let (d, off_plane) = farthest(all, |i| normal.dot(p[i] - p[a]).abs());
    let side = orient(p, [a, b, c], p[d]);
    if off_line.partial_cmp(&eps) != Some(std::cmp::Ordering::Greater)
        || off_plane.partial_cmp(&eps) != Some(std::cmp::Ordering::Greater)
        || side == 0.0
    {
        return Err(BlockError::ZeroVolume);
    }
    // Faces outward: d must be below the face (a, b, c).
    let (b, c) = if side < 0.0 { (c, b) } else { (b, c) };
    // Face k's neighbours across its edges, in the order of its corners.
    let faces = [[a, b, c], [a, d, b], [b, d, c], [c, d, a]];
    let neighbours = [[1, 2, 3], [3, 2, 0], [1, 3, 0], [2, 1, 0]];
    Ok(faces
        .into_iter()
        .zip(neighbours)
        .map(|(corners, n)| Triangle::new(p, corners, n))
        .collect())
}

/// The hull under construction: the triangles so far (dead ones kept, so that indices stay)
/// and, for each point, the triangle in whose list it waits.
struct Hull<'a> {
    p: &'a [DVec3],
    eps: f64,
    triangles: Vec<Triangle>,
    waiting_on: Vec<usize>,
    /// Per triangle, the point (plus 1) whose addition last found it visible.
    seen_by: Vec<usize>,
}

/// An edge of the horizon: its two ends (as in the replaced triangle) and the triangle that
/// stays on its other side, with the slot of the edge there.
#[derive(Clone, Copy)]
struct HorizonEdge {
    from: usize,
    to: usize,
    outer: usize,
    slot: usize,
}

impl Hull<'_> {
    /// Puts point `i` in the list of the first of `candidates` (alive) it lies more than the
    /// threshold above; otherwise it waits on none (it is within the threshold of the hull).
    fn assign(&mut self, i: usize, candidates: &[usize]) {
        let q = self.p[i];
        self.waiting_on[i] = NONE;
        for &t in candidates {
            let triangle = &mut self.triangles[t];
            if triangle.alive && triangle.height(self.p, q) > self.eps {
                triangle.outside.push(i);
                self.waiting_on[i] = t;
                return;
            }
        }
    }

    /// Takes from triangle `t`'s list the point most above it: of those within the threshold
    /// of the greatest height, the farthest from the triangle's centre (the end of an edge
    /// or a corner of a face parallel to the triangle, never a point between; then the
    /// first given). `None` when no point waits on it.
    fn take_farthest(&mut self, t: usize) -> Option<usize> {
        let p = self.p;
        let triangle = &self.triangles[t];
        let heights: Vec<f64> = triangle
            .outside
            .iter()
            .map(|&i| triangle.height(p, p[i]))
            .collect();
        let highest = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let centre = triangle.corners.iter().map(|&i| p[i]).sum::<DVec3>() / 3.0;
        let mut best: Option<(usize, f64)> = None;
        for (k, &i) in triangle.outside.iter().enumerate() {
            if heights[k] >= highest - self.eps {
                let d = p[i].distance_squared(centre);
                let better = match best {
                    None => true,
                    Some((b, bd)) => d > bd || (d == bd && i < triangle.outside[b]),
                };
                if better {
                    best = Some((k, d));
                }
            }
        }
        let (k, _) = best?;
        let i = self.triangles[t].outside.swap_remove(k);
        Some(i)
    }

    /// Adds point `i` if it waits on a triangle: every triangle that it is exactly above
    /// goes (a connected patch around that one), and the patch's rim (the horizon) is joined
    /// to it. The points of the triangles gone move to the new ones.
    fn add_point(&mut self, i: usize) {
        let start = self.waiting_on[i];
        self.waiting_on[i] = NONE;
        if start == NONE {
            return; // inside, or on the hull within the tolerance
        }
        let (p, q) = (self.p, self.p[i]);
        self.seen_by.resize(self.triangles.len(), 0);
        if !self.triangles[start].sees(p, q) {
            // More than the threshold above in floating point but not exactly above: never
            // (the threshold is far above the rounding); left out rather than trusted.
            return;
        }
        // The patch, in the order found (breadth first from `start`).
        let mut seen = vec![start];
        self.seen_by[start] = i + 1;
        let mut k = 0;
        while k < seen.len() {
            for n in self.triangles[seen[k]].neighbours {
                if self.seen_by[n] != i + 1 && self.triangles[n].sees(p, q) {
                    self.seen_by[n] = i + 1;
                    seen.push(n);
                }
            }
            k += 1;
        }
        let Some(horizon) = self.horizon(&seen, i + 1) else {
            return; // not one loop: never for an exactly convex hull; the point is left out
        };
        // The new triangles, one per horizon edge, each next to the following one.
        let base = self.triangles.len();
        let m = horizon.len();
        for (k, e) in horizon.iter().enumerate() {
            let neighbours = [e.outer, base + (k + 1) % m, base + (k + m - 1) % m];
            self.triangles
                .push(Triangle::new(p, [e.from, e.to, i], neighbours));
            self.triangles[e.outer].neighbours[e.slot] = base + k;
        }
        // The points waiting on the triangles gone: onto a new triangle, else onto a
        // triangle of the horizon's other side, else dropped.
        let mut candidates: Vec<usize> = (base..base + m).collect();
        candidates.extend(horizon.iter().map(|e| e.outer));
        for &t in &seen {
            self.triangles[t].alive = false;
            let outside = std::mem::take(&mut self.triangles[t].outside);
            for j in outside {
                if j != i && self.waiting_on[j] == t {
                    self.assign(j, &candidates);
                }
            }
        }
    }

    /// The rim of the patch `seen` (its triangles marked `mark` in `seen_by`) as one loop,
    /// starting at the first rim edge in the patch's order; `None` if it is not one loop.
    fn horizon(&self, seen: &[usize], mark: usize) -> Option<Vec<HorizonEdge>> {
        let mut edges = Vec::new();
        for &t in seen {
            let triangle = &self.triangles[t];
            for k in 0..3 {
                let outer = triangle.neighbours[k];
                if self.seen_by[outer] != mark {
                    let from = triangle.corners[k];
                    let to = triangle.corners[(k + 1) % 3];
                    let slot = (0..3).find(|&s| self.triangles[outer].corners[s] == to)?;
                    edges.push(HorizonEdge {
                        from,
                        to,
                        outer,
                        slot,
                    });
                }
            }
        }
        let mut by_start = HashMap::with_capacity(edges.len());
        for (k, e) in edges.iter().enumerate() {
            if by_start.insert(e.from, k).is_some() {
                return None;
            }
        }
        let mut cycle = Vec::with_capacity(edges.len());
        let mut k = *by_start.get(&edges.first()?.from)?;
        while cycle.len() < edges.len() {
            cycle.push(edges[k]);
            k = *by_start.get(&edges[k].to)?;
            if k == 0 {
                break;
            }
        }
        (cycle.len() == edges.len() && k == 0).then_some(cycle)
    }
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
