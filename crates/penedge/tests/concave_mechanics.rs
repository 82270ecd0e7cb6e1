//! Concave blocks in the mechanics (issue 20): a block made of glued convex parts
//! (`BlockSystem::with_bodies`) is one rigid body. The references are formulas computed here:
//! the mass, centroid and inertia of an L-shaped block from its two boxes (parallel axes), a
//! free-fall parabola, and the statics of a block at rest (reaction = weight, through the
//! centroid).

use penedge::glam::{DMat3, DVec3};
use penedge::mechanics::{Damping, JointModel, Simulation};
use penedge::{BlockSystem, ConvexBlock, Tolerance};

const G: f64 = 9.81;
const DENSITY: f64 = 2500.0;

fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
    ConvexBlock::cuboid(lo, hi).unwrap()
}

/// The L-block: a 2 x 1 x 1 slab with a 1 x 1 x 1 cube on its left half, cut into convex
/// parts in one of three ways.
fn l_block(cut: usize) -> Vec<ConvexBlock> {
    match cut {
        // The slab and the cube.
        0 => vec![
            cuboid([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
            cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
        ],
        // A column and the right cube.
        1 => vec![
            cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 2.0]),
            cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
        ],
        // Three cubes.
        _ => vec![
            cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
            cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        ],
    }
}

/// Mass, centroid and inertia tensor (about the centroid) of the L-block, from its two
/// boxes: each box's `m (b² + c²) / 12` moments, moved to the common centroid by the
/// parallel-axis theorem.
fn l_reference() -> (f64, DVec3, DMat3) {
    let boxes = [
        (DVec3::new(2.0, 1.0, 1.0), DVec3::new(1.0, 0.5, 0.5)),
        (DVec3::new(1.0, 1.0, 1.0), DVec3::new(0.5, 0.5, 1.5)),
    ];
    let mass: f64 = boxes.iter().map(|(s, _)| DENSITY * s.x * s.y * s.z).sum();
    let centroid = boxes
        .iter()
        .map(|(s, c)| *c * (DENSITY * s.x * s.y * s.z))
        .sum::<DVec3>()
        / mass;
    let mut inertia = DMat3::ZERO;
    for (s, c) in boxes {
        let m = DENSITY * s.x * s.y * s.z;
        let own = DMat3::from_diagonal(
            DVec3::new(
                s.y * s.y + s.z * s.z,
                s.x * s.x + s.z * s.z,
                s.x * s.x + s.y * s.y,
            ) * m
                / 12.0,
        );
        let d = c - centroid;
        let shift = DMat3::from_diagonal(DVec3::splat(d.length_squared()))
            - DMat3::from_cols(d * d.x, d * d.y, d * d.z);
        inertia += own + shift * m;
    }
    (mass, centroid, inertia)
}

/// A system of `blocks` whose first `parts` blocks are one body (the rest each its own).
fn glued(blocks: Vec<ConvexBlock>, first: usize, parts: usize) -> BlockSystem {
    let ids: Vec<u32> = (0..blocks.len())
        .map(|k| {
            if (first..first + parts).contains(&k) {
                first as u32
            } else {
                k as u32
            }
        })
        .collect();
    BlockSystem::new(blocks)
        .with_bodies(ids, &Tolerance::default())
        .unwrap()
}

fn joint(kn: f64) -> JointModel {
    JointModel {
        kn,
        ks: kn,
        friction: 30.0,
        cohesion: 0.0,
        tension: 0.0,
        ..JointModel::default()
    }
}

/// The principal moments' invariants (trace, sum of the 2 x 2 principal minors,
/// determinant) against those of the reference tensor.
fn same_inertia(principal: DVec3, reference: DMat3) {
    let [a, b, c] = principal.to_array();
    let r = reference;
    let minors = r.x_axis.x * r.y_axis.y + r.y_axis.y * r.z_axis.z + r.x_axis.x * r.z_axis.z
        - r.y_axis.x * r.x_axis.y
        - r.z_axis.y * r.y_axis.z
        - r.z_axis.x * r.x_axis.z;
    let scale = r.x_axis.x + r.y_axis.y + r.z_axis.z;
    let checks = [
        (a + b + c, scale, scale),
        (a * b + b * c + a * c, minors, scale * scale),
        (a * b * c, r.determinant(), scale * scale * scale),
    ];
    for (got, expected, size) in checks {
        assert!(
            (got - expected).abs() < 1e-12 * size,
            "{principal} vs {reference}: {got} vs {expected}"
        );
    }
}

/// The L-block is one body whatever its cut: the mass, centroid and inertia of the union.
#[test]
fn a_concave_block_is_one_body_with_the_mass_properties_of_the_union() {
    let (mass, centroid, inertia) = l_reference();
    for cut in 0..3 {
        let parts = l_block(cut);
        let n = parts.len();
        let sim = Simulation::new(&glued(parts, 0, n), DENSITY).unwrap();
        let bodies = sim.bodies();
        assert_eq!(bodies.len(), 1, "cut {cut}");
        assert_eq!(bodies.shape(0).parts().len(), n);
        assert!(
            (bodies.masses()[0] - mass).abs() < 1e-12 * mass,
            "cut {cut}"
        );
        let c = bodies.poses()[0].translation;
        assert!(
            (c - centroid).length() < 1e-12,
            "cut {cut}: {c} vs {centroid}"
        );
        same_inertia(bodies.principal_inertia()[0], inertia);
    }
    // Not the mean of the parts' centroids (0.75 for the first cut): the union's, 5/6.
    assert!((centroid.x - 5.0 / 6.0).abs() < 1e-15);
}

/// A material point of the body at `pose` that was at `x` at `start`.
fn carried(start: penedge::block::Pose, pose: penedge::block::Pose, x: DVec3) -> DVec3 {
    let local = start.rotation.inverse() * (x - start.translation);
    pose.rotation * local + pose.translation
}

/// Thrown with a velocity and a spin-free start, the L-block's centroid follows the
/// parabola `c + v t + g t² / 2` and the block does not turn; cut in three ways, its
/// corners move the same.
#[test]
fn an_l_block_falls_as_one_body_along_a_parabola_however_it_is_cut() {
    let (_, centroid, _) = l_reference();
    let v0 = DVec3::new(1.0, -0.5, 3.0);
    let corners = [
        DVec3::ZERO,
        DVec3::new(2.0, 1.0, 1.0),
        DVec3::new(0.0, 1.0, 2.0),
        DVec3::new(1.0, 0.0, 2.0),
    ];
    let mut paths: Vec<Vec<DVec3>> = Vec::new();
    for cut in 0..3 {
        let parts = l_block(cut);
        let n = parts.len();
        let mut sim = Simulation::new(&glued(parts, 0, n), DENSITY).unwrap();
        // A soft joint: no contact here, and the critical step allows 1 ms.
        sim.set_default_joint(joint(1.0)).unwrap();
        sim.set_timestep(Some(1e-3)).unwrap();
        sim.set_velocity(0, v0, DVec3::ZERO).unwrap();
        let start = sim.bodies().poses()[0];
        let g = sim.gravity();
        assert_eq!(g, DVec3::new(0.0, 0.0, -G));
        let mut path = Vec::new();
        for _ in 0..500 {
            sim.step().unwrap();
            let t = sim.time();
            let pose = sim.bodies().poses()[0];
            let expected = centroid + v0 * t + 0.5 * g * t * t;
            assert!(
                (pose.translation - expected).length() < 1e-12,
                "cut {cut}, t = {t}: {} vs {expected}",
                pose.translation
            );
            assert!(pose.rotation.angle_between(start.rotation) < 1e-12);
            path.extend(corners.map(|x| carried(start, pose, x)));
        }
        assert!(
            sim.contacts().list.is_empty(),
            "no contact between its parts"
        );
        paths.push(path);
    }
    for other in &paths[1..] {
        let off = paths[0].iter().zip(other).map(|(p, q)| p.distance(*q));
        assert!(off.fold(0.0, f64::max) < 1e-12);
    }
}

/// On a fixed base, the L-block comes to rest: the base pushes it up with its weight, and
/// the centre of pressure of the sub-contact forces (computed from their points) lies under
/// the union's centroid (5/6, 1/2), not under the middle of its footprint (1, 1/2) nor the
/// mean of the parts' centroids; the same for every cut (the cut under the footprint makes
/// two part contacts with the base). No contact joins two parts of the L-block.
#[test]
fn an_l_block_rests_on_a_base_with_its_weight_through_its_centroid_however_it_is_cut() {
    let (mass, centroid, _) = l_reference();
    let kn = 1e10;
    for cut in 0..3 {
        let mut blocks = vec![cuboid([-2.0, -2.0, -1.0], [4.0, 3.0, 0.0])];
        let parts = l_block(cut);
        let n = parts.len();
        blocks.extend(parts);
        let system = glued(blocks, 1, n);
        let mut sim = Simulation::new(&system, DENSITY).unwrap();
        assert_eq!(sim.bodies().len(), 2);
        sim.fix(0).unwrap();
        sim.set_default_joint(joint(kn)).unwrap();
        sim.set_damping(Damping {
            local: 0.8,
            viscous: 0.0,
        })
        .unwrap();
        let report = sim.solve(1e-7, 200_000).unwrap();
        assert!(report.converged, "cut {cut}: {report:?}");
        let contacts = sim.contacts();
        let (mut force, mut moment_x, mut moment_y, mut pieces) = (DVec3::ZERO, 0.0, 0.0, 0);
        for (i, c) in contacts.list.iter().enumerate() {
            assert_ne!(
                c.bodies[0], c.bodies[1],
                "cut {cut}: a contact within a body"
            );
            let sign = if c.bodies[1] == 1 { 1.0 } else { -1.0 };
            pieces += 1;
            for s in contacts.subs_of(i) {
                let f = s.force(c.normal) * sign;
                force += f;
                moment_x += s.point.x * f.z;
                moment_y += s.point.y * f.z;
            }
        }
        let weight = mass * G;
        assert!(
            (force - DVec3::new(0.0, 0.0, weight)).length() < 1e-5 * weight,
            "cut {cut}: {force} vs {weight}"
        );
        let pressure = [moment_x / force.z, moment_y / force.z];
        assert!(
            (pressure[0] - centroid.x).abs() < 1e-4 && (pressure[1] - centroid.y).abs() < 1e-4,
            "cut {cut}: centre of pressure {pressure:?} vs centroid {centroid}"
        );
        // The footprint is one part's bottom or two parts' bottoms.
        assert_eq!(pieces, if cut == 0 { 1 } else { 2 }, "cut {cut}");
        let settled = sim.bodies().poses()[1].translation;
        assert!((settled - centroid).length() < 1e-4, "cut {cut}: {settled}");
    }
}

/// The map from blocks to bodies: bodies in the order of their first block, whatever the
/// body ids; the parts, listed body by body, are the system's blocks (each part where its
/// block is).
#[test]
fn each_block_maps_to_its_body_and_the_parts_are_the_blocks() {
    let blocks = vec![
        cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        cuboid([3.0, 0.0, 0.0], [4.0, 1.0, 1.0]),
        cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
    ];
    // blocks 0 and 2 are one bar (body id 5), block 1 alone (body id 1)
    let system = BlockSystem::new(blocks.clone())
        .with_bodies(vec![5, 1, 5], &Tolerance::default())
        .unwrap();
    let sim = Simulation::new(&system, DENSITY).unwrap();
    assert_eq!(sim.block_bodies(), &[0, 1, 0]);
    assert_eq!(sim.body_of_block(2), Some(0));
    assert_eq!(sim.body_of_block(3), None);
    assert_eq!(sim.bodies().len(), 2);
    assert_eq!(sim.part_bodies(), &[0, 0, 1]);
    // body 0 the bar of blocks 0 and 2 (two cubes), body 1 is block 1 (mass of one cube)
    let masses = sim.bodies().masses();
    assert!((masses[0] - 2.0 * DENSITY).abs() < 1e-9 && (masses[1] - DENSITY).abs() < 1e-9);
    let placed = sim.placed_system();
    for (part, block) in [(0, 0), (1, 2), (2, 1)] {
        let centroid = placed.blocks()[part].centroid();
        assert!((centroid - blocks[block].centroid()).length() < 1e-12);
    }
    // convex blocks: block i is body i
    let convex = BlockSystem::new(blocks);
    let sim = Simulation::new(&convex, DENSITY).unwrap();
    assert_eq!(sim.block_bodies(), &[0, 1, 2]);
}
