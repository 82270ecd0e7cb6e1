//! Statistics of a block system: block count and the volume distribution.
//!
//! `V10`, `V50`, `V90` follow the sieve-curve convention of rock fragmentation: `VX` is the
//! smallest block volume `v` such that blocks of volume `<= v` make up at least X % of the
//! total rock volume. The count percentiles (`N10`, ...) are by number of blocks instead
//! (nearest rank).

use crate::block::ConvexBlock;

/// Block count and volume distribution.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BlockStatistics {
    /// Number of blocks.
    pub count: usize,
    /// Sum of the volumes.
    pub total_volume: f64,
    /// Smallest volume.
    pub min_volume: f64,
    /// Largest volume.
    pub max_volume: f64,
    /// Mean volume.
    pub mean_volume: f64,
    /// Volume-weighted 10 % passing volume.
    pub v10: f64,
    /// Volume-weighted 50 % passing volume.
    pub v50: f64,
    /// Volume-weighted 90 % passing volume.
    pub v90: f64,
    /// Block volume at the 10th, 50th and 90th percentile by count.
    pub count_percentiles: [f64; 3],
}

/// One point of the volume distribution curve.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DistributionPoint {
    /// A block volume.
    pub volume: f64,
    /// Fraction (0 to 1) of the total volume in blocks of this volume or less.
    pub passing: f64,
}

impl BlockStatistics {
    /// Statistics of the blocks; `None` when there are none.
    pub fn of(blocks: &[ConvexBlock]) -> Option<BlockStatistics> {
        let volumes: Vec<f64> = blocks.iter().map(ConvexBlock::volume).collect();
        BlockStatistics::of_volumes(&volumes)
    }

    /// Statistics of a list of volumes; `None` when empty.
    pub fn of_volumes(volumes: &[f64]) -> Option<BlockStatistics> {
        let curve = distribution_curve(volumes);
        let last = curve.last()?;
        let total: f64 = volumes.iter().sum();
        let passing = |x: f64| {
            curve
                .iter()
                .find(|p| p.passing >= x)
                .map_or(last.volume, |p| p.volume)
        };
        let n = curve.len();
        let rank = |q: f64| curve[((q * n as f64).ceil() as usize).clamp(1, n) - 1].volume;
        Some(BlockStatistics {
            count: n,
            total_volume: total,
            min_volume: curve[0].volume,
            max_volume: last.volume,
            mean_volume: total / n as f64,
            v10: passing(0.1),
            v50: passing(0.5),
            v90: passing(0.9),
            count_percentiles: [rank(0.1), rank(0.5), rank(0.9)],
        })
    }
}

/// The cumulative volume curve: volumes in increasing order, each with the fraction of the
/// total volume in blocks no larger (the curve a PNG of the distribution plots).
pub fn distribution_curve(volumes: &[f64]) -> Vec<DistributionPoint> {
    let mut sorted = volumes.to_vec();
    sorted.sort_by(f64::total_cmp);
    let total: f64 = sorted.iter().sum();
    let mut acc = 0.0;
    sorted
        .into_iter()
        .map(|volume| {
            acc += volume;
            DistributionPoint {
                volume,
                passing: acc / total,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passing_volumes_by_hand() {
        // Volumes 1, 2, 3, 4: cumulative fractions 0.1, 0.3, 0.6, 1.0.
        let s = BlockStatistics::of_volumes(&[4.0, 1.0, 3.0, 2.0]).unwrap();
        assert_eq!((s.count, s.total_volume, s.mean_volume), (4, 10.0, 2.5));
        assert_eq!((s.v10, s.v50, s.v90), (1.0, 3.0, 4.0));
        assert_eq!(s.count_percentiles, [1.0, 2.0, 4.0]);
        assert!(BlockStatistics::of_volumes(&[]).is_none());
    }
}
