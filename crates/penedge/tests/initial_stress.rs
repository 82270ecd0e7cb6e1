//! Initial stresses (issue 19, docs/mechanics.md "Initial stresses"): installed on the first
//! detection's contacts as the traction of the stress tensor, a confined mass is in
//! equilibrium at once; an excavation releases it. References are formulas computed here.

use penedge::glam::{DMat3, DVec3};
use penedge::mechanics::{Damping, InitialStress, JointModel, MechanicsError, Simulation};
use penedge::{BlockSystem, ContactType, ConvexBlock};

const KN: f64 = 1e9;

fn joint() -> JointModel {
    JointModel {
        kn: KN,
        ks: KN,
        friction: 40.0,
        cohesion: 0.0,
        tension: 0.0,
        ..JointModel::default()
    }
}

/// Unit cubes at the integer points of `0..n` cubed; the outer shell fixed.
fn grid(n: usize) -> (Simulation, Vec<usize>) {
    let mut blocks = Vec::new();
    let mut inner = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let (x, y, z) = (i as f64, j as f64, k as f64);
                let shell = [i, j, k].iter().any(|&c| c == 0 || c == n - 1);
                if !shell {
                    inner.push(blocks.len());
                }
                blocks.push(ConvexBlock::cuboid([x, y, z], [x + 1.0, y + 1.0, z + 1.0]).unwrap());
            }
        }
    }
    let mut sim = Simulation::new(&BlockSystem::new(blocks), 2500.0).unwrap();
    for i in 0..sim.bodies().len() {
        if !inner.contains(&i) {
            sim.fix(i).unwrap();
        }
    }
    sim.set_default_joint(joint()).unwrap();
    sim.set_gravity(DVec3::ZERO).unwrap();
    (sim, inner)
}

/// The stress tensor of components `xx, yy, zz, xy, yz, zx`, written here from its
/// definition (not from the library).
fn tensor(c: [f64; 6]) -> DMat3 {
    DMat3::from_cols_array(&[c[0], c[3], c[5], c[3], c[1], c[4], c[5], c[4], c[2]])
}

/// A box of 4 × 4 × 4 cubes with its shell fixed, under a uniform stress with shear
/// components, gravity off: at the first step each sub-contact carries the traction of the
/// tensor (normal stress `-n·σ·n`, shear `-(σn - (n·σ·n) n)` on B) and the eight free
/// blocks are in equilibrium: the unbalanced force over the contact forces (3DEC's ratio,
/// gravity being off) below 1e-5; they stay put.
#[test]
fn a_confined_box_under_an_initial_stress_is_in_equilibrium_at_once() {
    let c = [-2e6, -1e6, -3e6, 0.5e6, 0.2e6, -0.3e6];
    let sigma = tensor(c);
    let (mut sim, inner) = grid(4);
    sim.set_initial_stress(Some(InitialStress::uniform(c)))
        .unwrap();
    sim.step().unwrap();
    let contacts = sim.contacts();
    assert!(!contacts.list.is_empty());
    for (k, contact) in contacts.list.iter().enumerate() {
        let n = contact.normal;
        // Face-face contacts carry the traction; the edge and vertex contacts of diagonal
        // neighbours none.
        let t = if contact.kind == ContactType::FaceFace {
            sigma * n
        } else {
            DVec3::ZERO
        };
        for (j, s) in contacts.subs_of(k).iter().enumerate() {
            let installed = contacts.prestress(contact.first as usize + j);
            let normal = -n.dot(t);
            let shear = -(t - n * n.dot(t)) * s.area;
            assert!((installed - normal).abs() < 1e-9 * 3e6, "{installed}");
            // The shear force after one step: installed, then loaded by the step's
            // (zero) relative motion.
            assert!((s.shear_force - shear).length() < 1e-6 * 3e6 * s.area);
        }
    }
    let mut largest = 0.0f64;
    let mut reference = 0.0f64;
    for &i in &inner {
        largest = largest.max(sim.contact_forces()[i].length());
        // Every face of a free block touches: its contact forces' magnitudes sum to about
        // 6 faces × |σ| × 1 m².
        let mut sum = 0.0;
        for (k, contact) in contacts.list.iter().enumerate() {
            if contact.bodies.contains(&(i as u32)) {
                sum += contacts
                    .subs_of(k)
                    .iter()
                    .map(|s| s.force(contact.normal).length())
                    .sum::<f64>();
            }
        }
        reference = reference.max(sum);
        assert!(sim.contact_moments()[i].length() < 1e-5 * sum);
    }
    assert!(reference > 6.0 * 1e6, "{reference}");
    assert!(largest / reference < 1e-5, "ratio {}", largest / reference);
    let before: Vec<DVec3> = inner
        .iter()
        .map(|&i| sim.bodies().poses()[i].translation)
        .collect();
    sim.cycle(200).unwrap();
    for (k, &i) in inner.iter().enumerate() {
        let moved = sim.bodies().poses()[i].translation - before[k];
        // Far below the elastic displacement of the stress, |σ| / kn = 3e-3 m.
        assert!(moved.length() < 1e-9, "block {i} moved by {moved}");
    }
}

/// A row of three free cubes between two fixed walls, under σxx = -1 MPa: in equilibrium at
/// once; the right wall excavated (relaxed over 2000 steps, some 20 periods of a cube on
/// its joint: quasi-static, with local damping), the row expands until its joints
/// carry nothing: each joint opens by σ/kn, so the last cube moves 3 σ/kn. (Checked at the
/// end of the relaxation: after it, the joints are open, with no force, and the cubes keep
/// whatever small velocity they have left.)
#[test]
fn an_excavation_releases_an_initial_stress() {
    let s = 1e6;
    let blocks: Vec<ConvexBlock> = (0..5)
        .map(|i| {
            let x = i as f64;
            ConvexBlock::cuboid([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0]).unwrap()
        })
        .collect();
    let mut sim = Simulation::new(&BlockSystem::new(blocks), 2500.0).unwrap();
    sim.fix(0).unwrap();
    sim.fix(4).unwrap();
    sim.set_default_joint(joint()).unwrap();
    sim.set_gravity(DVec3::ZERO).unwrap();
    sim.set_initial_stress(Some(InitialStress::uniform([-s, 0.0, 0.0, 0.0, 0.0, 0.0])))
        .unwrap();
    sim.step().unwrap();
    let start: Vec<f64> = (0..5)
        .map(|i| sim.bodies().poses()[i].translation.x)
        .collect();
    for i in 1..4 {
        assert!(sim.contact_forces()[i].length() < 1e-9 * s, "{i}");
    }
    let report = sim.excavate(&[4], 2000).unwrap();
    // The wall pushed the last cube with σ A = 1 MN.
    assert_eq!(report.loaded.len(), 1);
    assert!((report.loaded[0].1 - DVec3::new(-s, 0.0, 0.0)).length() < 1e-6 * s);
    sim.set_damping(Damping {
        local: 0.8,
        viscous: 0.0,
    })
    .unwrap();
    sim.cycle(2000).unwrap(); // the relaxation
    let opening = s / KN;
    for (k, i) in (1..4).enumerate() {
        let moved = sim.bodies().poses()[i].translation.x - start[i];
        let expected = (k + 1) as f64 * opening;
        assert!(
            (moved - expected).abs() < 0.02 * expected,
            "cube {i}: {moved} against {expected}"
        );
    }
    let left = sim
        .contacts()
        .subs
        .iter()
        .map(|x| x.normal_force.abs())
        .fold(0.0, f64::max);
    assert!(left < 0.01 * s * 0.25, "{left}");
}

#[test]
fn an_initial_stress_is_set_before_the_first_step() {
    let (mut sim, _) = grid(3);
    let bad = InitialStress::uniform([f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(
        sim.set_initial_stress(Some(bad)),
        Err(MechanicsError::NotFinite("the initial stress"))
    );
    sim.step().unwrap();
    assert_eq!(
        sim.set_initial_stress(None),
        Err(MechanicsError::InitialStressTooLate)
    );
}

/// The overburden field: σzz = -γ (surface - z), σxx = k0x σzz, σyy = k0y σzz, none above.
#[test]
fn the_overburden_stress_grows_with_depth() {
    let f = InitialStress::overburden(100.0, 2.6e4, 1.5, 0.8);
    let at = f.at(DVec3::new(3.0, 4.0, 40.0));
    assert_eq!(at.z_axis.z, -2.6e4 * 60.0);
    assert_eq!(at.x_axis.x, -2.6e4 * 60.0 * 1.5);
    assert_eq!(at.y_axis.y, -2.6e4 * 60.0 * 0.8);
    assert_eq!(f.at(DVec3::new(0.0, 0.0, 120.0)), DMat3::ZERO);
}

/// On a joint narrower than the point width (a slab 0.2 m by 2 m, `w` = 0.2 × its 2 m
/// diameter), the floor of the corners' area shares doubles their sum; the installed
/// stress still gives the joint's own area's force, σ A, not σ times the shares' sum
/// (docs/mechanics.md, "Areas of sub-contacts").
#[test]
fn a_narrow_joint_carries_its_own_area_of_an_initial_stress() {
    let s = 1e6;
    let (lx, ly, h) = (0.2, 2.0, 0.04);
    let base = ConvexBlock::cuboid([-3.0, -3.0, -1.0], [3.0, 3.0, 0.0]).unwrap();
    let slab = ConvexBlock::cuboid([-lx / 2.0, -ly / 2.0, 0.0], [lx / 2.0, ly / 2.0, h]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![base, slab]), 2500.0).unwrap();
    sim.fix(0).unwrap();
    sim.set_default_joint(joint()).unwrap();
    sim.set_gravity(DVec3::ZERO).unwrap();
    sim.set_initial_stress(Some(InitialStress::uniform([0.0, 0.0, -s, 0.0, 0.0, 0.0])))
        .unwrap();
    sim.step().unwrap();
    let subs = &sim.contacts().subs;
    let shares: f64 = subs.iter().map(|c| c.area).sum();
    let area = lx * ly;
    assert!(
        shares > 1.5 * area,
        "the floor is active: {shares} against {area}"
    );
    let force: f64 = subs.iter().map(|c| c.normal_force).sum();
    assert!(
        (force - s * area).abs() < 1e-9 * s * area,
        "{force} against σ A = {}",
        s * area
    );
}
