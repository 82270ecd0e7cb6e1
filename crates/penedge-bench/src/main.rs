//! Benchmarks of penedge against its peers.
//!
//! `cargo run --release -p penedge-bench -- narrow [--pairs N] [--reps R] [--hot H]
//! [--seed S] [--no-detail]` times the narrow phase (one pair query) of penedge and
//! parry3d-f64 on the same generated hexahedron pairs and prints Markdown tables (see
//! docs/benchmarks.md).
//!
//! `cargo run --release -p penedge-bench -- geometry [--pairs N] [--reps R] [--hot H]
//! [--seed S] [--no-detail] [--export PAIRS.json]` times the contact geometry on top of
//! classification (penedge `detect` vs `detect_with_geometry`) beside parry3d-f64's
//! contact manifold, and can write the pairs for `benches/python/coal_patch.py`.
//!
//! `cargo run --release -p penedge-bench -- generate [--spec SPEC.toml] [--runs N]
//! [--big-runs N] [--no-big]` times block generation (about 1e5 and 1e6 blocks, each size in
//! a child process for its peak memory).
//!
//! `cargo run --release -p penedge-bench -- system [--grid N] [--runs R] [--threads T]
//! [--no-parry] [--no-jointed] [--broad N]` times whole systems: all contacts of an `N^3`
//! grid of unit cubes beside parry3d-f64 (BVH + `contact`), a jointed rock mass of about
//! 10^5 blocks, and the broad-phase methods (see `system.rs`).
//!
//! `cargo run --release -p penedge-bench -- tracker [--grid N] [--gap G] [--steps S]
//! [--runs R] [--threads T]` times `ContactTracker` steps (every block jittered, 1 % of them,
//! none) beside full detections (see `tracker.rs`).
//!
//! `cargo run --release -p penedge-bench -- concave [--runs R] [--threads T] [--share S]`
//! times the detection of a jointed mass with concave blocks (pairs of blocks glued) beside
//! the same parts as separate blocks (see `concave.rs`).
//!
//! `cargo run --release -p penedge-bench -- tunnel [--runs R] [--threads T] [--spacing S]
//! [--persistence P] [--radius M]` times the detection of about 10^5 blocks around a tunnel,
//! with concave blocks and rock bridges of a finite-joint set, beside the same parts as
//! separate blocks (see `tunnel.rs`).
//!
//! `cargo run --release -p penedge-bench -- mechanics [--blocks N] [--threads T] [--ratio R]
//! [--max-steps S] [--samples K] [--seed X] [--export FILE]` times a mass of blocks settling
//! under gravity on fixed boundary blocks to equilibrium (`penedge::mechanics`), and can write
//! the model for the YADE script `benches/yade/settle.py` (see `mechanics.rs`).
//!
//! `cargo run --release -p penedge-bench -- profile --scenario NAME --family cube|rock
//! [--pairs N] [--seconds S] [--geometry]` runs penedge alone on one set for a while
//! (`detect`, or `detect_with_geometry` with `--geometry`), to be watched by a profiler
//! (`perf record`). NAME is a row of the narrow or the geometry tables.

mod concave;
mod export;
mod family;
mod generation;
mod geometry;
mod heap;
mod mechanics;
mod outcomes;
mod pairs;
mod placement;
mod report;
mod rng;
mod system;
mod timing;
mod tracker;
mod tunnel;

use family::Family;
use pairs::{PairSet, Scenario};
use placement::{Push, Touch, PENETRATION, SEPARATION_MAX, SEPARATION_MIN};
use rng::SplitMix64;
use std::process::ExitCode;
use std::time::Duration;
use timing::{Job, Window};

/// Counts live heap bytes for the memory figures of `mechanics` (off in the other
/// subcommands).
#[global_allocator]
static ALLOCATOR: heap::Counting = heap::Counting;

/// The four situations of the main table.
const SITUATIONS: [Scenario; 4] = [
    Scenario {
        name: "separated",
        push: Push::Apart,
        touches: &Touch::ALL,
    },
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
        name: "penetrating 1e-3",
        push: Push::Into,
        touches: &Touch::ALL,
    },
];

static TOUCHES: [Touch; 7] = Touch::ALL;

/// One touching scenario per contact type.
fn by_contact_type() -> Vec<Scenario> {
    TOUCHES
        .iter()
        .map(|t| Scenario {
            name: t.contact_type().name(),
            push: Push::Touching,
            touches: std::slice::from_ref(t),
        })
        .collect()
}

struct Options {
    pairs: usize,
    reps: usize,
    seed: u64,
    detail: bool,
    scenario: String,
    family: Family,
    seconds: f64,
    hot: usize,
    export: Option<String>,
    geometry: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            pairs: 4000,
            reps: 21,
            seed: 2004,
            detail: true,
            scenario: "face-face touching".to_string(),
            family: Family::Cube,
            seconds: 10.0,
            hot: 256,
            export: None,
            geometry: false,
        }
    }
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options::default();
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--pairs" => o.pairs = number(value()?)?,
            "--reps" => o.reps = number(value()?)?,
            "--seed" => o.seed = number(value()?)?,
            "--seconds" => o.seconds = number(value()?)?,
            "--hot" => o.hot = number(value()?)?,
            "--scenario" => o.scenario = value()?.clone(),
            "--family" => o.family = family(value()?)?,
            "--no-detail" => o.detail = false,
            "--export" => o.export = Some(value()?.clone()),
            "--geometry" => o.geometry = true,
            other => return Err(format!("unknown option {other}")),
        }
    }
    if o.pairs == 0 || o.reps == 0 || o.hot == 0 {
        return Err("--pairs, --reps and --hot must be positive".to_string());
    }
    Ok(o)
}

fn number<T: std::str::FromStr>(s: &str) -> Result<T, String> {
    s.parse().map_err(|_| format!("not a number: {s}"))
}

fn family(s: &str) -> Result<Family, String> {
    Family::ALL
        .into_iter()
        .find(|f| f.name() == s)
        .ok_or(format!("unknown family {s} (cube or rock)"))
}

/// A generator for row `row` and `family`, so that every set depends on the seed only.
fn set_rng(seed: u64, row: usize, family: Family) -> SplitMix64 {
    let mut mix = SplitMix64::new(seed ^ ((row as u64) << 8) ^ family as u64);
    SplitMix64::new(mix.next_u64())
}

/// How the pairs of a set are visited when timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// Every pair once per round.
    Cold,
    /// The first `--hot` pairs, looped.
    Hot,
}

impl Mode {
    fn window(self, set: &PairSet, o: &Options) -> Window {
        match self {
            Mode::Cold => Window::cold(set),
            Mode::Hot => Window::hot(set, o.hot),
        }
    }

    fn caption(self, o: &Options) -> String {
        match self {
            Mode::Cold => format!(
                "cold: all {} pairs once per round, blocks from main memory",
                o.pairs
            ),
            Mode::Hot => format!(
                "hot: the first {} pairs, warmed up and looped, blocks in cache",
                o.hot.min(o.pairs)
            ),
        }
    }
}

/// Generates, verifies and times every set of `scenarios` in each mode; prints the
/// verification table and one timing table per mode.
fn run_table(title: &str, scenarios: &[Scenario], first_row: usize, modes: &[Mode], o: &Options) {
    let sets: Vec<PairSet> = scenarios
        .iter()
        .enumerate()
        .flat_map(|(i, scenario)| {
            Family::ALL.map(|family| {
                let mut rng = set_rng(o.seed, first_row + i, family);
                PairSet::generate(*scenario, family, o.pairs, &mut rng)
            })
        })
        .collect();
    println!("### {title}: outcomes as expected\n");
    println!("{}", report::agreement_header());
    for set in &sets {
        println!("{}", report::agreement_row(set, &set.verify()));
        report_misses(set);
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
    let medians = timing::measure(&jobs, o.reps);
    for (mode, medians) in modes.iter().zip(medians.chunks(sets.len())) {
        println!(
            "\n### {title}: ns per pair, median of {} rounds ({})\n",
            o.reps,
            mode.caption(o)
        );
        println!("{}", report::timing_header());
        for (set, m) in sets.iter().zip(medians) {
            println!("{}", report::timing_row(set, m));
        }
    }
    println!();
}

fn report_misses(set: &PairSet) {
    for (i, expected, got) in set.penedge_misses().into_iter().take(5) {
        eprintln!(
            "penedge miss: {} {} pair {i}: expected {expected:?}, got {got:?}",
            set.scenario.name,
            set.family.name()
        );
    }
}

fn narrow(o: &Options) {
    println!("## Narrow phase: penedge vs parry3d-f64\n");
    println!(
        "{} pairs per row, seed {}, single thread; {}.",
        o.pairs,
        o.seed,
        report::machine()
    );
    println!(
        "Separated: {SEPARATION_MIN}..{SEPARATION_MAX} apart; penetrating: {PENETRATION} deep; \
         penedge default tolerance; parry prediction = penedge's absolute gap."
    );
    println!(
        "Times are CPU time of the benchmark thread. Load average at the start: {}.\n",
        report::load()
    );
    let both = [Mode::Cold, Mode::Hot];
    run_table("Main situations", &SITUATIONS, 0, &both, o);
    if o.detail {
        let title = "Touching, by contact type";
        run_table(title, &by_contact_type(), 100, &[Mode::Hot], o);
    }
    println!("Load average at the end: {}.", report::load());
}

fn profile(o: &Options) -> Result<(), String> {
    let all: Vec<Scenario> = SITUATIONS
        .into_iter()
        .chain(by_contact_type())
        .chain(geometry::SITUATIONS)
        .collect();
    let (row, scenario) = all
        .iter()
        .enumerate()
        .find(|(_, s)| s.name == o.scenario)
        .ok_or(format!("unknown scenario {}", o.scenario))?;
    let (n, types) = (SITUATIONS.len(), Touch::ALL.len());
    let row = match row {
        r if r < n => r,
        r if r < n + types => 100 + r - n,
        r => geometry::FIRST_ROW + r - n - types,
    };
    let set = PairSet::generate(
        *scenario,
        o.family,
        o.pairs,
        &mut set_rng(o.seed, row, o.family),
    );
    let n = timing::spin_penedge(&set, Duration::from_secs_f64(o.seconds), o.geometry);
    println!("{n} pairs detected ({} {})", scenario.name, o.family.name());
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("narrow") => parse(&args[1..]).map(|o| narrow(&o)),
        Some("geometry") => parse(&args[1..]).and_then(|o| geometry::run(&o)),
        Some("generate") => generation::run(&args[1..]),
        Some("generate-one") => generation::run_one(&args[1..]),
        Some("system") => system::run(&args[1..]),
        Some("tracker") => tracker::run(&args[1..]),
        Some("concave") => concave::run(&args[1..]),
        Some("tunnel") => tunnel::run(&args[1..]),
        Some("mechanics") => mechanics::run(&args[1..]),
        Some("outcomes") => outcomes::run(&args[1..]),
        Some("profile") => parse(&args[1..]).and_then(|o| profile(&o)),
        _ => Err(
            "usage: penedge-bench narrow|geometry|generate|system|tracker|concave|tunnel|mechanics|profile [options] (see the crate docs)"
                .to_string(),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
