//! Bad input at every Rust entry point gives an error naming the problem: never a panic, an
//! overflow, a hang or a half-written file (issue #6). Complements `src/block/tests.rs` (the
//! block checks one by one), `generation_spec.rs` and `generation_io.rs`.

use penedge::block::{BlockError, MAX_HALFSPACES};
use penedge::generation::{generate, Problem, SpecError};
use penedge::io::{self, csv, json, spec, vtp, vtu, IoError};
use penedge::{BlockSystem, ConvexBlock, Detector, Tolerance};
use std::path::PathBuf;
use std::time::{Duration, Instant};

fn cube_mesh(scale: f64, offset: f64) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let vertices = cube
        .vertices()
        .iter()
        .map(|v| (*v * scale + offset).to_array())
        .collect();
    let faces = cube
        .faces()
        .map(|f| f.iter().map(|&v| v as usize).collect())
        .collect();
    (vertices, faces)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penedge-bad-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn names_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

// -- blocks ---------------------------------------------------------------------------------

#[test]
fn coordinates_beyond_double_range_are_refused_by_name() {
    // 1e100: the volume (1e300) fits but its moments (1e400) do not, and the centroid came out
    // infinite; 1e103: the volume itself overflowed; 1e-200: the diagonal underflowed to 0
    // and the cube read as "vertices 0 and 3 at the same position".
    for (scale, offset, what) in [
        (1e100, 0.0, "largest coordinate"),
        (1e103, 0.0, "largest coordinate"),
        (1e300, 0.0, "largest coordinate"),
        (1.0, 1e51, "largest coordinate"),
        (1e-51, 0.0, "size"),
        (1e-200, 0.0, "size"),
    ] {
        let (v, f) = cube_mesh(scale, offset);
        match ConvexBlock::new(&v, &f) {
            Err(BlockError::OutOfRange { what: w, value }) => {
                assert_eq!(w, what, "scale {scale:e}");
                assert!(value.is_finite() && value > 0.0);
            }
            other => panic!("scale {scale:e}, offset {offset:e}: {other:?}"),
        }
    }
}

#[test]
fn no_vertices_at_all_is_too_small_not_out_of_range() {
    let none: [[f64; 3]; 0] = [];
    let e = ConvexBlock::new(&none, &[[0usize, 1, 2]]).unwrap_err();
    assert_eq!(
        e,
        BlockError::TooSmall {
            vertices: 0,
            faces: 1
        }
    );
}

#[test]
fn blocks_at_the_ends_of_the_range_are_finite() {
    for (scale, offset) in [(4e49, 0.0), (1e-49, 0.0), (1e-49, 1e-40), (1.0, 5e5)] {
        let (v, f) = cube_mesh(scale, offset);
        let b = ConvexBlock::new(&v, &f).unwrap();
        assert!(b.volume().is_finite() && b.volume() > 0.0, "{scale:e}");
        assert!(b.centroid().is_finite(), "{scale:e}: {}", b.centroid());
        let back = json::from_json_str(&json::to_json_string(&BlockSystem::new(vec![b]))).unwrap();
        assert_eq!(back.len(), 1);
    }
}

#[test]
fn a_stored_block_out_of_range_is_refused_too() {
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let text = json::to_json_string(&BlockSystem::new(vec![cube]));
    let huge = text.replacen("[0.0,0.0,0.0]", "[-1e60,0.0,0.0]", 1);
    assert_ne!(huge, text);
    match json::from_json_str(&huge) {
        Err(IoError::Format { field, message }) => {
            assert_eq!(field, "blocks[0]");
            assert!(message.contains("largest coordinate is 1e60"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn half_spaces_beyond_the_limit_are_refused_at_once() {
    let m = 10 * MAX_HALFSPACES;
    let normals: Vec<[f64; 3]> = (0..m)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / m as f64;
            [a.cos(), a.sin(), 1.0]
        })
        .collect();
    let start = Instant::now();
    let e = ConvexBlock::from_planes(&normals, &vec![1.0; m]).unwrap_err();
    assert!(start.elapsed() < Duration::from_secs(2));
    assert_eq!(
        e,
        BlockError::TooManyPlanes {
            count: m,
            limit: MAX_HALFSPACES
        }
    );
}

#[test]
fn a_cone_of_as_many_half_spaces_as_allowed_is_built_in_reasonable_time() {
    // Every triple of side planes meets at the apex: the worst case of the corner search.
    let sides = MAX_HALFSPACES - 1;
    let mut normals = vec![[0.0, 0.0, -1.0]];
    let mut offsets = vec![0.0];
    for k in 0..sides {
        let a = k as f64 * std::f64::consts::TAU / sides as f64;
        normals.push([a.cos(), a.sin(), 1.0]);
        offsets.push(1.0);
    }
    let block = ConvexBlock::from_planes(&normals, &offsets).unwrap();
    assert_eq!(block.vertices().len(), sides + 1);
    assert_eq!(block.n_faces(), sides + 1);
}

/// The outward normals of a box, one per face.
const AXES: [[f64; 3]; 6] = [
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, -1.0],
];

#[test]
fn half_space_normals_of_any_finite_length_count_by_direction() {
    let base = AXES;
    for big in [1e200, 1e-200, 1e300, f64::MIN_POSITIVE] {
        let mut normals = base;
        normals[0] = [big, 0.0, 0.0];
        // n · x <= d with n = (big, 0, 0) and d = big: x <= 1.
        let b = ConvexBlock::from_planes(&normals, &[big, 0.0, 1.0, 0.0, 1.0, 0.0])
            .unwrap_or_else(|e| panic!("{big:e}: {e}"));
        assert!((b.volume() - 1.0).abs() < 1e-12, "{big:e}");
    }
    for bad in [
        [0.0; 3],
        [0.0, f64::NAN, 0.0],
        [1.0, f64::NAN, 0.0],
        [0.0, -1.0, f64::INFINITY],
    ] {
        let mut normals = base;
        normals[3] = bad;
        let e = ConvexBlock::from_planes(&normals, &[1.0, 0.0, 1.0, 0.0, 1.0, 0.0]);
        assert_eq!(
            e.unwrap_err(),
            BlockError::DegeneratePlane { plane: 3 },
            "{bad:?}"
        );
    }
}

#[test]
fn a_cutting_plane_must_have_a_finite_unit_normal() {
    use penedge::cutting::split_block;
    use penedge::geometry::{DVec3, Plane};
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let tol = Tolerance::default();
    let centre = DVec3::splat(0.5);
    // The bug: a normal of length 1 + 1.6e-8 was accepted and carried by the caps, so the
    // pieces had a face plane that is not a unit vector.
    for (normal, point) in [
        (DVec3::new(0.0, 1.000_000_015_6, 0.0), centre),
        (DVec3::ZERO, centre),
        (DVec3::new(f64::NAN, 0.0, 0.0), centre),
        (DVec3::Y, DVec3::new(0.5, f64::INFINITY, 0.5)),
    ] {
        let e = split_block(&cube, &Plane { normal, point }, &tol).unwrap_err();
        assert!(
            matches!(e, BlockError::DegenerateCut { .. }),
            "{normal}: {e}"
        );
    }
    let split = split_block(
        &cube,
        &Plane {
            normal: DVec3::Y,
            point: centre,
        },
        &tol,
    )
    .unwrap();
    assert!(split.below.is_some() && split.above.is_some());
}

// -- detection ------------------------------------------------------------------------------

/// A block moved by the unchecked `translated` to NaN coordinates (a caller's bug the type
/// allows): the broad phase doubled its cell for the block's infinite extent until the
/// level's `u8` overflowed, a panic ("attempt to add with overflow") in `detect` and in
/// `ContactTracker::new`. Now no panic; the finite blocks' contacts are found as without it.
#[test]
fn a_block_with_nan_coordinates_does_not_panic_the_detection() {
    use penedge::geometry::DVec3;
    use penedge::system::ContactTracker;
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let b = ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
    let broken = a.translated(DVec3::splat(f64::NAN));
    let tol = Tolerance::default();
    let clean = BlockSystem::new(vec![a.clone(), b.clone()]).detect(&tol);
    let with = BlockSystem::new(vec![a, b, broken]);
    let found = with.detect(&tol);
    let between = |c: &penedge::system::SystemContacts| {
        c.contacts
            .iter()
            .filter(|p| p.pair == [0, 1])
            .map(|p| p.contact.kind)
            .collect::<Vec<_>>()
    };
    assert_eq!(between(&found), between(&clean));
    assert_eq!(between(&clean).len(), 1);
    let _ = ContactTracker::new(&with, tol, 0.0);
    // The block and its broken copy alone (the case that panicked).
    let pair = BlockSystem::new(vec![with.blocks()[0].clone(), with.blocks()[2].clone()]);
    assert!(pair.detect(&tol).contacts.is_empty());
    let _ = ContactTracker::new(&pair, tol, 0.0);
    // NaN in one coordinate only, with an absolute gap (boxes NaN in z alone): three such
    // blocks made the grid's median and span NaN, and with the level bounded (no panic) the
    // grid lost every pair of the three touching cubes (a reviewer's case). They are found.
    let cubes: Vec<ConvexBlock> = (0..3)
        .map(|k| {
            let x = k as f64 * 0.5;
            ConvexBlock::cuboid([x, 0.0, 0.0], [x + 0.5, 1.0, 1.0]).unwrap()
        })
        .collect();
    let absolute = Tolerance::with_absolute_gap(1e-6).unwrap();
    let pairs = |system: &BlockSystem| {
        system
            .detect(&absolute)
            .contacts
            .iter()
            .map(|p| p.pair)
            .collect::<Vec<_>>()
    };
    let expected = pairs(&BlockSystem::new(cubes.clone()));
    assert_eq!(expected, vec![[0, 1], [1, 2]]);
    for broken in 1..=4 {
        let mut blocks = cubes.clone();
        let copy = cubes[0].translated(DVec3::new(0.0, 0.0, f64::NAN));
        blocks.extend(std::iter::repeat_n(copy, broken));
        let system = BlockSystem::new(blocks);
        assert_eq!(pairs(&system), expected, "{broken} broken blocks");
        let tracker = ContactTracker::new(&system, absolute, 0.0).unwrap();
        let tracked: Vec<[u32; 2]> = tracker.contacts().contacts.iter().map(|p| p.pair).collect();
        assert_eq!(tracked, expected, "{broken} broken blocks, tracker");
    }
}

#[test]
fn an_empty_system_detects_and_writes_nothing() {
    let empty = BlockSystem::new(Vec::new());
    let tol = Tolerance::default();
    let (found, geometry) = empty.detect_with_geometry(&tol);
    assert!(found.contacts.is_empty() && found.penetrating.is_empty());
    assert_eq!(geometry.len(), 0);
    let mut out = Vec::new();
    vtu::write_blocks_to(&empty, &mut out).unwrap();
    vtu::write_faces_to(&empty, &mut out).unwrap();
    csv::write_block_table_to(&empty, &mut out).unwrap();
    vtp::write_contacts_vtp_to(&found, &geometry, &mut out).unwrap();
    let back = json::from_json_str(&json::to_json_string(&empty)).unwrap();
    assert!(back.is_empty());
}

#[test]
fn blocks_far_from_the_origin_are_detected_with_finite_geometry() {
    // Mine-grid and far-away coordinates, down to the scale where the rounding floor decides.
    for offset in [5e5, 4e6, 1e9, 1e12] {
        let a = ConvexBlock::cuboid([offset; 3], [offset + 10.0; 3]).unwrap();
        let b = ConvexBlock::cuboid(
            [offset + 10.0, offset, offset],
            [offset + 20.0, offset + 10.0, offset + 10.0],
        )
        .unwrap();
        let (result, geometry) = Detector::new(Tolerance::default()).detect_with_geometry(&a, &b);
        assert_eq!(result.name(), "face-face", "offset {offset:e}");
        let g = geometry.unwrap();
        assert!(g.normal().is_finite() && g.distance().is_finite() && g.area().is_finite());
        assert!(
            (g.area() - 100.0).abs() < 1e-6,
            "offset {offset:e}: {}",
            g.area()
        );
    }
}

#[test]
fn domain_cut_planes_count_by_direction() {
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    for big in [1e200, 1e-200] {
        let cut = BlockSystem::from_domain_cut(
            cube.clone(),
            &[[big, 0.0, 0.0]],
            &[0.5 * big],
            &Tolerance::default(),
        );
        assert_eq!(cut.map(|s| s.len()).ok(), Some(2), "{big:e}");
    }
}

#[test]
fn a_cutting_normal_with_a_nan_component_is_degenerate() {
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    for n in [[1.0, f64::NAN, 0.0], [f64::NAN, 1.0, 0.0]] {
        let cut = BlockSystem::from_domain_cut(cube.clone(), &[n], &[0.5], &Tolerance::default());
        assert!(
            matches!(
                cut,
                Err(penedge::system::SystemError::DegeneratePlane { plane: 0 })
            ),
            "{n:?}"
        );
    }
}

// -- block files ----------------------------------------------------------------------------

fn small_file() -> String {
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let b = ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
    json::to_json_string(&BlockSystem::new(vec![a, b]))
}

#[test]
fn every_truncation_of_a_block_file_is_a_syntax_error() {
    let text = small_file();
    for end in 0..text.len() {
        match json::from_json_str(&text[..end]) {
            Err(IoError::Syntax { message, .. }) if end == 0 => {
                assert!(message.contains("empty"), "{message}")
            }
            Err(IoError::Syntax { message, .. }) => assert!(message.contains("line 1 column")),
            other => panic!("{end} bytes: {other:?}"),
        }
    }
    assert_eq!(json::from_json_str(&text).unwrap().len(), 2);
}

/// A generated system's file with `edit` applied to its JSON value.
fn edited(edit: impl FnOnce(&mut serde_json::Value)) -> String {
    let spec = spec::parse_toml(
        "[domain]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [2, 2, 2]\n\
         [[joints]]\ntype = 'plane'\npoint = [1, 1, 1]\nnormal = [1, 0, 0]\n\
         [[joints]]\ntype = 'disc'\ncenter = [0.5, 1, 1]\nnormal = [0, 0, 1]\nradius = 3\n",
    )
    .unwrap();
    let system = generate(&spec).unwrap().system;
    let mut value: serde_json::Value =
        serde_json::from_str(&json::to_json_string(&system)).unwrap();
    edit(&mut value);
    value.to_string()
}

#[test]
fn joints_of_a_block_file_are_checked() {
    use serde_json::json;
    let cases: [(&str, serde_json::Value, &str, &str); 7] = [
        (
            "/joints/0/normal",
            json!([0.0, 0.0, 0.0]),
            "joints[0].normal",
            "unit",
        ),
        (
            "/joints/0/normal",
            json!([0.0, 0.0, 3.0]),
            "joints[0].normal",
            "unit",
        ),
        ("/joints/0/point", json!([0.0, 0.0, 1e300]), "", ""),
        ("/joints/0/set", json!(7), "joints[0].set", "spec entry 7"),
        ("/joints/1/id", json!(0), "joints[1].id", "in order"),
        (
            "/joints/1/shape/radius",
            json!(0.0),
            "joints[1].shape.radius",
            "greater than zero",
        ),
        (
            "/joints/1/shape",
            json!({"kind": "polygon", "vertices": [[0, 0, 0], [1, 0, 0]]}),
            "joints[1].shape.vertices",
            "3 vertices",
        ),
    ];
    for (pointer, new, want_field, want) in cases {
        let text = edited(|v| *v.pointer_mut(pointer).unwrap() = new.clone());
        match json::from_json_str(&text) {
            Err(IoError::Format { field, message }) => {
                assert_eq!(field, want_field, "{pointer}");
                assert!(message.contains(want), "{pointer}: {message}");
            }
            // A finite point far away is a valid (if odd) joint.
            Ok(system) if want_field.is_empty() => {
                let again = json::to_json_string(&system);
                assert!(json::from_json_str(&again).is_ok());
            }
            other => panic!("{pointer}: {other:?}"),
        }
    }
}

#[test]
fn a_file_that_reads_always_writes_again() {
    // The bug: a joint with a zero normal was read, and writing the system back panicked
    // ("joint normals are unit vectors") in `JointRecord::attitude`.
    let text = edited(|v| v["joints"][0]["normal"] = serde_json::json!([0.0, 0.0, 0.0]));
    assert!(json::from_json_str(&text).is_err());
    let text = edited(|_| {});
    let system = json::from_json_str(&text).unwrap();
    let value = |t: &str| serde_json::from_str::<serde_json::Value>(t).unwrap();
    assert_eq!(value(&json::to_json_string(&system)), value(&text));
}

#[test]
fn a_system_cut_with_a_coarse_tolerance_reads_back() {
    // The bug: with `gap = 1e-3` (length 1e-2), the corner (0, 0, 0), 2.9e-3 from the plane,
    // counts as on it and stays where it is on the cap; the file was checked with the default
    // threshold (1e-9) and refused ("face 6 is not planar").
    let text = format!(
        "{BOX}[[joints]]\ntype = 'plane'\npoint = [0.005, 0, 0]\nnormal = [1, 1, -1]\n\
         [options]\ngap = 1e-3\n"
    );
    let system = generate(&spec::parse_toml(&text).unwrap()).unwrap().system;
    assert_eq!(system.len(), 2);
    let written = json::to_json_string(&system);
    let value: serde_json::Value = serde_json::from_str(&written).unwrap();
    let length = value["length"].as_f64().unwrap();
    assert!(length > 1e-3 && length < 1e-2, "{length}");
    let back = json::from_json_str(&written).unwrap();
    assert_eq!(back.len(), 2);
    assert_eq!(json::to_json_string(&back), written);
    // A default system writes no `length`, and a bad one is named.
    let default = json::to_json_string(&generate(&spec::parse_toml(BOX).unwrap()).unwrap().system);
    assert!(!default.contains("\"length\""));
    let with_length = |v: &str| written.replacen(&format!("\"length\":{length}"), v, 1);
    for bad in ["0.5", "-1"] {
        match json::from_json_str(&with_length(&format!("\"length\":{bad}"))) {
            Err(IoError::Format { field, message }) => {
                assert_eq!(field, "length");
                assert!(message.contains("tolerance `length`"), "{message}");
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
    let twice = with_length("\"length\":0.001,\"length\":0.001");
    assert!(matches!(
        json::from_json_str(&twice),
        Err(IoError::Syntax { .. })
    ));
}

#[test]
fn a_joint_table_built_by_hand_with_a_bad_normal_writes_without_a_panic() {
    use penedge::generation::{JointRecord, JointShape, SetKind, SetRecord};
    use penedge::geometry::{DVec3, Plane};
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    for normal in [DVec3::ZERO, DVec3::new(f64::NAN, 1.0, 0.0)] {
        let joint = JointRecord {
            set: 0,
            member: 0,
            plane: Plane {
                normal,
                point: DVec3::splat(0.5),
            },
            shape: JointShape::Infinite,
        };
        let set = SetRecord {
            name: "hand-made".into(),
            kind: SetKind::Plane,
        };
        let system =
            BlockSystem::with_provenance(vec![cube.clone()], vec![], vec![joint], vec![set]);
        let text = json::to_json_string(&system); // panicked in JointRecord::attitude
        assert!(json::from_json_str(&text).is_err(), "{normal}");
    }
}

#[test]
fn a_binary_file_is_a_syntax_error_naming_the_file() {
    let dir = scratch("binary");
    let path = dir.join("blocks.json");
    std::fs::write(&path, b"{\"format\": \xff\xfe}").unwrap();
    match json::read_json(&path) {
        Err(IoError::Syntax { path: p, message }) => {
            assert_eq!(p, path);
            assert!(message.contains("not UTF-8"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let spec_path = dir.join("spec.toml");
    std::fs::write(&spec_path, b"[domain]\ntype = \xff").unwrap();
    match spec::read_spec(&spec_path) {
        Err(IoError::Spec(e)) => {
            assert_eq!(e.field, "spec");
            assert!(matches!(e.problem, Problem::Syntax(ref m) if m.contains("not UTF-8")));
        }
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[cfg(unix)]
#[test]
fn an_endless_stream_is_an_error_not_a_hang() {
    let zero = std::path::Path::new("/dev/zero");
    if !zero.exists() {
        return;
    }
    let start = Instant::now();
    match json::read_json(zero) {
        Err(IoError::Syntax { message, .. }) => assert!(message.contains("endless"), "{message}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(spec::read_spec(zero), Err(IoError::Spec(_))));
    assert!(start.elapsed() < Duration::from_secs(60));
}

#[cfg(unix)]
#[test]
fn a_spec_from_a_pipe_is_read() {
    let dir = scratch("fifo");
    let fifo = dir.join("spec.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        return; // no mkfifo here
    }
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(fifo, BOX).unwrap())
    };
    let spec = spec::read_spec(&fifo).unwrap();
    writer.join().unwrap();
    assert_eq!(generate(&spec).unwrap().system.len(), 1);
    std::fs::remove_dir_all(dir).unwrap();
}

// -- writing --------------------------------------------------------------------------------

#[test]
fn a_write_that_fails_half_way_keeps_the_old_file_and_leaves_no_temporary() {
    let dir = scratch("atomic");
    let path = dir.join("blocks.json");
    std::fs::write(&path, "old").unwrap();
    let result = io::write_atomic(&path, |w| {
        w.write_all(b"{\"format\": \"penedge-blocks\", \"blo")?;
        Err(std::io::Error::other("disk full, say"))
    });
    assert!(matches!(result, Err(IoError::Io { .. })));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    assert_eq!(names_in(&dir), ["blocks.json"]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn writing_over_a_folder_or_under_a_file_fails_cleanly() {
    let dir = scratch("targets");
    std::fs::create_dir(dir.join("folder")).unwrap();
    std::fs::write(dir.join("file"), "x").unwrap();
    let system = BlockSystem::new(vec![ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap()]);
    for path in [dir.join("folder"), dir.join("file").join("x.json")] {
        assert!(matches!(
            json::write_json(&system, &path),
            Err(IoError::Io { .. })
        ));
        assert!(matches!(
            vtu::write_vtu(&system, &path),
            Err(IoError::Io { .. })
        ));
    }
    assert_eq!(names_in(&dir), ["file", "folder"]);
    assert!(names_in(&dir.join("folder")).is_empty());
    std::fs::remove_dir_all(dir).unwrap();
}

// -- generation specs -----------------------------------------------------------------------

fn spec_error(text: &str) -> SpecError {
    match spec::parse_toml(text) {
        Err(e) => e,
        Ok(spec) => match generate(&spec) {
            Err(penedge::generation::GenerationError::Spec(e)) => e,
            other => panic!("{text}: {other:?}"),
        },
    }
}

const BOX: &str = "[domain]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n";

#[test]
fn toml_errors_are_one_short_line_with_line_and_column() {
    let long = format!(
        "{BOX}[[joints]]\ntype = 'set'\ndip = [{}\n",
        "1, ".repeat(200_000)
    );
    for (text, starts) in [
        (
            format!("{BOX}[[joints]]\ndipp = 3\n"),
            "line 6, column 1: unknown field `dipp`",
        ),
        (long, "line 7, column "),
        (format!("{BOX}max = 2\n"), "line 5, column 1: duplicate key"),
        ("a = ".to_string() + &"[".repeat(100_000), "line 1, column "),
    ] {
        let e = spec_error(&text);
        assert_eq!(e.field, "spec");
        let message = e.to_string();
        assert!(message.starts_with(&format!("spec: {starts}")), "{message}");
        assert!(!message.contains('\n') && message.len() < 400, "{message}");
    }
}

#[test]
fn numbers_in_messages_are_short() {
    let huge =
        format!("{BOX}[[joints]]\ntype = 'set'\ndip = 1e300\ndip_direction = 0\nspacing = 1\n");
    let e = spec_error(&huge);
    assert_eq!(e.field, "joints[0].dip");
    assert!(e.to_string().ends_with("got 1e300"), "{e}");
    let tiny =
        format!("{BOX}[[joints]]\ntype = 'set'\ndip = -1e-300\ndip_direction = 0\nspacing = 1\n");
    assert!(spec_error(&tiny).to_string().ends_with("got -1e-300"));
    let plain =
        format!("{BOX}[[joints]]\ntype = 'set'\ndip = 120\ndip_direction = 0\nspacing = 1\n");
    assert!(spec_error(&plain).to_string().ends_with("got 120"));
    let e = Tolerance::new(1e308, 0.1).unwrap_err().to_string();
    assert!(e.ends_with("got 1e308"), "{e}");
}

#[test]
fn specs_that_would_take_forever_fail_fast() {
    let m = 1000;
    let normals: Vec<String> = (0..m)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / m as f64;
            format!("[{}, {}, 1]", a.cos(), a.sin())
        })
        .collect();
    let cases = [
        format!(
            "[domain]\ntype = 'halfspaces'\nnormals = [[0, 0, -1], {}]\noffsets = [0{}]\n",
            normals.join(", "),
            ", 1".repeat(m)
        ),
        format!("{BOX}[[joints]]\ntype = 'set'\ndip = 0\ndip_direction = 0\nspacing = 1e-300\n"),
        format!(
            "{BOX}[[joints]]\ntype = 'set'\ndip = 0\ndip_direction = 0\nspacing = 1e-3\n\
             origin = [0, 0, 1e300]\n"
        ),
        format!("{BOX}[[joints]]\ntype = 'set'\ndip = 0\ndip_direction = 0\nspacing = 1\nnumber = 4294967295\n"),
        "[domain]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1e300, 1, 1]\n".to_string(),
    ];
    for (i, text) in cases.iter().enumerate() {
        let start = Instant::now();
        let e = spec_error(text);
        assert!(start.elapsed() < Duration::from_secs(5), "case {i}: {e}");
        let message = e.to_string();
        assert!(
            message.contains("at most 128")
                || message.contains("more than the limit")
                || message.contains("put the origin near the domain")
                || message.contains("largest coordinate is 1e300"),
            "case {i}: {message}"
        );
    }
}

/// A block moved so far that its coordinates collapse or overflow is refused by the checked
/// moves, with the rule of construction (the unchecked ones kept the old volume: a unit cube
/// moved by 1e17 had coincident vertices and volume 1, moved by 1.7e308 twice infinite
/// vertices); and no writer writes a NaN or infinite coordinate (JSON wrote `null`, which
/// the reader refuses, the table and ParaView files `inf`).
#[test]
fn blocks_moved_beyond_double_range_are_refused_and_never_written() {
    use penedge::geometry::DVec3;
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let x = |d: f64| DVec3::new(d, 0.0, 0.0);
    // Moves within range: the same block as the unchecked move, bit for bit.
    let q = glam::DQuat::from_rotation_z(0.3);
    let moved = cube.try_transformed(q, x(1e6), 2.0).unwrap();
    let unchecked = cube.transformed(q, x(1e6), 2.0);
    assert_eq!(moved, unchecked);
    assert_eq!(moved.planes(), unchecked.planes());
    assert_eq!(moved.volume(), unchecked.volume());
    assert_eq!(
        cube.try_translated(x(5.0)).unwrap(),
        cube.translated(x(5.0))
    );
    assert_eq!(
        cube.try_rotated(q, cube.centroid()).unwrap(),
        cube.rotated(q, cube.centroid())
    );
    // Collapsed by rounding: the vertices x = 1e17 and 1e17 + 1 are one number.
    assert!(matches!(
        cube.try_translated(x(1e17)),
        Err(BlockError::RepeatedVertex { .. })
    ));
    // Beyond the largest coordinate, then beyond double precision.
    assert!(matches!(
        cube.try_translated(x(1.7e308)),
        Err(BlockError::OutOfRange { .. })
    ));
    let far = cube.translated(x(1.7e308));
    assert!(matches!(
        far.try_translated(x(1.7e308)),
        Err(BlockError::NonFiniteVertex { .. })
    ));
    assert!(matches!(
        cube.try_rotated(q, DVec3::splat(1e60)),
        Err(BlockError::OutOfRange { .. })
    ));
    // A rotation that is not a unit quaternion scaled and sheared the block, its volume
    // and centroid carried over (a cube's edge 62 long, its volume still 1): refused, with
    // its length; a normalised one (rounded) is a rotation.
    for (q, length) in [
        (glam::DQuat::from_xyzw(0.0, 0.0, 3.0, 10.0), 109f64.sqrt()),
        (glam::DQuat::from_xyzw(0.0, 0.0, 0.3, 1.0), 1.09f64.sqrt()),
        (glam::DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0), 0.0),
    ] {
        match cube.try_rotated(q, cube.centroid()) {
            Err(BlockError::NotUnitRotation { length: l }) => assert_eq!(l, length),
            other => panic!("{q:?}: {other:?}"),
        }
        assert!(
            cube.try_rotated(q.normalize() * (1.0 + 1e-12), DVec3::ZERO)
                .is_ok()
                || q.length() == 0.0
        );
    }
    assert!(matches!(
        cube.try_rotated(glam::DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0), DVec3::ZERO),
        Err(BlockError::NotUnitRotation { .. })
    ));
    for scale in [0.0, -1.0, f64::NAN] {
        assert!(
            cube.try_transformed(glam::DQuat::IDENTITY, DVec3::ZERO, scale)
                .is_err(),
            "scale {scale}"
        );
    }
    // The writers refuse a system holding an infinite block, naming it; nothing written.
    let broken = far.translated(x(1.7e308));
    assert!(!broken.vertices()[1].is_finite());
    let system = BlockSystem::new(vec![cube.clone(), broken]);
    let dir = scratch("infinite");
    let refused = |result: Result<(), IoError>| match result {
        Err(IoError::Format { field, message }) => {
            assert_eq!(field, "blocks[1]");
            assert!(message.contains("NaN or infinite"), "{message}");
        }
        other => panic!("expected a format error, got {other:?}"),
    };
    refused(json::write_json(&system, &dir.join("b.json")));
    refused(json::try_to_json_string(&system).map(|_| ()));
    refused(csv::write_block_table(&system, &dir.join("b.csv")));
    refused(vtu::write_vtu(&system, &dir.join("b.vtu")));
    refused(vtu::write_faces_vtu(&system, &dir.join("f.vtu")));
    assert!(names_in(&dir).is_empty(), "{:?}", names_in(&dir));
    let mut out = Vec::new();
    assert!(csv::write_block_table_to(&system, &mut out).is_err());
    assert!(vtu::write_blocks_to(&system, &mut out).is_err());
}

/// Planes given with a different number of normals and offsets: `from_domain_cut` dropped
/// the normals without an offset (2 normals and 1 offset gave 2 blocks, the second plane
/// ignored), and `from_planes` called the mistake an unbounded set. Both name the counts.
#[test]
fn planes_with_more_normals_than_offsets_are_refused_with_the_counts() {
    use penedge::system::SystemError;
    let domain = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let normals = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let e = BlockSystem::from_domain_cut(domain.clone(), &normals, &[0.5], &Tolerance::default())
        .unwrap_err();
    assert_eq!(
        e,
        SystemError::PlaneCount {
            normals: 2,
            offsets: 1
        }
    );
    assert!(e.to_string().starts_with("2 normals but 1 offsets"), "{e}");
    let e = BlockSystem::from_domain_cut(domain, &normals[..1], &[0.5, 0.5], &Tolerance::default())
        .unwrap_err();
    assert!(
        matches!(
            e,
            SystemError::PlaneCount {
                normals: 1,
                offsets: 2
            }
        ),
        "{e:?}"
    );

    let e = ConvexBlock::from_planes(&AXES, &[1.0; 5]).unwrap_err();
    assert_eq!(
        e,
        BlockError::PlaneCount {
            normals: 6,
            offsets: 5
        }
    );
    assert!(e.to_string().contains("6 normals but 5 offsets"), "{e}");
    ConvexBlock::from_planes(&AXES, &[1.0; 6]).unwrap();
}
