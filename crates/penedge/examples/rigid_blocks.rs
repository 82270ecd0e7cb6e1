//! Rigid-block mechanics: `penedge::mechanics::Simulation` (a 3DEC-style distinct element
//! method on penedge's contacts; docs/mechanics.md), checked against two closed forms.
//!
//! Run: `cargo run --release -p penedge --example rigid_blocks`
//!
//! Units: any consistent set; here SI (m, kg, s, N, Pa). Densities are mass per volume, the
//! joint stiffnesses `kn`, `ks` stresses per displacement (Pa/m), friction angles degrees,
//! gravity a vector (default (0, 0, -9.81)). Normal forces are positive in compression; a
//! contact's normal goes from A (the smaller id) to B, and its forces are those on B.
//!
//! **Poses: body frame to world.** The simulation stores each body in its own frame (origin
//! at the centroid, axes along its principal axes of inertia) and its pose maps that frame to
//! the world: `x = rotation * p + translation`. So `translation` *is* the centroid's position,
//! and the initial `rotation` is the principal axes' orientation, not the identity in general
//! (a 1 x 1 x 0.5 block may have its body x axis along the world z). Read a displacement as
//! the change of `translation`; world vertices from `Simulation::placed_system()` or by
//! applying the pose to the body-frame vertices (`bodies().shape(i).parts()`). This is not the
//! `ContactTracker`'s convention (poses that move world-frame blocks, starting at the identity;
//! example `time_stepping`); docs/bodies.md explains both.
use penedge::block::Pose;
use penedge::glam::DVec3;
use penedge::mechanics::{Damping, JointModel, Simulation, SubState};
use penedge::{BlockSystem, ConvexBlock};

const G: f64 = 9.81;
const DENSITY: f64 = 2500.0; // kg/m3

fn main() {
    resting_block();
    sliding_block();
    println!("\nall checks passed");
}

/// A 1 m cube on a fixed base settles by its weight over the joint's normal stiffness times
/// the contact area: `W / (kn A)`.
fn resting_block() {
    println!("A cube resting on a fixed block");
    let base = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).expect("a valid box");
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).expect("a valid box");
    let (volume, area) = (cube.volume(), 1.0); // the cube's base lies on the base: 1 m x 1 m
    let mut sim =
        Simulation::new(&BlockSystem::new(vec![base, cube]), DENSITY).expect("a valid simulation");
    // Body i is block i here (one convex block, one body).
    sim.fix(0).expect("body 0 exists");
    let kn = 1e9;
    sim.set_default_joint(JointModel {
        kn,
        ks: 1e9,
        friction: 30.0,
        ..JointModel::default()
    })
    .expect("a valid joint");

    // Poses map the body frame to the world: the translation is the centroid.
    let start = sim.bodies().poses()[1];
    assert!((start.translation - DVec3::new(0.0, 0.0, 0.5)).length() < 1e-12);

    // `solve` steps to equilibrium: until the unbalanced force is below 1e-6 of the weight
    // (with local damping 0.8 while it runs, since no damping was set).
    let report = sim.solve(1e-6, 100_000).expect("the run works");
    let end = sim.bodies().poses()[1];
    let settlement = start.translation.z - end.translation.z;
    let weight = DENSITY * volume * G;
    let expected = weight / (kn * area);
    println!(
        "  solved in {} steps (converged: {}, dt = {:.3e} s)",
        report.steps,
        report.converged,
        sim.timestep().expect("a time step")
    );
    println!(
        "  settlement {settlement:.6e} m, W / (kn A) = {expected:.6e} m (relative error {:.1e})",
        (settlement - expected).abs() / expected
    );
    assert!(report.converged);
    assert!((settlement - expected).abs() < 0.01 * expected);

    // Forces. `contact_forces()[i]` is the sum of the contact forces on body i: the base
    // pushes the cube up by its weight, and the cube pushes the fixed base down.
    let on_cube = sim.contact_forces()[1];
    println!(
        "  contact force on the cube {:.3?} N, weight {weight:.3} N",
        on_cube.to_array()
    );
    assert!((on_cube.z - weight).abs() < 1e-3 * weight);
    assert!((sim.contact_forces()[0] + on_cube).length() < 1e-6 * weight);
    // Per contact: the normal, from A (the base, body 0) to B (the cube), and its
    // sub-contacts, each with a point, a share of the area and its forces on B.
    let contacts = sim.contacts();
    assert_eq!(contacts.list.len(), 1);
    let c = &contacts.list[0];
    let subs = contacts.subs_of(0);
    let normal_force: f64 = subs.iter().map(|s| s.normal_force).sum();
    let shared_area: f64 = subs.iter().map(|s| s.area).sum();
    println!(
        "  contact {:?} of bodies {:?}: normal {:.6?}, {} sub-contacts, area {shared_area:.4} \
         m2, normal force {normal_force:.3} N",
        c.kind,
        c.bodies,
        c.normal.to_array(),
        subs.len()
    );
    assert_eq!(c.bodies, [0, 1]);
    assert!((c.normal - DVec3::Z).length() < 1e-9);
    assert!((normal_force - weight).abs() < 1e-3 * weight);
    assert!(sim.bodies().velocities()[1].length() < 1e-3);
}

/// A block on a 30 degree incline with a 20 degree friction angle slides, undamped, with the
/// acceleration `a = g (sin θ - cos θ tan φ)`: from a speed `v0` down the slope it travels
/// `v0 t + a t² / 2`.
fn sliding_block() {
    let (theta_deg, phi_deg) = (30.0_f64, 20.0_f64);
    println!("\nA block sliding down a {theta_deg} degree incline, friction angle {phi_deg}");
    let theta = theta_deg.to_radians();
    // Unit vectors: `up` along the slope (rising with x), `n` out of the slope's surface.
    let up = DVec3::new(theta.cos(), 0.0, theta.sin());
    let n = DVec3::new(-theta.sin(), 0.0, theta.cos());
    // The base, from half-spaces m . x <= d: under the slope's surface n . x <= 0, above
    // z = -20, x in [-1, 20], y in [-2, 2].
    let base = ConvexBlock::from_planes(
        &[
            n.to_array(),
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
        ],
        &[0.0, 20.0, 20.0, 1.0, 2.0, 2.0],
    )
    .expect("a bounded block");
    // The block, 1 m along the slope, 1 m across, 0.5 m thick, from its corners (their
    // convex hull), its base on the slope 10 m up it.
    //
    // The closed form is rigid-plastic: the block slides from the start, under a normal force
    // W cos θ. So the block is placed pressed into the slope by the overlap that carries that
    // force, W cos θ / (kn A) (the normal force is kn A times the overlap), and given a speed
    // down the slope: it then slides at once. Placed just touching and at rest, it would
    // bounce on the joint's spring (nothing damps the run; its normal force swinging between
    // 0 and 2 W cos θ) and stick elastically for its first steps, and its distance would
    // differ from the closed form by about 1e-2 (relative) after 0.4 s.
    let (kn, volume) = (1e9, 0.5);
    let weight = DENSITY * volume * G;
    let preload = weight * theta.cos() / (kn * 1.0);
    let mut corners = Vec::new();
    for a in [10.0, 11.0] {
        for b in [-0.5, 0.5] {
            for c in [0.0, 0.5] {
                corners.push((up * a + DVec3::Y * b + n * (c - preload)).to_array());
            }
        }
    }
    let block = ConvexBlock::hull(&corners).expect("a valid hull");
    assert!((block.volume() - volume).abs() < 1e-12);
    let mut sim = Simulation::new(&BlockSystem::new(vec![base, block.clone()]), DENSITY)
        .expect("a valid simulation");
    sim.fix(0).expect("body 0 exists");
    sim.set_default_joint(JointModel {
        kn,
        ks: 1e9,
        friction: phi_deg,
        ..JointModel::default()
    })
    .expect("a valid joint");
    // No damping (the default): the motion is the dynamics itself.
    assert_eq!(sim.damping(), Damping::default());
    let v0 = 0.5; // m/s, down the slope
    sim.set_velocity(1, -up * v0, DVec3::ZERO)
        .expect("body 1 is free");

    // The body frame: the initial translation is the block's centroid; the rotation turns
    // the principal axes into the world's, and applying the pose to the body-frame vertices
    // gives the block's world vertices back.
    let start: Pose = sim.bodies().poses()[1];
    assert!((start.translation - block.centroid()).length() < 1e-12);
    let (axis, angle) = start.rotation.to_axis_angle();
    println!(
        "  initial pose: centroid {:.4?}, rotation {:.1} degrees about {:.3?}",
        start.translation.to_array(),
        angle.to_degrees(),
        axis.to_array()
    );
    let body_frame = &sim.bodies().shape(1).parts()[0];
    for p in body_frame.vertices() {
        let world = start.apply(*p);
        assert!(block
            .vertices()
            .iter()
            .any(|v| (*v - world).length() < 1e-9));
    }

    // A DEM loop: step, read the state. (`run_until(t)` and `cycle(n)` step too.)
    let t_end = 0.4; // s
    let dt = sim.timestep().expect("a time step");
    let (mut normal_sum, mut shear_sum, mut steps) = (0.0, 0.0, 0);
    while sim.time() < t_end {
        sim.step().expect("the step works");
        // `contact_forces()[i]`: the sum of the contact forces on body i at this step.
        let f = sim.contact_forces()[1];
        normal_sum += f.dot(n);
        shear_sum += f.dot(up);
        steps += 1;
    }
    let t = sim.time();
    let pose = sim.bodies().poses()[1];
    // Down the slope is -up. The velocities are the leapfrog's (central differences): half a
    // step behind the poses (docs/mechanics.md, "Integration").
    let slid = (start.translation - pose.translation).dot(up);
    let speed = -sim.bodies().velocities()[1].dot(up);
    let a = G * (theta.sin() - theta.cos() * phi_deg.to_radians().tan());
    let slid_expected = v0 * t + 0.5 * a * t * t;
    let speed_expected = v0 + a * (t - 0.5 * dt);
    println!(
        "  {steps} steps of {dt:.3e} s, t = {t:.4} s: slid {slid:.6} m (v0 t + a t^2 / 2 = \
         {slid_expected:.6}), speed {speed:.6} m/s ({speed_expected:.6}), a = {a:.4} m/s2"
    );
    println!(
        "  relative errors: distance {:.1e}, speed {:.1e}; spin {:.1e} rad/s",
        (slid - slid_expected).abs() / slid_expected,
        (speed - speed_expected).abs() / speed_expected,
        sim.bodies().spin(1).length()
    );
    assert!((slid - slid_expected).abs() < 1e-4 * slid_expected);
    assert!((speed - speed_expected).abs() < 1e-4 * speed_expected);

    // The contact force on the block, averaged over the steps: its normal part carries
    // W cos θ, its shear part (friction, up the slope) tan φ times that.
    let (normal, shear) = (normal_sum / steps as f64, shear_sum / steps as f64);
    let normal_expected = weight * theta.cos();
    let shear_expected = normal_expected * phi_deg.to_radians().tan();
    println!(
        "  mean contact force on the block: normal {normal:.1} N (W cos θ = \
         {normal_expected:.1}), up the slope {shear:.1} N (W cos θ tan φ = {shear_expected:.1})"
    );
    assert!((normal - normal_expected).abs() < 1e-4 * normal_expected);
    assert!((shear - shear_expected).abs() < 1e-4 * shear_expected);

    // Per sub-contact, while it slides: at the Mohr-Coulomb limit, |shear| = tan φ x normal.
    let contacts = sim.contacts();
    let mut sliding = 0;
    for (i, c) in contacts.list.iter().enumerate() {
        // A face-face normal is normalize(nA - nB): the slope's, but for the block's slight
        // rocking (the friction acts below its centroid).
        assert!((c.normal - n).length() < 1e-4, "the normal is the slope's");
        for s in contacts.subs_of(i) {
            if s.state == SubState::Sliding {
                sliding += 1;
                let limit = phi_deg.to_radians().tan() * s.normal_force;
                assert!((s.shear_force.length() - limit).abs() < 1e-9 * limit);
            }
        }
    }
    println!("  {sliding} sub-contacts at the friction limit");
    assert!(sliding > 0);
}
