//! A block system generated from joint sets, and every contact in it, counted by type.
//!
//! Run: `cargo run --release -p penedge --example block_system`
//!
//! Three ways to the same kind of system:
//! 1. the generation API in Rust (`penedge::generation`: a `Spec` of a domain and its joints);
//! 2. the same spec as TOML text (`penedge::io::spec::parse_toml`): the file format of
//!    `penedge generate` and of the repository's `examples/*.toml` (docs/generation.md);
//! 3. a spec file read from disk (`penedge::io::spec::read_spec`): the paper's Example 3.
//!
//! (`BlockSystem::from_domain_cut(domain, normals, offsets, tol)` cuts a block by planes
//! `n . x = d` directly, without a spec; the generation API adds joint sets, finite joints,
//! excavations, slivers, a report and the joint table behind each face.)
use penedge::block::FaceOrigin;
use penedge::generation::{generate, Discontinuity, Domain, JointSet, Orientation, Spec};
use penedge::glam::DVec3;
use penedge::io::spec::{parse_toml, read_spec};
use penedge::system::{count_types, paper_table3, PaperExample};
use penedge::{BlockSystem, ContactType, ConvexBlock, Feature, Tolerance};
use std::path::Path;
use std::time::Instant;

fn main() {
    // --- 1. A spec in Rust -----------------------------------------------------------------
    // A 12 m x 10 m x 6 m box (x East, y North, z up) cut by a nearly flat bedding set and two
    // steep joint sets. Orientation::dip(dip, dip_direction) in degrees; a set fills the domain
    // with planes `spacing` apart, the first through `origin`.
    let set = |dip: f64, dip_direction: f64, spacing: f64, name: &str| {
        let mut set = JointSet::new(Orientation::dip(dip, dip_direction), spacing);
        set.origin = [0.3, 0.7, 0.11];
        Discontinuity::set(set).named(name)
    };
    let spec = Spec::new(Domain::cuboid([0.0; 3], [12.0, 10.0, 6.0]).expect("a valid box"))
        .with(set(8.0, 120.0, 2.0, "bedding"))
        .with(set(75.0, 30.0, 3.0, "J1"))
        .with(set(80.0, 290.0, 3.5, "J2"));
    let clock = Instant::now();
    let generated = generate(&spec).expect("the spec generates");
    let system = generated.system;
    let report = generated.report;
    println!(
        "generated {} blocks from {} joint planes in {:.1} ms (volume error {:.1e})",
        system.len(),
        report.joint_planes,
        clock.elapsed().as_secs_f64() * 1e3,
        report.volume_error
    );
    let volume: f64 = system.blocks().iter().map(ConvexBlock::volume).sum();
    assert!((volume - 12.0 * 10.0 * 6.0).abs() < 1e-9 * 720.0);
    assert!(report.volume_error < 1e-12);

    // --- Every contact, with its geometry ----------------------------------------------------
    // `detect` gives the types and features; `detect_with_geometry` adds the normals,
    // distances, areas and points as flat arrays, row i for contact i.
    let tol = Tolerance::default(); // exactly touching blocks touch
    let clock = Instant::now();
    let (found, geometry) = system.detect_with_geometry(&tol);
    println!(
        "{} contacts, {} penetrating pairs, in {:.1} ms",
        found.contacts.len(),
        found.penetrating.len(),
        clock.elapsed().as_secs_f64() * 1e3
    );
    print_counts(&count_types(&found.contacts));
    assert!(found.penetrating.is_empty());
    assert_eq!(geometry.len(), found.contacts.len());
    // `detect` gives the same contacts, without the geometry.
    assert_eq!(system.detect(&tol), found);

    // Which joint a face-face contact lies on: the face of block A (`pair[0]`) that holds it,
    // and that face's origin (the spec entry, `set`, and the plane in the joint table). A DEM
    // code reads its joint properties from `set`.
    let mut face_face_area = [0.0; 3];
    for (i, c) in found.contacts.iter().enumerate() {
        if c.contact.kind != ContactType::FaceFace {
            continue;
        }
        let Feature::Face(f) = c.contact.feature_a else {
            panic!("a face-face contact holds a face of each block");
        };
        let block = &system.blocks()[c.pair[0] as usize];
        match block.face_origins()[f as usize] {
            FaceOrigin::Joint { set, .. } => face_face_area[set as usize] += geometry.areas[i],
            other => panic!("a face-face contact on a face from {other:?}"),
        }
        // The normal, from pair[0] to pair[1], is the face's outward normal (up to rounding).
        let n = DVec3::from_array(geometry.normals[i]);
        assert!((n - block.planes()[f as usize].normal).length() < 1e-9);
    }
    // Each joint face inside the domain is shared by two blocks, with one face-face contact
    // between them (the sets' planes cross the whole domain): twice the contacts' area on a
    // set is the area of all the blocks' faces on it.
    let mut face_area = [0.0; 3];
    for block in system.blocks() {
        for (f, origin) in block.face_origins().iter().enumerate() {
            if let Some(set) = origin.set() {
                face_area[set as usize] += polygon_area(block, f);
            }
        }
    }
    for (k, name) in ["bedding", "J1", "J2"].iter().enumerate() {
        println!(
            "  face-face on {name:7}: {:9.3} m2 (faces on it: {:9.3} m2 = 2 x {:.3})",
            face_face_area[k],
            face_area[k],
            face_area[k] / 2.0
        );
        assert!((2.0 * face_face_area[k] - face_area[k]).abs() < 1e-9 * face_area[k]);
    }

    // --- 2. The same spec as TOML ----------------------------------------------------------
    let toml = r#"
        [domain]
        type = "box"
        min = [0, 0, 0]
        max = [12, 10, 6]

        [[joints]]
        type = "set"
        name = "bedding"
        dip = 8
        dip_direction = 120
        spacing = 2.0
        origin = [0.3, 0.7, 0.11]

        [[joints]]
        type = "set"
        name = "J1"
        dip = 75
        dip_direction = 30
        spacing = 3.0
        origin = [0.3, 0.7, 0.11]

        [[joints]]
        type = "set"
        name = "J2"
        dip = 80
        dip_direction = 290
        spacing = 3.5
        origin = [0.3, 0.7, 0.11]
    "#;
    let from_toml = generate(&parse_toml(toml).expect("a valid spec"))
        .expect("the spec generates")
        .system;
    println!("\nthe same spec as TOML: {} blocks", from_toml.len());
    assert_eq!(from_toml.len(), system.len());
    for (x, y) in from_toml.blocks().iter().zip(system.blocks()) {
        assert_eq!(x.vertices(), y.vertices());
    }
    assert_eq!(from_toml.detect(&tol), found);

    // --- 3. A spec file: the paper's Example 3 -----------------------------------------------
    // read_spec takes TOML, or JSON for a name ending in .json.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/paper_example_3.toml");
    let spec = read_spec(&path).expect("the example spec reads");
    let paper: BlockSystem = generate(&spec).expect("the spec generates").system;
    let found = paper.detect(&tol);
    let counts = count_types(&found.contacts);
    println!(
        "\n{}: {} blocks, {} contacts",
        path.file_name().unwrap().to_string_lossy(),
        paper.len(),
        found.contacts.len()
    );
    print_counts(&counts);
    // The paper's Table 3: 205 vertex-vertex, 78 edge-edge superpositions, 42 face-face.
    assert_eq!(paper.len(), 26);
    assert_eq!(counts, paper_table3(PaperExample::Three));
    println!("\nall checks passed");
}

/// Prints the counts of the seven contact types.
fn print_counts(counts: &[usize; 7]) {
    for (kind, count) in ContactType::ALL.iter().zip(counts) {
        println!("  {:24} {count:5}", kind.name());
    }
}

/// The area of face `f` of a block (half the length of the sum of its edges' cross
/// products).
fn polygon_area(block: &ConvexBlock, f: usize) -> f64 {
    let v = block.vertices();
    let face = block.face(f);
    let mut sum = DVec3::ZERO;
    for (k, &i) in face.iter().enumerate() {
        let j = face[(k + 1) % face.len()];
        sum += v[i as usize].cross(v[j as usize]);
    }
    0.5 * sum.length()
}
