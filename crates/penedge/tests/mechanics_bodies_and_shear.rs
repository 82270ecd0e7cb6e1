//! Checks of the mechanics left open by the audit of issue 18: a body's own density sets its
//! mass, inertia and weight (`Simulation::set_density`), and a stored shear force turns with
//! its contact when the bodies turn together (docs/mechanics.md, "Joint law", step 1).
//! References are formulas computed here, never numbers copied from a run.

use penedge::glam::{DQuat, DVec3};
use penedge::mechanics::{JointModel, Simulation, SubContact, SubState};
use penedge::{BlockSystem, ConvexBlock};

const G: f64 = 9.81;

fn joint(kn: f64, friction: f64) -> JointModel {
    JointModel {
        kn,
        ks: kn,
        friction,
        ..JointModel::default()
    }
}

/// Two cuboids resting apart on a fixed base, the second with twice the density of the
/// first (set after the simulation is made): each body's mass is `ρ a b c`, its principal
/// moments `m (b² + c²) / 12` and the two others, and at equilibrium its contact with the
/// base carries its own weight `ρ V g`. The solve stops when the largest unbalanced force of
/// a free body is below `ratio` times the largest weight, so that is the tolerance of each
/// body's contact force (and of its contact's total normal force, the normal being the
/// base's top face normal, up to rounding). With the same density for both, the second
/// body's force would be half its reference: the test fails.
#[test]
fn a_denser_block_is_heavier_and_weighs_more_on_its_base() {
    let base = ConvexBlock::cuboid([-3.0, -2.0, -1.0], [3.0, 2.0, 0.0]).unwrap();
    let corners = [
        ([-2.0, -0.5, 0.0], [-1.0, 0.5, 1.0]),
        ([1.0, -0.5, 0.0], [2.5, 0.5, 0.8]),
    ];
    let densities = [2500.0, 5000.0];
    let blocks = corners.map(|(lo, hi)| ConvexBlock::cuboid(lo, hi).unwrap());
    let system = BlockSystem::new(vec![base, blocks[0].clone(), blocks[1].clone()]);
    let mut sim = Simulation::new(&system, densities[0]).unwrap();
    sim.fix(0).unwrap();
    sim.set_density(2, densities[1]).unwrap();
    sim.set_default_joint(joint(1e9, 30.0)).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    let mut weights = [0.0; 2];
    for (k, ((lo, hi), rho)) in corners.iter().zip(densities).enumerate() {
        let [a, b, c] = [0, 1, 2].map(|d| hi[d] - lo[d]);
        let mass = rho * a * b * c;
        weights[k] = mass * G;
        let i = k + 1;
        assert_eq!(sim.bodies().densities()[i], rho);
        assert!(close(sim.bodies().masses()[i], mass), "body {i}: mass");
        // The principal moments of a cuboid, in any order of the body axes.
        let mut expected = [b * b + c * c, a * a + c * c, a * a + b * b].map(|s| mass * s / 12.0);
        let mut got = sim.bodies().principal_inertia()[i].to_array();
        expected.sort_by(f64::total_cmp);
        got.sort_by(f64::total_cmp);
        for (g, e) in got.into_iter().zip(expected) {
            assert!(
                close(g, e),
                "body {i}: moments {got:?}, expected {expected:?}"
            );
        }
    }
    let report = sim.solve(1e-6, 200_000).unwrap();
    assert!(report.converged, "{report:?}");
    let largest = weights[0].max(weights[1]);
    // The solve's bound, and a rounding allowance far below it.
    let tolerance = report.ratio * largest + 1e-12 * largest;
    for (k, weight) in weights.into_iter().enumerate() {
        let i = k + 1;
        let force = sim.contact_forces()[i];
        let off = (force - DVec3::Z * weight).length();
        println!("body {i}: contact force {force:?}, weight {weight}, off by {off:.3e}");
        assert!(off <= tolerance, "body {i}: {force:?} against {weight}");
        let contacts = sim.contacts();
        let c = contacts
            .list
            .iter()
            .position(|c| c.bodies == [0, i as u32])
            .expect("no contact with the base");
        let normal: f64 = contacts.subs_of(c).iter().map(|s| s.normal_force).sum();
        assert!(
            (normal - weight).abs() <= tolerance + 1e-9 * weight,
            "body {i}: normal force {normal}, weight {weight}"
        );
    }
}

/// The angle between two vectors (0 when one is zero).
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// A block pushed sideways on a fixed base, below its friction limit, holds an elastic
/// shear force; both bodies are then turned together about an axis through their centroids,
/// oblique to the contact (so that the contact plane both tilts and spins about its normal).
/// The stored shear force must turn with them: at the end, for each sub-contact, the same
/// magnitude, the direction `R` times the old one (`R` the rotation by the total angle about
/// the axis, a formula), and in the contact plane at every step.
///
/// The turn, about the axis through the block's centroid as it settled: the base is
/// prescribed the spin ω and, at each step, the velocity `ω × (c - c_B)` of its centroid `c`
/// (made on the axis, a quarter of a millimetre off it after the settling); the block is
/// given the same spin and made 1e18 times denser, without gravity or load, so
/// that it turns by its own inertia (a cube: ω stays along the axis) and its contact force
/// `F` moves it by `F T² / 2m` (about 5e-16 m) over the run of duration `T`. (A pair of two
/// prescribed bodies is not a candidate pair: one of them must be free.) The two bodies'
/// velocities are then the same at every point, and the shear increment is zero but for
/// that drift: a sub-contact's shear changes in length by at most `ks A F T² / 2m`, and by
/// the rounding of its turns (a few 1e-16 of it per step).
///
/// The rule (project on the new plane keeping the length, then turn about the normal by the
/// mean spin) keeps the length exactly; its direction is exact to first order per step: the
/// rescaled projection of a step that tilts the plane by α misses the rotation by at most
/// α²/4, the twist by O(a³) for a step's turn a. Over θ / a steps the direction is within
/// θ a of `R` times the old one: that is the tolerance (a missing twist would be 0.4 rad
/// off). The contact update of a step reads the spin the bodies turn with in that step, so
/// the shear turns one step before the bodies do: the last step is taken at rest, and its
/// contact is at the turned poses with the shear turned as far.
#[test]
fn a_stored_shear_force_turns_with_the_bodies_turned_together() {
    let axis = DVec3::new(1.0, 2.0, 2.0) / 3.0;
    let base = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
    // Its centroid 1.5 along the axis from the base's, (0, 0, -0.5).
    let block = ConvexBlock::cuboid([0.0, 0.5, 0.0], [1.0, 1.5, 1.0]).unwrap();
    let (centre_a, centre_b) = (base.centroid(), block.centroid());
    assert!((centre_b - centre_a).cross(axis).length() < 1e-15);
    let mut sim = Simulation::new(&BlockSystem::new(vec![base, block]), 2500.0).unwrap();
    sim.fix(0).unwrap();
    let stiffness = 1e8; // kn = ks, Pa/m
    sim.set_default_joint(joint(stiffness, 30.0)).unwrap();
    let weight = sim.bodies().masses()[1] * G;
    // A quarter of the weight, at the middle of the contact: no tipping moment about it, so
    // the four corners share the load; each holds a quarter of the push, below its friction
    // limit (tan 30° times a quarter of the weight).
    let push = DVec3::new(0.3f64.cos(), 0.3f64.sin(), 0.0) * (0.25 * weight);
    let middle = DVec3::new(centre_b.x, centre_b.y, 0.0);
    sim.apply_force_at(1, push, middle).unwrap();
    let report = sim.solve(1e-6, 200_000).unwrap();
    assert!(report.converged, "{report:?}");
    let contact = |sim: &Simulation| -> (DVec3, Vec<SubContact>) {
        let contacts = sim.contacts();
        assert_eq!(contacts.list.len(), 1, "one contact");
        assert_eq!(contacts.list[0].bodies, [0, 1]);
        (contacts.list[0].normal, contacts.subs_of(0).to_vec())
    };
    let (normal0, before) = contact(&sim);
    assert_eq!(before.len(), 4);
    let held: DVec3 = before.iter().map(|s| s.shear_force).sum();
    // The shear force on the block balances the push (to the solve's bound).
    assert!(
        (held + push).length() <= report.ratio * weight + 1e-12 * weight,
        "held {held:?} against the push {push:?}"
    );
    for s in &before {
        assert_eq!(s.state, SubState::Elastic);
        assert!(s.shear_force.length() > 0.2 * push.length());
    }

    // Turned together, without gravity or load, at the time step of the settling.
    let dt = sim.timestep().unwrap();
    sim.set_timestep(Some(dt)).unwrap();
    sim.set_gravity(DVec3::ZERO).unwrap();
    sim.apply_force(1, DVec3::ZERO).unwrap();
    sim.apply_moment(1, DVec3::ZERO).unwrap();
    sim.set_density(1, 2500.0 * 1e18).unwrap();
    let force = sim.contact_forces()[1].length();
    let (theta, a) = (0.6, 4e-5); // the total turn, a step's turn (radians)
    let steps = (theta / a) as u64;
    let spin = axis * (a / dt);
    let start = sim.bodies().poses().to_vec();
    // The axis through the block's centroid as it settled (a quarter of a millimetre from
    // where it was made): the block turns in place, the base's centroid about the axis.
    let centre = start[1].translation;
    sim.set_velocity(1, DVec3::ZERO, spin).unwrap();
    for step in 0..=steps {
        if step < steps {
            let c = sim.bodies().poses()[0].translation;
            sim.prescribe(0, spin.cross(c - centre), spin).unwrap();
        } else {
            sim.prescribe(0, DVec3::ZERO, DVec3::ZERO).unwrap();
            sim.set_velocity(1, DVec3::ZERO, DVec3::ZERO).unwrap();
        }
        sim.step().unwrap();
        let (n, subs) = contact(&sim);
        for s in &subs {
            assert!(
                s.shear_force.dot(n).abs() <= 1e-12 * s.shear_force.length(),
                "step {step}: the shear force leaves the contact plane"
            );
            assert_eq!(s.state, SubState::Elastic, "step {step}");
        }
    }
    // The total turn: `steps` steps of `a` (the last one at rest).
    let turned = steps as f64 * a;
    let r = DQuat::from_axis_angle(axis, turned);
    let poses = sim.bodies().poses();
    for i in [0, 1] {
        let (p, q) = (poses[i], start[i]);
        assert!(
            p.rotation.dot(r * q.rotation).abs() > 1.0 - 1e-12,
            "body {i} turned to {:?}, expected {:?}",
            p.rotation,
            r * q.rotation
        );
        // The linear steps of the base's centroid move it off its circle by θ a / 2 times
        // its distance from the axis (a quarter of a millimetre); the block turns in place.
        let arm = q.translation - centre;
        let radius = (arm - axis * arm.dot(axis)).length();
        let moved = p.translation.distance(centre + r * arm);
        assert!(
            moved <= 0.5 * turned * a * radius + 1e-12,
            "body {i}'s centroid is {moved} off its turned place"
        );
    }
    let (normal, after) = contact(&sim);
    assert!(angle(normal, r * normal0) < 1e-9, "normal {normal:?}");
    let allowed = turned * a;
    let duration = steps as f64 * dt;
    let drift = force * duration * duration / (2.0 * sim.bodies().masses()[1]);
    let (mut worst, mut longer): (f64, f64) = (0.0, 0.0);
    for s in &after {
        // The sub-contact that was at this point before the turn.
        let old = before
            .iter()
            .min_by(|x, y| {
                let d = |o: &SubContact| (centre + r * (o.point - centre)).distance(s.point);
                d(x).total_cmp(&d(y))
            })
            .unwrap();
        let expected = r * old.shear_force;
        let length = old.shear_force.length();
        assert!(
            (s.shear_force.length() - length).abs()
                <= stiffness * s.area * drift + steps as f64 * 1e-15 * length,
            "magnitude {} from {length}",
            s.shear_force.length()
        );
        let off = angle(s.shear_force, expected);
        worst = worst.max(off);
        longer = longer.max((s.shear_force.length() / length - 1.0).abs());
        assert!(
            off <= allowed,
            "{:?}: shear {:?}, expected {expected:?}: {off:.3e} rad off (allowed {allowed:.3e})",
            s.point,
            s.shear_force
        );
    }
    println!(
        "{steps} steps of {a} rad, dt {dt:.3e} s, drift {drift:.1e} m: worst direction \
         {worst:.3e} rad (allowed {allowed:.3e}), length {longer:.1e}; a missing twist would \
         be {:.3} rad off",
        turned * axis.dot(normal0)
    );
}
