//! Markdown output.

use crate::pairs::{Agreement, PairSet};
use crate::timing::Medians;

/// The machine, as `nproc` and the CPU model from `/proc/cpuinfo`.
pub fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".to_string());
    format!("{cores} logical CPUs available, {model}")
}

/// The 1, 5 and 15 minute load averages from `/proc/loadavg` (other work on the machine).
pub fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".to_string())
}

/// Header of the verification table.
pub fn agreement_header() -> String {
    "| situation | family | pairs | penedge as expected | parry `contact` as expected |\n|---|---|---:|---:|---:|".to_string()
}

/// One row of the verification table.
pub fn agreement_row(set: &PairSet, agree: &Agreement) -> String {
    format!(
        "| {} | {} | {} | {} | {} |",
        set.scenario.name,
        set.family.name(),
        set.len(),
        agree.penedge,
        agree.parry
    )
}

/// Header of a timing table.
pub fn timing_header() -> String {
    concat!(
        "| situation | family | penedge `detect` ns/pair | parry `contact` ns/pair | ratio parry/penedge ",
        "| parry `intersection_test` ns/pair | parry `contact`, `Cuboid` ns/pair |\n",
        "|---|---|---:|---:|---:|---:|---:|"
    )
    .to_string()
}

/// One row of a timing table.
pub fn timing_row(set: &PairSet, m: &Medians) -> String {
    let cuboid = m.parry_cuboid.map_or("n/a".to_string(), ns);
    format!(
        "| {} | {} | {} | {} | {:.1} | {} | {} |",
        set.scenario.name,
        set.family.name(),
        ns(m.penedge),
        ns(m.parry_contact),
        m.parry_contact / m.penedge,
        ns(m.parry_intersection),
        cuboid
    )
}

fn ns(t: f64) -> String {
    format!("{t:.0}")
}
