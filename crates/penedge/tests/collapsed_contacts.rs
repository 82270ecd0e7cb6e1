//! A face-face contact collapsed below the length threshold: two faces that overlap in a
//! strip narrower than it are an edge-edge superposition, and its contact segment lies on
//! A's edge, from one end of the overlap to the other (worked out here from the boxes), not
//! across the strip from corner to corner.

use penedge::glam::{DQuat, DVec3};
use penedge::{ContactType, ConvexBlock, Detector, Tolerance};

/// A unit cube, and a unit cube on it overlapping its top face in a strip `w` wide along
/// its edge `x = 1, z = 1`, turned by `turn` about the z axis.
fn strip(w: f64, turn: f64) -> (ConvexBlock, ConvexBlock) {
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let b = ConvexBlock::cuboid([1.0 - w, 0.0, 1.0], [2.0 - w, 1.0, 2.0])
        .unwrap()
        .transformed(DQuat::from_rotation_z(turn), DVec3::ZERO, 1.0);
    (a, b)
}

#[test]
fn a_strip_narrower_than_the_length_threshold_is_a_segment_on_the_edge() {
    // Length threshold 1e-3 (of the unit blocks): strips of 2e-4, straight and turned.
    let tol = Tolerance::new(1e-12, 1e-3).unwrap();
    for turn in [0.0, 1e-4] {
        let (a, b) = strip(2e-4, turn);
        let (result, geometry) = Detector::new(tol).detect_with_geometry(&a, &b);
        let kind = match result {
            penedge::PairResult::Contact(c) => c.kind,
            other => panic!("{other:?}"),
        };
        assert_eq!(kind, ContactType::EdgeEdgeSuperposition);
        let g = geometry.unwrap();
        assert!((g.normal() - DVec3::Z).length() < 1e-9);
        let points = g.points();
        assert_eq!(points.len(), 2, "{points:?}");
        // On A's edge x = 1, z = 1; along y from where B's edge starts (its corner
        // (1 - w, 0) turned: y = (1 - w) sin(turn)) to the end of A's edge (y = 1).
        let start = (1.0 - 2e-4) * turn.sin();
        let mut ys: Vec<f64> = points.iter().map(|p| p.y).collect();
        ys.sort_by(f64::total_cmp);
        for p in points {
            assert!(
                (p.x - 1.0).abs() < 1e-9 && (p.z - 1.0).abs() < 1e-9,
                "turn {turn}: {points:?} off the edge"
            );
        }
        assert!(
            (ys[0] - start).abs() < 1e-9 && (ys[1] - 1.0).abs() < 1e-9,
            "turn {turn}: {points:?}"
        );
    }
    // A strip wider than the threshold stays a face-face polygon of its area.
    let (a, b) = strip(5e-3, 0.0);
    let (_, g) = Detector::new(tol).detect_with_geometry(&a, &b);
    assert!((g.unwrap().area() - 5e-3).abs() < 1e-9);
}
