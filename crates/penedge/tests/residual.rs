//! Verification of the residual strength (docs/verification.md, "Residual strength"): after
//! its bond fails, a joint has the residual friction angle and cohesion. The references are
//! formulas computed here.

use penedge::glam::DVec3;
use penedge::mechanics::{Damping, JointModel, Simulation, SubState};
use penedge::{BlockSystem, ConvexBlock};

const G: f64 = 9.81;

/// A slab glued to a fixed base by cohesion, pushed sideways by a growing force until every
/// bond has failed (peak strength c A + N tan φ), then pushed by a constant force F between
/// the residual and the peak friction, `N tan φr < F < N tan φ`: the peak strength would hold
/// it, the residual does not, and it slides with `a = (F − cr A − N tan φr) / m`, undamped.
#[test]
fn a_block_whose_bond_broke_slides_on_the_residual_friction() {
    let (kn, density, phi, phi_r, cohesion, residual_cohesion) =
        (1e9, 25000.0, 35.0f64, 20.0f64, 2e4, 500.0);
    let base = ConvexBlock::cuboid([-3.0, -3.0, -1.0], [3.0, 3.0, 0.0]).unwrap();
    let thickness = 0.04;
    let (m, area) = (density * thickness, 1.0);
    let normal = m * G;
    let sink = normal / (kn * area);
    let slab = ConvexBlock::cuboid([-0.5, -0.5, -sink], [0.5, 0.5, thickness - sink]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![base, slab]), density).unwrap();
    sim.fix(0).unwrap();
    sim.set_default_joint(JointModel {
        kn,
        ks: kn,
        friction: phi,
        cohesion,
        residual_friction: Some(phi_r),
        residual_cohesion,
        ..JointModel::default()
    })
    .unwrap();
    sim.set_damping(Damping {
        local: 0.8,
        viscous: 0.0,
    })
    .unwrap();
    let push = DVec3::new(0.6, 0.8, 0.0);
    let peak = cohesion * area + normal * phi.to_radians().tan();
    // Load up quasi-statically until every bond has failed (within 2 % of the peak).
    loop {
        let load = 2e5 * sim.time();
        assert!(
            load < 1.02 * peak,
            "bonds still hold at {load} (peak {peak})"
        );
        sim.apply_force(1, push * load).unwrap();
        sim.step().unwrap();
        if sim.contacts().subs.iter().all(|s| !s.bonded) {
            break;
        }
    }
    // Between the residual and the peak friction: slides on the residual only.
    let residual = residual_cohesion * area + normal * phi_r.to_radians().tan();
    let force = 0.5 * (residual + normal * phi.to_radians().tan());
    assert!(force > residual && force < peak);
    sim.set_damping(Damping::default()).unwrap();
    sim.apply_force(1, push * force).unwrap();
    sim.cycle(100).unwrap();
    let (v0, t0) = (sim.bodies().velocities()[1].dot(push), sim.time());
    sim.cycle(400).unwrap();
    let a = (sim.bodies().velocities()[1].dot(push) - v0) / (sim.time() - t0);
    let expected = (force - residual) / m;
    println!("residual: acceleration {a} vs {expected}");
    assert!(sim
        .contacts()
        .subs
        .iter()
        .all(|s| s.state == SubState::Sliding && !s.bonded));
    assert!((a - expected).abs() < 0.01 * expected, "{a} vs {expected}");
}
