//! Excavation of a running simulation (issue 19, docs/mechanics.md "Excavation"): removed
//! bodies leave their forces on the rock that stays, relaxed linearly to zero; then the rock
//! they held falls freely. References are formulas computed here.

use penedge::glam::DVec3;
use penedge::mechanics::{Bolt, JointModel, MechanicsError, Simulation};
use penedge::{BlockSystem, ConvexBlock};

const G: f64 = 9.81;
const DENSITY: f64 = 2500.0;

/// A fixed base and five 1 m cubes stacked on it (bodies 1 to 5), settled.
fn column() -> Simulation {
    let mut blocks = vec![ConvexBlock::cuboid([-1.0, -1.0, -1.0], [1.0, 1.0, 0.0]).unwrap()];
    for k in 0..5 {
        let z = k as f64;
        blocks.push(ConvexBlock::cuboid([-0.5, -0.5, z], [0.5, 0.5, z + 1.0]).unwrap());
    }
    let mut sim = Simulation::new(&BlockSystem::new(blocks), DENSITY).unwrap();
    sim.fix(0).unwrap();
    sim.set_default_joint(JointModel {
        kn: 1e9,
        ks: 1e9,
        ..JointModel::default()
    })
    .unwrap();
    assert!(sim.solve(1e-6, 200_000).unwrap().converged);
    sim
}

/// The momentum of bodies `ids` (half-step velocities).
fn momentum(sim: &Simulation, ids: &[usize]) -> DVec3 {
    let b = sim.bodies();
    ids.iter().map(|&i| b.velocities()[i] * b.masses()[i]).sum()
}

fn centre_z(sim: &Simulation, ids: &[usize]) -> f64 {
    let b = sim.bodies();
    let m: f64 = ids.iter().map(|&i| b.masses()[i]).sum();
    ids.iter()
        .map(|&i| b.poses()[i].translation.z * b.masses()[i])
        .sum::<f64>()
        / m
}

/// The force of body `from` on body `on` through their contacts of the last step.
fn force_between(sim: &Simulation, from: usize, on: usize) -> DVec3 {
    let c = sim.contacts();
    let mut f = DVec3::ZERO;
    for (k, contact) in c.list.iter().enumerate() {
        let [a, b] = [contact.bodies[0] as usize, contact.bodies[1] as usize];
        for s in c.subs_of(k) {
            if [a, b] == [from, on] {
                f += s.force(contact.normal);
            } else if [a, b] == [on, from] {
                f -= s.force(contact.normal);
            }
        }
    }
    f
}

/// The middle block of the column removed with a relaxation over `n` steps: the three
/// blocks above get, as a group (their contacts with each other cancel), the force block 2
/// exerted on block 3 at the excavation times `1 - (j - 1) / n` at the `j`-th step, so
/// their momentum changes by `(F (1 - (j - 1)/n) - M g) dt` per step; after that they fall
/// freely: their centre of mass follows `z₀ + v₀ t - g t² / 2`. The block below stays.
#[test]
fn an_excavated_block_releases_its_load_gradually_then_the_rock_above_falls() {
    let n = 200u64;
    let mut sim = column();
    let above = [3, 4, 5];
    let mass = 3.0 * DENSITY; // three 1 m³ cubes
    let load = force_between(&sim, 2, 3);
    // Settled: block 2 carries the three blocks above.
    assert!((load.z - mass * G).abs() < 1e-4 * mass * G, "{load}");
    let below = sim.bodies().poses()[1].translation;
    let report = sim.excavate(&[2], n).unwrap();
    assert_eq!(report.removed, vec![2]);
    let loaded: Vec<usize> = report.loaded.iter().map(|l| l.0).collect();
    assert_eq!(loaded, vec![1, 3]);
    assert_eq!(report.loaded[1].1, load);
    assert!(sim.contacts().list.iter().all(|c| !c.bodies.contains(&2)));
    let dt = sim.timestep().unwrap();
    let tol = 1e-9 * mass * G;
    for j in 1..=n + 50 {
        let before = momentum(&sim, &above);
        sim.step().unwrap();
        let rate = (momentum(&sim, &above) - before) / dt;
        let share = if j <= n {
            1.0 - (j - 1) as f64 / n as f64
        } else {
            0.0
        };
        let expected = load * share - DVec3::new(0.0, 0.0, mass * G);
        assert!(
            (rate - expected).length() < tol,
            "step {j}: {rate} against {expected}"
        );
    }
    // Free fall from here: the centre of mass on the parabola from its state now (the
    // velocity at this step's time is the half-step one less g dt / 2).
    let (z0, v0) = (
        centre_z(&sim, &above),
        momentum(&sim, &above).z / mass - 0.5 * G * dt,
    );
    assert!(v0 < -0.5 * G * n as f64 * dt * 0.9, "not falling: {v0}");
    for k in 1..=300 {
        sim.step().unwrap();
        let t = k as f64 * dt;
        let z = z0 + v0 * t - 0.5 * G * t * t;
        assert!((centre_z(&sim, &above) - z).abs() < 1e-9, "step {k}");
    }
    // The block below stays on the base: unloaded of the three blocks' weight, it rises by
    // less than twice its elastic closure under them, 3 m g / (kn A) (no overshoot beyond
    // an undamped spring's).
    let closure = 3.0 * DENSITY * G / 1e9;
    let rise = sim.bodies().poses()[1].translation - below;
    assert!(rise.length() < 2.0 * closure, "{rise}");
    assert_eq!(sim.bodies().velocities()[2], DVec3::ZERO);
}

/// Without relaxation the load goes at once; a removed body cannot be used again.
#[test]
fn an_excavation_without_relaxation_releases_at_once_and_removed_bodies_are_refused() {
    let mut sim = column();
    sim.excavate(&[2], 0).unwrap();
    let before = momentum(&sim, &[3, 4, 5]);
    sim.step().unwrap();
    let dt = sim.timestep().unwrap();
    let rate = (momentum(&sim, &[3, 4, 5]) - before) / dt;
    let weight = 3.0 * DENSITY * G;
    assert!((rate.z + weight).abs() < 1e-9 * weight, "{rate}");
    assert_eq!(sim.removed(), vec![false, false, true, false, false, false]);
    assert_eq!(sim.excavate(&[2], 10), Err(MechanicsError::Removed(2)));
    assert_eq!(sim.fix(2), Err(MechanicsError::Removed(2)));
    assert_eq!(sim.free(2), Err(MechanicsError::Removed(2)));
    assert_eq!(
        sim.set_velocity(2, DVec3::X, DVec3::ZERO),
        Err(MechanicsError::Removed(2))
    );
    assert!(matches!(
        sim.excavate(&[9], 10),
        Err(MechanicsError::UnknownBody { id: 9, .. })
    ));
}

/// A run saved in the middle of a relaxation goes on bit for bit.
#[test]
fn a_relaxation_survives_a_restart() {
    let mut straight = column();
    straight.excavate(&[2], 100).unwrap();
    let mut first = straight.clone();
    straight.cycle(160).unwrap();
    first.cycle(40).unwrap();
    let mut resumed = Simulation::from_state_str(&first.to_state_string().unwrap()).unwrap();
    assert_eq!(resumed.removed(), first.removed());
    resumed.cycle(120).unwrap();
    assert_eq!(resumed.bodies().poses(), straight.bodies().poses());
    assert_eq!(
        resumed.bodies().velocities(),
        straight.bodies().velocities()
    );
    assert_eq!(resumed.contacts().subs, straight.contacts().subs);
}

/// Cubes of sides `sides` (bodies 1, 2, ...) standing apart on a fixed base (body 0), joints
/// of normal stiffness 1e9 and shear stiffness 5e8.
fn cubes(sides: &[f64]) -> Simulation {
    let mut blocks = vec![ConvexBlock::cuboid([-1.0, -1.0, -1.0], [9.0, 1.0, 0.0]).unwrap()];
    for (k, &a) in sides.iter().enumerate() {
        let x = 2.0 * k as f64;
        blocks.push(ConvexBlock::cuboid([x, 0.0, 0.0], [x + a, a, a]).unwrap());
    }
    let mut sim = Simulation::new(&BlockSystem::new(blocks), DENSITY).unwrap();
    sim.fix(0).unwrap();
    sim.set_default_joint(JointModel {
        kn: 1e9,
        ks: 5e8,
        ..JointModel::default()
    })
    .unwrap();
    sim
}

/// The mass-scaling factors the documented rule gives (docs/mechanics.md, "Critical time
/// step" and "Mass scaling") to a system of cubes of sides `sides` (body `i + 1` has side
/// `sides[i]`) of which the bodies `free` are free: each free cube's critical step
/// `2 / √(max(2 k S / m, 2 k R / I_min))`, `k = max(kn, ks)`, `S = 6 a²` its surface and
/// `R = Σ_f A_f max_v |r_v|² = 6 a² · 3 a² / 4` (every vertex of a cube at `√3 a / 2` from
/// its centroid), `m = ρ a³`, `I_min = ρ a⁵ / 6`; the median `t` of the free cubes' steps
/// (sorted, the one at index `len / 2`); a free cube's factor `max((t / dt)², 1)`, every
/// other body's 1.
fn expected_scales(sides: &[f64], free: &[usize]) -> Vec<f64> {
    let k = 1e9;
    let step = |a: f64| {
        let (s, r) = (6.0 * a * a, 6.0 * a * a * 0.75 * a * a);
        let (m, i) = (DENSITY * a.powi(3), DENSITY * a.powi(5) / 6.0);
        2.0 / (2.0 * k * s / m).max(2.0 * k * r / i).sqrt()
    };
    let mut steps: Vec<f64> = free.iter().map(|&b| step(sides[b - 1])).collect();
    steps.sort_by(f64::total_cmp);
    let t = steps[steps.len() / 2];
    (0..=sides.len())
        .map(|b| {
            if free.contains(&b) {
                (t / step(sides[b - 1])).powi(2).max(1.0)
            } else {
                1.0
            }
        })
        .collect()
}

fn assert_scales(sim: &Simulation, expected: &[f64]) {
    let got = sim.bodies().mass_scales();
    assert_eq!(got.len(), expected.len());
    for (b, (g, e)) in got.iter().zip(expected).enumerate() {
        assert!((g - e).abs() <= 1e-9 * e, "body {b}: {g} vs {e} ({got:?})");
    }
}

/// Mass scaling stays the rule's after an excavation: the factors are computed again from
/// the free bodies that stay (the removed ones, fixed, are no longer in the median and go
/// back to 1), also for a simulation read back from a restart file, which keeps that the
/// scaling is on.
#[test]
fn an_excavation_rescales_the_masses_from_the_free_bodies_that_stay() {
    let sides = [0.1, 0.2, 0.4, 0.8, 1.0];
    let mut sim = cubes(&sides);
    sim.set_mass_scaling(true).unwrap();
    assert!(sim.mass_scaling());
    assert_scales(&sim, &expected_scales(&sides, &[1, 2, 3, 4, 5]));
    sim.cycle(10).unwrap();
    let mut restored = Simulation::from_state_str(&sim.to_state_string().unwrap()).unwrap();
    assert!(restored.mass_scaling());
    // The two largest go: the median of the free cubes' steps falls from the 0.4 m cube's
    // to the 0.2 m cube's (the 0.1 m cube's factor from 4 to 2).
    let after = expected_scales(&sides, &[1, 2, 3]);
    assert!(
        (after[1] - 2.0).abs() < 1e-12
            && (expected_scales(&sides, &[1, 2, 3, 4, 5])[1] - 4.0).abs() < 1e-12
    );
    for s in [&mut sim, &mut restored] {
        s.excavate(&[4, 5], 0).unwrap();
        assert_scales(s, &after);
        s.step().unwrap();
    }
    assert_eq!(restored.bodies().poses(), sim.bodies().poses());
    // Off, nothing is scaled again by an excavation.
    let mut plain = cubes(&sides);
    plain.excavate(&[5], 0).unwrap();
    assert!(!plain.mass_scaling());
    assert_scales(&plain, &[1.0; 6]);
}

/// Only bodies with a load are reported and relaxed (docs/mechanics.md, "Excavation"):
/// before any step no bolt and no contact has a force, so an excavation then loads nothing;
/// after a step, a body that the removed one touches through an open contact (detected
/// within the gap, no force) is not loaded either, while the base it stands on is, with its
/// weight.
#[test]
fn an_excavation_reports_only_the_bodies_it_loads() {
    let bolt = Bolt {
        collar: DVec3::new(0.0, 0.5, 0.5),
        direction: DVec3::X,
        length: 1.9,
        stiffness: 1e8,
        capacity: 1e6,
        rupture_strain: None,
        dowel: None,
    };
    // Two 1 m cubes 0.5 mm apart (within the detection gap of 1e-3 × 1 m), a bolt across.
    let blocks = vec![
        ConvexBlock::cuboid([-1.0, -1.0, -1.0], [3.0, 2.0, 0.0]).unwrap(),
        ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap(),
        ConvexBlock::cuboid([1.0005, 0.0, 0.0], [2.0005, 1.0, 1.0]).unwrap(),
    ];
    let system = BlockSystem::new(blocks);
    let fresh = || {
        let mut sim = Simulation::new(&system, DENSITY).unwrap();
        sim.fix(0).unwrap();
        sim.set_default_joint(JointModel {
            kn: 1e9,
            ks: 1e9,
            ..JointModel::default()
        })
        .unwrap();
        sim
    };
    let mut before = fresh();
    before.add_bolt(bolt).unwrap();
    assert_eq!(before.bolts().elements().len(), 1);
    let report = before.excavate(&[2], 10).unwrap();
    assert_eq!(report.removed, vec![2]);
    assert_eq!(report.loaded, vec![]);
    // Nothing relaxes: the cube left feels its weight and its contact with the base only,
    // as in a simulation built without the removed cube.
    let mut without =
        Simulation::new(&BlockSystem::new(system.blocks()[..2].to_vec()), DENSITY).unwrap();
    without.fix(0).unwrap();
    without
        .set_default_joint(*before.joints().of_set(None))
        .unwrap();
    before.cycle(20).unwrap();
    without.cycle(20).unwrap();
    let [z, z0] = [&before, &without].map(|s| s.bodies().poses()[1].translation.z);
    assert!((z - z0).abs() < 1e-12, "{z} vs {z0}");

    let mut after = fresh();
    assert!(after.solve(1e-6, 200_000).unwrap().converged);
    let open = after.contacts().list.iter().enumerate().any(|(k, c)| {
        c.bodies == [1, 2]
            && after
                .contacts()
                .subs_of(k)
                .iter()
                .all(|s| s.force(c.normal) == DVec3::ZERO)
    });
    assert!(open, "the cubes should touch through an open contact");
    let report = after.excavate(&[2], 10).unwrap();
    let weight = DENSITY * G;
    assert_eq!(report.loaded.len(), 1, "{:?}", report.loaded);
    let (body, force) = report.loaded[0];
    assert_eq!(body, 0);
    assert!((force.z + weight).abs() < 1e-4 * weight, "{force}");
}
