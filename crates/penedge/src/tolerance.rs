//! The one tolerance policy of penedge.
//!
//! Every threshold is a fraction of a length scale, so that results do not change when a
//! whole system is scaled. For a pair of blocks the scale is the smaller of the two blocks'
//! characteristic lengths ([`crate::ConvexBlock::size`], the diagonal of its bounding box);
//! for a single block it is that block's size; for generation, the domain's. Two numbers,
//! both relative (the full rules, and where each is applied: `docs/tolerance.md`):
//!
//! * `gap`: a face plane with all of the other block more than `gap * scale` outside it
//!   separates the pair; otherwise the blocks touch when an edge of one meets the other with
//!   its face planes moved out by `gap * scale` (the paper's widening: along a face normal the
//!   blocks touch up to that distance, at edges and corners a little farther). A penetration
//!   of at most `gap * scale` still counts as touching; a penetration edge that goes deeper
//!   into the other block makes the pair *penetrating*. The default (`1e-12`) only absorbs
//!   floating-point rounding: exactly touching blocks touch. DEM and DDA users set the gap
//!   they allow.
//! * `length`: the length below which a penetration edge "has no length" (paper Table 1),
//!   and the distance within which a point counts as lying on a plane or two points as one.
//!   It must be at least `10 * gap`: a penetration edge born of the gap widening is about
//!   `gap / sin(angle)` long, and reads as a point by its length for most angles. Over the
//!   scale it also gives the one angle of "lies in": an edge lies in a face (or along an
//!   edge) when the sine of their angle is at most the absolute length threshold over the scale
//!   ([`Thresholds::sine`]), and the gap's stub of an edge that does not is a point however
//!   long. Block validation (planarity, repeated vertices) uses it too.
//!
//! A floor keeps the thresholds above the rounding of the coordinates themselves: blocks far
//! from the origin (mine-grid coordinates, x ~ 5e5, y ~ 4e6) carry a rounding error of about
//! `|x| * 2^-52` in every coordinate, which no computation can undo. The absolute gap is
//! therefore never below `ROUNDING_FLOOR * m`, where `m` is the largest coordinate magnitude of
//! the pair, and the absolute length threshold never below ten times the absolute gap.

use thiserror::Error;

/// The relative thresholds of the tolerance policy (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerance {
    gap: f64,
    length: f64,
}

/// An impossible tolerance setting.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ToleranceError {
    /// A threshold is NaN, infinite, negative or not small (the gap below 0.01, the length
    /// below 0.1, both relative to the block size).
    #[error("tolerance `{name}` must be a finite number in [0, {max}) (relative to block size), got {}", crate::geometry::Short(*value))]
    OutOfRange {
        /// Which threshold.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The exclusive upper bound.
        max: f64,
    },
    /// The length threshold is below ten times the gap.
    #[error("tolerance `length` ({length}) must be at least 10 x `gap` ({gap})")]
    LengthBelowGap {
        /// The gap given.
        gap: f64,
        /// The length given.
        length: f64,
    },
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            gap: 1e-12,
            length: 1e-9,
        }
    }
}

impl Tolerance {
    /// A policy with the given relative gap and length thresholds.
    pub fn new(gap: f64, length: f64) -> Result<Self, ToleranceError> {
        check_range("gap", gap, MAX_GAP)?;
        check_range("length", length, MAX_LENGTH)?;
        if length < 10.0 * gap {
            return Err(ToleranceError::LengthBelowGap { gap, length });
        }
        Ok(Tolerance { gap, length })
    }

    /// A policy with the given relative gap and the length threshold set to
    /// `max(default length, 10 * gap)`.
    pub fn with_gap(gap: f64) -> Result<Self, ToleranceError> {
        check_range("gap", gap, MAX_GAP)?;
        let length = Tolerance::default().length.max(10.0 * gap);
        Tolerance::new(gap, length)
    }

    /// The relative gap.
    pub fn gap(&self) -> f64 {
        self.gap
    }

    /// The relative length threshold.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Absolute thresholds for one block (or a set of points) with this bounding box.
    pub fn for_box(&self, aabb: &crate::geometry::Aabb) -> Thresholds {
        self.at_scale(aabb.diagonal(), aabb.magnitude())
    }

    /// Absolute thresholds for a given length scale, for coordinates of magnitude at most
    /// `magnitude` (see the rounding floor in the module docs).
    pub fn at_scale(&self, scale: f64, magnitude: f64) -> Thresholds {
        let gap = (self.gap * scale).max(ROUNDING_FLOOR * magnitude);
        let length = (self.length * scale).max(10.0 * gap);
        Thresholds {
            gap,
            length,
            sine: lies_in_sine(length, scale),
        }
    }
}

/// The largest relative gap (exclusive): its length threshold, ten times larger, stays below
/// [`MAX_LENGTH`].
pub const MAX_GAP: f64 = 0.01;
/// The largest relative length threshold (exclusive).
pub const MAX_LENGTH: f64 = 0.1;

fn check_range(name: &'static str, value: f64, max: f64) -> Result<(), ToleranceError> {
    if value.is_finite() && (0.0..max).contains(&value) {
        Ok(())
    } else {
        Err(ToleranceError::OutOfRange { name, value, max })
    }
}

/// The absolute gap is at least this fraction of the largest coordinate magnitude:
/// 16 units of rounding (`2^-52` each) of a coordinate.
pub const ROUNDING_FLOOR: f64 = 16.0 * f64::EPSILON;

/// The sine of the largest angle at which an edge lies in a face, or along an edge, for the
/// absolute length threshold `length` at the length scale `scale`: `length / scale` (at
/// most 1), so that over the scale such an edge departs from the face's plane (or from the
/// other edge's line) by at most the length threshold (docs/tolerance.md, "Lies in").
pub fn lies_in_sine(length: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        (length / scale).min(1.0)
    } else {
        1.0
    }
}

/// Absolute thresholds (lengths) for one pair or one block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// Absolute gap.
    pub gap: f64,
    /// Absolute length threshold.
    pub length: f64,
    /// The sine of the largest angle at which an edge lies in a face or along an edge
    /// ([`lies_in_sine`]: the length threshold over the scale).
    pub sine: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_impossible_settings() {
        assert!(Tolerance::new(f64::NAN, 1e-9).is_err());
        assert!(Tolerance::new(-1e-9, 1e-9).is_err());
        assert!(Tolerance::new(1e-6, 1e-9).is_err());
        assert!(Tolerance::new(1e-3, 0.5).is_err());
        assert!(Tolerance::new(0.02, 0.05).is_err());
        for gap in [0.0, 1e-3, 0.0099] {
            assert!(Tolerance::with_gap(gap).is_ok(), "{gap}");
        }
        assert!(matches!(
            Tolerance::with_gap(0.05),
            Err(ToleranceError::OutOfRange { name: "gap", .. })
        ));
        assert!(Tolerance::new(1e-6, 1e-5).is_ok());
    }

    #[test]
    fn with_gap_keeps_length_ten_times_larger() {
        let t = Tolerance::with_gap(1e-3).unwrap();
        assert_eq!(t.length(), 1e-2);
        let t = Tolerance::with_gap(1e-14).unwrap();
        assert_eq!(t.length(), Tolerance::default().length());
    }
}
