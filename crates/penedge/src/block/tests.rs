//! Block construction and validation: each error names what is wrong.

use super::*;

fn cube_vertices() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ]
}

fn cube_faces() -> Vec<Vec<usize>> {
    vec![
        vec![0, 3, 2, 1],
        vec![4, 5, 6, 7],
        vec![0, 1, 5, 4],
        vec![1, 2, 6, 5],
        vec![2, 3, 7, 6],
        vec![3, 0, 4, 7],
    ]
}

fn build(v: &[[f64; 3]], f: &[Vec<usize>]) -> Result<ConvexBlock, BlockError> {
    ConvexBlock::new(v, f)
}

#[test]
fn cube_has_its_derived_data() {
    let b = build(&cube_vertices(), &cube_faces()).unwrap();
    assert_eq!(
        (b.vertices().len(), b.edges().len(), b.n_faces()),
        (8, 12, 6)
    );
    assert!((b.volume() - 1.0).abs() < 1e-15);
    assert!(b.centroid().distance(DVec3::splat(0.5)) < 1e-15);
    assert!((b.size() - 3f64.sqrt()).abs() < 1e-15);
    for (f, plane) in b.planes().iter().enumerate() {
        assert!((plane.normal.length() - 1.0).abs() < 1e-15);
        // Outward: the centroid is inside.
        assert!(plane.distance(b.centroid()) < 0.0, "face {f}");
    }
    for e in b.edges() {
        let [f, g] = e.faces;
        assert_ne!(f, g);
        assert!(
            b.face(f as usize).contains(&e.vertices[0])
                && b.face(g as usize).contains(&e.vertices[1])
        );
    }
}

#[test]
fn triangulated_faces_are_merged() {
    let faces: Vec<Vec<usize>> = cube_faces()
        .into_iter()
        .flat_map(|f| [vec![f[0], f[1], f[2]], vec![f[0], f[2], f[3]]])
        .collect();
    let b = build(&cube_vertices(), &faces).unwrap();
    assert_eq!((b.n_faces(), b.edges().len()), (6, 12));
}

#[test]
fn from_planes_gives_the_same_cube() {
    let normals = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let offsets = [1.0, 0.0, 2.0, 0.0, 1.0, 0.0];
    let b = ConvexBlock::from_planes(&normals, &offsets).unwrap();
    assert_eq!((b.vertices().len(), b.n_faces()), (8, 6));
    assert!((b.volume() - 1.0).abs() < 1e-12);
}

#[test]
fn from_planes_rejects_unbounded_and_degenerate_sets() {
    let open = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    assert!(matches!(
        ConvexBlock::from_planes(&open, &[1.0; 5]),
        Err(BlockError::Unbounded { .. })
    ));
    let mut bad = open.to_vec();
    bad.push([0.0, 0.0, 0.0]);
    assert_eq!(
        ConvexBlock::from_planes(&bad, &[1.0; 6]).unwrap_err(),
        BlockError::DegeneratePlane { plane: 5 }
    );
    let nan = [
        [f64::NAN, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
    ];
    assert_eq!(
        ConvexBlock::from_planes(&nan, &[1.0; 4]).unwrap_err(),
        BlockError::DegeneratePlane { plane: 0 }
    );
    // Empty intersection: x <= 0 and x >= 1.
    let empty = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    assert!(ConvexBlock::from_planes(&empty, &[0.0, -1.0, 1.0, 1.0, 1.0, 1.0]).is_err());
}

/// Three planes whose normals are nearly coplanar (z <= 0.5 tilted by 2.5e-12, and the
/// octahedron's faces (1, 1, 1) and (-1, -1, 1)) meet at a point 1e11 away; that spurious
/// corner must not loosen the feasibility test of the others (it once set the rounding
/// allowance to 1e-9 of its magnitude, 100 m, and let infeasible corners in).
#[test]
fn a_far_corner_of_nearly_dependent_planes_is_ignored() {
    let mut normals: Vec<[f64; 3]> = Vec::new();
    for x in [-1.0, 1.0] {
        for y in [-1.0, 1.0] {
            for z in [-1.0, 1.0] {
                normals.push([x, y, z]);
            }
        }
    }
    let offsets = [0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 0.5, 0.75, 0.5, 0.5];
    let offsets: Vec<f64> = offsets
        .iter()
        .enumerate()
        .map(|(i, d)| if i < 8 { d * 3f64.sqrt() } else { *d })
        .collect();
    let exact = [normals.clone(), vec![[0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]].concat();
    let tilted = [normals, vec![[0.0, 2.48482792e-12, 1.0], [0.0, -1.0, 0.0]]].concat();
    let a = ConvexBlock::from_planes(&exact, &offsets).unwrap();
    let b = ConvexBlock::from_planes(&tilted, &offsets).unwrap();
    assert_eq!(a.vertices().len(), b.vertices().len());
    assert!((a.volume() - b.volume()).abs() < 1e-9);
}

#[test]
fn bad_input_is_named() {
    let v = cube_vertices();
    let f = cube_faces();
    let mut nan = v.clone();
    nan[3][1] = f64::NAN;
    assert_eq!(
        build(&nan, &f).unwrap_err(),
        BlockError::NonFiniteVertex { vertex: 3 }
    );
    let mut inf = v.clone();
    inf[5][0] = f64::INFINITY;
    assert_eq!(
        build(&inf, &f).unwrap_err(),
        BlockError::NonFiniteVertex { vertex: 5 }
    );

    let mut out_of_range = f.clone();
    out_of_range[2][1] = 9;
    assert!(matches!(
        build(&v, &out_of_range),
        Err(BlockError::VertexIndexOutOfRange {
            face: 2,
            vertex: 9,
            ..
        })
    ));

    let mut open = f.clone();
    open.pop();
    assert!(matches!(
        build(&v, &open),
        Err(BlockError::UnusedVertex { .. } | BlockError::OpenSurface { .. })
    ));
    let mut open = f.clone();
    open[1] = vec![4, 5, 6];
    assert!(matches!(
        build(&v, &open),
        Err(BlockError::OpenSurface { .. })
    ));

    let mut flipped = f.clone();
    flipped[0].reverse();
    assert!(matches!(
        build(&v, &flipped),
        Err(BlockError::InconsistentOrientation { .. })
    ));

    let inward: Vec<Vec<usize>> = f
        .iter()
        .map(|face| face.iter().rev().copied().collect())
        .collect();
    assert_eq!(
        build(&v, &inward).unwrap_err(),
        BlockError::WrongOrientation
    );

    let mut repeated = v.clone();
    repeated.push([1.0, 1.0, 1.0]);
    assert!(matches!(
        build(&repeated, &f),
        Err(BlockError::UnusedVertex { vertex: 8 })
    ));
    let mut dup = v.clone();
    dup[7] = dup[6];
    assert!(matches!(
        build(&dup, &f).unwrap_err(),
        BlockError::RepeatedVertex {
            first: 6,
            second: 7,
            ..
        }
    ));

    let mut short = f.clone();
    short[0] = vec![0, 3];
    assert_eq!(
        build(&v, &short).unwrap_err(),
        BlockError::DegenerateFaceList { face: 0 }
    );
    assert!(matches!(
        build(&v[..3], &f[..2]),
        Err(BlockError::TooSmall { .. })
    ));
}

#[test]
fn non_planar_and_non_convex_blocks_are_rejected() {
    let f = cube_faces();
    let mut warped = cube_vertices();
    warped[6] = [1.0, 1.0, 1.2];
    assert!(matches!(
        build(&warped, &f),
        Err(BlockError::NonPlanarFace { .. } | BlockError::NotConvex { .. })
    ));
    // A dent: the top face's centre pushed down, as four triangles.
    let mut v = cube_vertices();
    v.push([0.5, 0.5, 0.6]);
    let mut dented: Vec<Vec<usize>> = f[..1].to_vec();
    dented.extend(f[2..].iter().cloned());
    dented.extend([vec![4, 5, 8], vec![5, 6, 8], vec![6, 7, 8], vec![7, 4, 8]]);
    assert!(matches!(
        build(&v, &dented),
        Err(BlockError::NotConvex { .. })
    ));
}

#[test]
fn flat_blocks_have_zero_volume() {
    let v = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.3, 0.3, 0.0],
    ];
    let f = [vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![2, 0, 3]];
    assert_eq!(build(&v, &f).unwrap_err(), BlockError::ZeroVolume);
}

#[test]
fn two_tetrahedra_sharing_nothing_are_not_one_block() {
    let mut v: Vec<[f64; 3]> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    v.extend(v.clone().iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
    let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let f: Vec<Vec<usize>> = t
        .iter()
        .flat_map(|tri| [tri.to_vec(), tri.iter().map(|i| i + 4).collect()])
        .collect();
    assert!(matches!(
        build(&v, &f),
        Err(BlockError::NotASphere { euler: 4 })
    ));
}

#[test]
fn transformed_blocks_keep_volume_and_planes() {
    let b = ConvexBlock::cuboid([0.0; 3], [1.0, 2.0, 3.0]).unwrap();
    let q = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let t = b.transformed(q, DVec3::new(5e5, 4e6, 1e3), 2.0);
    assert!((t.volume() - 48.0).abs() < 1e-9);
    for (plane, face) in t.planes().iter().zip(t.faces()) {
        for &v in face {
            assert!(plane.distance(t.vertices()[v as usize]).abs() < 1e-9);
        }
    }
}

#[test]
fn translated_and_rotated_copies() {
    let b = ConvexBlock::cuboid([0.0; 3], [1.0, 2.0, 3.0]).unwrap();
    let moved = b.translated(DVec3::new(10.0, 0.0, -1.0));
    assert_eq!(
        moved,
        ConvexBlock::cuboid([10.0, 0.0, -1.0], [11.0, 2.0, 2.0]).unwrap()
    );
    assert_eq!(moved.face_origins(), b.face_origins());
    // A quarter turn about z through the centroid (0.5, 1, 1.5): x' = 0.5 - (y - 1),
    // y' = 1 + (x - 0.5), so the box spans x in [-0.5, 1.5], y in [0.5, 1.5].
    let quarter = glam::DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let turned = b.rotated(quarter, b.centroid());
    assert!(turned.centroid().distance(b.centroid()) < 1e-15);
    let aabb = turned.aabb();
    assert!(aabb.min.distance(DVec3::new(-0.5, 0.5, 0.0)) < 1e-15);
    assert!(aabb.max.distance(DVec3::new(1.5, 1.5, 3.0)) < 1e-15);
    // About a given point: the origin, so (1, 2, 3) goes to (-2, 1, 3).
    let about_origin = b.rotated(quarter, DVec3::ZERO);
    assert!(about_origin.vertices()[6].distance(DVec3::new(-2.0, 1.0, 3.0)) < 1e-15);
    assert!((turned.volume() - 6.0).abs() < 1e-14);
}

#[test]
fn blocks_are_equal_by_value() {
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let b = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    assert_eq!(a, b);
    assert_ne!(a, a.translated(DVec3::new(1e-12, 0.0, 0.0)));
    // The same box with each face's loop starting at its next vertex: the same shape,
    // other data, so not equal by value.
    let vertices: Vec<[f64; 3]> = a.vertices().iter().map(|v| v.to_array()).collect();
    let faces: Vec<Vec<usize>> = a
        .faces()
        .map(|f| {
            let mut loop_: Vec<usize> = f.iter().map(|&v| v as usize).collect();
            loop_.rotate_left(1);
            loop_
        })
        .collect();
    let c = ConvexBlock::new(&vertices, &faces).unwrap();
    assert_eq!(c.volume(), a.volume());
    assert_ne!(c, a);
}

mod no_panic {
    use super::*;
    use proptest::prelude::*;

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            8 => -2.0..2.0f64,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(1e300),
            1 => Just(0.0),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Arbitrary vertices and face lists give a block or an error, never a panic.
        #[test]
        fn arbitrary_input_never_panics(
            vertices in prop::collection::vec([coordinate(), coordinate(), coordinate()], 0..10),
            faces in prop::collection::vec(prop::collection::vec(0usize..12, 0..6), 0..10),
        ) {
            let _ = ConvexBlock::new(&vertices, &faces);
        }

        /// Arbitrary half-spaces likewise.
        #[test]
        fn arbitrary_planes_never_panic(
            normals in prop::collection::vec([coordinate(), coordinate(), coordinate()], 0..9),
            offsets in prop::collection::vec(coordinate(), 0..9),
        ) {
            let _ = ConvexBlock::from_planes(&normals, &offsets);
        }

        /// A perturbed cube (vertices moved a little) is either valid or named invalid.
        #[test]
        fn perturbed_cubes_never_panic(noise in prop::collection::vec(-0.2..0.2f64, 24)) {
            let mut v = cube_vertices();
            for (k, n) in noise.iter().enumerate() {
                v[k / 3][k % 3] += n;
            }
            if let Ok(b) = ConvexBlock::new(&v, &cube_faces()) {
                prop_assert!(b.volume() > 0.0);
            }
        }
    }
}

#[test]
fn cuboid_needs_lower_below_upper_corner() {
    assert_eq!(
        ConvexBlock::cuboid([0.0; 3], [1.0, -1.0, 1.0]).unwrap_err(),
        BlockError::EmptyBox { axis: 1 }
    );
    assert_eq!(
        ConvexBlock::cuboid([2.0, 0.0, 0.0], [1.0; 3]).unwrap_err(),
        BlockError::EmptyBox { axis: 0 }
    );
    assert_eq!(
        ConvexBlock::cuboid([0.0, 0.0, f64::NAN], [1.0; 3]).unwrap_err(),
        BlockError::EmptyBox { axis: 2 }
    );
    assert!(ConvexBlock::cuboid([0.0; 3], [1.0, 1.0, 0.0]).is_err());
}

/// Distances in messages read as three significant digits, not the 17 of an `f64`.
#[test]
fn messages_print_distances_readably() {
    assert_eq!(Readable(5.551_115_123_125_783e-17).to_string(), "5.55e-17");
    assert_eq!(Readable(1e300).to_string(), "1e300");
    assert_eq!(Readable(35.527_136_788_005_01).to_string(), "3.55e1");
    assert_eq!(Readable(f64::INFINITY).to_string(), "inf");
    let far = build(&[[1.234_567_890_123e60; 3]; 4], &cube_faces()[..4]).unwrap_err();
    assert!(
        far.to_string()
            .starts_with("the block's largest coordinate is 1.23e60, outside"),
        "{far}"
    );
    // A corner lifted by a third of a millimetre: off its face by a distance with no
    // exact decimal form.
    let mut warped = cube_vertices();
    warped[6][2] += 1e-3 / 3.0;
    let err = build(&warped, &cube_faces()).unwrap_err();
    let message = err.to_string();
    let distance = match err {
        BlockError::NonPlanarFace { distance, .. } | BlockError::NotConvex { distance, .. } => {
            distance
        }
        other => panic!("{other:?}"),
    };
    assert!(
        message.contains(&format!(" {} ", Readable(distance))),
        "{message}"
    );
    assert!(!message.contains(&format!("{distance:e}")), "{message}");
}

/// A unit cube at 1e15, where a vertex counts as repeated within the rounding of its
/// coordinates (35.5 there), says that the coordinates are too large for its size and names
/// both; a vertex given twice near the origin says only that.
#[test]
fn vertices_rounded_together_far_away_are_named_as_such() {
    let far = ConvexBlock::cuboid([1e15; 3], [1e15 + 1.0; 3]).unwrap_err();
    let BlockError::RepeatedVertex {
        within,
        magnitude,
        size,
        ..
    } = far
    else {
        panic!("{far:?}");
    };
    assert_eq!(magnitude, 1e15 + 1.0);
    assert_eq!(size, 3f64.sqrt());
    assert_eq!(
        within,
        10.0 * (crate::tolerance::ROUNDING_FLOOR * magnitude)
    );
    let message = far.to_string();
    for part in [
        format!("(within {})", Readable(within)),
        format!("up to {} in magnitude", Readable(magnitude)),
        format!("at the block's size ({} across)", Readable(size)),
        "too large for double precision".to_string(),
    ] {
        assert!(message.contains(&part), "{part}: {message}");
    }
    let mut dup = cube_vertices();
    dup[7] = dup[6];
    let near = build(&dup, &cube_faces()).unwrap_err();
    assert_eq!(
        near.to_string(),
        "vertices 6 and 7 are at the same position"
    );
}
