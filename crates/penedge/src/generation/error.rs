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
    /// Too many planes (a spacing far too small for the domain).
    #[error(
        "would make {count} planes, more than the limit of {limit}; is the spacing too small?"
    )]
    TooManyPlanes {
        /// Planes needed.
        count: u64,
        /// The limit.
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
}
