//! The `outcomes` subcommand: every answer of the narrow phase on a large, fixed corpus of
//! pairs, written as text, so that two builds can be compared line by line (`diff`) after
//! a change meant to make the narrow phase faster without changing what it answers.
//!
//! `cargo run --release -p penedge-bench -- outcomes [--pairs N] > outcomes.txt`
//!
//! The corpus: every set of the narrow and geometry benchmarks (cubes and rock-like
//! hexahedra; separated, touching by each type, penetrating, pushed within a wide gap), random
//! polytopes of 4 to 40 faces placed near each other (default gap and a relative gap of
//! 1e-3), and whole systems (the paper's examples, the jointed rock mass of
//! `examples/three_joint_sets.toml`). For each pair: the outcome with both features, the
//! penetration edges (side, edge, Table 1 type, ends, parameters to 9 digits) and, for
//! contacts, the contact geometry (normal, distance, area to 9 digits). For systems: every
//! contact with its features, and the penetrating pairs.

use crate::family::Family;
use crate::pairs::{PairSet, Scenario};
use crate::rng::SplitMix64;
use crate::{by_contact_type, set_rng, SITUATIONS};
use penedge::penetration::{EdgeEnd, PenetrationEdge, Side};
use penedge::system::BlockSystem;
use penedge::{ConvexBlock, Detector, PairResult, Tolerance};
use std::fmt::Write;
use std::io::Write as _;

/// `outcomes`: writes the corpus's answers to standard output.
pub fn run(args: &[String]) -> Result<(), String> {
    let mut pairs = 1000;
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        match flag.as_str() {
            "--pairs" => pairs = crate::number(it.next().ok_or("--pairs needs a value")?)?,
            other => return Err(format!("unknown option {other}")),
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut emit = |line: &str| writeln!(out, "{line}").map_err(|e| e.to_string());
    let scenarios: Vec<(usize, Scenario)> = SITUATIONS
        .into_iter()
        .enumerate()
        .chain(
            by_contact_type()
                .into_iter()
                .enumerate()
                .map(|(k, s)| (100 + k, s)),
        )
        .chain(
            crate::geometry::SITUATIONS
                .into_iter()
                .enumerate()
                .map(|(k, s)| (crate::geometry::FIRST_ROW + k, s)),
        )
        .collect();
    for (row, scenario) in scenarios {
        for family in Family::ALL {
            let set = PairSet::generate(scenario, family, pairs, &mut set_rng(2004, row, family));
            let mut det = Detector::new(set.tolerance);
            for (i, (a, b)) in set.blocks.iter().enumerate() {
                let name = format!("{} {} {i}", scenario.name, family.name());
                emit(&pair_line(&mut det, &name, a, b))?;
            }
        }
    }
    let mut rng = SplitMix64::new(77);
    for gap in [
        Tolerance::default(),
        Tolerance::with_gap(1e-3).expect("a valid gap"),
    ] {
        let mut det = Detector::new(gap);
        for i in 0..4 * pairs {
            let faces = [4, 5, 6, 8, 12, 16, 17, 24, 40][i % 9];
            let (a, b) = polytopes(&mut rng, faces);
            let name = format!("polytope gap {} faces {faces} {i}", gap.gap());
            emit(&pair_line(&mut det, &name, &a, &b))?;
            emit(&pair_line(&mut det, &format!("{name} swapped"), &b, &a))?;
        }
    }
    for (name, system) in systems()? {
        for tol in [
            Tolerance::default(),
            Tolerance::with_gap(1e-4).expect("a valid gap"),
        ] {
            let found = system.detect(&tol);
            for c in &found.contacts {
                let k = &c.contact;
                emit(&format!(
                    "{name} gap {} {:?} {:?} {:?} {:?}",
                    tol.gap(),
                    c.pair,
                    k.kind,
                    k.feature_a,
                    k.feature_b
                ))?;
            }
            for p in &found.penetrating {
                emit(&format!("{name} gap {} {p:?} penetrating", tol.gap()))?;
            }
        }
    }
    Ok(())
}

/// One pair's answer, penetration edges and geometry on one line.
fn pair_line(det: &mut Detector, name: &str, a: &ConvexBlock, b: &ConvexBlock) -> String {
    let (result, geometry) = det.detect_with_geometry(a, b);
    let mut line = format!("{name}: {}", outcome(&result));
    for pe in det.penetration_edges() {
        line.push_str(" | ");
        edge(&mut line, pe);
    }
    if let Some(g) = geometry {
        let n = g.normal();
        let _ = write!(
            line,
            " | normal {:.9} {:.9} {:.9} distance {:.9e} area {:.9e}",
            n.x,
            n.y,
            n.z,
            g.distance(),
            g.area()
        );
    }
    line
}

fn outcome(result: &PairResult) -> String {
    match result {
        PairResult::Contact(c) => format!("{:?} {:?} {:?}", c.kind, c.feature_a, c.feature_b),
        other => other.name().to_string(),
    }
}

fn edge(line: &mut String, pe: &PenetrationEdge) {
    let side = if pe.side == Side::A { "A" } else { "B" };
    let end = |e: EdgeEnd| match e {
        EdgeEnd::Vertex(v) => format!("v{v}"),
        EdgeEnd::Cut(f) => format!("f{f}"),
    };
    let _ = write!(
        line,
        "{side}{} T{} {} {} {:.9} {:.9}",
        pe.edge,
        pe.kind as u8,
        end(pe.ends[0]),
        end(pe.ends[1]),
        pe.t[0],
        pe.t[1]
    );
}

/// Two random polytopes with `faces` planes tangent to the unit sphere. One time in three
/// the second is about a random centre at 1.6 to 2.2 from the first's (mostly overlapping,
/// some apart); otherwise it has a face plane on a face plane of the first, facing it, with
/// its centre moved sideways by up to 1.5 (face, edge and vertex contacts and separations),
/// and then pushed along the plane's normal by one of 0, +-1e-13, +-1e-4.
fn polytopes(rng: &mut SplitMix64, faces: usize) -> (ConvexBlock, ConvexBlock) {
    use glam::DVec3;
    let (a, normals) = polytope(rng, faces, DVec3::ZERO, None);
    if rng.index(3) == 0 {
        let centre = rng.direction() * rng.range(1.6, 2.2);
        return (a, polytope(rng, faces, centre, None).0);
    }
    let n = DVec3::from_array(normals[rng.index(normals.len())]);
    let d = rng.direction();
    let side = (d - n * d.dot(n)) * rng.range(0.0, 1.5);
    let push = [0.0, 1e-13, -1e-13, 1e-4, -1e-4][rng.index(5)];
    let centre = n * (2.0 - push) + side;
    (a, polytope(rng, faces, centre, Some(-n)).0)
}

/// A polytope of `n` planes tangent to the unit sphere about `centre`, the first with the
/// normal `first` when given; with its normals.
fn polytope(
    rng: &mut SplitMix64,
    n: usize,
    centre: glam::DVec3,
    first: Option<glam::DVec3>,
) -> (ConvexBlock, Vec<[f64; 3]>) {
    loop {
        let mut normals: Vec<[f64; 3]> = (0..n).map(|_| rng.direction().to_array()).collect();
        if let Some(f) = first {
            normals[0] = f.to_array();
        }
        let offsets: Vec<f64> = normals
            .iter()
            .map(|m| 1.0 + glam::DVec3::from_array(*m).dot(centre))
            .collect();
        if let Ok(block) = ConvexBlock::from_planes(&normals, &offsets) {
            return (block, normals);
        }
    }
}

/// The paper's examples and the jointed rock mass of the examples folder.
fn systems() -> Result<Vec<(String, BlockSystem)>, String> {
    use penedge::system::{paper_example, PaperExample};
    let mut systems = Vec::new();
    for (k, example) in [PaperExample::One, PaperExample::Two, PaperExample::Three]
        .into_iter()
        .enumerate()
    {
        let system = paper_example(example).map_err(|e| e.to_string())?;
        systems.push((format!("example {}", k + 1), system));
    }
    systems.push(("jointed".to_string(), crate::system::jointed_system()?));
    Ok(systems)
}
