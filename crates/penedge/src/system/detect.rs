//! All contacts of a block system.
//!
//! Candidate pairs come from a sweep over the blocks' bounding boxes (widened by the gap)
//! sorted along x; the narrow phase runs in parallel over blocks with rayon, and the result is
//! sorted by block pair, so it is the same for any number of threads.

use super::BlockSystem;
use crate::classify::{Contact, PairResult};
use crate::contact::Detector;
use crate::tolerance::Tolerance;
use rayon::prelude::*;

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
    /// Candidate pairs `(i, j)`, `i < j`, whose bounding boxes widened by the gap overlap.
    pub fn candidate_pairs(&self, tol: &Tolerance) -> Vec<[u32; 2]> {
        let blocks = self.blocks();
        let margin = |i: usize| tol.for_box(&blocks[i].aabb()).gap;
        let mut order: Vec<usize> = (0..blocks.len()).collect();
        order.sort_by(|&i, &j| blocks[i].aabb().min.x.total_cmp(&blocks[j].aabb().min.x));
        let mut pairs = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            let bi = blocks[i].aabb();
            for &j in &order[k + 1..] {
                let bj = blocks[j].aabb();
                let m = margin(i).max(margin(j));
                if bj.min.x > bi.max.x + 2.0 * m {
                    break;
                }
                if bi.overlaps(&bj, m) {
                    pairs.push([i.min(j) as u32, i.max(j) as u32]);
                }
            }
        }
        pairs.sort_unstable();
        pairs
    }

    /// Detects and classifies every contact of the system.
    pub fn detect(&self, tol: &Tolerance) -> SystemContacts {
        let pairs = self.candidate_pairs(tol);
        let blocks = self.blocks();
        let results: Vec<([u32; 2], PairResult)> = pairs
            .par_iter()
            .map_init(
                || Detector::new(*tol),
                |det, &[i, j]| ([i, j], det.detect(&blocks[i as usize], &blocks[j as usize])),
            )
            .filter(|(_, r)| !matches!(r, PairResult::Separated))
            .collect();
        let mut out = SystemContacts::default();
        for (pair, result) in results {
            match result {
                PairResult::Contact(contact) => out.contacts.push(PairContact { pair, contact }),
                PairResult::Penetrating => out.penetrating.push(pair),
                PairResult::Separated => {}
            }
        }
        out
    }
}

/// Number of contacts of each type, in the order of [`crate::ContactType::ALL`].
pub fn count_types(contacts: &[PairContact]) -> [usize; 7] {
    let mut counts = [0; 7];
    for c in contacts {
        counts[c.contact.kind.code() as usize - 1] += 1;
    }
    counts
}
