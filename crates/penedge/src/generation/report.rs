//! What generation did: counts for the user, slivers never silently kept or dropped.

use super::expand::Plan;
use super::spec::{Options, SliverPolicy, DEFAULT_MIN_THICKNESS};
use super::tree::CutCounts;
use crate::block::ConvexBlock;

/// The report of one generation run.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GenerationReport {
    /// Blocks in the system.
    pub blocks: usize,
    /// Joint planes applied (the joint table's length).
    pub joint_planes: usize,
    /// Blocks split.
    pub splits: usize,
    /// Finite joints that ended inside a block, which was left whole (block-joint pairs).
    pub partial_cuts_skipped: usize,
    /// The same, per spec entry.
    pub partial_cuts_by_entry: Vec<usize>,
    /// Finite joints with rock bridges that ended inside a block, which was cut through
    /// (block-joint pairs; docs/generation.md, "Rock bridges").
    #[serde(default)]
    pub bridged_cuts: usize,
    /// Planes of joint sets with a given number that miss the domain, left out.
    pub set_planes_outside: usize,
    /// Cuts redone with exact signs because the pieces did not close with the length
    /// threshold (degenerate positions within the tolerance of a vertex or edge).
    pub retried_cuts: usize,
    /// Volume of the domain.
    pub domain_volume: f64,
    /// Total volume of the blocks kept.
    pub block_volume: f64,
    /// `|kept + dropped - domain| / domain`: the cutting's volume error.
    pub volume_error: f64,
    /// Slivers found.
    pub slivers: SliverReport,
    /// Blocks tiny beside the system's typical block (whatever the sliver limits).
    #[serde(default)]
    pub tiny: TinyReport,
    /// Volume removed by the spec's excavations, applied after the joints and the slivers:
    /// `blocks` and `block_volume` count the blocks (convex parts) left, `volume_error` and
    /// the sliver and tiny reports are the joints' cut, before excavation (block ids there
    /// are those before excavation).
    #[serde(default)]
    pub excavated_volume: f64,
    /// The bodies left by the excavations that are slivers, by the limits and policy of
    /// `slivers` (an excavation's boundary near a joint, or a profile's vertex, can leave a
    /// piece far thinner than any the joints cut).
    #[serde(default)]
    pub excavation_slivers: ExcavationSlivers,
}

/// The bodies left by a spec's excavations that are slivers (a body is one when its volume
/// is below the minimum volume or its [`body_thickness`] below the minimum thickness): kept
/// and listed, or dropped, by the spec's sliver policy, counted either way.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExcavationSlivers {
    /// Sliver bodies found (kept or dropped).
    pub count: usize,
    /// Their total volume.
    pub volume: f64,
    /// Body ids, in the system returned, of the sliver bodies kept (empty when dropped): the
    /// slivers are found before the rock bridges glue pieces into bodies (each piece is a
    /// rigid body of its own in a simulation), so a sliver piece a bridge glues to more rock
    /// is listed by the body it is glued into.
    pub kept_bodies: Vec<u32>,
}

/// Blocks whose volume is below [`TINY_SHARE`] of the median block volume: a spec's
/// sliver limits are absolute (by default 1e-6 of the domain's size, thinner than which a
/// block is a sliver), so a block millimetres across in a system of metre blocks passes
/// them, yet it sets a DEM model's time step. They are counted, never dropped.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TinyReport {
    /// The median volume of the blocks kept.
    pub median_volume: f64,
    /// The volume below which a block is tiny: [`TINY_SHARE`] of the median.
    pub threshold: f64,
    /// Tiny blocks.
    pub count: usize,
    /// The smallest block volume (0 when there is no block).
    pub smallest: f64,
}

/// A block is tiny below this share of the median block volume (a tenth of its size).
pub const TINY_SHARE: f64 = 1e-3;

impl TinyReport {
    /// The tiny blocks of `blocks`.
    pub fn of(blocks: &[ConvexBlock]) -> TinyReport {
        let mut volumes: Vec<f64> = blocks.iter().map(ConvexBlock::volume).collect();
        if volumes.is_empty() {
            return TinyReport::default();
        }
        // The usual median: the middle value of an odd count, the mean of the two middle
        // values of an even one (it was the upper of the two: 3 for volumes 1 and 3).
        let n = volumes.len();
        let (below, &mut upper, _) = volumes.select_nth_unstable_by(n / 2, f64::total_cmp);
        let median = if n.is_multiple_of(2) {
            let lower = below.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            lower / 2.0 + upper / 2.0
        } else {
            upper
        };
        let threshold = TINY_SHARE * median;
        TinyReport {
            median_volume: median,
            threshold,
            count: volumes.iter().filter(|&&v| v < threshold).count(),
            smallest: volumes.iter().copied().fold(f64::INFINITY, f64::min),
        }
    }
}

/// Slivers: blocks below the minimum volume or thickness.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SliverReport {
    /// Keep or drop.
    pub policy: SliverPolicy,
    /// The minimum volume used.
    pub min_volume: f64,
    /// The minimum thickness used.
    pub min_thickness: f64,
    /// Slivers found (kept or dropped).
    pub count: usize,
    /// Their total volume.
    pub volume: f64,
    /// Ids of the slivers kept in the system (empty when dropped).
    pub kept_ids: Vec<u32>,
}

/// Thickness of a convex block: the smallest, over its faces, of the distance from the face
/// plane to the farthest vertex (the width across that face; an upper bound of the true
/// minimum width, equal to it for blocks between parallel faces).
pub fn thickness(block: &ConvexBlock) -> f64 {
    block
        .planes()
        .iter()
        .map(|plane| {
            block
                .vertices()
                .iter()
                .map(|&v| -plane.distance(v))
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Finds the slivers among `blocks`, keeps or drops them as asked, and reports them.
pub(crate) fn sort_slivers(
    blocks: Vec<ConvexBlock>,
    options: &Options,
    domain_size: f64,
) -> (Vec<ConvexBlock>, SliverReport) {
    let mut report = SliverReport {
        policy: options.slivers,
        min_volume: options.min_volume,
        min_thickness: options
            .min_thickness
            .unwrap_or(DEFAULT_MIN_THICKNESS * domain_size),
        ..SliverReport::default()
    };
    let mut kept = Vec::with_capacity(blocks.len());
    for block in blocks {
        let sliver = block.volume() < report.min_volume || thickness(&block) < report.min_thickness;
        if sliver {
            report.count += 1;
            report.volume += block.volume();
            if options.slivers == SliverPolicy::Drop {
                continue;
            }
            report.kept_ids.push(kept.len() as u32);
        }
        kept.push(block);
    }
    (kept, report)
}

/// The thickness of a body of convex parts: the largest of its parts' [`thickness`] (a
/// body is at least as wide, in every direction, as each of its parts; for a convex body,
/// the block's own thickness).
pub fn body_thickness(parts: &[&ConvexBlock]) -> f64 {
    parts.iter().map(|p| thickness(p)).fold(0.0, f64::max)
}

/// Finds the sliver bodies of `system` (the blocks left by a spec's excavations) by the
/// limits and policy of `limits` (the joints' cut's report): a body is a sliver when its
/// volume is below the minimum volume or its thickness ([`body_thickness`]) below the
/// minimum thickness. Dropped, every part of each is removed (the other bodies keep their
/// glue; body ids renumbered `0..` in the order of each body's first part); kept, the ids
/// of their parts are returned (the report's `kept_bodies` is left to the caller, whose
/// bodies may still change: the bridges' glue).
pub(crate) fn sort_sliver_bodies(
    system: crate::system::BlockSystem,
    limits: &SliverReport,
) -> (crate::system::BlockSystem, ExcavationSlivers, Vec<u32>) {
    let mut report = ExcavationSlivers::default();
    let (mut bodies, mut parts_of_slivers) = (Vec::new(), Vec::new());
    for (body, parts) in system.body_parts() {
        let blocks: Vec<&ConvexBlock> = parts
            .iter()
            .map(|&k| &system.blocks()[k as usize])
            .collect();
        let volume: f64 = blocks.iter().map(|p| p.volume()).sum();
        if volume < limits.min_volume || body_thickness(&blocks) < limits.min_thickness {
            report.count += 1;
            report.volume += volume;
            bodies.push(body);
            parts_of_slivers.extend(parts);
        }
    }
    match limits.policy {
        SliverPolicy::Keep => (system, report, parts_of_slivers),
        SliverPolicy::Drop if bodies.is_empty() => (system, report, Vec::new()),
        SliverPolicy::Drop => (system.without_bodies(&bodies), report, Vec::new()),
    }
}

/// The report of a run (without the per-entry partial counts).
pub(crate) fn summarise(
    blocks: &[ConvexBlock],
    domain_volume: f64,
    plan: &Plan,
    counts: &CutCounts,
    slivers: SliverReport,
) -> GenerationReport {
    let block_volume: f64 = blocks.iter().map(|b| b.volume()).sum();
    let dropped = match slivers.policy {
        SliverPolicy::Drop => slivers.volume,
        SliverPolicy::Keep => 0.0,
    };
    GenerationReport {
        blocks: blocks.len(),
        joint_planes: plan.records.len(),
        splits: counts.splits,
        partial_cuts_skipped: counts.partial,
        partial_cuts_by_entry: Vec::new(),
        bridged_cuts: counts.bridged,
        set_planes_outside: plan.outside,
        retried_cuts: counts.retried,
        domain_volume,
        block_volume,
        volume_error: (block_volume + dropped - domain_volume).abs() / domain_volume,
        slivers,
        tiny: TinyReport::of(blocks),
        excavated_volume: 0.0,
        excavation_slivers: ExcavationSlivers::default(),
    }
}
