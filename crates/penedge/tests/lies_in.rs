//! The rule for "an edge lies in a face" (docs/tolerance.md, "Lies in"), swept over the angle.
//!
//! Three neighbours, each touching by one point in exact arithmetic, with one edge of A leaving
//! the contact at an angle `θ` to the top face of B (a box, top face z = 0, side face y = 0):
//!
//! * **vertex-face**: a vertex of A in the interior of B's top face, one of its edges rising
//!   from it at `θ`;
//! * **vertex-edge**: a vertex of A on B's top edge, one of its edges running over the top face
//!   at `θ` to it (A lies above the plane through B's edge and that edge: nothing else meets B);
//! * **edge-edge**: an edge of A crossing B's top edge, rising over the top face at `θ` on one
//!   side and falling past the side face on the other.
//!
//! The rule: the edge lies in the top face when `sin θ` is at most the length threshold over the
//! pair's scale (`length_abs / s`), and the contact is then an edge-face; otherwise the contact
//! keeps its type, however long the stub that the gap leaves along the edge. The expected
//! answer is computed here from the angle the blocks' own vertices make and the thresholds as
//! docs/tolerance.md states them. Swept from 0.1° to 10° at the default gap (the rule's angle,
//! about 6e-8°, is below the sweep: no change) and at a DEM-size relative gap of 1e-3 (length
//! threshold 1e-2: the type changes at 0.573°), near the origin; then the same placements
//! translated exactly to mine-grid coordinates (to 1e7, blocks of 1 cm and 1 m), which must
//! answer the same, and placements whose vertices are computed at mine scale (rounded once
//! there), which must answer what the rule gives for the rounded geometry.

mod support;

use glam::DVec3;
use penedge::{ContactType, ConvexBlock, Detector, PairResult, Tolerance};
use support::lies_in_sine;

/// A tetrahedron from four points in any order.
fn tetra(p: [DVec3; 4]) -> ConvexBlock {
    let faces: [[usize; 3]; 4] = if (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) < 0.0 {
        [[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]
    } else {
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    };
    ConvexBlock::new(&p.map(|v| v.to_array()), &faces).unwrap()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    VertexFace,
    VertexEdge,
    EdgeEdge,
}

impl Family {
    const ALL: [Family; 3] = [Family::VertexFace, Family::VertexEdge, Family::EdgeEdge];

    /// The type when the edge does not lie in the face.
    fn grazing(self) -> ContactType {
        match self {
            Family::VertexFace => ContactType::VertexFace,
            Family::VertexEdge => ContactType::VertexEdge,
            Family::EdgeEdge => ContactType::EdgeEdge,
        }
    }
}

/// How the vertices of a placement are made.
#[derive(Clone, Copy, Debug)]
enum Frame {
    /// Local coordinates rounded to multiples of `grid`, then moved by `offset` (exact when
    /// the grid is fine enough for the offset's magnitude: `grid >= ulp(offset)`).
    Exact { offset: DVec3, grid: f64 },
    /// Computed at `offset + local`: rounded once at the offset's magnitude.
    Rounded { offset: DVec3 },
}

impl Frame {
    const ORIGIN: Frame = Frame::Exact {
        offset: DVec3::ZERO,
        grid: 0.0,
    };

    fn place(self, local: DVec3) -> DVec3 {
        match self {
            Frame::Exact { offset, grid } if grid > 0.0 => {
                let on_grid = (local / grid).round() * grid;
                let p = on_grid + offset;
                assert_eq!(p - offset, on_grid, "not exact: {local} + {offset}");
                p
            }
            Frame::Exact { offset, .. } | Frame::Rounded { offset } => offset + local,
        }
    }
}

/// The pair of `family` at angle `theta` (radians), B's top face z = 0 and side face y = 0
/// about the point of contact (local origin), blocks about `u` across; and the sine of the
/// angle that the grazing edge of A makes with B's top face, from A's vertices as placed.
fn placement(family: Family, theta: f64, u: f64, frame: Frame) -> (ConvexBlock, ConvexBlock, f64) {
    let b = {
        let [lo, hi] =
            [DVec3::new(-u, -2.0 * u, -u), DVec3::new(u, 0.0, 0.0)].map(|p| frame.place(p));
        ConvexBlock::cuboid(lo.to_array(), hi.to_array()).unwrap()
    };
    let up = |x: f64, y: f64, z: f64| DVec3::new(x, y, z).normalize() * u;
    let (c, s) = (theta.cos(), theta.sin());
    let (points, grazing) = match family {
        Family::VertexFace => {
            let v = DVec3::new(0.0, -u, 0.0);
            let p = [
                v,
                v + DVec3::new(c, 0.0, s) * u,
                v + up(-0.6, 0.5, 0.6),
                v + up(-0.6, -0.5, 0.6),
            ]
            .map(|p| frame.place(p));
            (p, [0, 1])
        }
        Family::VertexEdge => {
            let p = [
                DVec3::ZERO,
                DVec3::new(0.0, -c, s) * u,
                up(0.6, 0.3, 0.75),
                up(-0.6, 0.3, 0.75),
            ]
            .map(|p| frame.place(p));
            (p, [0, 1])
        }
        Family::EdgeEdge => {
            let x = frame.place(DVec3::ZERO);
            let p1 = frame.place(DVec3::new(0.0, -c, s) * u);
            // Through the crossing point exactly where the frame is exact.
            let p2 = x * 2.0 - p1;
            let p = [
                p1,
                p2,
                frame.place(up(0.6, 0.3, 0.75)),
                frame.place(up(-0.6, 0.3, 0.75)),
            ];
            (p, [0, 1])
        }
    };
    let edge = points[grazing[1]] - points[grazing[0]];
    let sine = edge.z.abs() / edge.length();
    (tetra(points), b, sine)
}

/// The type the rule gives: edge-face when the edge lies in the face, else the family's.
fn expected(family: Family, sine: f64, lies_in: f64) -> ContactType {
    if sine <= lies_in {
        ContactType::EdgeFace
    } else {
        family.grazing()
    }
}

fn kind(result: PairResult) -> Option<ContactType> {
    result.contact_type()
}

/// The answer for (A, B), the same for (B, A).
fn answer(det: &mut Detector, a: &ConvexBlock, b: &ConvexBlock) -> PairResult {
    let ab = det.detect(a, b);
    let ba = det.detect(b, a);
    assert_eq!(kind(ab), kind(ba), "(A, B) and (B, A) differ");
    ab
}

/// The contact points of the pair's geometry.
fn contact_points(det: &mut Detector, a: &ConvexBlock, b: &ConvexBlock) -> Vec<DVec3> {
    let (_, geometry) = det.detect_with_geometry(a, b);
    geometry.map_or(Vec::new(), |g| g.points().to_vec())
}

/// Angles from 0.1° to 10°, evenly on a log scale, with the rule's angle at the DEM gap
/// (asin 0.01) approached from both sides.
fn angles() -> Vec<f64> {
    let n = 41;
    let mut degrees: Vec<f64> = (0..n)
        .map(|k| 0.1 * 100f64.powf(k as f64 / (n - 1) as f64))
        .collect();
    let dem = 0.01f64.asin().to_degrees();
    degrees.extend([dem * 0.99, dem * 1.01]);
    degrees.into_iter().map(f64::to_radians).collect()
}

fn tolerances() -> [(&'static str, Tolerance); 2] {
    [
        ("default gap", Tolerance::default()),
        ("DEM gap 1e-3", Tolerance::with_gap(1e-3).unwrap()),
    ]
}

/// Near the origin, the type changes where the rule says: at the default gap nowhere in the
/// sweep, at the DEM gap at asin(0.01) = 0.573°, for each of the three neighbours.
#[test]
fn type_changes_at_the_documented_angle() {
    for (label, tol) in tolerances() {
        let mut det = Detector::new(tol);
        for family in Family::ALL {
            let mut met = [0usize; 2];
            for theta in angles() {
                let (a, b, sine) = placement(family, theta, 1.0, Frame::ORIGIN);
                let lies_in = lies_in_sine(&tol, &a, &b);
                let want = expected(family, sine, lies_in);
                let got = answer(&mut det, &a, &b);
                assert_eq!(
                    kind(got),
                    Some(want),
                    "{label}, {family:?} at {:.4}°: sine {sine:e}, lies in below {lies_in:e}",
                    theta.to_degrees()
                );
                met[(want == ContactType::EdgeFace) as usize] += 1;
            }
            // The DEM gap's angle is inside the sweep, the default's below it.
            if tol.gap() > 1e-6 {
                assert!(met[0] > 0 && met[1] > 0, "{label}, {family:?}: {met:?}");
            } else {
                assert_eq!(met[1], 0, "{label}, {family:?}");
            }
        }
    }
}

/// Exact translations (coordinates stay representable: the same geometry) up to 1e7, blocks
/// of 1 cm and 1 m: the same answers as at the origin, features included, at both gaps.
#[test]
fn grazing_types_are_invariant_under_exact_translation() {
    let offsets = [
        DVec3::new(512345.5, 4012345.25, 1234.125),
        DVec3::new(-9999999.5, 9999999.75, 3e6),
        DVec3::new(1e7, 1e7, -1e7),
    ];
    // A grid every offset's coordinates carry exactly (below 2^24: ulp at most 2^-29).
    let grid = 2f64.powi(-29);
    for (label, tol) in tolerances() {
        let mut det = Detector::new(tol);
        for u in [0.01, 1.0] {
            for family in Family::ALL {
                for theta in angles() {
                    let at_origin = Frame::Exact {
                        offset: DVec3::ZERO,
                        grid,
                    };
                    let (a, b, _) = placement(family, theta, u, at_origin);
                    let expected = answer(&mut det, &a, &b);
                    assert!(kind(expected).is_some(), "{label}, {family:?} at origin");
                    let points = contact_points(&mut det, &a, &b);
                    for offset in offsets {
                        let (a, b, _) = placement(family, theta, u, Frame::Exact { offset, grid });
                        let what = format!(
                            "{label}, {family:?}, {u} m at {:.4}°, moved by {offset}",
                            theta.to_degrees()
                        );
                        assert_eq!(answer(&mut det, &a, &b), expected, "{what}");
                        // As many contact points (one for a point contact: no second point
                        // at the end of a stub), each moved by the offset.
                        let moved = contact_points(&mut det, &a, &b);
                        assert_eq!(moved.len(), points.len(), "{what}");
                        for (p, q) in points.iter().zip(&moved) {
                            assert!((*q - offset - *p).length() <= 1e-6 * u, "{what}: {p} {q}");
                        }
                    }
                }
            }
        }
    }
}

/// Vertices computed at mine scale (rounded once there, as a survey gives them): the type the
/// rule gives for the rounded geometry (its angle, the thresholds with the rounding floor).
#[test]
fn rounded_at_mine_scale_gives_the_rule_for_the_rounded_geometry() {
    let offsets = [
        DVec3::new(512345.3, 4012345.7, 1234.1),
        DVec3::new(-9876543.21, 9e6 + 0.1, 2345.678),
    ];
    for (label, tol) in tolerances() {
        let mut det = Detector::new(tol);
        for u in [0.01, 1.0] {
            for family in Family::ALL {
                for theta in angles() {
                    for offset in offsets {
                        let (a, b, sine) = placement(family, theta, u, Frame::Rounded { offset });
                        let want = expected(family, sine, lies_in_sine(&tol, &a, &b));
                        assert_eq!(
                            kind(answer(&mut det, &a, &b)),
                            Some(want),
                            "{label}, {family:?}, {u} m at {:.4}°, at {offset}",
                            theta.to_degrees()
                        );
                    }
                }
            }
        }
    }
}
