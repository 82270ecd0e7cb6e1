//! Block generation: volume conservation, faces shared by neighbours or on the boundary,
//! reproducibility, finite joints, slivers, known orientations.

use penedge::generation::*;
use penedge::geometry::DVec3;
use penedge::{BlockSystem, ConvexBlock, Tolerance};

mod generation_support;
use generation_support::{check_faces, random_spec};

#[test]
fn volumes_add_up_to_the_domain_on_random_joint_systems() {
    for seed in 0..24 {
        let spec = random_spec(seed);
        let out = generate(&spec).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        let total: f64 = out.system.blocks().iter().map(|b| b.volume()).sum();
        let rel = (total - spec.domain.volume()).abs() / spec.domain.volume();
        assert!(rel <= 1e-9, "seed {seed}: relative volume error {rel:e}");
        assert!(out.report.volume_error <= 1e-9);
        assert!(out.system.blocks().iter().all(|b| b.volume() > 0.0));
        assert_eq!(out.report.retried_cuts, 0, "seed {seed}");
    }
}

#[test]
fn a_seed_gives_the_same_blocks_and_another_seed_others() {
    let spec = random_spec(4);
    let (a, b) = (generate(&spec).unwrap(), generate(&spec).unwrap());
    assert_eq!(a.system.len(), b.system.len());
    for (x, y) in a.system.blocks().iter().zip(b.system.blocks()) {
        assert_eq!(x.vertices(), y.vertices());
        assert_eq!(x.face_origins(), y.face_origins());
    }
    let mut other = spec.clone();
    for j in &mut other.joints {
        if let JointKind::Set(js) = &mut j.kind {
            js.seed += 1;
        }
    }
    let c = generate(&other).unwrap();
    assert_ne!(a.system.joints(), c.system.joints());
}

#[test]
fn joint_sets_with_known_orientations_cut_where_expected() {
    // Vertical joints dipping east (normal +x) every 2.5 m from x = 1; horizontal ones at
    // z = 2, 5, 8 (number = 3).
    let mut east = JointSet::new(Orientation::dip(90.0, 90.0), 2.5);
    east.origin = [1.0, 0.0, 0.0];
    let mut flat = JointSet::new(Orientation::dip(0.0, 0.0), 3.0);
    flat.origin = [0.0, 0.0, 2.0];
    flat.number = Some(3);
    let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap())
        .with(Discontinuity::set(east).named("east"))
        .with(Discontinuity::set(flat));
    let out = generate(&spec).unwrap();
    let xs: Vec<f64> = out
        .system
        .joints()
        .iter()
        .filter(|j| j.set == 0)
        .map(|j| j.plane.point.x)
        .collect();
    assert_eq!(xs, [1.0, 3.5, 6.0, 8.5]);
    for j in out.system.joints() {
        let expected = if j.set == 0 { DVec3::X } else { DVec3::Z };
        assert_eq!(j.plane.normal, expected);
    }
    let zs: Vec<f64> = out
        .system
        .joints()
        .iter()
        .filter(|j| j.set == 1)
        .map(|j| j.plane.point.z)
        .collect();
    assert_eq!(zs, [2.0, 5.0, 8.0]);
    assert_eq!(out.system.len(), 5 * 4);
    assert_eq!(out.system.sets()[0].name, "east");
    assert_eq!(out.system.sets()[1].name, "joints[1]");
}

#[test]
fn a_set_with_a_number_reports_planes_outside_the_domain() {
    let mut js = JointSet::new(Orientation::dip(0.0, 0.0), 4.0);
    js.origin = [0.0, 0.0, 3.0];
    js.number = Some(4); // z = 3, 7, 11, 15: two outside the 10 m cube
    let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap()).with(Discontinuity::set(js));
    let out = generate(&spec).unwrap();
    assert_eq!((out.system.len(), out.report.set_planes_outside), (3, 2));
}

fn slabs() -> Spec {
    let mut js = JointSet::new(Orientation::dip(90.0, 90.0), 2.5);
    js.origin = [2.5, 0.0, 0.0]; // x = 2.5, 5, 7.5
    Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap()).with(Discontinuity::set(js))
}

#[test]
fn a_finite_disc_splits_only_the_blocks_it_crosses_completely() {
    // The first slab's section at z = 5 is 2.5 x 10: a disc of radius 5.2 centred on it
    // covers it, and ends inside the next two slabs (it reaches x = 6.45).
    let spec = slabs().with(Discontinuity::disc(
        [1.25, 5.0, 5.0],
        Orientation::dip(0.0, 0.0),
        5.2,
    ));
    let out = generate(&spec).unwrap();
    assert_eq!(out.system.len(), 5);
    assert_eq!(out.report.partial_cuts_skipped, 2);
    assert_eq!(out.report.partial_cuts_by_entry, [0, 2]);
}

#[test]
fn a_finite_polygon_splits_only_the_blocks_it_crosses_completely() {
    // A horizontal rectangle over x in [0, 6], all y: covers slabs 1 and 2, ends in slab 3.
    let rect = vec![
        [0.0, -1.0, 4.0],
        [6.0, -1.0, 4.0],
        [6.0, 11.0, 4.0],
        [0.0, 11.0, 4.0],
    ];
    let out = generate(&slabs().with(Discontinuity::polygon(rect))).unwrap();
    assert_eq!((out.system.len(), out.report.partial_cuts_skipped), (6, 1));
    let cut: usize = out
        .system
        .blocks()
        .iter()
        .filter(|b| b.face_origins().iter().any(|o| o.set() == Some(1)))
        .count();
    assert_eq!(cut, 4);
}

#[test]
fn slivers_are_counted_and_kept_or_dropped() {
    let thin = Discontinuity::plane([0.0, 0.0, 10.0 - 1e-7], Orientation::dip(0.0, 0.0));
    let spec = slabs().with(thin);
    let kept = generate(&spec).unwrap();
    assert_eq!((kept.system.len(), kept.report.slivers.count), (8, 4));
    assert_eq!(kept.report.slivers.kept_ids.len(), 4);
    let mut drop = spec.clone();
    drop.options.slivers = SliverPolicy::Drop;
    let dropped = generate(&drop).unwrap();
    assert_eq!((dropped.system.len(), dropped.report.slivers.count), (4, 4));
    assert!((dropped.report.slivers.volume - 1e-5).abs() < 1e-12);
    assert!(dropped.report.volume_error < 1e-12);
    let mut quiet = spec;
    quiet.options.min_thickness = Some(0.0);
    assert_eq!(generate(&quiet).unwrap().report.slivers.count, 0);
}

#[test]
fn mine_grid_coordinates_keep_volume() {
    let (x, y) = (512_345.0, 4_123_456.0);
    let mut js = JointSet::new(Orientation::dip(60.0, 135.0), 1.7);
    js.origin = [x, y, 100.0];
    let mut js2 = JointSet::new(Orientation::dip(80.0, 20.0), 2.3);
    js2.origin = [x, y, 100.0];
    let spec = Spec::new(Domain::cuboid([x, y, 100.0], [x + 20.0, y + 15.0, 110.0]).unwrap())
        .with(Discontinuity::set(js))
        .with(Discontinuity::set(js2));
    let out = generate(&spec).unwrap();
    assert!(out.system.len() > 50);
    assert!(
        out.report.volume_error <= 1e-9,
        "{:e}",
        out.report.volume_error
    );
    check_faces(&out.system, 0);
}

#[test]
fn the_paper_examples_come_from_the_generator() {
    use penedge::system::{paper_spec, PaperExample};
    for (example, blocks) in [
        (PaperExample::One, 8),
        (PaperExample::Two, 8),
        (PaperExample::Three, 26),
    ] {
        let out = generate(&paper_spec(example)).unwrap();
        assert_eq!(out.system.len(), blocks);
        assert_eq!(out.report.slivers.count, 0);
        check_faces(&out.system, 0);
    }
}

#[test]
fn from_domain_cut_tags_faces() {
    let domain = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let s = BlockSystem::from_domain_cut(domain, &[[1.0, 0.0, 0.0]], &[0.5], &Tolerance::default())
        .unwrap();
    assert_eq!(s.len(), 2);
    for b in s.blocks() {
        let joints = b
            .face_origins()
            .iter()
            .filter(|o| **o == FaceOrigin::Joint { set: 0, joint: 0 })
            .count();
        assert_eq!(joints, 1);
        assert_eq!(
            b.face_origins().iter().filter(|o| o.is_boundary()).count(),
            5
        );
    }
}

#[test]
fn progress_is_reported_per_plane() {
    let mut seen = Vec::new();
    let out = generate_with_progress(&slabs(), &mut |p| seen.push(p.planes_done)).unwrap();
    assert_eq!(seen, [1, 2, 3]);
    assert_eq!(out.report.joint_planes, 3);
}

#[test]
fn tiny_blocks_are_flagged_beside_the_median_block_though_not_slivers() {
    // Planes at z = 5 and z = 5.001 in a 10 m cube: blocks of 500, 0.1 and 499.9 m^3. The
    // 1 mm layer is 60 times thicker than the default sliver limit (1e-6 of the 17.3 m
    // diagonal) but 1/4999 of the median block (499.9).
    let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap())
        .with(Discontinuity::plane(
            [0.0, 0.0, 5.0],
            Orientation::dip(0.0, 0.0),
        ))
        .with(Discontinuity::plane(
            [0.0, 0.0, 5.001],
            Orientation::dip(0.0, 0.0),
        ));
    let report = generate(&spec).unwrap().report;
    assert_eq!(report.slivers.count, 0);
    let tiny = &report.tiny;
    assert_eq!(tiny.count, 1);
    assert!((tiny.median_volume - 499.9).abs() < 1e-9, "{tiny:?}");
    assert!(
        (tiny.threshold - 499.9 * TINY_SHARE).abs() < 1e-12,
        "{tiny:?}"
    );
    assert!((tiny.smallest - 0.1).abs() < 1e-9, "{tiny:?}");
    // Without the thin layer, none.
    let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap()).with(Discontinuity::plane(
        [0.0, 0.0, 5.0],
        Orientation::dip(0.0, 0.0),
    ));
    assert_eq!(generate(&spec).unwrap().report.tiny.count, 0);
}

#[test]
fn the_estimate_is_within_a_small_factor_of_the_blocks_made() {
    // Random specs (one to three sets with random orientations and deviations, single
    // planes, boxes and tilted prisms) and the examples: the estimate errs high (oblique
    // pairs counted by their share of the domain's box, deviated sets by their reach), and
    // low only where planes are not in general position (three through one point).
    let mut ratios = Vec::new();
    for seed in 0..12 {
        let spec = random_spec(seed);
        let blocks = generate(&spec).unwrap().system.len() as f64;
        ratios.push((
            format!("seed {seed}"),
            estimate(&spec).unwrap().blocks / blocks,
        ));
    }
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for name in [
        "joint_set_random",
        "finite_disc",
        "finite_polygon",
        "domain_polyhedron",
    ] {
        let spec = penedge::io::spec::read_spec(&examples.join(format!("{name}.toml"))).unwrap();
        let blocks = generate(&spec).unwrap().system.len() as f64;
        ratios.push((name.to_string(), estimate(&spec).unwrap().blocks / blocks));
    }
    for (what, ratio) in ratios {
        assert!(
            (0.7..=6.0).contains(&ratio),
            "{what}: estimate / blocks = {ratio}"
        );
    }
}

#[test]
fn the_median_block_of_an_even_count_is_the_mean_of_the_two_middle_ones() {
    // A 4 x 1 x 1 box cut at x = 1: blocks of 1 and 3 m^3, median 2 (it read 3, the upper
    // of the two); then at x = 1 and x = 1.5 as well: 1, 0.5 and 2.5, median 1 (odd).
    let cut = |xs: &[f64]| {
        let mut spec = Spec::new(Domain::cuboid([0.0; 3], [4.0, 1.0, 1.0]).unwrap());
        for &x in xs {
            spec = spec.with(Discontinuity::plane(
                [x, 0.0, 0.0],
                Orientation::dip(90.0, 90.0),
            ));
        }
        generate(&spec).unwrap().report.tiny
    };
    let two = cut(&[1.0]);
    assert!((two.median_volume - 2.0).abs() < 1e-12, "{two:?}");
    assert!((two.threshold - 2.0 * TINY_SHARE).abs() < 1e-15, "{two:?}");
    let three = cut(&[1.0, 1.5]);
    assert!((three.median_volume - 1.0).abs() < 1e-12, "{three:?}");
    // Four: 1, 0.5, 0.5 and 2; median 0.75.
    let four = cut(&[1.0, 1.5, 2.0]);
    assert!((four.median_volume - 0.75).abs() < 1e-12, "{four:?}");
}
