//! Block generation: a rock domain cut into convex blocks by joint planes, joint sets and
//! finite joints (see `docs/generation.md`).
//!
//! The pipeline reads as the algorithm:
//!
//! 1. plan (`expand.rs`): check the spec (each error names its field) and expand it into
//!    the joint table, every plane in the order it is applied (sets laid out along their
//!    normal with their random deviations; planes that miss the domain and duplicate planes
//!    are errors);
//! 2. estimate (`work.rs`): the blocks the arrangement of the planes makes; a spec whose
//!    estimate passes the run's [`Limits`] (by default what half the memory available
//!    holds) is refused before anything is cut;
//! 3. cut: each plane descends the cutting tree (`tree.rs`) into the blocks whose bounding
//!    box it crosses and splits those it crosses ([`crate::cutting`]); a finite joint splits a
//!    block only where it crosses it completely, and counts the blocks it ends inside;
//!    A run stops once it makes more blocks than its limit, and between two planes when
//!    its progress callback says so ([`generate_with`]);
//! 4. slivers: blocks below the minimum volume or thickness are kept or dropped, and counted
//!    either way;
//! 5. the [`BlockSystem`] with its domain, joint table and face origins, and a
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

pub(crate) mod check;
mod domain;
mod duplicates;
mod error;
mod excavation;
mod expand;
mod finite;
pub mod orientation;
mod record;
mod report;
pub mod rng;
mod slope;
mod spec;
mod stats;
mod topography;
mod tree;
mod work;

pub use crate::block::FaceOrigin;
pub use check::{MAX_UNIT_CHARS, NAME_SEPARATOR};
pub use domain::Domain;
pub use error::{GenerationError, Problem, SpecError};
pub use excavation::{Excavation, ExcavationShape, Profile, MAX_SEGMENTS};
pub use orientation::{Attitude, Frame};
pub use record::{upward, JointRecord, JointShape, SetKind, SetRecord};
pub use report::{
    body_thickness, thickness, ExcavationSlivers, GenerationReport, SliverReport, TinyReport,
    TINY_SHARE,
};
pub(crate) use slope::Extent;
pub use slope::MAX_PROFILE_VERTICES;
pub use spec::{
    Deviation, Discontinuity, JointKind, JointSet, Options, Orientation, SliverPolicy, Spec,
    DEFAULT_MIN_THICKNESS, MAX_PLANES,
};
pub use stats::{distribution_curve, BlockStatistics, DistributionPoint};
pub use topography::{Surface, MAX_TRIANGLES};
pub use work::{available_memory, Estimate, Limits, BYTES_PER_BLOCK, FALLBACK_MAX_BLOCKS};

use crate::system::BlockSystem;
use std::ops::ControlFlow;
use tree::{Cut, CutCounts, CuttingTree};

/// A generated block system and what generation did.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The blocks, with the domain, joint table and face origins.
    pub system: BlockSystem,
    /// Counts, slivers, volume check.
    pub report: GenerationReport,
}

/// Progress of a run, reported after each joint plane, then during the excavations (after
/// each of their cuts and blocks, with every plane applied).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Planes applied so far.
    pub planes_done: usize,
    /// Planes in all.
    pub planes_total: usize,
    /// Blocks so far (during an excavation: the convex parts it holds, those still to be
    /// cut included).
    pub blocks: usize,
    /// Excavations done (0 while the planes are cut).
    pub excavations_done: usize,
    /// Excavations in all.
    pub excavations_total: usize,
}

impl Progress {
    /// Whether this is the run's last report: every plane applied, every excavation done.
    pub fn is_last(&self) -> bool {
        self.planes_done == self.planes_total && self.excavations_done == self.excavations_total
    }
}

/// Generates the block system of a spec, within the memory available ([`Limits::default`]).
pub fn generate(spec: &Spec) -> Result<Generated, GenerationError> {
    generate_with(spec, &Limits::default(), &mut |_| ControlFlow::Continue(()))
}

/// [`generate`], calling `progress` after each joint plane (for progress bars).
pub fn generate_with_progress(
    spec: &Spec,
    progress: &mut dyn FnMut(Progress),
) -> Result<Generated, GenerationError> {
    generate_with(spec, &Limits::default(), &mut |p| {
        progress(p);
        ControlFlow::Continue(())
    })
}

/// Generates within `limits`, calling `progress` after each joint plane and, during the
/// excavations, after each of their cuts; the run stops there with
/// [`GenerationError::Cancelled`] when `progress` returns `Break` (Ctrl-C, an error in a
/// callback), so a run stops within one plane's cuts (or one excavation cut's).
///
/// # Errors
///
/// A bad spec; [`GenerationError::TooManyBlocks`] before cutting when the spec's
/// [`estimate`] passes `limits.max_blocks`; [`GenerationError::Outgrew`] when the run
/// makes more blocks than that all the same (the cuts of the joints, or of an excavation:
/// its convex parts); a cut that cannot be made.
pub fn generate_with(
    spec: &Spec,
    limits: &Limits,
    progress: &mut dyn FnMut(Progress) -> ControlFlow<()>,
) -> Result<Generated, GenerationError> {
    let plan = expand::plan(spec)?;
    let extent = slope::Extent::of(spec.domain.parts());
    for (k, excavation) in spec.excavations.iter().enumerate() {
        excavation.regions_at(&format!("excavations[{k}]"), extent.as_ref())?;
    }
    let estimate = work::estimate(spec, &plan);
    if estimate.blocks > limits.max_blocks as f64 {
        return Err(GenerationError::TooManyBlocks {
            blocks: estimate.blocks,
            planes: estimate.planes,
            lines: estimate.lines,
            points: estimate.points,
            bytes: estimate.bytes(),
            limit: limits.max_blocks,
            given: limits.given,
        });
    }
    let max_blocks = usize::try_from(limits.max_blocks).unwrap_or(usize::MAX);
    let mut tree = CuttingTree::new(spec.domain.parts(), plan.eps, max_blocks);
    let mut counts = CutCounts::default();
    let mut partial = vec![0; plan.sets.len()];
    let planes_total = plan.records.len();
    for (done, j) in cut_order(&plan.records).into_iter().enumerate() {
        let record = &plan.records[j];
        let before = counts.partial;
        let bridge = spec
            .joints
            .get(record.set as usize)
            .is_some_and(|d| d.bridge);
        let cut = tree.cut(record, j as u32, bridge, &mut counts)?;
        if cut == Cut::Full {
            return Err(GenerationError::Outgrew {
                estimate: estimate.blocks,
                limit: limits.max_blocks,
                given: limits.given,
                planes_done: done + 1,
                planes_total,
                excavation: None,
            });
        }
        partial[record.set as usize] += counts.partial - before;
        let step = Progress {
            planes_done: done + 1,
            planes_total,
            blocks: tree.len(),
            excavations_done: 0,
            excavations_total: spec.excavations.len(),
        };
        if progress(step).is_break() {
            return Err(GenerationError::Cancelled {
                planes_done: done + 1,
                planes_total,
            });
        }
    }
    let (blocks, slivers) =
        report::sort_slivers(tree.into_blocks(), &spec.options, spec.domain.size());
    let mut report = GenerationReport {
        partial_cuts_by_entry: partial,
        ..report::summarise(&blocks, spec.domain.volume(), &plan, &counts, slivers)
    };
    let domain = spec.domain.parts().to_vec();
    let mut system = BlockSystem::with_provenance(blocks, domain, plan.records, plan.sets)
        .with_unit(spec.unit.clone());
    let excavations_total = spec.excavations.len();
    for (k, excavation) in spec.excavations.iter().enumerate() {
        let prefix = format!("excavations[{k}]");
        let tol = &spec.options.tolerance;
        // The excavation's parts within the limit, and the callback asked as the cutting's.
        let watch = &mut |blocks: usize| {
            if blocks > max_blocks {
                return Err(GenerationError::Outgrew {
                    estimate: estimate.blocks,
                    limit: limits.max_blocks,
                    given: limits.given,
                    planes_done: planes_total,
                    planes_total,
                    excavation: Some(k),
                });
            }
            let step = Progress {
                planes_done: planes_total,
                planes_total,
                blocks,
                excavations_done: k,
                excavations_total,
            };
            if progress(step).is_break() {
                return Err(GenerationError::Cancelled {
                    planes_done: planes_total,
                    planes_total,
                });
            }
            Ok(())
        };
        let (excavated, done) = system.excavate_watched(excavation, &prefix, tol, watch)?;
        if excavated.is_empty() {
            // As a ground entirely below the rock (slope.rs, topography.rs): a spec's
            // excavation of every kind may not leave an empty system (`BlockSystem::excavate`
            // may, for rock excavated in stages).
            let msg = format!(
                "the excavation would remove all of the rock: every one of the {} blocks lies \
                 inside it, so no block would be left",
                system.len()
            );
            return Err(SpecError::new(prefix, Problem::Invalid(msg)).into());
        }
        report.excavated_volume += done.volume_removed;
        system = excavated;
        // The last report (planes and excavations done) comes once, at the end.
        if k + 1 < excavations_total {
            watch_between(progress, planes_total, &system, k + 1, excavations_total)?;
        }
    }
    if excavations_total > 0 {
        watch_between(
            progress,
            planes_total,
            &system,
            excavations_total,
            excavations_total,
        )?;
    }
    // The excavations' slivers, by body (a body is removed whole or not at all), before the
    // bridges' glue: a sliver piece a bridge glues to more rock is still a rigid body of its
    // own in a simulation (`rigid_body_ids`), whose time step it sets.
    let excavated = !spec.excavations.is_empty();
    let mut sliver_blocks = Vec::new();
    if excavated {
        let (kept, slivers, parts) = report::sort_sliver_bodies(system, &report.slivers);
        if kept.is_empty() {
            let msg = format!(
                "every one of the {} blocks the excavations leave is a sliver (thinner than \
                 {:.3e} or smaller than {:.3e}), and slivers = \"drop\" would leave no block",
                slivers.count, report.slivers.min_thickness, report.slivers.min_volume
            );
            return Err(SpecError::new("options.slivers", Problem::Invalid(msg)).into());
        }
        sliver_blocks = parts;
        system = kept;
        report.excavation_slivers = slivers;
    }
    // The pieces a bridged joint cut through, one body while the bridge holds (after the
    // excavations: they cut and remove single pieces, and the bridges left glue what holds).
    if let Some(ids) = system.bridge_glued_ids(&spec.options.tolerance) {
        system = system
            .with_bodies(ids, &spec.options.tolerance)
            .map_err(|e| SpecError::new("joints", Problem::Invalid(e.to_string())))?;
    }
    if excavated {
        // The slivers kept, by their bodies' ids now (a sliver piece glued by a bridge: the
        // body it is glued to).
        let mut bodies: Vec<u32> = sliver_blocks.iter().map(|&k| system.body_of(k)).collect();
        bodies.sort_unstable();
        bodies.dedup();
        report.excavation_slivers.kept_bodies = bodies;
        report.blocks = system.len();
        report.block_volume = system.blocks().iter().map(|b| b.volume()).sum();
    }
    Ok(Generated { system, report })
}

/// Reports the blocks after `done` of `total` excavations; a `Break` cancels the run.
fn watch_between(
    progress: &mut dyn FnMut(Progress) -> ControlFlow<()>,
    planes_total: usize,
    system: &BlockSystem,
    done: usize,
    total: usize,
) -> Result<(), GenerationError> {
    let step = Progress {
        planes_done: planes_total,
        planes_total,
        blocks: system.len(),
        excavations_done: done,
        excavations_total: total,
    };
    if progress(step).is_break() {
        return Err(GenerationError::Cancelled {
            planes_done: planes_total,
            planes_total,
        });
    }
    Ok(())
}

/// The number of joint planes a spec makes (checked and expanded, nothing cut): to bound
/// the work before [`generate`] (the fuzz targets do).
pub(crate) fn planned_planes(spec: &Spec) -> Result<usize, SpecError> {
    Ok(expand::plan(spec)?.records.len())
}

/// What a spec will make (checked and expanded, nothing cut): planes, and the blocks their
/// arrangement makes (see `work.rs` for how they are counted).
///
/// ```
/// use penedge::generation::{estimate, Discontinuity, Domain, JointSet, Orientation, Spec};
/// let set = |dip, dir| Discontinuity::set(JointSet::new(Orientation::dip(dip, dir), 0.01));
/// let spec = Spec::new(Domain::cuboid([0.0; 3], [100.0; 3]).unwrap())
///     .with(set(0.0, 0.0))
///     .with(set(90.0, 0.0))
///     .with(set(90.0, 90.0));
/// let e = estimate(&spec).unwrap();
/// assert!(e.blocks > 0.99e12); // 10^4 planes a set: (1 + 9999)^3 blocks
/// ```
pub fn estimate(spec: &Spec) -> Result<Estimate, SpecError> {
    Ok(work::estimate(spec, &expand::plan(spec)?))
}

/// Cuts the domain by infinite planes (no checks, no slivers: for
/// [`BlockSystem::from_domain_cut`]); the faces get origin `Joint { set, joint: i }`.
pub(crate) fn cut_domain(
    domain: &Domain,
    joints: &[JointRecord],
    eps: f64,
) -> Result<Vec<crate::block::ConvexBlock>, GenerationError> {
    let mut tree = CuttingTree::new(domain.parts(), eps, usize::MAX);
    let mut counts = CutCounts::default();
    for j in cut_order(joints) {
        tree.cut(&joints[j], j as u32, false, &mut counts)?;
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
