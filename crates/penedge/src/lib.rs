//! # penedge
//!
//! Contact detection between convex rock blocks by the **penetration-edge method**
//! (Chen, Zheng, Cheng, Ge 2004): every edge of block A is clipped by the face planes of
//! block B widened by a gap, and vice versa; the surviving pieces (the *penetration edges*)
//! tell whether the blocks touch and which of the seven contact types it is
//! ([`ContactType`]: vertex-vertex, vertex-edge, edge-edge, edge-edge superposition,
//! vertex-face, edge-face, face-face), or that they are separated or penetrate deeper than
//! the gap ([`PairResult`]).
//!
//! ## A first example
//!
//! Two unit cubes side by side share a face; a third cube touches the second one along an
//! edge:
//!
//! ```
//! use penedge::{detect_pair, ContactType, ConvexBlock, PairResult, Tolerance};
//!
//! let a = ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap();
//! let b = ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
//! let c = ConvexBlock::cuboid([2.0, 1.0, 0.0], [3.0, 2.0, 1.0]).unwrap();
//! let tol = Tolerance::default(); // a relative gap of 1e-12: rounding only
//!
//! let ab = detect_pair(&a, &b, &tol);
//! println!("a-b: {}", ab.name()); // a-b: face-face
//! assert_eq!(ab.contact_type(), Some(ContactType::FaceFace));
//! if let PairResult::Contact(contact) = ab {
//!     println!("features: {:?} of a, {:?} of b", contact.feature_a, contact.feature_b);
//! }
//! assert_eq!(
//!     detect_pair(&b, &c, &tol).contact_type(),
//!     Some(ContactType::EdgeEdgeSuperposition)
//! );
//! assert_eq!(detect_pair(&a, &c, &tol), PairResult::Separated);
//! ```
//!
//! A block system finds every contact at once, in parallel; with the geometry, each
//! contact also gets its normal, signed distance, area and contact points
//! ([`contact_geometry`]):
//!
//! ```
//! use penedge::system::{paper_example, PaperExample};
//! use penedge::{ContactType, Tolerance};
//!
//! let system = paper_example(PaperExample::Three).unwrap(); // 26 blocks
//! let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
//! assert_eq!(found.contacts.len(), 325); // the paper's Table 3
//! let face_face = found
//!     .contacts
//!     .iter()
//!     .filter(|c| c.contact.kind == ContactType::FaceFace)
//!     .count();
//! assert_eq!(face_face, 42);
//! let area: f64 = geometry.areas.iter().sum(); // the six cuts: 300 + 300 sqrt(2)
//! assert!((area - 300.0 * (1.0 + 2f64.sqrt())).abs() < 1e-9);
//! ```
//!
//! ## Modules
//!
//! The data flows block system -> candidate pairs -> penetration edges -> contacts:
//!
//! * [`block`]: convex blocks (vertices, edges, faces, planes) built and validated from
//!   vertices + faces or from half-spaces;
//! * [`body`]: a body's convex parts in its own frame (centroid, principal axes) and its
//!   exact mass properties (`docs/bodies.md`);
//! * [`tolerance`]: the one tolerance policy (gap and length thresholds relative to block size);
//! * [`penetration`]: penetration edges of a pair (paper section 3.3, Table 1);
//! * [`classify`]: contact decision and the seven contact types (paper sections 3.1, 3.4);
//! * [`contact`]: the pair query that ties them together ([`detect_pair`], [`Detector`]);
//! * [`contact_geometry`]: normal, contact points, area and signed distance of a contact;
//! * [`overlap`]: normal, depth and region of two penetrating blocks (soft-contact mechanics);
//! * [`cutting`]: splitting a block by a plane;
//! * [`generation`]: rock domains cut into blocks by joint planes, joint sets and finite
//!   joints, from a spec;
//! * [`system`]: block systems (a box cut by planes, the paper's examples) and all-pairs
//!   detection;
//! * [`mechanics`]: rigid-block mechanics (3DEC-style distinct elements) on the contacts:
//!   bodies, sub-contacts with a Mohr-Coulomb joint law, time stepping (`docs/mechanics.md`);
//! * [`io`]: files: the spec (TOML, JSON), the block file (JSON), ParaView (blocks VTU,
//!   contacts VTP, time series PVD: [`io::pvd::TimeSeries`]) and CSV tables.
//!
//! Conventions: right-handed frame, faces counter-clockwise seen from outside, face normals
//! point outwards, a signed distance `s = n · (x - p)` is positive outside a face plane.
//!
//! The Python package (`pip install .`, module `penedge`) wraps this crate; the user guide
//! is in the repository's `README.md` and `docs/`.
#![warn(missing_docs)]

pub mod block;
pub mod body;
pub mod classify;
pub mod contact;
pub mod contact_geometry;
pub mod cutting;
#[doc(hidden)]
pub mod fuzzing;
pub mod generation;
pub mod geometry;
pub mod io;
pub mod mechanics;
pub mod overlap;
pub mod penetration;
pub mod system;
pub mod tolerance;

pub use block::{BlockError, ConvexBlock};
pub use classify::{ContactType, Feature, PairResult};
pub use contact::{detect_pair, Detector};
/// The vector and quaternion types of the API ([`geometry::DVec3`], [`block::Pose`]).
pub use glam;
pub use system::BlockSystem;
pub use tolerance::Tolerance;
