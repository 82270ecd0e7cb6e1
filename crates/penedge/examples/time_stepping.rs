//! The contact detection of a DEM code's time loop: `system::ContactTracker`.
//!
//! Run: `cargo run --release -p penedge --example time_stepping`
//!
//! The DEM code owns the motion; penedge answers "which blocks touch, and how" at each step.
//! The tracker is made once from the blocks in their reference placement; each step the code
//! gives one `block::Pose` per block and calls `update`, and reads `contacts()`.
//!
//! **Tracker poses** are rigid motions of the reference blocks, in world coordinates: the
//! point `x` of a reference block is at `rotation * x + translation` (a rotation about the
//! world origin, then a translation), and every pose starts at `Pose::IDENTITY`. To turn a
//! block about its own centroid `c` and move it by `d`, give `rotation = q` and
//! `translation = c + d - q * c`. (The mechanics' `Simulation` uses the other convention of
//! `Pose`: a body frame at the centroid; see the example `rigid_blocks` and docs/bodies.md.)
//!
//! Each step's contacts are exactly those of a full detection of the moved blocks
//! (`BlockSystem::detect`); this example computes both at every step and checks they are
//! equal. The tracker is faster because it skips the pairs whose blocks did not move and the
//! pairs whose earlier answer is certified by how little their blocks travelled
//! (docs/systems.md, "Time stepping").
use penedge::block::Pose;
use penedge::glam::{DQuat, DVec3};
use penedge::system::{count_types, ContactTracker, SystemContacts};
use penedge::{BlockSystem, ConvexBlock, Detector, PairResult, Tolerance};
use std::time::Instant;

fn main() {
    // A 5 m x 5 m x 3 m box cut into 1 m cubes, and an oblique plane x + y + z = 6.5 through
    // them: 99 blocks.
    let domain = ConvexBlock::cuboid([0.0; 3], [5.0, 5.0, 3.0]).expect("a valid box");
    let mut normals = Vec::new();
    let mut offsets = Vec::new();
    for k in 1..5 {
        normals.extend([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        offsets.extend([k as f64; 2]);
    }
    for k in 1..3 {
        normals.push([0.0, 0.0, 1.0]);
        offsets.push(k as f64);
    }
    normals.push([1.0, 1.0, 1.0]);
    offsets.push(6.5);
    let tol = Tolerance::with_gap(1e-4).expect("a valid gap"); // 0.17 mm for a 1 m cube
    let system =
        BlockSystem::from_domain_cut(domain, &normals, &offsets, &tol).expect("the cut works");
    let reference: Vec<ConvexBlock> = system.blocks().to_vec();
    let n = reference.len();

    // The tracker: `skin` (a length) widens the broad phase's boxes so that it need not run
    // again until a block has moved half of it.
    let skin = 0.05;
    let mut tracker = ContactTracker::new(&system, tol, skin).expect("a valid tracker");
    let start = tracker.contacts().clone();
    println!(
        "{n} blocks; at the reference poses {} contacts, types {:?}",
        start.contacts.len(),
        count_types(&start.contacts)
    );

    // What moves: the blocks of the top layer (centroid above z = 2) rise and turn about their
    // own vertical axes, a little more each step; one block of the middle layer is pushed
    // into its neighbours in +x and +y. The rest stay where they are.
    let top: Vec<usize> = (0..n)
        .filter(|&i| reference[i].centroid().z > 2.0)
        .collect();
    let pushed = (0..n)
        .find(|&i| (reference[i].centroid() - DVec3::new(1.5, 1.5, 1.5)).length() < 0.2)
        .expect("the cube at (1.5, 1.5, 1.5)");
    let mut poses = vec![Pose::IDENTITY; n];
    let steps = 40;
    let (mut tracker_time, mut full_time) = (0.0, 0.0);
    let (mut queried, mut skipped) = (0, 0);
    for step in 1..=steps {
        let s = step as f64;
        // The DEM code's integration would give these poses; here they are prescribed.
        for &i in &top {
            let lift = DVec3::new(0.0, 0.0, 1e-5 * s); // 10 um more each step
            poses[i] = about_centroid(&reference[i], DQuat::from_rotation_z(2e-6 * s), lift);
        }
        poses[pushed] = about_centroid(
            &reference[pushed],
            DQuat::IDENTITY,
            DVec3::new(1e-5 * s, 5e-6 * s, 0.0),
        );

        // The tracker's step.
        let clock = Instant::now();
        let report = tracker.update(&poses).expect("valid poses");
        tracker_time += clock.elapsed().as_secs_f64();
        queried += report.queried;
        skipped += report.certified + report.unmoved;

        // A full detection of the blocks moved independently of the tracker.
        let clock = Instant::now();
        let moved: Vec<ConvexBlock> = reference
            .iter()
            .zip(&poses)
            .map(|(block, pose)| block.transformed(pose.rotation, pose.translation, 1.0))
            .collect();
        let full = BlockSystem::new(moved).detect(&tol);
        full_time += clock.elapsed().as_secs_f64();

        let contacts: &SystemContacts = tracker.contacts();
        assert_eq!(
            contacts, &full,
            "step {step}: the tracker differs from a full detection"
        );
        if step % 10 == 0 || step == 1 {
            println!(
                "step {step:2}: {:3} contacts, {} penetrating; {:3} of {} candidate pairs \
                 queried, {} certified, {} unmoved, broad phase rebuilt: {}",
                contacts.contacts.len(),
                contacts.penetrating.len(),
                report.queried,
                report.candidate_pairs,
                report.certified,
                report.unmoved,
                report.rebuilt
            );
        }
    }
    let end = tracker.contacts().clone();
    println!(
        "after {steps} steps: {} contacts (types {:?}), penetrating pairs {:?}",
        end.contacts.len(),
        count_types(&end.contacts),
        end.penetrating
    );
    println!(
        "tracker {:.2} ms, full detections {:.2} ms in all; {queried} pair queries, {skipped} \
         answers without a query",
        tracker_time * 1e3,
        full_time * 1e3
    );
    // The top layer has risen by 0.4 mm, beyond the gap: it no longer touches the layer
    // below; the pushed cube went 0.4 mm and 0.2 mm into its neighbours, deeper than the gap.
    assert!(end.contacts.len() < start.contacts.len());
    assert!(start.penetrating.is_empty() && !end.penetrating.is_empty());
    // Most pairs were answered without a query.
    assert!(skipped > queried);

    // --- The geometry of the tracked contacts ---------------------------------------------
    // `contacts()` holds types and features. For normals, distances, areas and points, ask a
    // Detector about each contact's pair, with the blocks at their current poses:
    // `tracker.system()` places them (it borrows the tracker mutably: the contacts were
    // cloned into `end` above). `ContactTracker::tracking_bodies` keeps such geometry per pair
    // of bodies.
    let placed = tracker.system();
    let mut detector = Detector::new(tol);
    let mut apart = 0;
    for c in &end.contacts {
        let a = &placed.blocks()[c.pair[0] as usize];
        let b = &placed.blocks()[c.pair[1] as usize];
        let (result, geometry) = detector.detect_with_geometry(a, b);
        assert_eq!(result, PairResult::Contact(c.contact));
        let g = geometry.expect("a contact has a geometry");
        // Blocks apart by less than the gap touch, with a positive distance (here blocks of
        // the top layer that turned about different centroids).
        if g.distance() > 1e-9 {
            apart += 1;
        }
    }
    println!("{apart} of the final contacts are apart within the gap (distance > 1e-9 m)");
    println!("\nall checks passed");
}

/// The tracker pose that turns `block` by `rotation` about its centroid and then moves it by
/// `shift`.
fn about_centroid(block: &ConvexBlock, rotation: DQuat, shift: DVec3) -> Pose {
    let c = block.centroid();
    Pose::new(rotation, c + shift - rotation * c).expect("a finite pose")
}
