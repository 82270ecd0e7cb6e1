//! Sets of generated pairs, as penedge blocks and as parry shapes with poses.

use crate::family::Family;
use crate::placement::{place, Expected, Placement, Push, Touch};
use crate::rng::SplitMix64;
use parry3d_f64::math::{Pose, Rot3, Vector};
use parry3d_f64::query::Contact;
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid};
use penedge::{ConvexBlock, Detector, Tolerance};

/// What a set of pairs holds: how B is pushed and which touching configurations it starts
/// from (drawn uniformly).
#[derive(Clone, Copy, Debug)]
pub struct Scenario {
    /// Row name.
    pub name: &'static str,
    /// Push from the touching configuration.
    pub push: Push,
    /// Touching configurations to draw from.
    pub touches: &'static [Touch],
}

/// A pair as parry sees it: each block's shape in its body frame and its pose.
pub struct ParryPair {
    /// Shape of A.
    pub a: ConvexPolyhedron,
    /// Shape of B.
    pub b: ConvexPolyhedron,
    /// Pose of A.
    pub pose_a: Pose,
    /// Pose of B.
    pub pose_b: Pose,
    /// Prediction distance: penedge's absolute gap for this pair.
    pub prediction: f64,
}

/// Generated pairs of one scenario and family, with their expected outcomes.
pub struct PairSet {
    /// The scenario.
    pub scenario: Scenario,
    /// The family.
    pub family: Family,
    /// Expected outcome of each pair.
    pub expected: Vec<Expected>,
    /// The pairs as penedge blocks, in world coordinates.
    pub blocks: Vec<(ConvexBlock, ConvexBlock)>,
    /// The same pairs for parry.
    pub parry: Vec<ParryPair>,
    /// The tolerance penedge uses on these pairs (`scenario.push.tolerance()`).
    pub tolerance: Tolerance,
    /// The reference blocks of each pair in their body frames (the parry shapes' vertices
    /// and faces), kept only when asked for (to export the pairs).
    pub refs: Vec<(ConvexBlock, ConvexBlock)>,
}

impl PairSet {
    /// `n` pairs of `family` in `scenario`, reproducible from `rng`'s state.
    pub fn generate(scenario: Scenario, family: Family, n: usize, rng: &mut SplitMix64) -> Self {
        Self::generate_keeping(scenario, family, n, rng, false)
    }

    /// [`PairSet::generate`], also keeping the reference blocks when `keep_refs`.
    pub fn generate_keeping(
        scenario: Scenario,
        family: Family,
        n: usize,
        rng: &mut SplitMix64,
        keep_refs: bool,
    ) -> Self {
        let tolerance = scenario.push.tolerance();
        let detector = Detector::new(tolerance);
        let mut set = PairSet {
            scenario,
            family,
            expected: Vec::with_capacity(n),
            blocks: Vec::with_capacity(n),
            parry: Vec::with_capacity(n),
            tolerance,
            refs: Vec::new(),
        };
        for i in 0..n {
            let (ref_a, ref_b) = (family.block(rng), family.block(rng));
            let touch = scenario.touches[i % scenario.touches.len()];
            let p = place(&ref_a, &ref_b, touch, scenario.push, rng);
            let a = ref_a.transformed(p.rot_a, p.pos_a, 1.0);
            let b = ref_b.transformed(p.rot_b, p.pos_b, 1.0);
            let prediction = detector.thresholds(&a, &b).gap;
            set.parry.push(parry_pair(&ref_a, &ref_b, &p, prediction));
            set.expected.push(p.expected);
            set.blocks.push((a, b));
            if keep_refs {
                set.refs.push((ref_a, ref_b));
            }
        }
        set
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }
}

fn parry_pair(
    ref_a: &ConvexBlock,
    ref_b: &ConvexBlock,
    p: &Placement,
    prediction: f64,
) -> ParryPair {
    ParryPair {
        a: polyhedron(ref_a),
        b: polyhedron(ref_b),
        pose_a: pose(p.rot_a, p.pos_a),
        pose_b: pose(p.rot_b, p.pos_b),
        prediction,
    }
}

/// The parry shape with the block's vertices and faces (fan-triangulated; parry merges the
/// coplanar triangles back into faces).
pub fn polyhedron(block: &ConvexBlock) -> ConvexPolyhedron {
    let points = block.vertices().iter().map(|v| vector(*v)).collect();
    let triangles: Vec<[u32; 3]> = block
        .faces()
        .flat_map(|face| (1..face.len() - 1).map(move |k| [face[0], face[k], face[k + 1]]))
        .collect();
    ConvexPolyhedron::from_convex_mesh(points, &triangles)
        .expect("a valid block is a valid polyhedron")
}

/// The unit cube as a parry `Cuboid` (its specialised cuboid-cuboid contact).
pub fn unit_cuboid() -> Cuboid {
    Cuboid::new(Vector::splat(0.5))
}

fn vector(v: glam::DVec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn pose(rotation: glam::DQuat, translation: glam::DVec3) -> Pose {
    let r = Rot3::from_xyzw(rotation.x, rotation.y, rotation.z, rotation.w);
    Pose::from_parts(vector(translation), r)
}

/// Counts of pairs whose outcome is the expected one, for penedge and for parry's `contact`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Agreement {
    /// penedge `Detector::detect` gives the expected outcome (and contact type).
    pub penedge: usize,
    /// parry `contact` gives the expected outcome: `None` when separated, `|dist| <=
    /// PARRY_TOUCH` when touching, `dist < -PARRY_TOUCH` when penetrating.
    pub parry: usize,
}

/// Distance within which parry's answer counts as touching.
pub const PARRY_TOUCH: f64 = 1e-9;

impl PairSet {
    /// Runs both engines once on every pair and counts the expected outcomes.
    pub fn verify(&self) -> Agreement {
        let mut detector = Detector::new(self.tolerance);
        let mut agree = Agreement::default();
        for ((expected, (a, b)), p) in self.expected.iter().zip(&self.blocks).zip(&self.parry) {
            agree.penedge += expected.matches(&detector.detect(a, b)) as usize;
            agree.parry += parry_matches(*expected, parry_contact(p)) as usize;
        }
        agree
    }

    /// The pairs (index, expected, penedge's answer) where penedge disagrees.
    pub fn penedge_misses(&self) -> Vec<(usize, Expected, penedge::PairResult)> {
        let mut detector = Detector::new(self.tolerance);
        (0..self.len())
            .filter_map(|i| {
                let (a, b) = &self.blocks[i];
                let r = detector.detect(a, b);
                (!self.expected[i].matches(&r)).then_some((i, self.expected[i], r))
            })
            .collect()
    }
}

/// parry's `contact` on one pair.
pub fn parry_contact(p: &ParryPair) -> Option<Contact> {
    parry3d_f64::query::contact(&p.pose_a, &p.a, &p.pose_b, &p.b, p.prediction)
        .expect("parry supports polyhedron pairs")
}

fn parry_matches(expected: Expected, contact: Option<Contact>) -> bool {
    match (expected, contact) {
        (Expected::Separated, None) => true,
        (Expected::Contact(_), Some(c)) => c.dist.abs() <= PARRY_TOUCH,
        (Expected::Penetrating, Some(c)) => c.dist < -PARRY_TOUCH,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every touching configuration, pushed every way, in both families, gives penedge the
    /// expected outcome (the benchmark reports the same check on thousands of pairs).
    #[test]
    fn generated_pairs_have_the_expected_outcome() {
        static TOUCHES: [Touch; 7] = Touch::ALL;
        for family in Family::ALL {
            for push in [Push::Apart, Push::Touching, Push::Into] {
                for touch in &TOUCHES {
                    let scenario = Scenario {
                        name: "test",
                        push,
                        touches: std::slice::from_ref(touch),
                    };
                    let set = PairSet::generate(scenario, family, 20, &mut SplitMix64::new(1));
                    let misses = set.penedge_misses();
                    assert!(
                        misses.is_empty(),
                        "{family:?} {push:?} {touch:?}: {misses:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn generation_depends_on_the_seed_only() {
        let scenario = Scenario {
            name: "test",
            push: Push::Touching,
            touches: &Touch::EDGE_OR_VERTEX,
        };
        let set = |seed| PairSet::generate(scenario, Family::Rock, 5, &mut SplitMix64::new(seed));
        let (x, y) = (set(7), set(7));
        for ((a1, b1), (a2, b2)) in x.blocks.iter().zip(&y.blocks) {
            assert_eq!(a1.vertices(), a2.vertices());
            assert_eq!(b1.vertices(), b2.vertices());
        }
        assert_ne!(x.blocks[0].1.vertices(), set(8).blocks[0].1.vertices());
    }
}
