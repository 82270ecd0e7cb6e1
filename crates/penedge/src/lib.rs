//! # penedge
//!
//! Contact detection between convex rock blocks by the **penetration-edge method**
//! (Chen, Zheng, Cheng, Ge 2004): every edge of block A is clipped by the face planes of
//! block B widened by a gap, and vice versa; the surviving pieces (the *penetration edges*)
//! tell whether the blocks touch and which of the seven contact types it is.
//!
//! The data flows block system -> candidate pairs -> penetration edges -> contacts:
//!
//! * [`block`]: convex blocks (vertices, edges, faces, planes) built and validated from
//!   vertices + faces or from half-spaces;
//! * [`tolerance`]: the one tolerance policy (gap and length thresholds relative to block size);
//! * [`penetration`]: penetration edges of a pair (paper section 3.3, Table 1);
//! * [`classify`]: contact decision and the seven contact types (paper sections 3.1, 3.4);
//! * [`contact`]: the pair query that ties them together;
//! * [`cutting`]: splitting a block by a plane;
//! * [`system`]: block systems (a box cut by planes, the paper's examples) and all-pairs detection.
//!
//! Conventions: right-handed frame, faces counter-clockwise seen from outside, face normals
//! point outwards, a signed distance `s = n · (x - p)` is positive outside a face plane.
//!
//! ```
//! use penedge::{block::ConvexBlock, contact::detect_pair, classify::ContactType, tolerance::Tolerance};
//! let a = ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap();
//! let b = ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
//! let result = detect_pair(&a, &b, &Tolerance::default());
//! assert_eq!(result.contact_type(), Some(ContactType::FaceFace));
//! ```
#![warn(missing_docs)]

pub mod block;
pub mod classify;
pub mod contact;
pub mod contact_geometry;
pub mod cutting;
pub mod generation;
pub mod geometry;
pub mod io;
pub mod penetration;
pub mod system;
pub mod tolerance;

pub use block::{BlockError, ConvexBlock};
pub use classify::{ContactType, Feature, PairResult};
pub use contact::{detect_pair, Detector};
pub use system::BlockSystem;
pub use tolerance::Tolerance;
