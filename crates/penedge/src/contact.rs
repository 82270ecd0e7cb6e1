//! The pair query: penetration edges, then the contact decision and type.

use crate::block::ConvexBlock;
use crate::classify::{decide, spread_exceeds, FaceLists, FaceMasks, PairResult};
use crate::geometry::DVec3;
use crate::penetration::{
    clip_edges, DistanceTable, EdgeSink, Kernel, PenetrationEdge, Piece, Side,
};
use crate::tolerance::{Thresholds, Tolerance};

/// A reusable pair detector: holds the tolerance and the scratch buffers, so that a loop
/// over many pairs allocates nothing once the buffers have grown.
///
/// After [`Detector::detect`] the penetration edges of the last pair stay available through
/// [`Detector::penetration_edges`].
#[derive(Clone, Debug, Default)]
pub struct Detector {
    tolerance: Tolerance,
    kernel: Kernel,
    a_to_b: DistanceTable,
    b_to_a: DistanceTable,
    edges: Vec<PenetrationEdge>,
    points: Vec<DVec3>,
}

impl Detector {
    /// A detector with the given tolerance.
    pub fn new(tolerance: Tolerance) -> Self {
        Detector {
            tolerance,
            ..Default::default()
        }
    }

    /// The tolerance in use.
    pub fn tolerance(&self) -> &Tolerance {
        &self.tolerance
    }

    /// Absolute thresholds for a pair: the policy at the smaller block's size, with the
    /// rounding floor of the pair's largest coordinate.
    pub fn thresholds(&self, a: &ConvexBlock, b: &ConvexBlock) -> Thresholds {
        let magnitude = a.magnitude().max(b.magnitude());
        self.tolerance.at_scale(a.size().min(b.size()), magnitude)
    }

    /// Detects and classifies the contact of `a` and `b`.
    ///
    /// 1. distances of each block's vertices to the other's planes; a separating face plane
    ///    ends the query (`Separated`);
    /// 2. penetration edges with the gap; none means `Separated`. The faces of each block
    ///    that hold their representative points are gathered as they are made
    ///    ([`crate::classify`]);
    /// 3. an edge deeper than the gap inside the other block means `Penetrating`;
    /// 4. otherwise the type from the features those faces give.
    pub fn detect(&mut self, a: &ConvexBlock, b: &ConvexBlock) -> PairResult {
        let th = self.thresholds(a, b);
        let features = match FaceMasks::new(a, b, th.length) {
            Some(mut masks) => match self.clip_pair(a, b, th, &mut masks) {
                Some(false) if !self.edges.is_empty() => masks.features(),
                outcome => return self.unclassified(outcome),
            },
            None => {
                let mut lists = FaceLists::new(a, b, th.length);
                match self.clip_pair(a, b, th, &mut Sides(&mut lists)) {
                    Some(false) if !self.edges.is_empty() => lists.features(),
                    outcome => return self.unclassified(outcome),
                }
            }
        };
        decide(a, b, features, th.length, |l| {
            spread_exceeds(a, b, &self.edges, l)
        })
    }

    /// The outcome of a pair that is not classified: separated by a face plane (`None`) or
    /// with no penetration edge, or penetrating (`Some(true)`).
    fn unclassified(&self, clipped: Option<bool>) -> PairResult {
        match clipped {
            Some(true) if !self.edges.is_empty() => PairResult::Penetrating,
            _ => PairResult::Separated,
        }
    }

    /// Whether no edge of either block meets the other one widened by `gap`: the
    /// `Separated` of [`Detector::detect`] at another gap (no classification). Leaves the
    /// penetration edges of this query.
    pub(crate) fn separated_at(&mut self, a: &ConvexBlock, b: &ConvexBlock, gap: f64) -> bool {
        let length = self.thresholds(a, b).length;
        self.clip_pair(a, b, Thresholds { gap, length }, &mut ())
            .is_none()
            || self.edges.is_empty()
    }

    /// Steps 1 and 2 of [`Detector::detect`]: the penetration edges at `th`, each told to
    /// `sink`, or `None` when a face plane separates the blocks; `Some(deep)` tells whether
    /// an edge goes deeper than the gap.
    fn clip_pair(
        &mut self,
        a: &ConvexBlock,
        b: &ConvexBlock,
        th: Thresholds,
        sink: &mut impl EdgeSink,
    ) -> Option<bool> {
        self.edges.clear();
        if !self.fill_tables(a, b, th) {
            return None;
        }
        let deep_a = clip_edges(a, Side::A, b, &self.a_to_b, th, &mut self.edges, sink);
        let deep_b = clip_edges(b, Side::B, a, &self.b_to_a, th, &mut self.edges, sink);
        Some(deep_a || deep_b)
    }

    /// Penetration edges of the pair last given to [`Detector::detect`] (empty when it was
    /// separated by a face plane before any clipping).
    pub fn penetration_edges(&self) -> &[PenetrationEdge] {
        &self.edges
    }

    /// Representative points of the last pair's penetration edges ([`crate::classify`],
    /// step 1), `a` and `b` being the blocks last given to [`Detector::detect`]. The
    /// classification itself needs no list of them; it is made here for the contact
    /// geometry.
    pub(crate) fn representative_points(&mut self, a: &ConvexBlock, b: &ConvexBlock) -> &[DVec3] {
        crate::classify::representative_points(a, b, &self.edges, &mut self.points);
        &self.points
    }

    /// Counts of the last pair's penetration edges by block and Table 1 type
    /// (`[side][type - 1]`), and the number of distinct original vertices of each block
    /// among them (`N^orig`), as in the paper's Table 2.
    pub fn table1_counts(&self) -> ([[usize; 5]; 2], [usize; 2]) {
        let mut counts = [[0; 5]; 2];
        let mut originals: [Vec<u32>; 2] = [Vec::new(), Vec::new()];
        for pe in &self.edges {
            let s = (pe.side == Side::B) as usize;
            counts[s][pe.kind as usize - 1] += 1;
            for end in pe.ends {
                if let crate::penetration::EdgeEnd::Vertex(v) = end {
                    if !originals[s].contains(&v) {
                        originals[s].push(v);
                    }
                }
            }
        }
        (counts, [originals[0].len(), originals[1].len()])
    }

    fn fill_tables(&mut self, a: &ConvexBlock, b: &ConvexBlock, th: Thresholds) -> bool {
        self.a_to_b.fill(self.kernel, a, b, th) && self.b_to_a.fill(self.kernel, b, a, th)
    }
}

impl EdgeSink for FaceMasks<'_> {
    #[inline(always)]
    fn edge(&mut self, piece: &Piece<'_>, table: &DistanceTable) {
        self.add(piece, table);
    }
}

/// [`FaceLists`] as an [`EdgeSink`].
struct Sides<'l, 'a>(&'l mut FaceLists<'a>);

impl EdgeSink for Sides<'_, '_> {
    fn edge(&mut self, piece: &Piece<'_>, table: &DistanceTable) {
        self.0.add(piece, table);
    }
}

/// Detects and classifies the contact of two blocks (allocates scratch buffers; use a
/// [`Detector`] in loops).
pub fn detect_pair(a: &ConvexBlock, b: &ConvexBlock, tolerance: &Tolerance) -> PairResult {
    Detector::new(*tolerance).detect(a, b)
}
