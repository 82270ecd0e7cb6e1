//! The detection of a system whose blocks are parts of bodies (concave blocks around
//! excavations and under slopes, pieces held by rock bridges): two parts of one body are
//! glued into one rigid block, so the glue between them is never a contact, in
//! `BlockSystem::detect` as in the contact tracker and `detect_bodies`.
//!
//! References: the same blocks as a system without bodies (each block its own body),
//! detected, with the pairs of parts of one body taken out by their body ids; and a bridged
//! cube worked out by hand (one block: no contact at all).

use penedge::generation::{generate, Discontinuity, Domain, Spec};
use penedge::io::spec::read_spec;
use penedge::system::{ContactTracker, SystemContacts};
use penedge::{BlockSystem, Tolerance};
use std::path::PathBuf;

fn example(name: &str) -> BlockSystem {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    generate(&read_spec(&path).unwrap()).unwrap().system
}

/// The contacts of `system`'s blocks found as if each were its own body, less the pairs of
/// two parts of one body of `system` (by its body ids); and how many such pairs there were.
fn per_part_less_same_body(system: &BlockSystem, tol: &Tolerance) -> (SystemContacts, usize) {
    let ids = system.body_ids();
    let mut found = BlockSystem::new(system.blocks().to_vec()).detect(tol);
    let before = found.contacts.len();
    found
        .contacts
        .retain(|c| ids[c.pair[0] as usize] != ids[c.pair[1] as usize]);
    let same_body = before - found.contacts.len();
    found
        .penetrating
        .retain(|p| ids[p[0] as usize] != ids[p[1] as usize]);
    (found, same_body)
}

#[test]
fn generated_concave_blocks_report_no_contact_between_parts_of_one_body() {
    let tol = Tolerance::default();
    for name in [
        "tunnel_circular.toml",
        "cavern.toml",
        "shaft.toml",
        "slope_topography.toml",
    ] {
        let system = example(name);
        let bodies = system.body_parts().len();
        assert!(bodies < system.len(), "{name}: some body has several parts");
        let found = system.detect(&tol);
        let (expected, same_body) = per_part_less_same_body(&system, &tol);
        // The glue inside the blocks was there to be left out.
        assert!(same_body > 0, "{name}");
        assert_eq!(found, expected, "{name}");
        let ids = system.body_ids();
        assert!(found
            .contacts
            .iter()
            .all(|c| ids[c.pair[0] as usize] != ids[c.pair[1] as usize]));
        // With the geometry: the same contacts, one geometry row each.
        let (with_geometry, geometry) = system.detect_with_geometry(&tol);
        assert_eq!(with_geometry, found, "{name}");
        assert_eq!(geometry.len(), found.contacts.len(), "{name}");
        // The tracker reports the same contacts (docs/systems.md, "Time stepping").
        let tracker = ContactTracker::new(&system, tol, 0.0).unwrap();
        assert_eq!(tracker.contacts(), &found, "{name}");
        // The contacts of the bodies are made of exactly these part contacts.
        let regions = system.detect_bodies(&tol);
        if regions.penetrating.is_empty() {
            let mut pieces: Vec<[u32; 2]> = regions
                .pieces
                .iter()
                .map(|p| [p.pair[0].min(p.pair[1]), p.pair[0].max(p.pair[1])])
                .collect();
            pieces.sort_unstable();
            let pairs: Vec<[u32; 2]> = found.contacts.iter().map(|c| c.pair).collect();
            assert_eq!(pieces, pairs, "{name}");
        }
    }
}

/// A 10 m cube with a horizontal 4 x 4 m square joint with rock bridges inside it at
/// z = 5: the joint ends inside the cube, so the cube is cut through into pieces held by
/// the bridges, one body. One block touches no other block: no contact.
#[test]
fn a_cube_held_by_rock_bridges_is_one_block_without_contacts() {
    let tol = Tolerance::default();
    let square = [
        [3.0, 3.0, 5.0],
        [7.0, 3.0, 5.0],
        [7.0, 7.0, 5.0],
        [3.0, 7.0, 5.0],
    ];
    let spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap())
        .with(Discontinuity::polygon(square.to_vec()).with_bridges());
    let system = generate(&spec).unwrap().system;
    assert!(system.len() > 1, "the joint cuts the cube into pieces");
    assert_eq!(system.body_parts().len(), 1);
    let found = system.detect(&tol);
    assert!(found.contacts.is_empty(), "{:?}", found.contacts);
    assert!(found.penetrating.is_empty());
    assert!(system.detect_with_geometry(&tol).0.contacts.is_empty());
    assert!(system.detect_bodies(&tol).contacts.is_empty());
    // The pieces touch each other: as blocks of their own they would be in contact.
    let (_, same_body) = per_part_less_same_body(&system, &tol);
    assert!(same_body > 0);
}

/// A system without bodies keeps every pair: its contacts are those of every pair of its
/// blocks queried one by one (no broad phase, no pair list: brute force over the 26 blocks of
/// the paper's Example 3).
#[test]
fn blocks_that_are_their_own_bodies_keep_every_contact() {
    use penedge::contact::Detector;
    use penedge::PairResult;
    let tol = Tolerance::default();
    let system = example("paper_example_3.toml");
    assert!(!system.has_concave());
    let blocks = system.blocks();
    let mut detector = Detector::new(tol);
    let mut expected = Vec::new();
    for i in 0..blocks.len() {
        for j in i + 1..blocks.len() {
            if let PairResult::Contact(c) = detector.detect(&blocks[i], &blocks[j]) {
                expected.push(([i as u32, j as u32], c.kind));
            }
        }
    }
    let found: Vec<_> = system
        .detect(&tol)
        .contacts
        .iter()
        .map(|c| (c.pair, c.contact.kind))
        .collect();
    assert_eq!(found, expected);
}

/// Twelve unit cubes in a row (11 touching pairs), the last two one body when `glued`.
fn cube_row(glued: bool, tol: &Tolerance) -> BlockSystem {
    use penedge::ConvexBlock;
    let blocks: Vec<ConvexBlock> = (0..12)
        .map(|i| {
            let x = f64::from(i);
            ConvexBlock::cuboid([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0]).unwrap()
        })
        .collect();
    let system = BlockSystem::new(blocks);
    if !glued {
        return system;
    }
    let mut ids: Vec<u32> = (0..12).collect();
    ids[11] = 10;
    system.with_bodies(ids, tol).unwrap()
}

/// A tracker step that drops the regions of the first pair of bodies copies the later
/// pairs' regions to an earlier place in its output: their piece and point offsets move
/// down. That shift is negative (it overflowed, a panic in debug builds, a tester's finding
/// through `tracking_bodies` and through `ContactTracker::new` on concave blocks); the
/// regions after the step are those of a fresh `detect_bodies`.
#[test]
fn a_tracker_step_that_drops_the_first_pairs_regions_matches_a_fresh_detection() {
    use penedge::block::Pose;
    use penedge::glam::DVec3;
    let tol = Tolerance::default();
    for glued in [false, true] {
        let system = cube_row(glued, &tol);
        let mut tracker = if glued {
            ContactTracker::new(&system, tol, 1.0).unwrap()
        } else {
            ContactTracker::tracking_bodies(&system, tol, 1.0).unwrap()
        };
        let before = tracker.body_contacts().unwrap().contacts.len();
        assert_eq!(before, if glued { 10 } else { 11 });
        // Cube 0 moves 0.1 away from cube 1: only pair (0, 1) is queried, and it loses its
        // region.
        let mut poses = vec![Pose::IDENTITY; 12];
        poses[0].translation = DVec3::new(-0.1, 0.0, 0.0);
        tracker.update(&poses).unwrap();
        let tracked = tracker.body_contacts().unwrap().clone();
        assert_eq!(tracked.contacts.len(), before - 1, "glued {glued}");
        assert!(tracked.contacts.iter().all(|c| c.bodies != [0, 1]));
        let fresh = tracker.system().detect_bodies(&tol);
        assert_eq!(tracked, fresh, "glued {glued}");
    }
}
