//! The `tracker` subcommand: `ContactTracker` steps beside full detections (issue 18,
//! "Updating contacts cheaply").
//!
//! `cargo run --release -p penedge-bench -- tracker [--grid N] [--gap G] [--steps S]
//! [--runs R] [--threads T]`
//!
//! An `N^3` grid of unit cubes (default 50: 125,000 blocks, 1,558,396 candidate pairs) at a
//! relative gap `G` (default 1e-3, where every candidate pair touches), a tracker with a
//! skin of 0.05. Three motions, `S` steps each (default 4): every block jittered (a random
//! rigid step of up to 1e-5 along each axis and 1e-5 rad about its centroid), 1 % of the
//! blocks (drawn anew each step) jittered and the others still, and no block moved. Each
//! step: `ContactTracker::update` (placing the blocks included) beside `BlockSystem::detect`
//! on the same moved blocks (their placing not timed, median of `R` runs, default 3), checked
//! equal, and beside the time to place every block at its pose (`ConvexBlock::transformed`
//! into a new `BlockSystem`), which a step without a tracker pays before detecting.

use crate::system::{cube_grid, pool, step, timed};
use penedge::block::Pose;
use penedge::system::{BlockSystem, ContactTracker};
use penedge::Tolerance;
use rayon::prelude::*;
use std::time::Instant;

struct Options {
    grid: usize,
    gap: f64,
    steps: usize,
    runs: usize,
    threads: usize,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        grid: 50,
        gap: 1e-3,
        steps: 4,
        runs: 3,
        threads: 2,
    };
    // Every option takes a value.
    for pair in args.chunks(2) {
        let [flag, value] = pair else {
            return Err(format!("{} needs a value", pair[0]));
        };
        match flag.as_str() {
            "--grid" => o.grid = crate::number(value)?,
            "--gap" => o.gap = value.parse().map_err(|e| format!("--gap: {e}"))?,
            "--steps" => o.steps = crate::number(value)?,
            "--runs" => o.runs = crate::number(value)?,
            "--threads" => o.threads = crate::number(value)?,
            other => return Err(format!("unknown option {other}")),
        }
    }
    if [o.grid, o.runs, o.threads].contains(&0) {
        return Err("--grid, --runs and --threads must be positive".to_string());
    }
    Ok(o)
}

/// `tracker`: prints the table.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    let tol = Tolerance::with_gap(o.gap).map_err(|e| e.to_string())?;
    pool(o.threads)?.install(|| steps(&o, tol))
}

/// Which blocks a step moves.
#[derive(Clone, Copy)]
enum Motion {
    All,
    OnePercent,
    None,
}

impl Motion {
    fn name(self) -> &'static str {
        match self {
            Motion::All => "every block jittered",
            Motion::OnePercent => "1 % of the blocks jittered",
            Motion::None => "no block moved",
        }
    }
}

fn steps(o: &Options, tol: Tolerance) -> Result<(), String> {
    let n = o.grid;
    let system = cube_grid(n);
    let skin = 0.05;
    let start = Instant::now();
    let mut tracker = ContactTracker::new(&system, tol, skin).map_err(|e| e.to_string())?;
    let new_s = start.elapsed().as_secs_f64();
    println!(
        "### Tracker steps: {n}^3 grid of unit cubes, relative gap {:e}, skin {skin}, {} threads\n\n\
         {}; load average at the start: {}. `ContactTracker::new` (a full detection): {new_s:.3} s. \
         Each step: `ContactTracker::update` (placing the blocks included) beside \
         `BlockSystem::detect` on the same moved blocks (their placing not timed, median of {} \
         runs); the two agree at every step.\n",
        o.gap,
        o.threads,
        crate::report::machine(),
        crate::report::load(),
        o.runs
    );
    println!(
        "| motion | step | rebuilt | candidate pairs | certified | unmoved | queried | contacts | update s | full detect s | update / full | place s | update / (place + full) |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut rng = crate::rng::SplitMix64::new(18);
    let mut poses = vec![Pose::IDENTITY; system.len()];
    let (jitter, angle) = (1e-5, 1e-5);
    for motion in [Motion::All, Motion::OnePercent, Motion::None] {
        for k in 1..=o.steps {
            match motion {
                Motion::All => {
                    for (pose, block) in poses.iter_mut().zip(system.blocks()) {
                        *pose = step(pose, block.centroid(), &mut rng, jitter, angle);
                    }
                }
                Motion::OnePercent => {
                    for _ in 0..system.len() / 100 {
                        let i = rng.index(system.len());
                        let c = system.blocks()[i].centroid();
                        poses[i] = step(&poses[i], c, &mut rng, jitter, angle);
                    }
                }
                Motion::None => {}
            }
            let start = Instant::now();
            let report = tracker.update(&poses).map_err(|e| e.to_string())?;
            let update_s = start.elapsed().as_secs_f64();
            let moved = tracker.system().clone();
            let (full_s, full) = timed(o.runs, || moved.detect(&tol));
            // What a step without a tracker does: place every block at its pose, detect.
            let (place_s, placed) = timed(o.runs, || {
                let blocks = system.blocks().par_iter().zip(&poses);
                BlockSystem::new(
                    blocks
                        .map(|(b, p)| b.transformed(p.rotation, p.translation, 1.0))
                        .collect(),
                )
            });
            if placed.blocks().len() != moved.blocks().len() {
                return Err("placing lost blocks".to_string());
            }
            if &full != tracker.contacts() {
                return Err(format!(
                    "{} step {k}: the tracker disagrees with a full detection",
                    motion.name()
                ));
            }
            println!(
                "| {} | {k} | {} | {} | {} | {} | {} | {} | {update_s:.3} | {full_s:.3} | {:.2} | {place_s:.3} | {:.2} |",
                motion.name(),
                if report.rebuilt { "yes" } else { "no" },
                report.candidate_pairs,
                report.certified,
                report.unmoved,
                report.queried,
                full.contacts.len(),
                update_s / full_s,
                update_s / (place_s + full_s)
            );
        }
    }
    println!("\nLoad average at the end: {}.", crate::report::load());
    Ok(())
}
