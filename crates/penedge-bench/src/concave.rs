//! The `concave` subcommand: detection on a system with concave blocks (issue 20).
//!
//! `cargo run --release -p penedge-bench -- concave [--runs R] [--threads T] [--share S]`
//!
//! The jointed rock mass of `examples/three_joint_sets.toml` (about 10^5 convex blocks).
//! Blocks are glued into concave blocks in pairs along face-face contacts (taken in order,
//! each block at most once) until `S` (default 0.5) of the blocks are glued: the system
//! then has `N (1 - S / 2)` bodies, of which `N S / 2` have two parts (a third of the bodies
//! for S = 0.5, above the fifth the issue asks), if enough such pairs are found. Whether the union of two glued blocks is
//! convex or not does not change the work: their part contacts are grouped and typed the same.
//!
//! Times (wall clock, median of `R` runs, `T` threads):
//! 1. `detect_bodies` on the system with the concave blocks;
//! 2. `detect_bodies` on the same parts, each its own body (what the first is compared with);
//! 3. `detect_with_geometry` and `detect` on the parts, for reference;
//! 4. `with_bodies` (checking the parts and finding the internal faces), once per system.

use crate::system::{jointed_system, pool, timed};
use penedge::system::BlockSystem;
use penedge::{ContactType, Tolerance};

struct Options {
    runs: usize,
    threads: usize,
    share: f64,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        runs: 5,
        threads: 2,
        share: 0.5,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--runs" => o.runs = crate::number(value()?)?,
            "--threads" => o.threads = crate::number(value()?)?,
            "--share" => o.share = value()?.parse().map_err(|e| format!("--share: {e}"))?,
            other => return Err(format!("unknown option {other}")),
        }
    }
    if o.runs == 0 || o.threads == 0 || !(0.0..=1.0).contains(&o.share) {
        return Err("--runs and --threads must be positive, --share in [0, 1]".to_string());
    }
    Ok(o)
}

/// Body ids gluing pairs of blocks along face-face contacts until `share` of the blocks are
/// glued; the number of concave bodies.
fn glued_pairs(system: &BlockSystem, tol: &Tolerance, share: f64) -> (Vec<u32>, usize) {
    let mut ids: Vec<u32> = (0..system.len() as u32).collect();
    let mut used = vec![false; system.len()];
    let target = (share * system.len() as f64) as usize;
    let mut glued = 0;
    for c in system.detect(tol).contacts {
        let [a, b] = c.pair.map(|k| k as usize);
        if glued + 2 > target {
            break;
        }
        if c.contact.kind == ContactType::FaceFace && !used[a] && !used[b] {
            used[a] = true;
            used[b] = true;
            ids[b] = a as u32;
            glued += 2;
        }
    }
    (ids, glued / 2)
}

/// `concave`: prints the table.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    pool(o.threads)?.install(|| table(&o))
}

fn table(o: &Options) -> Result<(), String> {
    let tol = Tolerance::default();
    let parts = jointed_system()?;
    let (ids, concave) = glued_pairs(&parts, &tol, o.share);
    let (setup, bodies) = timed(1, || parts.clone().with_bodies(ids.clone(), &tol));
    let bodies = bodies.map_err(|e| e.to_string())?;
    let n_bodies = parts.len() - concave;
    println!("## Concave blocks: examples/three_joint_sets.toml\n");
    println!(
        "{} threads; {}. Load average at the start: {}.\n",
        o.threads,
        crate::report::machine(),
        crate::report::load()
    );
    println!(
        "{} convex parts; {n_bodies} bodies, {concave} of them concave blocks of two parts \
         ({:.1} % of the bodies); {} internal faces.\n",
        parts.len(),
        100.0 * concave as f64 / n_bodies as f64,
        bodies.internal_faces().len()
    );
    let (with, found) = timed(o.runs, || bodies.detect_bodies(&tol));
    let (without, separate) = timed(o.runs, || parts.detect_bodies(&tol));
    let (geometry, _) = timed(o.runs, || parts.detect_with_geometry(&tol));
    let (plain, _) = timed(o.runs, || parts.detect(&tol));
    let several = found.contacts.iter().filter(|c| c.region > 0).count();
    println!(
        "Regions: {} with the concave blocks ({several} of them a second or later region of \
         a pair), {} with the parts as separate blocks.\n",
        found.contacts.len(),
        separate.contacts.len()
    );
    println!("| what | wall s (median of {}) | ratio |", o.runs);
    println!("|---|---:|---:|");
    println!(
        "| `detect_bodies`, concave blocks | {with:.3} | {:.2} |",
        with / without
    );
    println!("| `detect_bodies`, the parts as separate blocks | {without:.3} | 1.00 |");
    println!(
        "| `detect_with_geometry`, the parts | {geometry:.3} | {:.2} |",
        geometry / without
    );
    println!(
        "| `detect`, the parts | {plain:.3} | {:.2} |",
        plain / without
    );
    println!(
        "| `with_bodies` (once) | {setup:.3} | {:.2} |\n",
        setup / without
    );
    println!("Load average at the end: {}.", crate::report::load());
    Ok(())
}
