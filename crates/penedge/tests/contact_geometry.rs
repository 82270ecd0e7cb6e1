//! Contact geometry (normal, points, area, signed distance) against the exact intersections
//! of `tests/data/dev-cases.json`, under swaps, rotations and motions along the normal,
//! and the paper's examples against their shared face areas computed by hand.

use glam::{DQuat, DVec3};
use penedge::classify::Contact;
use penedge::contact_geometry::{ContactGeometry, ContactPoints};
use penedge::system::{paper_example, PaperExample};
use penedge::{ContactType, ConvexBlock, Detector, Feature, PairResult, Tolerance};
use proptest::prelude::*;
use serde_json::Value;
use std::path::PathBuf;
use std::sync::OnceLock;
use ContactType::{EdgeEdge, EdgeFace, FaceFace, VertexFace};

/// Agreement required, relative to the pair's size (areas: to its square).
const REL: f64 = 1e-9;

/// A dev case.
struct Case {
    id: String,
    expected: String,
    a: ConvexBlock,
    b: ConvexBlock,
    intersection: Vec<DVec3>,
    /// For a pair moved off a contact along its normal: the exact distance moved.
    shift: Option<f64>,
}

fn cases_path() -> PathBuf {
    if let Ok(dir) = std::env::var("PENEDGE_SHARED") {
        return PathBuf::from(dir).join("cases/dev-cases.json");
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/dev-cases.json")
}

fn numbers<T>(v: &Value, each: impl Fn(&Value) -> T) -> Vec<T> {
    v.as_array().unwrap().iter().map(each).collect()
}

fn block(v: &Value) -> ConvexBlock {
    let vertices = numbers(&v["vertices"], |p| {
        let c = numbers(p, |x| x.as_f64().unwrap());
        [c[0], c[1], c[2]]
    });
    let faces = numbers(&v["faces"], |f| {
        numbers(f, |i| i.as_u64().unwrap() as usize)
    });
    ConvexBlock::new(&vertices, &faces).unwrap()
}

/// An exact rational "p/q" (or "p") as the nearest double, near enough.
fn fraction(v: &Value) -> f64 {
    let s = v.as_str().unwrap();
    match s.split_once('/') {
        Some((p, q)) => p.parse::<f64>().unwrap() / q.parse::<f64>().unwrap(),
        None => s.parse().unwrap(),
    }
}

fn case(c: &Value) -> Case {
    let near = &c["near"];
    let moved_off = near["exact_distance"].as_bool() == Some(true) && c["expected"] == "separated";
    Case {
        id: c["id"].as_str().unwrap().to_string(),
        expected: c["expected"].as_str().unwrap().to_string(),
        a: block(&c["a"]),
        b: block(&c["b"]),
        intersection: numbers(&c["intersection"], |p| {
            DVec3::from_array([fraction(&p[0]), fraction(&p[1]), fraction(&p[2])])
        }),
        shift: moved_off.then(|| near["shift"].as_f64().unwrap()),
    }
}

/// Every dev case.
fn cases() -> &'static [Case] {
    static CASES: OnceLock<Vec<Case>> = OnceLock::new();
    CASES.get_or_init(|| {
        let text = std::fs::read_to_string(cases_path()).expect("dev cases");
        let all: Vec<Value> = serde_json::from_str(&text).unwrap();
        all.iter().map(case).collect()
    })
}

/// The dev cases with a contact (not separated, not penetrating).
fn contact_cases() -> Vec<&'static Case> {
    let no_contact = ["separated", "penetrating"];
    cases()
        .iter()
        .filter(|c| !no_contact.contains(&c.expected.as_str()))
        .collect()
}

fn scale(a: &ConvexBlock, b: &ConvexBlock) -> f64 {
    a.size().min(b.size())
}

type Touch = (Contact, ContactGeometry);

/// The contact and its geometry; panics when the pair does not touch.
fn touch(det: &mut Detector, a: &ConvexBlock, b: &ConvexBlock) -> Touch {
    match det.detect_with_geometry(a, b) {
        (PairResult::Contact(c), Some(g)) => (c, g),
        (r, _) => panic!("expected a contact, got {}", r.name()),
    }
}

/// The length over which a rounding of the coordinates turns the normal: the pair's size,
/// or for an edge-edge crossing the shorter edge times the sine of the edges' angle (the
/// crossing's normal and point are ill-conditioned at small angles).
fn conditioning(a: &ConvexBlock, b: &ConvexBlock, c: &Contact) -> f64 {
    let edge = |block: &ConvexBlock, e: u32| {
        let [p, q] = block.edges()[e as usize].vertices;
        block.vertices()[q as usize] - block.vertices()[p as usize]
    };
    match (c.kind, c.feature_a, c.feature_b) {
        (EdgeEdge, Feature::Edge(ea), Feature::Edge(eb)) => {
            let (u, v) = (edge(a, ea), edge(b, eb));
            u.length().min(v.length()) * u.normalize().cross(v.normalize()).length()
        }
        _ => scale(a, b),
    }
}

fn assert_none(failures: Vec<String>) {
    let n = failures.len();
    assert!(n == 0, "{n} failures:\n{}", failures.join("\n"));
}

/// Whether each point of `p` is within `tol` of a point of `q` and vice versa.
fn same_set(p: &[DVec3], q: &[DVec3], tol: f64) -> bool {
    let covered =
        |x: &[DVec3], y: &[DVec3]| x.iter().all(|s| y.iter().any(|t| s.distance(*t) <= tol));
    covered(p, q) && covered(q, p)
}

/// Area of the convex polygon with these vertices, in any order (fan from the centroid,
/// sorted by angle): independent of the engine's hull.
fn exact_area(vertices: &[DVec3]) -> f64 {
    let c = vertices.iter().sum::<DVec3>() / vertices.len() as f64;
    let (p0, p1, p2) = (vertices[0], vertices[1], vertices[2]);
    let u = (p0 - c).normalize();
    let v = (p1 - p0).cross(p2 - p0).cross(u).normalize();
    let angle = |p: &DVec3| (*p - c).dot(v).atan2((*p - c).dot(u));
    let mut ring = vertices.to_vec();
    ring.sort_by(|p, q| angle(p).total_cmp(&angle(q)));
    ring.push(ring[0]);
    let fan = ring.windows(2).map(|w| (w[0] - c).cross(w[1] - c).length());
    0.5 * fan.sum::<f64>()
}

/// Whether the polygon turns counter-clockwise about `n` at every vertex.
fn convex_ccw(points: &[DVec3], n: DVec3) -> bool {
    let k = points.len();
    (0..k).all(|i| {
        let (p, q, r) = (points[i], points[(i + 1) % k], points[(i + 2) % k]);
        (q - p).cross(r - q).dot(n) > 0.0
    })
}

/// What is wrong with the geometry of `(a, b)` against the exact case, if anything.
fn check_exact(case: &Case, a: &ConvexBlock, b: &ConvexBlock, g: &ContactGeometry) -> Vec<String> {
    let s = scale(a, b);
    let mut wrong = Vec::new();
    if !same_set(g.points(), &case.intersection, REL * s) {
        wrong.push(format!(
            "points {:?} vs exact {:?}",
            g.points(),
            case.intersection
        ));
    }
    if (g.normal().length() - 1.0).abs() > 1e-12 {
        wrong.push(format!("normal {} not unit", g.normal()));
    }
    // Exactly touching: the plane through the contact with this normal separates them.
    if g.distance().abs() > REL * s {
        wrong.push(format!("distance {} for touching blocks", g.distance()));
    }
    if let ContactPoints::Polygon(p) = g.shape() {
        let exact = exact_area(&case.intersection);
        if (p.area() - exact).abs() > REL * s * s || !convex_ccw(p.vertices(), g.normal()) {
            wrong.push(format!(
                "area {} vs exact {exact}, or not convex ccw",
                p.area()
            ));
        }
    }
    wrong
}

#[test]
fn every_dev_contact_matches_the_exact_intersection_in_both_orders() {
    let cases = contact_cases();
    assert!(cases.len() > 200, "expected the full case list");
    let mut det = Detector::new(Tolerance::default());
    let mut failures = Vec::new();
    for case in cases {
        let (kind_ab, ab) = touch(&mut det, &case.a, &case.b);
        let (kind_ba, ba) = touch(&mut det, &case.b, &case.a);
        let (kind_ab, kind_ba) = (kind_ab.kind.name(), kind_ba.kind.name());
        let mut wrong = check_exact(case, &case.a, &case.b, &ab);
        wrong.extend(check_exact(case, &case.b, &case.a, &ba));
        if kind_ab != case.expected || kind_ba != case.expected {
            wrong.push(format!("type {kind_ab} / {kind_ba}"));
        }
        if ba.normal() != -ab.normal() || ba.distance() != ab.distance() {
            wrong.push(format!("swap: {} / {}", ab.normal(), ba.normal()));
        }
        if !wrong.is_empty() {
            failures.push(format!(
                "{} [{}]: {}",
                case.id,
                case.expected,
                wrong.join("; ")
            ));
        }
    }
    assert_none(failures);
}

/// Moves B by `t` gaps along the normal found at rest; whether the features stayed, or what
/// is wrong: with the same features the normal must stay and the distance follow the motion;
/// with other features (the coarse length threshold) the distance must agree within it.
fn check_motion(det: &mut Detector, case: &Case, rest: &Touch, t: f64) -> Result<bool, String> {
    let (c0, g0) = rest;
    let (n, s) = (g0.normal(), scale(&case.a, &case.b));
    let th = det.thresholds(&case.a, &case.b);
    let moved = case.b.transformed(DQuat::IDENTITY, n * (t * th.gap), 1.0);
    let (c, g) = touch(det, &case.a, &moved);
    let error = g.distance() - (g0.distance() + t * th.gap);
    let same = (c.feature_a, c.feature_b) == (c0.feature_a, c0.feature_b);
    let allowed = if same { REL * s } else { th.length };
    if (same && g.normal().distance(n) > 1e-12) || error.abs() > allowed {
        return Err(format!(
            "{} [{}] moved by {t} gap: {}, normal {} (was {n}), distance off by {error:e}",
            case.id,
            c0.kind,
            c.kind,
            g.normal()
        ));
    }
    Ok(same)
}

/// With a gap of 1e-3, each dev contact whose type at that tolerance is still the exact
/// type is moved along its normal from 0.9 gap apart to 0.9 gap in ([`check_motion`]).
#[test]
fn distance_follows_a_motion_along_the_normal_within_the_gap() {
    let mut det = Detector::new(Tolerance::with_gap(1e-3).unwrap());
    let (mut failures, mut counts, mut coarse) = (Vec::new(), [0usize; 2], 0);
    for case in contact_cases() {
        let rest = touch(&mut det, &case.a, &case.b);
        if rest.0.kind.name() != case.expected {
            coarse += 1;
            continue;
        }
        for t in [0.9, 0.5, 0.1, -0.1, -0.5, -0.9] {
            match check_motion(&mut det, case, &rest, t) {
                Ok(same) => counts[same as usize] += 1,
                Err(e) => failures.push(e),
            }
        }
    }
    let [changed, strict] = counts;
    println!("{strict} motions, {changed} with other features, {coarse} cases of another type");
    assert!(
        strict > 1000 && changed < strict / 50,
        "{strict} / {changed}"
    );
    assert_none(failures);
}

/// Dev cases moved off a contact along its normal by an exact shift touch again with a gap
/// above the shift, at a distance equal to the shift for the types whose normal is unique
/// (the one the case moved along), and at most the shift for the others.
#[test]
fn cases_moved_off_a_contact_are_at_their_shift() {
    let mut checked = 0;
    for case in cases() {
        let Some(shift) = case.shift else { continue };
        let s = scale(&case.a, &case.b);
        let Ok(tolerance) = Tolerance::with_gap(1.5 * shift / s) else {
            continue; // a shift too large for a tolerance
        };
        let (c, g) = touch(&mut Detector::new(tolerance), &case.a, &case.b);
        let unique = [VertexFace, EdgeFace, FaceFace, EdgeEdge].contains(&c.kind);
        let d = g.distance();
        let ok = (d - shift).abs() <= REL * s || (!unique && d > 0.0 && d <= shift);
        assert!(
            ok,
            "{} ({}): distance {d} for a shift of {shift}",
            case.id, c.kind
        );
        checked += 1;
    }
    assert!(checked >= 20, "{checked} cases checked");
}

/// Total face-face contact area of a paper example.
fn face_face_area(example: PaperExample) -> f64 {
    let system = paper_example(example).unwrap();
    let blocks = system.blocks();
    let mut det = Detector::new(Tolerance::default());
    let found = system.detect(&Tolerance::default());
    assert!(found.penetrating.is_empty());
    let areas = found.contacts.iter().map(|c| {
        let (a, b) = (&blocks[c.pair[0] as usize], &blocks[c.pair[1] as usize]);
        touch(&mut det, a, b).1.area()
    });
    areas.sum()
}

/// By hand: every point of a cutting plane inside the cube, off the other planes, lies in
/// exactly one face-face contact (between the blocks on its two sides), so the total
/// face-face area is the sum over the planes of the plane's section of the 10 m cube:
/// 10 x 10 for `x = 5`, 10 sqrt(2) x 10 for `x + y = 10` (the diagonal rectangle).
#[test]
fn paper_examples_face_face_area_is_the_area_of_the_cuts() {
    let axis = 100.0;
    let diagonal = 100.0 * 2f64.sqrt();
    let expected = [
        (PaperExample::One, 3.0 * axis),
        (PaperExample::Two, 3.0 * diagonal),
        (PaperExample::Three, 3.0 * (axis + diagonal)),
    ];
    for (example, area) in expected {
        let found = face_face_area(example);
        assert!(
            (found - area).abs() <= 1e-9 * area,
            "{example:?}: {found} vs {area}"
        );
    }
}

fn rotation() -> impl Strategy<Value = DQuat> {
    prop::array::uniform4(-1.0f64..1.0)
        .prop_filter("non-zero", |q| q.iter().map(|c| c * c).sum::<f64>() > 1e-3)
        .prop_map(|q| DQuat::from_array(q).normalize())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Rotating and translating both blocks rotates the normal and the points, keeps area
    /// and distance; swapping them negates the normal exactly.
    #[test]
    fn geometry_moves_with_the_blocks(
        index in 0usize..10_000,
        q in rotation(),
        shift in prop::array::uniform3(-100.0f64..100.0),
    ) {
        let cases = contact_cases();
        let case = &cases[index % cases.len()];
        let mut det = Detector::new(Tolerance::default());
        let (c, g) = touch(&mut det, &case.a, &case.b);
        let shift = DVec3::from_array(shift);
        let (a, b) = (case.a.transformed(q, shift, 1.0), case.b.transformed(q, shift, 1.0));
        let (moved, h) = touch(&mut det, &a, &b);
        let (_, swapped) = touch(&mut det, &b, &a);
        let s = scale(&a, &b);
        // Rounding of the moved coordinates, over the length that turns the normal.
        let rounding = 8.0 * f64::EPSILON * a.aabb().magnitude().max(b.aabb().magnitude());
        let angle_tol = REL.max(rounding / conditioning(&a, &b, &moved));
        let expected_points: Vec<DVec3> = g.points().iter().map(|&p| q * p + shift).collect();
        prop_assert_eq!(moved.kind, c.kind, "{}", case.id);
        prop_assert!((h.normal().length() - 1.0).abs() < 1e-12);
        prop_assert!(h.normal().distance(q * g.normal()) <= angle_tol, "{}: {} vs {}", case.id, h.normal(), q * g.normal());
        prop_assert!(same_set(h.points(), &expected_points, angle_tol * s), "{}", case.id);
        prop_assert!((h.area() - g.area()).abs() <= REL * s * s);
        prop_assert!((h.distance() - g.distance()).abs() <= REL * s);
        prop_assert_eq!(swapped.normal(), -h.normal());
    }
}

type Pairs<'a> = Vec<(&'a ConvexBlock, &'a ConvexBlock)>;

/// Mean time per pair of `f` over `pairs`, in nanoseconds.
fn per_pair(pairs: &Pairs, f: &mut dyn FnMut(&ConvexBlock, &ConvexBlock) -> usize) -> f64 {
    let rounds = (200_000 / pairs.len()).max(1);
    let start = std::time::Instant::now();
    let mut sink = 0;
    for _ in 0..rounds {
        for (a, b) in pairs {
            sink += f(a, b);
        }
    }
    std::hint::black_box(sink);
    start.elapsed().as_nanos() as f64 / (rounds * pairs.len()) as f64
}

/// Per-pair cost of the geometry on top of the classification, by contact type, for the
/// contacts of Example 3 and the dev contacts (both orders); the best of 7 interleaved runs.
/// `cargo test -p penedge --release --test contact_geometry -- --ignored --nocapture`
#[test]
#[ignore]
fn cost_of_geometry_per_pair() {
    let system = paper_example(PaperExample::Three).unwrap();
    let (blocks, mut det) = (system.blocks(), Detector::new(Tolerance::default()));
    let mut groups = std::collections::BTreeMap::<String, Pairs>::new();
    for [i, j] in system.candidate_pairs(&Tolerance::default()) {
        let (a, b) = (&blocks[i as usize], &blocks[j as usize]);
        let name = format!("example 3, {}", det.detect(a, b).name());
        groups.entry(name).or_default().push((a, b));
    }
    for c in contact_cases() {
        let group = groups.entry(format!("dev, {}", c.expected)).or_default();
        group.extend([(&c.a, &c.b), (&c.b, &c.a)]);
    }
    for (name, pairs) in &groups {
        let (mut classify, mut both) = (f64::MAX, f64::MAX);
        for _ in 0..7 {
            let detect = &mut |a: &_, b: &_| det.detect(a, b).contact_type().is_some() as usize;
            classify = classify.min(per_pair(pairs, detect));
            let with = &mut |a: &_, b: &_| {
                det.detect_with_geometry(a, b)
                    .1
                    .map_or(0, |g| g.points().len())
            };
            both = both.min(per_pair(pairs, with));
        }
        let extra = both - classify;
        println!(
            "{name} ({}): classify {classify:.0} ns, geometry +{extra:.0} ns",
            pairs.len()
        );
    }
}
