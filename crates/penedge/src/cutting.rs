//! Splitting a convex block by a plane.
//!
//! Vertices within the length threshold of the plane count as on it and go to both pieces;
//! each edge whose ends lie strictly on opposite sides gets one cut point, shared by the two
//! faces along it; the cap face is the convex polygon of the on-plane vertices and cut points.
//! Each piece is rebuilt (and so validated) as a [`ConvexBlock`].

use crate::block::{BlockError, ConvexBlock};
use crate::geometry::{DVec3, Plane};
use crate::tolerance::Tolerance;
use std::collections::HashMap;

/// The two pieces of a block split by a plane; a side is `None` when nothing of the block
/// lies strictly on it.
#[derive(Clone, Debug)]
pub struct Split {
    /// The piece on the negative side (`normal · (x - point) <= 0`).
    pub below: Option<ConvexBlock>,
    /// The piece on the positive side.
    pub above: Option<ConvexBlock>,
}

/// Splits `block` by `plane` (unit normal).
pub fn split_block(
    block: &ConvexBlock,
    plane: &Plane,
    tol: &Tolerance,
) -> Result<Split, BlockError> {
    let eps = tol.for_box(&block.aabb()).length;
    let side: Vec<i8> = block
        .vertices()
        .iter()
        .map(|&v| {
            let s = plane.distance(v);
            if s < -eps {
                -1
            } else if s > eps {
                1
            } else {
                0
            }
        })
        .collect();
    if !side.contains(&1) {
        return Ok(Split {
            below: Some(block.clone()),
            above: None,
        });
    }
    if !side.contains(&-1) {
        return Ok(Split {
            below: None,
            above: Some(block.clone()),
        });
    }
    let mut points = block.vertices().to_vec();
    let cuts = cut_points(block, plane, &side, &mut points);
    let mut cap: Vec<usize> = (0..side.len()).filter(|&v| side[v] == 0).collect();
    cap.extend(cuts.values().copied());
    let mut below = Vec::new();
    let mut above = Vec::new();
    for face in block.faces() {
        let (lo, hi) = split_face(face, &side, &cuts);
        below.extend((lo.len() >= 3).then_some(lo));
        above.extend((hi.len() >= 3).then_some(hi));
    }
    below.push(crate::block::sort_ccw(&points, cap.clone(), plane.normal));
    above.push(crate::block::sort_ccw(&points, cap, -plane.normal));
    Ok(Split {
        below: Some(piece(&points, below, tol)?),
        above: Some(piece(&points, above, tol)?),
    })
}

/// One cut point per edge crossing the plane strictly, keyed by the edge's vertex pair.
fn cut_points(
    block: &ConvexBlock,
    plane: &Plane,
    side: &[i8],
    points: &mut Vec<DVec3>,
) -> HashMap<(u32, u32), usize> {
    let mut cuts = HashMap::new();
    for e in block.edges() {
        let [a, b] = e.vertices;
        if side[a as usize] * side[b as usize] < 0 {
            let (p, q) = (block.vertices()[a as usize], block.vertices()[b as usize]);
            let (sp, sq) = (plane.distance(p), plane.distance(q));
            cuts.insert((a.min(b), a.max(b)), points.len());
            points.push(p + (q - p) * (sp / (sp - sq)));
        }
    }
    cuts
}

fn split_face(
    face: &[u32],
    side: &[i8],
    cuts: &HashMap<(u32, u32), usize>,
) -> (Vec<usize>, Vec<usize>) {
    let (mut lo, mut hi) = (Vec::new(), Vec::new());
    for k in 0..face.len() {
        let (a, b) = (face[k], face[(k + 1) % face.len()]);
        let sa = side[a as usize];
        if sa <= 0 {
            lo.push(a as usize);
        }
        if sa >= 0 {
            hi.push(a as usize);
        }
        if let Some(&c) = cuts.get(&(a.min(b), a.max(b))) {
            lo.push(c);
            hi.push(c);
        }
    }
    (lo, hi)
}

/// Builds one piece from the shared point list, keeping only the points it uses.
fn piece(
    points: &[DVec3],
    faces: Vec<Vec<usize>>,
    tol: &Tolerance,
) -> Result<ConvexBlock, BlockError> {
    let mut remap: HashMap<usize, usize> = HashMap::new();
    let mut coords = Vec::new();
    let faces: Vec<Vec<usize>> = faces
        .into_iter()
        .map(|f| {
            f.into_iter()
                .map(|v| {
                    *remap.entry(v).or_insert_with(|| {
                        coords.push(points[v].to_array());
                        coords.len() - 1
                    })
                })
                .collect()
        })
        .collect();
    ConvexBlock::with_tolerance(&coords, &faces, tol)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitting_a_cube_in_half_keeps_volume() {
        let cube = ConvexBlock::cuboid([0.0; 3], [2.0; 3]).unwrap();
        let plane = Plane {
            normal: DVec3::new(1.0, 1.0, 0.0).normalize(),
            point: DVec3::splat(1.0),
        };
        let split = split_block(&cube, &plane, &Tolerance::default()).unwrap();
        let (lo, hi) = (split.below.unwrap(), split.above.unwrap());
        assert!((lo.volume() - 4.0).abs() < 1e-12 && (hi.volume() - 4.0).abs() < 1e-12);
        assert_eq!((lo.n_faces(), hi.n_faces()), (5, 5));
    }

    #[test]
    fn a_plane_through_a_face_leaves_the_block_whole() {
        let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let plane = Plane {
            normal: DVec3::X,
            point: DVec3::X,
        };
        let split = split_block(&cube, &plane, &Tolerance::default()).unwrap();
        assert!(split.below.is_some() && split.above.is_none());
    }

    #[test]
    fn a_plane_through_a_vertex_cuts_the_opposite_edges() {
        // The plane x + y = 1 passes through vertices (1,0,*) and (0,1,*) of the unit cube.
        let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let plane = Plane {
            normal: DVec3::new(1.0, 1.0, 0.0).normalize(),
            point: DVec3::new(1.0, 0.0, 0.0),
        };
        let split = split_block(&cube, &plane, &Tolerance::default()).unwrap();
        let (lo, hi) = (split.below.unwrap(), split.above.unwrap());
        assert_eq!((lo.vertices().len(), hi.vertices().len()), (6, 6));
        assert!((lo.volume() - 0.5).abs() < 1e-12);
    }
}
