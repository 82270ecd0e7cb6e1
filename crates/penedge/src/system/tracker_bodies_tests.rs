//! The tracker on concave blocks: after every step its contacts of the bodies equal
//! [`BlockSystem::detect_bodies`] on the blocks at their new poses (a full detection, regions
//! made anew), and its part contacts equal [`BlockSystem::detect`]'s between parts of
//! different bodies.

use super::*;
use crate::classify::ContactType;
use crate::system::test_rng::Rng;
use glam::DQuat;

fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
    ConvexBlock::cuboid(lo, hi).unwrap()
}

/// Per block, the pose of its body.
fn part_poses(system: &BlockSystem, body_poses: &[Pose]) -> Vec<Pose> {
    (0..system.len() as u32)
        .map(|k| body_poses[system.body_of(k) as usize])
        .collect()
}

/// The blocks at `poses`, with the bodies of `system`.
fn moved(system: &BlockSystem, poses: &[Pose], tol: &Tolerance) -> BlockSystem {
    let blocks = system.blocks().iter().zip(poses);
    BlockSystem::new(
        blocks
            .map(|(b, p)| b.transformed(p.rotation, p.translation, 1.0))
            .collect(),
    )
    .with_bodies(system.body_ids(), tol)
    .unwrap()
}

/// Updates the tracker to `poses` and checks it against full detections there: exactly
/// against [`BlockSystem::detect_bodies`] on the tracker's own placement of the blocks, and
/// against the blocks moved independently ([`ConvexBlock::transformed`], which rounds
/// differently) in every discrete answer (pairs, regions, types, pieces and features,
/// penetrating pairs), its numbers within 1e-9.
fn check(tracker: &mut ContactTracker, system: &BlockSystem, poses: &[Pose], tol: &Tolerance) {
    let report = tracker.update(poses).unwrap();
    let tracked = tracker.body_contacts().unwrap().clone();
    let placed = tracker.system().detect_bodies(tol);
    assert!(
        tracked == placed,
        "{report:?}: {}",
        difference(&tracked, &placed)
    );
    let full = moved(system, poses, tol);
    let bodies = full.detect_bodies(tol);
    assert_eq!(tracked.penetrating, bodies.penetrating, "{report:?}");
    assert_eq!(tracked.pieces, bodies.pieces, "{report:?}");
    assert_eq!(tracked.piece_offsets, bodies.piece_offsets, "{report:?}");
    assert_eq!(tracked.piece_point_offsets, bodies.piece_point_offsets);
    assert_eq!(tracked.contacts.len(), bodies.contacts.len(), "{report:?}");
    for (t, f) in tracked.contacts.iter().zip(&bodies.contacts) {
        assert_eq!((t.bodies, t.region, t.kind), (f.bodies, f.region, f.kind));
        let near = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(a, b)| (a - b).abs() < 1e-9);
        assert!(
            near(&t.normal, &f.normal) && near(&[t.distance, t.area], &[f.distance, f.area]),
            "{t:?} {f:?}"
        );
    }
    let points = tracked.piece_points.iter().zip(&bodies.piece_points);
    assert!(points
        .into_iter()
        .all(|(p, q)| (0..3).all(|c| (p[c] - q[c]).abs() < 1e-9)));
    let mut parts = full.detect(tol);
    parts
        .contacts
        .retain(|c| full.body_of(c.pair[0]) != full.body_of(c.pair[1]));
    parts
        .penetrating
        .retain(|p| full.body_of(p[0]) != full.body_of(p[1]));
    assert_eq!(tracker.contacts(), &parts, "{report:?}");
}

/// Where two outputs differ, in words.
fn difference(tracked: &BodyContacts, full: &BodyContacts) -> String {
    let first = (0..tracked.contacts.len().max(full.contacts.len()))
        .find(|&k| tracked.contacts.get(k) != full.contacts.get(k));
    match first {
        Some(k) => format!(
            "region {k}: tracked {:?}, full {:?}",
            tracked.contacts.get(k),
            full.contacts.get(k),
        ),
        None => format!(
            "regions agree; penetrating {:?} / {:?}; pieces equal {}, points equal {}",
            tracked.penetrating,
            full.penetrating,
            tracked.pieces == full.pieces,
            tracked.piece_points == full.piece_points
        ),
    }
}

/// A pose turning by a small random rotation about `centre`, then shifting a little,
/// composed after `pose`.
fn nudged(rng: &mut Rng, pose: Pose, centre: DVec3, shift: f64, angle: f64) -> Pose {
    let axis = DVec3::new(rng.signed(), rng.signed(), rng.signed()).normalize();
    let turn = DQuat::from_axis_angle(axis, angle * rng.signed());
    let c = pose.apply(centre);
    let by = DVec3::new(rng.signed(), rng.signed(), rng.signed()) * shift;
    Pose {
        rotation: (turn * pose.rotation).normalize(),
        translation: turn * (pose.translation - c) + c + by,
    }
}

/// A grid of `n`^3 unit cubes glued at random into polycubes (L-, U- and other concave
/// blocks, blocks sitting in their notches), each face of two neighbours glued with
/// probability `glue`.
fn polycubes(n: usize, glue: f64, rng: &mut Rng) -> BlockSystem {
    let index = |x: usize, y: usize, z: usize| x + n * (y + n * z);
    let mut root: Vec<usize> = (0..n * n * n).collect();
    fn find(root: &mut [usize], mut k: usize) -> usize {
        while root[k] != k {
            root[k] = root[root[k]];
            k = root[k];
        }
        k
    }
    let mut blocks = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = [x as f64, y as f64, z as f64];
                blocks.push(cuboid(p, p.map(|c| c + 1.0)));
                let k = index(x, y, z);
                for (near, ok) in [
                    (k.wrapping_sub(1), x > 0),
                    (k.wrapping_sub(n), y > 0),
                    (k.wrapping_sub(n * n), z > 0),
                ] {
                    if ok && rng.unit() < glue {
                        let (a, b) = (find(&mut root, k), find(&mut root, near));
                        root[a.max(b)] = a.min(b);
                    }
                }
            }
        }
    }
    let ids: Vec<u32> = (0..n * n * n).map(|k| find(&mut root, k) as u32).collect();
    BlockSystem::new(blocks)
        .with_bodies(ids, &Tolerance::with_gap(1e-3).unwrap())
        .unwrap()
}

/// Random rigid motions of the concave blocks of a glued grid: some steps move every body,
/// some a few (the tracker then rebuilds the regions of the changed pairs of bodies only),
/// some none; pairs of bodies touch, part and penetrate, in one region or several. Every
/// step equals a full detection.
#[test]
fn random_motions_of_concave_blocks_agree_with_a_full_detection() {
    let mut rng = Rng(41);
    let tol = Tolerance::with_gap(1e-3).unwrap();
    for round in 0..2 {
        let system = polycubes(4, 0.2, &mut rng);
        let bodies = system.body_parts();
        assert!(bodies.iter().any(|(_, p)| p.len() >= 3), "concave blocks");
        let mut tracker = ContactTracker::new(&system, tol, 0.05).unwrap();
        assert_eq!(tracker.body_contacts(), Some(&system.detect_bodies(&tol)));
        let several = |found: &BodyContacts| found.contacts.iter().any(|c| c.region > 0);
        assert!(several(tracker.body_contacts().unwrap()));
        let centres: Vec<DVec3> = (0..system.len() as u32)
            .map(|b| {
                let parts = bodies.iter().find(|(id, _)| *id == b);
                parts.map_or(DVec3::ZERO, |(_, p)| {
                    system.blocks()[p[0] as usize].centroid()
                })
            })
            .collect();
        let mut body_poses = vec![Pose::IDENTITY; system.len()];
        let (mut sparse, mut penetrating, mut many) = (0, 0, 0);
        // (share of the bodies moved, shift, angle)
        let steps = [
            (1.0, 1e-5, 1e-5),
            (0.1, 2e-4, 1e-4),
            (0.1, 2e-4, 1e-4),
            (0.0, 0.0, 0.0),
            (0.05, 1e-3, 5e-4),
            (1.0, 1e-4, 1e-4),
            (0.05, 5e-4, 0.0),
            (0.3, 0.03, 0.01),
            (0.05, 5e-4, 0.0),
        ];
        for (share, shift, angle) in steps {
            for (b, pose) in body_poses.iter_mut().enumerate() {
                if rng.unit() < share {
                    *pose = nudged(&mut rng, *pose, centres[b], shift, angle);
                }
            }
            let poses = part_poses(&system, &body_poses);
            check(&mut tracker, &system, &poses, &tol);
            let found = tracker.body_contacts().unwrap();
            sparse += usize::from(share > 0.0 && share < 0.2);
            penetrating += found.penetrating.len();
            many += usize::from(several(found));
        }
        assert!(sparse >= 4 && penetrating > 0 && many > 0, "round {round}");
    }
}

/// A block sitting in the corner of an L-block's notch touches its floor and its wall in two
/// regions; moved off the wall and back, and lifted off the floor, it touches in one region,
/// then two again, each step as a full detection finds it.
#[test]
fn a_block_in_a_notch_touches_in_two_regions_then_one() {
    let tol = Tolerance::default();
    // The L-block: a floor slab (parts 0, 1, glued at x = 1.5) and a wall (part 2) on part
    // 0; the block (3) stands on the floor against the wall, across the glue of parts 0, 1.
    let system = BlockSystem::new(vec![
        cuboid([0.0, 0.0, 0.0], [1.5, 1.0, 1.0]),
        cuboid([1.5, 0.0, 0.0], [3.0, 1.0, 1.0]),
        cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 3.0]),
        cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
    ])
    .with_bodies(vec![0, 0, 0, 1], &tol)
    .unwrap();
    let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
    let regions = |t: &ContactTracker| {
        let found = t.body_contacts().unwrap();
        let mut r: Vec<(u32, ContactType, i64, [i64; 3])> = found
            .contacts
            .iter()
            .map(|c| {
                let normal = c.normal.map(|x| (x * 1e6).round() as i64);
                (c.region, c.kind, (c.area * 1e6).round() as i64, normal)
            })
            .collect();
        r.sort_unstable_by_key(|x| x.3);
        r
    };
    let floor = (ContactType::FaceFace, 1_000_000, [0, 0, 1_000_000]);
    let wall = (ContactType::FaceFace, 1_000_000, [1_000_000, 0, 0]);
    let both: Vec<_> = regions(&tracker).iter().map(|r| (r.1, r.2, r.3)).collect();
    assert_eq!(both, [floor, wall]);
    let shift = |x: f64, z: f64| {
        let mut poses = vec![Pose::IDENTITY; 4];
        poses[3].translation = DVec3::new(x, 0.0, z);
        poses
    };
    // Off the wall by 1 mm: the floor only; back: both; lifted: the wall only (the wall is
    // 2 m tall: still 1 m² of it).
    for (x, z, expected) in [
        (1e-3, 0.0, vec![floor]),
        (0.0, 0.0, vec![floor, wall]),
        (0.0, 1e-3, vec![wall]),
        (0.0, 0.0, vec![floor, wall]),
    ] {
        check(&mut tracker, &system, &shift(x, z), &tol);
        let found: Vec<_> = regions(&tracker).iter().map(|r| (r.1, r.2, r.3)).collect();
        assert_eq!(found, expected, "{x} {z}");
        let indices: Vec<u32> = tracker
            .body_contacts()
            .unwrap()
            .contacts
            .iter()
            .map(|c| c.region)
            .collect();
        assert_eq!(indices, (0..expected.len() as u32).collect::<Vec<_>>());
    }
    // The floor region spans the glue of parts 0 and 1 under the block: two face-face
    // pieces of 0.5 m² each.
    let found = tracker.body_contacts().unwrap();
    let floor_region = found
        .contacts
        .iter()
        .position(|c| c.normal[2] > 0.5)
        .unwrap();
    let halves: Vec<u32> = found
        .pieces_of(floor_region)
        .iter()
        .filter(|p| p.contact.kind == ContactType::FaceFace)
        .map(|p| p.pair[0])
        .collect();
    assert_eq!(halves, [0, 1]);
}

/// The parts of one body must share a pose: a tracker refuses others, naming them.
#[test]
fn parts_of_one_body_with_different_poses_are_refused() {
    let tol = Tolerance::default();
    let system = BlockSystem::new(vec![
        cuboid([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
        cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
        cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
    ])
    .with_bodies(vec![0, 0, 1], &tol)
    .unwrap();
    let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
    let mut poses = vec![Pose::IDENTITY; 3];
    poses[1].translation.z = 1e-3;
    assert_eq!(
        tracker.update(&poses),
        Err(TrackerError::BodyPose {
            body: 0,
            first: 0,
            part: 1
        })
    );
    // Moved together, they are one body: the contacts follow.
    poses[0].translation.z = 1e-3;
    check(&mut tracker, &system, &poses, &tol);
}

/// One rotation given as `q`, `-q` or a multiple of `q` to the parts of one body is one
/// pose (a rotation, not a quaternion, is compared): the update is taken, and the parts are
/// placed exactly as with `q` for each; a rotation that differs, however little, is refused.
#[test]
fn parts_of_one_body_take_one_rotation_as_any_quaternion_of_it() {
    let tol = Tolerance::default();
    let system = BlockSystem::new(vec![
        cuboid([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
        cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
        cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
        cuboid([0.0, 0.0, -1.0], [2.0, 1.0, 0.0]),
    ])
    .with_bodies(vec![0, 0, 0, 1], &tol)
    .unwrap();
    let q = DQuat::from_axis_angle(DVec3::new(0.3, -0.5, 0.8).normalize(), 0.4);
    let t = DVec3::new(0.25, -0.5, 3.0);
    let pose = |rotation: DQuat| Pose {
        rotation,
        translation: t,
    };
    // Body 1 moves with body 0: they keep touching along z = 0 (turned).
    let same = vec![pose(q); 4];
    let mut expected = ContactTracker::tracking_bodies(&system, tol, 0.1).unwrap();
    expected.update(&same).unwrap();
    assert!(!expected.body_contacts().unwrap().contacts.is_empty());
    for (b, c) in [(-q, q * 3.0), (q * -2.5, q * 1e-3), (q, -q)] {
        let mut tracker = ContactTracker::tracking_bodies(&system, tol, 0.1).unwrap();
        let poses = vec![pose(q), pose(b), pose(c), pose(q)];
        tracker.update(&poses).unwrap();
        let vertices = |t: &mut ContactTracker| -> Vec<Vec<DVec3>> {
            let blocks = t.system().blocks();
            blocks.iter().map(|b| b.vertices().to_vec()).collect()
        };
        assert_eq!(vertices(&mut tracker), vertices(&mut expected));
        assert_eq!(tracker.body_contacts(), expected.body_contacts());
    }
    // Another rotation by 1e-9 rad, or another translation, is another pose.
    let turned = q * DQuat::from_rotation_z(1e-9);
    for other in [pose(-turned), Pose::new(q, t + DVec3::X * 1e-12).unwrap()] {
        let mut tracker = ContactTracker::tracking_bodies(&system, tol, 0.1).unwrap();
        let poses = vec![pose(q), pose(q), other, pose(q)];
        assert_eq!(
            tracker.update(&poses),
            Err(TrackerError::BodyPose {
                body: 0,
                first: 0,
                part: 2
            })
        );
    }
}

/// On convex blocks, a tracker made to report the contacts of the bodies gives
/// [`BlockSystem::detect_bodies`]' regions (one per touching pair) at every step, and its
/// part contacts are those of an ordinary tracker.
#[test]
fn convex_blocks_tracked_as_bodies() {
    let tol = Tolerance::default();
    let system = crate::system::paper_example(crate::system::PaperExample::Three).unwrap();
    let mut tracker = ContactTracker::tracking_bodies(&system, tol, 0.5).unwrap();
    let mut plain = ContactTracker::new(&system, tol, 0.5).unwrap();
    assert!(plain.body_contacts().is_none());
    let mut rng = Rng(5);
    let mut poses = vec![Pose::IDENTITY; system.len()];
    for (shift, angle) in [(1e-3, 1e-4), (1e-4, 1e-4), (0.0, 0.0), (1e-2, 1e-3)] {
        for (pose, block) in poses.iter_mut().zip(system.blocks()) {
            *pose = nudged(&mut rng, *pose, block.centroid(), shift, angle);
        }
        check(&mut tracker, &system, &poses, &tol);
        plain.update(&poses).unwrap();
        assert_eq!(plain.contacts(), tracker.contacts());
    }
}
