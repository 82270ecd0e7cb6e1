//! The `geometry` subcommand: the cost of contact geometry (normal, points or polygon, area,
//! signed distance) on top of classification, beside parry3d-f64's contact manifold.
//!
//! Per pair, on the same generated sets as the narrow benchmark: penedge
//! `Detector::detect` and `Detector::detect_with_geometry` (the difference is the cost of
//! the geometry), parry's `contact` (one point pair and a normal) and parry's
//! `contact_manifolds` (the points of the contact manifold and a normal). The pairs can be
//! written to a JSON file (`--export`) for `benches/python/coal_patch.py`, which times coal's
//! contact patch on them.

use crate::family::Family;
use crate::pairs::{PairSet, ParryPair, Scenario};
use crate::placement::{Expected, Push, Touch, PENETRATION, WIDE_GAP};
use crate::timing::{median_rounds, timed, Job};
use crate::{report, set_rng, Mode, Options};
use parry3d_f64::math::Vector;
use parry3d_f64::query::{
    contact, ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher,
};
use penedge::{ConvexBlock, Detector, PairResult, Tolerance};
use std::hint::black_box;

/// The three situations of the main table: every pair is a contact.
pub const SITUATIONS: [Scenario; 3] = [
    Scenario {
        name: "face-face touching",
        push: Push::Touching,
        touches: &[Touch::FaceFace],
    },
    Scenario {
        name: "edge/vertex touching",
        push: Push::Touching,
        touches: &Touch::EDGE_OR_VERTEX,
    },
    Scenario {
        name: "penetrating 1e-3, gap 1e-3",
        push: Push::IntoWithinGap,
        touches: &Touch::ALL,
    },
];

/// First row number of the sets (seeds), apart from the narrow benchmark's.
pub const FIRST_ROW: usize = 200;
/// First row number of the by-type sets.
const DETAIL_ROW: usize = 300;

/// A parry manifold distance within this of 0 counts as touching (as in the narrow bench).
const PARRY_TOUCH: f64 = 1e-9;
/// Two unit normals closer than this agree.
const NORMAL_AGREE: f64 = 1e-6;

/// What each engine answers on a set, checked once before timing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Check {
    /// penedge: a contact of the expected type.
    pub penedge_type: usize,
    /// penedge: geometry given, with a distance as expected (`|d| <= 1e-9` touching,
    /// `-PENETRATION - 1e-9 <= d < -1e-9` pushed in).
    pub penedge_distance: usize,
    /// penedge: contact points in all (one, two or the polygon's vertices).
    pub penedge_points: usize,
    /// parry: a non-empty manifold whose smallest distance is as expected (same bounds).
    pub parry_manifold: usize,
    /// parry: contact points in all.
    pub parry_points: usize,
    /// Pairs where both give a normal and the two agree within 1e-6.
    pub same_normal: usize,
}

/// Whether a signed distance is what the push made.
fn distance_ok(push: Push, d: f64) -> bool {
    match push {
        Push::IntoWithinGap => (-PENETRATION - PARRY_TOUCH..-PARRY_TOUCH).contains(&d),
        _ => d.abs() <= PARRY_TOUCH,
    }
}

impl Check {
    /// Runs penedge (with geometry) and parry's manifold once on every pair of `set`.
    pub fn of(set: &PairSet) -> Check {
        let mut detector = Detector::new(set.tolerance);
        let mut manifolds = Vec::new();
        let mut check = Check::default();
        let push = set.scenario.push;
        for ((expected, (a, b)), p) in set.expected.iter().zip(&set.blocks).zip(&set.parry) {
            let (result, geometry) = detector.detect_with_geometry(a, b);
            check.penedge_type += expected.matches(&result) as usize;
            let mut penedge_normal = None;
            if let Some(g) = geometry {
                check.penedge_distance += distance_ok(push, g.distance()) as usize;
                check.penedge_points += g.points().len();
                penedge_normal = Some(g.normal());
            }
            parry_manifold(p, &mut manifolds);
            let m = &manifolds[0];
            let least = m
                .points
                .iter()
                .map(|c| c.dist)
                .fold(f64::INFINITY, f64::min);
            check.parry_manifold += (!m.points.is_empty() && distance_ok(push, least)) as usize;
            check.parry_points += m.points.len();
            if let (Some(n), false) = (penedge_normal, m.points.is_empty()) {
                let parry_n = p.pose_a.rotation * m.local_n1;
                let d = (n.x - parry_n.x, n.y - parry_n.y, n.z - parry_n.z);
                let agree = (d.0 * d.0 + d.1 * d.1 + d.2 * d.2).sqrt() <= NORMAL_AGREE;
                check.same_normal += agree as usize;
            }
        }
        check
    }
}

/// parry's contact manifolds of one pair, computed afresh: the manifold is emptied and its
/// cached normals reset first, so no coherence from the previous (unrelated) pair is used.
fn parry_manifold(p: &ParryPair, manifolds: &mut Vec<ContactManifold<(), ()>>) {
    for m in manifolds.iter_mut() {
        m.clear();
        m.local_n1 = Vector::ZERO;
        m.local_n2 = Vector::ZERO;
    }
    let pos12 = p.pose_a.inv_mul(&p.pose_b);
    DefaultQueryDispatcher
        .contact_manifolds(&pos12, &p.a, &p.b, p.prediction, manifolds, &mut None)
        .expect("parry supports polyhedron pairs");
}

/// One detector per tolerance in use, so that the scratch buffers of each stay grown.
#[derive(Default)]
struct Detectors(Vec<Detector>);

impl Detectors {
    fn get(&mut self, tolerance: Tolerance) -> &mut Detector {
        match self.0.iter().position(|d| *d.tolerance() == tolerance) {
            Some(i) => &mut self.0[i],
            None => {
                self.0.push(Detector::new(tolerance));
                self.0.last_mut().expect("just pushed")
            }
        }
    }
}

/// One round of the four queries over the job's window: ns per pair of penedge `detect`,
/// penedge `detect_with_geometry`, parry `contact`, parry `contact_manifolds`.
fn round(
    job: &Job,
    detectors: &mut Detectors,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> [f64; 4] {
    let w = job.window;
    let (blocks, parry) = (&job.set.blocks[..w.len], &job.set.parry[..w.len]);
    let detector = detectors.get(job.set.tolerance);
    [
        timed(w, || detect_round(detector, blocks)),
        timed(w, || geometry_round(detector, blocks)),
        timed(w, || parry_contact_round(parry)),
        timed(w, || parry_manifold_round(parry, manifolds)),
    ]
}

fn detect_round(detector: &mut Detector, blocks: &[(ConvexBlock, ConvexBlock)]) {
    for (a, b) in blocks {
        black_box(detector.detect(black_box(a), black_box(b)));
    }
}

fn geometry_round(detector: &mut Detector, blocks: &[(ConvexBlock, ConvexBlock)]) {
    for (a, b) in blocks {
        black_box(detector.detect_with_geometry(black_box(a), black_box(b)));
    }
}

fn parry_contact_round(pairs: &[ParryPair]) {
    for p in pairs {
        let p = black_box(p);
        black_box(contact(&p.pose_a, &p.a, &p.pose_b, &p.b, p.prediction).ok());
    }
}

fn parry_manifold_round(pairs: &[ParryPair], manifolds: &mut Vec<ContactManifold<(), ()>>) {
    for p in pairs {
        parry_manifold(black_box(p), manifolds);
        black_box(&manifolds[0].points);
    }
}

fn verification_header() -> &'static str {
    concat!(
        "| situation | family | pairs | penedge type as expected | penedge distance as expected ",
        "| parry manifold as expected | same normal (1e-6) | penedge points/pair ",
        "| parry points/pair |\n",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|"
    )
}

fn verification_row(set: &PairSet, c: &Check) -> String {
    let n = set.len() as f64;
    format!(
        "| {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} |",
        set.scenario.name,
        set.family.name(),
        set.len(),
        c.penedge_type,
        c.penedge_distance,
        c.parry_manifold,
        c.same_normal,
        c.penedge_points as f64 / n,
        c.parry_points as f64 / n
    )
}

fn timing_header() -> &'static str {
    concat!(
        "| situation | family | penedge `detect` | penedge `detect_with_geometry` ",
        "| geometry (difference) | geometry / `detect` | parry `contact` ",
        "| parry `contact_manifolds` | ratio parry manifold / penedge with geometry |\n",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|"
    )
}

fn timing_row(set: &PairSet, [detect, with_geometry, contact, manifold]: [f64; 4]) -> String {
    format!(
        "| {} | {} | {:.0} | {:.0} | {:.0} | {:.0} % | {:.0} | {:.0} | {:.1} |",
        set.scenario.name,
        set.family.name(),
        detect,
        with_geometry,
        with_geometry - detect,
        100.0 * (with_geometry - detect) / detect,
        contact,
        manifold,
        manifold / with_geometry
    )
}

/// Generates, checks and times the sets of `scenarios` in each mode, prints the tables,
/// and returns the sets.
fn run_table(
    title: &str,
    scenarios: &[Scenario],
    first_row: usize,
    modes: &[Mode],
    o: &Options,
) -> Vec<PairSet> {
    let keep = o.export.is_some();
    let sets: Vec<PairSet> = scenarios
        .iter()
        .enumerate()
        .flat_map(|(i, scenario)| {
            Family::ALL.map(|family| {
                let mut rng = set_rng(o.seed, first_row + i, family);
                PairSet::generate_keeping(*scenario, family, o.pairs, &mut rng, keep)
            })
        })
        .collect();
    println!("### {title}: answers\n");
    println!("{}", verification_header());
    for set in &sets {
        println!("{}", verification_row(set, &Check::of(set)));
    }
    let jobs: Vec<Job> = modes
        .iter()
        .flat_map(|mode| {
            sets.iter().map(|set| Job {
                set,
                window: mode.window(set, o),
            })
        })
        .collect();
    let mut detectors = Detectors::default();
    let mut manifolds = Vec::new();
    let medians = median_rounds(&jobs, o.reps, |job| {
        round(job, &mut detectors, &mut manifolds)
    });
    for (mode, medians) in modes.iter().zip(medians.chunks(sets.len())) {
        println!(
            "\n### {title}: ns per pair, median of {} rounds ({})\n",
            o.reps,
            mode.caption(o)
        );
        println!("{}", timing_header());
        for (set, m) in sets.iter().zip(medians) {
            println!("{}", timing_row(set, *m));
        }
    }
    println!();
    sets
}

/// Touching sets, one per contact type.
fn by_contact_type() -> Vec<Scenario> {
    static TOUCHES: [Touch; 7] = Touch::ALL;
    TOUCHES
        .iter()
        .map(|t| Scenario {
            name: t.contact_type().name(),
            push: Push::Touching,
            touches: std::slice::from_ref(t),
        })
        .collect()
}

/// The `geometry` subcommand.
pub fn run(o: &Options) -> Result<(), String> {
    println!("## Contact geometry: penedge with and without geometry, parry3d-f64 manifold\n");
    println!(
        "{} pairs per row, seed {}, single thread; {}.",
        o.pairs,
        o.seed,
        report::machine()
    );
    println!(
        "Touching: penedge default tolerance; pushed in by {PENETRATION}: relative gap \
         {WIDE_GAP}. parry prediction = penedge's absolute gap."
    );
    println!(
        "Times are CPU time of the benchmark thread. Load average at the start: {}.\n",
        report::load()
    );
    let sets = run_table(
        "Main situations",
        &SITUATIONS,
        FIRST_ROW,
        &[Mode::Cold, Mode::Hot],
        o,
    );
    if let Some(path) = &o.export {
        crate::export::write_pairs(path, &sets, o).map_err(|e| format!("{path}: {e}"))?;
        eprintln!("pairs written to {path}");
    }
    drop(sets);
    if o.detail {
        let title = "Touching, by contact type";
        run_table(title, &by_contact_type(), DETAIL_ROW, &[Mode::Hot], o);
    }
    println!("Load average at the end: {}.", report::load());
    Ok(())
}

/// Expected contact of a pair, as a name for files.
pub fn expected_name(e: Expected) -> &'static str {
    match e {
        Expected::Separated => "separated",
        Expected::Penetrating => "penetrating",
        Expected::Contact(kind) => kind.name(),
    }
}

/// penedge's answer, as a name for files.
pub fn result_name(r: &PairResult) -> &'static str {
    match r {
        PairResult::Separated => "separated",
        PairResult::Penetrating => "penetrating",
        PairResult::Contact(c) => c.kind.name(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// Every pair of the geometry sets is a contact with a geometry whose signed distance is
    /// what the push made (0 touching, about -1e-3 pushed in within the wide gap).
    #[test]
    fn geometry_sets_are_contacts_with_the_expected_distance() {
        for scenario in SITUATIONS {
            for family in Family::ALL {
                let set = PairSet::generate(scenario, family, 20, &mut SplitMix64::new(3));
                let check = Check::of(&set);
                assert_eq!(
                    check.penedge_distance,
                    set.len(),
                    "{} {family:?}",
                    scenario.name
                );
                if scenario.push == Push::Touching {
                    assert_eq!(
                        check.penedge_type,
                        set.len(),
                        "{} {family:?}",
                        scenario.name
                    );
                }
            }
        }
    }
}
