//! Restart files (issue 19, docs/mechanics.md "Restart files"): a run of N + M steps is bit
//! for bit the run of N steps, saved, read back and stepped M more; bad files are named.

use penedge::body::Shape;
use penedge::glam::{DQuat, DVec3};
use penedge::io::IoError;
use penedge::mechanics::{
    Bodies, Bolt, BoltState, Dowel, InitialStress, JointModel, Simulation, SubState, Water,
};
use penedge::{BlockSystem, ConvexBlock};
use std::path::PathBuf;
use std::sync::Arc;

mod support;

const G: f64 = 9.81;

/// A fixed base tilted by 40° (steeper than the 30° friction: the slab on it slides), a
/// slab on it, an L-shaped body of two parts resting on it and a flat square spinning in
/// its plane on it; cohesion on the default joint (bonds that break as the slab slides), a
/// set with its own properties, local damping off, gravity along -z.
fn scene() -> Simulation {
    let frame = DQuat::from_rotation_z(0.6) * DQuat::from_rotation_x(40f64.to_radians());
    let place = |b: ConvexBlock| b.transformed(frame, DVec3::new(10.0, -5.0, 2.0), 1.0);
    let base = place(ConvexBlock::cuboid([-5.0, -5.0, -1.0], [5.0, 5.0, 0.0]).unwrap());
    let slab = place(ConvexBlock::cuboid([-0.5, -0.4, 0.0], [0.5, 0.4, 0.3]).unwrap());
    let leg = place(ConvexBlock::cuboid([2.0, 2.0, 0.0], [3.0, 2.5, 0.5]).unwrap());
    let arm = place(ConvexBlock::cuboid([2.0, 2.5, 0.0], [2.5, 3.5, 0.5]).unwrap());
    let cube = place(ConvexBlock::cuboid([-3.0, -3.0, 0.0], [-2.4, -2.4, 0.2]).unwrap());
    let mut bodies = Bodies::default();
    for parts in [vec![base], vec![slab], vec![leg, arm], vec![cube]] {
        let (shape, pose) = Shape::from_parts(&parts).unwrap();
        bodies.push(Arc::new(shape), pose, 2500.0).unwrap();
    }
    let mut sim = Simulation::from_bodies(bodies);
    sim.fix(0).unwrap();
    let joint = JointModel {
        kn: 1e8,
        ks: 1e8,
        friction: 30.0,
        cohesion: 2e3,
        tension: 1e3,
        ..JointModel::default()
    };
    sim.set_default_joint(joint).unwrap();
    sim.set_joint(
        3,
        JointModel {
            friction: 20.0,
            ..joint
        },
    )
    .unwrap();
    sim.set_velocity(3, DVec3::ZERO, frame * DVec3::new(0.0, 0.0, 0.2))
        .unwrap();
    sim
}

/// Everything a step reads or reports, compared with `==` (bit for bit, as f64 `==` is
/// for the finite values here).
fn assert_same(a: &Simulation, b: &Simulation) {
    assert_eq!(a.steps(), b.steps());
    assert_eq!(a.time().to_bits(), b.time().to_bits());
    assert_eq!(
        a.unbalanced_ratio().to_bits(),
        b.unbalanced_ratio().to_bits()
    );
    assert_eq!(a.bodies().poses(), b.bodies().poses());
    assert_eq!(a.bodies().velocities(), b.bodies().velocities());
    assert_eq!(a.bodies().angular_momenta(), b.bodies().angular_momenta());
    assert_eq!(a.contacts().list, b.contacts().list);
    assert_eq!(a.contacts().subs, b.contacts().subs);
    assert_eq!(a.contact_forces(), b.contact_forces());
    assert_eq!(a.contact_moments(), b.contact_moments());
    assert_eq!(a.water(), b.water());
    assert_eq!(a.bolts().specs(), b.bolts().specs());
    assert_eq!(a.bolts().elements(), b.bolts().elements());
    // The wet joints as a restart file keeps them (an opened joint's force is computed
    // again at the next step).
    let kept = |s: &Simulation| -> Vec<_> {
        s.wet_joints()
            .iter()
            .map(|j| (j.parts, j.faces, j.set, j.opened))
            .collect()
    };
    assert_eq!(kept(a), kept(b));
}

/// Runs `scene` for `total` steps straight, and for `stop` steps, saved, read back and
/// stepped to `total`, for each `stop`: the two are the same bit for bit. The straight run.
fn resumes_bit_for_bit(
    name: &str,
    scene: fn() -> Simulation,
    stops: &[u64],
    total: u64,
) -> Simulation {
    let mut straight = scene();
    straight.cycle(total).unwrap();
    let dir = scratch(name);
    for &stop in stops {
        let mut first = scene();
        first.cycle(stop).unwrap();
        let path = dir.join(format!("at-{stop}.json"));
        first.save_state(&path).unwrap();
        let mut resumed = Simulation::load_state(&path).unwrap();
        assert_same(&first, &resumed);
        resumed.cycle(total - stop).unwrap();
        assert_same(&straight, &resumed);
    }
    // No temporary file is left beside them.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), stops.len(), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
    straight
}

/// The scene of [`scene`] wet: a phreatic surface parallel to the incline 0.1 m above it
/// (every contact on the base under water, the uplift a fraction of the blocks' weight), and
/// a uniform pressure given for set 3.
fn wet_scene() -> Simulation {
    let mut sim = scene();
    let frame = DQuat::from_rotation_z(0.6) * DQuat::from_rotation_x(40f64.to_radians());
    let point = DVec3::new(10.0, -5.0, 2.0) + frame * DVec3::new(0.0, 0.0, 0.1);
    let water = Water::phreatic(point, frame * DVec3::Z, 9810.0)
        .unwrap()
        .with_set_pressure(3, 500.0)
        .unwrap();
    sim.set_water(water);
    sim
}

#[test]
fn a_resumed_run_with_water_is_bit_for_bit_the_uninterrupted_one() {
    let (n, m) = (600, 400);
    let wet = resumes_bit_for_bit("water", wet_scene, &[0, 1, n], n + m);
    // The water acts: the wet run is not the dry one.
    let mut dry = scene();
    dry.cycle(n + m).unwrap();
    assert_ne!(wet.bodies().poses(), dry.bodies().poses());
    assert!(wet
        .water()
        .contact_forces(wet.contacts())
        .iter()
        .any(|&(u, _)| u > 0.0));
}

/// A slab pushed down an incline by the water of a tension crack behind it
/// (`support::tension_crack`), undamped: the crack opens past the detection gap within
/// some 200 steps and keeps its water (docs/mechanics.md, "Opened joints").
fn crack_scene() -> Simulation {
    let (system, _) = support::tension_crack(20f64.to_radians());
    let mut sim = Simulation::new(&system, 2500.0).unwrap();
    sim.fix(0).unwrap();
    sim.fix(1).unwrap();
    let law = JointModel {
        kn: 1e9,
        ks: 1e9,
        friction: 30.0,
        ..JointModel::default()
    };
    sim.set_joint(0, law).unwrap();
    sim.set_joint(1, law).unwrap();
    sim.set_water(Water::none().with_set_pressure(1, 1e4).unwrap());
    sim
}

#[test]
fn a_resumed_run_with_an_opened_crack_is_bit_for_bit_the_uninterrupted_one() {
    let mut sim = crack_scene();
    while !sim.wet_joints().iter().any(|j| j.opened) {
        assert!(sim.steps() < 5000, "the crack did not open");
        sim.step().unwrap();
    }
    let opened = sim.steps();
    let straight = resumes_bit_for_bit("crack", crack_scene, &[1, opened + 5], opened + 300);
    assert!(straight.wet_joints()[0].opened && straight.wet_joints()[0].force > 0.0);
}

/// A fixed ceiling and a free 1 m cube 0.1 m below it hanging from a bolt whose capacity is
/// half the cube's weight (it yields and the cube falls), with a dowel.
fn hanging_cube() -> Simulation {
    let ceiling = ConvexBlock::cuboid([-1.0, -1.0, 1.1], [1.0, 1.0, 2.0]).unwrap();
    let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
    let mut sim = Simulation::new(&BlockSystem::new(vec![ceiling, cube]), 2500.0).unwrap();
    sim.fix(0).unwrap();
    sim.add_bolt(Bolt {
        collar: DVec3::new(0.0, 0.0, 2.0),
        direction: DVec3::new(0.0, 0.0, -1.0),
        length: 1.5,
        stiffness: 1e7,
        capacity: 0.5 * 2500.0 * G,
        rupture_strain: Some(0.5),
        dowel: Some(Dowel {
            stiffness: 1e6,
            capacity: 1e3,
        }),
    })
    .unwrap();
    sim
}

#[test]
fn a_resumed_run_with_a_yielding_bolt_is_bit_for_bit_the_uninterrupted_one() {
    let n = 600;
    // Stopped while the bolt yields: its plastic elongation and state go through the file.
    let mut at_n = hanging_cube();
    at_n.cycle(n).unwrap();
    let e = at_n.bolts().elements()[0];
    assert_eq!(e.state(), BoltState::Yielding);
    // Past the elastic stretch at the capacity, C / k: plastic elongation.
    assert!(e.elongation() > 1.2 * e.force() / 1e7, "{e:?}");
    resumes_bit_for_bit("bolt", hanging_cube, &[0, 1, n], n + 400);
}

/// A file written before excavation ended the bolts anchored in removed bodies (its bolt
/// element anchored in the excavated ceiling) reads without that element: the cube no longer
/// hangs from removed rock.
#[test]
fn a_bolt_anchored_in_a_removed_body_of_an_old_file_is_dropped() {
    let mut sim = hanging_cube();
    sim.cycle(5).unwrap();
    let mut json: serde_json::Value =
        serde_json::from_str(&sim.to_state_string().unwrap()).unwrap();
    // The ceiling excavated, as that engine left it: removed, its bolt element kept.
    json["excavation"]["removed"] = serde_json::json!([0]);
    let back = Simulation::from_state_str(&json.to_string()).unwrap();
    assert_eq!(back.removed(), vec![true, false]);
    assert!(back.bolts().elements().is_empty());
    assert_eq!(back.bolts().len(), 1);
    // The time step is the cube's without the bolt.
    let mut plain = hanging_cube();
    plain.excavate(&[0], 0).unwrap();
    assert_eq!(back.critical_timestep(), plain.critical_timestep());
}

#[test]
fn a_run_whose_bolt_lost_every_element_to_an_excavation_resumes_bit_for_bit() {
    // The ceiling the bolt is anchored in excavated: the bolt keeps its id with no element
    // left (it was refused on reading: "a bolt has at least one element").
    let mut sim = hanging_cube();
    sim.cycle(5).unwrap();
    sim.excavate(&[0], 20).unwrap();
    sim.cycle(5).unwrap();
    assert_eq!((sim.bolts().len(), sim.bolts().elements().len()), (1, 0));
    let mut back = Simulation::from_state_str(&sim.to_state_string().unwrap()).unwrap();
    assert_same(&sim, &back);
    sim.cycle(30).unwrap();
    back.cycle(30).unwrap();
    assert_same(&sim, &back);
}

#[test]
fn a_file_without_water_or_bolts_reads_as_dry_and_unbolted() {
    // As files written before penedge stored them (version 1 all the same).
    let mut sim = scene();
    sim.cycle(5).unwrap();
    let mut json: serde_json::Value =
        serde_json::from_str(&sim.to_state_string().unwrap()).unwrap();
    json["settings"]
        .as_object_mut()
        .unwrap()
        .remove("water")
        .unwrap();
    json.as_object_mut().unwrap().remove("bolts").unwrap();
    let back = Simulation::from_state_str(&json.to_string()).unwrap();
    assert!(back.water().is_dry());
    assert!(back.bolts().is_empty());
    assert_same(&sim, &back);
}

#[test]
fn a_bad_bolt_or_water_field_is_named() {
    let mut sim = hanging_cube();
    sim.set_water(
        Water::level(0.5, 9810.0)
            .unwrap()
            .with_set_pressure(2, 10.0)
            .unwrap(),
    );
    sim.cycle(50).unwrap();
    let text = sim.to_state_string().unwrap();
    assert_eq!(
        Simulation::from_state_str(&text)
            .unwrap()
            .to_state_string()
            .unwrap(),
        text
    );
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cases: Vec<(&str, Edit)> = vec![
        ("bolts[0].elements[0].stiffness", |j| {
            j["bolts"][0]["elements"][0]["stiffness"] = (-1.0).into()
        }),
        ("bolts[0].elements[0].bodies", |j| {
            j["bolts"][0]["elements"][0]["bodies"] = serde_json::json!([1, 7])
        }),
        ("bolts[0].elements[0].dowel.capacity", |j| {
            j["bolts"][0]["elements"][0]["dowel"]["capacity"] = (-3.0).into()
        }),
        ("bolts[0].elements", |j| {
            j["bolts"][0]["elements"] = serde_json::json!([])
        }),
        ("bolts[0]", |j| j["bolts"][0]["capacity"] = 0.0.into()),
        ("settings.water.surface.normal", |j| {
            j["settings"]["water"]["surface"]["normal"] = serde_json::json!([0.0, 0.0, -1.0])
        }),
        ("settings.water.sets[0]", |j| {
            j["settings"]["water"]["sets"][0]["pressure"] = (-1.0).into()
        }),
    ];
    each_edit_is_named(&json, cases);
    // An unknown field in an element (a typo) is named too.
    json["bolts"][0]["elements"][0]["forse"] = 3.into();
    let e = error_of(&json.to_string());
    assert!(e.contains("forse"), "{e}");
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penedge-restart-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_resumed_run_is_bit_for_bit_the_uninterrupted_one() {
    let (n, m) = (1500, 700);
    let straight = resumes_bit_for_bit("resume", scene, &[0, 1, n], n + m);
    // The run has what a restart must carry: a sliding sub-contact with shear history.
    let sliding = straight
        .contacts()
        .subs
        .iter()
        .filter(|s| s.state == SubState::Sliding)
        .count();
    assert!(sliding > 0, "no sliding sub-contact");
    assert!(straight
        .contacts()
        .subs
        .iter()
        .any(|s| s.shear_displacement.length() > 1e-4));
}

/// A velocity set during a run is at the whole step for that body alone (docs/mechanics.md,
/// "Integration"): a file saved before the next step says which body, and the resumed run
/// is the uninterrupted one bit for bit (without that, the resumed body gets a whole kick).
#[test]
fn a_velocity_set_during_a_run_survives_a_restart_file() {
    let frame = DQuat::from_rotation_z(0.6) * DQuat::from_rotation_x(40f64.to_radians());
    let mut straight = scene();
    straight.cycle(100).unwrap();
    straight
        .set_velocity(
            3,
            frame * DVec3::new(0.02, 0.0, 0.0),
            frame * DVec3::new(0.0, 0.0, -0.1),
        )
        .unwrap();
    let text = straight.to_state_string().unwrap();
    assert!(text.contains("\"synced_bodies\":[3]"), "no synced body");
    let mut resumed = Simulation::from_state_str(&text).unwrap();
    assert_same(&straight, &resumed);
    straight.cycle(200).unwrap();
    resumed.cycle(200).unwrap();
    assert_same(&straight, &resumed);
    // After a step no velocity is at the whole step: the field is left out.
    assert!(!straight
        .to_state_string()
        .unwrap()
        .contains("synced_bodies"));
}

/// The file reads back to the same file: nothing is lost or rounded.
#[test]
fn a_restart_file_reads_back_to_the_same_file() {
    let mut sim = scene();
    sim.set_gravity(DVec3::new(0.1, 0.0, -G)).unwrap();
    sim.prescribe(2, DVec3::new(0.01, 0.0, 0.0), DVec3::ZERO)
        .unwrap();
    // Small beside the blocks' weight (a stress above it would throw them off the base).
    let stress = InitialStress::uniform([-100.0, -80.0, -120.0, 10.0, 5.0, -7.0]);
    sim.set_initial_stress(Some(stress)).unwrap();
    assert_eq!(
        Simulation::from_state_str(&sim.to_state_string().unwrap())
            .unwrap()
            .initial_stress(),
        Some(&stress)
    );
    sim.step().unwrap();
    assert!(sim.contacts().prestresses.iter().any(|&p| p > 0.0));
    sim.cycle(299).unwrap();
    let text = sim.to_state_string().unwrap();
    let back = Simulation::from_state_str(&text).unwrap();
    assert_eq!(back.to_state_string().unwrap(), text);
    assert_same(&sim, &back);
    assert_eq!(back.gravity(), sim.gravity());
    assert_eq!(back.joints().of_set(Some(3)).friction, 20.0);
    assert_eq!(back.bodies().fixities(), sim.bodies().fixities());
    assert_eq!(back.timestep().unwrap(), sim.timestep().unwrap());
}

#[test]
fn rock_bridge_models_survive_a_restart_file() {
    let mut sim = scene();
    let intact = JointModel {
        kn: 2e8,
        ks: 2e8,
        friction: 45.0,
        cohesion: 1e6,
        tension: 5e5,
        ..JointModel::default()
    };
    sim.set_bridge(3, intact).unwrap();
    sim.set_default_bridge(JointModel {
        cohesion: 2e6,
        ..intact
    })
    .unwrap();
    sim.cycle(10).unwrap();
    let back = Simulation::from_state_str(&sim.to_state_string().unwrap()).unwrap();
    let models = |s: &Simulation| -> Vec<(u32, JointModel)> {
        s.bridges().sets().map(|(k, m)| (k, *m)).collect()
    };
    assert_eq!(models(&back), vec![(3, intact)]);
    assert_eq!(back.bridges().default_model().unwrap().cohesion, 2e6);
    let flags =
        |s: &Simulation| -> Vec<bool> { s.contacts().list.iter().map(|c| c.bridge).collect() };
    assert_eq!(flags(&back), flags(&sim));
    assert_same(&sim, &back);
}

fn error_of(text: &str) -> String {
    match Simulation::from_state_str(text) {
        Ok(_) => panic!("read a bad file"),
        Err(e) => e.to_string(),
    }
}

type Edit = fn(&mut serde_json::Value);

/// Each edit of the restart file `json` (a field edited by hand into nonsense) makes it an
/// error naming the field.
fn each_edit_is_named(json: &serde_json::Value, cases: Vec<(&str, Edit)>) {
    for (field, edit) in cases {
        let mut edited = json.clone();
        edit(&mut edited);
        let e = error_of(&edited.to_string());
        assert!(e.contains(field), "`{field}` not named in: {e}");
    }
}

#[test]
fn a_bad_restart_file_is_named() {
    let mut sim = scene();
    sim.cycle(200).unwrap();
    let text = sim.to_state_string().unwrap();
    // Cut short (a copy that did not finish).
    let cut = error_of(&text[..text.len() / 2]);
    assert!(cut.contains("cut short"), "{cut}");
    // Another kind of file.
    let blocks = penedge::io::json::to_json_string(&sim.placed_system());
    let other = error_of(&blocks);
    assert!(
        other.contains("penedge-blocks") && other.contains("not a restart file"),
        "{other}"
    );
    // Another version.
    let v = error_of(&text.replacen("\"version\":1", "\"version\":99", 1));
    assert!(v.contains("version 99"), "{v}");
    // Edited by hand into nonsense: each names its field.
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cases: Vec<(&str, Edit)> = vec![
        ("bodies[1].shape", |j| j["bodies"][1]["shape"] = 99.into()),
        ("bodies[2].density", |j| {
            j["bodies"][2]["density"] = (-1.0).into()
        }),
        ("bodies[1].pose.rotation", |j| {
            j["bodies"][1]["pose"]["rotation"][0] = 0.5.into()
        }),
        ("contacts[0].parts", |j| {
            j["contacts"][0]["parts"] = serde_json::json!([3, 1])
        }),
        ("contacts[0].subs", |j| {
            j["contacts"][0]["subs"] = serde_json::json!([])
        }),
        ("settings.joints.default", |j| {
            j["settings"]["joints"]["default"]["friction"] = 95.0.into()
        }),
        ("shapes[0].parts[0]", |j| {
            j["shapes"][0]["parts"][0]["vertices"][0][0] = 1e3.into()
        }),
        ("forces", |j| j["forces"] = serde_json::json!([])),
        ("clock.synced_bodies", |j| {
            j["clock"]["synced_bodies"] = serde_json::json!([99])
        }),
        ("clock.synced_bodies", |j| {
            j["clock"]["synced_bodies"] = serde_json::json!([2, 1])
        }),
        ("clock.synced_bodies", |j| {
            j["clock"]["synced"] = true.into();
            j["clock"]["synced_bodies"] = serde_json::json!([1])
        }),
        ("settings.update_fraction", |j| {
            j["settings"]["update_fraction"] = (-0.5).into()
        }),
        ("settings.bridges.default", |j| {
            j["settings"]["bridges"]["default"] = serde_json::json!({
                "kn": -1.0, "ks": 1e8, "friction": 30.0, "cohesion": 0.0, "tension": 0.0,
                "residual_friction": null, "residual_cohesion": 0.0
            })
        }),
    ];
    each_edit_is_named(&json, cases);
    // A gap of 0, which `set_gap` refuses (no contact could carry a load), is refused here too.
    let mut zero = json.clone();
    zero["settings"]["tolerance"]["gap"] = 0.0.into();
    let e = error_of(&zero.to_string());
    assert!(
        e.contains("settings.tolerance") && e.contains("gap of 0"),
        "{e}"
    );
    // An unknown field (a typo) is named too.
    json["clock"]["stpes"] = 3.into();
    let e = error_of(&json.to_string());
    assert!(e.contains("stpes"), "{e}");
}

#[test]
fn a_missing_file_or_folder_is_an_error_and_leaves_nothing() {
    let dir = scratch("missing");
    let sim = scene();
    let nowhere = dir.join("no-such-folder").join("state.json");
    match sim.save_state(&nowhere) {
        Err(IoError::Io { path, .. }) => assert_eq!(path, nowhere),
        other => panic!("{other:?}"),
    }
    assert!(!dir.join("no-such-folder").exists());
    let e = Simulation::load_state(&dir.join("absent.json")).unwrap_err();
    assert!(e.to_string().contains("absent.json"), "{e}");
    // A good file overwritten by a good file: the new one, whole.
    let path = dir.join("state.json");
    sim.save_state(&path).unwrap();
    let mut later = scene();
    later.cycle(10).unwrap();
    later.save_state(&path).unwrap();
    assert_eq!(Simulation::load_state(&path).unwrap().steps(), 10);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A simulation of a system with spec entries, a unit and a concave block (its two parts
/// share body id 7, the others' ids are not their indices).
fn labelled() -> (BlockSystem, Simulation) {
    use penedge::generation::{JointRecord, JointShape, SetKind, SetRecord};
    use penedge::geometry::Plane;
    let blocks = vec![
        ConvexBlock::cuboid([-3.0, -3.0, -1.0], [3.0, 3.0, 0.0]).unwrap(),
        ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 0.5, 0.5]).unwrap(),
        ConvexBlock::cuboid([0.0, 0.5, 0.0], [0.5, 1.5, 0.5]).unwrap(),
        ConvexBlock::cuboid([-2.0, -2.0, 0.0], [-1.0, -1.0, 1.0]).unwrap(),
    ];
    let sets = vec![
        SetRecord {
            name: "bedding".into(),
            kind: SetKind::Set,
        },
        SetRecord {
            name: "fault".into(),
            kind: SetKind::Plane,
        },
    ];
    let joints = vec![
        JointRecord {
            set: 0,
            member: 0,
            plane: Plane {
                normal: DVec3::Z,
                point: DVec3::new(0.0, 0.0, 0.5),
            },
            shape: JointShape::Disc {
                center: DVec3::new(0.5, 0.5, 0.5),
                radius: 2.0,
            },
        },
        JointRecord {
            set: 1,
            member: 0,
            plane: Plane {
                normal: DVec3::X,
                point: DVec3::new(0.5, 0.0, 0.0),
            },
            shape: JointShape::Infinite,
        },
    ];
    let system = BlockSystem::with_provenance(blocks, Vec::new(), joints, sets)
        .with_unit(Some("ft".into()))
        .with_bodies(vec![3, 7, 7, 1], &Default::default())
        .unwrap();
    let mut sim = Simulation::new(&system, 2500.0).unwrap();
    sim.fix(0).unwrap();
    (system, sim)
}

/// The sets, joint table, unit and body ids of the system a simulation was made of survive
/// a restart file (docs/mechanics.md, "Restart files"), and so does whether mass scaling is on.
#[test]
fn the_system_labels_and_mass_scaling_survive_a_restart_file() {
    let (system, mut sim) = labelled();
    let labels = sim.system_labels().clone();
    assert_eq!(labels.sets, system.sets());
    assert_eq!(labels.joints, system.joints());
    assert_eq!(labels.unit.as_deref(), Some("ft"));
    assert_eq!(labels.body_ids, system.body_ids());
    sim.set_mass_scaling(true).unwrap();
    sim.cycle(3).unwrap();
    let back = Simulation::from_state_str(&sim.to_state_string().unwrap()).unwrap();
    assert_eq!(back.system_labels(), &labels);
    assert!(back.mass_scaling());
    assert_eq!(back.bodies().mass_scales(), sim.bodies().mass_scales());
    sim.set_mass_scaling(false).unwrap();
    let back = Simulation::from_state_str(&sim.to_state_string().unwrap()).unwrap();
    assert!(!back.mass_scaling());
}

/// A file written before the labels and the mass-scaling switch were kept reads with none
/// known (no sets, no joints, no unit, no body ids) and with mass scaling on exactly when
/// it scaled some body; a unit, a joint or body ids edited into nonsense are named.
#[test]
fn a_file_without_labels_reads_with_none_and_scaling_from_its_factors() {
    let (_, mut sim) = labelled();
    sim.cycle(3).unwrap();
    let old = |sim: &Simulation| {
        let mut json: serde_json::Value =
            serde_json::from_str(&sim.to_state_string().unwrap()).unwrap();
        json.as_object_mut().unwrap().remove("system").unwrap();
        json["settings"]
            .as_object_mut()
            .unwrap()
            .remove("mass_scaling")
            .unwrap();
        json
    };
    let back = Simulation::from_state_str(&old(&sim).to_string()).unwrap();
    assert_eq!(back.system_labels(), &Default::default());
    assert!(!back.mass_scaling());
    assert_same(&sim, &back);
    // The 0.5 m thick L's step is below the 1 m cube's, the median of the two: it is
    // scaled; a file of a run with scaling on (and a factor above 1) reads as on.
    sim.set_mass_scaling(true).unwrap();
    assert!(sim.bodies().mass_scales().iter().any(|&s| s > 1.0));
    let back = Simulation::from_state_str(&old(&sim).to_string()).unwrap();
    assert!(back.mass_scaling());
    let json: serde_json::Value = serde_json::from_str(&sim.to_state_string().unwrap()).unwrap();
    each_edit_is_named(
        &json,
        vec![
            ("system.unit", |j| j["system"]["unit"] = "\u{7}".into()),
            ("system.joints[1].normal", |j| {
                j["system"]["joints"][1]["normal"] = serde_json::json!([2.0, 0.0, 0.0])
            }),
            ("system.joints[0].set", |j| {
                j["system"]["joints"][0]["set"] = serde_json::json!(5)
            }),
            ("system.body_ids", |j| {
                j["system"]["body_ids"] = serde_json::json!([1, 2])
            }),
        ],
    );
}
