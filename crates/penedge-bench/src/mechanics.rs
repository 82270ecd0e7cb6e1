//! The `mechanics` subcommand: a jointed mass of blocks settling under gravity on fixed
//! boundary blocks, to equilibrium (issue 18, "Speed").
//!
//! `cargo run --release -p penedge-bench -- mechanics [--blocks N] [--threads T]
//! [--ratio R] [--speed V] [--max-steps S] [--samples K] [--seed X] [--export FILE] [--full 0|1]
//! [--update F] [--dormant 0|1] [--progress P] [--save-at S --save FILE] [--load FILE]
//! [--max-wall W] [--joints open|closed|jointed]`
//!
//! `--update F` (default 0.1, `FAST_UPDATE_FRACTION`) carries touching pairs until their
//! bodies have moved `F` × the gap; `--update 0` is the engine's exact default.
//! `--full 1` queries every candidate pair at every step (`Simulation::set_full_detection`,
//! the step before the contact updates), for comparison. `--dormant 0` updates every
//! carried open contact's sub-contacts (`Simulation::set_dormant_contacts`; default 1: an
//! open contact certified to stay open keeps them), for comparison.
//!
//! **The model** (`N` blocks at most, default 100,000): a grid of `(n + 2) × (n + 2) ×
//! (n + 1)` unit cubes, `n` the largest that fits in `N`, at a spacing of 1.002 (open joints
//! of 2 mm). The cubes of the bottom layer and of the four side walls are fixed and sit
//! exactly on the grid; the `n^3` inner cubes are free, each turned by a random angle of up
//! to 0.5 mrad about a random axis and shifted by up to 0.1 mm along each axis (seed `X`),
//! so that no two blocks touch at the start (the smallest gap is above 1 mm, the detection
//! gap). Density 2500 kg/m³, gravity 9.81 m/s², joints kn = 1e10 Pa/m, ks = 5e9 Pa/m, 30°,
//! no cohesion or tension, local damping 0.8, the automatic time step.
//!
//! `--joints closed`: the same grid at a spacing of 1 with no turn or shift, every joint
//! closed at zero stress at the start (a jointed rock mass in place, 3DEC's usual start):
//! the free blocks do not fall, they settle by the joints' elastic closure under their
//! weight, and every block touches its 26 neighbours (faces, edges, corners).
//!
//! `--joints jointed`: the closed grid with the face origins a generation from three joint
//! sets gives it (`FaceOrigin::Joint`: set 0, 1, 2 for the planes normal to x, y, z, one
//! joint per plane; the box's outer faces `FaceOrigin::Boundary`). The cubes' contacts of
//! edges and corners then lie where joints cross and bear only past half the detection gap
//! (docs/mechanics.md, "Where joints cross"), as in a rock mass generated from joint sets;
//! `closed` has no origins (blocks given by their vertices), and those contacts bear from
//! the first overlap.
//!
//! **The run**: `Simulation::step` until the unbalanced-force ratio (largest unbalanced
//! force of a free block over its weight) is below `R` (default 1e-5, 3DEC's), at most `S`
//! steps (default 20,000), as `Simulation::solve` does but with each step timed (wall
//! clock, in a rayon pool of `T` threads, default 2). Printed: wall time, steps, block-steps
//! per second over all steps and over the steps while blocks move (the fastest free block
//! faster than 1 mm/s), the CPU time of the process in the steps (all threads: the figure the
//! load of a shared machine distorts least) and block-steps per CPU second, the state reached (mean settlement of the free blocks, the ratio).
//!
//! With `--speed V` the run also stops, as settled, at the first step at which the fastest
//! free block is slower than `V` (m/s) after one has been faster than the moving speed
//! (1 mm/s): a physical criterion that YADE's run (`settle.py`, given the same `speed` in the
//! exported model) checks the same way, for the time to the same settled state.
//!
//! `--progress P` prints a line every `P` steps while the run goes on (step, simulated time,
//! wall and CPU seconds so far, the fastest free block, the ratio, the mean settlement, the
//! kinetic energy of the free blocks, contacts): a long run to equilibrium then gives figures
//! even when it is stopped before it ends.
//!
//! `--max-wall W` stops the run, as not converged, after the first step that ends `W`
//! seconds (wall) after the first step began, and prints the same summary: a run to
//! equilibrium longer than the time at hand still gives its figures so far.
//!
//! `--save-at S --save FILE` writes the simulation's restart file (`Simulation::save_state`)
//! after step `S` (`--save-at end`: after the run's last step, however it stopped: a run to
//! equilibrium longer than the time at hand goes on later from there); `--load FILE` starts
//! from such a file instead of the model's initial state (the same model and options
//! otherwise): a profile of the dense phase of a long run then starts where it is, without
//! the minutes of steps before it. The steps of a loaded run count from the file's step
//! (`--max-steps` and the summary's steps), its rates from the steps it took; its first step
//! re-queries the pairs (the pair answers are not in the file), so time a loaded run over
//! many steps.
//!
//! **Time split** (the mechanics has no counters of its own): at `K` steps spread over the
//! run (default 8), the detection alone is timed from outside on the same poses
//! (`Simulation::placed_system`): the broad phase (`WideBoxes`, boxes widened by the gap
//! plus the simulation's half skin) and the pair query with geometry
//! (`Detector::detect_with_geometry`) on its pairs with a free block, as the step does
//! them; the rest of the step (sub-contacts, forces, integration, placing) is the step's
//! time minus the query's. The step reuses its broad phase within the skin, so the broad
//! phase is shown apart.
//!
//! **Memory**: the live heap bytes (a counting allocator) added by `Simulation::new` per
//! body, and by the first step with contacts per contact (sub-contacts and candidate pairs
//! included), beside `size_of` of the public contact types.
//!
//! `--export FILE` writes the model for `benches/yade/settle.py` (the same blocks in YADE's
//! Polyhedra DEM): a header of `key value` lines, then one line per block: `fixed` (0 or 1)
//! and its 8 corners' coordinates.

use crate::heap;
use crate::rng::SplitMix64;
use crate::system::pool;
use penedge::block::FaceOrigin;
use penedge::classify::PairResult;
use penedge::glam::{DQuat, DVec3};
use penedge::mechanics::{BodyContact, Damping, JointModel, Simulation, StepTimings, SubContact};
use penedge::system::{BroadPhase, WideBoxes};
use penedge::{BlockSystem, ConvexBlock, Detector, Tolerance};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

/// Spacing of the grid: unit cubes with 2 mm open joints.
const SPACING: f64 = 1.002;
/// The largest turn of a free cube (rad) and its largest shift along each axis (m).
const TURN: f64 = 5e-4;
const SHIFT: f64 = 1e-4;
const DENSITY: f64 = 2500.0;
const JOINT: JointModel = JointModel {
    kn: 1e10,
    ks: 5e9,
    friction: 30.0,
    cohesion: 0.0,
    tension: 0.0,
    residual_friction: None,
    residual_cohesion: 0.0,
};
const LOCAL_DAMPING: f64 = 0.8;
/// The simulation's detection gap (relative) and skin (relative to the mean block size), its
/// defaults: the outside detection of the time split uses the same.
const GAP: f64 = 1e-3;
const SKIN: f64 = 0.05;
/// A free block faster than this (m/s) counts as moving.
const MOVING: f64 = 1e-3;

struct Options {
    blocks: usize,
    threads: usize,
    ratio: f64,
    /// Settled when the fastest free block is slower than this (m/s), after moving.
    speed: Option<f64>,
    max_steps: u64,
    samples: u64,
    seed: u64,
    export: Option<String>,
    /// Query every candidate pair every step (`Simulation::set_full_detection`).
    full: bool,
    /// The update tolerance of touching pairs, a fraction of the gap
    /// (`Simulation::set_update_fraction`).
    update: f64,
    /// Whether carried open contacts may stay dormant (`Simulation::set_dormant_contacts`).
    dormant: bool,
    /// Print a progress line every this many steps (0: none).
    progress: u64,
    /// Write the restart file to the path after the step (`None`: after the last step).
    save: Option<(Option<u64>, String)>,
    /// Start from this restart file.
    load: Option<String>,
    /// Stop after this many wall seconds of steps.
    max_wall: Option<f64>,
    /// Joints closed at the start (spacing 1, no turn or shift) instead of open 2 mm, with
    /// or without the faces' joint origins.
    joints: Joints,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        blocks: 100_000,
        threads: 2,
        ratio: 1e-5,
        speed: None,
        max_steps: 20_000,
        samples: 8,
        seed: 18,
        export: None,
        full: false,
        update: penedge::mechanics::FAST_UPDATE_FRACTION,
        dormant: true,
        progress: 0,
        save: None,
        load: None,
        max_wall: None,
        joints: Joints::Open,
    };
    let mut save_at = None;
    let mut save_to = None;
    for pair in args.chunks(2) {
        let [flag, value] = pair else {
            return Err(format!("{} needs a value", pair[0]));
        };
        match flag.as_str() {
            "--blocks" => o.blocks = crate::number(value)?,
            "--threads" => o.threads = crate::number(value)?,
            "--update" => {
                o.update = value
                    .parse()
                    .map_err(|_| format!("--update needs a number, got {value}"))?
            }
            "--ratio" => o.ratio = crate::number(value)?,
            "--speed" => o.speed = Some(crate::number(value)?),
            "--max-steps" => o.max_steps = crate::number(value)?,
            "--samples" => o.samples = crate::number(value)?,
            "--seed" => o.seed = crate::number(value)?,
            "--export" => o.export = Some(value.clone()),
            "--progress" => o.progress = crate::number(value)?,
            "--save-at" => {
                save_at = Some(if value == "end" {
                    None
                } else {
                    Some(crate::number(value)?)
                })
            }
            "--save" => save_to = Some(value.clone()),
            "--load" => o.load = Some(value.clone()),
            "--max-wall" => o.max_wall = Some(crate::number(value)?),
            "--full" => o.full = crate::number::<u8>(value)? != 0,
            "--dormant" => o.dormant = crate::number::<u8>(value)? != 0,
            "--joints" => {
                o.joints = match value.as_str() {
                    "open" => Joints::Open,
                    "closed" => Joints::Closed,
                    "jointed" => Joints::Jointed,
                    _ => return Err(format!("--joints is open, closed or jointed, got {value}")),
                }
            }
            other => return Err(format!("unknown option {other}")),
        }
    }
    o.save = match (save_at, save_to) {
        (Some(step), Some(path)) => Some((step, path)),
        (None, None) => None,
        _ => return Err("--save-at and --save go together".to_string()),
    };
    if o.blocks < 18 {
        return Err("--blocks must be at least 18 (one free block in its box)".to_string());
    }
    if o.threads == 0 || o.max_steps == 0 {
        return Err("--threads and --max-steps must be positive".to_string());
    }
    if !(o.ratio.is_finite() && o.ratio > 0.0) {
        return Err(format!("--ratio must be a number > 0, got {}", o.ratio));
    }
    if let Some(v) = o.speed {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("--speed must be a number > 0, got {v}"));
        }
    }
    Ok(o)
}

/// The joints of the model (`--joints`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Joints {
    /// Open 2 mm, the free blocks turned and shifted a little.
    Open,
    /// Closed, the blocks without face origins.
    Closed,
    /// Closed, the faces with the origins of three joint sets.
    Jointed,
}

/// The face origins of a unit cube of the closed grid whose lower corner is `lo` (integer
/// coordinates), in a box of `size` cubes along each axis: the origins a generation from
/// three joint sets of spacing 1 gives (set `a` for the planes normal to axis `a`, joint
/// numbers counted across the sets), the box's own faces its boundary.
fn grid_origins(block: &ConvexBlock, lo: DVec3, size: [usize; 3]) -> Vec<FaceOrigin> {
    block
        .planes()
        .iter()
        .map(|plane| {
            let axis = (0..3)
                .max_by(|&i, &j| plane.normal[i].abs().total_cmp(&plane.normal[j].abs()))
                .expect("three axes");
            let upper = plane.normal[axis] > 0.0;
            let at = lo[axis] as usize + usize::from(upper);
            if at == 0 || at == size[axis] {
                FaceOrigin::Boundary {
                    part: 0,
                    face: (2 * axis + usize::from(upper)) as u32,
                }
            } else {
                let before: usize = size[..axis].iter().map(|s| s - 1).sum();
                FaceOrigin::Joint {
                    set: axis as u32,
                    joint: (before + at - 1) as u32,
                }
            }
        })
        .collect()
}

/// The model: blocks and which are fixed.
struct Model {
    system: BlockSystem,
    fixed: Vec<bool>,
    /// Free blocks per side.
    n: usize,
}

/// Free blocks per side: the largest `n` with `(n + 2)^2 (n + 1) <= blocks`.
fn side(blocks: usize) -> usize {
    (1..)
        .take_while(|n| (n + 2) * (n + 2) * (n + 1) <= blocks)
        .last()
        .unwrap_or(1)
}

fn model(blocks: usize, seed: u64, joints: Joints) -> Model {
    let closed = joints != Joints::Open;
    let n = side(blocks);
    let spacing = if closed { 1.0 } else { SPACING };
    let (w, h) = (n + 2, n + 1);
    let unit = ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).expect("a unit cube");
    let mut rng = SplitMix64::new(seed);
    let mut blocks = Vec::with_capacity(w * w * h);
    let mut fixed = Vec::with_capacity(w * w * h);
    for k in 0..h {
        for j in 0..w {
            for i in 0..w {
                let wall = k == 0 || i == 0 || j == 0 || i == w - 1 || j == w - 1;
                let centre = DVec3::new(i as f64, j as f64, k as f64) * spacing + 0.5;
                let (turn, shift) = if wall || closed {
                    (DQuat::IDENTITY, DVec3::ZERO)
                } else {
                    let angle = rng.range(-TURN, TURN);
                    (
                        DQuat::from_axis_angle(rng.direction(), angle),
                        rng.point_in_cube(SHIFT),
                    )
                };
                let block = unit.transformed(turn, centre + shift, 1.0);
                let block = match joints {
                    Joints::Jointed => {
                        let lo = DVec3::new(i as f64, j as f64, k as f64);
                        let origins = grid_origins(&block, lo, [w, w, h]);
                        block.with_face_origins(origins).expect("one per face")
                    }
                    _ => block,
                };
                blocks.push(block);
                fixed.push(wall);
            }
        }
    }
    Model {
        system: BlockSystem::new(blocks),
        fixed,
        n,
    }
}

/// `mechanics`: prints the report.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    pool(o.threads)?.install(|| settle(&o))
}

/// Live heap bytes at the points of the run that the memory figures need.
struct Heap {
    before: isize,
    bodies: isize,
    contacts: isize,
    contacts_peak: isize,
}

fn settle(o: &Options) -> Result<(), String> {
    let m = model(o.blocks, o.seed, o.joints);
    let (bodies, free) = (m.system.len(), m.n * m.n * m.n);
    heap::count();
    let before = heap::live();
    let mut sim = Simulation::new(&m.system, DENSITY).map_err(|e| e.to_string())?;
    let after_new = heap::live();
    for (i, _) in m.fixed.iter().enumerate().filter(|(_, f)| **f) {
        sim.fix(i).map_err(|e| e.to_string())?;
    }
    sim.set_default_joint(JOINT).map_err(|e| e.to_string())?;
    if let Some(path) = &o.load {
        sim = Simulation::load_state(std::path::Path::new(path))
            .map_err(|e| format!("{path}: {e}"))?;
        if sim.bodies().len() != m.system.len() {
            return Err(format!(
                "{path}: {} bodies, the model of --blocks {} has {}",
                sim.bodies().len(),
                o.blocks,
                m.system.len()
            ));
        }
    }
    sim.set_full_detection(o.full);
    sim.set_dormant_contacts(o.dormant);
    sim.set_update_fraction(o.update)
        .map_err(|e| e.to_string())?;
    sim.set_damping(Damping {
        local: LOCAL_DAMPING,
        viscous: 0.0,
    })
    .map_err(|e| e.to_string())?;
    let dt = sim.timestep().map_err(|e| e.to_string())?;
    if let Some(path) = &o.export {
        std::fs::write(path, export(&m, dt, o.ratio, o.speed))
            .map_err(|e| format!("{path}: {e}"))?;
    }
    println!(
        "### Mechanics: {bodies} unit cubes ({free} free, {} fixed: floor and walls) settling \
         to an unbalanced-force ratio of {:e}, {} threads, {}\n\n{}; load average at the start: {}. \
         Time step {dt:.4e} s (automatic: 0.5 × critical).\n",
        bodies - free,
        o.ratio,
        o.threads,
        if o.full {
            "every candidate pair queried every step (--full 1)".to_string()
        } else {
            format!(
                "contact updates (answers kept for unmoved and certified pairs, touching \
                 pairs carried up to --update {} × the gap{})",
                o.update,
                if o.dormant {
                    ", open ones dormant while certified"
                } else {
                    "; --dormant 0: open ones updated"
                }
            )
        },
        crate::report::machine(),
        crate::report::load(),
    );
    let z0: Vec<f64> = free_ids(&m).map(|i| pose_z(&sim, i)).collect();
    if o.progress > 0 {
        println!(
            "progress: | step | simulated s | wall s | CPU s | fastest free block m/s | ratio | \
             mean settlement mm | kinetic energy of the free blocks J | contacts | sub-contacts |"
        );
    }
    let sample_every = (o.max_steps / o.samples.max(1)).max(1);
    let mut heap_at = Heap {
        before,
        bodies: after_new,
        contacts: 0,
        contacts_peak: 0,
    };
    let mut log = Run::default();
    let start = Instant::now();
    // The step the run starts from (that of a loaded restart file): rates count the steps
    // taken here.
    let first = sim.steps();
    let mut converged = false;
    // Whether a free block has been faster than the moving speed (for `--speed`).
    let mut moved = false;
    while sim.steps() < o.max_steps {
        if heap_at.contacts == 0 {
            heap::reset_peak();
        }
        let (t, cpu) = (Instant::now(), process_cpu_s());
        sim.step().map_err(|e| e.to_string())?;
        let s = t.elapsed().as_secs_f64();
        log.cpu_s += process_cpu_s() - cpu;
        if heap_at.contacts == 0 && !sim.contacts().list.is_empty() {
            heap_at.contacts = heap::live();
            heap_at.contacts_peak = heap::peak();
            log.first_contacts = (sim.contacts().list.len(), sim.contacts().subs.len());
        }
        let fastest = free_ids(&m)
            .map(|i| sim.bodies().velocities()[i].length())
            .fold(0.0, f64::max);
        let moving = fastest > MOVING;
        moved |= moving;
        log.record(s, moving);
        if sim.unbalanced_ratio() < o.ratio {
            converged = true;
            break;
        }
        if o.speed.is_some_and(|v| moved && fastest < v) {
            converged = true;
            log.settled_by_speed = true;
            break;
        }
        if let Some((Some(at), path)) = &o.save {
            if sim.steps() == *at {
                sim.save_state(std::path::Path::new(path))
                    .map_err(|e| format!("{path}: {e}"))?;
            }
        }
        if o.progress > 0 && sim.steps() % o.progress == 0 {
            progress(
                &sim,
                &m,
                &z0,
                start.elapsed().as_secs_f64(),
                log.cpu_s,
                fastest,
            );
        }
        if o.max_wall
            .is_some_and(|w| start.elapsed().as_secs_f64() > w)
        {
            break;
        }
        if o.samples > 0 && sim.steps() % sample_every == 0 {
            log.splits.push(split(&sim, &m, s));
        }
    }
    let wall = start.elapsed().as_secs_f64();
    if let Some((None, path)) = &o.save {
        sim.save_state(std::path::Path::new(path))
            .map_err(|e| format!("{path}: {e}"))?;
    }
    let settlement = mean_settlement(&sim, &m, &z0);
    let steps = sim.steps();
    let taken = steps - first;
    println!("| bodies | free | steps | converged | ratio | simulated s | wall s | steps/s | block-steps/s (all bodies) | CPU s | block-steps per CPU s | free-block-steps/s | moving steps | block-steps/s while moving | mean settlement mm | contacts | sub-contacts |");
    println!(
        "|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    println!(
        "| {bodies} | {free} | {steps} | {} | {:.2e} | {:.4} | {wall:.2} | {:.1} | {:.3e} | {:.2} | {:.3e} | {:.3e} | {} | {} | {:.4} | {} | {} |",
        match (converged, log.settled_by_speed) {
            (true, true) => "yes (speed)",
            (true, false) => "yes (ratio)",
            _ => "no",
        },
        sim.unbalanced_ratio(),
        sim.time(),
        taken as f64 / wall,
        (bodies as u64 * taken) as f64 / wall,
        log.cpu_s,
        (bodies as u64 * taken) as f64 / log.cpu_s,
        (free as u64 * taken) as f64 / wall,
        log.moving_steps,
        if log.moving_steps > 0 {
            format!("{:.3e}", (bodies as u64 * log.moving_steps) as f64 / log.moving_s)
        } else {
            "-".to_string()
        },
        settlement * 1e3,
        sim.contacts().list.len(),
        sim.contacts().subs.len(),
    );
    print_phases(&sim.timings(), bodies);
    let fastest = free_ids(&m)
        .map(|i| sim.bodies().velocities()[i].length())
        .fold(0.0, f64::max);
    let kinetic: f64 = free_ids(&m).map(|i| sim.bodies().kinetic_energy(i)).sum();
    println!(
        "\nAt the end: fastest free block {fastest:.3e} m/s, kinetic energy of the free blocks \
         {kinetic:.3e} J."
    );
    // Contacts that carry no force: every sub-contact open (a positive gap, no bond), as
    // the lateral joints open by less than the detection gap.
    let contacts = sim.contacts();
    let mut by_kind = std::collections::BTreeMap::<String, usize>::new();
    let (open, open_subs) = (0..contacts.list.len()).fold((0, 0), |(open, subs), i| {
        let n = contacts
            .subs_of(i)
            .iter()
            .filter(|s| s.gap > 0.0 && !s.bonded && s.normal_force == 0.0)
            .count();
        let all = n == contacts.list[i].count as usize;
        if all {
            *by_kind
                .entry(format!("{:?}", contacts.list[i].kind))
                .or_default() += 1;
        }
        (open + usize::from(all), subs + n)
    });
    let kinds: Vec<String> = by_kind.iter().map(|(k, n)| format!("{k} {n}")).collect();
    println!(
        "Open contacts (every sub-contact at a positive gap, unbonded, without force): {open} \
         of {} ({}); open sub-contacts {open_subs} of {}.",
        contacts.list.len(),
        kinds.join(", "),
        contacts.subs.len()
    );
    print_splits(&log.splits);
    print_memory(&heap_at, bodies, log.first_contacts);
    println!("\nLoad average at the end: {}.", crate::report::load());
    Ok(())
}

/// CPU time of the process, all threads, user and system (`getrusage`): under the load of a
/// shared machine, wall time also counts the time the threads wait for a core.
pub(crate) fn process_cpu_s() -> f64 {
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `usage` is a valid, writable rusage; RUSAGE_SELF is a constant Linux supports.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) };
    assert_eq!(rc, 0, "getrusage(RUSAGE_SELF) failed");
    let s = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    s(usage.ru_utime) + s(usage.ru_stime)
}

/// The mean fall of the free blocks since the start (m).
fn mean_settlement(sim: &Simulation, m: &Model, z0: &[f64]) -> f64 {
    free_ids(m)
        .zip(z0)
        .map(|(i, z)| z - pose_z(sim, i))
        .sum::<f64>()
        / z0.len() as f64
}

/// One progress line (`--progress`), flushed so that a stopped run keeps it.
fn progress(sim: &Simulation, m: &Model, z0: &[f64], wall: f64, cpu: f64, fastest: f64) {
    use std::io::Write as _;
    let kinetic: f64 = free_ids(m).map(|i| sim.bodies().kinetic_energy(i)).sum();
    println!(
        "progress: | {} | {:.4} | {wall:.1} | {cpu:.1} | {fastest:.3e} | {:.2e} | {:.4} | {kinetic:.3e} | {} | {} |",
        sim.steps(),
        sim.time(),
        sim.unbalanced_ratio(),
        mean_settlement(sim, m, z0) * 1e3,
        sim.contacts().list.len(),
        sim.contacts().subs.len(),
    );
    // A closed stdout is no reason to stop the run: the final table says the same.
    let _ = std::io::stdout().flush();
}

fn free_ids(m: &Model) -> impl Iterator<Item = usize> + '_ {
    m.fixed
        .iter()
        .enumerate()
        .filter(|(_, f)| !**f)
        .map(|(i, _)| i)
}

fn pose_z(sim: &Simulation, i: usize) -> f64 {
    sim.bodies().poses()[i].translation.z
}

/// Per-step times of the run.
#[derive(Default)]
struct Run {
    moving_steps: u64,
    moving_s: f64,
    /// CPU time of the process (all threads) in the steps.
    cpu_s: f64,
    /// Whether the run stopped on `--speed` rather than on the ratio.
    settled_by_speed: bool,
    first_contacts: (usize, usize),
    splits: Vec<Split>,
}

impl Run {
    fn record(&mut self, seconds: f64, moving: bool) {
        if moving {
            self.moving_steps += 1;
            self.moving_s += seconds;
        }
    }
}

/// The detection timed from outside on the poses of one step.
struct Split {
    step: u64,
    step_s: f64,
    broad_s: f64,
    query_s: f64,
    pairs: usize,
    contacts: usize,
    subs: usize,
}

fn split(sim: &Simulation, m: &Model, step_s: f64) -> Split {
    let placed = sim.placed_system();
    let blocks = placed.blocks();
    let tol = Tolerance::with_gap(GAP).expect("a valid gap");
    let mean = blocks.iter().map(ConvexBlock::size).sum::<f64>() / blocks.len() as f64;
    let half = 0.5 * SKIN * mean;
    let t = Instant::now();
    let boxes = WideBoxes::from_fn(blocks.len(), |k| {
        let aabb = blocks[k].aabb();
        (aabb, tol.for_box(&aabb).gap + half)
    });
    let pairs: Vec<[u32; 2]> = boxes
        .pairs(BroadPhase::default())
        .into_iter()
        .filter(|&[i, j]| !(m.fixed[i as usize] && m.fixed[j as usize]))
        .collect();
    let broad_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let contacts: usize = pairs
        .par_iter()
        .map_init(
            || Detector::new(tol),
            |det, &[i, j]| {
                let (r, g) = det.detect_with_geometry(&blocks[i as usize], &blocks[j as usize]);
                usize::from(matches!(r, PairResult::Contact(_)) && g.is_some())
            },
        )
        .sum();
    let query_s = t.elapsed().as_secs_f64();
    Split {
        step: sim.steps(),
        step_s,
        broad_s,
        query_s,
        pairs: pairs.len(),
        contacts,
        subs: sim.contacts().subs.len(),
    }
}

/// The step's own split (`Simulation::timings`: one clock reading per part and step).
fn print_phases(t: &StepTimings, bodies: usize) {
    let total = t.total();
    println!(
        "\nTime per part of the step (`Simulation::timings`, wall clock, summed over the {} \
         steps; {} broad phases built). Candidate pairs per step: {:.0} queried, {:.0} kept \
         unmoved, {:.0} kept certified separated, {:.0} carried ({:.0} of them dormant: \
         open contacts kept).\n",
        t.steps,
        t.rebuilds,
        t.queried as f64 / t.steps.max(1) as f64,
        t.unmoved as f64 / t.steps.max(1) as f64,
        t.certified as f64 / t.steps.max(1) as f64,
        t.carried as f64 / t.steps.max(1) as f64,
        t.dormant as f64 / t.steps.max(1) as f64,
    );
    println!("| part | s | share | per step ms | ns per block-step |");
    println!("|---|---:|---:|---:|---:|");
    let block_steps = (bodies as u64 * t.steps.max(1)) as f64;
    for (name, s) in [
        ("candidate pairs (travel check, broad phase)", t.pairs),
        ("pair queries (detection)", t.detect),
        ("sub-contacts and joint law", t.contacts),
        ("force sums", t.forces),
        ("integration", t.integration),
        ("placing moved blocks", t.placement),
        ("**total**", total),
    ] {
        println!(
            "| {name} | {s:.3} | {:.2} | {:.2} | {:.0} |",
            s / total,
            1e3 * s / t.steps.max(1) as f64,
            1e9 * s / block_steps
        );
    }
}

fn print_splits(splits: &[Split]) {
    if splits.is_empty() {
        return;
    }
    println!(
        "\nTime split, from outside on the poses after the step (the mechanics has no counters): \
         the step's wall time; the detection on the same poses: broad phase (rebuilt by the \
         step only when a block has moved half the skin) and the pair query with geometry on \
         the candidate pairs; the rest (sub-contacts, joint law, force sums, integration, \
         placing) = step - query.\n"
    );
    println!("| step | step s | broad phase s | pair queries s | query / step | rest s | candidate pairs | contacts | sub-contacts |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for s in splits {
        println!(
            "| {} | {:.4} | {:.4} | {:.4} | {:.2} | {:.4} | {} | {} | {} |",
            s.step,
            s.step_s,
            s.broad_s,
            s.query_s,
            s.query_s / s.step_s,
            (s.step_s - s.query_s).max(0.0),
            s.pairs,
            s.contacts,
            s.subs
        );
    }
}

fn print_memory(h: &Heap, bodies: usize, (contacts, subs): (usize, usize)) {
    println!(
        "\nMemory (live heap, counting allocator): `Simulation::new` adds {:.0} bytes per body \
         (its state, shape and placed copy of the block; the block system it is built from is \
         not counted). `size_of`: `BodyContact` {} bytes, `SubContact` {} bytes.",
        (h.bodies - h.before) as f64 / bodies as f64,
        std::mem::size_of::<BodyContact>(),
        std::mem::size_of::<SubContact>(),
    );
    if contacts > 0 {
        println!(
            "The first step with contacts ({contacts} contacts, {subs} sub-contacts, {:.2} per \
             contact) kept {:.0} bytes per contact (sub-contacts, candidate pairs and vector \
             slack included), {:.0} at its peak (the detection's answers before they become \
             contacts).",
            subs as f64 / contacts as f64,
            (h.contacts - h.bodies) as f64 / contacts as f64,
            (h.contacts_peak - h.bodies) as f64 / contacts as f64,
        );
    }
}

/// The model for `benches/yade/settle.py`.
fn export(m: &Model, dt: f64, ratio: f64, speed: Option<f64>) -> String {
    let mut s = String::new();
    let lines = [
        ("format", "penedge-bench mechanics 1".to_string()),
        ("dt", format!("{dt:?}")),
        ("kn", format!("{:?}", JOINT.kn)),
        ("ks", format!("{:?}", JOINT.ks)),
        ("friction_deg", format!("{:?}", JOINT.friction)),
        ("density", format!("{DENSITY:?}")),
        ("local_damping", format!("{LOCAL_DAMPING:?}")),
        ("gravity", "9.81".to_string()),
        ("ratio", format!("{ratio:?}")),
        ("moving", format!("{MOVING:?}")),
        // 0: no speed criterion.
        ("speed", format!("{:?}", speed.unwrap_or(0.0))),
        ("blocks", m.system.len().to_string()),
    ];
    for (k, v) in lines {
        writeln!(s, "{k} {v}").expect("writing to a String");
    }
    for (b, fixed) in m.system.blocks().iter().zip(&m.fixed) {
        write!(s, "{}", u8::from(*fixed)).expect("writing to a String");
        for v in b.vertices() {
            write!(s, " {:?} {:?} {:?}", v.x, v.y, v.z).expect("writing to a String");
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_side_is_the_largest_that_fits() {
        // (n + 2)^2 (n + 1): 18, 48, 100, ...; 46^2 * 45 = 95,220 <= 1e5 < 47^2 * 46.
        assert_eq!(side(18), 1);
        assert_eq!(side(47), 1);
        assert_eq!(side(48), 2);
        assert_eq!(side(100_000), 44);
    }

    #[test]
    fn closed_joints_put_every_block_exactly_on_the_unit_grid() {
        let m = model(100, 1, Joints::Closed);
        for (b, block) in m.system.blocks().iter().enumerate() {
            let (i, j, k) = (b % 5, (b / 5) % 5, b / 25);
            let lo = DVec3::new(i as f64, j as f64, k as f64);
            for v in block.vertices() {
                let d = *v - lo;
                for x in d.to_array() {
                    assert!(x == 0.0 || x == 1.0, "block {b}: corner {v:?}");
                }
            }
        }
    }

    #[test]
    fn jointed_faces_name_the_joint_plane_they_lie_in() {
        let m = model(100, 1, Joints::Jointed);
        let (w, h) = (5usize, 4usize);
        for (b, block) in m.system.blocks().iter().enumerate() {
            for (plane, origin) in block.planes().iter().zip(block.face_origins()) {
                // The plane's axis and its coordinate along it (an integer on the grid).
                let axis = (0..3).find(|&a| plane.normal[a].abs() == 1.0).unwrap();
                let at = plane.point[axis].round() as usize;
                let size = [w, w, h][axis];
                match *origin {
                    FaceOrigin::Boundary { face, .. } => {
                        assert!(at == 0 || at == size, "block {b}");
                        assert_eq!(face as usize / 2, axis);
                    }
                    FaceOrigin::Joint { set, joint } => {
                        assert_eq!(set as usize, axis, "block {b}");
                        // joints 0..4 normal to x (x = 1..4), 4..8 to y, 8..11 to z
                        let first = [0, w - 1, 2 * (w - 1)][axis];
                        assert_eq!(joint as usize, first + at - 1, "block {b}");
                    }
                    other => panic!("block {b}: {other:?}"),
                }
            }
        }
    }

    #[test]
    fn neighbouring_blocks_of_the_model_are_at_least_a_millimetre_apart() {
        let m = model(100, 1, Joints::Open);
        assert_eq!(m.system.len(), 5 * 5 * 4);
        assert_eq!(m.fixed.iter().filter(|f| !**f).count(), 27);
        // Along each axis, the extent of a block's corners ends at least 1 mm before its
        // neighbour's begins (the joints are 2 mm, the turn and the shift take < 1 mm).
        let (w, h) = (5, 4);
        let extent = |b: usize, axis: usize| {
            let c = m.system.blocks()[b].vertices().iter().map(|v| v[axis]);
            (
                c.clone().fold(f64::INFINITY, f64::min),
                c.fold(f64::NEG_INFINITY, f64::max),
            )
        };
        let id = |i: usize, j: usize, k: usize| i + w * (j + w * k);
        let mut checked = 0;
        for k in 0..h {
            for j in 0..w {
                for i in 0..w {
                    let next = [(i + 1, j, k), (i, j + 1, k), (i, j, k + 1)];
                    for (axis, (a, b, c)) in next.into_iter().enumerate() {
                        if a < w && b < w && c < h {
                            let (_, hi) = extent(id(i, j, k), axis);
                            let (lo, _) = extent(id(a, b, c), axis);
                            assert!(
                                lo - hi > 1e-3,
                                "blocks {i} {j} {k} along {axis}: {}",
                                lo - hi
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(checked, 3 * 5 * 5 * 4 - 5 * 5 - 2 * 5 * 4);
        let tol = Tolerance::with_gap(GAP).unwrap();
        assert!(m.system.detect(&tol).penetrating.is_empty());
    }
}
