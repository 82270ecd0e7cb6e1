//! Rock bridges as concave blocks (docs/generation.md, "Rock bridges"): the pieces of a block
//! a bridged finite joint cut through are one body, so that the detection sees one block
//! while the bridge holds; the mechanics keeps them separate rigid bodies held by bonded
//! bridge contacts. References: the same rock without the finite joint (its blocks convex,
//! each its own body), and face areas from the geometry.

use penedge::generation::*;
use penedge::geometry::DVec3;
use penedge::mechanics::Simulation;
use penedge::system::BodyContact;
use penedge::{BlockSystem, ContactType, Tolerance};

/// A row of three columns 10 m wide (planes x = 10 and x = 20) of 10 m of rock under 5 m
/// more (plane z = 10), 10 m deep in y: six blocks.
fn rock() -> Spec {
    let vertical = Orientation::dip(90.0, 90.0);
    Spec::new(Domain::cuboid([0.0; 3], [30.0, 10.0, 15.0]).unwrap())
        .with(Discontinuity::plane([10.0, 0.0, 0.0], vertical))
        .with(Discontinuity::plane([20.0, 0.0, 0.0], vertical))
        .with(Discontinuity::plane(
            [0.0, 0.0, 10.0],
            Orientation::dip(0.0, 0.0),
        ))
}

/// A square joint of half side 3 dipping 30° towards +x through (15, 5, 5), the centre of
/// the middle lower block: it reaches x = 15 ± 3 cos 30° and y = 5 ± 3, inside the block,
/// whose section by its plane spans x = 10..20 (z = 5 ∓ 5 tan 30°, inside the block).
fn square_joint() -> Discontinuity {
    square_joint_at(15.0)
}

/// The square joint through `(x, 5, 5 + (x - 15) tan 30°)`, on the same plane.
fn square_joint_at(x: f64) -> Discontinuity {
    let t = 30f64.to_radians();
    let (u, w) = (DVec3::new(t.cos(), 0.0, t.sin()), DVec3::Y);
    let centre = DVec3::new(x, 5.0, 5.0 + (x - 15.0) * t.tan());
    let vertices = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(s, r)| (centre + u * (3.0 * s) + w * (3.0 * r)).to_array())
        .collect();
    Discontinuity::polygon(vertices).with_bridges()
}

/// Per body, its centroid (volume-weighted over its parts).
fn body_centroids(system: &BlockSystem) -> Vec<DVec3> {
    system
        .body_parts()
        .iter()
        .map(|(_, parts)| {
            let blocks = parts.iter().map(|&k| &system.blocks()[k as usize]);
            let (v, m) = blocks.fold((0.0, DVec3::ZERO), |(v, m), b| {
                (v + b.volume(), m + b.centroid() * b.volume())
            });
            m / v
        })
        .collect()
}

/// The contacts of the bodies, each named by the two bodies' centroids (rounded to the
/// millimetre, smaller first), sorted: comparable between two systems whose bodies are the
/// same rock whatever their parts and ids.
fn named_contacts(system: &BlockSystem) -> Vec<([[i64; 3]; 2], u32, ContactType, f64)> {
    let centroids = body_centroids(system);
    let key = |b: u32| {
        (centroids[b as usize] * 1000.0)
            .round()
            .as_i64vec3()
            .to_array()
    };
    let mut out: Vec<_> = system
        .detect_bodies(&Tolerance::default())
        .contacts
        .iter()
        .map(|c: &BodyContact| {
            let mut pair = [key(c.bodies[0]), key(c.bodies[1])];
            pair.sort();
            (pair, c.region, c.kind, c.area)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)));
    out
}

#[test]
fn the_block_a_bridged_joint_ends_inside_is_one_body_of_its_pieces() {
    let out = generate(&rock().with(square_joint())).unwrap();
    let system = &out.system;
    // Four seams cross the section: 5 pieces below the plane, 1 above, for 1 block.
    assert_eq!(system.len(), 6 + 5);
    let bodies = system.body_parts();
    assert_eq!(bodies.len(), 6, "one body per block of the rock");
    let (_, parts) = bodies.iter().find(|(_, p)| p.len() > 1).unwrap();
    assert_eq!(parts.len(), 6);
    let volume: f64 = parts
        .iter()
        .map(|&k| system.blocks()[k as usize].volume())
        .sum();
    assert!((volume - 1000.0).abs() < 1e-9, "{volume}");
    // The piece above keeps one face on the plane, over the joint and the bridge: glued over
    // the whole of it (bridge pieces and the crack), so inside the body.
    let n = DVec3::new(-(30f64.to_radians().sin()), 0.0, 30f64.to_radians().cos());
    let above = parts
        .iter()
        .flat_map(|&k| (0..system.blocks()[k as usize].n_faces()).map(move |f| (k, f)))
        .filter(|&(k, f)| {
            let p = system.blocks()[k as usize].planes()[f];
            (p.normal + n).length() < 1e-9
                && (p.point - DVec3::new(15.0, 5.0, 5.0)).dot(n).abs() < 1e-9
        })
        .collect::<Vec<_>>();
    assert_eq!(above.len(), 1, "one face of outward normal -n on the plane");
    let (k, f) = above[0];
    assert!(system.is_internal_face(k, f as u32));
}

#[test]
fn the_detection_sees_the_block_as_without_the_joint() {
    let with = generate(&rock().with(square_joint())).unwrap().system;
    let without = generate(&rock()).unwrap().system;
    assert_eq!(without.len(), 6);
    assert!(!without.has_concave());
    let (got, reference) = (named_contacts(&with), named_contacts(&without));
    assert_eq!(got.len(), reference.len(), "{got:?}\nvs\n{reference:?}");
    for (g, r) in got.iter().zip(&reference) {
        assert_eq!((g.0, g.1, g.2), (r.0, r.1, r.2));
        assert!((g.3 - r.3).abs() < 1e-9, "{g:?} vs {r:?}");
    }
    // The middle lower block's faces against its left and right neighbours (10 × 10) and the
    // block above it (10 × 10), each one face-face region whatever pieces make it.
    let middle = [15000, 5000, 5000];
    let faces: Vec<_> = got
        .iter()
        .filter(|c| c.0.contains(&middle) && c.2 == ContactType::FaceFace)
        .collect();
    assert_eq!(faces.len(), 3, "{faces:?}");
    for c in faces {
        assert!((c.3 - 100.0).abs() < 1e-9, "{c:?}");
    }
    // No contact inside the body: the detection reports pairs of distinct bodies only, and
    // the rock has no other pair than the reference's.
    let found = with.detect_bodies(&Tolerance::default());
    assert!(found.contacts.iter().all(|c| c.bodies[0] < c.bodies[1]));
    assert!(found.penetrating.is_empty());
}

#[test]
fn a_crack_open_to_a_neighbour_leaves_their_contact_whole() {
    // Centred at x = 18, the joint reaches x = 15.40..20.60: it ends inside the middle block
    // and inside the right one, both cut through, its mouth a line across the face they
    // share (x = 20). Their contact is still one face-face region of 10 × 10, made of the
    // pieces of both sides of the crack.
    let with = generate(&rock().with(square_joint_at(18.0)))
        .unwrap()
        .system;
    assert_eq!(with.body_parts().len(), 6);
    assert!(
        with.body_parts()
            .iter()
            .filter(|(_, p)| p.len() > 1)
            .count()
            == 2
    );
    let without = generate(&rock()).unwrap().system;
    let (got, reference) = (named_contacts(&with), named_contacts(&without));
    assert_eq!(got.len(), reference.len(), "{got:?}\nvs\n{reference:?}");
    for (g, r) in got.iter().zip(&reference) {
        assert_eq!((g.0, g.1, g.2), (r.0, r.1, r.2));
        assert!((g.3 - r.3).abs() < 1e-9, "{g:?} vs {r:?}");
    }
    let shared = [[15000, 5000, 5000], [25000, 5000, 5000]];
    let c = got.iter().find(|c| c.0 == shared).unwrap();
    assert_eq!(c.2, ContactType::FaceFace);
    assert!((c.3 - 100.0).abs() < 1e-9, "{c:?}");
    let found = with.detect_bodies(&Tolerance::default());
    let pieces = |k: usize| found.piece_offsets[k + 1] - found.piece_offsets[k];
    let k = (0..found.contacts.len())
        .max_by_key(|&k| pieces(k))
        .unwrap();
    assert!(
        pieces(k) >= 4,
        "the shared face's region is made of several pieces"
    );
}

#[test]
fn bodies_do_not_depend_on_whether_a_joint_set_cuts_before_or_after() {
    // Vertical planes x = 2.5, 5, 7.5 through [0, 10]³ and the square joint centred there:
    // it reaches x = 2.40..7.60 and y = 2..8, so it ends inside every column, and each
    // column is one body held by its bridges, whichever is cut first.
    let set = Discontinuity::set(JointSet {
        origin: [2.5, 0.0, 0.0],
        ..JointSet::new(Orientation::dip(90.0, 90.0), 2.5)
    });
    let t = 30f64.to_radians();
    let (u, w) = (DVec3::new(t.cos(), 0.0, t.sin()), DVec3::Y);
    let centre = DVec3::splat(5.0);
    let square = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(s, r)| (centre + u * (3.0 * s) + w * (3.0 * r)).to_array())
        .collect();
    let joint = Discontinuity::polygon(square).with_bridges();
    let domain = || Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap());
    for spec in [
        domain().with(set.clone()).with(joint.clone()),
        domain().with(joint.clone()).with(set.clone()),
    ] {
        let system = generate(&spec).unwrap().system;
        let bodies = system.body_parts();
        assert_eq!(bodies.len(), 4, "one body per column");
        let mut columns: Vec<(f64, f64)> = body_centroids(&system)
            .iter()
            .zip(&bodies)
            .map(|(c, (_, parts))| {
                let v = parts.iter().map(|&k| system.blocks()[k as usize].volume());
                (c.x, v.sum())
            })
            .collect();
        columns.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (k, (x, v)) in columns.iter().enumerate() {
            assert!(
                (x - (1.25 + 2.5 * k as f64)).abs() < 1e-9,
                "column {k} at {x}"
            );
            assert!((v - 250.0).abs() < 1e-9, "column {k}: {v}");
        }
    }
}

#[test]
fn a_bridged_system_keeps_its_body_ids_in_its_block_file() {
    let system = generate(&rock().with(square_joint())).unwrap().system;
    let text = penedge::io::json::to_json_string(&system);
    let back = penedge::io::json::from_json_str(&text).unwrap();
    assert_eq!(back.body_ids(), system.body_ids());
    assert_eq!(back.internal_faces().len(), system.internal_faces().len());
    assert_eq!(back.rigid_body_ids(), system.rigid_body_ids());
}

#[test]
fn the_mechanics_keeps_the_pieces_apart_held_by_bonded_bridges() {
    let system = generate(&rock().with(square_joint())).unwrap().system;
    let mut sim = Simulation::new(&system, 2600.0).unwrap();
    // Every piece its own rigid body, in block order: the bridge can break.
    assert_eq!(sim.bodies().len(), system.len());
    let identity: Vec<u32> = (0..system.len() as u32).collect();
    assert_eq!(sim.block_bodies(), &identity[..]);
    assert_eq!(sim.body_of_block(3), Some(3));
    assert_eq!(sim.body_of_block(system.len()), None);
    sim.step().unwrap();
    // The contacts on the joint's plane (normal ±n) are the piece above's with the pieces
    // below: a joint contact with the one whose face there is the joint's, bridge contacts
    // with those whose face there is a bridge face, bonded at the start.
    let t = 30f64.to_radians();
    let n = DVec3::new(-t.sin(), 0.0, t.cos());
    let below = |bridge: bool| -> Vec<u32> {
        let on_plane = |b: &penedge::ConvexBlock, f: usize| {
            let p = b.planes()[f];
            (p.normal - n).length() < 1e-9
                && (p.point - DVec3::new(15.0, 5.0, 5.0)).dot(n).abs() < 1e-9
        };
        (0..system.len() as u32)
            .filter(|&k| {
                let b = &system.blocks()[k as usize];
                (0..b.n_faces())
                    .any(|f| on_plane(b, f) && b.face_origins()[f].is_bridge() == bridge)
            })
            .collect()
    };
    let (joint_piece, bridge_pieces) = (below(false), below(true));
    assert_eq!((joint_piece.len(), bridge_pieces.len()), (1, 4));
    let contacts = sim.contacts();
    let (mut joint, mut bridge) = (Vec::new(), Vec::new());
    for (i, c) in contacts.list.iter().enumerate() {
        if c.normal.cross(n).length() > 1e-9 {
            continue;
        }
        if c.bridge {
            assert!(contacts.subs_of(i).iter().all(|s| s.bonded), "{c:?}");
            bridge.push(c.bodies);
        } else {
            joint.push(c.bodies);
        }
    }
    assert_eq!(joint.len(), 1);
    assert!(joint[0].contains(&joint_piece[0]));
    let mut touched: Vec<u32> = bridge.iter().flatten().copied().collect();
    touched.sort_unstable();
    touched.dedup();
    let above = joint[0][0] + joint[0][1] - joint_piece[0];
    let mut expected = [bridge_pieces.clone(), vec![above]].concat();
    expected.sort_unstable();
    assert_eq!(touched, expected);
    assert_eq!(bridge.len(), 4);
}

#[test]
fn restart_files_keep_the_blocks_bodies() {
    let a = penedge::ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let b = penedge::ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
    let c = penedge::ConvexBlock::cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]).unwrap();
    let system = BlockSystem::new(vec![a, b, c])
        .with_bodies(vec![1, 0, 1], &Tolerance::default())
        .unwrap();
    let sim = Simulation::new(&system, 2600.0).unwrap();
    // Bodies in the order of their first block: blocks 0 and 2 are body 0.
    assert_eq!(sim.block_bodies(), &[0, 1, 0]);
    let text = sim.to_state_string().unwrap();
    let back = Simulation::from_state_str(&text).unwrap();
    assert_eq!(back.block_bodies(), &[0, 1, 0]);
    // A body without a block is named.
    let bad = text.replace("\"block_bodies\":[0,1,0]", "\"block_bodies\":[0,0,0]");
    assert_ne!(bad, text);
    let err = Simulation::from_state_str(&bad).unwrap_err().to_string();
    assert!(err.contains("block_bodies"), "{err}");
    // An older file without the map: per part, in body order.
    let old = text.replace("\"block_bodies\":[0,1,0],", "");
    assert_ne!(old, text);
    assert_eq!(
        Simulation::from_state_str(&old).unwrap().block_bodies(),
        &[0, 0, 1]
    );
}

#[test]
fn parts_an_excavation_glued_stay_one_rigid_body_beside_the_bridges() {
    // A cavern along x through the upper layer: each upper block a ring of parts, one body
    // and one rigid body; the bridged block below one body of 6 rigid pieces.
    let cavern = Excavation::new(ExcavationShape::Cavern {
        center: [15.0, 5.0, 12.5],
        trend: 90.0,
        length: 40.0,
        width: 2.0,
        height: 1.0,
    });
    let mut spec = rock().with(square_joint());
    spec.excavations.push(cavern);
    let system = generate(&spec).unwrap().system;
    assert_eq!(system.body_parts().len(), 6);
    let sim = Simulation::new(&system, 2600.0).unwrap();
    assert_eq!(sim.bodies().len(), 3 + 2 + 6);
    let map = sim.block_bodies();
    for (_, parts) in system.body_parts() {
        let above = system.blocks()[parts[0] as usize].centroid().z > 10.0;
        let rigid: std::collections::BTreeSet<u32> =
            parts.iter().map(|&k| map[k as usize]).collect();
        let expected = if above || parts.len() == 1 { 1 } else { 6 };
        assert_eq!(rigid.len(), expected, "body of parts {parts:?}");
        if above {
            assert!(parts.len() > 1, "a ring is made of several parts");
        }
    }
}
