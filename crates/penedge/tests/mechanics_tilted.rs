//! A block on a fixed base tilted by 40°, stiffness kn = ks = 1e8 Pa/m, no damping (the
//! setting of tests/restart.rs's slab): when it stops with `MechanicsError::Penetration`, and
//! why that is a correct refusal and not a lost contact.

use penedge::body::Shape;
use penedge::glam::{DQuat, DVec3};
use penedge::mechanics::{Bodies, Damping, JointModel, MechanicsError, Simulation};
use penedge::ConvexBlock;
use std::sync::Arc;

/// A 10 m × 10 m base tilted by 40° about x then turned by 0.6 rad about z, and a block of
/// half-widths `half` (height 2 `half[2]`) resting on its centre, both of density 2500.
fn scene(kn: f64, half: [f64; 3], friction: f64) -> Simulation {
    let frame = DQuat::from_rotation_z(0.6) * DQuat::from_rotation_x(40f64.to_radians());
    let place = |b: ConvexBlock| b.transformed(frame, DVec3::new(10.0, -5.0, 2.0), 1.0);
    let base = place(ConvexBlock::cuboid([-5.0, -5.0, -1.0], [5.0, 5.0, 0.0]).unwrap());
    let [x, y, z] = half;
    let block = place(ConvexBlock::cuboid([-x, -y, 0.0], [x, y, 2.0 * z]).unwrap());
    let mut bodies = Bodies::default();
    for part in [base, block] {
        let (shape, pose) = Shape::from_parts(&[part]).unwrap();
        bodies.push(Arc::new(shape), pose, 2500.0).unwrap();
    }
    let mut sim = Simulation::from_bodies(bodies);
    sim.fix(0).unwrap();
    let joint = JointModel {
        kn,
        ks: kn,
        friction,
        ..JointModel::default()
    };
    sim.set_default_joint(joint).unwrap();
    sim
}

/// Steps until `steps` or an error; the error, if any.
fn run(sim: &mut Simulation, steps: usize) -> Option<MechanicsError> {
    (0..steps).find_map(|_| sim.step().err())
}

const CUBE: [f64; 3] = [0.25; 3];

/// A 0.5 m cube, released at rest on the 40° slope, friction 45° (it cannot slide): loaded
/// at once and undamped it rocks on its lower edge (the moment of the slope's pull, tan 40° ×
/// 0.25 m = 0.21 m off its centre, is twice that under the sudden load, more than the 0.25 m
/// half-width), walks down the slope and lands back on an edge with an overlap beyond the
/// detection gap. The same time whatever the time step (the overlap is the contact law's,
/// not the integration's), and at the same step for a cube twice as large (every length of
/// the rocking, the overlap and the relative gap scales with the size): a correct refusal.
#[test]
fn an_undamped_cube_rocking_on_a_40_degree_slope_lands_deeper_than_the_gap_at_any_time_step() {
    let mut times = Vec::new();
    for (half, factor) in [(CUBE, None), (CUBE, Some(0.25)), ([0.5; 3], None)] {
        let mut sim = scene(1e8, half, 45.0);
        if let Some(f) = factor {
            let critical = sim.critical_timestep().unwrap();
            sim.set_timestep(Some(f * critical)).unwrap();
        }
        match run(&mut sim, 3000) {
            Some(MechanicsError::Penetration { bodies, step, .. }) => {
                assert_eq!(bodies, [0, 1]);
                times.push((sim.time(), step, half[0]));
            }
            other => panic!("{half:?} {factor:?}: {other:?}"),
        }
    }
    let [(t, step, _), (t_fine, _, _), (t_large, step_large, _)] = times[..] else {
        unreachable!()
    };
    assert!(
        (t_fine - t).abs() < 0.05 * t,
        "{t} s vs {t_fine} s at a quarter step"
    );
    // Same step up to rounding (the runs differ in the last bits), time × √2.
    assert!(
        step.abs_diff(step_large) <= 2,
        "steps {step} and {step_large}"
    );
    assert!(
        (t_large / t / 2f64.sqrt() - 1.0).abs() < 1e-2,
        "{t} s vs {t_large} s"
    );
}

/// The remedies the error names: local damping (3DEC's 0.8 for quasi-static runs) stops the
/// rocking and the cube stays put (it cannot slide); a stiffer contact (kn = 1e10) keeps the
/// landings within the gap, undamped, for 3,000 steps.
#[test]
fn damping_or_a_stiffer_contact_keep_the_rocking_cube_running() {
    let mut damped = scene(1e8, CUBE, 45.0);
    damped
        .set_damping(Damping {
            local: 0.8,
            viscous: 0.0,
        })
        .unwrap();
    let start = damped.bodies().poses()[1].translation;
    assert!(run(&mut damped, 3000).is_none());
    let moved = (damped.bodies().poses()[1].translation - start).length();
    // Its weight over kn A sinks and shears it by ρ g (2 half) / kn = 1.2e-4 m at most each
    // way (measured: 2.5e-4 m in all, with the settling of its tilt); undamped it walks 4 cm
    // down the slope before the refusal.
    assert!(moved < 1e-3, "moved {moved} m");
    let mut stiff = scene(1e10, CUBE, 45.0);
    assert!(run(&mut stiff, 3000).is_none());
    // A wider gap only delays it: at 5e-3 (five times the default) the rocking, which grows
    // as the cube walks down, still lands deeper within 3,000 steps.
    let mut wide = scene(1e8, CUBE, 45.0);
    wide.set_gap(5e-3).unwrap();
    assert!(matches!(
        run(&mut wide, 3000),
        Some(MechanicsError::Penetration { .. })
    ));
}

/// The refusal names what helps here (stiffness, damping, gap) and says when the time step
/// does: a user who only lowers it (the old message's first advice) gets the same refusal.
#[test]
fn the_penetration_error_names_the_remedies_that_work() {
    let mut sim = scene(1e8, CUBE, 45.0);
    let message = run(&mut sim, 3000).expect("a refusal").to_string();
    for words in [
        "bodies 0 and 1",
        "raise kn",
        "local damping",
        "widen the gap",
    ] {
        assert!(message.contains(words), "{words:?} not in {message:?}");
    }
    assert!(message.contains("time step helps only"), "{message}");
}
