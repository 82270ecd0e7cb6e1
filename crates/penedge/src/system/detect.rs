//! All contacts of a block system.
//!
//! Candidate pairs come from the broad phase ([`super::BroadPhase`]); the narrow phase runs in parallel over blocks with rayon, and the result is
//! sorted by block pair, so it is the same for any number of threads.

use super::{BlockSystem, BroadPhase, WideBoxes};
use crate::block::ConvexBlock;
use crate::classify::{Contact, PairResult};
use crate::contact::Detector;
use crate::tolerance::Tolerance;
use rayon::prelude::*;
use std::ops::ControlFlow;
use thiserror::Error;

/// A contact between blocks `pair[0] < pair[1]`, features in the same order.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PairContact {
    /// The two block ids, smaller first.
    pub pair: [u32; 2],
    /// Type and features.
    pub contact: Contact,
}

/// Every contact of a system, and the pairs that penetrate beyond the tolerance.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct SystemContacts {
    /// Touching pairs, sorted by pair.
    pub contacts: Vec<PairContact>,
    /// Penetrating pairs, sorted.
    pub penetrating: Vec<[u32; 2]>,
}

impl BlockSystem {
    /// Candidate pairs `(i, j)`, `i < j`, sorted, whose bounding boxes widened by their
    /// gaps overlap, by the default broad phase ([`BroadPhase::Grid`]).
    pub fn candidate_pairs(&self, tol: &Tolerance) -> Vec<[u32; 2]> {
        self.candidate_pairs_by(tol, BroadPhase::default())
    }

    /// Candidate pairs by the given broad-phase method (all methods give the same pairs).
    pub fn candidate_pairs_by(&self, tol: &Tolerance, method: BroadPhase) -> Vec<[u32; 2]> {
        self.wide_boxes(tol).pairs(method)
    }

    /// Each block's bounding box widened by its own gap.
    pub fn wide_boxes(&self, tol: &Tolerance) -> WideBoxes {
        let blocks = self.blocks();
        WideBoxes::from_fn(blocks.len(), |i| {
            let aabb = blocks[i].aabb();
            (aabb, tol.for_box(&aabb).gap)
        })
    }

    /// Detects and classifies every contact of the system.
    pub fn detect(&self, tol: &Tolerance) -> SystemContacts {
        match self.detect_with_progress(tol, &mut |_| ControlFlow::Continue(())) {
            Ok(found) => found,
            Err(Cancelled) => unreachable!("never cancelled"),
        }
    }

    /// [`BlockSystem::detect`], calling `progress` after each slice of candidate pairs
    /// (about 65,000 pairs, a few milliseconds); `ControlFlow::Break` stops the run.
    pub fn detect_with_progress(
        &self,
        tol: &Tolerance,
        progress: &mut dyn FnMut(DetectProgress) -> ControlFlow<()>,
    ) -> Result<SystemContacts, Cancelled> {
        let pairs = self.candidate_pairs(tol);
        let mut out = SystemContacts::default();
        out.contacts.reserve(pairs.len());
        let mut touching: Vec<usize> = Vec::new();
        narrow_phase(
            self,
            &pairs,
            tol,
            progress,
            |det, a, b| det.detect(a, b),
            |slice, outcomes| {
                // The contacts are written into the output by both threads, in pair order
                // (an indexed parallel extend writes in place): neither waits while the
                // other appends, and the output's fresh pages are touched by both.
                touching.clear();
                touching.par_extend(
                    (0..slice.len())
                        .into_par_iter()
                        .filter(|&k| matches!(outcomes[k], PairResult::Contact(_))),
                );
                out.contacts.par_extend(touching.par_iter().map(|&k| {
                    let PairResult::Contact(contact) = outcomes[k] else {
                        unreachable!("kept as a contact")
                    };
                    PairContact {
                        pair: slice[k],
                        contact,
                    }
                }));
                let penetrating = slice.iter().zip(outcomes);
                out.penetrating
                    .extend(penetrating.filter_map(|(&pair, outcome)| {
                        matches!(outcome, PairResult::Penetrating).then_some(pair)
                    }));
            },
        )?;
        out.contacts.shrink_to_fit();
        Ok(out)
    }
}

/// How far a system detection has come.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DetectProgress {
    /// Candidate pairs done.
    pub pairs_done: usize,
    /// Candidate pairs in all (the broad phase is done before the first report).
    pub pairs_total: usize,
}

/// A detection stopped by its progress callback.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
#[error("detection cancelled")]
pub struct Cancelled;

/// Candidate pairs per slice of the narrow phase: each slice runs in parallel, its outcomes
/// are kept in pair order, and progress is reported between slices. Small enough that the
/// per-slice buffer stays in the caches (and a cancellation is quick), large enough that
/// the threads rarely wait for each other.
const SLICE: usize = 1 << 16;

/// Runs `query` on every candidate pair, in parallel within each slice of [`SLICE`] pairs,
/// and hands each slice's pairs and outcomes (in pair order) to `keep`: the memory beyond
/// the output is one slice's outcomes, and the output is the same for any number of threads.
pub(super) fn narrow_phase<T: Send>(
    system: &BlockSystem,
    pairs: &[[u32; 2]],
    tol: &Tolerance,
    progress: &mut dyn FnMut(DetectProgress) -> ControlFlow<()>,
    query: impl Fn(&mut Detector, &ConvexBlock, &ConvexBlock) -> T + Sync,
    mut keep: impl FnMut(&[[u32; 2]], &[T]),
) -> Result<(), Cancelled> {
    let blocks = system.blocks();
    let mut outcomes = Vec::with_capacity(SLICE.min(pairs.len()));
    for (k, slice) in pairs.chunks(SLICE).enumerate() {
        slice
            .par_iter()
            .map_init(
                || Detector::new(*tol),
                |det, &[i, j]| query(det, &blocks[i as usize], &blocks[j as usize]),
            )
            .collect_into_vec(&mut outcomes);
        keep(slice, &outcomes);
        let done = (k * SLICE + slice.len()).min(pairs.len());
        if progress(DetectProgress {
            pairs_done: done,
            pairs_total: pairs.len(),
        })
        .is_break()
        {
            return Err(Cancelled);
        }
    }
    Ok(())
}

/// Number of contacts of each type, in the order of [`crate::ContactType::ALL`].
pub fn count_types(contacts: &[PairContact]) -> [usize; 7] {
    let mut counts = [0; 7];
    for c in contacts {
        counts[c.contact.kind.code() as usize - 1] += 1;
    }
    counts
}
