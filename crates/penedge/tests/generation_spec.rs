//! The TOML spec: every example in `examples/` generates, the paper's examples match the
//! Rust ones, and every bad input gets an error naming its field.

use penedge::generation::{generate, GenerationError, Problem, SpecError};
use penedge::io::spec::{parse_json, parse_toml, read_spec};
use penedge::system::{paper_spec, PaperExample};
use std::path::PathBuf;

fn examples() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn every_example_generates() {
    let mut seen = 0;
    for entry in std::fs::read_dir(examples()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") || path.ends_with("three_joint_sets.toml") {
            continue;
        }
        let spec = read_spec(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let out = generate(&spec).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(out.system.len() > 1, "{}", path.display());
        assert!(out.report.volume_error < 1e-12 || out.report.slivers.count > 0);
        seen += 1;
    }
    assert!(seen >= 12);
}

#[test]
fn examples_give_the_documented_counts() {
    let run = |name: &str| generate(&read_spec(&examples().join(name)).unwrap()).unwrap();
    let disc = run("finite_disc.toml");
    assert_eq!(
        (disc.system.len(), disc.report.partial_cuts_skipped),
        (5, 2)
    );
    let poly = run("finite_polygon.toml");
    assert_eq!(
        (poly.system.len(), poly.report.partial_cuts_skipped),
        (6, 1)
    );
    let number = run("joint_set_number.toml");
    assert_eq!(number.system.len(), 4);
    let slivers = run("slivers.toml");
    assert_eq!((slivers.system.len(), slivers.report.slivers.count), (4, 4));
    let octahedron = run("domain_halfspaces.toml");
    assert!((octahedron.report.block_volume - 288.0).abs() < 1e-9);
}

#[test]
fn the_paper_example_files_match_the_built_in_examples() {
    for (n, example) in [
        (1, PaperExample::One),
        (2, PaperExample::Two),
        (3, PaperExample::Three),
    ] {
        let path = examples().join(format!("paper_example_{n}.toml"));
        let from_file = generate(&read_spec(&path).unwrap()).unwrap().system;
        let built_in = generate(&paper_spec(example)).unwrap().system;
        assert_eq!(from_file.len(), built_in.len());
        for (a, b) in from_file.blocks().iter().zip(built_in.blocks()) {
            assert_eq!(a.vertices(), b.vertices());
        }
    }
}

const BOX: &str = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n";

/// The error of a spec with the box domain and these joint lines.
fn error_of(joints: &str) -> SpecError {
    let text = format!("{BOX}{joints}");
    let spec = match parse_toml(&text) {
        Ok(spec) => spec,
        Err(e) => return e,
    };
    match generate(&spec) {
        Err(GenerationError::Spec(e)) => e,
        other => panic!("expected a spec error for\n{joints}\ngot {other:?}"),
    }
}

fn assert_error(joints: &str, field: &str, problem: impl Fn(&Problem) -> bool) {
    let e = error_of(joints);
    assert_eq!(e.field, field, "{e}");
    assert!(problem(&e.problem), "{e}");
}

#[test]
fn a_dip_of_120_degrees_is_named() {
    let e = error_of("[[joints]]\ntype = \"set\"\ndip = 120\ndip_direction = 30\nspacing = 1\n");
    assert_eq!(
        e.to_string(),
        "joints[0].dip: dip must be between 0 and 90 degrees, got 120"
    );
    assert_error(
        "[[joints]]\ntype = \"plane\"\npoint = [1, 1, 1]\ndip = 30\ndip_direction = 400\n",
        "joints[0].dip_direction",
        |p| matches!(p, Problem::DipDirection { value } if *value == 400.0),
    );
}

#[test]
fn zero_and_negative_spacings_are_named() {
    let e = error_of("[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 30\nspacing = 0\n");
    assert_eq!(
        e.to_string(),
        "joints[0].spacing: must be greater than zero, got 0"
    );
    assert_error(
        "[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 30\nspacing = -2\n",
        "joints[0].spacing",
        |p| matches!(p, Problem::NotPositive { .. }),
    );
    assert_error(
        "[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 30\nspacing = 1\nspacing_deviation = 1\n",
        "joints[0].spacing_deviation",
        |p| matches!(p, Problem::DeviationTooLarge { .. }),
    );
    assert_error(
        "[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 30\nspacing = 1\nnumber = 0\n",
        "joints[0].number",
        |p| matches!(p, Problem::NotPositive { .. }),
    );
    assert_error(
        "[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 30\nspacing = 1e-6\n",
        "joints[0].spacing",
        |p| matches!(p, Problem::TooManyPlanes { .. }),
    );
}

#[test]
fn a_set_whose_origin_is_far_from_the_domain_says_so_not_that_the_spacing_is_small() {
    // Eleven planes cross the box, but the walk from the origin, gap after gap, is 1e12
    // steps: the error used to say "would make 1000000000010 planes; is the spacing too
    // small?".
    let far = "[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1\n";
    let e = error_of(&format!("{far}origin = [0, 0, -1e12]\n"));
    assert_eq!(e.field, "joints[0].origin", "{e}");
    let Problem::OriginFar { spacings, limit } = e.problem else {
        panic!("{e}");
    };
    assert!((1e12..1.1e12).contains(&spacings), "{spacings}");
    assert_eq!(limit, 10 * penedge::generation::MAX_PLANES);
    assert!(
        e.to_string().contains("put the origin near the domain"),
        "{e}"
    );
    assert!(!e.to_string().contains("spacing too small"), "{e}");
    // Nearer, the same set is fine.
    let spec = parse_toml(&format!("{BOX}{far}origin = [0, 0, -1e6]\n")).unwrap();
    let report = generate(&spec).expect("a set 1e6 spacings away").report;
    assert_eq!(report.joint_planes, 9); // z = 1 ... 9 cut the box; 0 and 10 are its faces
                                        // The walk is counted, not bounded by its worst case: gaps of 1 +- 0.9999 from 1e3 away
                                        // take about 1e3 steps, though the smallest gap would need 1e7.
    let spread = format!("{far}spacing_deviation = 0.9999\norigin = [0, 0, -1000]\n");
    let spec = parse_toml(&format!("{BOX}{spread}")).unwrap();
    generate(&spec).expect("a set with spread gaps 1e3 spacings away");
}

#[test]
fn a_plane_that_misses_the_domain_is_named() {
    let e = error_of("[[joints]]\ntype = \"plane\"\npoint = [0, 0, 12]\nnormal = [0, 0, 1]\n");
    assert_eq!(
        e.to_string(),
        "joints[0]: the plane misses the domain (it does not cross its interior)"
    );
    // On a face of the domain: it does not cross the interior either.
    assert_error(
        "[[joints]]\ntype = \"plane\"\npoint = [10, 0, 0]\nnormal = [1, 0, 0]\n",
        "joints[0]",
        |p| matches!(p, Problem::MissesDomain { what: "plane" }),
    );
    let set = "[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1\nnumber = 2\norigin = [0, 0, 20]\n";
    assert_error(set, "joints[0]", |p| {
        matches!(p, Problem::MissesDomain { what: "joint set" })
    });
    let disc =
        "[[joints]]\ntype = \"disc\"\ncenter = [20, 20, 5]\nnormal = [0, 0, 1]\nradius = 2\n";
    assert_error(disc, "joints[0]", |p| {
        matches!(p, Problem::MissesDomain { what: "disc" })
    });
}

#[test]
fn parallel_duplicate_planes_are_named() {
    let one = "[[joints]]\ntype = \"plane\"\npoint = [5, 0, 0]\nnormal = [1, 0, 0]\n";
    let two = "[[joints]]\ntype = \"plane\"\npoint = [5, 3, 7]\nnormal = [-2, 0, 0]\n";
    let e = error_of(&format!("{one}{two}"));
    assert_eq!(e.field, "joints[1]");
    assert!(
        e.to_string()
            .contains("the same plane as joints[0] plane 0"),
        "{e}"
    );
    // A member of a set on a single plane.
    let set = "[[joints]]\ntype = \"set\"\ndip = 90\ndip_direction = 90\nspacing = 2.5\n";
    let e = error_of(&format!("{set}{one}"));
    assert_eq!(e.field, "joints[1]");
    assert!(e.to_string().contains("joints[0] plane 1"), "{e}");
}

#[test]
fn nan_is_named() {
    assert_error(
        "[[joints]]\ntype = \"set\"\ndip = nan\ndip_direction = 30\nspacing = 1\n",
        "joints[0].dip",
        |p| matches!(p, Problem::NotFinite { .. }),
    );
    assert_error(
        "[[joints]]\ntype = \"plane\"\npoint = [1, nan, 1]\nnormal = [0, 0, 1]\n",
        "joints[0].point",
        |p| matches!(p, Problem::NotFinite { .. }),
    );
    assert_error(
        "[[joints]]\ntype = \"disc\"\ncenter = [1, 1, 1]\nnormal = [0, 0, 1]\nradius = inf\n",
        "joints[0].radius",
        |p| matches!(p, Problem::NotFinite { .. }),
    );
    let e =
        parse_toml("[domain]\ntype = \"box\"\nmin = [0, 0, nan]\nmax = [1, 1, 1]\n").unwrap_err();
    assert_eq!(e.field, "domain.min");
}

#[test]
fn shape_errors_are_named() {
    let e = error_of(
        "[[joints]]\ntype = \"plane\"\npoint = [1, 1, 1]\nnormal = [0, 0, 1]\nradius = 3\n",
    );
    assert_eq!(
        e.to_string(),
        "joints[0].radius: not a field of a `plane` entry"
    );
    assert_error(
        "[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 20\n",
        "joints[0].spacing",
        |p| matches!(p, Problem::Missing),
    );
    assert_error(
        "[[joints]]\ntype = \"plane\"\npoint = [1, 1, 1]\nnormal = [0, 0, 1]\ndip = 3\n",
        "joints[0]",
        |p| matches!(p, Problem::Orientation),
    );
    assert_error(
        "[[joints]]\ntype = \"plane\"\npoint = [1, 1, 1]\ndip = 3\n",
        "joints[0].dip_direction",
        |p| matches!(p, Problem::Missing),
    );
    assert_error("[[joints]]\ntype = \"fault\"\n", "joints[0].type", |p| {
        matches!(p, Problem::UnknownType { .. })
    });
    assert_error(
        "[[joints]]\ntype = \"plane\"\npoint = [1, 1, 1]\nnormal = [0, 0, 0]\n",
        "joints[0].normal",
        |p| matches!(p, Problem::ZeroNormal),
    );
    let e = error_of("[[joints]]\ntype = \"set\"\ndipp = 10\n");
    assert_eq!(e.field, "spec");
    assert!(
        e.to_string().contains("dipp") && e.to_string().contains("line 7"),
        "{e}"
    );
}

#[test]
fn bad_polygons_and_domains_are_named() {
    let bowtie = "[[joints]]\ntype = \"polygon\"\nvertices = [[0, 0, 5], [10, 10, 5], [10, 0, 5], [0, 10, 5]]\n";
    assert_error(bowtie, "joints[0].vertices", |p| {
        matches!(p, Problem::BadPolygon { .. })
    });
    let bent = "[[joints]]\ntype = \"polygon\"\nvertices = [[0, 0, 5], [10, 0, 5], [10, 10, 6], [0, 10, 5]]\n";
    assert_error(bent, "joints[0].vertices", |p| {
        matches!(p, Problem::BadPolygon { .. })
    });
    let flat = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 0]\n";
    assert_eq!(parse_toml(flat).unwrap_err().field, "domain.max");
    let open = "[domain]\ntype = \"polyhedron\"\nvertices = [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]\nfaces = [[0,2,1],[0,1,3],[1,2,3]]\n";
    let e = parse_toml(open).unwrap_err();
    assert!(
        e.field == "domain" && matches!(e.problem, Problem::Domain(_)),
        "{e}"
    );
    let options = format!("{BOX}[options]\nslivers = \"maybe\"\n");
    assert_eq!(parse_toml(&options).unwrap_err().field, "options.slivers");
    let options = format!("{BOX}[options]\nmin_thickness = -1\n");
    let e = generate(&parse_toml(&options).unwrap()).unwrap_err();
    assert!(e.to_string().contains("options.min_thickness"), "{e}");
}

#[test]
fn json_specs_read_like_toml() {
    let json = r#"{"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
        "joints": [{"type": "set", "dip": 90, "dip_direction": 90, "spacing": 2.5, "origin": [2.5, 0, 0]}]}"#;
    let out = generate(&parse_json(json).unwrap()).unwrap();
    assert_eq!(out.system.len(), 4);
}

mod no_panic {
    use penedge::generation::*;
    use proptest::prelude::*;

    fn number() -> impl Strategy<Value = f64> {
        prop_oneof![
            6 => -20.0..20.0f64,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(1e300),
            1 => Just(0.0),
            1 => Just(90.0),
        ]
    }

    fn triple() -> impl Strategy<Value = [f64; 3]> {
        [number(), number(), number()]
    }

    fn joint() -> impl Strategy<Value = Discontinuity> {
        prop_oneof![
            (triple(), triple()).prop_map(|(p, n)| Discontinuity::plane(p, Orientation::Normal(n))),
            (number(), number(), number(), number(), triple()).prop_map(|(dip, dd, s, dev, o)| {
                let mut set = JointSet::new(Orientation::dip(dip, dd), s.abs() + 0.3);
                set.origin = o;
                set.deviation = Deviation {
                    dip: dev.abs(),
                    dip_direction: dev.abs(),
                    spacing: 0.1,
                };
                Discontinuity::set(set)
            }),
            (triple(), number(), number(), number())
                .prop_map(|(c, dip, dd, r)| Discontinuity::disc(c, Orientation::dip(dip, dd), r)),
            prop::collection::vec(triple(), 0..5).prop_map(Discontinuity::polygon),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Any spec gives blocks or an error, never a panic.
        #[test]
        fn arbitrary_specs_never_panic(joints in prop::collection::vec(joint(), 0..4)) {
            let mut spec = Spec::new(Domain::cuboid([-10.0; 3], [10.0; 3]).unwrap());
            spec.joints = joints;
            if let Ok(out) = generate(&spec) {
                prop_assert!(out.report.volume_error <= 1e-9);
            }
        }
    }
}

/// A list of coordinates with more than 3 values is refused, naming where (the extra values
/// used to be dropped: `point = [5, 5, 5, 5]` generated as `[5, 5, 5]`), in TOML and JSON.
#[test]
fn coordinate_lists_of_the_wrong_length_are_refused() {
    let cases = [
        "[[joints]]\ntype = \"plane\"\npoint = [5, 5, 5, 5]\nnormal = [0, 0, 1]\n",
        "[[joints]]\ntype = \"plane\"\npoint = [5, 5, 5]\nnormal = [0, 0, 1, 0]\n",
        "[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 20\nspacing = 2\norigin = [0, 0, 0, 9]\n",
        "[[joints]]\ntype = \"disc\"\ncenter = [5, 5, 5, 1]\nnormal = [0, 0, 1]\nradius = 2\n",
        "[[joints]]\ntype = \"polygon\"\nvertices = [[0, 0, 5], [10, 0, 5], [10, 10, 5, 1]]\n",
        "[[excavations]]\ntype = \"tunnel\"\nprofile = \"circle\"\nradius = 1\nstart = [0, 5, 5, 5]\ntrend = 90\nlength = 10\n",
        "[[excavations]]\ntype = \"slope\"\norigin = [0, 0, 5]\ntrend = 0\nvertices = [[0, 0], [5, -5, 1]]\n",
    ];
    for joints in cases {
        let e = parse_toml(&format!("{BOX}{joints}")).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("got a list of 4 values, expected a list of 3 values")
                || text.contains("got a list of 3 values, expected a list of 2 values"),
            "{joints}: {text}"
        );
        assert!(text.contains("line "), "{text}");
    }
    for domain in [
        "[domain]\ntype = \"box\"\nmin = [0, 0, 0, 0]\nmax = [10, 10, 10]\n",
        "[domain]\ntype = \"halfspaces\"\nnormals = [[1, 0, 0, 0]]\noffsets = [1]\n",
        "[domain]\ntype = \"polyhedron\"\nvertices = [[0, 0, 0, 1]]\nfaces = [[0]]\n",
    ] {
        let text = parse_toml(domain).unwrap_err().to_string();
        assert!(text.contains("got a list of 4 values"), "{domain}: {text}");
    }
    let json = r#"{"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10, 10]}}"#;
    let text = parse_json(json).unwrap_err().to_string();
    assert!(
        text.contains("got a list of 4 values, expected a list of 3 values"),
        "{text}"
    );
    // Two values were and are refused the same way.
    let e = parse_toml(&format!(
        "{BOX}[[joints]]\ntype = \"plane\"\npoint = [5, 5]\nnormal = [0, 0, 1]\n"
    ))
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("got a list of 2 values, expected a list of 3 values"),
        "{e}"
    );
}

/// A table of fields must be a table: serde also reads a struct from a list of its
/// fields' values in order, which read `options = [1e9, 0.5, "drop"]` as `min_volume = 1e9`
/// and so on, past the check of unknown fields.
#[test]
fn tables_given_as_lists_are_refused() {
    let cases = [
        format!("options = [1e9, 0.5, \"drop\", 1e-12, 1e-9]\n{BOX}"),
        format!("options = [[]]\n{BOX}"),
        format!("joints = [[\"plane\", \"p\", [5, 5, 5], [0, 0, 1]]]\n{BOX}"),
        "domain = [\"box\", [0, 0, 0], [10, 10, 10]]\n".to_string(),
    ];
    for text in &cases {
        let e = parse_toml(text).unwrap_err();
        assert_eq!(e.field, "spec", "{text}: {e}");
        let message = e.to_string();
        assert!(
            message.contains("got a list, expected a table of fields"),
            "{text}: {message}"
        );
        assert!(!message.contains("elements"), "{message}");
    }
    let json = r#"{"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
        "options": [1e9, 0.5, "drop"]}"#;
    let message = parse_json(json).unwrap_err().to_string();
    assert!(
        message.contains("got a list, expected a table of fields"),
        "{message}"
    );
    let whole = r#"[{"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]}]"#;
    let message = parse_json(whole).unwrap_err().to_string();
    assert!(
        message.contains("got a list, expected a table of fields"),
        "{message}"
    );
    // Tables still read, and their unknown fields are still named.
    let ok = format!("{BOX}[options]\nmin_volume = 1e-3\nslivers = \"drop\"\n");
    assert!(parse_toml(&ok).is_ok());
    let typo = parse_toml(&format!("{BOX}[options]\nmin_volum = 1\n")).unwrap_err();
    assert!(
        typo.to_string().contains("unknown field `min_volum`"),
        "{typo}"
    );
}

/// An opening's size far from the rock's, or from its other sizes, is named with the range
/// allowed (a radius of 1e20 or 1e-12, a length of 1e20, a depth of 1e-12 read "the
/// half-spaces do not bound a solid block" or "half-space 2 has a zero ... normal").
#[test]
fn excavation_sizes_out_of_range_are_named() {
    let tunnel = |radius: &str, length: &str| {
        format!(
            "[[excavations]]\ntype = \"tunnel\"\nprofile = \"circle\"\nradius = {radius}\n\
             start = [5, -1, 5]\ntrend = 0\nlength = {length}\n"
        )
    };
    let shaft = |depth: &str| {
        format!(
            "[[excavations]]\ntype = \"shaft\"\nprofile = \"circle\"\nradius = 1\n\
             top = [5, 5, 10]\ndepth = {depth}\n"
        )
    };
    for (entry, field) in [
        (tunnel("1e20", "12"), "radius"),
        (tunnel("1e-12", "12"), "radius"),
        (tunnel("2", "1e20"), "length"),
        (shaft("1e-12"), "depth"),
    ] {
        let e = error_of(&entry);
        assert_eq!(e.field, format!("excavations[0].{field}"), "{e}");
        let text = e.to_string();
        assert!(
            text.contains(
                "must be between 1.732e-5 and 1.732e7 (1e-6 to 1e6 times the size of the rock"
            ),
            "{text}"
        );
        assert!(!text.contains("half-space"), "{text}");
    }
    // Without the rock (an excavation's own regions), the sizes are checked against each
    // other.
    let e = penedge::io::spec::parse_excavation_toml(
        "type = \"tunnel\"\nprofile = \"circle\"\nradius = 1e-12\nstart = [0, 0, 0]\ntrend = 0\nlength = 12\n",
    )
    .unwrap()
    .regions()
    .unwrap_err();
    assert_eq!(e.field, "excavation.radius", "{e}");
    assert!(
        e.to_string()
            .contains("must be at least 1e-6 times the opening's length (12), got 1e-12"),
        "{e}"
    );
    // Sizes within range still cut.
    let ok = format!("{BOX}{}", tunnel("2", "12"));
    assert!(generate(&parse_toml(&ok).unwrap()).is_ok());
}

/// A whole number too large for its field says so (it read "got the whole number `...`,
/// expected a whole number").
#[test]
fn whole_numbers_too_large_are_named_as_such() {
    let toml = format!(
        "{BOX}[[joints]]\ntype = \"set\"\ndip = 10\ndip_direction = 20\nspacing = 1\n\
         number = 9223372036854775808\n"
    );
    let json = r#"{"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
        "joints": [{"type": "set", "dip": 10, "dip_direction": 20, "spacing": 1,
        "number": 9223372036854775808}]}"#;
    for e in [
        parse_toml(&toml).unwrap_err(),
        parse_json(json).unwrap_err(),
    ] {
        assert!(
            e.to_string().contains(
                "got the whole number `9223372036854775808`, which is too large: expected a \
                 whole number up to 9223372036854775807"
            ),
            "{e}"
        );
    }
}

#[test]
fn every_number_of_planes_above_the_limit_is_too_many_without_a_spacing_hint() {
    // Past 2^32 - 1 the count read "must be greater than zero" (a 32-bit conversion).
    for n in [
        1_000_001u64,
        4_294_967_295,
        4_294_967_296,
        1 << 53,
        i64::MAX as u64,
    ] {
        let e = error_of(&format!(
            "[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1\nnumber = {n}\n"
        ));
        assert_eq!(e.field, "joints[0].number", "{e}");
        assert!(
            matches!(e.problem, Problem::TooManyPlanes { count, by_number: true, .. } if count == n),
            "{e}"
        );
        assert_eq!(
            e.to_string(),
            format!("joints[0].number: would make {n} planes, more than the limit of 1000000")
        );
    }
    for n in [0, -1, i64::MIN] {
        assert_error(
            &format!("[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1\nnumber = {n}\n"),
            "joints[0].number",
            |p| matches!(p, Problem::NotPositive { .. }),
        );
    }
    // Two sets of 600,000 planes each: too many together, and no spacing to blame.
    let two = "[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1e-5\n\
               number = 600000\n[[joints]]\ntype = \"set\"\ndip = 90\ndip_direction = 0\n\
               spacing = 1e-5\nnumber = 600000\n";
    let e = error_of(two);
    assert_eq!(e.field, "joints[1]", "{e}");
    assert!(!e.to_string().contains("spacing"), "{e}");
    // A set that fills the domain is told about its spacing.
    let e = error_of("[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1e-6\n");
    assert!(
        e.to_string().ends_with("; is the spacing too small?"),
        "{e}"
    );
}

#[test]
fn a_vertical_set_grows_towards_its_dip_direction_and_its_record_says_so() {
    // dip 90: the normal is the formula's, in the sense of the dip direction given, and the
    // joint table's dip direction is the one the stored normal points to (dip direction
    // 270 was stored as normal (-1, 0, 0) with a derived dip direction of 90).
    let set = |orientation: &str| {
        let text = format!(
            "{BOX}[[joints]]\ntype = \"set\"\n{orientation}\nspacing = 3\norigin = [1, 1, 0]\n\
             number = 3\n"
        );
        let system = generate(&parse_toml(&text).unwrap()).unwrap().system;
        let json: serde_json::Value =
            serde_json::from_str(&penedge::io::json::to_json_string(&system)).unwrap();
        json["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| {
                let f = |k: &str| j[k].as_f64().unwrap();
                let normal: Vec<f64> = (0..3).map(|c| j["normal"][c].as_f64().unwrap()).collect();
                (
                    j["point"][0].as_f64().unwrap(),
                    normal,
                    f("dip"),
                    f("dip_direction"),
                )
            })
            .collect::<Vec<_>>()
    };
    // Towards West: x = 1 (the other two planes, x = -2 and -5, outside the box).
    let west = set("dip = 90\ndip_direction = 270");
    assert_eq!(west, [(1.0, vec![-1.0, 0.0, 0.0], 90.0, 270.0)]);
    // Towards East, given by dip direction 90 or by a normal (stored upward: +x).
    let east = [
        (1.0, vec![1.0, 0.0, 0.0], 90.0, 90.0),
        (4.0, vec![1.0, 0.0, 0.0], 90.0, 90.0),
        (7.0, vec![1.0, 0.0, 0.0], 90.0, 90.0),
    ];
    assert_eq!(set("dip = 90\ndip_direction = 90"), east);
    assert_eq!(set("normal = [-1, 0, 0]"), east);
    // Every record's attitude gives its normal back, whatever the dip direction.
    for dd in [0, 45, 135, 180, 225, 300, 360] {
        for (_, n, dip, dir) in set(&format!("dip = 90\ndip_direction = {dd}")) {
            let a = penedge::generation::Attitude::new(dip, dir).normal();
            let back = [a.x, a.y, a.z];
            assert!(
                n.iter().zip(back).all(|(p, q)| (p - q).abs() < 1e-12),
                "{dd}: {n:?} {back:?}"
            );
        }
    }
}

#[test]
fn a_seed_is_any_whole_number_from_minus_two_to_the_63_to_two_to_the_64_less_one() {
    // Negative seeds were taken (as 2^64 + s) while 2^64 - 1 itself was refused.
    let planes = |seed: &str| {
        let text = format!(
            r#"{{"domain": {{"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]}},
               "joints": [{{"type": "set", "dip": 30, "dip_direction": 40, "spacing": 2,
                            "dip_deviation": 10, "spacing_deviation": 1, "seed": {seed}}}]}}"#
        );
        let system = generate(&parse_json(&text).unwrap()).unwrap().system;
        system
            .joints()
            .iter()
            .map(|j| (j.plane.normal.to_array(), j.plane.point.to_array()))
            .collect::<Vec<_>>()
    };
    let top = planes("18446744073709551615");
    assert_eq!(top, planes("-1"));
    assert_ne!(top, planes("0"));
    assert_eq!(
        planes("-9223372036854775808"),
        planes("9223372036854775808")
    );
    assert_eq!(planes("null"), planes("0")); // not given, as before
    let toml = |seed: &str| {
        parse_toml(&format!(
            "{BOX}[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 1\n\
             seed = {seed}\n"
        ))
    };
    assert!(toml("-9223372036854775808").is_ok());
    let e = toml("1.5").unwrap_err().to_string();
    assert!(e.contains("expected a whole number"), "{e}");
    // TOML holds 2^64 - 1 too, and one beyond it is the seed's error, naming the field (the
    // parser's 128-bit number was "got the whole number ... as i128, expected a whole number").
    let spec = |seed: &str| toml(seed).map(|s| generate(&s).map(|g| g.system.len()));
    assert_eq!(spec("18446744073709551615").unwrap().unwrap(), 10);
    for beyond in [
        "18446744073709551616",
        "-9223372036854775809",
        "1".repeat(39).as_str(),
    ] {
        let e = spec(beyond).unwrap_err().to_string();
        assert!(
            e.starts_with("joints[0].seed: must be a whole number from -2^63"),
            "{beyond}: {e}"
        );
    }
}
