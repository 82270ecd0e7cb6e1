//! `ConvexBlock::hull` of dense clouds (scans, thousands of points on a sphere): a valid
//! convex block, every point inside it or within the length tolerance of it, and a volume
//! between bounds computed here without penedge (docs/api.md, `Block.from_hull`).
//!
//! Until 2026-11-29 the hull replaced only the triangles a new point was more than the
//! tolerance above, so each point could leave a fold of up to the tolerance, and the folds
//! added up: 6,400 and 12,800 random points on a unit sphere were refused as "not convex" by
//! 4.5e-9 and 2.3e-8 (the tolerance there: 3.5e-9), and the cube below as "not a sphere"
//! (points jittered out of its faces kept as vertices inside them). The Fibonacci lattices
//! were blocks before too: they check the hull's accuracy and the time of 25,600 points.

use penedge::glam::DVec3;
use penedge::tolerance::Tolerance;
use penedge::ConvexBlock;
use std::collections::HashMap;
use std::f64::consts::PI;

/// A reproducible sequence in [0, 1) (a linear congruential generator).
fn uniform(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// `n` random points uniform on the unit sphere (z uniform, the angle uniform).
fn random_on_sphere(n: usize, mut seed: u64) -> Vec<[f64; 3]> {
    (0..n)
        .map(|_| {
            let z = 2.0 * uniform(&mut seed) - 1.0;
            let phi = 2.0 * PI * uniform(&mut seed);
            let r = (1.0 - z * z).sqrt();
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect()
}

/// The Fibonacci lattice of `n` points on the unit sphere.
fn fibonacci_sphere(n: usize) -> Vec<[f64; 3]> {
    let turn = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2 * i + 1) as f64 / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = turn * i as f64;
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect()
}

/// The length threshold of the default tolerance for these points (1e-9 x their box's
/// diagonal), computed here.
fn length_threshold(points: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(DVec3::from_array(*p));
        hi = hi.max(DVec3::from_array(*p));
    }
    Tolerance::default().length() * (hi - lo).length()
}

/// The volume of the convex hull of a few points, by brute force and no tolerance: a
/// triple of points is a face when all the other points are strictly on one side of its
/// plane; the hull is the sum of the tetrahedra from the points' mean to its faces. Four
/// points in one plane would leave their face out (no triple has all others strictly on one
/// side): never more than the hull.
fn brute_force_hull_volume(points: &[DVec3]) -> f64 {
    let centre = points.iter().sum::<DVec3>() / points.len() as f64;
    let mut volume = 0.0;
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            for k in j + 1..points.len() {
                let (a, b, c) = (points[i], points[j], points[k]);
                let n = (b - a).cross(c - a);
                let (mut above, mut below) = (false, false);
                for (l, &q) in points.iter().enumerate() {
                    if l != i && l != j && l != k {
                        let s = n.dot(q - a);
                        above |= s >= 0.0;
                        below |= s <= 0.0;
                    }
                }
                if above != below {
                    volume += ((a - centre).dot((b - centre).cross(c - centre)) / 6.0).abs();
                }
            }
        }
    }
    volume
}

/// The largest height of a point of the unit sphere above a face plane of `block`, each
/// point against the faces whose normals are near its direction: a point of the unit sphere
/// can be above the plane n·x = h only when |n - q|² = 2 - 2 n·q < 2 - 2 h, so faces are
/// filed by their normals in cells of that chord (for the lowest plane) and each point looks
/// in its own cell and the 26 around it.
fn largest_height_on_unit_sphere(block: &ConvexBlock, points: &[[f64; 3]]) -> f64 {
    let planes = block.planes();
    let lowest = planes
        .iter()
        .map(|f| f.normal.dot(f.point))
        .fold(f64::INFINITY, f64::min);
    let cell = (2.0 - 2.0 * (lowest - 1e-6)).sqrt() * 1.01;
    let key = |v: DVec3| (v / cell).floor().as_i64vec3().to_array();
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (f, plane) in planes.iter().enumerate() {
        cells.entry(key(plane.normal)).or_default().push(f);
    }
    let mut largest = f64::NEG_INFINITY;
    for p in points {
        let q = DVec3::from_array(*p);
        let [x, y, z] = key(q);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &f in cells.get(&[x + dx, y + dy, z + dz]).into_iter().flatten() {
                        largest = largest.max(planes[f].distance(q));
                    }
                }
            }
        }
    }
    largest
}

/// The checks of a hull of points on the unit sphere: a block; every point within the
/// tolerance of it; every vertex one of the points; its volume below the ball's and above
/// the brute-force hull of 60 of the points spread over the list.
fn check_sphere_hull(points: &[[f64; 3]]) -> ConvexBlock {
    let eps = length_threshold(points);
    let block = ConvexBlock::hull(points).unwrap_or_else(|e| panic!("{}: {e}", points.len()));
    let height = largest_height_on_unit_sphere(&block, points);
    assert!(height <= eps, "{}: a point {height} outside", points.len());
    let mut given: Vec<[u64; 3]> = points.iter().map(|p| p.map(f64::to_bits)).collect();
    given.sort_unstable();
    for v in block.vertices() {
        let bits = v.to_array().map(f64::to_bits);
        assert!(given.binary_search(&bits).is_ok(), "{v} is not a point");
    }
    let ball = 4.0 / 3.0 * PI;
    let step = points.len() / 60;
    let subset: Vec<DVec3> = (0..60)
        .map(|k| DVec3::from_array(points[k * step]))
        .collect();
    let inscribed = brute_force_hull_volume(&subset);
    assert!(inscribed > 3.0, "{inscribed}"); // 60 points spread over the sphere
    assert!(
        block.volume() > inscribed && block.volume() < ball,
        "{}: {} not in ({inscribed}, {ball})",
        points.len(),
        block.volume()
    );
    block
}

#[test]
fn random_points_on_a_sphere_give_a_block() {
    // One stream of seed 11: its 6,400 points after the first 4,800, and the 12,800 after
    // those, were refused as not convex (by 4.5e-9 and 2.3e-8); 25,600 of seed 1 were not,
    // and stay a block. Every point is a corner.
    let stream = random_on_sphere(24_000, 11);
    for points in [
        stream[4_800..11_200].to_vec(),
        stream[11_200..].to_vec(),
        random_on_sphere(25_600, 1),
    ] {
        let block = check_sphere_hull(&points);
        assert_eq!(block.vertices().len(), points.len());
    }
}

#[test]
fn a_fibonacci_lattice_on_a_sphere_gives_a_block() {
    for n in [2_000, 25_600] {
        let points = fibonacci_sphere(n);
        let block = check_sphere_hull(&points);
        assert_eq!(block.vertices().len(), n);
    }
}

#[test]
fn points_jittered_on_a_cubes_faces_give_the_cube() {
    // A 2 m cube's corners and 2,400 points on its faces, every coordinate moved by up to
    // 1e-12: the hull is the cube, its 8 corners and 6 faces, its volume 8 within the
    // tolerance over its surface.
    let mut seed = 5;
    let mut jitter = |x: f64| x + 1e-12 * (2.0 * uniform(&mut seed) - 1.0);
    let mut points = Vec::new();
    for k in 0..8 {
        let corner = [0, 1, 2].map(|d| 2.0 * f64::from((k >> d) & 1));
        points.push(corner.map(&mut jitter));
    }
    for axis in 0..3 {
        for side in [0.0, 2.0] {
            for i in 1..=20 {
                for j in 1..=20 {
                    let (u, v) = (i as f64 / 10.5, j as f64 / 10.5);
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[(axis + 1) % 3] = u;
                    p[(axis + 2) % 3] = v;
                    points.push(p.map(&mut jitter));
                }
            }
        }
    }
    let eps = length_threshold(&points);
    let cube = ConvexBlock::hull(&points).expect("the cube");
    assert_eq!(cube.vertices().len(), 8);
    assert_eq!(cube.n_faces(), 6);
    assert!(
        (cube.volume() - 8.0).abs() < 24.0 * eps,
        "{}",
        cube.volume()
    );
    for p in &points {
        for plane in cube.planes() {
            assert!(plane.distance(DVec3::from_array(*p)) <= eps);
        }
    }
}
