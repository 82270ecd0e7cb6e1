//! The two families of hexahedra: unit cubes and "rock-like" perturbed boxes.

use crate::rng::SplitMix64;
use glam::DVec3;
use penedge::ConvexBlock;

/// A family of reference blocks, each in its own body frame (centred near the origin).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// The unit cube `[-0.5, 0.5]^3`.
    Cube,
    /// A unit box whose six face planes are tilted (up to about 14 degrees) and shifted
    /// (up to 30 % of the half width) at random: a convex hexahedron with no parallel faces.
    Rock,
}

impl Family {
    /// Both families, in table order.
    pub const ALL: [Family; 2] = [Family::Cube, Family::Rock];

    /// The name in tables and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Family::Cube => "cube",
            Family::Rock => "rock",
        }
    }

    /// A reference block of this family.
    pub fn block(self, rng: &mut SplitMix64) -> ConvexBlock {
        match self {
            Family::Cube => {
                ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).expect("the unit cube is valid")
            }
            Family::Rock => rock(rng),
        }
    }
}

/// A random convex hexahedron with 8 vertices, 12 edges and 6 faces.
fn rock(rng: &mut SplitMix64) -> ConvexBlock {
    loop {
        let mut normals = Vec::with_capacity(6);
        let mut offsets = Vec::with_capacity(6);
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            for sign in [1.0, -1.0] {
                let n = axis * sign + rng.point_in_cube(0.25);
                normals.push(n.normalize().to_array());
                offsets.push(0.5 * rng.range(0.7, 1.3));
            }
        }
        if let Ok(block) = ConvexBlock::from_planes(&normals, &offsets) {
            if block.vertices().len() == 8 && block.n_faces() == 6 {
                return block;
            }
        }
    }
}
