//! The rock domain that joints cut: a union of convex parts.
//!
//! Today a domain is one convex polyhedron (a box, vertices and faces, or half-spaces). The
//! type holds a list of parts so that non-convex domains (a slope profile extruded along
//! strike, a tunnel opening) can come as unions of non-overlapping convex parts without a
//! change of interface: cutting works part by part, and boundary faces are tagged with their
//! part and face.

use crate::block::{BlockError, ConvexBlock, FaceOrigin};
use crate::geometry::Aabb;

/// A rock domain; every face of every part is tagged [`FaceOrigin::Boundary`].
#[derive(Clone, Debug)]
pub struct Domain {
    parts: Vec<ConvexBlock>,
}

impl Domain {
    /// The box with corners `min` and `max`.
    pub fn cuboid(min: [f64; 3], max: [f64; 3]) -> Result<Domain, BlockError> {
        Ok(Domain::convex(ConvexBlock::cuboid(min, max)?))
    }

    /// A convex polyhedron given by vertices and faces (counter-clockwise seen from outside).
    pub fn from_vertices_faces<F: AsRef<[usize]>>(
        vertices: &[[f64; 3]],
        faces: &[F],
    ) -> Result<Domain, BlockError> {
        Ok(Domain::convex(ConvexBlock::new(vertices, faces)?))
    }

    /// The convex polyhedron `{x : normals[i] · x <= offsets[i]}`.
    pub fn from_halfspaces(normals: &[[f64; 3]], offsets: &[f64]) -> Result<Domain, BlockError> {
        Ok(Domain::convex(ConvexBlock::from_planes(normals, offsets)?))
    }

    /// A convex domain: the block, its faces tagged as boundary faces of part 0.
    pub fn convex(block: ConvexBlock) -> Domain {
        let tags = (0..block.n_faces() as u32)
            .map(|face| FaceOrigin::Boundary { part: 0, face })
            .collect();
        let block = block
            .with_face_origins(tags)
            .expect("one tag per face by construction");
        Domain { parts: vec![block] }
    }

    /// The convex parts.
    pub fn parts(&self) -> &[ConvexBlock] {
        &self.parts
    }

    /// Total volume.
    pub fn volume(&self) -> f64 {
        self.parts.iter().map(ConvexBlock::volume).sum()
    }

    /// Bounding box of all parts.
    pub fn aabb(&self) -> Aabb {
        let mut b = self.parts[0].aabb();
        for p in &self.parts[1..] {
            b.min = b.min.min(p.aabb().min);
            b.max = b.max.max(p.aabb().max);
        }
        b
    }

    /// Characteristic length: the diagonal of the bounding box.
    pub fn size(&self) -> f64 {
        self.aabb().diagonal()
    }
}
