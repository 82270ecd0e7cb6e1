//! The joint table of a generated system: every joint plane that was applied, in order.

use super::orientation::Attitude;
use crate::geometry::{DVec3, Plane};

/// The extent of a joint within its plane.
#[derive(Clone, Debug, PartialEq)]
pub enum JointShape {
    /// An infinite plane: cuts every block it crosses.
    Infinite,
    /// A disc: cuts a block only where it crosses it completely.
    Disc {
        /// Centre (on the plane).
        center: DVec3,
        /// Radius.
        radius: f64,
    },
    /// A convex polygon: cuts a block only where it crosses it completely.
    Polygon {
        /// Vertices, counter-clockwise about the plane's normal.
        vertices: Vec<DVec3>,
    },
}

/// One joint plane as applied: member `member` of discontinuity `set` of the spec.
#[derive(Clone, Debug, PartialEq)]
pub struct JointRecord {
    /// Index of the discontinuity (plane, joint set, disc or polygon) in the spec.
    pub set: u32,
    /// Index within the set, in the order of position along the set's normal.
    pub member: u32,
    /// The plane, with its upward normal (`normal.z >= 0`).
    pub plane: Plane,
    /// Infinite, disc or polygon.
    pub shape: JointShape,
}

impl JointRecord {
    /// Dip and dip direction of the plane; `None` for a zero or non-finite normal, which
    /// the generators never record but a hand-built record can hold (the fields are public).
    pub fn attitude(&self) -> Option<Attitude> {
        Attitude::from_normal(self.plane.normal)
    }

    /// Whether the joint is finite (a disc or polygon).
    pub fn is_finite(&self) -> bool {
        !matches!(self.shape, JointShape::Infinite)
    }
}

/// What kind of discontinuity a spec entry is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SetKind {
    /// A single infinite plane.
    Plane,
    /// A joint set of parallel (or randomly deviated) infinite planes.
    Set,
    /// A finite disc-shaped joint.
    Disc,
    /// A finite convex polygonal joint.
    Polygon,
    /// An excavation (tunnel, cavern, shaft): its faces are free faces of the rock, one
    /// joint record per face of its convex regions.
    Excavation,
}

/// A discontinuity of the spec, as recorded in the system: its name and kind.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SetRecord {
    /// The name given in the spec (or `"joints[i]"`).
    pub name: String,
    /// Plane, set, disc or polygon.
    pub kind: SetKind,
}

/// An upward normal: `n` or `-n`, whichever has `z > 0` (or, for a horizontal normal, the
/// first non-zero component positive).
pub fn upward(n: DVec3) -> DVec3 {
    let key = if n.z != 0.0 {
        n.z
    } else if n.y != 0.0 {
        n.y
    } else {
        n.x
    };
    if key < 0.0 {
        -n
    } else {
        n
    }
}
