//! Building a [`ConvexBlock`] from everything a block file stores, without recomputing it.

use super::build::{check_face_lists, check_points};
use super::{BlockError, BlockParts, ConvexBlock, FaceOrigin};
use crate::geometry::Plane;
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
        let points = check_points(vertices)?;
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
        check_on_planes(&block, tol.for_box(&block.aabb()).length)?;
        Ok(block)
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
fn check_on_planes(block: &ConvexBlock, eps: f64) -> Result<(), BlockError> {
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
