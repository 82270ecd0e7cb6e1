//! Concave blocks: the same shapes decomposed into convex parts in different ways give the
//! same contacts, equal to the contacts worked out by hand for each shape (analytic areas
//! and normals); bad decompositions are refused.

use super::{BlockSystem, ConcaveError};
use crate::body::MassProperties;
use crate::classify::ContactType;
use crate::geometry::DVec3;
use crate::tolerance::Tolerance;
use crate::ConvexBlock;
use glam::DQuat;

fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
    ConvexBlock::cuboid(lo, hi).unwrap()
}

/// A contact region as compared: bodies, type, area and normal rounded to 1e-9.
type Region = ([u32; 2], ContactType, i64, [i64; 3]);

fn round(x: f64) -> i64 {
    (x * 1e9).round() as i64
}

/// The regions of a system of (body id, part) entries, sorted.
fn regions(parts: &[(u32, ConvexBlock)]) -> Vec<Region> {
    let tol = Tolerance::default();
    let system = BlockSystem::new(parts.iter().map(|p| p.1.clone()).collect())
        .with_bodies(parts.iter().map(|p| p.0).collect(), &tol)
        .unwrap();
    let found = system.detect_bodies(&tol);
    assert!(found.penetrating.is_empty(), "{:?}", found.penetrating);
    // Region indices run 0, 1, ... within each pair of bodies.
    for w in found.contacts.windows(2) {
        let next = if w[0].bodies == w[1].bodies {
            w[0].region + 1
        } else {
            0
        };
        assert_eq!(w[1].region, next);
    }
    let mut out: Vec<Region> = found
        .contacts
        .iter()
        .map(|c| (c.bodies, c.kind, round(c.area), c.normal.map(round)))
        .collect();
    out.sort();
    out
}

/// A region expected by hand.
fn region(bodies: [u32; 2], kind: ContactType, area: f64, normal: [f64; 3]) -> Region {
    (bodies, kind, round(area), normal.map(round))
}

/// The blocks around the L-block (body 0: the floor `[0, 3] x [0, 10] x [0, 1]` and the
/// column `[0, 1] x [0, 10] x [1, 3]` on it): 1 sits in the corner of the notch, 2 lies on
/// the floor across x = 2, 3 stands on a vertex at (2, 5, 1), 4 lies on an edge along
/// y = 7.5 from x = 1.5 to 2.5.
fn around_the_l_block() -> Vec<(u32, ConvexBlock)> {
    // A unit cube with a corner down: its diagonal turned onto -z, that corner placed.
    let diagonal = DVec3::ONE.normalize();
    let corner_down = DQuat::from_rotation_arc(diagonal, -DVec3::Z);
    let cube = cuboid([0.0; 3], [1.0; 3]).transformed(corner_down, DVec3::ZERO, 1.0);
    let low = *cube
        .vertices()
        .iter()
        .min_by(|p, q| p.z.total_cmp(&q.z))
        .unwrap();
    let vertex_down = cube.transformed(DQuat::IDENTITY, DVec3::new(2.0, 5.0, 1.0) - low, 1.0);
    // A bar 1 long along x, turned 45 degrees about x: an edge down.
    let edge_down = cuboid([-0.5, -0.3, -0.3], [0.5, 0.3, 0.3]).transformed(
        DQuat::from_rotation_x(std::f64::consts::FRAC_PI_4),
        DVec3::new(2.0, 7.5, 1.0 + 0.3 * 2f64.sqrt()),
        1.0,
    );
    vec![
        (1, cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0])),
        (2, cuboid([1.5, 2.0, 1.0], [2.5, 3.0, 2.0])),
        (3, vertex_down),
        (4, edge_down),
    ]
}

/// The L-block in three decompositions: a vertical cut at x = 1, a horizontal cut at z = 1,
/// and eight parts with cuts through the contacts of the blocks around it (x = 2 under
/// block 2 and 3, y = 5 under 3's vertex, y = 7.5 along 4's edge).
fn l_block_decompositions() -> Vec<Vec<ConvexBlock>> {
    let vertical = vec![
        cuboid([0.0, 0.0, 0.0], [1.0, 10.0, 3.0]),
        cuboid([1.0, 0.0, 0.0], [3.0, 10.0, 1.0]),
    ];
    let horizontal = vec![
        cuboid([0.0, 0.0, 0.0], [3.0, 10.0, 1.0]),
        cuboid([0.0, 0.0, 1.0], [1.0, 10.0, 3.0]),
    ];
    let mut fine = vec![
        cuboid([0.0, 0.0, 1.0], [1.0, 10.0, 3.0]),
        cuboid([0.0, 0.0, 0.0], [1.0, 10.0, 1.0]),
    ];
    for (x0, x1) in [(1.0, 2.0), (2.0, 3.0)] {
        for (y0, y1) in [(0.0, 5.0), (5.0, 7.5), (7.5, 10.0)] {
            fine.push(cuboid([x0, y0, 0.0], [x1, y1, 1.0]));
        }
    }
    vec![vertical, horizontal, fine]
}

fn with_body(id: u32, parts: Vec<ConvexBlock>) -> Vec<(u32, ConvexBlock)> {
    parts.into_iter().map(|p| (id, p)).collect()
}

#[test]
fn an_l_block_has_the_same_contacts_however_it_is_cut() {
    let z = [0.0, 0.0, 1.0];
    // By hand: block 1 touches the floor and the wall of the notch (two regions of 1 m²);
    // 2 lies on the floor with 1 m² whatever cuts run under it; 3's vertex and 4's edge
    // touch the floor's face, not the parts' vertices and edges under them.
    let expected = vec![
        region([0, 1], ContactType::FaceFace, 1.0, [1.0, 0.0, 0.0]),
        region([0, 1], ContactType::FaceFace, 1.0, z),
        region([0, 2], ContactType::FaceFace, 1.0, z),
        region([0, 3], ContactType::VertexFace, 0.0, z),
        region([0, 4], ContactType::EdgeFace, 0.0, z),
    ];
    let mut expected = expected;
    expected.sort();
    for (k, parts) in l_block_decompositions().into_iter().enumerate() {
        let mut system = with_body(0, parts);
        system.extend(around_the_l_block());
        assert_eq!(regions(&system), expected, "decomposition {k}");
    }
}

#[test]
fn the_fine_cut_l_block_has_part_contacts_of_other_types_than_the_block() {
    // The check above is not vacuous: under the fine cuts the parts touch block 3 at a
    // vertex and block 4 along edges, which the merging turns into a face of the block.
    let tol = Tolerance::default();
    let mut parts = with_body(0, l_block_decompositions().pop().unwrap());
    parts.extend(around_the_l_block());
    let system = BlockSystem::new(parts.iter().map(|p| p.1.clone()).collect())
        .with_bodies(parts.iter().map(|p| p.0).collect(), &tol)
        .unwrap();
    let plain = system.detect(&tol);
    let kinds: Vec<ContactType> = plain.contacts.iter().map(|c| c.contact.kind).collect();
    assert!(kinds.contains(&ContactType::VertexVertex), "{kinds:?}");
    assert!(
        kinds.contains(&ContactType::EdgeEdgeSuperposition),
        "{kinds:?}"
    );
}

/// The U-block (body 0): `[0, 3] x [0, 1] x [0, 2]` less the notch `[1, 2] x [0, 1] x [1, 2]`,
/// cut into three columns or into a floor slab and two arms.
fn u_block_decompositions() -> Vec<Vec<ConvexBlock>> {
    vec![
        vec![
            cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 2.0]),
            cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
            cuboid([2.0, 0.0, 0.0], [3.0, 1.0, 2.0]),
        ],
        vec![
            cuboid([0.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
            cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            cuboid([2.0, 0.0, 1.0], [3.0, 1.0, 2.0]),
        ],
    ]
}

#[test]
fn a_block_sitting_in_a_notch_touches_it_in_three_regions() {
    let z = [0.0, 0.0, 1.0];
    let fitting = cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.5]);
    let narrow = cuboid([1.25, 0.0, 1.0], [1.75, 1.0, 2.0]);
    for (block, expected) in [
        (
            fitting,
            vec![
                region([0, 1], ContactType::FaceFace, 1.0, [-1.0, 0.0, 0.0]),
                region([0, 1], ContactType::FaceFace, 1.0, [1.0, 0.0, 0.0]),
                region([0, 1], ContactType::FaceFace, 1.0, z),
            ],
        ),
        (narrow, vec![region([0, 1], ContactType::FaceFace, 0.5, z)]),
    ] {
        let mut expected = expected;
        expected.sort();
        for (k, parts) in u_block_decompositions().into_iter().enumerate() {
            let mut system = with_body(0, parts);
            system.push((1, block.clone()));
            assert_eq!(regions(&system), expected, "decomposition {k}");
        }
    }
}

#[test]
fn two_concave_blocks_interlock_in_separate_regions() {
    // An upside-down T-shaped block (body 1) whose stem fills the U's notch: the U touches it
    // on the notch's floor and walls, and the T's flanges lie on the U's arms.
    let t_parts = [
        vec![
            cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
            cuboid([0.0, 0.0, 2.0], [3.0, 1.0, 3.0]),
        ],
        vec![
            cuboid([0.0, 0.0, 2.0], [1.0, 1.0, 3.0]),
            cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 3.0]),
            cuboid([2.0, 0.0, 2.0], [3.0, 1.0, 3.0]),
        ],
    ];
    let z = [0.0, 0.0, 1.0];
    let mut expected = vec![
        region([0, 1], ContactType::FaceFace, 1.0, [-1.0, 0.0, 0.0]),
        region([0, 1], ContactType::FaceFace, 1.0, [1.0, 0.0, 0.0]),
        region([0, 1], ContactType::FaceFace, 1.0, z),
        region([0, 1], ContactType::FaceFace, 1.0, z),
        region([0, 1], ContactType::FaceFace, 1.0, z),
    ];
    expected.sort();
    for u in u_block_decompositions() {
        for t in &t_parts {
            let mut system = with_body(0, u.clone());
            system.extend(with_body(1, t.clone()));
            assert_eq!(regions(&system), expected);
        }
    }
}

/// A prism along z (0 to 1) over the convex polygon `corners` (either way round).
fn prism(corners: &[[f64; 2]]) -> ConvexBlock {
    let mut corners = corners.to_vec();
    let twice_area: f64 = (0..corners.len())
        .map(|k| {
            let (p, q) = (corners[k], corners[(k + 1) % corners.len()]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum();
    if twice_area < 0.0 {
        corners.reverse();
    }
    let mut normals = vec![[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]];
    let mut offsets = vec![0.0, 1.0];
    for k in 0..corners.len() {
        let (p, q) = (corners[k], corners[(k + 1) % corners.len()]);
        let n = DVec3::new(q[1] - p[1], p[0] - q[0], 0.0).normalize();
        normals.push(n.to_array());
        offsets.push(n.x * p[0] + n.y * p[1]);
    }
    ConvexBlock::from_planes(&normals, &offsets).unwrap()
}

/// The point at radius `r`, angle `t` (degrees).
fn polar(r: f64, t: f64) -> [f64; 2] {
    let t = t.to_radians();
    [r * t.cos(), r * t.sin()]
}

/// A ring segment around a tunnel along z: radii 2 and 4 (polygonal: chords every 22.5
/// degrees) from `from` to `from + 90` degrees, as one prism per chord, or each chord's prism
/// cut in two along the line joining the middles of its inner and outer chords.
fn ring_segment(from: f64, halves: bool) -> Vec<ConvexBlock> {
    let mut parts = Vec::new();
    for k in 0..4 {
        let (t0, t1) = (from + 22.5 * k as f64, from + 22.5 * (k + 1) as f64);
        let (i0, i1, o0, o1) = (
            polar(2.0, t0),
            polar(2.0, t1),
            polar(4.0, t0),
            polar(4.0, t1),
        );
        if halves {
            let mid = |p: [f64; 2], q: [f64; 2]| [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
            let (im, om) = (mid(i0, i1), mid(o0, o1));
            parts.push(prism(&[i0, im, om, o0]));
            parts.push(prism(&[im, i1, o1, om]));
        } else {
            parts.push(prism(&[i0, i1, o1, o0]));
        }
    }
    parts
}

#[test]
fn a_ring_segment_around_a_tunnel_has_the_same_contacts_however_it_is_cut() {
    // Body 0: the segment from 0 to 90 degrees; body 1: the next one (90 to 180), touching
    // it along the radial face at 90 degrees (2 x 1 m); body 2: a plate in the tunnel
    // lying against the inner chord from 22.5 to 45 degrees, across the chord's middle.
    let (c0, c1) = (polar(2.0, 22.5), polar(2.0, 45.0));
    let chord = DVec3::new(c1[0] - c0[0], c1[1] - c0[1], 0.0);
    let mid = DVec3::new((c0[0] + c1[0]) / 2.0, (c0[1] + c1[1]) / 2.0, 0.0);
    // The chord's outward normal (from the ring into the tunnel) points to the axis.
    let inward = -mid.normalize();
    let along = chord.normalize();
    // The plate: 0.4 along the chord, 0.2 thick towards the axis, 1 along z.
    let corners = [
        mid - along * 0.2,
        mid + along * 0.2,
        mid + along * 0.2 + inward * 0.2,
        mid - along * 0.2 + inward * 0.2,
    ];
    let plate = prism(&corners.map(|c| [c.x, c.y]));
    let radial = DVec3::new(-1.0, 0.0, 0.0); // normal of the face at 90 degrees, 0 to 1
    let mut expected = vec![
        region([0, 1], ContactType::FaceFace, 2.0, radial.to_array()),
        region([0, 2], ContactType::FaceFace, 0.4, inward.to_array()),
    ];
    expected.sort();
    for halves in [false, true] {
        let mut system = with_body(0, ring_segment(0.0, halves));
        system.extend(with_body(1, ring_segment(90.0, !halves)));
        system.push((2, plate.clone()));
        assert_eq!(regions(&system), expected, "halves {halves}");
    }
}

#[test]
fn convex_blocks_get_the_contacts_of_the_system_detection() {
    let tol = Tolerance::default();
    let system = super::paper_example(super::PaperExample::Three).unwrap();
    let (found, geometry) = system.detect_with_geometry(&tol);
    let bodies = system.detect_bodies(&tol);
    assert_eq!(bodies.contacts.len(), found.contacts.len());
    assert_eq!(bodies.penetrating, found.penetrating);
    for (i, (b, c)) in bodies.contacts.iter().zip(&found.contacts).enumerate() {
        assert_eq!((b.bodies, b.region, b.kind), (c.pair, 0, c.contact.kind));
        assert_eq!(b.normal, geometry.normals[i]);
        assert_eq!(b.area.to_bits(), geometry.areas[i].to_bits());
        assert_eq!(bodies.pieces_of(i), std::slice::from_ref(c));
        assert_eq!(bodies.piece_points_of(i), geometry.points_of(i));
    }
}

#[test]
fn the_mass_properties_of_a_concave_block_do_not_depend_on_its_parts() {
    let tol = Tolerance::default();
    // The L-block by hand: floor 3 x 10 x 1 (centroid (1.5, 5, 0.5)), column 1 x 10 x 2
    // (centroid (0.5, 5, 2)); inertia of each box about its centroid V (b² + c²) / 12 and
    // so on, moved to the common centroid by the parallel-axis theorem.
    let boxes = [
        ([3.0, 10.0, 1.0], [1.5, 5.0, 0.5]),
        ([1.0, 10.0, 2.0], [0.5, 5.0, 2.0]),
    ];
    let volume: f64 = boxes.iter().map(|(d, _)| d[0] * d[1] * d[2]).sum();
    let centroid = boxes
        .iter()
        .map(|(d, c)| DVec3::from_array(*c) * (d[0] * d[1] * d[2]))
        .sum::<DVec3>()
        / volume;
    let mut diagonal = DVec3::ZERO;
    for (d, c) in boxes {
        let v = d[0] * d[1] * d[2];
        let r = DVec3::from_array(c) - centroid;
        let own = DVec3::new(
            d[1] * d[1] + d[2] * d[2],
            d[0] * d[0] + d[2] * d[2],
            d[0] * d[0] + d[1] * d[1],
        ) * v
            / 12.0;
        let shift = DVec3::new(
            r.y * r.y + r.z * r.z,
            r.x * r.x + r.z * r.z,
            r.x * r.x + r.y * r.y,
        ) * v;
        diagonal += own + shift;
    }
    for parts in l_block_decompositions() {
        let system = BlockSystem::new(parts.clone())
            .with_bodies(vec![7; parts.len()], &tol)
            .unwrap();
        let all: Vec<(u32, MassProperties)> = system.body_mass_properties();
        assert_eq!(all.len(), 1);
        let (body, m) = all[0];
        assert_eq!(body, 7);
        assert!((m.volume - volume).abs() < 1e-12);
        assert!((m.centroid - centroid).length() < 1e-12);
        let got = DVec3::new(m.inertia.x_axis.x, m.inertia.y_axis.y, m.inertia.z_axis.z);
        assert!((got - diagonal).length() < 1e-9, "{got} {diagonal}");
    }
}

#[test]
fn the_internal_faces_are_the_glue_and_partly_glued_faces_stay_real() {
    let tol = Tolerance::default();
    let parts = l_block_decompositions().remove(0); // column [0,1] x [0,10] x [0,3], floor
    let system = BlockSystem::new(parts)
        .with_bodies(vec![0, 0], &tol)
        .unwrap();
    let glue = system.internal_faces();
    assert_eq!(glue.len(), 1, "{glue:?}");
    assert_eq!(glue[0].parts, [0, 1]);
    // The contact polygon is clipped within the gap: the area to about 1e-11.
    assert!((glue[0].area - 10.0).abs() < 1e-9, "{glue:?}");
    // The floor's face at x = 1 is covered entirely; the column's at x = 1 only up to z = 1.
    let [column_face, floor_face] = glue[0].faces;
    assert!(system.is_internal_face(1, floor_face));
    assert!(!system.is_internal_face(0, column_face));
}

#[test]
fn parts_that_do_not_touch_face_to_face_or_that_overlap_are_refused() {
    let tol = Tolerance::default();
    let apart = BlockSystem::new(vec![
        cuboid([0.0; 3], [1.0; 3]),
        cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
        cuboid([3.0, 0.0, 0.0], [4.0, 1.0, 1.0]),
        cuboid([2.0, 1.0, 1.0], [3.0, 2.0, 2.0]), // touches part 1 along an edge only
    ]);
    assert_eq!(
        apart
            .clone()
            .with_bodies(vec![5, 5, 5, 5], &tol)
            .unwrap_err(),
        ConcaveError::Detached {
            body: 5,
            detached: vec![2, 3]
        }
    );
    let message = apart
        .clone()
        .with_bodies(vec![0, 0, 1, 1], &tol)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("body 1") && message.contains("glued face to face"),
        "{message}"
    );
    let overlapping = BlockSystem::new(vec![
        cuboid([0.0; 3], [1.0; 3]),
        cuboid([0.5, 0.0, 0.0], [2.0, 1.0, 1.0]),
    ]);
    assert_eq!(
        overlapping.with_bodies(vec![0, 0], &tol).unwrap_err(),
        ConcaveError::Overlap {
            body: 0,
            a: 0,
            b: 1
        }
    );
    assert_eq!(
        apart.with_bodies(vec![0], &tol).unwrap_err(),
        ConcaveError::Count {
            given: 1,
            blocks: 4
        }
    );
}

#[test]
fn block_files_keep_the_bodies_and_version_1_files_still_read() {
    use crate::io::json::{from_json_str, to_json_string};
    let tol = Tolerance::default();
    let mut parts = with_body(3, l_block_decompositions().remove(0));
    parts.push((1, cuboid([10.0, 0.0, 1.0], [11.0, 1.0, 2.0])));
    let system = BlockSystem::new(parts.iter().map(|p| p.1.clone()).collect())
        .with_bodies(parts.iter().map(|p| p.0).collect(), &tol)
        .unwrap();
    let text = to_json_string(&system);
    assert!(
        text.contains("\"version\":2") && text.contains("\"body\":3"),
        "{text}"
    );
    assert!(
        text.contains("\"internal_faces\":[{\"parts\":[0,1]"),
        "{text}"
    );
    let back = from_json_str(&text).unwrap();
    assert_eq!(back.body_ids(), [3, 3, 1]);
    assert_eq!(back.internal_faces(), system.internal_faces());
    assert_eq!(back.detect_bodies(&tol), system.detect_bodies(&tol));
    // The same file as version 1 (no body ids): each block its own body.
    let v1 = text
        .replace("\"version\":2", "\"version\":1")
        .replace("\"body\":3,", "")
        .replace("\"body\":1,", "");
    let v1 = &v1[..v1.find(",\"internal_faces\"").unwrap()];
    let old = from_json_str(&format!("{v1}}}")).unwrap();
    assert_eq!(old.body_ids(), [0, 1, 2]);
    assert!(old.internal_faces().is_empty());
    // Body ids in a version 1 file, or missing in version 2, or parts apart: named errors.
    let bad = from_json_str(&text.replace("\"version\":2", "\"version\":1")).unwrap_err();
    assert!(bad.to_string().contains("blocks[0].body"), "{bad}");
    let bad = from_json_str(&text.replacen("\"body\":3,", "", 1)).unwrap_err();
    assert!(bad.to_string().contains("blocks[0].body"), "{bad}");
    let apart = from_json_str(&text.replace("\"body\":1,", "\"body\":3,")).unwrap_err();
    assert!(apart.to_string().contains("glued face to face"), "{apart}");
}

#[test]
fn the_vtu_files_carry_the_body_ids_and_the_internal_faces() {
    let tol = Tolerance::default();
    let system = BlockSystem::new(l_block_decompositions().remove(1))
        .with_bodies(vec![4, 4], &tol)
        .unwrap();
    let mut cells = Vec::new();
    crate::io::vtu::write_blocks_to(&system, &mut cells).unwrap();
    let cells = String::from_utf8(cells).unwrap();
    assert!(cells.contains("Name=\"body_id\""), "{cells}");
    let mut faces = Vec::new();
    crate::io::vtu::write_faces_to(&system, &mut faces).unwrap();
    let faces = String::from_utf8(faces).unwrap();
    // The column's bottom (face 0 of a cuboid: -z) lies on the floor: internal; the floor's
    // top (face 1) is covered only where the column stands: a real face.
    let internal = faces.split("Name=\"internal\"").nth(1).unwrap();
    let values: Vec<&str> = internal
        .split('>')
        .nth(1)
        .unwrap()
        .split('<')
        .next()
        .unwrap()
        .split_whitespace()
        .collect();
    assert_eq!(values.len(), 12);
    let ones: Vec<usize> = (0..12).filter(|&k| values[k] == "1").collect();
    assert_eq!(ones, [6], "{values:?}");
}

#[test]
fn the_csv_and_vtp_files_of_body_contacts_carry_the_regions() {
    let tol = Tolerance::default();
    let mut parts = with_body(0, u_block_decompositions().remove(1));
    parts.push((1, cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.5])));
    let system = BlockSystem::new(parts.iter().map(|p| p.1.clone()).collect())
        .with_bodies(parts.iter().map(|p| p.0).collect(), &tol)
        .unwrap();
    let found = system.detect_bodies(&tol);
    let mut csv = Vec::new();
    crate::io::csv::write_body_contacts_to(&found, &mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], crate::io::csv::BODY_CONTACTS_HEADER);
    let regions: Vec<&str> = rows[1..]
        .iter()
        .map(|r| r.split(',').nth(2).unwrap())
        .collect();
    assert_eq!(regions, ["0", "1", "2"]);
    assert!(rows[1..]
        .iter()
        .all(|r| r.starts_with("0,1,") && r.contains(",face-face,")));
    let mut vtp = Vec::new();
    crate::io::vtp::write_body_contacts_vtp_to(&found, &mut vtp).unwrap();
    let vtp = String::from_utf8(vtp).unwrap();
    assert!(vtp.contains("NumberOfPolys=\"3\""), "{vtp}");
    let region = vtp.split("Name=\"region\"").nth(1).unwrap();
    let region = &region[region.find('>').unwrap() + 1..region.find("</DataArray>").unwrap()];
    let mut values: Vec<&str> = region.split_whitespace().collect();
    values.sort();
    assert_eq!(values, ["0", "1", "2"]);
}

/// Blocks touching the box `[0, 4] x [0, 4] x [0, 2]` from outside: boxes lying on its top
/// at random places (face-face, some reaching over its rim: face-face of a smaller area),
/// cubes standing on a vertex and bars lying on an edge at random points of the top, a box
/// against its side, and boxes meeting its top edges and corners.
fn around_the_box(rng: &mut super::test_rng::Rng) -> Vec<ConvexBlock> {
    let mut out = Vec::new();
    // Placed apart from each other: each in its own cell of a 4 x 4 grid on the top.
    for cell in 0..12 {
        let (cx, cy) = ((cell % 4) as f64 + 0.2, (cell / 4) as f64 + 0.2);
        let (x, y) = (cx + 0.6 * rng.unit(), cy + 0.6 * rng.unit());
        let block = match cell % 3 {
            0 => cuboid([x - 0.15, y - 0.15, 2.0], [x + 0.15, y + 0.15, 2.4]),
            1 => {
                let tilt = DQuat::from_rotation_arc(DVec3::ONE.normalize(), -DVec3::Z);
                let spin = DQuat::from_rotation_z(6.0 * rng.unit());
                let cube = cuboid([0.0; 3], [0.2; 3]).transformed(spin * tilt, DVec3::ZERO, 1.0);
                let low = *cube
                    .vertices()
                    .iter()
                    .min_by(|p, q| p.z.total_cmp(&q.z))
                    .unwrap();
                cube.transformed(DQuat::IDENTITY, DVec3::new(x, y, 2.0) - low, 1.0)
            }
            _ => {
                let turn = DQuat::from_rotation_z(3.0 * rng.unit())
                    * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_4);
                cuboid([-0.15, -0.05, -0.05], [0.15, 0.05, 0.05]).transformed(
                    turn,
                    DVec3::new(x, y, 2.0 + 0.05 * 2f64.sqrt()),
                    1.0,
                )
            }
        };
        out.push(block);
    }
    out.push(cuboid([3.6, 3.6, 2.0], [4.3, 4.3, 2.5])); // over the corner: face-face
    out.push(cuboid([4.0, 1.0, 0.5], [4.5, 2.0, 1.5])); // against the side
    out.push(cuboid([4.0, 0.5, 2.0], [4.5, 0.9, 2.5])); // on the top edge: edge-edge sup.
    out.push(cuboid([4.0, -0.5, 2.0], [4.3, 0.0, 2.3])); // at a top corner: vertex-vertex
    out
}

#[test]
fn a_box_cut_into_random_parts_has_the_contacts_of_the_uncut_box() {
    // Reference: the same blocks against the uncut box, a convex block whose contacts the
    // ordinary detection finds (exact on convex blocks). Glued back, the parts must give the
    // same contacts: one region per block, same type, area and normal.
    let tol = Tolerance::default();
    let mut rng = super::test_rng::Rng(20);
    let domain = cuboid([0.0; 3], [4.0, 4.0, 2.0]);
    let mut merged = 0;
    for round in 0..6 {
        let others = around_the_box(&mut rng);
        let reference = {
            let mut blocks = vec![domain.clone()];
            blocks.extend(others.iter().cloned());
            let ids: Vec<u32> = (0..blocks.len() as u32).collect();
            let system = BlockSystem::new(blocks);
            let mut found = regions(
                &ids.iter()
                    .map(|&k| (k, system.blocks()[k as usize].clone()))
                    .collect::<Vec<_>>(),
            );
            found.retain(|r| r.0[0] == 0);
            found
        };
        assert_eq!(
            reference.len(),
            others.len(),
            "round {round}: every block touches the box"
        );
        // Cuts: vertical planes through random points of the top (some through the
        // contacts), at random angles, and a horizontal one.
        let mut normals = vec![[0.0, 0.0, 1.0]];
        let mut offsets = vec![0.5 + rng.unit()];
        for _ in 0..4 {
            let angle = 6.0 * rng.unit();
            let n = [angle.cos(), angle.sin(), 0.0];
            let p = [4.0 * rng.unit(), 4.0 * rng.unit()];
            normals.push(n);
            offsets.push(n[0] * p[0] + n[1] * p[1]);
        }
        let cut = BlockSystem::from_domain_cut(domain.clone(), &normals, &offsets, &tol).unwrap();
        assert!(cut.len() >= 4, "round {round}: {} parts", cut.len());
        let mut parts: Vec<(u32, ConvexBlock)> =
            cut.blocks().iter().map(|b| (0, b.clone())).collect();
        parts.extend(
            others
                .iter()
                .enumerate()
                .map(|(k, b)| (k as u32 + 1, b.clone())),
        );
        assert_eq!(regions(&parts), reference, "round {round}");
        // Not vacuous: some regions are made of several part contacts.
        let system = BlockSystem::new(parts.iter().map(|p| p.1.clone()).collect())
            .with_bodies(parts.iter().map(|p| p.0).collect(), &tol)
            .unwrap();
        let found = system.detect_bodies(&tol);
        merged += found.pieces.len() - found.contacts.len();
    }
    assert!(
        merged >= 10,
        "{merged} pieces merged into regions of others"
    );
}

/// Two parts of one body of a fine zig-zag slope excavation (`penedge generate` of a 10 m
/// box, one vertical joint set and a slope profile of 8,000 vertices), as generated, planes
/// included: prisms 10 m long along y whose cross-sections are needles 2.6 m long and 2 to
/// 8 mm wide, glued along one face of the slope (face 4 of the first, face 3 of the second,
/// one plane with opposite normals). The plane, fitted to the long thin face, leaves the
/// needles' shared tip 1.27e-8 inside the first part's face and outside the second's, beyond
/// the pair's length threshold (1.03e-8), so that the classification finds no face of the
/// second part holding the contact and calls the pair penetrating.
fn needles() -> [ConvexBlock; 2] {
    use crate::block::FaceOrigin;
    use crate::geometry::{Aabb, Plane};
    let part = |vertices: &[[f64; 3]], faces: &[&[u32]], planes: &[([f64; 3], [f64; 3])]| {
        let planes: Vec<Plane> = planes
            .iter()
            .map(|&(n, p)| Plane {
                normal: DVec3::from(n),
                point: DVec3::from(p),
            })
            .collect();
        let origins = vec![FaceOrigin::Unknown; faces.len()];
        // Checked at the domain's scale, as the generation made them.
        let domain = Aabb {
            min: DVec3::ZERO,
            max: DVec3::splat(10.0),
        };
        let tol = Tolerance::default();
        ConvexBlock::from_parts_in(vertices, faces, &planes, &origins, &tol, Some(&domain)).unwrap()
    };
    let a = part(
        &[
            [6.619577447, 0.0, 6.7027870550000035],
            [6.618327291000001, 0.0, 6.688780474999998],
            [7.1446246588908355, 0.0, 4.175638512728671],
            [7.1446246588908355, 10.0, 4.175638512728671],
            [6.618327291000001, 10.0, 6.688780474999998],
            [6.619577447, 10.0, 6.7027870550000035],
        ],
        &[
            &[0, 1, 2],
            &[3, 4, 5],
            &[2, 1, 4, 3],
            &[5, 4, 1, 0],
            &[2, 3, 5, 0],
        ],
        &[
            ([0.0, -1.0, 0.0], [5.0, 0.0, 5.0]),
            ([0.0, 1.0, 0.0], [5.0, 10.0, 5.0]),
            (
                [-0.9787679009252925, 0.0, -0.20497169589554765],
                [6.617702213, 4.999999999999999, 6.691765308000001],
            ),
            (
                [-0.996040422910225, -0.0, 0.08890149565007498],
                [6.6189523690000005, 5.0, 6.695783765],
            ),
            (
                [0.9790918262847176, -0.0, 0.2034187692973699],
                [6.620202525000001, 4.999999999999999, 6.699778439999996],
            ),
        ],
    );
    let b = part(
        &[
            [6.622077759999999, 0.0, 6.710728727000002],
            [6.620827602990678, 0.0, 6.69676982489592],
            [7.1446246588908355, 0.0, 4.175638512728671],
            [7.1446306101978, 0.0, 4.175610319778413],
            [7.1446306101978, 10.0, 4.175610319778413],
            [7.1446246588908355, 10.0, 4.175638512728671],
            [6.620827602990678, 10.0, 6.69676982489592],
            [6.622077759999999, 10.0, 6.710728727000002],
        ],
        &[
            &[0, 1, 2, 3],
            &[4, 5, 6, 7],
            &[3, 2, 5, 4],
            &[2, 1, 6, 5],
            &[7, 6, 1, 0],
            &[3, 4, 7, 0],
        ],
        &[
            ([0.0, -1.0, 0.0], [5.0, 0.0, 5.0]),
            ([0.0, 1.0, 0.0], [5.0, 10.0, 5.0]),
            (
                [-0.9784380582140522, 0.0, -0.20654047118740412],
                [6.6152019, 4.999999999999998, 6.683657271499988],
            ),
            (
                [-0.9790918262847176, 0.0, -0.2034187692973699],
                [6.620202525000001, 4.999999999999999, 6.699778439999996],
            ),
            (
                [-0.9960134835347997, -0.0, 0.08920280610425566],
                [6.621452681499999, 4.999999999999999, 6.703749275999999],
            ),
            (
                [0.9794099583739811, -0.0, 0.2018814836429451],
                [6.622702838, 4.999999999999999, 6.707696217000001],
            ),
        ],
    );
    [a, b]
}

/// The outward normal of the first needle's glued face, from its vertices (the line of its
/// two edges across, turned about y).
fn needle_face_normal(a: &ConvexBlock) -> DVec3 {
    let v = a.vertices();
    DVec3::Y.cross(v[0] - v[2]).normalize()
}

#[test]
fn needle_parts_glued_along_a_long_thin_face_touch_and_keep_their_internal_face() {
    let tol = Tolerance::default();
    let [a, b] = needles();
    // The premise: the classification calls the pair penetrating (both ways), though the
    // parts only touch: the shortest translation that separates them is below 1e-15.
    let mut det = crate::Detector::new(tol);
    assert_eq!(det.detect(&a, &b), crate::PairResult::Penetrating);
    assert_eq!(det.detect(&b, &a), crate::PairResult::Penetrating);
    let o = crate::overlap::overlap(&a, &b, &tol).unwrap();
    assert!(
        o.min_translation.length() < 1e-15,
        "{:?}",
        o.min_translation
    );
    // The glue is the whole face 3 of the second needle (its tip lies on the first one's
    // face 4, which reaches 6 mm farther): the face's length across times 10 m.
    let vb = b.vertices();
    let glued = (vb[1] - vb[2]).length() * 10.0;
    for (order, faces) in [([0, 1], [4, 3]), ([1, 0], [3, 4])] {
        let parts: Vec<ConvexBlock> = order.iter().map(|&k| [&a, &b][k].clone()).collect();
        let system = BlockSystem::new(parts)
            .with_bodies(vec![0, 0], &tol)
            .unwrap();
        let internal = system.internal_faces();
        assert_eq!(internal.len(), 1, "{internal:?}");
        assert_eq!((internal[0].parts, internal[0].faces), ([0, 1], faces));
        assert!(
            (internal[0].area - glued).abs() < 1e-9 * glued,
            "{internal:?}"
        );
        // The second needle's face is covered entirely, the first one's in part.
        let at_a = order.iter().position(|&k| k == 0).unwrap() as u32;
        assert!(system.is_internal_face(1 - at_a, 3));
        assert!(!system.is_internal_face(at_a, 4));
        let volume = system.body_mass_properties()[0].1.volume;
        assert!((volume - a.volume() - b.volume()).abs() < 1e-12);
    }
}

#[test]
fn needle_parts_pushed_into_each_other_beyond_the_gap_are_refused() {
    let tol = Tolerance::default();
    let [a, b] = needles();
    let n = needle_face_normal(&a);
    let gap = crate::Detector::new(tol).thresholds(&a, &b).gap;
    // The second needle moved into the first along the face normal: by half the gap it
    // still touches (glued), by twice the gap and by 1 µm (1e5 gaps) the parts overlap.
    for (depth, overlaps) in [(0.5 * gap, false), (2.0 * gap, true), (1e-6, true)] {
        let pushed = b.translated(-n * depth);
        let result = BlockSystem::new(vec![a.clone(), pushed]).with_bodies(vec![7, 7], &tol);
        match result {
            Err(e) => {
                assert!(overlaps, "{depth:e}: {e}");
                assert_eq!(
                    e,
                    ConcaveError::Overlap {
                        body: 7,
                        a: 0,
                        b: 1
                    }
                );
            }
            Ok(system) => {
                assert!(!overlaps, "{depth:e}: accepted");
                assert_eq!(system.internal_faces().len(), 1, "{depth:e}");
            }
        }
    }
}
