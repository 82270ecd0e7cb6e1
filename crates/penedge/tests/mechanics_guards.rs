//! Guards of the rigid-block mechanics against input that would give a quiet wrong answer
//! (a Rust user's findings, 2026-11-29): a step so long that a block passes through another
//! unseen, poses and velocities out of the range the detection works in, masses that are not
//! finite, time steps too small to end a run. Each is a `MechanicsError` naming what is wrong.

use penedge::block::Pose;
use penedge::glam::{DQuat, DVec3};
use penedge::mechanics::{
    Damping, JointModel, MechanicsError, Simulation, MIN_STEP_FRACTION, TRAVEL_LIMIT,
};
use penedge::{BlockSystem, ConvexBlock};

/// A fixed 4 × 4 × 1 m base (top at z = 0) and a free 1 m cube resting on it.
fn cube_on_base() -> Simulation {
    let base = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![base, cube]), 2500.0).unwrap();
    sim.fix(0).unwrap();
    sim
}

/// Soft joints (kn = ks = 1e2) give an automatic time step of 0.68 s: the cube fell through
/// the 1 m base in one step, with no error. Now the step that moves it farther than a tenth
/// of its radius is an error naming the body, the travel, the time step and the cause.
#[test]
fn a_step_that_moves_a_body_farther_than_a_tenth_of_its_radius_is_refused() {
    for kn in [1e2, 1e-300] {
        let mut sim = cube_on_base();
        let soft = JointModel {
            kn,
            ks: kn,
            ..JointModel::default()
        };
        sim.set_default_joint(soft).unwrap();
        let dt = sim.timestep().unwrap();
        assert!(dt > 0.5, "kn {kn}: dt {dt}");
        let e = sim.step().unwrap_err();
        let radius = 0.75f64.sqrt();
        match e {
            MechanicsError::Travel {
                body,
                step,
                travel,
                radius: r,
                dt: d,
            } => {
                assert_eq!((body, step, d), (1, 0, dt), "kn {kn}");
                assert!((r - radius).abs() < 1e-12, "{r}");
                // Fallen from rest for one step with a half kick: g dt² / 2 (at kn = 1e-300,
                // 2e302: the bound of the displacement overflows to infinity).
                let fall = 0.5 * 9.81 * dt * dt;
                if kn == 1e2 {
                    assert!((travel - fall).abs() <= 1e-9 * fall, "{travel} {fall}");
                }
                assert!(travel > TRAVEL_LIMIT * radius, "{travel}");
            }
            other => panic!("kn {kn}: {other:?}"),
        }
        let text = e.to_string();
        for words in ["body 1 moved", "time step", "too soft", "pass through"] {
            assert!(text.contains(words), "{words}: {text}");
        }
    }
}

/// The bound is the stated one: a free body in flight (no gravity, no contact) at a speed
/// that moves it 0.99 of the limit per step runs on; at 1.01 of it, the step is refused.
#[test]
fn the_travel_bound_is_a_tenth_of_the_radius() {
    for (fraction, allowed) in [(0.99, true), (1.01, false)] {
        let mut sim = cube_on_base();
        sim.set_gravity(DVec3::ZERO).unwrap();
        let pose = sim.bodies().poses()[1];
        sim.set_pose(
            1,
            Pose::new(pose.rotation, pose.translation + DVec3::Z).unwrap(),
        )
        .unwrap();
        let dt = sim.timestep().unwrap();
        let radius = 0.75f64.sqrt();
        let speed = fraction * TRAVEL_LIMIT * radius / dt;
        sim.set_velocity(1, DVec3::new(speed, 0.0, 0.0), DVec3::ZERO)
            .unwrap();
        let result = sim.step();
        assert_eq!(result.is_ok(), allowed, "{fraction}: {result:?}");
    }
}

/// `set_pose` took x = 1e20 (the placed 1 m cube degenerate, every vertex at x = 1e20, and
/// spinning after 3 steps); it is refused as `ContactTracker::update` refuses it, naming the
/// body, and the pose stays. A far pose the detection holds is taken.
#[test]
fn a_pose_beyond_the_range_of_double_precision_is_refused() {
    let mut sim = cube_on_base();
    let before = sim.bodies().poses()[1];
    let far = Pose::new(DQuat::IDENTITY, DVec3::new(1e20, 0.0, 0.5)).unwrap();
    let e = sim.set_pose(1, far).unwrap_err();
    match e {
        MechanicsError::OutOfRange {
            body,
            what,
            magnitude,
            limit,
        } => {
            assert_eq!((body, what), (1, "pose"));
            assert!(magnitude >= 1e20 && limit < 1e20, "{magnitude} {limit}");
        }
        ref other => panic!("{other:?}"),
    }
    let text = e.to_string();
    assert!(
        text.contains("body 1") && text.contains("too far"),
        "{text}"
    );
    assert_eq!(sim.bodies().poses()[1], before);
    // The fixed base too.
    assert!(matches!(
        sim.set_pose(0, far),
        Err(MechanicsError::OutOfRange { body: 0, .. })
    ));
    // Far but held: 1e6 m away, the cube is a cube.
    let held = Pose::new(DQuat::IDENTITY, DVec3::new(1e6, 0.0, 0.5)).unwrap();
    sim.set_pose(1, held).unwrap();
    assert_eq!(sim.bodies().poses()[1], held);
}

/// `set_velocity(1, 1e200)` was taken; a speed beyond 1e50 per unit of time (the largest
/// coordinate a block may have) is refused, naming the body, in `set_velocity` and in
/// `prescribe`; a spin counts by the body's radius.
#[test]
fn a_velocity_beyond_the_range_of_coordinates_is_refused() {
    let mut sim = cube_on_base();
    for (v, w) in [
        (DVec3::new(1e200, 0.0, 0.0), DVec3::ZERO),
        (DVec3::ZERO, DVec3::new(0.0, 0.0, 1.01e50 / 0.75f64.sqrt())),
    ] {
        let e = sim.set_velocity(1, v, w).unwrap_err();
        assert!(
            matches!(
                e,
                MechanicsError::OutOfRange {
                    body: 1,
                    what: "velocity",
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("body 1"), "{e}");
        assert!(!e.to_string().contains("inf"), "{e}");
        assert!(matches!(
            sim.prescribe(1, v, w),
            Err(MechanicsError::OutOfRange { body: 1, .. })
        ));
    }
    assert_eq!(sim.bodies().velocities()[1], DVec3::ZERO);
    sim.set_velocity(1, DVec3::new(1e49, 0.0, 0.0), DVec3::ZERO)
        .unwrap();
}

/// A density of 1e308 on a 10 m cube gave an infinite mass, taken; the first step then
/// failed with a NaN state. `Simulation::new` and `set_density` refuse it, naming the body.
#[test]
fn a_density_whose_mass_is_not_finite_is_refused() {
    let block = ConvexBlock::cuboid([0.0; 3], [10.0; 3]).unwrap();
    let system = BlockSystem::new(vec![block]);
    let e = Simulation::new(&system, 1e308).unwrap_err();
    match e {
        MechanicsError::Mass {
            body,
            density,
            mass,
            ..
        } => {
            assert_eq!((body, density), (0, 1e308));
            assert!(mass.is_infinite());
        }
        ref other => panic!("{other:?}"),
    }
    let text = e.to_string();
    assert!(
        text.contains("body 0") && text.contains("density 1e308"),
        "{text}"
    );
    // The moments overflow before the mass: 1.5e305 gives a finite mass of 1.5e308 and
    // moments of 1.5e305 × 1000 × 100 / 6 = 2.5e309.
    assert!(matches!(
        Simulation::new(&system, 1.5e305),
        Err(MechanicsError::Mass { body: 0, .. })
    ));
    let mut sim = Simulation::new(&system, 2500.0).unwrap();
    let e = sim.set_density(0, 1e308).unwrap_err();
    assert!(matches!(e, MechanicsError::Mass { body: 0, .. }), "{e:?}");
    assert_eq!(sim.bodies().densities()[0], 2500.0);
    sim.step().unwrap();
}

/// `set_timestep(Some(1e-300))` was taken (a `run_until(1.0)` would never end), and so was
/// a viscous damping rate of 1e300, which takes the automatic step to 1e-300. A step below
/// `MIN_STEP_FRACTION` of the undamped critical step is refused, and the setting stays.
#[test]
fn a_time_step_below_the_rounding_of_the_critical_one_is_refused() {
    let mut sim = cube_on_base();
    let critical = sim.critical_timestep().unwrap();
    let e = sim.set_timestep(Some(1e-300)).unwrap_err();
    match e {
        MechanicsError::TimeStepTooSmall {
            dt,
            smallest,
            given,
            ..
        } => {
            assert_eq!((dt, given), (1e-300, true));
            assert_eq!(smallest, MIN_STEP_FRACTION * critical);
        }
        ref other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("set_timestep"), "{e}");
    assert_eq!(sim.timestep().unwrap(), 0.5 * critical);
    // At the bound, and just below it.
    sim.set_timestep(Some(MIN_STEP_FRACTION * critical))
        .unwrap();
    assert!(sim
        .set_timestep(Some(0.99 * MIN_STEP_FRACTION * critical))
        .is_err());
    sim.set_timestep(None).unwrap();
    // Viscous damping that takes the automatic step below the bound.
    let e = sim
        .set_damping(Damping {
            local: 0.0,
            viscous: 1e300,
        })
        .unwrap_err();
    assert!(
        matches!(e, MechanicsError::TimeStepTooSmall { given: false, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("viscous damping"), "{e}");
    assert_eq!(sim.damping(), Damping::default());
    // A rate that lowers the step a thousandfold is taken.
    sim.set_damping(Damping {
        local: 0.0,
        viscous: 4000.0 / critical,
    })
    .unwrap();
    assert!(sim.timestep().unwrap() < 1e-3 * critical);
    // So is the safety factor.
    sim.set_damping(Damping::default()).unwrap();
    assert!(matches!(
        sim.set_safety(1e-17),
        Err(MechanicsError::TimeStepTooSmall { .. })
    ));
    sim.set_safety(1e-15).unwrap();
    sim.step().unwrap();
}

/// A given step valid for the joints when it was set, then joints a trillion times softer:
/// the critical step grows a millionfold and the given step falls below its floor. The step
/// refuses it (the path `set_timestep` cannot see: the stiffness changed after it).
#[test]
fn a_given_step_below_the_floor_after_the_joints_soften_is_refused_by_the_step() {
    let mut sim = cube_on_base();
    let stiff = JointModel {
        kn: 1e9,
        ks: 1e9,
        ..JointModel::default()
    };
    sim.set_default_joint(stiff).unwrap();
    let critical = sim.critical_timestep().unwrap();
    // Ten times the floor now, so accepted.
    let dt = 10.0 * MIN_STEP_FRACTION * critical;
    sim.set_timestep(Some(dt)).unwrap();
    let soft = JointModel {
        kn: 1e-3,
        ks: 1e-3,
        ..JointModel::default()
    };
    sim.set_default_joint(soft).unwrap();
    let softer = sim.critical_timestep().unwrap();
    assert!(dt < MIN_STEP_FRACTION * softer, "{dt} {softer}");
    let e = sim.step().unwrap_err();
    match e {
        MechanicsError::TimeStepTooSmall {
            dt: refused,
            smallest,
            given,
            ..
        } => {
            assert_eq!((refused, given), (dt, true));
            assert_eq!(smallest, MIN_STEP_FRACTION * softer);
        }
        ref other => panic!("{other:?}"),
    }
}
