//! Verification of rock bolts and applied moments (issue 19, docs/verification.md, "Rock
//! bolts"). Every reference is a formula computed here, never a number copied from a run.

use penedge::glam::DVec3;
use penedge::mechanics::{Bolt, BoltState, Dowel, JointModel, MechanicsError, Simulation};
use penedge::{BlockSystem, ConvexBlock};

const G: f64 = 9.81;
const DENSITY: f64 = 2500.0;

/// A fixed ceiling (z in [1.1, 2]) and a free 1 m cube (z in [0, 1]) 0.1 m below it, held by
/// a bolt from the ceiling's top (0, 0, 2) straight down to the cube's centroid: the
/// bolt's single element is 1.5 m long, anchored at the plate on the ceiling and at the
/// centroid (so the cube hangs without turning).
fn hanging_cube(stiffness: f64, capacity: f64, rupture_strain: Option<f64>) -> Simulation {
    let ceiling = ConvexBlock::cuboid([-1.0, -1.0, 1.1], [1.0, 1.0, 2.0]).unwrap();
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![ceiling, cube]), DENSITY).unwrap();
    sim.fix(0).unwrap();
    let id = sim
        .add_bolt(Bolt {
            collar: DVec3::new(0.0, 0.0, 2.0),
            direction: DVec3::new(0.0, 0.0, -1.0),
            length: 1.5,
            stiffness,
            capacity,
            rupture_strain,
            dowel: None,
        })
        .unwrap();
    assert_eq!(id, 0);
    let elements = sim.bolts().elements();
    assert_eq!(elements.len(), 1);
    assert_eq!(elements[0].bodies(), [0, 1]);
    assert!((elements[0].rest_length() - 1.5).abs() < 1e-12);
    sim
}

/// A block hanging from a bolt: at equilibrium the bolt force is the weight and the
/// elongation (and the cube's drop) W / k.
#[test]
fn a_block_hanging_from_a_bolt_stretches_it_by_its_weight_over_the_stiffness() {
    let k = 1e7;
    let mut sim = hanging_cube(k, 1e6, None);
    let report = sim.solve(1e-7, 200_000).unwrap();
    assert!(report.converged, "{report:?}");
    let weight = DENSITY * 1.0 * G;
    let e = &sim.bolts().elements()[0];
    assert!((e.force() - weight).abs() < 1e-6 * weight, "{}", e.force());
    assert!((e.elongation() - weight / k).abs() < 1e-6 * weight / k);
    assert_eq!(e.state(), BoltState::Elastic);
    let drop = 0.5 - sim.bodies().poses()[1].translation.z;
    assert!((drop - weight / k).abs() < 1e-6 * weight / k, "{drop}");
    // The time step is bounded by the bolt too: at most 2 / √(2 k / m).
    let bound = 2.0 / (2.0 * k / (DENSITY * 1.0)).sqrt();
    assert!(sim.critical_timestep().unwrap() <= bound);
}

/// A bolt across three bodies is a chain: a fixed ceiling (z in [2.2, 3]) and two cubes
/// hanging one under the other (z in [1.1, 2.1] and [0, 1]), a 2.5 m bolt from the ceiling's
/// top down to the lower cube's centroid. Its nodes: the plate (t = 0), the middle of its run
/// through the upper cube (t = 1.4, that cube's centroid) and its end (t = 2.5); so two
/// elements of 1.4 and 1.1 m, each of stiffness EA / l with EA = k × 2.5. At equilibrium the
/// upper element carries both weights, the lower one the lower cube's: the cubes drop by
/// e₁ = 2W l₁ / EA and e₁ + e₂, e₂ = W l₂ / EA.
#[test]
fn a_bolt_across_three_bodies_is_a_chain_of_springs_carrying_what_hangs_below() {
    let ceiling = ConvexBlock::cuboid([-1.0, -1.0, 2.2], [1.0, 1.0, 3.0]).unwrap();
    let upper = ConvexBlock::cuboid([-0.5, -0.5, 1.1], [0.5, 0.5, 2.1]).unwrap();
    let lower = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let system = BlockSystem::new(vec![lower, ceiling, upper]);
    let mut sim = Simulation::new(&system, DENSITY).unwrap();
    sim.fix(1).unwrap();
    let k = 1e7;
    sim.add_bolt(Bolt {
        collar: DVec3::new(0.0, 0.0, 3.0),
        direction: DVec3::new(0.0, 0.0, -1.0),
        length: 2.5,
        stiffness: k,
        capacity: 1e6,
        rupture_strain: None,
        dowel: None,
    })
    .unwrap();
    let elements = sim.bolts().elements().to_vec();
    assert_eq!(elements.len(), 2);
    assert_eq!(elements[0].bodies(), [1, 2]);
    assert_eq!(elements[1].bodies(), [2, 0]);
    let (l1, l2) = (1.4, 1.1);
    assert!((elements[0].rest_length() - l1).abs() < 1e-12);
    assert!((elements[1].rest_length() - l2).abs() < 1e-12);
    let report = sim.solve(1e-7, 400_000).unwrap();
    assert!(report.converged, "{report:?}");
    let weight = DENSITY * G;
    let ea = k * 2.5;
    let (e1, e2) = (2.0 * weight * l1 / ea, weight * l2 / ea);
    let [first, second] = [sim.bolts().elements()[0], sim.bolts().elements()[1]];
    assert!((first.force() - 2.0 * weight).abs() < 1e-5 * weight);
    assert!((second.force() - weight).abs() < 1e-5 * weight);
    let poses = sim.bodies().poses();
    let drop_upper = 1.6 - poses[2].translation.z;
    let drop_lower = 0.5 - poses[0].translation.z;
    assert!((drop_upper - e1).abs() < 1e-5 * e1, "{drop_upper} {e1}");
    assert!(
        (drop_lower - (e1 + e2)).abs() < 1e-5 * (e1 + e2),
        "{drop_lower}"
    );
}

/// The elastic-then-yielding fall of a cube held by a bolt of capacity C < W, undamped:
/// from rest the bolt stretches as x(t) = (W / k)(1 − cos ωt) until k x = C, at
/// cos ωt_y = 1 − C / W, then it yields and the cube falls with the constant acceleration
/// (W − C) / m: x(t) = C / k + v_y (t − t_y) + ½ a (t − t_y)², within 1e-4.
#[test]
fn a_bolt_below_the_weight_yields_and_the_block_falls_at_the_analytic_rate() {
    let (k, m) = (1e7, DENSITY);
    let weight = m * G;
    let capacity = 0.5 * weight;
    let mut sim = hanging_cube(k, capacity, None);
    let omega = (k / m).sqrt();
    let t_y = (1.0 - capacity / weight).acos() / omega;
    let v_y = weight / k * omega * (omega * t_y).sin();
    let a = (weight - capacity) / m;
    let expected = |t: f64| capacity / k + v_y * (t - t_y) + 0.5 * a * (t - t_y).powi(2);
    for t in [0.3, 0.4, 0.5] {
        sim.run_until(t).unwrap();
        let (t, x) = (sim.time(), 0.5 - sim.bodies().poses()[1].translation.z);
        assert!(x > 100.0 * capacity / k);
        let want = expected(t);
        assert!(
            (x - want).abs() < 1e-4 * want,
            "t {t}: x {x}, expected {want}"
        );
        let e = &sim.bolts().elements()[0];
        assert_eq!(e.state(), BoltState::Yielding);
        assert_eq!(e.force(), capacity);
    }
}

/// Past its rupture strain the bolt breaks: no force any more, the cube falls freely
/// (acceleration g, from the second difference of its height).
#[test]
fn a_bolt_past_its_rupture_strain_breaks_and_the_block_falls_freely() {
    let weight = DENSITY * G;
    let mut sim = hanging_cube(1e7, 0.5 * weight, Some(0.01)); // breaks at 15 mm
    sim.run_until(0.3).unwrap();
    let e = sim.bolts().elements()[0];
    assert_eq!(e.state(), BoltState::Broken);
    assert_eq!(e.force(), 0.0);
    assert!(e.elongation() > 0.01 * 1.5);
    let dt = sim.timestep().unwrap();
    let mut z = [0.0; 3];
    for zk in &mut z {
        *zk = sim.bodies().poses()[1].translation.z;
        sim.cycle(100).unwrap();
    }
    let h = 100.0 * dt;
    let accel = (z[2] - 2.0 * z[1] + z[0]) / (h * h);
    assert!((accel + G).abs() < 1e-6 * G, "{accel}");
}

/// A roof wedge (a prism under two fixed blocks: faces dipping atan(h / a) from the roof
/// z = 0 to the apex at height h) held by a bolt through its centroid, tilted by β from the
/// vertical towards +x. The bolt's horizontal pull presses the wedge onto the right face;
/// at the limit the wedge slides down that face (the left one opens). Limit equilibrium
/// along the face's normal n = (h, a)/√(a² + h²) and downward tangent s = (a, −h)/√(a² + h²)
/// with friction φ: `(W + T d)·s = tan φ (W + T d)·n`, so
/// `T = W (h + a tan φ) / (tan φ (h sin β + a cos β) − a sin β + h cos β)`.
/// The tests bracket it: held with a capacity 5 % above, falling with one 5 % below.
fn roof_wedge(capacity_factor: f64) -> (Simulation, f64, f64) {
    let (a, h, depth) = (1.0, 1.5, 1.0);
    let (big, top) = (3.0, 3.0);
    let prism = |xz: &[[f64; 2]]| {
        let points: Vec<[f64; 3]> = [0.0, depth]
            .iter()
            .flat_map(|&y| xz.iter().map(move |p| [p[0], y, p[1]]))
            .collect();
        ConvexBlock::hull(&points).unwrap()
    };
    let wedge = prism(&[[-a, 0.0], [a, 0.0], [0.0, h]]);
    let right = prism(&[[a, 0.0], [big, 0.0], [big, top], [0.0, top], [0.0, h]]);
    let left = prism(&[[-a, 0.0], [-big, 0.0], [-big, top], [0.0, top], [0.0, h]]);
    let mut sim = Simulation::new(&BlockSystem::new(vec![left, right, wedge]), DENSITY).unwrap();
    sim.fix(0).unwrap();
    sim.fix(1).unwrap();
    let phi = 30.0f64;
    sim.set_default_joint(JointModel {
        kn: 1e10,
        ks: 1e9,
        friction: phi,
        cohesion: 0.0,
        tension: 0.0,
        ..JointModel::default()
    })
    .unwrap();
    let beta = 30f64.to_radians();
    let weight = DENSITY * a * h * depth * G;
    let tan = phi.to_radians().tan();
    let (sb, cb) = beta.sin_cos();
    let required = weight * (h + a * tan) / (tan * (h * sb + a * cb) - a * sb + h * cb);
    // Through the centroid (0, depth / 2, h / 3): no moment about it.
    let collar = DVec3::new(-h / 3.0 * beta.tan(), depth / 2.0, 0.0);
    sim.add_bolt(Bolt {
        collar,
        direction: DVec3::new(sb, 0.0, cb),
        length: 2.5,
        stiffness: 5e7,
        capacity: capacity_factor * required,
        rupture_strain: None,
        dowel: None,
    })
    .unwrap();
    assert_eq!(sim.bolts().elements()[0].bodies(), [2, 1]);
    (sim, required, weight)
}

fn wedge_displacement(sim: &Simulation, start: DVec3) -> f64 {
    sim.bodies().poses()[2].translation.distance(start)
}

#[test]
fn a_roof_wedge_holds_with_a_bolt_above_the_limit_equilibrium_force() {
    let (mut sim, required, weight) = roof_wedge(1.05);
    assert!(required > weight); // the tilted bolt must carry more than the weight
    let start = sim.bodies().poses()[2].translation;
    let report = sim.solve(1e-5, 40_000).unwrap();
    assert!(report.converged, "{report:?}");
    let e = sim.bolts().elements()[0];
    // Held: the bolt carries at least the limit force, below its capacity, and the wedge
    // moved by the order of the bolt's stretch (force / stiffness), not more.
    assert!(
        e.force() >= 0.98 * required && e.force() <= 1.05 * required,
        "{}",
        e.force()
    );
    assert!(wedge_displacement(&sim, start) < 10.0 * 1.05 * required / 5e7);
}

#[test]
fn a_roof_wedge_falls_with_a_bolt_below_the_limit_equilibrium_force() {
    let (mut sim, required, _) = roof_wedge(0.95);
    let start = sim.bodies().poses()[2].translation;
    let report = sim.solve(1e-5, 40_000).unwrap();
    assert!(!report.converged, "{report:?}");
    let e = sim.bolts().elements()[0];
    assert_eq!(e.state(), BoltState::Yielding);
    assert!(wedge_displacement(&sim, start) > 100.0 * required / 5e7);
}

/// A cube on a frictionless joint (φ = 0, no cohesion) pinned by a vertical bolt with a dowel
/// of shear stiffness k_s and capacity V, pushed sideways by P at the joint's height (no
/// tipping moment): below the capacity it stops at P / k_s with the dowel carrying P; above
/// it, the dowel slips at V and the cube slides with acceleration (P − V) / m. The bolt's
/// axial capacity is 1 N, so that its axial force (which resists sliding once the bolt
/// tilts) is negligible: only the dowel acts. The bolt runs from the cube (its first body)
/// into the base: the dowel's force on the base is +P.
fn pinned_cube(push: f64) -> Simulation {
    let base = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![base, cube]), DENSITY).unwrap();
    sim.fix(0).unwrap();
    sim.set_default_joint(JointModel {
        kn: 1e10,
        ks: 1e9,
        friction: 0.0,
        cohesion: 0.0,
        tension: 0.0,
        ..JointModel::default()
    })
    .unwrap();
    sim.add_bolt(Bolt {
        collar: DVec3::new(0.0, 0.0, 1.0),
        direction: DVec3::new(0.0, 0.0, -1.0),
        length: 1.5,
        stiffness: 1e7,
        capacity: 1.0,
        rupture_strain: None,
        dowel: Some(Dowel {
            stiffness: 1e7,
            capacity: 2e4,
        }),
    })
    .unwrap();
    sim.apply_force_at(1, DVec3::new(push, 0.0, 0.0), DVec3::ZERO)
        .unwrap();
    sim
}

#[test]
fn a_dowel_holds_a_push_below_its_capacity_at_push_over_stiffness() {
    let push = 1e4;
    let mut sim = pinned_cube(push);
    let report = sim.solve(1e-7, 400_000).unwrap();
    assert!(report.converged, "{report:?}");
    let e = sim.bolts().elements()[0];
    // On the base, +P; across the bolt, which the cube's shift of P / k_s tilts.
    let v = e.shear_force();
    assert!(
        (v.x - push).abs() < 1e-5 * push && v.y.abs() < 1e-5 * push,
        "{v}"
    );
    let dx = sim.bodies().poses()[1].translation.x;
    assert!((dx - push / 1e7).abs() < 1e-4 * push / 1e7, "{dx}");
}

#[test]
fn a_dowel_past_its_capacity_slips_and_the_block_slides() {
    let (push, capacity) = (3e4, 2e4);
    let mut sim = pinned_cube(push);
    // Past the elastic phase (V / k_s = 2 mm, reached at 0.02 s), while the bolt's tilt is
    // still below 1 % (its cosine 1 within 5e-5).
    sim.run_until(0.05).unwrap();
    let dt = sim.timestep().unwrap();
    let mut x = [0.0; 3];
    for xk in &mut x {
        *xk = sim.bodies().poses()[1].translation.x;
        sim.cycle(200).unwrap();
    }
    let h = 200.0 * dt;
    let accel = (x[2] - 2.0 * x[1] + x[0]) / (h * h);
    let want = (push - capacity) / DENSITY;
    assert!((accel - want).abs() < 1e-3 * want, "{accel} {want}");
    let v = sim.bolts().elements()[0].shear_force();
    assert!((v.length() - capacity).abs() < 1e-9 * capacity);
}

/// An applied moment M on a free body in zero gravity: its angular momentum grows as M t
/// (exactly, up to rounding); a force F at a point p adds F t to its momentum and
/// (p − c) × F t to its angular momentum.
#[test]
fn applied_moments_and_forces_at_a_point_turn_a_free_body() {
    let cube = ConvexBlock::cuboid([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![cube]), DENSITY).unwrap();
    sim.set_gravity(DVec3::ZERO).unwrap();
    let moment = DVec3::new(1.0, -2.0, 0.5);
    sim.apply_moment(0, moment).unwrap();
    sim.set_timestep(Some(1e-4)).unwrap();
    sim.cycle(1000).unwrap();
    // Velocities are at the half step: the first kick was a half one.
    let t = 999.5e-4;
    let l = sim.bodies().angular_momenta()[0];
    assert!((l - moment * t).length() < 1e-12 * moment.length(), "{l}");
    // A force at a point: its moment about the centroid replaces the moment above.
    let (force, point) = (DVec3::new(0.0, 0.0, 10.0), DVec3::new(0.5, 0.0, 0.0));
    let c = sim.bodies().poses()[0].translation;
    sim.apply_force_at(0, force, point).unwrap();
    let (v0, l0) = (
        sim.bodies().velocities()[0],
        sim.bodies().angular_momenta()[0],
    );
    sim.cycle(1000).unwrap();
    let t = 0.1;
    let dv = sim.bodies().velocities()[0] - v0;
    let dl = sim.bodies().angular_momenta()[0] - l0;
    assert!((dv - force * t / DENSITY).length() < 1e-12);
    assert!((dl - (point - c).cross(force) * t).length() < 1e-12, "{dl}");
    let applied: Vec<_> = sim.applied_moments().collect();
    assert_eq!(applied.len(), 1);
}

#[test]
fn bad_bolts_get_clear_errors() {
    let ceiling = ConvexBlock::cuboid([-1.0, -1.0, 1.1], [1.0, 1.0, 2.0]).unwrap();
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![ceiling, cube]), DENSITY).unwrap();
    let bolt = Bolt {
        collar: DVec3::new(0.0, 0.0, 2.0),
        direction: DVec3::new(0.0, 0.0, -1.0),
        length: 1.5,
        stiffness: 1e7,
        capacity: 1e5,
        rupture_strain: None,
        dowel: None,
    };
    let outside = Bolt {
        collar: DVec3::new(5.0, 5.0, 0.0),
        ..bolt
    };
    let e = sim.add_bolt(outside).unwrap_err();
    assert!(e.to_string().contains("outside the rock"), "{e}");
    let one = Bolt {
        length: 0.5,
        ..bolt
    };
    let e = sim.add_bolt(one).unwrap_err();
    assert!(e.to_string().contains("ties nothing"), "{e}");
    for (bad, name) in [
        (
            Bolt {
                length: 0.0,
                ..bolt
            },
            "bolt length",
        ),
        (
            Bolt {
                stiffness: -1.0,
                ..bolt
            },
            "bolt stiffness",
        ),
        (
            Bolt {
                capacity: f64::NAN,
                ..bolt
            },
            "bolt capacity",
        ),
        (
            Bolt {
                rupture_strain: Some(0.0),
                ..bolt
            },
            "bolt rupture_strain",
        ),
    ] {
        match sim.add_bolt(bad) {
            Err(MechanicsError::Parameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("{other:?}"),
        }
    }
    let zero = Bolt {
        direction: DVec3::ZERO,
        ..bolt
    };
    assert!(sim.add_bolt(zero).is_err());
    assert!(sim.apply_moment(2, DVec3::X).is_err());
    assert!(sim.apply_moment(0, DVec3::NAN).is_err());
    assert!(sim.bolts().is_empty());
}

/// Excavating the rock a bolt is anchored in ends the bolt's action (docs/mechanics.md,
/// "Excavation"): the cube hanging from the ceiling's bolt, settled, then the ceiling
/// removed. The bolt's element goes, its pull on the cube (the cube's weight) is the load
/// that relaxes, the time step is the one without the bolt, and with no relaxation the cube
/// falls freely at once: from its half-step velocity `v` and height `z₀` the leapfrog puts
/// it at `z₀ + n dt v − g dt² n (n + 1) / 2` after `n` steps, which is `½ g t²` below
/// `z₀` but for `v t` and the half-step term `½ g dt t` (both computed here).
#[test]
fn excavating_the_rock_a_bolt_is_anchored_in_ends_the_bolt_and_the_block_falls() {
    let weight = DENSITY * G;
    let mut settled = hanging_cube(1e7, 1e6, None);
    assert!(settled.solve(1e-7, 200_000).unwrap().converged);
    // The same blocks without a bolt: the time step the cube has alone.
    let ceiling = ConvexBlock::cuboid([-1.0, -1.0, 1.1], [1.0, 1.0, 2.0]).unwrap();
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let mut unbolted = Simulation::new(&BlockSystem::new(vec![ceiling, cube]), DENSITY).unwrap();
    unbolted.fix(0).unwrap();
    assert!(settled.critical_timestep().unwrap() < unbolted.critical_timestep().unwrap());

    // Relaxed over 50 steps: the bolt's pull is the load reported, and the first step after
    // the excavation still holds the cube (the load as before, less a 50th).
    let mut relaxed = settled.clone();
    let report = relaxed.excavate(&[0], 50).unwrap();
    assert_eq!(report.removed, vec![0]);
    assert_eq!(report.loaded.len(), 1);
    let (on, force) = report.loaded[0];
    assert_eq!(on, 1);
    assert!(
        (force - DVec3::Z * weight).length() < 1e-6 * weight,
        "{force}"
    );
    assert!(relaxed.bolts().elements().is_empty());
    let v0 = relaxed.bodies().velocities()[1];
    relaxed.step().unwrap();
    let dv = relaxed.bodies().velocities()[1] - v0;
    let dt = relaxed.timestep().unwrap();
    // The bolt's force at the last step is the relaxing load; the weight as the cube's.
    let expected = (force.z - weight) / DENSITY * dt;
    assert!(
        (dv.z - expected).abs() < 1e-9 * G * dt,
        "{dv} vs {expected}"
    );

    // Released at once: the cube falls freely.
    let mut sim = settled;
    sim.excavate(&[0], 0).unwrap();
    assert!(sim.bolts().elements().is_empty());
    assert_eq!(sim.bolts().len(), 1); // the bolt's id stays
    assert_eq!(
        sim.critical_timestep().unwrap(),
        unbolted.critical_timestep().unwrap()
    );
    let dt = sim.timestep().unwrap();
    let z0 = sim.bodies().poses()[1].translation.z;
    let v = sim.bodies().velocities()[1].z;
    let n = 2000u32;
    sim.cycle(n as u64).unwrap();
    let (nf, t) = (n as f64, n as f64 * dt);
    let expected = z0 + t * v - 0.5 * G * dt * dt * nf * (nf + 1.0);
    let z = sim.bodies().poses()[1].translation.z;
    assert!((z - expected).abs() < 1e-9, "{z} vs {expected}");
    let fall = z0 - z;
    let free_fall = 0.5 * G * t * t + 0.5 * G * dt * t - v * t;
    assert!((fall - free_fall).abs() < 1e-9, "{fall} vs {free_fall}");
    // It fell, far past the bolt's elongation (where the bolt would have caught it).
    assert!(fall > 10.0 * weight / 1e7, "{fall}");
}

/// A bolt cannot be installed into excavated rock: one that crosses or ends in a removed
/// body is refused naming it; removed rock at the collar is the opening (the bolt starts at
/// the rock face), so a bolt from there ties what it reaches, or nothing.
#[test]
fn a_bolt_into_excavated_rock_is_refused_naming_the_body() {
    // Bottom to top: the cube (body 0), the ceiling (1), a layer above it (2), a top (3).
    let blocks = vec![
        ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap(),
        ConvexBlock::cuboid([-1.0, -1.0, 1.1], [1.0, 1.0, 2.0]).unwrap(),
        ConvexBlock::cuboid([-1.0, -1.0, 2.1], [1.0, 1.0, 3.0]).unwrap(),
        ConvexBlock::cuboid([-1.0, -1.0, 3.1], [1.0, 1.0, 4.0]).unwrap(),
    ];
    let mut sim = Simulation::new(&BlockSystem::new(blocks), DENSITY).unwrap();
    for i in [1, 2, 3] {
        sim.fix(i).unwrap();
    }
    sim.excavate(&[2], 0).unwrap();
    let up = |from: f64, length: f64| Bolt {
        collar: DVec3::new(0.0, 0.0, from),
        direction: DVec3::Z,
        length,
        stiffness: 1e7,
        capacity: 1e5,
        rupture_strain: None,
        dowel: None,
    };
    // Ends in the removed layer; crosses it to the top.
    for bolt in [up(0.5, 2.0), up(0.5, 3.0)] {
        let e = sim.add_bolt(bolt).unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, MechanicsError::Bolt(_)), "{e:?}");
        assert!(text.contains("body 2, which was excavated"), "{text}");
    }
    // From inside the removed layer down: the opening, then the ceiling and the cube.
    let down = Bolt {
        collar: DVec3::new(0.0, 0.0, 2.5),
        direction: -DVec3::Z,
        length: 2.0,
        ..up(0.0, 1.0)
    };
    let id = sim.add_bolt(down).unwrap();
    let e = sim.bolts().elements()[0];
    assert_eq!((e.bolt(), e.bodies()), (id, [1, 0]));
    // From the ceiling's face (z = 2, the rock face) to the cube's centroid.
    assert!((e.rest_length() - 1.5).abs() < 1e-12, "{}", e.rest_length());
    // From inside the removed layer to the ceiling only: one body, ties nothing, and the
    // message says why the layer does not count.
    let short = Bolt {
        length: 1.0,
        ..down
    };
    let text = sim.add_bolt(short).unwrap_err().to_string();
    assert!(text.contains("ties nothing"), "{text}");
    assert!(text.contains("excavated body 2"), "{text}");
    // Only the removed layer: the bolt meets no rock that stays.
    let inside = Bolt {
        length: 0.2,
        ..down
    };
    let text = sim.add_bolt(inside).unwrap_err().to_string();
    assert!(
        text.contains("outside the rock") && text.contains("excavated body 2"),
        "{text}"
    );
    assert_eq!(sim.bolts().len(), 1);
}
