//! The `system` subcommand: every contact of a whole block system (issue 4).
//!
//! `cargo run --release -p penedge-bench -- system [--grid N] [--runs R] [--threads T]
//! [--no-parry] [--no-jointed] [--broad N] [--incremental M]`
//!
//! 1. **Grid**: an `N x N x N` grid of unit cubes (default 100: 10^6 blocks, 12,731,796
//!    touching pairs). penedge `BlockSystem::detect` (broad phase + narrow phase + sorted
//!    output) in a rayon pool of `T` threads (default 2), wall-clock median of `R` runs; the
//!    broad phase alone; peak memory (`VmHWM`) of the process before parry runs. Then
//!    parry3d-f64 on the same system in the same pool: its BVH (`Bvh::from_leaves`, binned)
//!    over the same widened boxes, one `intersect_aabb` query per block, and `contact` on
//!    every pair found (one shared unit-cube `ConvexPolyhedron` with a translation per
//!    block, prediction = penedge's gap): the ratio of the two.
//! 2. **Jointed rock mass**: `examples/three_joint_sets.toml` (about 10^5 blocks): time,
//!    candidate pairs, contacts and contacts per second.
//! 3. **Incremental updates** on an `M^3` grid (`--incremental M`, default 50): a
//!    `ContactTracker` (skin 0.05) after a first small random motion of every block (up to
//!    1e-3 in each coordinate and 1e-3 rad) and then after eight more steps of 1e-6, each
//!    beside a full `BlockSystem::detect` of the moved blocks.
//! 4. **Broad phase methods** on an `N^3` grid (default 40) and on the jointed mass: the
//!    grid, sort-and-sweep (and brute force where it is small enough).

use crate::generation::vm_hwm_kib;
use crate::timing::median;
use parry3d_f64::bounding_volume::Aabb as ParryAabb;
use parry3d_f64::math::{Pose as ParryPose, Vector};
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query::contact;
use parry3d_f64::shape::ConvexPolyhedron;
use penedge::block::Pose;
use penedge::generation::generate;
use penedge::system::{count_types, BlockSystem, BroadPhase, ContactTracker};
use penedge::{ContactType, ConvexBlock, Tolerance};
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

struct SystemOptions {
    grid: usize,
    runs: usize,
    threads: usize,
    parry: bool,
    jointed: bool,
    broad: usize,
    incremental: usize,
}

fn parse(args: &[String]) -> Result<SystemOptions, String> {
    let mut o = SystemOptions {
        grid: 100,
        runs: 3,
        threads: 2,
        parry: true,
        jointed: true,
        broad: 40,
        incremental: 50,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--grid" => o.grid = crate::number(value()?)?,
            "--runs" => o.runs = crate::number(value()?)?,
            "--threads" => o.threads = crate::number(value()?)?,
            "--broad" => o.broad = crate::number(value()?)?,
            "--incremental" => o.incremental = crate::number(value()?)?,
            "--no-parry" => o.parry = false,
            "--no-jointed" => o.jointed = false,
            other => return Err(format!("unknown option {other}")),
        }
    }
    if o.grid == 0 || o.runs == 0 || o.threads == 0 {
        return Err("--grid, --runs and --threads must be positive".to_string());
    }
    Ok(o)
}

/// A thread pool of `threads` threads for a benchmark to run in.
pub(crate) fn pool(threads: usize) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| e.to_string())
}

/// `system`: prints the tables.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    let pool = pool(o.threads)?;
    println!("## Whole systems\n");
    println!(
        "{} threads; {}. Load average at the start: {}.\n",
        o.threads,
        crate::report::machine(),
        crate::report::load()
    );
    pool.install(|| grid(&o))?;
    if o.jointed {
        pool.install(|| jointed(&o))?;
    }
    if o.incremental > 0 {
        pool.install(|| incremental(&o))?;
    }
    if o.broad > 0 {
        pool.install(|| broad_phases(&o))?;
    }
    println!("\nLoad average at the end: {}.", crate::report::load());
    Ok(())
}

/// An `n^3` grid of unit cubes, block `x + n (y + n z)` at `(x, y, z)`.
pub fn cube_grid(n: usize) -> BlockSystem {
    let blocks = (0..n * n * n)
        .into_par_iter()
        .map(|k| {
            let p = [(k % n) as f64, (k / n % n) as f64, (k / (n * n)) as f64];
            ConvexBlock::cuboid(p, p.map(|c| c + 1.0)).expect("a unit cube")
        })
        .collect();
    BlockSystem::new(blocks)
}

/// Touching pairs of an `n^3` grid: face, edge and vertex neighbours.
fn grid_pairs(n: usize) -> usize {
    let (n, m) = (n, n.saturating_sub(1));
    3 * m * n * n + 6 * m * m * n + 4 * m * m * m
}

/// Wall-clock seconds of `f`, median of `runs`, with the last result.
pub(crate) fn timed<T>(runs: usize, f: impl FnMut() -> T) -> (f64, T) {
    let (mut times, last) = timed_each(runs, f);
    (median(&mut times), last)
}

/// Wall-clock seconds of each of `runs` runs of `f`, with the last result.
fn timed_each<T>(runs: usize, mut f: impl FnMut() -> T) -> (Vec<f64>, T) {
    let mut times = Vec::with_capacity(runs);
    let mut last = None;
    for _ in 0..runs {
        let start = Instant::now();
        let out = f();
        times.push(start.elapsed().as_secs_f64());
        last = Some(std::hint::black_box(out));
    }
    (times, last.expect("runs > 0"))
}

fn grid(o: &SystemOptions) -> Result<(), String> {
    let n = o.grid;
    let tol = Tolerance::default();
    let start = Instant::now();
    let system = cube_grid(n);
    let build = start.elapsed().as_secs_f64();
    let hwm_blocks = vm_hwm_kib()?;
    let (broad, pairs) = timed(o.runs, || system.candidate_pairs(&tol).len());
    let (mut each, found) = timed_each(o.runs, || system.detect(&tol));
    let every = each
        .iter()
        .map(|t| format!("{t:.3}"))
        .collect::<Vec<_>>()
        .join(", ");
    let full = median(&mut each);
    let hwm = vm_hwm_kib()?;
    let expected = grid_pairs(n);
    let counts = count_types(&found.contacts);
    println!(
        "### {n}^3 grid of unit cubes: {} blocks, {expected} touching pairs\n",
        n * n * n
    );
    println!(
        "Blocks built in {build:.2} s (not timed below). Candidate pairs: {pairs}. Contacts: {} \
         ({}), penetrating: {}.\n",
        found.contacts.len(),
        type_counts(&counts),
        found.penetrating.len()
    );
    if found.contacts.len() != expected || !found.penetrating.is_empty() {
        return Err(format!(
            "penedge found {} contacts, {} penetrating; expected {expected}, 0",
            found.contacts.len(),
            found.penetrating.len()
        ));
    }
    drop(found);
    println!(
        "| engine | what | wall s (median of {}) | pairs/s | peak memory |",
        o.runs
    );
    println!("|---|---|---:|---:|---:|");
    println!(
        "| penedge | broad phase (hierarchical grid) | {broad:.3} | {:.3e} | |",
        pairs as f64 / broad
    );
    println!(
        "| penedge | `BlockSystem::detect`: all contacts, classified, sorted | {full:.3} | {:.3e} | {} (blocks alone: {}) |",
        expected as f64 / full,
        gib(hwm),
        gib(hwm_blocks)
    );
    println!(
        "\n`BlockSystem::detect`, every run in order: {every} s (the two virtual cores are \
         sometimes slower together: see benchmarks.md).\n"
    );
    if o.parry {
        let (parry_s, parry_found) = parry_grid(&system, &tol);
        if parry_found != expected {
            eprintln!("parry found {parry_found} contacts, expected {expected}");
        }
        println!(
            "| parry3d-f64 | BVH + `intersect_aabb` + `contact` (shared cube shape) | {parry_s:.3} | {:.3e} | |",
            parry_found as f64 / parry_s
        );
        println!(
            "\nparry3d-f64 / penedge: **{:.1}x** (parry found {parry_found} contacts).",
            parry_s / full
        );
    }
    println!();
    Ok(())
}

fn gib(kib: u64) -> String {
    format!("{:.2} GiB", kib as f64 / (1024.0 * 1024.0))
}

fn type_counts(counts: &[usize; 7]) -> String {
    ContactType::ALL
        .iter()
        .zip(counts)
        .filter(|(_, &c)| c > 0)
        .map(|(t, c)| format!("{} {c}", t.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// parry on the grid: BVH over the widened boxes, a query per block, `contact` per pair
/// (wall-clock seconds, touching pairs found).
fn parry_grid(system: &BlockSystem, tol: &Tolerance) -> (f64, usize) {
    let blocks = system.blocks();
    let cube = ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).expect("a unit cube");
    let shape = crate::pairs::polyhedron(&cube);
    let boxes = system.wide_boxes(tol);
    let start = Instant::now();
    let leaves: Vec<ParryAabb> = blocks
        .iter()
        .map(|b| {
            let a = b.aabb();
            let m = tol.for_box(&a).gap;
            ParryAabb::new(vector(a.min - m), vector(a.max + m))
        })
        .collect();
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
    let found: usize = (0..blocks.len())
        .into_par_iter()
        .map(|i| {
            let pose_i = ParryPose::from_translation(vector(blocks[i].centroid()));
            bvh.intersect_aabb(&leaves[i])
                .filter(|&j| j as usize > i)
                .filter(|&j| {
                    let j = j as usize;
                    let pose_j = ParryPose::from_translation(vector(blocks[j].centroid()));
                    let gap = tol.for_box(&blocks[i].aabb()).gap;
                    touches(&pose_i, &shape, &pose_j, gap)
                })
                .count()
        })
        .sum();
    drop(boxes);
    (start.elapsed().as_secs_f64(), found)
}

fn touches(pose_a: &ParryPose, shape: &ConvexPolyhedron, pose_b: &ParryPose, gap: f64) -> bool {
    matches!(contact(pose_a, shape, pose_b, shape, gap), Ok(Some(c)) if c.dist <= gap)
}

fn vector(v: glam::DVec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

pub fn jointed_system() -> Result<BlockSystem, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/three_joint_sets.toml");
    let spec = penedge::io::spec::read_spec(&path).map_err(|e| e.to_string())?;
    Ok(generate(&spec).map_err(|e| e.to_string())?.system)
}

fn jointed(o: &SystemOptions) -> Result<(), String> {
    let tol = Tolerance::default();
    let system = jointed_system()?;
    let (broad, pairs) = timed(o.runs, || system.candidate_pairs(&tol).len());
    let (full, found) = timed(o.runs, || system.detect(&tol));
    println!(
        "### Jointed rock mass: examples/three_joint_sets.toml, {} blocks\n",
        system.len()
    );
    println!(
        "Candidate pairs {pairs}; contacts {} ({}); penetrating {}.\n",
        found.contacts.len(),
        type_counts(&count_types(&found.contacts)),
        found.penetrating.len()
    );
    println!("| what | wall s (median of {}) | per second |", o.runs);
    println!("|---|---:|---:|");
    println!(
        "| broad phase | {broad:.3} | {:.3e} candidate pairs |",
        pairs as f64 / broad
    );
    println!(
        "| `BlockSystem::detect` | {full:.3} | {:.3e} contacts ({:.3e} candidate pairs) |\n",
        found.contacts.len() as f64 / full,
        pairs as f64 / full
    );
    Ok(())
}

fn broad_phases(o: &SystemOptions) -> Result<(), String> {
    let tol = Tolerance::default();
    let grid = cube_grid(o.broad);
    let jointed = if o.jointed {
        Some(jointed_system()?)
    } else {
        None
    };
    println!("### Broad phase methods\n");
    println!(
        "| system | blocks | method | candidate pairs | wall s (median of {}) |",
        o.runs
    );
    println!("|---|---:|---|---:|---:|");
    let systems = [
        (format!("{}^3 grid of cubes", o.broad), Some(&grid)),
        ("jointed rock mass".to_string(), jointed.as_ref()),
    ];
    for (name, system) in systems {
        let Some(system) = system else { continue };
        let boxes = system.wide_boxes(&tol);
        let mut reference = None;
        for method in BroadPhase::ALL {
            if method == BroadPhase::BruteForce && system.len() > 20_000 {
                continue;
            }
            let (s, pairs) = timed(o.runs, || boxes.pairs(method));
            let same = reference.get_or_insert_with(|| pairs.clone()) == &pairs;
            if !same {
                return Err(format!("{name}: {} disagrees", method.name()));
            }
            println!(
                "| {name} | {} | {} | {} | {s:.3} |",
                system.len(),
                method.name(),
                pairs.len()
            );
        }
    }
    Ok(())
}

/// A small random rigid step composed onto `pose`: a rotation by up to `angle` about the
/// block's centroid `centre` (reference coordinates), then a shift of up to `shift` along
/// each axis.
pub(crate) fn step(
    pose: &Pose,
    centre: glam::DVec3,
    rng: &mut crate::rng::SplitMix64,
    shift: f64,
    angle: f64,
) -> Pose {
    let c = pose.apply(centre);
    let axis = rng.direction();
    let rotation = glam::DQuat::from_axis_angle(axis, angle * rng.range(-1.0, 1.0));
    let shift = glam::DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ) * shift;
    Pose {
        rotation: (rotation * pose.rotation).normalize(),
        translation: rotation * (pose.translation - c) + c + shift,
    }
}

/// Steps of the incremental benchmark: one of 1e-3, then small ones of 1e-6.
const STEPS: usize = 9;

fn incremental(o: &SystemOptions) -> Result<(), String> {
    let n = o.incremental;
    let tol = Tolerance::default();
    let system = cube_grid(n);
    let skin = 0.05;
    let mut tracker = ContactTracker::new(&system, tol, skin).map_err(|e| e.to_string())?;
    let mut rng = crate::rng::SplitMix64::new(4);
    let mut poses = vec![Pose::IDENTITY; system.len()];
    println!(
        "### Incremental updates: {n}^3 grid of unit cubes, skin {skin}\n\n\
         Each step moves every block by a random rigid step; `ContactTracker::update` (placing \
         the blocks included) beside `BlockSystem::detect` on the same moved blocks (their \
         placing not timed).\n"
    );
    println!(
        "| step | motion | broad phase rebuilt | candidate pairs | certified | queried | contacts | penetrating | update s | full detect s | full / update |"
    );
    println!("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut ratios = Vec::new();
    for k in 1..=STEPS {
        let (shift, angle) = if k == 1 { (1e-3, 1e-3) } else { (1e-6, 1e-6) };
        for (pose, block) in poses.iter_mut().zip(system.blocks()) {
            *pose = step(pose, block.centroid(), &mut rng, shift, angle);
        }
        let start = Instant::now();
        let report = tracker.update(&poses).map_err(|e| e.to_string())?;
        let update_s = start.elapsed().as_secs_f64();
        let moved = tracker.system().clone();
        let (full_s, full) = timed(o.runs, || moved.detect(&tol));
        if &full != tracker.contacts() {
            return Err(format!(
                "step {k}: the tracker disagrees with a full detection"
            ));
        }
        println!(
            "| {k} | {shift:.0e}, {angle:.0e} rad | {} | {} | {} | {} | {} | {} | {update_s:.3} | {full_s:.3} | **{:.1}x** |",
            if report.rebuilt { "yes" } else { "no" },
            report.candidate_pairs,
            report.certified,
            report.queried,
            full.contacts.len(),
            full.penetrating.len(),
            full_s / update_s
        );
        if k > 1 {
            ratios.push(full_s / update_s);
        }
    }
    println!(
        "\nMedian full / update over the small steps: **{:.1}x**.\n",
        median(&mut ratios)
    );
    Ok(())
}
