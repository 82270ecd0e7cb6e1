//! Verification of water pressure in the joints (docs/verification.md, "Water pressure in the
//! joints"): limit equilibrium with the water force `U` on the sliding planes, computed here
//! from the geometry, never copied from a run.

use penedge::block::FaceOrigin;
use penedge::glam::{DMat3, DQuat, DVec3};
use penedge::mechanics::{JointModel, Simulation, Water};
use penedge::{BlockSystem, ConvexBlock, Detector, Tolerance};
use support::face_area;

mod support;

const G: f64 = 9.81;

/// Every face of `block` tagged as joint set 0 (the set the water pressure is given for).
fn in_set_0(block: ConvexBlock) -> ConvexBlock {
    let n = block.n_faces();
    block
        .with_face_origins(vec![FaceOrigin::Joint { set: 0, joint: 0 }; n])
        .unwrap()
}

fn joint(friction: f64) -> JointModel {
    JointModel {
        kn: 1e8,
        ks: 1e8,
        friction,
        ..JointModel::default()
    }
}

/// Ramps gravity and the water pressure together from 0 to their full values over `ramp`
/// seconds (the ratio U / W, hence the limit friction angle, stays the one tested), then
/// holds them until `end`.
fn ramp(sim: &mut Simulation, pressure: f64, ramp: f64, end: f64) {
    while sim.time() < end {
        let f = (sim.time() / ramp).min(1.0);
        sim.set_gravity(DVec3::new(0.0, 0.0, -G * f)).unwrap();
        sim.set_water(Water::none().with_set_pressure(0, pressure * f).unwrap());
        sim.step().unwrap();
    }
}

/// (a) A slab on a plane inclined at θ (axes not aligned with the world's) with a uniform
/// water pressure u on its base, U = u A: it slides when
/// `tan φ < W sin θ / (W cos θ − U)`. It holds 1° above that angle (moves by the elastic
/// shear offset only) and slides 1° below it; dry, the same slab holds at both angles (the
/// water is what makes it slide).
#[test]
fn a_block_with_water_on_its_base_slides_below_the_effective_stress_friction_angle() {
    let (density, size) = (2500.0, [1.0, 0.8, 0.3]);
    let (weight, area) = (density * size[0] * size[1] * size[2] * G, size[0] * size[1]);
    let theta = 25f64.to_radians();
    let uplift = 0.3 * weight * theta.cos();
    let pressure = uplift / area;
    let critical = (weight * theta.sin() / (weight * theta.cos() - uplift))
        .atan()
        .to_degrees();
    let frame =
        DQuat::from_rotation_z(0.6) * DQuat::from_rotation_x(theta) * DQuat::from_rotation_z(0.4);
    let offset = DVec3::new(100.0, -50.0, 20.0);
    let base = ConvexBlock::cuboid([-5.0, -5.0, -1.0], [5.0, 5.0, 0.0]).unwrap();
    let slab = ConvexBlock::cuboid(
        [-size[0] / 2.0, -size[1] / 2.0, 0.0],
        [size[0] / 2.0, size[1] / 2.0, size[2]],
    )
    .unwrap();
    let system = BlockSystem::new(vec![
        in_set_0(base.transformed(frame, offset, 1.0)),
        in_set_0(slab.transformed(frame, offset, 1.0)),
    ]);
    let elastic = weight * theta.sin() / (1e8 * area);
    let n = frame * DVec3::Z;
    for (phi, wet, slides) in [
        (critical + 1.0, true, false),
        (critical - 1.0, true, true),
        (critical - 1.0, false, false),
    ] {
        let mut sim = Simulation::new(&system, density).unwrap();
        sim.fix(0).unwrap();
        sim.set_joint(0, joint(phi)).unwrap();
        let start = sim.bodies().poses()[1].translation;
        ramp(&mut sim, if wet { pressure } else { 0.0 }, 0.3, 0.5);
        let d = sim.bodies().poses()[1].translation - start;
        let moved = (d - n * d.dot(n)).length();
        println!("critical {critical:.3}°, φ = {phi:.3}°, water {wet}: moved {moved:.3e} m (elastic {elastic:.3e})");
        if slides {
            assert!(moved > 100.0 * elastic, "φ = {phi}°: moved only {moved}");
        } else {
            assert!(
                moved < 1.5 * elastic,
                "φ = {phi}°, water {wet}: moved {moved}"
            );
        }
        // The normal force the joints carry is the effective one, W cos θ − U, within the
        // undamped normal oscillation the ramp leaves (about 1 %).
        if !slides {
            let effective: f64 = sim.contacts().subs.iter().map(|s| s.normal_force).sum();
            let expected = weight * theta.cos() - if wet { uplift } else { 0.0 };
            assert!(
                (effective - expected).abs() < 0.02 * expected,
                "effective normal force {effective} vs {expected}"
            );
        }
    }
}

/// (b) Hoek and Bray's wedge with water: a wedge on two planes (normals n₁, n₂ towards the
/// wedge) along their intersection line d, with uniform pressures u₁, u₂ on the two planes:
/// water forces Uᵢ = uᵢ Aᵢ (Aᵢ the wedge's faces on the planes, from its vertices). Limit
/// equilibrium, `W + (N₁' + U₁) n₁ + (N₂' + U₂) n₂ − T d = 0`, gives the effective normal
/// reactions N'ᵢ and the critical friction angle `atan(T / (N₁' + N₂'))`. The simulated wedge
/// holds 1° above it and slides 1° below it.
#[test]
fn a_wedge_with_water_slides_below_its_limit_equilibrium_friction_angle() {
    let plunge = 35f64.to_radians();
    let d = DVec3::new(plunge.cos(), 0.0, -plunge.sin());
    let w = DVec3::new(plunge.sin(), 0.0, plunge.cos());
    let (b1, b2) = (40f64.to_radians(), 60f64.to_radians());
    let n1 = w * b1.cos() + DVec3::Y * b1.sin();
    let n2 = w * b2.cos() - DVec3::Y * b2.sin();
    let (density, pressure) = (2500.0, 1500.0);
    // The fixed blocks below each plane (n · x ≤ 0 within a box) and the wedge above both.
    let mut blocks = Vec::new();
    let box_planes: Vec<[f64; 3]> = [
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        -DVec3::X,
        -DVec3::Y,
        -DVec3::Z,
    ]
    .iter()
    .map(|a| a.to_array())
    .collect();
    for n in [n1, n2] {
        let mut planes = vec![n.to_array()];
        planes.extend(&box_planes);
        blocks.push(in_set_0(
            ConvexBlock::from_planes(&planes, &[0.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0]).unwrap(),
        ));
    }
    let planes = [
        (-n1).to_array(),
        (-n2).to_array(),
        w.to_array(),
        d.to_array(),
        (-d).to_array(),
    ];
    let wedge = in_set_0(ConvexBlock::from_planes(&planes, &[0.0, 0.0, 0.6, 0.5, 0.5]).unwrap());
    let weight = density * wedge.volume() * G;
    // The wedge's faces on the two planes: those whose outward normal is -nᵢ.
    let on_plane = |n: DVec3| {
        (0..wedge.n_faces())
            .find(|&f| wedge.planes()[f].normal.dot(-n) > 1.0 - 1e-9)
            .map(|f| face_area(&wedge, f))
            .unwrap()
    };
    let (u1, u2) = (pressure * on_plane(n1), pressure * on_plane(n2));
    blocks.push(wedge);
    // [n1 n2 -d] (N1, N2, T) = -W, W = (0, 0, -weight): the total normal reactions.
    let m = DMat3::from_cols(n1, n2, -d);
    let rhs = DVec3::new(0.0, 0.0, weight);
    let solve = |k: usize| {
        let mut cols = [n1, n2, -d];
        cols[k] = rhs;
        DMat3::from_cols(cols[0], cols[1], cols[2]).determinant() / m.determinant()
    };
    let (total1, total2, t) = (solve(0), solve(1), solve(2));
    let (eff1, eff2) = (total1 - u1, total2 - u2);
    assert!(eff1 > 0.0 && eff2 > 0.0 && t > 0.0);
    let critical = (t / (eff1 + eff2)).atan().to_degrees();
    let dry = (t / (total1 + total2)).atan().to_degrees();
    assert!(
        critical > dry + 2.0,
        "the water should matter: {critical}° vs {dry}° dry"
    );
    let system = BlockSystem::new(blocks);
    for (phi, slides) in [(critical + 1.0, false), (critical - 1.0, true)] {
        let mut sim = Simulation::new(&system, density).unwrap();
        sim.fix(0).unwrap();
        sim.fix(1).unwrap();
        sim.set_joint(
            0,
            JointModel {
                kn: 1e9,
                ks: 1e9,
                ..joint(phi)
            },
        )
        .unwrap();
        let start = sim.bodies().poses()[2].translation;
        ramp(&mut sim, pressure, 0.2, 0.5);
        let slid = (sim.bodies().poses()[2].translation - start).dot(d);
        println!(
            "wet wedge: critical {critical:.2}° (dry {dry:.2}°), φ = {phi:.2}°: slid {slid:.2e} m"
        );
        if slides {
            assert!(
                slid > 5e-3,
                "φ = {phi}° (critical {critical}°): slid only {slid}"
            );
        } else {
            assert!(
                slid < 5e-4,
                "φ = {phi}° (critical {critical}°): slid {slid}"
            );
        }
    }
}

/// The water forces are summed in contact order on one thread: a jointed block mass under a
/// water table that crosses it moves bit for bit the same with 1 and 3 threads.
#[test]
fn water_gives_the_same_motion_for_any_number_of_threads() {
    // Joint planes n · x = d through a 3 × 3 × 2 m box.
    const CUTS: [([f64; 3], f64); 4] = [
        ([1.0, 0.1, 0.0], 1.5),
        ([0.1, 1.0, 0.2], 1.4),
        ([0.0, 0.2, 1.0], 0.5),
        ([0.3, -0.2, 1.0], 1.4),
    ];
    let system = BlockSystem::from_domain_cut(
        ConvexBlock::cuboid([0.0; 3], [3.0, 3.0, 2.0]).unwrap(),
        &CUTS.map(|c| c.0),
        &CUTS.map(|c| c.1),
        &penedge::Tolerance::default(),
    )
    .unwrap();
    let motion = |threads: usize| -> (Vec<u64>, f64, bool) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut sim = Simulation::new(&system, 2500.0).unwrap();
            let low: Vec<usize> = (0..system.len())
                .filter(|&i| system.blocks()[i].centroid().z < 0.5)
                .collect();
            low.iter().for_each(|&i| sim.fix(i).unwrap());
            sim.set_default_joint(joint(15.0)).unwrap();
            sim.set_water(Water::level(1.2, 9810.0).unwrap());
            sim.cycle(100).unwrap();
            let water: f64 = sim
                .water()
                .contact_forces(sim.contacts())
                .iter()
                .map(|w| w.0)
                .sum();
            let poses = sim.bodies().poses().iter().flat_map(|p| {
                p.translation
                    .to_array()
                    .into_iter()
                    .chain(p.rotation.to_array())
            });
            let moved = sim.bodies().velocities().iter().any(|v| *v != DVec3::ZERO);
            (poses.map(f64::to_bits).collect(), water, moved)
        })
    };
    let (one, water, moved) = motion(1);
    assert!(
        water > 0.0 && moved,
        "no water force ({water}) or nothing moved"
    );
    assert_eq!(motion(3).0, one);
}

/// (c) Hoek and Bray's tension crack, opened: a slab on a plane inclined at θ (dry, set 0,
/// friction φ > θ: dry, it holds), pushed downhill by the water in a crack behind it (set 1,
/// a uniform pressure u on the slab's back face of area A_c: V = u A_c). Undamped, it slides
/// with `a = g sin θ + V / m − g cos θ tan φ`, `s = a t² / 2`, as long as the crack keeps its
/// water. The crack opens by the slide itself: past the detection gap (1.6 mm here) it is no
/// contact, and the water must stay (docs/mechanics.md, "Opened joints"). Before 2026-11-29
/// it went with the contact: the slab stopped after some 2 mm, and a factor of safety by
/// strength reduction came out that of a dry crack.
#[test]
fn the_water_of_an_opened_crack_keeps_pushing_a_sliding_block() {
    let (density, theta, phi) = (2500.0, 20f64.to_radians(), 30f64.to_radians());
    let (size, crack) = ([1.0, 0.8, 0.3], 0.8 * 0.3);
    let mass = density * size[0] * size[1] * size[2];
    let target = 1.0; // m/s², the slab's acceleration down the plane with the crack's push
    let push = mass * (target - G * theta.sin() + G * theta.cos() * phi.tan());
    assert!(push > 0.0 && G * theta.sin() < G * theta.cos() * phi.tan());
    let pressure = push / crack;
    let (system, frame) = support::tension_crack(theta);
    let mut sim = Simulation::new(&system, density).unwrap();
    sim.fix(0).unwrap();
    sim.fix(1).unwrap();
    let law = JointModel {
        kn: 1e9,
        ks: 1e9,
        ..joint(phi.to_degrees())
    };
    sim.set_joint(0, law).unwrap();
    sim.set_joint(1, law).unwrap();
    sim.set_water(Water::none().with_set_pressure(1, pressure).unwrap());
    let downhill = frame * DVec3::X;
    let start = sim.bodies().poses()[2].translation;
    // The slab sinks into the plane by its elastic overlap (up to twice the static
    // W cos θ / (kn A) in the undamped oscillation): its back face's strip below the back
    // block's base is then not covered, a relative share of at most that over its height.
    let sink = 2.0 * mass * G * theta.cos() / (law.kn * size[0] * size[1]);
    let mut opened = false;
    while sim.time() < 0.45 {
        sim.step().unwrap();
        let wet = sim.wet_joints();
        assert_eq!(wet.len(), 1, "the crack is one wet joint");
        if wet[0].opened {
            opened = true;
            // The whole back face still faces the crack's other side: V = u A_c.
            assert!(
                wet[0].force <= push && wet[0].force >= push * (1.0 - sink / size[2]),
                "{} vs {push}",
                wet[0].force
            );
        }
    }
    let slid = (sim.bodies().poses()[2].translation - start).dot(downhill);
    let expected = 0.5 * target * sim.time().powi(2);
    println!("opened crack: slid {slid:.5} m, a t²/2 = {expected:.5} m");
    assert!(opened, "the crack never opened past the detection gap");
    // The detection gap of the crack's pair, as the simulation's detector takes it.
    let gap = Detector::new(Tolerance::default())
        .thresholds(&system.blocks()[1], &system.blocks()[2])
        .gap;
    assert!(
        expected > 50.0 * gap,
        "the window must be well past the detection gap {gap}"
    );
    assert!(
        (slid - expected).abs() < 0.01 * expected,
        "slid {slid} m, expected {expected} m"
    );
}
