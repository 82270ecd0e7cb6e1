//! How far a block may be translated before double precision no longer holds it: the
//! cheap per-pose check of [`crate::system::ContactTracker::update`], the same rule as
//! [`ConvexBlock::try_translated`]'s without a pass over the vertices.

use super::{ConvexBlock, Pose, MAX_COORDINATE};
use crate::tolerance::ROUNDING_FLOOR;

/// The largest coordinate magnitude at which a block whose closest vertices are `spacing`
/// apart stays a valid block: the length threshold (at least ten times the rounding floor
/// times the magnitude, [`crate::Tolerance::at_scale`]) must stay below `spacing`, or the
/// vertices count as one; and no coordinate beyond [`MAX_COORDINATE`].
pub(crate) fn largest_magnitude(spacing: f64) -> f64 {
    (spacing / (10.0 * ROUNDING_FLOOR)).min(MAX_COORDINATE)
}

/// What a block allows of a pose: computed once per block, checked per pose in one
/// comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Reach {
    /// The farthest a vertex of the block is from the origin (a rotation about the origin
    /// keeps it; each coordinate of a placed vertex is at most this plus the translation's
    /// largest component).
    pub(crate) extent: f64,
    /// The distance of the block's closest two vertices.
    pub(crate) spacing: f64,
    /// [`largest_magnitude`] of `spacing`.
    pub(crate) limit: f64,
}

impl Reach {
    /// The reach of `block` (a pass over its pairs of vertices, once).
    pub(crate) fn of(block: &ConvexBlock) -> Reach {
        let v = block.vertices();
        let extent = v.iter().map(|p| p.length()).fold(0.0, f64::max);
        let spacing = (0..v.len())
            .flat_map(|i| (i + 1..v.len()).map(move |j| v[i].distance(v[j])))
            .fold(f64::INFINITY, f64::min);
        Reach {
            extent,
            spacing,
            limit: largest_magnitude(spacing),
        }
    }

    /// The largest coordinate magnitude the block can have at `pose` (a bound, up to √3
    /// times the true one for a rotated block).
    pub(crate) fn magnitude_at(&self, pose: &Pose) -> f64 {
        pose.translation.abs().max_element() + self.extent
    }

    /// Whether `pose` keeps the block within its limit. A pose without translation always
    /// does (the block is valid where it is, and a rotation about the origin moves its
    /// coordinates' magnitude by at most a factor √3), so does any translation up to the
    /// limit less the extent; beyond, the block's coordinates could pass the limit.
    pub(crate) fn admits(&self, pose: &Pose) -> bool {
        let shift = pose.translation.abs().max_element();
        shift == 0.0 || shift + self.extent <= self.limit
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DQuat, DVec3};

    fn shifted(by: f64) -> Pose {
        Pose {
            rotation: DQuat::IDENTITY,
            translation: DVec3::new(by, 0.0, 0.0),
        }
    }

    /// The reach agrees with `try_translated` on a unit cube: a translation it admits leaves
    /// a valid block, one it refuses (1e14: the cube's corners are 1 apart where the length
    /// threshold is 3.6) an invalid one.
    #[test]
    fn the_reach_agrees_with_try_translated() {
        let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let reach = Reach::of(&cube);
        assert_eq!(reach.spacing, 1.0);
        assert_eq!(reach.extent, 3f64.sqrt());
        for by in [0.0, 1.0, 1e6, 1e13] {
            assert!(reach.admits(&shifted(by)), "{by}");
            assert!(cube.try_translated(DVec3::X * by).is_ok(), "{by}");
        }
        for by in [1e14, 1e17, 1e300, -1e300] {
            assert!(!reach.admits(&shifted(by)), "{by}");
            assert!(cube.try_translated(DVec3::X * by).is_err(), "{by}");
        }
    }

    /// A large block is held only to 1e50, however far apart its vertices.
    #[test]
    fn no_coordinate_beyond_the_largest() {
        let cube = ConvexBlock::cuboid([0.0; 3], [1e40; 3]).unwrap();
        let reach = Reach::of(&cube);
        assert_eq!(reach.limit, MAX_COORDINATE);
        assert!(reach.admits(&shifted(1e49)));
        assert!(!reach.admits(&shifted(2e50)));
        assert!(cube.try_translated(DVec3::X * 2e50).is_err());
    }
}
