//! The work of a run: the estimate made before cutting, the block limit, cancellation.

use penedge::generation::*;
use std::ops::ControlFlow;

fn cube(size: f64) -> Spec {
    Spec::new(Domain::cuboid([0.0; 3], [size; 3]).unwrap())
}

fn set(dip: f64, dip_direction: f64, spacing: f64) -> Discontinuity {
    Discontinuity::set(JointSet::new(Orientation::dip(dip, dip_direction), spacing))
}

/// Three orthogonal sets, `spacing` apart from the origin of coordinates.
fn three_sets(size: f64, spacing: f64) -> Spec {
    cube(size)
        .with(set(0.0, 0.0, spacing))
        .with(set(90.0, 0.0, spacing))
        .with(set(90.0, 90.0, spacing))
}

#[test]
fn three_orthogonal_sets_are_estimated_as_the_product_of_their_layers() {
    // A 10 m cube, planes at 2.5, 5, 7.5 along each axis: 4 x 4 x 4 blocks, and the
    // arrangement 1 + 9 planes + 27 lines + 27 points.
    let spec = three_sets(10.0, 2.5);
    let e = estimate(&spec).unwrap();
    assert_eq!(e.planes, 9);
    assert!((e.lines - 27.0).abs() < 1e-9, "{e:?}");
    assert!((e.points - 27.0).abs() < 1e-9, "{e:?}");
    assert!((e.blocks - 64.0).abs() < 1e-9, "{e:?}");
    assert_eq!(generate(&spec).unwrap().system.len(), 64);
}

#[test]
fn vertical_sets_meet_in_lines_but_not_in_points() {
    // x = 5 and y = 5 (one plane each, both vertical) and the vertical plane x + y = 10
    // through their line: three normals in one plane make no point. The arrangement of the
    // first two is 1 + 2 + 1 = 4 blocks; the third line pair is counted by its share.
    let spec = cube(10.0)
        .with(Discontinuity::plane(
            [5.0, 5.0, 5.0],
            Orientation::Normal([1.0, 0.0, 0.0]),
        ))
        .with(Discontinuity::plane(
            [5.0, 5.0, 5.0],
            Orientation::Normal([0.0, 1.0, 0.0]),
        ));
    let e = estimate(&spec).unwrap();
    assert_eq!((e.planes, e.lines, e.points, e.blocks), (2, 1.0, 0.0, 4.0));
    let spec = spec.with(Discontinuity::plane(
        [0.0, 10.0, 5.0],
        Orientation::Normal([1.0, 1.0, 0.0]),
    ));
    assert_eq!(estimate(&spec).unwrap().points, 0.0);
}

#[test]
fn a_runaway_spec_is_refused_before_cutting_with_the_estimate_and_the_way_out() {
    // 10^4 planes a set in a 100 m box: 30,000 planes, within the plane limit, but about
    // (10^4)^3 = 10^12 blocks, some 4 PB.
    let spec = three_sets(100.0, 0.01);
    let e = estimate(&spec).unwrap();
    assert!(e.planes >= 29_997 && e.planes <= 30_003, "{e:?}");
    assert!(e.blocks > 0.99e12 && e.blocks < 1.01e12, "{e:?}");
    let err = generate(&spec).unwrap_err();
    assert!(
        matches!(err, GenerationError::TooManyBlocks { given: false, .. }),
        "{err:?}"
    );
    let message = err.to_string();
    for words in [
        "about 1.0e12 blocks",
        "larger spacing",
        "sub-domain",
        "--max-blocks",
    ] {
        assert!(message.contains(words), "{message}");
    }
}

#[test]
fn a_given_block_limit_refuses_a_spec_that_would_pass_it() {
    let spec = three_sets(10.0, 2.5); // 64 blocks
    let stop = &mut |_| ControlFlow::Continue(());
    let err = generate_with(&spec, &Limits::blocks(63), stop).unwrap_err();
    assert!(
        matches!(
            err,
            GenerationError::TooManyBlocks {
                limit: 63,
                given: true,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("(given)"));
    assert_eq!(
        generate_with(&spec, &Limits::blocks(64), stop)
            .unwrap()
            .system
            .len(),
        64
    );
}

#[test]
fn a_run_that_outgrows_its_estimate_stops_at_the_limit() {
    // The paper's Example 2: x + y = 10, y + z = 10, z + x = 10 through the centre of the
    // 10 m cube make 8 blocks; three planes through one point are not in general position,
    // and the estimate (6: the pairs' lines and the point counted by their share of the
    // cube) is lower. With a limit of 7 the estimate passes and the run stops.
    let spec = [[1.0, 1.0, 0.0], [0.0, 1.0, 1.0], [1.0, 0.0, 1.0]]
        .into_iter()
        .fold(cube(10.0), |spec, n| {
            spec.with(Discontinuity::plane([5.0; 3], Orientation::Normal(n)))
        });
    let e = estimate(&spec).unwrap();
    assert!(e.blocks <= 7.0, "{e:?}");
    let stop = &mut |_| ControlFlow::Continue(());
    let err = generate_with(&spec, &Limits::blocks(7), stop).unwrap_err();
    assert!(
        matches!(
            err,
            GenerationError::Outgrew {
                limit: 7,
                planes_done: 3,
                planes_total: 3,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("outgrew its estimate"), "{err}");
    assert_eq!(
        generate_with(&spec, &Limits::blocks(8), stop)
            .unwrap()
            .system
            .len(),
        8
    );
}

#[test]
fn a_progress_callback_that_says_stop_stops_the_run_between_two_planes() {
    let spec = three_sets(10.0, 2.5); // 9 planes
    let mut seen = Vec::new();
    let err = generate_with(&spec, &Limits::default(), &mut |p| {
        seen.push(p.planes_done);
        if p.planes_done == 2 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    })
    .unwrap_err();
    assert_eq!(seen, [1, 2]);
    assert_eq!(
        err,
        GenerationError::Cancelled {
            planes_done: 2,
            planes_total: 9
        }
    );
}

#[test]
fn the_default_limit_comes_from_the_memory_available() {
    let limits = Limits::from_memory();
    assert!(!limits.given);
    match available_memory() {
        // Half the memory available, read a moment apart (other programs run meanwhile).
        Some(bytes) => {
            let share = (limits.max_blocks * BYTES_PER_BLOCK) as f64 / bytes as f64;
            assert!((0.25..=1.0).contains(&share), "{share}");
        }
        None => assert_eq!(limits.max_blocks, FALLBACK_MAX_BLOCKS),
    }
}

#[test]
fn a_network_of_small_discs_is_not_counted_as_infinite_planes() {
    // 400 discs of radius 1 at random in a 20 m cube: as infinite planes they would make
    // about 400^3 / 6 = 10^7 blocks; as discs they meet a few times, and none crosses the
    // cube, so none cuts it (a finite joint cuts only the blocks it crosses completely).
    let mut r = penedge::generation::rng::SplitMix64::new(7);
    let mut spec = cube(20.0);
    for _ in 0..400 {
        let center = [20.0 * r.unit(), 20.0 * r.unit(), 20.0 * r.unit()];
        let orientation = Orientation::dip(90.0 * r.unit(), 360.0 * r.unit());
        spec = spec.with(Discontinuity::disc(center, orientation, 1.0));
    }
    let e = estimate(&spec).unwrap();
    let blocks = generate(&spec).unwrap().system.len() as f64;
    assert_eq!(blocks, 1.0);
    assert!(e.blocks < 100.0, "{e:?}");
}
