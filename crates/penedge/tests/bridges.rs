//! Rock bridges of finite joints (docs/generation.md, "Rock bridges"): the block a finite
//! joint ends inside is cut through; the part of the plane outside the joint's extent is
//! bridge faces, the part inside joint faces, each face wholly one or the other. References
//! from the geometry of the box and the joint, not from a run.

use penedge::generation::*;
use penedge::geometry::DVec3;

#[allow(dead_code)]
mod generation_support;
mod support;
use support::face_area;

const DIP: f64 = 30.0;

/// The joint plane through the box's centre, dipping 30° towards +x: its unit normal and
/// two unit vectors in it (`u` down the dip's opposite, along x-z; `w` = y).
fn plane() -> (DVec3, DVec3, DVec3) {
    let t = DIP.to_radians();
    let n = DVec3::new(-t.sin(), 0.0, t.cos());
    let u = DVec3::new(t.cos(), 0.0, t.sin());
    (n, u, DVec3::Y)
}

const CENTRE: DVec3 = DVec3::new(5.0, 5.0, 5.0);

/// The section of the box [0, 10]³ by the plane: it enters at x = 0 and leaves at x = 10
/// (z from 5 - 5 tan 30° to 5 + 5 tan 30°, inside the box): a rectangle 10 / cos 30° by 10.
fn section_area() -> f64 {
    100.0 / DIP.to_radians().cos()
}

/// A square joint of half side `a` on the plane, centred on the box's centre.
fn square(a: f64) -> Vec<[f64; 3]> {
    let (_, u, w) = plane();
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(s, t)| (CENTRE + u * (s * a) + w * (t * a)).to_array())
        .collect()
}

/// The faces on the joint plane: (joint area below, bridge area below, area above). The
/// pieces below the plane (outward normal `n`) are split by the seams, each face wholly joint
/// or bridge; the piece above keeps one face (outward normal `-n`), of origin joint.
fn areas_on_plane(system: &penedge::BlockSystem) -> (f64, f64, f64) {
    let (n, _, _) = plane();
    let (mut joint, mut bridge, mut above) = (0.0, 0.0, 0.0);
    for b in system.blocks() {
        for (f, origin) in b.face_origins().iter().enumerate() {
            let p = b.planes()[f];
            if p.normal.cross(n).length() > 1e-9 || (p.point - CENTRE).dot(n).abs() > 1e-9 {
                continue;
            }
            let area = face_area(b, f);
            match (origin, p.normal.dot(n) > 0.0) {
                (FaceOrigin::Joint { .. }, true) => joint += area,
                (FaceOrigin::Bridge { .. }, true) => bridge += area,
                (FaceOrigin::Joint { .. }, false) => above += area,
                _ => panic!("a face on the plane of origin {origin:?}"),
            }
        }
    }
    (joint, bridge, above)
}

fn spec(joint: Discontinuity) -> Spec {
    Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap()).with(joint)
}

fn total_volume(system: &penedge::BlockSystem) -> f64 {
    system.blocks().iter().map(|b| b.volume()).sum()
}

/// Whether every vertex of every joint face on the plane is inside the square (within
/// 1e-9), and every bridge face on it lies outside one of the square's edge lines.
fn faces_wholly_joint_or_bridge(system: &penedge::BlockSystem, a: f64) -> bool {
    let (n, u, w) = plane();
    let local = |p: DVec3| ((p - CENTRE).dot(u), (p - CENTRE).dot(w));
    system.blocks().iter().all(|b| {
        b.face_origins().iter().enumerate().all(|(f, origin)| {
            let pl = b.planes()[f];
            if pl.normal.cross(n).length() > 1e-9 || pl.normal.dot(n) < 0.0 {
                return true;
            }
            let pts: Vec<(f64, f64)> = b
                .face(f)
                .iter()
                .map(|&i| local(b.vertices()[i as usize]))
                .collect();
            match origin {
                FaceOrigin::Joint { .. } => pts
                    .iter()
                    .all(|&(s, t)| s.abs() <= a + 1e-9 && t.abs() <= a + 1e-9),
                FaceOrigin::Bridge { .. } => {
                    let beyond = |k: usize| {
                        pts.iter()
                            .all(|&(s, t)| [s - a, -s - a, t - a, -t - a][k] >= -1e-9)
                    };
                    (0..4).any(beyond)
                }
                _ => true,
            }
        })
    })
}

/// The areas of a square joint of half side `a` and its bridges, the volume, and each face
/// wholly joint or bridge.
fn check_square(system: &penedge::BlockSystem, a: f64) {
    let (joint, bridge, above) = areas_on_plane(system);
    assert!((joint - 4.0 * a * a).abs() < 1e-9, "joint area {joint}");
    let expected = section_area() - 4.0 * a * a;
    assert!(
        (bridge - expected).abs() < 1e-9,
        "bridge {bridge} vs {expected}"
    );
    assert!((above - section_area()).abs() < 1e-9, "above {above}");
    assert!((total_volume(system) - 1000.0).abs() < 1e-9);
    assert!(faces_wholly_joint_or_bridge(system, a));
}

#[test]
fn a_square_joint_with_bridges_cuts_the_box_through() {
    let a = 3.0;
    let out = generate(&spec(Discontinuity::polygon(square(a)).with_bridges())).unwrap();
    check_square(&out.system, a);
    // Four seams cross the section: below the plane, 4 pieces outside them and the joint's
    // piece; above it, one piece.
    assert_eq!(out.system.len(), 6);
    assert_eq!(out.report.bridged_cuts, 1);
    assert_eq!(out.report.partial_cuts_skipped, 0);
    // The block file keeps the bridge faces.
    let text = penedge::io::json::to_json_string(&out.system);
    assert!(text.contains(r#""kind":"bridge""#) || text.contains(r#""kind": "bridge""#));
    let back = penedge::io::json::from_json_str(&text).unwrap();
    for (x, y) in back.blocks().iter().zip(out.system.blocks()) {
        assert_eq!(x.face_origins(), y.face_origins());
    }
}

#[test]
fn without_bridges_the_block_is_left_whole() {
    let out = generate(&spec(Discontinuity::polygon(square(3.0)))).unwrap();
    assert_eq!(out.system.len(), 1);
    assert_eq!(out.report.partial_cuts_by_entry, vec![1]);
    assert_eq!(areas_on_plane(&out.system), (0.0, 0.0, 0.0));
}

#[test]
fn a_disc_with_bridges_has_the_disc_area() {
    let (n, _, _) = plane();
    let r = 2.5;
    let disc = Discontinuity::disc(CENTRE.to_array(), Orientation::Normal(n.to_array()), r);
    let out = generate(&spec(disc.with_bridges())).unwrap();
    let (joint, bridge, _) = areas_on_plane(&out.system);
    let disc_area = std::f64::consts::PI * r * r;
    assert!(
        (joint - disc_area).abs() < 1e-9,
        "joint {joint} vs {disc_area}"
    );
    let expected = section_area() - disc_area;
    assert!(
        (bridge - expected).abs() < 1e-9,
        "bridge {bridge} vs {expected}"
    );
    assert!((total_volume(&out.system) - 1000.0).abs() < 1e-9);
}

#[test]
fn bridges_through_blocks_of_a_joint_set() {
    // Vertical planes x = 2.5, 5, 7.5; the square reaches x = 5 ± 3 cos 30° = [2.40, 7.60],
    // so it ends inside each of the four columns and every column is cut through.
    let a = 3.0;
    let set = JointSet {
        origin: [2.5, 0.0, 0.0],
        ..JointSet::new(Orientation::dip(90.0, 90.0), 2.5)
    };
    let spec = spec(Discontinuity::set(set)).with(Discontinuity::polygon(square(a)).with_bridges());
    let out = generate(&spec).unwrap();
    check_square(&out.system, a);
    // Every joint and bridge face is covered by its neighbours' faces.
    generation_support::check_faces(&out.system, 0);
    assert_eq!(out.report.partial_cuts_by_entry, vec![0, 0]);
    assert_eq!(out.report.bridged_cuts, 4); // one per column
}

#[test]
fn the_spec_file_takes_bridge_on_finite_joints_only() {
    let text = |kind: &str| {
        format!(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n[[joints]]\n{kind}\nbridge = true\n"
        )
    };
    let disc =
        text("type = \"disc\"\ncenter = [5, 5, 5]\nradius = 2\ndip = 30\ndip_direction = 90");
    let spec = penedge::io::spec::parse_toml(&disc).unwrap();
    assert!(spec.joints[0].bridge);
    let plane = text("type = \"plane\"\npoint = [5, 5, 5]\ndip = 30\ndip_direction = 90");
    let err = penedge::io::spec::parse_toml(&plane)
        .unwrap_err()
        .to_string();
    assert!(err.contains("joints[0].bridge"), "{err}");
}

// ---- mechanics: a bridge holds a block on a slope until W sin θ > c A + N tan φ ----------

mod slope {
    use penedge::generation::FaceOrigin;
    use penedge::glam::{DQuat, DVec3};
    use penedge::mechanics::{JointModel, Simulation};
    use penedge::{BlockSystem, ConvexBlock};

    const G: f64 = 9.81;
    const DENSITY: f64 = 2500.0;
    const KN: f64 = 1e8;
    const PHI: f64 = 10.0;
    /// The slab: 1 m × 0.8 m × 0.1 m, its whole base a bridge of area A = 0.8 m².
    const SIZE: [f64; 3] = [1.0, 0.8, 0.1];

    /// The face of `block` whose outward normal is `n`, tagged `origin`.
    fn tag(block: ConvexBlock, n: DVec3, origin: FaceOrigin) -> ConvexBlock {
        let mut origins = block.face_origins().to_vec();
        let f = (0..block.n_faces())
            .max_by(|&i, &j| {
                let d = |k: usize| block.planes()[k].normal.dot(n);
                d(i).total_cmp(&d(j))
            })
            .unwrap();
        origins[f] = origin;
        block.with_face_origins(origins).unwrap()
    }

    /// A fixed base and the slab on it, on a slope `theta` (degrees) about a horizontal axis
    /// at azimuth 0.5 rad (not aligned with the axes); the two touching faces tagged `origin`.
    fn slab_on_slope(theta: f64, origin: FaceOrigin) -> (Simulation, DVec3) {
        let frame = DQuat::from_rotation_z(0.5) * DQuat::from_rotation_x(theta.to_radians());
        let [lx, ly, h] = SIZE;
        let base = ConvexBlock::cuboid([-4.0, -4.0, -1.0], [4.0, 4.0, 0.0]).unwrap();
        let slab =
            ConvexBlock::cuboid([-lx / 2.0, -ly / 2.0, 0.0], [lx / 2.0, ly / 2.0, h]).unwrap();
        let place = |b: ConvexBlock| b.transformed(frame, DVec3::new(30.0, 20.0, 10.0), 1.0);
        let n = frame * DVec3::Z;
        let base = tag(place(base), n, origin);
        let slab = tag(place(slab), -n, origin);
        let mut sim = Simulation::new(&BlockSystem::new(vec![base, slab]), DENSITY).unwrap();
        sim.fix(0).unwrap();
        (sim, n)
    }

    fn model(friction: f64, cohesion: f64) -> JointModel {
        let mut m = JointModel::default();
        (m.kn, m.ks, m.friction, m.cohesion, m.tension) = (KN, KN, friction, cohesion, 0.0);
        m
    }

    /// The slab's displacement along the slope after gravity is ramped up over 0.3 s and held
    /// to 0.6 s, and the elastic shear offset under its weight.
    fn run(sim: &mut Simulation, n: DVec3, theta: f64) -> (f64, f64) {
        let start = sim.bodies().poses()[1].translation;
        while sim.time() < 0.6 {
            let f = (sim.time() / 0.3).min(1.0);
            sim.set_gravity(DVec3::new(0.0, 0.0, -G * f)).unwrap();
            sim.step().unwrap();
        }
        let d = sim.bodies().poses()[1].translation - start;
        let area = SIZE[0] * SIZE[1];
        let weight = DENSITY * SIZE.iter().product::<f64>() * G;
        let elastic = weight * theta.to_radians().sin() / (KN * area);
        ((d - n * d.dot(n)).length(), elastic)
    }

    #[test]
    fn a_bridge_holds_a_block_until_its_cohesion_is_overcome() {
        // The cohesion that makes the slope of failure 30°: W sin θ = c A + W cos θ tan φ.
        let area = SIZE[0] * SIZE[1];
        let weight = DENSITY * SIZE.iter().product::<f64>() * G;
        let onset = 30.0f64.to_radians();
        let c = weight * (onset.sin() - onset.cos() * PHI.to_radians().tan()) / area;
        let bridge = FaceOrigin::Bridge { set: 0, joint: 0 };
        for (theta, breaks) in [(28.5, false), (31.5, true)] {
            let t = f64::to_radians(theta);
            assert_eq!(
                weight * t.sin() > c * area + weight * t.cos() * PHI.to_radians().tan(),
                breaks
            );
            let (mut sim, n) = slab_on_slope(theta, bridge);
            // The joints are frictional only: the bridge alone holds the slab.
            sim.set_default_joint(model(PHI, 0.0)).unwrap();
            sim.set_bridge(0, model(PHI, c)).unwrap();
            let (moved, elastic) = run(&mut sim, n, theta);
            let contacts = sim.contacts();
            assert!(contacts.list.iter().all(|k| k.bridge && k.set == Some(0)));
            let bonded = contacts.subs.iter().filter(|s| s.bonded).count();
            if breaks {
                assert!(moved > 100.0 * elastic, "{theta}°: moved only {moved}");
                assert_eq!(bonded, 0, "{theta}°: a broken bridge keeps no bond");
            } else {
                assert!(moved < 1.5 * elastic, "{theta}°: moved {moved} > {elastic}");
                assert!(bonded > 0);
            }
        }
    }

    #[test]
    fn the_same_faces_as_joint_faces_let_the_block_slide() {
        let theta = 28.5;
        let (mut sim, n) = slab_on_slope(theta, FaceOrigin::Joint { set: 0, joint: 0 });
        sim.set_default_joint(model(PHI, 0.0)).unwrap();
        sim.set_bridge(0, model(PHI, 1e9)).unwrap();
        let (moved, elastic) = run(&mut sim, n, theta);
        assert!(sim.contacts().list.iter().all(|k| !k.bridge));
        assert!(moved > 100.0 * elastic, "moved only {moved}");
    }
}
