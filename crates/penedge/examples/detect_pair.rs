//! One pair of blocks: the contact type, the normal, the signed distance, the contact
//! points and the area.
//!
//! Run: `cargo run --release -p penedge --example detect_pair`
//!
//! Conventions (docs/contact-geometry.md):
//! * the normal is a unit vector **from A to B** (the first block given to the second);
//!   swapping the blocks gives exactly the opposite normal;
//! * the distance is signed along that normal: **positive is a gap** (the blocks are apart),
//!   **negative is a depth** (they overlap); a pair counts as touching while the distance is
//!   within the tolerance's gap either way, and as `Penetrating` deeper than that;
//! * the points are one point, the two ends of a segment, or the vertices of a convex
//!   polygon (face-face), counter-clockwise about the normal, on the plane halfway between
//!   the blocks;
//! * the area of a face-face contact is the overlap of the two faces **widened by the gap**
//!   (docs/tolerance.md, "Lies in"): with a gap of 1e-3 it is a little larger than the exact
//!   overlap of the faces.
use penedge::contact_geometry::ContactGeometry;
use penedge::glam::DVec3;
use penedge::{detect_pair, ContactType, ConvexBlock, Detector, Feature, PairResult, Tolerance};

fn main() {
    // Block A: a unit cube (from its corners).
    let a = ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).expect("a valid box");

    // Block B: from half-spaces n . x <= d (normals need not be unit vectors). A slab
    // 1 <= z <= 2, 0.5 <= x, x + z <= 3.5 (a sloping end), 0.25 <= y <= 0.75. Its bottom
    // face (x in [0.5, 2.5], y in [0.25, 0.75], z = 1) lies on A's top face over
    // x in [0.5, 1], y in [0.25, 0.75]: an overlap of 0.5 x 0.5 = 0.25.
    let normals = [
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
    ];
    let offsets = [-1.0, 2.0, -0.5, 3.5, 0.75, -0.25];
    let b = ConvexBlock::from_planes(&normals, &offsets).expect("a bounded block");
    println!(
        "A: {} vertices, {} faces, volume {}; B: {} vertices, {} faces, volume {}",
        a.vertices().len(),
        a.n_faces(),
        a.volume(),
        b.vertices().len(),
        b.n_faces(),
        b.volume()
    );

    // --- The free function: the type only -------------------------------------------------
    // The default tolerance has a relative gap of 1e-12: rounding only, so exactly touching
    // blocks touch and nothing else does.
    let exact = Tolerance::default();
    let result = detect_pair(&a, &b, &exact);
    println!("\ndetect_pair(A, B): {}", result.name());
    let PairResult::Contact(contact) = result else {
        panic!("A and B touch, got {}", result.name());
    };
    // The features that hold the contact: a face of each block here.
    println!(
        "  type {:?} (code {}), feature of A {:?}, feature of B {:?}",
        contact.kind,
        contact.kind.code(),
        contact.feature_a,
        contact.feature_b
    );
    assert_eq!(contact.kind, ContactType::FaceFace);
    assert!(matches!(contact.feature_a, Feature::Face(_)));
    assert!(matches!(contact.feature_b, Feature::Face(_)));

    // --- A Detector: the type and the geometry ----------------------------------------------
    // A Detector keeps its scratch buffers: reuse one in a loop over many pairs.
    let mut detector = Detector::new(exact);
    let (_, geometry) = detector.detect_with_geometry(&a, &b);
    let g = geometry.expect("a contact has a geometry");
    show("A-B, touching exactly", &g);
    // The normal goes from A to B: up, from A's top face into B.
    assert_eq!(g.normal(), DVec3::Z);
    assert!(g.distance().abs() < 1e-12);
    assert!((g.area() - 0.25).abs() < 1e-9);
    assert_eq!(g.points().len(), 4); // the square x in [0.5, 1], y in [0.25, 0.75]
    for p in g.points() {
        assert!((p.z - 1.0).abs() < 1e-12 && (0.5..=1.0 + 1e-12).contains(&p.x));
    }
    // Swapping the blocks turns the normal round, exactly; the distance stays.
    let (_, swapped) = detector.detect_with_geometry(&b, &a);
    let swapped = swapped.expect("still a contact");
    assert_eq!(swapped.normal(), -g.normal());
    assert_eq!(swapped.distance(), g.distance());

    // --- The distance sign and the gap -----------------------------------------------------
    // A DEM code sets the gap it allows: relative to the smaller block's size (the diagonal of
    // its bounding box), here 1e-3 x sqrt(3) = 1.73 mm for A.
    let dem = Tolerance::with_gap(1e-3).expect("a valid gap");
    let mut detector = Detector::new(dem);
    let gap = detector.thresholds(&a, &b).gap;
    println!("\nwith a relative gap of 1e-3: the pair's absolute gap is {gap:.6}");
    assert!((gap - 1e-3 * 3f64.sqrt()).abs() < 1e-15);
    let lift = 1e-3; // less than the gap
    for dz in [lift, -lift] {
        let moved = b.translated(DVec3::new(0.0, 0.0, dz));
        let (result, geometry) = detector.detect_with_geometry(&a, &moved);
        let g = geometry.expect("within the gap: a contact");
        show(&format!("B moved by {dz:+e} along z"), &g);
        assert_eq!(result.contact_type(), Some(ContactType::FaceFace));
        // Moving B by t along the normal adds t to the distance: + is a gap, - a depth.
        assert!((g.distance() - dz).abs() < 1e-12);
        // The area includes the gap's band: a little more than the faces' exact overlap.
        assert!(g.area() > 0.25 && g.area() < (0.5 + 2.0 * gap).powi(2));
    }
    // Beyond the gap: separated when lifted, penetrating when pressed in.
    let far = 2.0 * gap;
    let up = detector.detect(&a, &b.translated(DVec3::new(0.0, 0.0, far)));
    let down = detector.detect(&a, &b.translated(DVec3::new(0.0, 0.0, -far)));
    println!(
        "B moved by +/-{far:.6} (twice the gap): {} / {}",
        up.name(),
        down.name()
    );
    assert_eq!(up, PairResult::Separated);
    assert_eq!(down, PairResult::Penetrating);

    // --- A block from a convex hull: a vertex on a face --------------------------------------
    // An octahedron (the hull of its six corners; an interior point is dropped) whose lowest
    // corner sits on A's right face x = 1 at (1, 0.5, 0.5): a vertex-face contact, one point.
    let c = DVec3::new(1.5, 0.5, 0.5);
    let r = 0.5;
    let corners: Vec<[f64; 3]> = [
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
        DVec3::ZERO,
    ]
    .iter()
    .map(|d| (c + *d * r).to_array())
    .collect();
    let octahedron = ConvexBlock::hull(&corners).expect("a valid hull");
    assert_eq!((octahedron.vertices().len(), octahedron.n_faces()), (6, 8));
    let mut detector = Detector::new(exact);
    let (result, geometry) = detector.detect_with_geometry(&a, &octahedron);
    let g = geometry.expect("the corner touches A's face");
    println!("\nA-octahedron: {}", result.name());
    show("A-octahedron", &g);
    assert_eq!(result.contact_type(), Some(ContactType::VertexFace));
    // The face is A's, so the normal is that face's outward normal: +x, from A to B.
    assert_eq!(g.normal(), DVec3::X);
    assert_eq!(g.points().len(), 1);
    assert!((g.points()[0] - DVec3::new(1.0, 0.5, 0.5)).length() < 1e-12);
    // Only a polygon has an area.
    assert_eq!(g.area(), 0.0);
    // B lies above z = 1 and the octahedron's top corner is at z = 1: it touches B's bottom
    // face at that vertex (x = 1.5, y = 0.5, z = 1), another vertex-face contact.
    let bo = detect_pair(&b, &octahedron, &exact);
    println!("B-octahedron: {}", bo.name());
    assert_eq!(bo.contact_type(), Some(ContactType::VertexFace));
    println!("\nall checks passed");
}

/// Prints a contact's geometry.
fn show(what: &str, g: &ContactGeometry) {
    println!(
        "  {what}: normal {:?}, distance {:+.3e}, area {:.6}, {} point(s):",
        g.normal().to_array(),
        g.distance(),
        g.area(),
        g.points().len()
    );
    for p in g.points() {
        println!("    ({:.6}, {:.6}, {:.6})", p.x, p.y, p.z);
    }
}
