use super::*;
use crate::block::ConvexBlock;
use glam::EulerRot;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

fn assert_mat_close(a: &DMat3, b: &DMat3, tol: f64) {
    for (x, y) in a.to_cols_array().iter().zip(b.to_cols_array()) {
        assert!(close(*x, y, tol), "{a:?} != {b:?}");
    }
}

/// Inertia of an a × b × c box about its centroid, per unit density (the textbook formula).
fn box_inertia(a: f64, b: f64, c: f64) -> DMat3 {
    let m = a * b * c;
    DMat3::from_diagonal(DVec3::new(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12.0))
}

#[test]
fn a_box_has_the_textbook_inertia_anywhere() {
    for corner in [
        [0.0, 0.0, 0.0],
        [-3.5, 2.0, 7.25],
        [512345.5, 4012345.25, 1234.125],
    ] {
        let max = [corner[0] + 2.0, corner[1] + 3.0, corner[2] + 5.0];
        let block = ConvexBlock::cuboid(corner, max).unwrap();
        let m = MassProperties::of_block(&block);
        assert!(close(m.volume, 30.0, 1e-13));
        let expected = DVec3::from_array(corner) + DVec3::new(1.0, 1.5, 2.5);
        assert!((m.centroid - expected).length() < 1e-9, "{:?}", m.centroid);
        assert_mat_close(&m.inertia, &box_inertia(2.0, 3.0, 5.0), 1e-12);
    }
}

#[test]
fn a_rotated_box_has_rotated_inertia_and_the_principal_axes_recover_the_rotation() {
    let q = DQuat::from_euler(EulerRot::ZXY, 0.4, -1.1, 2.3);
    let block = ConvexBlock::cuboid([0.0; 3], [1.0, 2.0, 4.0])
        .unwrap()
        .transformed(q, DVec3::new(3.0, -2.0, 1.0), 1.0);
    let m = MassProperties::of_block(&block);
    let r = DMat3::from_quat(q);
    let expected = r * box_inertia(1.0, 2.0, 4.0) * r.transpose();
    assert_mat_close(&m.inertia, &expected, 1e-12);
    let p = m.principal();
    let i0 = box_inertia(1.0, 2.0, 4.0);
    // Ascending moments: the long axis (z of the box) has the smallest moment.
    let want = [i0.z_axis.z, i0.y_axis.y, i0.x_axis.x];
    for (got, want) in p.moments.to_array().iter().zip(want) {
        assert!(close(*got, want, 1e-12), "{:?}", p.moments);
    }
    // Each principal axis is a box axis (up to sign), in the order of the moments.
    let axes = DMat3::from_quat(p.axes);
    for (k, box_axis) in [r.z_axis, r.y_axis, r.x_axis].iter().enumerate() {
        assert!(close(axes.col(k).dot(*box_axis).abs(), 1.0, 1e-12));
    }
    assert!(close(axes.determinant(), 1.0, 1e-12));
}

#[test]
fn a_regular_tetrahedron_has_the_textbook_inertia() {
    // Edge a: V = a³ / (6 √2), every axis through the centroid has I = m a² / 20.
    let a = 2.0f64;
    let v = [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let faces: [&[usize]; 4] = [&[0, 1, 2], &[0, 3, 1], &[0, 2, 3], &[1, 3, 2]];
    let block = ConvexBlock::new(&v, &faces).unwrap();
    let edge = a * 2f64.sqrt(); // the corners of the cube of side 2
    let m = MassProperties::of_block(&block);
    let volume = edge.powi(3) / (6.0 * 2f64.sqrt());
    assert!(close(m.volume, volume, 1e-13));
    assert!(m.centroid.length() < 1e-15);
    let expected = DMat3::from_diagonal(DVec3::splat(volume * edge * edge / 20.0));
    assert_mat_close(&m.inertia, &expected, 1e-12);
}

#[test]
fn parts_sum_to_the_whole_by_the_parallel_axis_theorem() {
    // An L of two boxes, against the parallel-axis theorem written out by hand.
    let a = ConvexBlock::cuboid([0.0, 0.0, 0.0], [4.0, 1.0, 1.0]).unwrap();
    let b = ConvexBlock::cuboid([0.0, 1.0, 0.0], [1.0, 3.0, 1.0]).unwrap();
    let m = MassProperties::of_parts(&[a.clone(), b.clone()]).unwrap();
    let (va, vb) = (4.0, 2.0);
    let (ca, cb) = (DVec3::new(2.0, 0.5, 0.5), DVec3::new(0.5, 2.0, 0.5));
    let c = (ca * va + cb * vb) / (va + vb);
    let steiner = |v: f64, d: DVec3| {
        DMat3::from_diagonal(DVec3::splat(d.length_squared())) * v
            - DMat3::from_cols(d * d.x, d * d.y, d * d.z) * v
    };
    let expected = box_inertia(4.0, 1.0, 1.0)
        + steiner(va, ca - c)
        + box_inertia(1.0, 2.0, 1.0)
        + steiner(vb, cb - c);
    assert!(close(m.volume, 6.0, 1e-14));
    assert!((m.centroid - c).length() < 1e-14);
    assert_mat_close(&m.inertia, &expected, 1e-12);
    // The same box cut in two parts has the mass properties of the whole box.
    let halves = [
        ConvexBlock::cuboid([0.0; 3], [1.0, 2.0, 3.0]).unwrap(),
        ConvexBlock::cuboid([1.0, 0.0, 0.0], [3.0, 2.0, 3.0]).unwrap(),
    ];
    let whole = MassProperties::of_block(&ConvexBlock::cuboid([0.0; 3], [3.0, 2.0, 3.0]).unwrap());
    let parts = MassProperties::of_parts(&halves).unwrap();
    assert!(close(parts.volume, whole.volume, 1e-14));
    assert!((parts.centroid - whole.centroid).length() < 1e-14);
    assert_mat_close(&parts.inertia, &whole.inertia, 1e-13);
    assert!(MassProperties::of_parts(&[]).is_none());
}

/// SplitMix64: random symmetric matrices for the eigen solver.
fn next(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

#[test]
fn principal_axes_diagonalise_symmetric_matrices() {
    let mut s = 7u64;
    for case in 0..500 {
        let mut m = DMat3::ZERO;
        for i in 0..3 {
            for j in i..3 {
                let x = next(&mut s) * 10f64.powi((case % 7) - 3);
                m.col_mut(i)[j] = x;
                m.col_mut(j)[i] = x;
            }
        }
        if case % 5 == 0 {
            m.col_mut(1)[1] = m.col(0)[0]; // repeated diagonal entries
        }
        let p = principal_axes(&m);
        let v = DMat3::from_quat(p.axes);
        let norm = m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let d = v.transpose() * m * v;
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { p.moments[i] } else { 0.0 };
                assert!(
                    (d.col(j)[i] - want).abs() <= 1e-13 * norm,
                    "case {case}: {d:?}"
                );
            }
        }
        assert!(p.moments.x <= p.moments.y && p.moments.y <= p.moments.z);
        assert!(close(v.determinant(), 1.0, 1e-13));
    }
    // Already diagonal, and a multiple of the identity (a cube).
    let p = principal_axes(&DMat3::from_diagonal(DVec3::new(3.0, 1.0, 2.0)));
    assert_eq!(p.moments, DVec3::new(1.0, 2.0, 3.0));
    let p = principal_axes(&DMat3::from_diagonal(DVec3::splat(2.0)));
    assert_eq!(p.moments, DVec3::splat(2.0));
}
