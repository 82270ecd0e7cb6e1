//! What to generate: a domain, the discontinuities that cut it (in order), and options.
//!
//! The same structure is built by the Rust API (below), by the TOML spec file and by JSON
//! (see [`crate::io::spec`]); it is checked once, by [`crate::generation::generate`], and
//! each error names the field as a path into the spec (`joints[2].dip`).

use super::domain::Domain;
use super::excavation::Excavation;
use super::orientation::Attitude;
use crate::tolerance::Tolerance;

/// A generation spec.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The rock domain.
    pub domain: Domain,
    /// Discontinuities, applied in this order.
    pub joints: Vec<Discontinuity>,
    /// Excavations (tunnels, caverns, shafts), applied in this order after the joints.
    pub excavations: Vec<Excavation>,
    /// Tolerance and sliver options.
    pub options: Options,
    /// The length unit of the spec's coordinates and spacings (`"m"`, `"ft"`), for labels
    /// only: penedge computes in whatever unit the numbers are. Carried into the system and
    /// its block file.
    pub unit: Option<String>,
}

impl Spec {
    /// A spec with no joints and default options.
    pub fn new(domain: Domain) -> Spec {
        Spec {
            domain,
            joints: Vec::new(),
            excavations: Vec::new(),
            options: Options::default(),
            unit: None,
        }
    }

    /// The spec with one more excavation, applied after the joints and the other
    /// excavations.
    pub fn excavate(mut self, excavation: Excavation) -> Spec {
        self.excavations.push(excavation);
        self
    }

    /// The spec with one more discontinuity, applied after the others.
    pub fn with(mut self, joint: Discontinuity) -> Spec {
        self.joints.push(joint);
        self
    }
}

/// One entry of the joint list: a plane, a joint set, a disc or a polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Discontinuity {
    /// A name for reports and files (`"joints[i]"` when `None`).
    pub name: Option<String>,
    /// What it is.
    pub kind: JointKind,
    /// For a disc or polygon: cut every block the joint ends inside through along the
    /// joint's plane and tag the uncut part as rock-bridge faces ([`FaceOrigin::Bridge`],
    /// docs/generation.md, "Rock bridges"); `false` (the default): such a block is left
    /// whole.
    ///
    /// [`FaceOrigin::Bridge`]: crate::block::FaceOrigin::Bridge
    pub bridge: bool,
}

/// The kinds of discontinuity.
#[derive(Clone, Debug, PartialEq)]
pub enum JointKind {
    /// An infinite plane through `point`.
    Plane {
        /// A point of the plane.
        point: [f64; 3],
        /// Its orientation.
        orientation: Orientation,
    },
    /// A joint set.
    Set(JointSet),
    /// A finite disc-shaped joint.
    Disc {
        /// Centre.
        center: [f64; 3],
        /// Orientation of its plane.
        orientation: Orientation,
        /// Radius (> 0).
        radius: f64,
    },
    /// A finite convex polygonal joint (vertices in order, either sense, in one plane).
    Polygon {
        /// Vertices.
        vertices: Vec<[f64; 3]>,
    },
}

/// A plane's orientation: a normal (either sense, any length) or dip and dip direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Orientation {
    /// A normal vector.
    Normal([f64; 3]),
    /// Dip and dip direction in degrees.
    Attitude(Attitude),
}

impl Orientation {
    /// Dip and dip direction in degrees.
    pub fn dip(dip: f64, dip_direction: f64) -> Orientation {
        Orientation::Attitude(Attitude::new(dip, dip_direction))
    }
}

/// A joint set, as in 3DEC's `block cut joint-set`: planes with one orientation at a given
/// spacing, the first through `origin`.
///
/// With `number = Some(n)`, the planes are at `origin + k * spacing * n̂` for `k = 0..n`
/// (`n̂` the upward normal); with `None` the set fills the domain (`k` over all integers
/// whose plane meets the domain). Random deviations are uniform in `[-d, d]`: each plane's
/// dip and dip direction are drawn around the set's, and each gap between neighbouring
/// planes around `spacing`; a seed gives the same set on every platform.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSet {
    /// Orientation of the set (the mean, with deviations).
    pub orientation: Orientation,
    /// A point of the first plane.
    pub origin: [f64; 3],
    /// Distance between neighbouring planes (> 0).
    pub spacing: f64,
    /// Number of planes, or `None` to fill the domain.
    pub number: Option<u32>,
    /// Random deviations (all zero: a regular set).
    pub deviation: Deviation,
    /// Seed of the random deviations.
    pub seed: u64,
}

impl JointSet {
    /// A regular set filling the domain, through the origin of coordinates.
    pub fn new(orientation: Orientation, spacing: f64) -> JointSet {
        JointSet {
            orientation,
            origin: [0.0; 3],
            spacing,
            number: None,
            deviation: Deviation::default(),
            seed: 0,
        }
    }
}

/// Half-widths of the uniform random deviations of a joint set.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Of the dip, in degrees.
    pub dip: f64,
    /// Of the dip direction, in degrees.
    pub dip_direction: f64,
    /// Of each spacing (smaller than the spacing).
    pub spacing: f64,
}

impl Discontinuity {
    /// An infinite plane.
    pub fn plane(point: [f64; 3], orientation: Orientation) -> Self {
        Self::unnamed(JointKind::Plane { point, orientation })
    }

    /// A joint set.
    pub fn set(set: JointSet) -> Self {
        Self::unnamed(JointKind::Set(set))
    }

    /// A disc-shaped finite joint.
    pub fn disc(center: [f64; 3], orientation: Orientation, radius: f64) -> Self {
        Self::unnamed(JointKind::Disc {
            center,
            orientation,
            radius,
        })
    }

    /// A convex polygonal finite joint.
    pub fn polygon(vertices: Vec<[f64; 3]>) -> Self {
        Self::unnamed(JointKind::Polygon { vertices })
    }

    /// The same finite joint with rock bridges ([`Discontinuity::bridge`]).
    pub fn with_bridges(mut self) -> Self {
        self.bridge = true;
        self
    }

    /// The same discontinuity with a name.
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    fn unnamed(kind: JointKind) -> Self {
        Discontinuity {
            name: None,
            kind,
            bridge: false,
        }
    }
}

/// What to do with slivers: blocks thinner than `min_thickness` or smaller than `min_volume`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SliverPolicy {
    /// Keep them, and list them in the report.
    #[default]
    Keep,
    /// Drop them, and report how many and how much volume.
    Drop,
}

/// Generation options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// The tolerance policy: its length threshold, relative to the domain's size, is the
    /// distance within which a vertex lies on a cutting plane.
    pub tolerance: Tolerance,
    /// Blocks with a smaller volume are slivers (default 0: none).
    pub min_volume: f64,
    /// Blocks thinner than this are slivers (default: 1e-6 of the domain's size).
    pub min_thickness: Option<f64>,
    /// Keep or drop slivers; either way they are counted.
    pub slivers: SliverPolicy,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tolerance: Tolerance::default(),
            min_volume: 0.0,
            min_thickness: None,
            slivers: SliverPolicy::Keep,
        }
    }
}

/// The default minimum thickness, relative to the domain's size.
pub const DEFAULT_MIN_THICKNESS: f64 = 1e-6;

/// The most joint planes one spec may make.
pub const MAX_PLANES: u64 = 1_000_000;
