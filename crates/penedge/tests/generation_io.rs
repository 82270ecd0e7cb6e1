//! Output files: the JSON block file reads back losslessly, files are written atomically,
//! VTU and CSV hold what they should.

use penedge::generation::*;
use penedge::geometry::DVec3;
use penedge::io::{csv, json, vtu, write_atomic, IoError};
use penedge::{BlockSystem, ConvexBlock};
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penedge-io-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A system with every kind of joint and a non-box domain.
fn mixed_system() -> BlockSystem {
    let normals = [
        [1.0, 0.0, 0.2],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.1],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let domain = Domain::from_halfspaces(&normals, &[10.0, 0.0, 8.0, 0.0, 6.0, 0.0]).unwrap();
    let mut set = JointSet::new(Orientation::dip(65.0, 120.0), 1.5);
    set.deviation = Deviation {
        dip: 4.0,
        dip_direction: 8.0,
        spacing: 0.4,
    };
    set.seed = 7;
    let spec = Spec::new(domain)
        .with(Discontinuity::set(set).named("J1"))
        .with(Discontinuity::plane(
            [3.0, 3.0, 3.0],
            Orientation::dip(20.0, 300.0),
        ))
        .with(Discontinuity::disc(
            [5.0, 4.0, 2.0],
            Orientation::dip(30.0, 10.0),
            2.5,
        ))
        .with(Discontinuity::polygon(vec![
            [0.0, 0.0, 4.5],
            [9.0, 0.0, 4.5],
            [9.0, 8.0, 4.5],
        ]));
    generate(&spec).unwrap().system
}

fn same_block(a: &ConvexBlock, b: &ConvexBlock) {
    assert_eq!(a.vertices(), b.vertices());
    assert!(a.faces().eq(b.faces()));
    assert_eq!(a.planes(), b.planes());
    assert_eq!(a.face_origins(), b.face_origins());
    assert_eq!(a.edges(), b.edges());
    assert_eq!(a.volume().to_bits(), b.volume().to_bits());
    assert_eq!(a.centroid(), b.centroid());
}

#[test]
fn json_round_trip_is_lossless() {
    let system = mixed_system();
    assert!(system.len() > 20);
    let path = scratch("round").join("blocks.json");
    json::write_json(&system, &path).unwrap();
    let back = json::read_json(&path).unwrap();
    assert_eq!(back.len(), system.len());
    for (a, b) in system.blocks().iter().zip(back.blocks()) {
        same_block(a, b);
    }
    for (a, b) in system.domain().iter().zip(back.domain()) {
        same_block(a, b);
    }
    assert_eq!(back.joints(), system.joints());
    assert_eq!(back.sets(), system.sets());
    assert_eq!(json::to_json_string(&back), json::to_json_string(&system));
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn the_spec_unit_goes_into_the_system_and_its_block_file() {
    let text = |unit: &str| {
        format!(
            "unit = {unit}\n[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [3, 3, 3]\n\
             [[joints]]\ntype = \"plane\"\npoint = [1, 1, 1]\nnormal = [0, 0, 1]\n"
        )
    };
    let spec = penedge::io::spec::parse_toml(&text("\" ft \"")).unwrap();
    assert_eq!(spec.unit.as_deref(), Some("ft"));
    let system = generate(&spec).unwrap().system;
    assert_eq!(system.unit(), Some("ft"));
    let file = json::to_json_string(&system);
    assert!(file.contains("\"unit\":\"ft\""), "{file}");
    assert_eq!(json::from_json_str(&file).unwrap().unit(), Some("ft"));
    // Without a unit: none in the system, none in the file (older files read as before).
    let plain = generate(&Spec { unit: None, ..spec }).unwrap().system;
    assert_eq!(plain.unit(), None);
    assert!(!json::to_json_string(&plain).contains("\"unit\""));
    for bad in ["\"\"", "\"a very long name of a unit\"", "\"m\\u0007\""] {
        let err = penedge::io::spec::parse_toml(&text(bad)).unwrap_err();
        assert_eq!(err.field, "unit", "{bad}: {err}");
    }
}

#[test]
fn bad_block_files_are_named() {
    let system = mixed_system();
    let text = json::to_json_string(&system);
    let v3 = text.replacen("\"version\":2", "\"version\":3", 1);
    assert!(
        matches!(json::from_json_str(&v3), Err(IoError::Format { field, .. }) if field == "version")
    );
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
    value["blocks"][3]["vertices"][0][2] = serde_json::json!(1000.0);
    match json::from_json_str(&value.to_string()) {
        Err(IoError::Format { field, .. }) => assert_eq!(field, "blocks[3]"),
        other => panic!("expected a format error, got {other:?}"),
    }
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
    value["blocks"][0]["origins"][0] =
        serde_json::json!({"kind": "joint", "set": 0, "joint": 100000});
    assert!(
        matches!(json::from_json_str(&value.to_string()), Err(IoError::Format { field, .. }) if field == "blocks[0].origins[0]")
    );
    assert!(matches!(
        json::from_json_str("{\"format\": 1"),
        Err(IoError::Syntax { .. })
    ));
}

/// A vertex of 4 values is named as such (it was "more text after the end of the data"),
/// and a block, a joint, a shape or a face origin given as a list of its fields' values
/// is refused (serde read them as the fields in order).
#[test]
fn block_files_need_lists_of_3_values_and_tables_of_fields() {
    let system = mixed_system();
    let text = json::to_json_string(&system);
    let syntax = |value: &serde_json::Value| match json::from_json_str(&value.to_string()) {
        Err(IoError::Syntax { message, .. }) => message,
        other => panic!("expected a syntax error, got {other:?}"),
    };
    let original: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut value = original.clone();
    value["blocks"][0]["vertices"][0] = serde_json::json!([0.0, 0.0, 0.0, 0.0]);
    let message = syntax(&value);
    assert!(
        message.contains("got a list of 4 values, expected a list of 3 values"),
        "{message}"
    );
    assert!(!message.contains("more text"), "{message}");
    let mut value = original.clone();
    value["joints"][0]["normal"] = serde_json::json!([0.0, 0.0, 1.0, 0.0]);
    assert!(syntax(&value).contains("got a list of 4 values"));
    let mut value = original.clone();
    value["blocks"][0]["planes"][0] = serde_json::json!([0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
    assert!(syntax(&value).contains("got a list of 7 values, expected a list of 6 values"));
    // Lists of the fields' values in place of tables.
    let as_list = |v: &serde_json::Value| {
        serde_json::Value::Array(v.as_object().unwrap().values().cloned().collect())
    };
    let mut value = original.clone();
    let block = value["blocks"][0].clone();
    value["blocks"][0] = as_list(&block);
    assert!(syntax(&value).contains("got a list, expected a table of fields"));
    let mut value = original.clone();
    value["blocks"][0]["origins"][0] = serde_json::json!(["joint", 0, 0]);
    assert!(syntax(&value).contains("got a list, expected a table of fields"));
    let mut value = original.clone();
    let joint = value["joints"][0].clone();
    value["joints"][0] = as_list(&joint);
    assert!(syntax(&value).contains("got a list, expected a table of fields"));
    let mut value = original.clone();
    value["sets"][0] = serde_json::json!(["name", "plane"]);
    assert!(syntax(&value).contains("got a list, expected a table of fields"));
    // The file as written still reads.
    assert_eq!(
        json::from_json_str(&text).unwrap().blocks(),
        system.blocks()
    );
}

/// A boundary origin names a face its domain part has, a joint origin a joint of its own
/// set; the message writes the origin as the file does (it printed Rust's `Joint { .. }`).
#[test]
fn face_origins_must_match_the_domain_and_the_joint_table() {
    let system = mixed_system();
    let text = json::to_json_string(&system);
    let original: serde_json::Value = serde_json::from_str(&text).unwrap();
    let joints = original["joints"].as_array().unwrap();
    let (j, other) = (0..joints.len())
        .find_map(|j| {
            let set = joints[j]["set"].as_u64().unwrap();
            (set > 0).then(|| (j, set - 1))
        })
        .expect("a joint of a set other than 0");
    let refused = |origin: serde_json::Value| {
        let mut value = original.clone();
        value["blocks"][0]["origins"][0] = origin;
        match json::from_json_str(&value.to_string()) {
            Err(IoError::Format { field, message }) => {
                assert_eq!(field, "blocks[0].origins[0]", "{message}");
                message
            }
            other => panic!("expected a format error, got {other:?}"),
        }
    };
    let m = refused(serde_json::json!({"kind": "boundary", "part": 0, "face": 99}));
    assert!(
        m.starts_with("{\"kind\":\"boundary\",\"part\":0,\"face\":99}: face 99 does not exist"),
        "{m}"
    );
    let m = refused(serde_json::json!({"kind": "joint", "set": other, "joint": j}));
    assert!(m.contains(&format!("joint {j} is of set")), "{m}");
    let m = refused(serde_json::json!({"kind": "bridge", "set": other, "joint": j}));
    assert!(m.contains("not of set"), "{m}");
    let m = refused(serde_json::json!({"kind": "joint", "set": 0, "joint": 99999}));
    assert!(
        m.starts_with("{\"kind\":\"joint\",\"set\":0,\"joint\":99999}: joint 99999 does not exist"),
        "{m}"
    );
    assert!(!m.contains("Joint {"), "{m}");
    let m = refused(serde_json::json!({"kind": "boundary", "part": 7, "face": 0}));
    assert!(m.contains("domain part 7 does not exist"), "{m}");
}

/// The faces an excavation made are free faces (the outside of the rock mass) in the block
/// table and the ParaView file, as docs/generation.md says (only boundary faces counted).
#[test]
fn excavation_faces_are_free_faces() {
    let text = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\
        [[joints]]\ntype = \"plane\"\npoint = [5, 5, 5]\nnormal = [0, 0, 1]\n\
        [[excavations]]\ntype = \"tunnel\"\nprofile = \"circle\"\nradius = 2\n\
        start = [5, -1, 5]\ntrend = 0\nlength = 12\n";
    let system = generate(&penedge::io::spec::parse_toml(text).unwrap())
        .unwrap()
        .system;
    let excavation = system
        .sets()
        .iter()
        .position(|s| s.kind == SetKind::Excavation)
        .unwrap() as u32;
    let expected: Vec<usize> = system
        .blocks()
        .iter()
        .map(|b| {
            b.face_origins()
                .iter()
                .filter(|o| {
                    o.is_boundary()
                        || matches!(o, FaceOrigin::Joint { set, .. } if *set == excavation)
                })
                .count()
        })
        .collect();
    let boundary: Vec<usize> = system
        .blocks()
        .iter()
        .map(|b| b.face_origins().iter().filter(|o| o.is_boundary()).count())
        .collect();
    assert!(expected.iter().zip(&boundary).all(|(e, b)| e > b));
    let mut table = Vec::new();
    csv::write_block_table_to(&system, &mut table).unwrap();
    let column: Vec<usize> = String::from_utf8(table)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(column, expected);
    let mut vtu_text = Vec::new();
    vtu::write_blocks_to(&system, &mut vtu_text).unwrap();
    let free = data_array(&String::from_utf8(vtu_text).unwrap(), "n_free_faces");
    let free: Vec<usize> = free.iter().map(|&v| v as usize).collect();
    assert_eq!(free, expected);
}

/// A system built of blocks taken from a generated one keeps their face origins but has no
/// domain and no joint table: its file reads back with the origins as written (they used to
/// be refused as pointing to sets and joints the file does not have).
#[test]
fn blocks_taken_out_of_a_system_read_back_with_their_origins() {
    let generated = mixed_system();
    let taken = BlockSystem::new(generated.blocks().iter().step_by(2).cloned().collect());
    let joint_faces = taken
        .blocks()
        .iter()
        .flat_map(|b| b.face_origins())
        .filter(|o| matches!(o, penedge::block::FaceOrigin::Joint { .. }))
        .count();
    assert!(joint_faces > 0);
    assert!(taken.sets().is_empty() && taken.joints().is_empty());
    let back = json::from_json_str(&json::to_json_string(&taken)).unwrap();
    assert_eq!(back.blocks(), taken.blocks());
    // With a joint table, an origin outside it is still refused (bad_block_files_are_named).
}

#[test]
fn a_block_file_written_by_hand_needs_vertices_and_faces_only() {
    // Two unit cubes side by side; volume, centroid, planes and origins derived.
    let text = r#"{"format": "penedge-blocks", "version": 1, "blocks": [
        {"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
         "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]},
        {"vertices": [[1,0,0],[2,0,0],[2,1,0],[1,1,0],[1,0,1],[2,0,1],[2,1,1],[1,1,1]],
         "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]],
         "volume": 99, "centroid": [9, 9, 9]}
    ]}"#;
    let system = json::from_json_str(text).unwrap();
    assert_eq!(system.len(), 2);
    let centroids = [[0.5, 0.5, 0.5], [1.5, 0.5, 0.5]];
    for (b, c) in system.blocks().iter().zip(centroids) {
        assert!((b.volume() - 1.0).abs() < 1e-12);
        assert!((b.centroid() - DVec3::from_array(c)).length() < 1e-12);
        assert_eq!(b.n_faces(), 6);
        assert!(b.face_origins().iter().all(|o| *o == FaceOrigin::Unknown));
        for (f, plane) in b.planes().iter().enumerate() {
            for &v in b.face(f) {
                assert!(plane.distance(b.vertices()[v as usize]).abs() < 1e-12);
            }
            // Outward: the centroid is inside.
            assert!(plane.distance(b.centroid()) < 0.0);
        }
    }
    assert!(system.domain().is_empty() && system.joints().is_empty());
    // Written back in full, it reads back the same.
    let full = json::to_json_string(&system);
    assert!(full.contains("\"planes\"") && full.contains("\"volume\":1"));
    assert_eq!(
        json::to_json_string(&json::from_json_str(&full).unwrap()),
        full
    );
    // Faces given the wrong way round are named.
    let inverted = text.replace("[0,3,2,1],[4,5,6,7]", "[0,1,2,3],[4,7,6,5]");
    match json::from_json_str(&inverted) {
        Err(IoError::Format { field, .. }) => assert_eq!(field, "blocks[0]"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_file_of_another_kind_is_named_with_what_to_do() {
    let cases = [
        (
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\n",
            "joint spec (TOML)",
        ),
        (
            "{\"domain\": {\"type\": \"box\"}, \"joints\": []}",
            "joint spec (JSON)",
        ),
        ("[1, 2, 3]", "JSON list"),
    ];
    for (text, kind) in cases {
        match json::from_json_str(text) {
            Err(IoError::Syntax { message, .. }) => {
                assert!(message.contains(kind), "{message}");
                assert!(!message.contains("expected a string"), "{message}");
            }
            other => panic!("{text}: {other:?}"),
        }
    }
    // And a block file given as a spec.
    let blocks = json::to_json_string(&mixed_system());
    let err = penedge::io::spec::parse_json(&blocks).unwrap_err();
    assert!(err.to_string().contains("penedge detect"), "{err}");
}

#[test]
fn writes_are_atomic() {
    let dir = scratch("atomic");
    let path = dir.join("table.csv");
    std::fs::write(&path, "old").unwrap();
    let failed = write_atomic(&path, |w| {
        w.write_all(b"half a fi")?;
        Err(std::io::Error::other("disk full"))
    });
    assert!(failed.is_err());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    write_atomic(&path, |w| w.write_all(b"new")).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "no temporary file left: {names:?}");
    let missing = dir.join("no/such/folder/blocks.json");
    assert!(matches!(
        json::write_json(&mixed_system(), &missing),
        Err(IoError::Io { .. })
    ));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_block_table_lists_every_block() {
    let system = mixed_system();
    let path = scratch("csv").join("blocks.csv");
    csv::write_block_table(&system, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(csv::HEADER));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), system.len());
    for (row, b) in rows.iter().zip(system.blocks()) {
        assert_eq!(row[1], b.volume());
        assert_eq!([row[2], row[3], row[4]], b.centroid().to_array());
        assert_eq!(row[5] as usize, b.n_faces());
    }
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

fn data_array(text: &str, name: &str) -> Vec<f64> {
    let start = text
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no {name}"));
    let body = &text[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
    body.split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

#[test]
fn vtu_files_hold_polyhedra_and_faces() {
    let system = mixed_system();
    let dir = scratch("vtu");
    vtu::write_vtu(&system, &dir.join("blocks.vtu")).unwrap();
    vtu::write_faces_vtu(&system, &dir.join("faces.vtu")).unwrap();
    let blocks = std::fs::read_to_string(dir.join("blocks.vtu")).unwrap();
    let n_points: usize = system.blocks().iter().map(|b| b.vertices().len()).sum();
    assert!(blocks.contains(&format!(
        "NumberOfPoints=\"{n_points}\" NumberOfCells=\"{}\"",
        system.len()
    )));
    assert_eq!(data_array(&blocks, "Points").len(), 3 * n_points);
    assert!(data_array(&blocks, "types").iter().all(|&t| t == 42.0));
    let faces = data_array(&blocks, "faces");
    assert_eq!(
        *data_array(&blocks, "faceoffsets").last().unwrap() as usize,
        faces.len()
    );
    assert_eq!(
        data_array(&blocks, "volume")[5],
        system.blocks()[5].volume()
    );
    let face_file = std::fs::read_to_string(dir.join("faces.vtu")).unwrap();
    let n_faces: usize = system.blocks().iter().map(|b| b.n_faces()).sum();
    let origin = data_array(&face_file, "origin");
    assert_eq!(origin.len(), n_faces);
    assert!(origin.contains(&1.0) && origin.contains(&2.0) && !origin.contains(&0.0));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn statistics_of_a_regular_system() {
    // 4 x 4 slabs of 2.5 x 2.5 x 10: all 62.5.
    let set = |dd: f64| {
        let mut s = JointSet::new(Orientation::dip(90.0, dd), 2.5);
        s.origin = [2.5, 2.5, 0.0];
        Discontinuity::set(s)
    };
    let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap())
        .with(set(90.0))
        .with(set(0.0));
    let stats = BlockStatistics::of(generate(&spec).unwrap().system.blocks()).unwrap();
    assert_eq!(stats.count, 16);
    for v in [
        stats.v10,
        stats.v50,
        stats.v90,
        stats.min_volume,
        stats.max_volume,
    ] {
        assert!((v - 62.5).abs() < 1e-9);
    }
    let curve = distribution_curve(&[1.0, 3.0]);
    assert_eq!((curve[0].passing, curve[1].passing), (0.25, 1.0));
}

#[test]
fn flat_arrays_index_every_face() {
    let system = mixed_system();
    let a = system.arrays();
    assert_eq!(a.vertex_offsets.len(), system.len() + 1);
    assert_eq!(
        *a.face_offsets.last().unwrap() as usize,
        a.origin_kind.len()
    );
    assert_eq!(
        *a.loop_offsets.last().unwrap() as usize,
        a.face_vertices.len()
    );
    let b = 7;
    let block = &system.blocks()[b];
    let f0 = a.face_offsets[b] as usize;
    for (f, face) in block.faces().enumerate() {
        let (s, e) = (
            a.loop_offsets[f0 + f] as usize,
            a.loop_offsets[f0 + f + 1] as usize,
        );
        for (k, &v) in a.face_vertices[s..e].iter().enumerate() {
            assert_eq!(
                a.vertices[v as usize],
                block.vertices()[face[k] as usize].to_array()
            );
        }
        assert_eq!(a.origin_kind[f0 + f], block.face_origins()[f].code());
    }
    assert_eq!(a.volumes[b], block.volume());
}
