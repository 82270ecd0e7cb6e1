//! Excavation of a running simulation (issue 19, docs/mechanics.md "Excavation"): removed
//! bodies leave their forces on the rock that stays, relaxed linearly to zero; then the rock
//! they held falls freely. References are formulas computed here.

use penedge::glam::DVec3;
use penedge::mechanics::{JointModel, MechanicsError, Simulation};
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
