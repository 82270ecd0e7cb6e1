//! Where a face of a block comes from: the domain's boundary or a joint.

/// The origin of a face, kept through every cut.
///
/// Generation tags each face: a face of the domain keeps `Boundary` (and so stays a *free*
/// face, on the outside of the rock mass), a face made by a cut gets the `Joint` that made it.
/// Blocks built directly from vertices and faces have `Unknown` faces.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum FaceOrigin {
    /// Not known (a block given by its vertices and faces).
    #[default]
    Unknown,
    /// Face `face` of convex part `part` of the domain.
    Boundary {
        /// Domain part (0 for a convex domain).
        part: u32,
        /// Face index in that part.
        face: u32,
    },
    /// Joint plane `joint` (an index into the system's joint table), a member of the
    /// discontinuity `set` (its index in the generation spec: a joint set, or a single plane
    /// or finite joint, which form a set of one).
    Joint {
        /// Index of the discontinuity in the spec.
        set: u32,
        /// Index of the joint plane in the system's joint table.
        joint: u32,
    },
    /// A rock bridge of the finite joint `joint` (set `set`), generated with bridges on
    /// (docs/generation.md, "Rock bridges"): a face cut through intact rock, on the joint's
    /// plane outside its extent or on a seam that separates the joint's part of a block's
    /// section from the bridge's. The mechanics bonds it with the intact rock's strength.
    Bridge {
        /// Index of the discontinuity in the spec.
        set: u32,
        /// Index of the finite joint in the system's joint table.
        joint: u32,
    },
}

impl FaceOrigin {
    /// Whether the face lies on the domain boundary (a free face of the rock mass).
    pub fn is_boundary(self) -> bool {
        matches!(self, FaceOrigin::Boundary { .. })
    }

    /// The joint set, for a joint face or a rock-bridge face (which lies on the set's joint
    /// plane: once broken it is a fracture of that set).
    pub fn set(self) -> Option<u32> {
        match self {
            FaceOrigin::Joint { set, .. } | FaceOrigin::Bridge { set, .. } => Some(set),
            _ => None,
        }
    }

    /// Whether the face is a rock bridge (intact rock cut through by generation).
    pub fn is_bridge(self) -> bool {
        matches!(self, FaceOrigin::Bridge { .. })
    }

    /// A small integer code: 0 unknown, 1 boundary, 2 joint, 3 bridge (for arrays and VTK
    /// files).
    pub fn code(self) -> u8 {
        match self {
            FaceOrigin::Unknown => 0,
            FaceOrigin::Boundary { .. } => 1,
            FaceOrigin::Joint { .. } => 2,
            FaceOrigin::Bridge { .. } => 3,
        }
    }

    /// The two numbers of the origin: `(part, face)` for a boundary face, `(set, joint)` for
    /// a joint or bridge face, `(-1, -1)` when unknown.
    pub fn ids(self) -> (i64, i64) {
        match self {
            FaceOrigin::Unknown => (-1, -1),
            FaceOrigin::Boundary { part, face } => (part as i64, face as i64),
            FaceOrigin::Joint { set, joint } | FaceOrigin::Bridge { set, joint } => {
                (set as i64, joint as i64)
            }
        }
    }
}
