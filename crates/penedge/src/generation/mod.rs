//! Block generation: a rock domain cut into convex blocks by joint planes, joint sets and
//! finite joints (see `docs/generation.md`).
//!
//! The pipeline reads as the algorithm:
//!
//! 1. plan (`expand.rs`): check the spec (each error names its field) and expand it into
//!    the joint table, every plane in the order it is applied (sets laid out along their
//!    normal with their random deviations; planes that miss the domain and duplicate planes
//!    are errors);
//! 2. cut: each plane descends the cutting tree (`tree.rs`) into the blocks whose bounding
//!    box it crosses and splits those it crosses ([`crate::cutting`]); a finite joint splits a
//!    block only where it crosses it completely, and counts the blocks it ends inside;
//! 3. slivers: blocks below the minimum volume or thickness are kept or dropped, and counted
//!    either way;
//! 4. the [`BlockSystem`] with its domain, joint table and face origins, and a
//!    [`GenerationReport`].
//!
//! Axes: x East, y North, z up; see [`orientation`] for dip and dip direction.
//!
//! ```
//! use penedge::generation::{generate, Discontinuity, Domain, JointSet, Orientation, Spec};
//! let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap())
//!     .with(Discontinuity::set(JointSet::new(Orientation::dip(0.0, 0.0), 2.5)))
//!     .with(Discontinuity::plane([5.0, 5.0, 5.0], Orientation::dip(90.0, 90.0)));
//! let out = generate(&spec).unwrap();
//! assert_eq!(out.system.len(), 8); // 4 layers (planes at z = 2.5, 5, 7.5), split at x = 5
//! assert!(out.report.volume_error < 1e-12);
//! ```

mod check;
mod domain;
mod duplicates;
mod error;
mod expand;
mod finite;
pub mod orientation;
mod record;
mod report;
pub mod rng;
mod spec;
mod stats;
mod tree;

pub use crate::block::FaceOrigin;
pub use domain::Domain;
pub use error::{GenerationError, Problem, SpecError};
pub use orientation::{Attitude, Frame};
pub use record::{upward, JointRecord, JointShape, SetKind, SetRecord};
pub use report::{thickness, GenerationReport, SliverReport};
pub use spec::{
    Deviation, Discontinuity, JointKind, JointSet, Options, Orientation, SliverPolicy, Spec,
    DEFAULT_MIN_THICKNESS, MAX_PLANES,
};
pub use stats::{distribution_curve, BlockStatistics, DistributionPoint};

use crate::system::BlockSystem;
use tree::{CutCounts, CuttingTree};

/// A generated block system and what generation did.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The blocks, with the domain, joint table and face origins.
    pub system: BlockSystem,
    /// Counts, slivers, volume check.
    pub report: GenerationReport,
}

/// Progress of a run, reported after each joint plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Planes applied so far.
    pub planes_done: usize,
    /// Planes in all.
    pub planes_total: usize,
    /// Blocks so far.
    pub blocks: usize,
}

/// Generates the block system of a spec.
pub fn generate(spec: &Spec) -> Result<Generated, GenerationError> {
    generate_with_progress(spec, &mut |_| {})
}

/// [`generate`], calling `progress` after each joint plane (for progress bars).
pub fn generate_with_progress(
    spec: &Spec,
    progress: &mut dyn FnMut(Progress),
) -> Result<Generated, GenerationError> {
    let plan = expand::plan(spec)?;
    let mut tree = CuttingTree::new(spec.domain.parts(), plan.eps);
    let mut counts = CutCounts::default();
    let mut partial = vec![0; plan.sets.len()];
    for (done, j) in cut_order(&plan.records).into_iter().enumerate() {
        let record = &plan.records[j];
        let before = counts.partial;
        tree.cut(record, j as u32, &mut counts)?;
        partial[record.set as usize] += counts.partial - before;
        progress(Progress {
            planes_done: done + 1,
            planes_total: plan.records.len(),
            blocks: tree.len(),
        });
    }
    let (blocks, slivers) =
        report::sort_slivers(tree.into_blocks(), &spec.options, spec.domain.size());
    let report = GenerationReport {
        partial_cuts_by_entry: partial,
        ..report::summarise(&blocks, spec.domain.volume(), &plan, &counts, slivers)
    };
    let domain = spec.domain.parts().to_vec();
    let system = BlockSystem::with_provenance(blocks, domain, plan.records, plan.sets)
        .with_unit(spec.unit.clone());
    Ok(Generated { system, report })
}

/// The number of joint planes a spec makes (checked and expanded, nothing cut): to bound
/// the work before [`generate`] (the fuzz targets do).
pub(crate) fn planned_planes(spec: &Spec) -> Result<usize, SpecError> {
    Ok(expand::plan(spec)?.records.len())
}

/// Cuts the domain by infinite planes (no checks, no slivers: for
/// [`BlockSystem::from_domain_cut`]); the faces get origin `Joint { set, joint: i }`.
pub(crate) fn cut_domain(
    domain: &Domain,
    joints: &[JointRecord],
    eps: f64,
) -> Result<Vec<crate::block::ConvexBlock>, GenerationError> {
    let mut tree = CuttingTree::new(domain.parts(), eps);
    let mut counts = CutCounts::default();
    for j in cut_order(joints) {
        tree.cut(&joints[j], j as u32, &mut counts)?;
    }
    Ok(tree.into_blocks())
}

/// The order in which the joint table is applied: entries in spec order; within a joint set
/// (infinite planes, which commute) middle plane first, then the middles of the halves, and
/// so on, so that the cutting tree stays balanced (depth `log n`, not `n`).
fn cut_order(joints: &[JointRecord]) -> Vec<usize> {
    let mut order = Vec::with_capacity(joints.len());
    let mut start = 0;
    while start < joints.len() {
        let same = |r: &JointRecord| r.set == joints[start].set && !r.is_finite();
        let run = joints[start..]
            .iter()
            .take_while(|r| same(r))
            .count()
            .max(1);
        let mut queue = std::collections::VecDeque::from([(start, start + run)]);
        while let Some((lo, hi)) = queue.pop_front() {
            if lo < hi {
                let mid = lo + (hi - lo) / 2;
                order.push(mid);
                queue.extend([(lo, mid), (mid + 1, hi)]);
            }
        }
        start += run;
    }
    order
}
