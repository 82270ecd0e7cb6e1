//! Building a [`ConvexBlock`] from everything a block file stores, without recomputing it.

use super::build::{check_face_lists, check_points, check_range};
use super::{BlockError, BlockParts, ConvexBlock, Edge, FaceOrigin};
use crate::geometry::{Aabb, Plane};
use crate::tolerance::Tolerance;

impl ConvexBlock {
    /// A block from vertices, faces (counter-clockwise seen from outside), one outward unit
    /// plane and one origin per face, as stored by a block file: the planes are kept as given
    /// (not refitted), so a block written and read back is the same block, bit for bit.
    ///
    /// Checks the input shape, a closed consistently oriented surface with corners only,
    /// unit normals, every face vertex within `tol.length()` (relative to the block's size)
    /// of its plane and every vertex inside every plane.
    pub fn from_parts<F: AsRef<[u32]>>(
        vertices: &[[f64; 3]],
        faces: &[F],
        planes: &[Plane],
        origins: &[FaceOrigin],
        tol: &Tolerance,
    ) -> Result<ConvexBlock, BlockError> {
        ConvexBlock::from_parts_in(vertices, faces, planes, origins, tol, None)
    }

    /// [`ConvexBlock::from_parts`] for a block of a system whose bounding box is `system`:
    /// the length threshold is taken at the scale of the system's box (with the block's)
    /// rather than at the block's own. The blocks of a generated system (and the pieces of
    /// [`crate::cutting::split_block`]) were cut with the threshold at the domain's scale
    /// (the parent block's): a vertex within it of a cutting plane goes on the cap as it is,
    /// which can be farther from the cap's plane than a small piece's own threshold.
    pub fn from_parts_in<F: AsRef<[u32]>>(
        vertices: &[[f64; 3]],
        faces: &[F],
        planes: &[Plane],
        origins: &[FaceOrigin],
        tol: &Tolerance,
        system: Option<&Aabb>,
    ) -> Result<ConvexBlock, BlockError> {
        let points = check_points(vertices)?;
        check_range(&points)?;
        let lists: Vec<Vec<usize>> = faces
            .iter()
            .map(|f| f.as_ref().iter().map(|&v| v as usize).collect())
            .collect();
        check_face_lists(&lists, points.len())?;
        for given in [planes.len(), origins.len()] {
            if given != faces.len() {
                return Err(BlockError::OriginCount {
                    expected: faces.len(),
                    got: given,
                });
            }
        }
        check_unit_planes(planes, tol)?;
        let mut parts = BlockParts {
            vertices: points,
            face_offsets: vec![0],
            planes: planes.to_vec(),
            origins: origins.to_vec(),
            ..BlockParts::default()
        };
        for f in faces {
            parts.face_vertices.extend_from_slice(f.as_ref());
            parts.face_offsets.push(parts.face_vertices.len() as u32);
        }
        check_corners(&parts)?;
        let block = ConvexBlock::assemble(parts)?;
        let mut scale = block.aabb();
        if let Some(system) = system {
            scale.min = scale.min.min(system.min);
            scale.max = scale.max.max(system.max);
        }
        check_on_planes(&block, tol.for_box(&scale).length)?;
        Ok(block)
    }
}

impl ConvexBlock {
    /// This block (as [`ConvexBlock::from_parts`] rebuilt it) with its edges, volume and
    /// centroid as stored by a restart file (`mechanics::state`): a body-frame part was made
    /// by [`ConvexBlock::transformed`], which keeps the edges' order and transforms the
    /// centroid rather than recomputing them, and the detection reads both (feature ids,
    /// normals), so a resumed run needs them bit for bit. The stored edges must be this
    /// block's edges (in any order) and the volume within `1e-9` of its own, relatively;
    /// the centroid must be finite (the caller checks its distance).
    pub(crate) fn with_stored(
        mut self,
        edges: Vec<Edge>,
        volume: f64,
        centroid: crate::geometry::DVec3,
    ) -> Result<ConvexBlock, String> {
        let key = |e: &Edge| (e.vertices, e.faces);
        let (mut given, mut own) = (edges.clone(), self.edges.clone());
        given.sort_by_key(key);
        own.sort_by_key(key);
        if given != own {
            return Err("the edges are not those of the block's faces".into());
        }
        if !(volume.is_finite() && (volume - self.volume).abs() <= 1e-9 * self.volume) {
            return Err(format!(
                "the volume {volume} is not the block's ({})",
                self.volume
            ));
        }
        if !centroid.is_finite() {
            return Err("the centroid is not finite".into());
        }
        self.edges = edges;
        self.volume = volume;
        self.centroid = centroid;
        Ok(self)
    }
}

fn check_unit_planes(planes: &[Plane], tol: &Tolerance) -> Result<(), BlockError> {
    for (face, p) in planes.iter().enumerate() {
        let unit = (p.normal.length() - 1.0).abs() <= tol.length();
        if !(unit && p.normal.is_finite() && p.point.is_finite()) {
            return Err(BlockError::BadPlane { face });
        }
    }
    Ok(())
}

fn check_corners(parts: &BlockParts) -> Result<(), BlockError> {
    let mut degree = vec![0u32; parts.vertices.len()];
    for &v in &parts.face_vertices {
        degree[v as usize] += 1;
    }
    match degree.iter().position(|&d| d < 3) {
        Some(vertex) => Err(BlockError::NotACorner { vertex }),
        None => Ok(()),
    }
}

/// Every face vertex on its plane, every vertex inside every plane, within `eps`.
pub(super) fn check_on_planes(block: &ConvexBlock, eps: f64) -> Result<(), BlockError> {
    for (face, plane) in block.planes().iter().enumerate() {
        for &v in block.face(face) {
            let distance = plane.distance(block.vertices()[v as usize]);
            if distance.abs() > eps {
                let vertex = v as usize;
                return Err(BlockError::NonPlanarFace {
                    face,
                    vertex,
                    distance,
                });
            }
        }
        for (vertex, &p) in block.vertices().iter().enumerate() {
            let distance = plane.distance(p);
            if distance > eps {
                return Err(BlockError::NotConvex {
                    face,
                    vertex,
                    distance,
                });
            }
        }
    }
    Ok(())
}
