//! The `generate` subcommand: block generation speed and peak memory (issue 3).
//!
//! Two sizes, each in a child process of its own (`generate-one`) so that the peak memory
//! (`VmHWM` of `/proc/self/status`) belongs to that size alone:
//!
//! * **1e5**: the spec file (default `examples/three_joint_sets.toml`: three joint sets
//!   filling a 100 m cube, about 10^5 blocks);
//! * **1e6**: the same spec with every joint set's spacing divided by the cube root of 10,
//!   about ten times the blocks.
//!
//! Each child runs `generation::generate` several times (the spec parsed once, the output
//! dropped after each run) and reports the thread CPU time and the wall-clock time of each.

use crate::timing::{median, thread_cpu_ns};
use penedge::generation::{generate, JointKind, Spec};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Options of `generate`.
pub struct GenOptions {
    /// The spec file.
    spec: PathBuf,
    /// The spec file as shown in the output.
    shown: String,
    /// Runs of the ~1e5 size.
    runs: usize,
    /// Runs of the ~1e6 size.
    big_runs: usize,
    /// Whether the ~1e6 size is run at all.
    big: bool,
}

/// The default spec: the workspace's three-joint-set example.
fn default_spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/three_joint_sets.toml")
}

fn parse(args: &[String]) -> Result<GenOptions, String> {
    let mut o = GenOptions {
        spec: default_spec(),
        shown: "examples/three_joint_sets.toml".to_string(),
        runs: 7,
        big_runs: 3,
        big: true,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--spec" => {
                o.shown = value()?.clone();
                o.spec = PathBuf::from(&o.shown);
            }
            "--runs" => o.runs = crate::number(value()?)?,
            "--big-runs" => o.big_runs = crate::number(value()?)?,
            "--no-big" => o.big = false,
            other => return Err(format!("unknown option {other}")),
        }
    }
    if o.runs == 0 || o.big_runs == 0 {
        return Err("--runs and --big-runs must be positive".to_string());
    }
    Ok(o)
}

/// The two sizes: name, spacing divisor.
const SIZES: [(&str, f64); 2] = [("1e5", 1.0), ("1e6", 2.154_434_690_031_884)];

/// What one child measured.
struct Measured {
    blocks: usize,
    planes: usize,
    volume_error: f64,
    retried: usize,
    cpu_s: Vec<f64>,
    sys_s: Vec<f64>,
    wall_s: Vec<f64>,
    hwm_before_kib: u64,
    hwm_kib: u64,
}

/// `generate`: runs each size in a child process and prints the table.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    println!("## Block generation\n");
    println!(
        "Spec {}; single thread; {}. Load average at the start: {}.\n",
        o.shown,
        crate::report::machine(),
        crate::report::load()
    );
    println!(
        "| size | spacing | joint planes | blocks | runs | first run: CPU s (kernel s) | blocks/s | median: CPU s (kernel s) \
         | wall s | blocks/s | peak memory (VmHWM) | before generation \
         | peak per block | volume error |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let spacing = first_spacing(&read(&o.spec)?);
    for (k, (name, divisor)) in SIZES.iter().enumerate() {
        if k == 1 && !o.big {
            continue;
        }
        let runs = if k == 0 { o.runs } else { o.big_runs };
        let out = Command::new(&exe)
            .arg("generate-one")
            .arg(&o.spec)
            .arg(divisor.to_string())
            .arg(runs.to_string())
            .output()
            .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
        if !out.status.success() {
            return Err(format!(
                "size {name} failed: {}",
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        let mut m = parse_measured(&String::from_utf8_lossy(&out.stdout))?;
        let (first, first_sys) = (m.cpu_s[0], m.sys_s[0]);
        let cpu = median(&mut m.cpu_s);
        let sys = median(&mut m.sys_s);
        let wall = median(&mut m.wall_s);
        let extra = m.hwm_kib.saturating_sub(m.hwm_before_kib) as f64 * 1024.0;
        println!(
            "| {name} | {} | {} | {} | {runs} | {first:.3} ({first_sys:.3}) | {:.0} | {cpu:.3} ({sys:.3}) | {wall:.3} | {:.0} | {} | {} | {:.0} B | {:.1e} |",
            spacing.map_or("n/a".to_string(), |s| format!("{:.4}", s / divisor)),
            m.planes,
            m.blocks,
            m.blocks as f64 / first,
            m.blocks as f64 / cpu,
            mib(m.hwm_kib),
            mib(m.hwm_before_kib),
            extra / m.blocks as f64,
            m.volume_error
        );
        if m.retried > 0 {
            eprintln!("size {name}: {} cuts retried", m.retried);
        }
    }
    println!("\nLoad average at the end: {}.", crate::report::load());
    Ok(())
}

fn mib(kib: u64) -> String {
    format!("{:.0} MiB", kib as f64 / 1024.0)
}

fn read(path: &Path) -> Result<Spec, String> {
    penedge::io::spec::read_spec(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The spacing of the first joint set, if all sets share it (for the table).
fn first_spacing(spec: &Spec) -> Option<f64> {
    let spacings: Vec<f64> = spec
        .joints
        .iter()
        .filter_map(|j| match &j.kind {
            JointKind::Set(set) => Some(set.spacing),
            _ => None,
        })
        .collect();
    let first = *spacings.first()?;
    spacings.iter().all(|&s| s == first).then_some(first)
}

/// `generate-one SPEC DIVISOR RUNS` (the child): prints one `key value` per line.
pub fn run_one(args: &[String]) -> Result<(), String> {
    let [spec, divisor, runs] = args else {
        return Err("usage: penedge-bench generate-one SPEC DIVISOR RUNS".to_string());
    };
    let divisor: f64 = crate::number(divisor)?;
    let runs: usize = crate::number(runs)?;
    let mut spec = read(Path::new(spec))?;
    for joint in &mut spec.joints {
        if let JointKind::Set(set) = &mut joint.kind {
            set.spacing /= divisor;
        }
    }
    println!("hwm_before_kib {}", vm_hwm_kib()?);
    for _ in 0..runs {
        let (wall, cpu, sys) = (Instant::now(), thread_cpu_ns(), thread_sys_s());
        let out = generate(&spec).map_err(|e| e.to_string())?;
        let cpu_s = (thread_cpu_ns() - cpu) as f64 * 1e-9;
        let sys_s = thread_sys_s() - sys;
        let wall_s = wall.elapsed().as_secs_f64();
        println!("cpu_s {cpu_s}");
        println!("sys_s {sys_s}");
        println!("wall_s {wall_s}");
        println!("blocks {}", out.system.len());
        println!("planes {}", out.report.joint_planes);
        println!("volume_error {}", out.report.volume_error);
        println!("retried {}", out.report.retried_cuts);
        drop(std::hint::black_box(out));
    }
    println!("hwm_kib {}", vm_hwm_kib()?);
    Ok(())
}

fn parse_measured(text: &str) -> Result<Measured, String> {
    let mut m = Measured {
        blocks: 0,
        planes: 0,
        volume_error: 0.0,
        retried: 0,
        cpu_s: Vec::new(),
        sys_s: Vec::new(),
        wall_s: Vec::new(),
        hwm_before_kib: 0,
        hwm_kib: 0,
    };
    for line in text.lines() {
        let (key, value) = line
            .split_once(' ')
            .ok_or(format!("bad line from the child: {line}"))?;
        match key {
            "cpu_s" => m.cpu_s.push(crate::number(value)?),
            "wall_s" => m.wall_s.push(crate::number(value)?),
            "sys_s" => m.sys_s.push(crate::number(value)?),
            "blocks" => m.blocks = crate::number(value)?,
            "planes" => m.planes = crate::number(value)?,
            "volume_error" => m.volume_error = crate::number(value)?,
            "retried" => m.retried = m.retried.max(crate::number(value)?),
            "hwm_before_kib" => m.hwm_before_kib = crate::number(value)?,
            "hwm_kib" => m.hwm_kib = crate::number(value)?,
            _ => return Err(format!("unknown key from the child: {key}")),
        }
    }
    Ok(m)
}

/// System (kernel) CPU time of the calling thread so far, in seconds (`getrusage`,
/// `RUSAGE_THREAD`): page faults of fresh memory land here.
fn thread_sys_s() -> f64 {
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `usage` is a valid, writable rusage; RUSAGE_THREAD is supported by Linux.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut usage) };
    assert_eq!(rc, 0, "getrusage(RUSAGE_THREAD) failed");
    usage.ru_stime.tv_sec as f64 + usage.ru_stime.tv_usec as f64 * 1e-6
}

/// The peak resident set size of this process so far (`VmHWM`, KiB).
pub(crate) fn vm_hwm_kib() -> Result<u64, String> {
    let status = std::fs::read_to_string("/proc/self/status").map_err(|e| e.to_string())?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| "no VmHWM in /proc/self/status".to_string())
}
