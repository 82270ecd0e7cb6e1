//! Timing loops: in each round every engine runs over a window of a set's pairs, the engines
//! and the sets taking turns; the median of the rounds is kept. Times are CPU time of the
//! benchmark thread.

use crate::family::Family;
use crate::pairs::{unit_cuboid, PairSet, ParryPair};
use parry3d_f64::query::{contact, intersection_test};
use penedge::{ConvexBlock, Detector};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Median nanoseconds per pair of each engine on one job.
#[derive(Clone, Copy, Debug)]
pub struct Medians {
    /// penedge `Detector::detect`, one detector reused.
    pub penedge: f64,
    /// parry `contact` on `ConvexPolyhedron`s.
    pub parry_contact: f64,
    /// parry `intersection_test` on `ConvexPolyhedron`s.
    pub parry_intersection: f64,
    /// parry `contact` on `Cuboid`s (unit cubes only).
    pub parry_cuboid: Option<f64>,
}

/// Which pairs a timing round visits: the first `len` pairs of a set, `loops` times over,
/// after an untimed pass when `warm`.
///
/// The rounds of all jobs take turns (see [`measure`]), so the data of one job has left the
/// caches by its next round. With every pair once and no warm-up pass, each query meets
/// blocks that come from main memory ("cold"); with a few hundred pairs, a warm-up pass and
/// several passes, the blocks stay in the core's L2 cache ("hot").
#[derive(Clone, Copy, Debug)]
pub struct Window {
    /// Number of pairs from the start of the set.
    pub len: usize,
    /// Timed passes over them per round.
    pub loops: usize,
    /// Whether an untimed pass comes first.
    pub warm: bool,
}

impl Window {
    /// Every pair of the set once.
    pub fn cold(set: &PairSet) -> Self {
        Window {
            len: set.len(),
            loops: 1,
            warm: false,
        }
    }

    /// The first `len` pairs, warmed up, then looped so that a round makes about as many
    /// queries as a cold round.
    pub fn hot(set: &PairSet, len: usize) -> Self {
        let len = len.clamp(1, set.len());
        Window {
            len,
            loops: set.len().div_ceil(len),
            warm: true,
        }
    }
}

/// One set timed through one window.
#[derive(Clone, Copy)]
pub struct Job<'a> {
    /// The pairs.
    pub set: &'a PairSet,
    /// Which of them, how often.
    pub window: Window,
}

/// Times every job `reps` times (after one warm-up round) and keeps the medians, one per job.
///
/// The rounds go job after job, repetition after repetition, so the samples of each job
/// are spread over the whole run and a burst of load from other processes on the shared
/// machine spoils a few samples of every job rather than all samples of one.
pub fn measure(jobs: &[Job], reps: usize) -> Vec<Medians> {
    let mut detector = Detector::default();
    let medians = median_rounds(jobs, reps, |job| round(job, &mut detector));
    jobs.iter()
        .zip(medians)
        .map(|(job, [pe, pc, pi, cu])| Medians {
            penedge: pe,
            parry_contact: pc,
            parry_intersection: pi,
            parry_cuboid: (job.set.family == Family::Cube).then_some(cu),
        })
        .collect()
}

/// Runs `round` on every job `reps` times (after one warm-up round), job after job,
/// repetition after repetition, and returns the median of each of its `N` timings (ns per
/// pair) per job.
pub fn median_rounds<const N: usize>(
    jobs: &[Job],
    reps: usize,
    mut round: impl FnMut(&Job) -> [f64; N],
) -> Vec<[f64; N]> {
    let mut samples: Vec<[Vec<f64>; N]> = (0..jobs.len())
        .map(|_| std::array::from_fn(|_| Vec::with_capacity(reps)))
        .collect();
    for rep in 0..=reps {
        for (job, s) in jobs.iter().zip(&mut samples) {
            let times = round(job);
            if rep > 0 {
                s.iter_mut().zip(times).for_each(|(s, t)| s.push(t));
            }
        }
    }
    samples
        .iter_mut()
        .map(|s| std::array::from_fn(|i| median(&mut s[i])))
        .collect()
}

/// One round of each engine over the job's window: ns per pair (NaN for the `Cuboid`
/// variant when the blocks are not unit cubes).
fn round(job: &Job, detector: &mut Detector) -> [f64; 4] {
    let w = job.window;
    let (blocks, parry) = (&job.set.blocks[..w.len], &job.set.parry[..w.len]);
    [
        timed(w, || penedge_round(detector, blocks)),
        timed(w, || parry_contact_round(parry)),
        timed(w, || parry_intersection_round(parry)),
        if job.set.family == Family::Cube {
            timed(w, || parry_cuboid_round(parry))
        } else {
            f64::NAN
        },
    ]
}

/// Runs `pass` over the window (untimed first if warm) and returns ns per pair, in CPU time
/// of this thread.
pub fn timed(w: Window, mut pass: impl FnMut()) -> f64 {
    if w.warm {
        pass();
    }
    let start = thread_cpu_ns();
    (0..w.loops).for_each(|_| pass());
    (thread_cpu_ns() - start) as f64 / (w.len * w.loops) as f64
}

/// CPU time of the calling thread, in ns (`CLOCK_THREAD_CPUTIME_ID`): unlike wall-clock
/// time it leaves out the time the thread waits while other processes run on the shared
/// cores (their effect on the caches stays in).
pub fn thread_cpu_ns() -> i128 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant Linux supports.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as i128 * 1_000_000_000 + ts.tv_nsec as i128
}

/// Runs penedge over the set again and again for about `duration` (for a profiler), with
/// `detect_with_geometry` when `geometry`; returns the number of pairs detected.
pub fn spin_penedge(set: &PairSet, duration: Duration, geometry: bool) -> usize {
    let mut detector = Detector::new(set.tolerance);
    let start = Instant::now();
    let mut count = 0;
    // At least one round (`--seconds 0`: exactly one, for instruction counts).
    loop {
        if geometry {
            for (a, b) in &set.blocks {
                black_box(detector.detect_with_geometry(black_box(a), black_box(b)));
            }
        } else {
            penedge_round(&mut detector, &set.blocks);
        }
        count += set.len();
        if start.elapsed() >= duration {
            break count;
        }
    }
}

#[inline(never)] // a symbol of its own for profilers (instructions per pair)
fn penedge_round(detector: &mut Detector, blocks: &[(ConvexBlock, ConvexBlock)]) {
    for (a, b) in blocks {
        black_box(detector.detect(black_box(a), black_box(b)));
    }
}

fn parry_contact_round(pairs: &[ParryPair]) {
    for p in pairs {
        let p = black_box(p);
        black_box(contact(&p.pose_a, &p.a, &p.pose_b, &p.b, p.prediction).ok());
    }
}

fn parry_intersection_round(pairs: &[ParryPair]) {
    for p in pairs {
        let p = black_box(p);
        black_box(intersection_test(&p.pose_a, &p.a, &p.pose_b, &p.b).ok());
    }
}

fn parry_cuboid_round(pairs: &[ParryPair]) {
    let cube = unit_cuboid();
    for p in pairs {
        let p = black_box(p);
        black_box(contact(&p.pose_a, &cube, &p.pose_b, &cube, p.prediction).ok());
    }
}

/// The median (NaN samples sort last; the `Cuboid` column of rock sets is all NaN).
pub fn median(samples: &mut [f64]) -> f64 {
    samples.sort_by(f64::total_cmp);
    let m = samples.len() / 2;
    if samples.len() % 2 == 1 {
        samples[m]
    } else {
        0.5 * (samples[m - 1] + samples[m])
    }
}
