//! Splitting single blocks: volumes, faces, planes and origins of the pieces.

use super::*;

fn plane(normal: [f64; 3], point: [f64; 3]) -> Plane {
    Plane {
        normal: DVec3::from_array(normal).normalize(),
        point: DVec3::from_array(point),
    }
}

#[test]
fn splitting_a_cube_in_half_keeps_volume() {
    let cube = ConvexBlock::cuboid([0.0; 3], [2.0; 3]).unwrap();
    let p = plane([1.0, 1.0, 0.0], [1.0; 3]);
    let split = split_block(&cube, &p, &Tolerance::default()).unwrap();
    let (lo, hi) = (split.below.unwrap(), split.above.unwrap());
    assert!((lo.volume() - 4.0).abs() < 1e-12 && (hi.volume() - 4.0).abs() < 1e-12);
    assert_eq!((lo.n_faces(), hi.n_faces()), (5, 5));
}

#[test]
fn a_plane_through_a_face_leaves_the_block_whole() {
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let p = plane([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let split = split_block(&cube, &p, &Tolerance::default()).unwrap();
    assert!(split.below.is_some() && split.above.is_none());
}

#[test]
fn a_plane_through_a_vertex_cuts_the_opposite_edges() {
    // The plane x + y = 1 passes through the edges (1,0,*) and (0,1,*) of the unit cube.
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let p = plane([1.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
    let split = split_block(&cube, &p, &Tolerance::default()).unwrap();
    let (lo, hi) = (split.below.unwrap(), split.above.unwrap());
    assert_eq!((lo.vertices().len(), hi.vertices().len()), (6, 6));
    assert!((lo.volume() - 0.5).abs() < 1e-12);
}

#[test]
fn a_plane_through_one_corner_only_makes_a_tetrahedron() {
    // x + y + z = 1 passes through three corners of the unit cube.
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let p = plane([1.0, 1.0, 1.0], [1.0, 0.0, 0.0]);
    let split = split_block(&cube, &p, &Tolerance::default()).unwrap();
    let (lo, hi) = (split.below.unwrap(), split.above.unwrap());
    assert_eq!((lo.vertices().len(), lo.n_faces()), (4, 4));
    assert_eq!((hi.vertices().len(), hi.n_faces()), (7, 7));
    assert!((lo.volume() - 1.0 / 6.0).abs() < 1e-15);
    assert!((lo.volume() + hi.volume() - 1.0).abs() < 1e-15);
}

#[test]
fn pieces_keep_parent_planes_and_get_the_cut_origin() {
    let cube = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let tags: Vec<FaceOrigin> = (0..6)
        .map(|face| FaceOrigin::Boundary { part: 0, face })
        .collect();
    let cube = cube.with_face_origins(tags).unwrap();
    let p = plane([0.3, 0.2, 1.0], [0.5, 0.5, 0.5]);
    let mut splitter = Splitter::default();
    assert_eq!(splitter.prepare(&cube, &p, 1e-12).unwrap(), Side::Across);
    let section: Vec<DVec3> = splitter.section().collect();
    assert_eq!(section.len(), 4);
    let cut = FaceOrigin::Joint { set: 2, joint: 7 };
    let [lo, hi] = splitter.finish(cut).unwrap();
    for piece in [&lo, &hi] {
        let caps: Vec<usize> = (0..piece.n_faces())
            .filter(|&f| piece.face_origins()[f] == cut)
            .collect();
        assert_eq!(caps.len(), 1);
        for (f, pl) in piece.planes().iter().enumerate() {
            if piece.face_origins()[f] != cut {
                assert!(cube.planes().contains(pl), "a parent plane is kept exactly");
            }
            for &v in piece.face(f) {
                assert!(pl.distance(piece.vertices()[v as usize]).abs() < 1e-15);
            }
        }
    }
    assert_eq!(lo.planes()[lo.n_faces() - 1].normal, p.normal);
    assert_eq!(hi.planes()[hi.n_faces() - 1].normal, -p.normal);
    assert!((lo.volume() + hi.volume() - 1.0).abs() < 1e-15);
}

#[test]
fn neighbours_get_the_same_cut_points() {
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let b = ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
    let p = plane([0.1, 0.37, 1.0], [0.9, 0.4, 0.55]);
    let (sa, sb) = (
        split_block(&a, &p, &Tolerance::default()).unwrap(),
        split_block(&b, &p, &Tolerance::default()).unwrap(),
    );
    let on_x1 = |blk: &ConvexBlock| -> Vec<[f64; 3]> {
        let mut v: Vec<[f64; 3]> = blk
            .vertices()
            .iter()
            .filter(|v| v.x == 1.0)
            .map(|v| v.to_array())
            .collect();
        v.sort_by(|p, q| p.partial_cmp(q).unwrap());
        v
    };
    assert_eq!(
        on_x1(sa.below.as_ref().unwrap()),
        on_x1(sb.below.as_ref().unwrap())
    );
}
