//! Checks of the mechanics left open by the audit of issue 18: a body's own density sets its
//! mass, inertia and weight (`Simulation::set_density`). References are formulas computed
//! here, never numbers copied from a run.

use penedge::glam::DVec3;
use penedge::mechanics::{JointModel, Simulation};
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
