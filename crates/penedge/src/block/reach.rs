//! How far a block may be translated before double precision no longer holds it: the
//! cheap per-pose check of [`crate::system::ContactTracker::update`], the same rule as
//! [`ConvexBlock::try_translated`]'s without a pass over the vertices: a bound of the placed
//! block's coordinates from its placed centroid and its radius.

use super::{ConvexBlock, Pose, MAX_COORDINATE};
use crate::geometry::DVec3;
use crate::tolerance::ROUNDING_FLOOR;

/// The largest coordinate magnitude at which a block whose closest vertices are `spacing`
/// apart stays a valid block: the length threshold (at least ten times the rounding floor
/// times the magnitude, [`crate::Tolerance::at_scale`]) must stay below `spacing`, or the
/// vertices count as one; and no coordinate beyond [`MAX_COORDINATE`].
pub(crate) fn largest_magnitude(spacing: f64) -> f64 {
    (spacing / (10.0 * ROUNDING_FLOOR)).min(MAX_COORDINATE)
}

/// What a block allows of a pose: computed once per block, checked per pose with one
/// rotation of a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Reach {
    /// The block's centroid.
    pub(crate) centre: DVec3,
    /// The farthest a vertex is from the centroid: each coordinate of the block placed at a
    /// pose is within this of the placed centroid's.
    pub(crate) radius: f64,
    /// A bound of the block's coordinates at any rotation without translation (the
    /// centroid's distance from the origin plus the radius): such a pose is always
    /// admitted, the block being valid where it is given.
    pub(crate) home: f64,
    /// The distance of the block's closest two vertices.
    pub(crate) spacing: f64,
    /// [`largest_magnitude`] of `spacing`.
    pub(crate) limit: f64,
}

impl Reach {
    /// The reach of `block` (a pass over its pairs of vertices, once).
    pub(crate) fn of(block: &ConvexBlock) -> Reach {
        let v = block.vertices();
        let centre = block.centroid();
        let radius = v.iter().map(|p| p.distance(centre)).fold(0.0, f64::max);
        let spacing = (0..v.len())
            .flat_map(|i| (i + 1..v.len()).map(move |j| v[i].distance(v[j])))
            .fold(f64::INFINITY, f64::min);
        Reach {
            centre,
            radius,
            home: centre.length() + radius,
            spacing,
            limit: largest_magnitude(spacing),
        }
    }

    /// A bound of the largest coordinate magnitude of the block at `pose` (a normalised
    /// one): the placed centroid's largest coordinate plus the radius.
    pub(crate) fn magnitude_at(&self, pose: &Pose) -> f64 {
        pose.apply(self.centre).abs().max_element() + self.radius
    }

    /// Whether `pose` (normalised) keeps the block within its limit: its coordinates'
    /// bound ([`Reach::magnitude_at`]) is at most the limit, or at most the bound of the
    /// block rotated where it is given ([`Reach::home`]: a pose without translation always
    /// passes, even for a block given near its limit).
    pub(crate) fn admits(&self, pose: &Pose) -> bool {
        self.magnitude_at(pose) <= self.limit.max(self.home)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

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
        assert_eq!(reach.radius, 0.5 * 3f64.sqrt());
        for by in [0.0, 1.0, 1e6, 1e13] {
            assert!(reach.admits(&shifted(by)), "{by}");
            assert!(cube.try_translated(DVec3::X * by).is_ok(), "{by}");
        }
        for by in [1e14, 1e17, 1e300, -1e300] {
            assert!(!reach.admits(&shifted(by)), "{by}");
            assert!(cube.try_translated(DVec3::X * by).is_err(), "{by}");
        }
    }

    /// The bound follows the placed centroid: a unit cube moved to 2e13 (its corners 1 apart,
    /// more than the 0.71 within which they would count as one there) and moved back to the
    /// origin is admitted, as its moved copy is valid; moved on by as much again it is not,
    /// nor is its copy. A rotation without translation is admitted wherever the block is.
    #[test]
    fn the_bound_follows_the_placed_centroid() {
        let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let far = cube.try_translated(DVec3::splat(2e13)).unwrap();
        let reach = Reach::of(&far);
        for (by, valid) in [(-2e13, true), (2e13, false)] {
            assert_eq!(reach.admits(&shifted(by)), valid, "{by}");
            let moved = far.try_translated(DVec3::X * by);
            assert_eq!(moved.is_ok(), valid, "{by}");
        }
        let turned = Pose {
            rotation: DQuat::from_rotation_z(0.7),
            translation: DVec3::ZERO,
        };
        assert!(reach.admits(&turned));
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
