//! All contacts of a block system.
//!
//! Candidate pairs come from the broad phase ([`super::BroadPhase`]); the narrow phase runs in parallel over blocks with rayon, and the result is
//! sorted by block pair, so it is the same for any number of threads.
//!
//! In a system with concave blocks ([`BlockSystem::with_bodies`]: blocks that are convex
//! parts of one body), two parts of one body are never a pair: they are glued into one rigid
//! block, and their glue faces are inside it, not contacts. The detection, its geometry, the
//! contacts of the bodies and the contact tracker all leave them out
//! ([`BlockSystem::contact_pairs`]).

use super::{append_in_parallel, BlockSystem, BroadPhase, WideBoxes};
use crate::block::{ConvexBlock, Prefetch};
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

    /// The candidate pairs that the detection queries: [`BlockSystem::candidate_pairs`] less
    /// the pairs of two parts of one body (a concave or bridged block), which are glued, not
    /// in contact. Without concave blocks, every candidate pair.
    ///
    /// ```
    /// use penedge::{BlockSystem, ConvexBlock, Tolerance};
    /// let tol = Tolerance::default();
    /// // Two boxes glued into one body (an L-block's parts), and a third box beside them.
    /// let system = BlockSystem::new(vec![
    ///     ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap(),
    ///     ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap(),
    ///     ConvexBlock::cuboid([0.0, 1.0, 0.0], [1.0, 2.0, 1.0]).unwrap(),
    /// ]);
    /// assert_eq!(system.candidate_pairs(&tol), [[0, 1], [0, 2], [1, 2]]);
    /// let glued = system.with_bodies(vec![0, 0, 1], &tol).unwrap();
    /// assert_eq!(glued.contact_pairs(&tol), [[0, 2], [1, 2]]);
    /// // The glue face between parts 0 and 1 is not a contact.
    /// let pairs: Vec<[u32; 2]> = glued.detect(&tol).contacts.iter().map(|c| c.pair).collect();
    /// assert_eq!(pairs, [[0, 2], [1, 2]]);
    /// ```
    pub fn contact_pairs(&self, tol: &Tolerance) -> Vec<[u32; 2]> {
        let mut pairs = self.candidate_pairs(tol);
        if self.has_concave() {
            pairs.retain(|&[i, j]| self.body_of(i) != self.body_of(j));
        }
        pairs
    }

    /// Each block's bounding box widened by its own gap.
    pub fn wide_boxes(&self, tol: &Tolerance) -> WideBoxes {
        let blocks = self.blocks();
        WideBoxes::from_fn(blocks.len(), |i| {
            let aabb = blocks[i].aabb();
            (aabb, tol.for_box(&aabb).gap)
        })
    }

    /// Detects and classifies every contact of the system: of every pair of blocks but two
    /// parts of one body ([`BlockSystem::contact_pairs`]).
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
        let pairs = self.contact_pairs(tol);
        let mut out = SystemContacts::default();
        out.contacts.reserve(pairs.len());
        narrow_phase(
            self,
            &pairs,
            tol,
            progress,
            |det, _, a, b| det.detect(a, b),
            |slice, outcomes| out.extend_from(slice, outcomes),
        )?;
        out.contacts.shrink_to_fit();
        Ok(out)
    }
}

impl SystemContacts {
    /// Appends the contacts and the penetrating pairs among `results` (the answers for
    /// `pairs`), in pair order. Each chunk of the results is sorted out by one thread, then
    /// the chunks' parts are appended in parallel ([`super::append_in_parallel`]): no thread
    /// waits while another appends, and the output's fresh pages are touched by all (on a
    /// grid of 10^6 blocks, appending from one thread cost 0.15 to 0.9 s).
    pub(super) fn extend_from(&mut self, pairs: &[[u32; 2]], results: &[PairResult]) {
        const CHUNK: usize = 1 << 14;
        let parts: Vec<SystemContacts> = pairs
            .par_chunks(CHUNK)
            .zip(results.par_chunks(CHUNK))
            .map(|(pairs, results)| {
                let mut part = SystemContacts::default();
                for (&pair, result) in pairs.iter().zip(results) {
                    match *result {
                        PairResult::Contact(contact) => {
                            part.contacts.push(PairContact { pair, contact })
                        }
                        PairResult::Penetrating => part.penetrating.push(pair),
                        PairResult::Separated => {}
                    }
                }
                part
            })
            .collect();
        let contacts: Vec<&[PairContact]> = parts.iter().map(|p| &p.contacts[..]).collect();
        append_in_parallel(&mut self.contacts, &contacts);
        let penetrating: Vec<&[[u32; 2]]> = parts.iter().map(|p| &p.penetrating[..]).collect();
        append_in_parallel(&mut self.penetrating, &penetrating);
    }

    /// This output with the answers of some of its candidate pairs replaced: `changed`
    /// holds those pairs, sorted and distinct, with their new answers; every other pair
    /// keeps its answer. A step of [`super::ContactTracker`] that queries few pairs reads the
    /// last output this way, rather than every candidate pair's answer.
    pub(super) fn with_changes(&self, changed: &[([u32; 2], PairResult)]) -> SystemContacts {
        debug_assert!(changed.windows(2).all(|w| w[0].0 < w[1].0));
        SystemContacts {
            contacts: merged(
                &self.contacts,
                |c| c.pair,
                changed,
                |pair, result| match *result {
                    PairResult::Contact(contact) => Some(PairContact { pair, contact }),
                    _ => None,
                },
            ),
            penetrating: merged(
                &self.penetrating,
                |&p| p,
                changed,
                |pair, result| (*result == PairResult::Penetrating).then_some(pair),
            ),
        }
    }
}

/// `old` (sorted by pair) with the entries of the pairs of `changed` (sorted) replaced by
/// `entry` of their new answers (`None`: no entry). The stretches between changed pairs are
/// found by binary search and copied whole.
fn merged<T: Copy>(
    old: &[T],
    pair_of: impl Fn(&T) -> [u32; 2],
    changed: &[([u32; 2], PairResult)],
    entry: impl Fn([u32; 2], &PairResult) -> Option<T>,
) -> Vec<T> {
    let mut out = Vec::with_capacity(old.len() + changed.len());
    let mut rest = old;
    for (pair, result) in changed {
        let before = rest.partition_point(|x| pair_of(x) < *pair);
        out.extend_from_slice(&rest[..before]);
        rest = &rest[before..];
        if rest.first().is_some_and(|x| pair_of(x) == *pair) {
            rest = &rest[1..];
        }
        out.extend(entry(*pair, result));
    }
    out.extend_from_slice(rest);
    out
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

/// How many pairs ahead of its query a block's buffers are asked for ([`ask_ahead`]; the
/// block itself twice as far, so that the buffers' addresses are in cache by then).
const AHEAD: usize = 2;

/// Asks the processor for the blocks of the pairs a little after the `n`-th one
/// (`pair_at(m)`: the `m`-th pair, if any), the second block of each or, with `first_too`,
/// both ([`ConvexBlock::prefetch`]). A hint, with no effect on any result: a query waits on
/// each cache line of its blocks that is not in cache, and the blocks of the pairs that
/// follow are elsewhere in memory (by 10^4 blocks on a 100^3 grid; anywhere in a tracker's
/// step). On the 100^3 grid and the jointed mass it made the detection about 10 % faster,
/// and a tracker's small step a quarter.
#[inline(always)]
pub(super) fn ask_ahead(
    blocks: &[ConvexBlock],
    pair_at: impl Fn(usize) -> Option<[u32; 2]>,
    n: usize,
    first_too: bool,
) {
    let ends = |pair: [u32; 2]| pair.into_iter().skip(usize::from(!first_too));
    if let Some(pair) = pair_at(n + 2 * AHEAD) {
        ends(pair).for_each(|b| blocks[b as usize].prefetch(Prefetch::Block));
    }
    if let Some(pair) = pair_at(n + AHEAD) {
        ends(pair).for_each(|b| blocks[b as usize].prefetch(Prefetch::Query));
    }
}

/// Candidate pairs per slice of the narrow phase (and queried pairs per slice of a
/// [`super::ContactTracker`] step): each slice runs in parallel, its outcomes
/// are kept in pair order, and progress is reported between slices. Small enough that the
/// per-slice buffer stays in the caches (and a cancellation is quick), large enough that
/// the threads rarely wait for each other.
pub(super) const SLICE: usize = 1 << 16;

/// Runs `query` on every candidate pair (given its block ids and blocks), in parallel within each slice of [`SLICE`] pairs,
/// and hands each slice's pairs and outcomes (in pair order; `keep` may move them out) to
/// `keep`: the memory beyond
/// the output is one slice's outcomes, and the output is the same for any number of threads.
pub(super) fn narrow_phase<T: Send>(
    system: &BlockSystem,
    pairs: &[[u32; 2]],
    tol: &Tolerance,
    progress: &mut dyn FnMut(DetectProgress) -> ControlFlow<()>,
    query: impl Fn(&mut Detector, [u32; 2], &ConvexBlock, &ConvexBlock) -> T + Sync,
    mut keep: impl FnMut(&[[u32; 2]], &mut [T]),
) -> Result<(), Cancelled> {
    let blocks = system.blocks();
    let mut outcomes = Vec::with_capacity(SLICE.min(pairs.len()));
    for (k, slice) in pairs.chunks(SLICE).enumerate() {
        slice
            .par_iter()
            .enumerate()
            .map_init(
                || Detector::new(*tol),
                |det, (n, &[i, j])| {
                    // The pairs run by first block: the second ones are asked for.
                    ask_ahead(blocks, |m| slice.get(m).copied(), n, false);
                    query(det, [i, j], &blocks[i as usize], &blocks[j as usize])
                },
            )
            .collect_into_vec(&mut outcomes);
        keep(slice, &mut outcomes);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::{ContactType, Feature};
    use crate::system::test_rng::Rng;

    /// An answer drawn at random: separated, penetrating or a contact (types in turn).
    fn random_result(rng: &mut Rng, k: usize) -> PairResult {
        match (rng.unit() * 3.0) as u32 {
            0 => PairResult::Separated,
            1 => PairResult::Penetrating,
            _ => PairResult::Contact(Contact {
                kind: ContactType::ALL[k % 7],
                feature_a: Feature::Vertex(k as u32),
                feature_b: Feature::Face(7),
            }),
        }
    }

    /// An output with some pairs' answers replaced equals the output built anew from every
    /// pair's answer: pairs that change category, stay, appear or go, at the ends too.
    #[test]
    fn with_changes_equals_the_output_built_anew() {
        let mut rng = Rng(8);
        let n = 3000;
        let pairs: Vec<[u32; 2]> = (0..n as u32).map(|k| [k / 40, k]).collect();
        let mut results: Vec<PairResult> = (0..n).map(|k| random_result(&mut rng, k)).collect();
        let mut old = SystemContacts::default();
        old.extend_from(&pairs, &results);
        for (round, share) in [0.0, 0.01, 0.3, 1.0].into_iter().enumerate() {
            let mut changed = Vec::new();
            for k in 0..n {
                let ends = k == 0 || k == n - 1;
                if rng.unit() < share || (ends && round == 2) {
                    results[k] = random_result(&mut rng, k + round);
                    changed.push((pairs[k], results[k]));
                }
            }
            let mut anew = SystemContacts::default();
            anew.extend_from(&pairs, &results);
            let merged = old.with_changes(&changed);
            assert_eq!(merged, anew, "round {round}, {} changed", changed.len());
            old = merged;
        }
    }

    /// The output built in parallel chunks equals the contacts and penetrating pairs picked
    /// one by one, in order, appended after what was there, across chunk boundaries.
    #[test]
    fn extend_from_keeps_pair_order_across_chunks() {
        let mut rng = Rng(3);
        let n = 50_000;
        let pairs: Vec<[u32; 2]> = (0..n as u32).map(|k| [k, k + 1]).collect();
        let results: Vec<PairResult> = (0..n).map(|k| random_result(&mut rng, k)).collect();
        let mut expected = SystemContacts {
            contacts: Vec::new(),
            penetrating: vec![[9, 9]],
        };
        let mut found = expected.clone();
        for (&pair, result) in pairs.iter().zip(&results) {
            match *result {
                PairResult::Contact(contact) => {
                    expected.contacts.push(PairContact { pair, contact })
                }
                PairResult::Penetrating => expected.penetrating.push(pair),
                PairResult::Separated => {}
            }
        }
        found.extend_from(&pairs[..n / 3], &results[..n / 3]);
        found.extend_from(&pairs[n / 3..], &results[n / 3..]);
        assert_eq!(found, expected);
        assert!(expected.contacts.len() > n / 4 && expected.penetrating.len() > n / 4);
    }
}
