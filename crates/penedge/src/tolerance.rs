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

/// The thresholds of the tolerance policy (see the module docs): relative to the blocks'
/// size, or with the gap absolute ([`Tolerance::with_absolute_gap`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerance {
    gap: f64,
    length: f64,
    /// A gap in the model's length unit, used instead of `gap * scale`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    absolute_gap: Option<f64>,
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
    /// An absolute gap that is NaN, infinite or negative.
    #[error("tolerance `absolute_gap` must be a finite number >= 0 (in the model's length unit), got {}", crate::geometry::Short(*value))]
    AbsoluteGap {
        /// The value given.
        value: f64,
    },
    /// Both a relative and an absolute gap were given (the bindings' arguments).
    #[error("give a relative `gap` or an `absolute_gap`, not both")]
    BothGaps,
    /// A relative gap above 0 but below [`MIN_GAP`]: a gap the rounding floor always
    /// overrules, or that asks for less than the rounding of the block's own coordinates.
    #[error("tolerance `gap` must be 0 or at least {} (16 x 2^-52: a smaller relative gap is below the rounding of the coordinates, and the rounding floor overrules it), got {}", crate::geometry::Short(MIN_GAP), crate::geometry::Short(*value))]
    GapBelowRounding {
        /// The value given.
        value: f64,
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
            absolute_gap: None,
        }
    }
}

impl Tolerance {
    /// A policy with the given relative gap and length thresholds.
    pub fn new(gap: f64, length: f64) -> Result<Self, ToleranceError> {
        check_gap(gap)?;
        check_range("length", length, MAX_LENGTH)?;
        if length < 10.0 * gap {
            return Err(ToleranceError::LengthBelowGap { gap, length });
        }
        Ok(Tolerance {
            gap,
            length,
            absolute_gap: None,
        })
    }

    /// A policy whose gap is absolute: `gap` in the model's length unit for every pair (for
    /// a DEM model whose contact gap is a length), with the default relative length
    /// threshold. For a pair of scale `s`, the absolute gap is `min(gap, MAX_GAP × s)` (a gap
    /// of a block's size would make every contact of it one point), never below the rounding
    /// floor, and the length threshold at least ten times it. `gap` must be finite and not
    /// negative.
    pub fn with_absolute_gap(gap: f64) -> Result<Self, ToleranceError> {
        Tolerance::default().and_absolute_gap(gap)
    }

    /// This policy with its gap replaced by an absolute one ([`Tolerance::with_absolute_gap`]);
    /// the relative length threshold is kept.
    pub fn and_absolute_gap(self, gap: f64) -> Result<Self, ToleranceError> {
        if !(gap.is_finite() && gap >= 0.0) {
            return Err(ToleranceError::AbsoluteGap { value: gap });
        }
        Ok(Tolerance {
            gap: 0.0,
            absolute_gap: Some(gap),
            ..self
        })
    }

    /// The absolute gap, when the policy has one ([`Tolerance::with_absolute_gap`]).
    pub fn absolute_gap(&self) -> Option<f64> {
        self.absolute_gap
    }

    /// A policy with the given relative gap and the length threshold set to
    /// `max(default length, 10 * gap)`.
    pub fn with_gap(gap: f64) -> Result<Self, ToleranceError> {
        check_gap(gap)?;
        let length = Tolerance::default().length.max(10.0 * gap);
        Tolerance::new(gap, length)
    }

    /// The relative gap (0 when the gap is absolute: [`Tolerance::absolute_gap`]).
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

    /// How fast the gap of [`Tolerance::at_scale`] grows with the scale (the block size): the
    /// relative gap, or for an absolute gap the cap `MAX_GAP` (a bound: the gap is then
    /// constant until the cap). The certificates of separation charge the growth of the
    /// blocks' sizes (their boxes' diagonals, which turn with them) to it.
    pub(crate) fn gap_slope(&self) -> f64 {
        match self.absolute_gap {
            Some(_) => MAX_GAP,
            None => self.gap,
        }
    }

    /// Absolute thresholds for a given length scale, for coordinates of magnitude at most
    /// `magnitude` (see the rounding floor in the module docs).
    pub fn at_scale(&self, scale: f64, magnitude: f64) -> Thresholds {
        let gap = match self.absolute_gap {
            Some(gap) => gap.min(MAX_GAP * scale),
            None => self.gap * scale,
        };
        let gap = gap.max(ROUNDING_FLOOR * magnitude);
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

/// The smallest relative gap above 0 ([`ToleranceError::GapBelowRounding`]): the rounding
/// floor's fraction, 16 units of rounding (`2^-52` each). The absolute gap of a pair is
/// `max(gap × s, ROUNDING_FLOOR × m)` (`s` the smaller block's size, `m` the largest
/// coordinate magnitude of the pair), and `s ≤ 2√3 m` for any box (its diagonal is at most
/// the sum of its corners' lengths), so a relative gap below `ROUNDING_FLOOR / (2√3)` never
/// changes the absolute gap: it is 0 in effect, under a name that says otherwise. Between
/// that and `ROUNDING_FLOOR` it can matter only for a block around the origin, and then asks
/// for less than 16 units of rounding of the block's own size, less than the rounding the
/// distances to its face planes carry. So a positive gap must be at least this (the
/// default, 1e-12, is 4,500 units); a gap of 0 stays: the floor alone, as documented.
pub const MIN_GAP: f64 = ROUNDING_FLOOR;

/// A relative gap: 0, or in `[MIN_GAP, MAX_GAP)`.
fn check_gap(gap: f64) -> Result<(), ToleranceError> {
    check_range("gap", gap, MAX_GAP)?;
    if gap > 0.0 && gap < MIN_GAP {
        return Err(ToleranceError::GapBelowRounding { value: gap });
    }
    Ok(())
}

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
    fn absolute_gap_is_a_length() {
        let t = Tolerance::with_absolute_gap(1e-3).unwrap();
        assert_eq!(t.absolute_gap(), Some(1e-3));
        // The same gap for pairs of 1 m and of 10 m; the length threshold ten times it.
        for scale in [1.0, 10.0] {
            let th = t.at_scale(scale, 1.0);
            assert_eq!((th.gap, th.length), (1e-3, 1e-2));
            assert_eq!(th.sine, 1e-2 / scale);
        }
        // A pair smaller than 100 gaps: at most 1 % of its size; the floor far away.
        assert_eq!(t.at_scale(0.05, 1.0).gap, MAX_GAP * 0.05);
        assert_eq!(t.at_scale(1.0, 1e12).gap, ROUNDING_FLOOR * 1e12);
        // The relative length threshold still applies where it is larger.
        assert_eq!(t.at_scale(1e8, 0.0).length, 1e-9 * 1e8);
        for bad in [f64::NAN, -1e-3, f64::INFINITY] {
            assert!(matches!(
                Tolerance::with_absolute_gap(bad),
                Err(ToleranceError::AbsoluteGap { .. })
            ));
        }
        let kept = Tolerance::new(1e-6, 1e-3)
            .unwrap()
            .and_absolute_gap(0.0)
            .unwrap();
        assert_eq!(
            (kept.gap(), kept.length(), kept.absolute_gap()),
            (0.0, 1e-3, Some(0.0))
        );
    }

    /// A positive relative gap below the rounding floor's fraction is refused by every
    /// constructor (it was taken, and was 0 in effect); 0 and `MIN_GAP` itself are taken.
    #[test]
    fn a_gap_below_the_rounding_is_refused() {
        for gap in [1e-300, f64::MIN_POSITIVE, 5e-324, 1e-16, MIN_GAP * 0.999] {
            let refused = |r: Result<Tolerance, ToleranceError>| matches!(r, Err(ToleranceError::GapBelowRounding { value }) if value == gap);
            assert!(refused(Tolerance::with_gap(gap)), "{gap}");
            assert!(refused(Tolerance::new(gap, 1e-9)), "{gap}");
        }
        for gap in [0.0, MIN_GAP, 1e-14] {
            assert_eq!(Tolerance::with_gap(gap).unwrap().gap(), gap);
        }
        let message = Tolerance::with_gap(1e-300).unwrap_err().to_string();
        assert!(
            message.contains("`gap`") && message.contains("1e-300"),
            "{message}"
        );
    }

    #[test]
    fn with_gap_keeps_length_ten_times_larger() {
        let t = Tolerance::with_gap(1e-3).unwrap();
        assert_eq!(t.length(), 1e-2);
        let t = Tolerance::with_gap(1e-14).unwrap();
        assert_eq!(t.length(), Tolerance::default().length());
    }
}
