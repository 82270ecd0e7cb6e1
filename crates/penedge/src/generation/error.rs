//! Errors of block generation: a bad spec names the field and the problem.

use crate::block::BlockError;
use crate::geometry::Short;
use thiserror::Error;

/// A problem with one field of a generation spec, e.g. `joints[2].dip: dip must be between 0
/// and 90 degrees, got 120`.
#[derive(Debug, Error, Clone, PartialEq)]
#[error("{field}: {problem}")]
pub struct SpecError {
    /// The field, as a path into the spec (`domain.max`, `joints[2].spacing`, `options`).
    pub field: String,
    /// What is wrong with it.
    pub problem: Problem,
}

impl SpecError {
    /// An error for `field`.
    pub fn new(field: impl Into<String>, problem: Problem) -> Self {
        SpecError {
            field: field.into(),
            problem,
        }
    }
}

/// What is wrong with a field.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Problem {
    /// NaN or infinite.
    #[error("must be a finite number, got {}", Short(*value))]
    NotFinite {
        /// The value given.
        value: f64,
    },
    /// A dip outside [0, 90].
    #[error("dip must be between 0 and 90 degrees, got {}", Short(*value))]
    Dip {
        /// The value given.
        value: f64,
    },
    /// A dip direction outside [0, 360].
    #[error("dip direction must be between 0 and 360 degrees, got {}", Short(*value))]
    DipDirection {
        /// The value given.
        value: f64,
    },
    /// Zero or negative where a positive number is needed (spacing, radius, number).
    #[error("must be greater than zero, got {}", Short(*value))]
    NotPositive {
        /// The value given.
        value: f64,
    },
    /// A negative deviation, volume or thickness.
    #[error("must not be negative, got {}", Short(*value))]
    Negative {
        /// The value given.
        value: f64,
    },
    /// A random spacing deviation that could make a spacing of zero or less.
    #[error(
        "the spacing deviation ({}) must be smaller than the spacing ({})",
        Short(*deviation),
        Short(*spacing)
    )]
    DeviationTooLarge {
        /// The deviation given.
        deviation: f64,
        /// The spacing given.
        spacing: f64,
    },
    /// A zero normal vector.
    #[error("the normal is the zero vector")]
    ZeroNormal,
    /// Both a normal and dip / dip direction, or neither.
    #[error("give either `normal` or both `dip` and `dip_direction`")]
    Orientation,
    /// The joint does not cross the domain's interior.
    #[error("the {what} misses the domain (it does not cross its interior)")]
    MissesDomain {
        /// "plane", "joint set", "disc", "polygon".
        what: &'static str,
    },
    /// The same plane as another joint.
    #[error("its plane {member} is the same plane as {other} (parallel and within {distance:e})")]
    Duplicate {
        /// The plane within this entry (0 for a single plane).
        member: u32,
        /// The other joint: entry and plane.
        other: String,
        /// The distance allowed (the length threshold).
        distance: f64,
    },
    /// Too many planes (a spacing far too small for the domain, or a `number` too large).
    #[error(
        "would make {count} planes, more than the limit of {limit}{}",
        if *by_number { "" } else { "; is the spacing too small?" }
    )]
    TooManyPlanes {
        /// Planes needed (at least; `u64::MAX` for more).
        count: u64,
        /// The limit.
        limit: u64,
        /// Whether the count is a set's `number` as given (no hint about the spacing).
        by_number: bool,
    },
    /// A filling set whose origin is so far from the domain that walking its planes out to
    /// the domain, one gap after the other (each plane's gap is drawn in turn), would take
    /// more than `limit` gaps.
    #[error(
        "lies about {spacings:.1e} spacings from the domain's far side: a set's planes are \
         placed one gap after the other from its origin, and the walk would take more than \
         {limit} gaps; put the origin near the domain (e.g. at its centre)"
    )]
    OriginFar {
        /// The distance from the origin to the domain's far side, in spacings.
        spacings: f64,
        /// The most gaps walked.
        limit: u64,
    },
    /// A polygon joint that is not a flat convex polygon.
    #[error("not a flat convex polygon: {reason}")]
    BadPolygon {
        /// What is wrong.
        reason: &'static str,
    },
    /// The domain is not a valid convex polyhedron.
    #[error("invalid domain: {0}")]
    Domain(BlockError),
    /// A required field is missing.
    #[error("missing (required)")]
    Missing,
    /// A field that does not belong to this kind of entry.
    #[error("not a field of a `{kind}` entry")]
    NotAllowed {
        /// The entry's kind.
        kind: String,
    },
    /// An unknown `type` value.
    #[error("unknown type `{found}`, expected one of {expected}")]
    UnknownType {
        /// The value given.
        found: String,
        /// The values allowed.
        expected: &'static str,
    },
    /// A bad value of another kind.
    #[error("{0}")]
    Invalid(String),
    /// The file does not parse (TOML or JSON syntax, wrong value type, unknown key).
    #[error("{0}")]
    Syntax(String),
}

/// Why generation failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GenerationError {
    /// The spec is invalid.
    #[error("invalid spec: {0}")]
    Spec(#[from] SpecError),
    /// A cut could not be made consistently (reported, never silently skipped).
    #[error("joint {joint} (spec entry {set}) cannot cut a block: {source}")]
    Cut {
        /// Spec entry.
        set: u32,
        /// Joint table index.
        joint: u32,
        /// What went wrong.
        source: BlockError,
    },
    /// The spec would make more blocks than the run may: refused before cutting.
    #[error(
        "the spec would make about {} blocks (1 + {planes} planes + {} lines + {} points where \
         planes meet, estimated), needing about {} of memory; the limit is {} blocks{}. Use a \
         larger spacing or a smaller domain (a sub-domain of the rock mass), or raise the \
         limit (max_blocks, `--max-blocks`) if the estimate is too high",
        Count(*blocks), Count(*lines), Count(*points), Bytes(*bytes), Count(*limit as f64),
        limit_reason(*given)
    )]
    TooManyBlocks {
        /// Blocks estimated.
        blocks: f64,
        /// Planes crossing the domain.
        planes: usize,
        /// Lines estimated.
        lines: f64,
        /// Points estimated.
        points: f64,
        /// Memory estimated, in bytes.
        bytes: f64,
        /// The most blocks allowed.
        limit: u64,
        /// Whether the limit was set by the caller (else: from the memory available).
        given: bool,
    },
    /// The run made more blocks than its limit (its estimate was too low) and stopped.
    #[error(
        "the run outgrew its estimate (about {} blocks): it made more than the limit of {} \
         blocks{} {} and was stopped. Use a larger spacing or a smaller domain, or raise the \
         limit (max_blocks, `--max-blocks`)",
        Count(*estimate), Count(*limit as f64), limit_reason(*given),
        outgrew_when(*planes_done, *planes_total, *excavation)
    )]
    Outgrew {
        /// The estimate made before cutting.
        estimate: f64,
        /// The most blocks allowed.
        limit: u64,
        /// Whether the limit was set by the caller.
        given: bool,
        /// Planes applied, the last one in part.
        planes_done: usize,
        /// Planes in all.
        planes_total: usize,
        /// The excavation (its index in the spec) whose convex parts outgrew the limit;
        /// `None` when the joints' cuts did.
        excavation: Option<usize>,
    },
    /// The progress callback asked the run to stop (Ctrl-C, an exception in a callback).
    #[error("generation cancelled after {planes_done} of {planes_total} joint planes")]
    Cancelled {
        /// Planes applied.
        planes_done: usize,
        /// Planes in all.
        planes_total: usize,
    },
}

/// When a run outgrew its limit: `after 3 of 9 joint planes`, or `in excavations[0] (after
/// all 9 joint planes)`.
fn outgrew_when(planes_done: usize, planes_total: usize, excavation: Option<usize>) -> String {
    match excavation {
        None => format!("after {planes_done} of {planes_total} joint planes"),
        Some(k) => format!(
            "in the convex parts of excavations[{k}] (after all {planes_total} joint planes)"
        ),
    }
}

fn limit_reason(given: bool) -> &'static str {
    if given {
        " (given)"
    } else {
        " (what half the memory available now holds)"
    }
}

/// A count for people: `1234` below a million, `1.2e12` above.
struct Count(f64);

impl std::fmt::Display for Count {
    /// A count is never below zero: a rounding error of the estimate's sums (`-1e-9`) reads
    /// `0`, not `-0`; one too large for a number (infinite, NaN) reads as such in words.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let value = self.0;
        if value.is_nan() || value == f64::INFINITY {
            f.write_str("more than can be counted")
        } else if value < 1e6 {
            // `max` may keep a zero's sign (`-0.0` against `0.0`): a rounding below zero,
            // or a negative zero, reads 0.
            let count = if value > 0.0 { value.round() } else { 0.0 };
            write!(f, "{count}")
        } else {
            write!(f, "{value:.1e}")
        }
    }
}

/// Bytes for people: `3.2 GB`.
struct Bytes(f64);

impl std::fmt::Display for Bytes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let units = ["bytes", "kB", "MB", "GB", "TB", "PB"];
        let mut value = self.0;
        let mut unit = 0;
        while value >= 1000.0 && unit + 1 < units.len() {
            value /= 1000.0;
            unit += 1;
        }
        write!(f, "{value:.1} {}", units[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::Count;

    #[test]
    fn counts_are_never_negative_zero() {
        assert_eq!(Count(-1e-9).to_string(), "0");
        assert_eq!(Count(-0.0).to_string(), "0");
        assert_eq!(Count(184.4).to_string(), "184");
        assert_eq!(Count(2.5e7).to_string(), "2.5e7");
        assert_eq!(Count(f64::NAN).to_string(), "more than can be counted");
    }
}
