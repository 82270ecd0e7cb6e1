//! Faces of generated blocks: shared by neighbours or on the domain boundary, also where
//! planes pass exactly through (or just beside) existing vertices and edges.

use penedge::generation::rng::SplitMix64;
use penedge::generation::*;
use penedge::geometry::DVec3;

mod generation_support;
use generation_support::{check_faces, random_spec};

#[test]
fn every_face_is_shared_by_neighbours_or_on_the_boundary() {
    for seed in [1, 2, 3, 5, 9] {
        let spec = random_spec(seed);
        let out = generate(&spec).unwrap();
        check_faces(&out.system, seed);
    }
}

#[test]
fn lattice_planes_through_vertices_and_edges_cut_cleanly() {
    // Axis sets and diagonal sets through the same lattice points: most cuts pass exactly
    // through existing vertices and along existing edges (the paper's Example 3, scaled up).
    let s = 2f64.sqrt();
    let set = |n: [f64; 3], spacing: f64| {
        Discontinuity::set(JointSet::new(Orientation::Normal(n), spacing))
    };
    let spec = Spec::new(Domain::cuboid([0.0; 3], [4.0; 3]).unwrap())
        .with(set([1.0, 0.0, 0.0], 1.0))
        .with(set([0.0, 1.0, 0.0], 1.0))
        .with(set([0.0, 0.0, 1.0], 1.0))
        .with(set([1.0, 1.0, 0.0], s))
        .with(set([0.0, 1.0, 1.0], s))
        .with(set([1.0, 0.0, 1.0], s));
    let out = generate(&spec).unwrap();
    // Axis planes at every integer, diagonals x + y = 2, 4, 6 (and the like): each of the
    // eight 2 m cubes is cut through its centre like the paper's Example 3 (26 blocks).
    assert_eq!(out.system.len(), 8 * 26);
    assert!(out.report.volume_error <= 1e-12);
    assert_eq!((out.report.retried_cuts, out.report.slivers.count), (0, 0));
    check_faces(&out.system, 0);
}

#[test]
fn planes_through_lattice_points_and_just_off_them_keep_the_system_closed() {
    // Planes through three random points of the quarter lattice pass through many existing
    // vertices and edges exactly; shifted by less than, about, and more than the length
    // threshold (1e-9 of the size) they pass just beside them.
    for (seed, shift) in (0..12).zip([0.0, 1e-13, 1e-10, 1.5e-9, 3e-9, 1e-8].iter().cycle()) {
        let spec = lattice_spec(seed, *shift);
        let out = generate(&spec).unwrap();
        let error = out.report.volume_error;
        assert!(error <= 1e-12, "seed {seed}: {error:e}");
        check_faces(&out.system, seed);
    }
}

/// Unit cube, axis sets every 0.25, and four planes through lattice points (moved by
/// `shift` along their normal) that the spec accepts.
fn lattice_spec(seed: u64, shift: f64) -> Spec {
    let mut r = SplitMix64::new(seed);
    let mut lattice = || {
        let mut c = || 0.25 * (r.next_u64() % 5) as f64;
        DVec3::new(c(), c(), c())
    };
    let mut spec = Spec::new(Domain::cuboid([0.0; 3], [1.0; 3]).unwrap());
    for n in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
        let set = JointSet::new(Orientation::Normal(n), 0.25);
        spec = spec.with(Discontinuity::set(set));
    }
    let mut added = 0;
    while added < 4 {
        let (a, b, c) = (lattice(), lattice(), lattice());
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            continue;
        };
        let point = (a + n * shift).to_array();
        let plane = Discontinuity::plane(point, Orientation::Normal(n.to_array()));
        let candidate = spec.clone().with(plane);
        if generate(&candidate).is_ok() {
            spec = candidate;
            added += 1;
        }
    }
    spec
}
