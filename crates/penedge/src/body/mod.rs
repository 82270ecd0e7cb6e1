//! Bodies' geometry in their own frames: shapes made of convex parts, and their mass
//! properties (see `docs/bodies.md` for why blocks are stored this way).
//!
//! A [`Shape`] holds a body's convex parts with the origin at the body's centroid and the axes
//! along its principal axes of inertia; a [`crate::block::Pose`] places it in the world. The
//! mechanics keeps one pose per body; the detection runs on the parts placed at the poses.
//!
//! ```
//! use penedge::body::Shape;
//! use penedge::ConvexBlock;
//! // A 2 x 1 x 1 brick with its corner at (10, 20, 30).
//! let brick = ConvexBlock::cuboid([10.0, 20.0, 30.0], [12.0, 21.0, 31.0]).unwrap();
//! let (shape, pose) = Shape::from_parts(&[brick]).unwrap();
//! assert!((pose.translation - penedge::glam::DVec3::new(11.0, 20.5, 30.5)).length() < 1e-12);
//! // Principal moments per unit density, ascending: V (b² + c²) / 12 with the long side first.
//! let expected = [2.0 * (1.0 + 1.0) / 12.0, 2.0 * (4.0 + 1.0) / 12.0, 2.0 * (4.0 + 1.0) / 12.0];
//! for (m, e) in shape.principal_moments().to_array().iter().zip(expected) {
//!     assert!((m - e).abs() < 1e-12);
//! }
//! ```

mod mass;
mod shape;

pub use mass::{principal_axes, MassProperties, Principal};
pub use shape::Shape;

use thiserror::Error;

/// Why a body cannot be made.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum BodyError {
    /// A body needs at least one convex part.
    #[error("a body needs at least one convex part")]
    NoParts,
    /// The parts' centroid or principal axes are not finite.
    #[error("the body's centroid or principal axes are not finite")]
    NotFinite,
}
