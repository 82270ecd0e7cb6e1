//! Shared by the invariance, determinism and reference tests: random jointed systems, rigid
//! motions and scalings of whole systems, and contact lists in a comparable form.
#![allow(dead_code)] // each test file uses part of it

pub mod dev_cases;
pub mod reference;

use penedge::generation::rng::SplitMix64;
use penedge::generation::{
    generate, Deviation, Discontinuity, Domain, JointSet, Orientation, Spec,
};
use penedge::geometry::DVec3;
use penedge::system::SystemContacts;
use penedge::tolerance::ROUNDING_FLOOR;
use penedge::{BlockSystem, ConvexBlock, Tolerance};
use reference::{grazing, touch, touching};

/// A 10 m box cut by two or three joint sets with random orientations, spacings and
/// deviations (a few hundred blocks), seeded. Systems with two random sets get a third,
/// horizontal one (layers).
pub fn jointed(seed: u64) -> BlockSystem {
    let mut r = SplitMix64::new(seed);
    let sets = 2 + r.next_u64() % 2;
    generate(&spec(&mut r, seed, sets))
        .unwrap_or_else(|e| panic!("seed {seed}: {e}"))
        .system
}

fn spec(r: &mut SplitMix64, seed: u64, sets: u64) -> Spec {
    let mut spec = Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap());
    for s in 0..sets {
        let orientation = Orientation::dip(90.0 * r.unit(), 360.0 * r.unit());
        // Two sets: about 10 x 10 x (3 to 5) blocks; three sets: about 7^3.
        let spacing = if sets == 2 { 1.0 } else { 1.4 } + 0.4 * r.unit();
        let mut js = JointSet::new(orientation, spacing);
        js.origin = [10.0 * r.unit(), 10.0 * r.unit(), 10.0 * r.unit()];
        js.deviation = Deviation {
            dip: 4.0 * r.unit(),
            dip_direction: 8.0 * r.unit(),
            spacing: 0.3 * spacing * r.unit(),
        };
        js.seed = seed * 10 + s;
        spec = spec.with(Discontinuity::set(js));
    }
    if sets == 2 {
        let mut layers = JointSet::new(Orientation::dip(0.0, 0.0), 2.5 + r.unit());
        layers.origin = [0.0, 0.0, 10.0 * r.unit()];
        spec = spec.with(Discontinuity::set(layers));
    }
    spec
}

/// A jointed system of two random sets and horizontal layers, each layer then slid by a
/// random horizontal offset (a few decimetres) on the one below: across the layer joints,
/// faces overlap in part, edges in part, and no vertex meets a vertex where it was cut.
pub fn sheared(seed: u64) -> BlockSystem {
    let mut r = SplitMix64::new(seed);
    let sys = generate(&spec(&mut r, seed, 2))
        .unwrap_or_else(|e| panic!("seed {seed}: {e}"))
        .system;
    let layers = sys.sets().len() as u32 - 1;
    let mut cuts: Vec<f64> = sys
        .joints()
        .iter()
        .filter(|j| j.set == layers)
        .map(|j| j.plane.point.z)
        .collect();
    cuts.sort_by(f64::total_cmp);
    let mut offsets = vec![DVec3::ZERO];
    for _ in &cuts {
        let last = *offsets.last().unwrap();
        offsets.push(last + DVec3::new(r.symmetric(0.7), r.symmetric(0.7), 0.0));
    }
    let blocks = sys
        .blocks()
        .iter()
        .map(|b| {
            let layer = cuts.iter().filter(|&&z| z < b.centroid().z).count();
            b.transformed(glam::DQuat::IDENTITY, offsets[layer], 1.0)
        })
        .collect();
    BlockSystem::new(blocks)
}

/// Random touching pairs of all seven types (constructed as in `reference.rs`), in a row ten
/// metres apart: jointed systems have vertex-vertex, edge-edge superposition and face-face
/// contacts only.
pub fn pairs_of_every_type() -> BlockSystem {
    let mut r = SplitMix64::new(17);
    let mut blocks = Vec::new();
    for k in 0..42 {
        let target = k % 7;
        let (a, b) = loop {
            let Some((a, b, _)) = touching(&mut r, target) else {
                continue;
            };
            // Clear cases only: no distance near the reference's thresholds, no grazing edge.
            match touch(&a, &b) {
                Ok(t) if !grazing(&a, &b, &t, 1e-2) => break (a, b),
                _ => continue,
            }
        };
        let shift = DVec3::X * 10.0 * k as f64;
        for p in [a, b] {
            blocks.push(p.block().transformed(glam::DQuat::IDENTITY, shift, 1.0));
        }
    }
    BlockSystem::new(blocks)
}

/// A random rotation (uniform enough: a normalised random quaternion).
pub fn rotation(r: &mut SplitMix64) -> glam::DQuat {
    loop {
        let q = glam::DQuat::from_xyzw(
            r.symmetric(1.0),
            r.symmetric(1.0),
            r.symmetric(1.0),
            r.symmetric(1.0),
        );
        if q.length() > 0.2 {
            return q.normalize();
        }
    }
}

/// The system with every block rotated about the origin, scaled and translated
/// ([`ConvexBlock::transformed`]: ids, topology and feature numbering kept).
pub fn transformed(sys: &BlockSystem, q: glam::DQuat, t: DVec3, s: f64) -> BlockSystem {
    BlockSystem::new(
        sys.blocks()
            .iter()
            .map(|b| b.transformed(q, t, s))
            .collect(),
    )
}

/// The system with every block rebuilt from its transformed vertices (planes fitted again),
/// as blocks read from a project in those coordinates would be.
pub fn rebuilt(sys: &BlockSystem, f: impl Fn(DVec3) -> DVec3) -> BlockSystem {
    BlockSystem::new(sys.blocks().iter().map(|b| rebuilt_block(b, &f)).collect())
}

/// One block rebuilt from its vertices mapped by `f`.
pub fn rebuilt_block(b: &ConvexBlock, f: impl Fn(DVec3) -> DVec3) -> ConvexBlock {
    let v: Vec<[f64; 3]> = b.vertices().iter().map(|&p| f(p).to_array()).collect();
    let faces: Vec<Vec<usize>> = b
        .faces()
        .map(|f| f.iter().map(|&i| i as usize).collect())
        .collect();
    ConvexBlock::new(&v, &faces).unwrap()
}

/// `(pair, type code, feature of the smaller id, feature of the larger)` per contact, and the
/// penetrating pairs: the whole answer as plain data, for comparisons and messages.
pub type Answer = (Vec<([u32; 2], u8, String)>, Vec<[u32; 2]>);

pub fn answer(found: &SystemContacts) -> Answer {
    let contacts = found
        .contacts
        .iter()
        .map(|c| {
            let features = format!("{:?} {:?}", c.contact.feature_a, c.contact.feature_b);
            (c.pair, c.contact.kind.code(), features)
        })
        .collect();
    (contacts, found.penetrating.clone())
}

/// The differences between two answers, for a readable failure message (at most 10 lines).
pub fn differences(expected: &Answer, got: &Answer) -> String {
    let mut out = Vec::new();
    for c in &expected.0 {
        if !got.0.contains(c) {
            out.push(format!("lost {c:?}"));
        }
    }
    for c in &got.0 {
        if !expected.0.contains(c) {
            out.push(format!("new {c:?}"));
        }
    }
    if expected.1 != got.1 {
        out.push(format!("penetrating {:?} -> {:?}", expected.1, got.1));
    }
    let n = out.len();
    out.truncate(10);
    format!("{n} differences: {}", out.join("; "))
}

/// The sine below which an edge lies in a face or along an edge, as docs/tolerance.md
/// ("Lies in") states it: the pair's absolute length threshold over its scale, computed here
/// from the blocks' bounding boxes.
pub fn lies_in_sine(tol: &Tolerance, a: &ConvexBlock, b: &ConvexBlock) -> f64 {
    let scale = a.aabb().diagonal().min(b.aabb().diagonal());
    let magnitude = a.aabb().magnitude().max(b.aabb().magnitude());
    let gap = (tol.gap() * scale).max(ROUNDING_FLOOR * magnitude);
    let length = (tol.length() * scale).max(10.0 * gap);
    length / scale
}

/// The area of face `f` of `block`, from its corners (half the length of their Newell sum),
/// independent of the crate's geometry code.
pub fn face_area(block: &ConvexBlock, f: usize) -> f64 {
    let v: Vec<DVec3> = block
        .face(f)
        .iter()
        .map(|&i| block.vertices()[i as usize])
        .collect();
    let mut twice = DVec3::ZERO;
    for k in 0..v.len() {
        twice += v[k].cross(v[(k + 1) % v.len()]);
    }
    twice.length() / 2.0
}

/// A plain 64-bit LCG's uniform numbers in [0, 1), from `seed` (the mechanics tests' jitter:
/// a fixed stream, so that a case stays the case it was written for).
pub fn lcg(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A simulation of unit cubes (density 2500) on a `w` × `w` × `h` grid 1.002 apart: the floor
/// layer and the side walls fixed, the cubes inside placed with `jitter()` (a turn and a
/// shift, drawn in grid order).
pub fn cubes_in_a_box(
    w: usize,
    h: usize,
    jitter: impl FnMut() -> (glam::DQuat, DVec3),
) -> penedge::mechanics::Simulation {
    cubes_in_a_box_at(w, h, 1.002, jitter)
}

/// [`cubes_in_a_box`] with the cubes `spacing` apart (1: every joint closed). Cube
/// `i + w (j + w k)` is at grid point `(i, j, k)`, its lowest corner at `(i, j, k) × spacing`
/// before its jitter.
pub fn cubes_in_a_box_at(
    w: usize,
    h: usize,
    spacing: f64,
    jitter: impl FnMut() -> (glam::DQuat, DVec3),
) -> penedge::mechanics::Simulation {
    grid_of_cubes(w, h, spacing, jitter, |_, block| block)
}

/// The grid of [`cubes_in_a_box_at`], each cube passed through `tag` with its grid point
/// `(i, j, k)` before it is placed in the system.
fn grid_of_cubes(
    w: usize,
    h: usize,
    spacing: f64,
    mut jitter: impl FnMut() -> (glam::DQuat, DVec3),
    tag: impl Fn([usize; 3], ConvexBlock) -> ConvexBlock,
) -> penedge::mechanics::Simulation {
    let unit = ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).unwrap();
    let (mut blocks, mut fixed) = (Vec::new(), Vec::new());
    for k in 0..h {
        for j in 0..w {
            for i in 0..w {
                let wall = k == 0 || i == 0 || j == 0 || i == w - 1 || j == w - 1;
                let centre = DVec3::new(i as f64, j as f64, k as f64) * spacing + 0.5;
                let (turn, shift) = if wall {
                    (glam::DQuat::IDENTITY, DVec3::ZERO)
                } else {
                    jitter()
                };
                let block = unit.transformed(turn, centre + shift, 1.0);
                blocks.push(tag([i, j, k], block));
                fixed.push(wall);
            }
        }
    }
    let mut sim = penedge::mechanics::Simulation::new(&BlockSystem::new(blocks), 2500.0).unwrap();
    for i in (0..fixed.len()).filter(|&i| fixed[i]) {
        sim.fix(i).unwrap();
    }
    sim
}

/// The box from `lo` to `hi` with its faces in the plane x = 0 of joint 0 (set 0), those in
/// z = 0 of joint 1 (set 1), the others of the domain's boundary: blocks around the line
/// where two joints cross.
pub fn jointed_box(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
    use penedge::block::FaceOrigin;
    let cube = ConvexBlock::cuboid(lo, hi).unwrap();
    let origins = (0..cube.n_faces())
        .map(|i| {
            let p = cube.planes()[i];
            let on =
                |axis: DVec3| p.normal.dot(axis).abs() > 0.5 && p.point.dot(axis).abs() < 1e-12;
            if on(DVec3::X) {
                FaceOrigin::Joint { set: 0, joint: 0 }
            } else if on(DVec3::Z) {
                FaceOrigin::Joint { set: 1, joint: 1 }
            } else {
                FaceOrigin::Boundary {
                    part: 0,
                    face: i as u32,
                }
            }
        })
        .collect();
    cube.with_face_origins(origins).unwrap()
}

/// [`cubes_in_a_box_at`] at a spacing of 1 (every joint closed, no jitter), each face with
/// the origin a generation from three joint sets of spacing 1 gives it: set `a` for the
/// planes normal to axis `a`, one joint per plane (numbered across the sets), the box's
/// outer faces its boundary. The cubes' edges and corners then meet where joints cross.
pub fn jointed_cubes_in_a_box(w: usize, h: usize) -> penedge::mechanics::Simulation {
    let still = || (glam::DQuat::IDENTITY, DVec3::ZERO);
    grid_of_cubes(w, h, 1.0, still, |lo, block| {
        let origins = grid_origins(&block, lo, [w, w, h]);
        block.with_face_origins(origins).unwrap()
    })
}

/// The face origins of the unit cube at grid point `lo` of a box of `size` cubes: set `a`
/// for the planes normal to axis `a`, one joint per inner plane (numbered across the sets),
/// the box's outer faces its boundary (as `penedge-bench mechanics --joints jointed`).
fn grid_origins(
    block: &ConvexBlock,
    lo: [usize; 3],
    size: [usize; 3],
) -> Vec<penedge::block::FaceOrigin> {
    use penedge::block::FaceOrigin;
    block
        .planes()
        .iter()
        .map(|p| {
            let axis = (0..3).find(|&a| p.normal[a].abs() == 1.0).unwrap();
            let upper = p.normal[axis] > 0.0;
            let at = lo[axis] + usize::from(upper);
            if at == 0 || at == size[axis] {
                FaceOrigin::Boundary {
                    part: 0,
                    face: (2 * axis + usize::from(upper)) as u32,
                }
            } else {
                let before: usize = size[..axis].iter().map(|s| s - 1).sum();
                FaceOrigin::Joint {
                    set: axis as u32,
                    joint: (before + at - 1) as u32,
                }
            }
        })
        .collect()
}

/// Every face of `block` tagged with the joint set `set(normal)` of its outward normal.
pub fn with_sets(block: ConvexBlock, set: impl Fn(DVec3) -> u32) -> ConvexBlock {
    let origins = block
        .planes()
        .iter()
        .map(|p| penedge::block::FaceOrigin::Joint {
            set: set(p.normal),
            joint: 0,
        })
        .collect();
    block.with_face_origins(origins).unwrap()
}

/// Hoek and Bray's tension crack on a bench: a base block (set 0) whose top is a plane
/// inclined at `theta`, a block behind the crack (set 1) and a 1 × 0.8 × 0.3 m slab on the
/// plane in front of it, whose back face, 0.8 × 0.3 m, is in the crack (set 1; its other
/// faces set 0). In the plane's frame (returned: the plane is z = 0, downhill +x, the crack
/// x = 0), turned and moved off the world's axes.
pub fn tension_crack(theta: f64) -> (BlockSystem, glam::DQuat) {
    let frame = glam::DQuat::from_rotation_z(0.6) * glam::DQuat::from_rotation_y(theta);
    let offset = DVec3::new(100.0, -50.0, 20.0);
    let place = |b: ConvexBlock| b.transformed(frame, offset, 1.0);
    let uphill = frame * -DVec3::X;
    let base = ConvexBlock::cuboid([-5.0, -5.0, -1.0], [5.0, 5.0, 0.0]).unwrap();
    let back = ConvexBlock::cuboid([-1.0, -0.4, 0.0], [0.0, 0.4, 0.5]).unwrap();
    let slab = ConvexBlock::cuboid([0.0, -0.4, 0.0], [1.0, 0.4, 0.3]).unwrap();
    let system = BlockSystem::new(vec![
        with_sets(place(base), |_| 0),
        with_sets(place(back), |_| 1),
        with_sets(place(slab), |n| u32::from(n.dot(uphill) > 0.99)),
    ]);
    (system, frame)
}
