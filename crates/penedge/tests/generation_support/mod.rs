//! Shared by the generation tests: random joint systems and the check that every face is
//! shared by neighbours or lies on the domain boundary.

use penedge::generation::rng::SplitMix64;
use penedge::generation::*;
use penedge::geometry::{DVec3, Plane};
use penedge::{BlockSystem, ConvexBlock, Tolerance};

/// A random spec: a box (or a tilted convex domain) near (±1000, ±1000, 0), one to three
/// joint sets with random orientations and deviations, and up to two single planes.
pub fn random_spec(seed: u64) -> Spec {
    let mut r = SplitMix64::new(seed);
    let corner = DVec3::new(r.symmetric(1e3), r.symmetric(1e3), 0.0);
    let size = DVec3::new(5.0, 5.0, 5.0) + 10.0 * DVec3::new(r.unit(), r.unit(), r.unit());
    let mut spec = Spec::new(random_domain(seed.is_multiple_of(3), corner, size));
    for s in 0..1 + r.next_u64() % 3 {
        let orientation = Orientation::dip(90.0 * r.unit(), 360.0 * r.unit());
        let mut js = JointSet::new(orientation, 1.0 + 2.0 * r.unit());
        js.origin = (corner + DVec3::new(r.unit(), r.unit(), r.unit())).to_array();
        js.deviation = Deviation {
            dip: 5.0 * r.unit(),
            dip_direction: 10.0 * r.unit(),
            spacing: 0.5 * r.unit(),
        };
        js.seed = seed * 10 + s;
        spec = spec.with(Discontinuity::set(js));
    }
    for _ in 0..r.next_u64() % 3 {
        let p = corner + size * DVec3::new(r.unit(), r.unit(), r.unit());
        let n = [r.symmetric(1.0), r.symmetric(1.0), r.symmetric(1.0)];
        spec = spec.with(Discontinuity::plane(p.to_array(), Orientation::Normal(n)));
    }
    spec
}

/// A box, or a tilted prism of six half-spaces about the same centre.
fn random_domain(tilted: bool, corner: DVec3, size: DVec3) -> Domain {
    if !tilted {
        return Domain::cuboid(corner.to_array(), (corner + size).to_array()).unwrap();
    }
    let n = [
        [1.0, 0.2, 0.0],
        [-1.0, 0.1, 0.0],
        [0.0, 1.0, 0.3],
        [0.0, -1.0, 0.2],
        [0.1, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let c = corner + size / 2.0;
    let d: Vec<f64> = (0..6)
        .map(|i| {
            let m = DVec3::from_array(n[i]);
            m.dot(c) + 0.5 * size[i / 2] * m.length()
        })
        .collect();
    Domain::from_halfspaces(&n, &d).unwrap()
}

/// Each boundary face lies on its domain face; each joint face is covered, to 1e-9 of its
/// area, by faces of other blocks in the same plane facing the other way.
pub fn check_faces(system: &BlockSystem, seed: u64) {
    let blocks = system.blocks();
    let mut neighbours = vec![Vec::new(); blocks.len()];
    for [i, j] in system.candidate_pairs(&Tolerance::default()) {
        neighbours[i as usize].push(j as usize);
        neighbours[j as usize].push(i as usize);
    }
    let eps = 1e-9 * system.domain()[0].size();
    for (a, block) in blocks.iter().enumerate() {
        for f in 0..block.n_faces() {
            let face = polygon(block, f);
            let plane = block.planes()[f];
            match block.face_origins()[f] {
                FaceOrigin::Boundary { part, face: k } => {
                    let dp = system.domain()[part as usize].planes()[k as usize];
                    assert!(
                        face.iter().all(|&p| dp.distance(p).abs() <= eps),
                        "seed {seed}"
                    );
                }
                FaceOrigin::Joint { .. } | FaceOrigin::Bridge { .. } => {
                    let covered: f64 = neighbours[a]
                        .iter()
                        .flat_map(|&b| (0..blocks[b].n_faces()).map(move |g| (b, g)))
                        .filter(|&(b, g)| {
                            facing(&plane, &blocks[b].planes()[g], &polygon(&blocks[b], g), eps)
                        })
                        .map(|(b, g)| overlap_area(&plane, &face, &polygon(&blocks[b], g)))
                        .sum();
                    let area = overlap_area(&plane, &face, &face);
                    assert!(
                        (covered - area).abs() <= 1e-9 * area,
                        "seed {seed}: block {a} face {f}: {covered} of {area}"
                    );
                }
                FaceOrigin::Unknown => panic!("a generated face has no origin"),
            }
        }
    }
}

fn polygon(b: &ConvexBlock, f: usize) -> Vec<DVec3> {
    b.face(f)
        .iter()
        .map(|&v| b.vertices()[v as usize])
        .collect()
}

fn facing(p: &Plane, q: &Plane, poly: &[DVec3], eps: f64) -> bool {
    p.normal.dot(q.normal) < -1.0 + 1e-9 && poly.iter().all(|&x| p.distance(x).abs() <= eps)
}

/// Area of the intersection of two convex polygons in `plane` (Sutherland-Hodgman).
fn overlap_area(plane: &Plane, a: &[DVec3], b: &[DVec3]) -> f64 {
    let u = plane.normal.any_orthonormal_vector();
    let w = plane.normal.cross(u);
    let flat = |p: &[DVec3]| -> Vec<[f64; 2]> {
        p.iter()
            .map(|&x| [(x - plane.point).dot(u), (x - plane.point).dot(w)])
            .collect()
    };
    let mut clip = flat(b);
    if signed_area(&clip) < 0.0 {
        clip.reverse();
    }
    let mut poly = flat(a);
    for k in 0..clip.len() {
        let (p, q) = (clip[k], clip[(k + 1) % clip.len()]);
        let side = |x: [f64; 2]| (q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0]);
        let mut out = Vec::new();
        for i in 0..poly.len() {
            let (x, y) = (poly[i], poly[(i + 1) % poly.len()]);
            let (sx, sy) = (side(x), side(y));
            if sx >= 0.0 {
                out.push(x);
            }
            if sx * sy < 0.0 {
                let t = sx / (sx - sy);
                out.push([x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])]);
            }
        }
        poly = out;
        if poly.len() < 3 {
            return 0.0;
        }
    }
    signed_area(&poly).abs()
}

fn signed_area(p: &[[f64; 2]]) -> f64 {
    (0..p.len())
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        / 2.0
}
