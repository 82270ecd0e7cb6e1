//! Contact detection over time steps, as DEM and DDA codes call it: the blocks move rigidly,
//! and each step asks for the contacts at the new poses.
//!
//! Three things carry over from step to step:
//!
//! - **The broad phase, with a skin.** Candidate pairs are found once with every box widened
//!   by its gap plus half the skin. While no block has moved more than half the skin since,
//!   every pair within its gap is still among them (each box moved at most that much), so
//!   the broad phase is skipped; a block moving farther triggers a rebuild.
//! - **Pairs whose blocks have not moved.** Each block records the update at which its pose
//!   last changed (in any bit), each pair the update at which it was last queried. A pair
//!   neither of whose blocks has moved since is placed exactly as then, and the query, a
//!   deterministic function of the two blocks, would give the same answer: it is not asked
//!   (touching pairs included). docs/mechanics.md proves, case by case, that the contacts
//!   stay exactly those of a full detection.
//! - **Certificates for pairs that are clearly apart or clearly overlapping.** A separated
//!   pair keeps a face plane with every vertex of the other block at least `s` beyond it; a
//!   penetrating pair keeps a point of an edge at least `D` inside the other block. Each
//!   block accumulates an upper bound of how far any of its points has travelled
//!   ([`Pose::displacement_bound`], step after step); while the two blocks have together
//!   travelled less than `s - gap` (or `D - gap`), the plane still separates them by more
//!   than the gap (or the point is still deeper than the gap) and the pair's answer is known
//!   without a query. A pair separated without a separating face plane is queried again
//!   with a wider gap, which certifies it for a travel a little under the widening
//!   ([`edge_certificate`]). Every other pair is queried anew.
//!
//! The contacts of each step are exactly those of [`BlockSystem::detect`] on the blocks at
//! their new poses (the tests check it step by step).
//!
//! A block's geometry is placed at its new pose only when it is needed: for a queried pair,
//! for a rebuild of the broad phase, or when [`ContactTracker::system`] is asked for.
//! Placing is bound by memory traffic (a block's vertices, planes and coordinates written,
//! its reference read), and in a small step most pairs are certified: their blocks need
//! only their travel, which comes from the poses. The blocks placed in a step, and those of
//! the pairs it queries, are scattered through memory: each is asked for (prefetched) a few
//! places ahead of its turn, which made a small step of a 50^3 grid a quarter faster.

use super::body_contacts::{BodyContacts, FaceMarks, Piece};
use super::detect::{ask_ahead, SystemContacts, SLICE};
use super::{BlockSystem, BroadPhase, WideBoxes};
use crate::block::{readable, ConvexBlock, Pose, Prefetch, Reach};
use crate::classify::PairResult;
use crate::contact::Detector;
use crate::geometry::DVec3;
use crate::penetration::{PenetrationEdge, Side};
use crate::tolerance::{Tolerance, ROUNDING_FLOOR};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use thiserror::Error;

/// Why a tracker cannot be made or updated.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum TrackerError {
    /// The skin is negative, NaN or infinite.
    #[error("the skin must be a finite length of at least 0, got {0}")]
    Skin(f64),
    /// Not one pose per block.
    #[error("{given} poses given for {blocks} blocks")]
    PoseCount {
        /// Poses given.
        given: usize,
        /// Blocks.
        blocks: usize,
    },
    /// A pose with a NaN or infinite component or a zero rotation.
    #[error("pose {0} has a NaN or infinite component or a zero rotation")]
    Pose(usize),
    /// A pose that would move its block where double precision no longer holds it: the
    /// rule of [`ConvexBlock::try_translated`], checked on a bound of the placed block's
    /// coordinates (see [`ContactTracker::update`]).
    #[error(
        "pose {block} moves block {block} too far: its coordinates could reach {} in \
         magnitude, beyond {}, the most at which double precision keeps its closest \
         vertices ({} apart) distinct (and at most 1e50)",
        readable(.magnitude), readable(.limit), readable(.spacing)
    )]
    OutOfRange {
        /// The block (and its pose).
        block: usize,
        /// The largest coordinate magnitude the block could have at the pose.
        magnitude: f64,
        /// The largest the block may have.
        limit: f64,
        /// The distance of its closest two vertices.
        spacing: f64,
    },
    /// Two parts of one body (a concave block) given different poses.
    #[error(
        "blocks {first} and {part} are parts of body {body} but were given different poses; \
         a concave block moves rigidly: give its parts one pose"
    )]
    BodyPose {
        /// The body.
        body: u32,
        /// Its first part.
        first: u32,
        /// A part whose pose differs from the first part's.
        part: u32,
    },
}

/// What an update did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UpdateReport {
    /// Whether the broad phase ran again (a block moved more than half the skin).
    pub rebuilt: bool,
    /// Candidate pairs.
    pub candidate_pairs: usize,
    /// Pairs answered by their certificate, without a query.
    pub certified: usize,
    /// Pairs answered because neither block moved since the pair's last query.
    pub unmoved: usize,
    /// Pairs queried.
    pub queried: usize,
}

/// Slack on the certificates' comparison: the rounding floor of the gap grows with the
/// coordinates' magnitude, which grows by at most the distance travelled, plus the rounding
/// of the sums themselves.
pub(crate) const TRAVEL_SLACK: f64 = 1.0 + ROUNDING_FLOOR + 4.0 * f64::EPSILON;

/// How much a block's box diagonal (its size, which sets its gap) can grow per unit of its
/// largest vertex motion: each of the box's three extents by twice the motion.
pub(crate) const SIZE_GROWTH: f64 = 2.0 * 1.732_050_807_568_877_2;

/// The travel sum below which a certificate holds: with margin `m` (separation or depth)
/// and gap `g` recorded when the blocks had travelled `ti0` and `tj0`, the answer stands
/// while `m - (ti - ti0) - (tj - tj0) > g + gap growth + floor growth`. The gap is `slope`
/// ([`Tolerance::gap_slope`](crate::Tolerance)) times the smaller block's box diagonal,
/// which turns with the block and so grows by at most `SIZE_GROWTH` times its travel: the
/// travel since is charged `1 + SIZE_GROWTH slope` times. That is while `(ti + tj) *
/// TRAVEL_SLACK < (m - g) / (1 + SIZE_GROWTH slope) + ti0 + tj0` (less the rounding of this
/// sum). One number per pair, so that checking a certified pair reads 16 bytes and two
/// travels.
pub(crate) fn deadline(margin: f64, gap: f64, travel: [f64; 2], slope: f64) -> f64 {
    if margin <= gap {
        return f64::NEG_INFINITY;
    }
    let allowed = (margin - gap) / (1.0 + SIZE_GROWTH * slope);
    let sum = allowed + travel[0] + travel[1];
    sum - 4.0 * f64::EPSILON * (margin + gap + travel[0] + travel[1])
}

/// Whether a certificate with deadline `deadline` ([`deadline`]) still answers its pair, the
/// blocks having travelled `travel` in all.
#[inline]
pub(crate) fn holds(deadline: f64, travel: [f64; 2]) -> bool {
    (travel[0] + travel[1]) * TRAVEL_SLACK < deadline
}

/// The contacts of a block system whose blocks move rigidly, updated step by step.
///
/// ```
/// use penedge::block::Pose;
/// use penedge::system::{paper_example, ContactTracker, PaperExample};
/// use penedge::Tolerance;
/// let system = paper_example(PaperExample::One).unwrap();
/// let mut tracker = ContactTracker::new(&system, Tolerance::default(), 0.1).unwrap();
/// assert_eq!(tracker.contacts().contacts.len(), 28);
/// // Move block 0 (at a bottom corner) down by 1 mm: it leaves some of its neighbours.
/// let mut poses = vec![Pose::IDENTITY; system.len()];
/// poses[0].translation.z = -1e-3;
/// let report = tracker.update(&poses).unwrap();
/// assert!(!report.rebuilt);
/// assert!(tracker.contacts().contacts.len() < 28);
/// ```
#[derive(Clone, Debug)]
pub struct ContactTracker {
    tol: Tolerance,
    skin: f64,
    reference: Vec<ConvexBlock>,
    current: BlockSystem,
    centre: Vec<DVec3>,
    radius: Vec<f64>,
    /// Per block, how far a pose may translate it ([`Reach`]).
    reach: Vec<Reach>,
    poses: Vec<Pose>,
    built_at: Vec<Pose>,
    travel: Vec<f64>,
    /// Per block, its travel in the last update (sizes the edge certificates).
    last_step: Vec<f64>,
    pairs: Vec<[u32; 2]>,
    /// Per pair, the travel sum below which its last answer stands ([`deadline`]).
    deadlines: Vec<f64>,
    /// Per pair, its last answer.
    results: Vec<PairResult>,
    contacts: SystemContacts,
    /// Per block, whether its geometry lags its pose.
    stale: Vec<bool>,
    /// Updates so far.
    step: u32,
    /// Per block, the update at which its pose last changed (0: never).
    moved_at: Vec<u32>,
    /// Per pair, the update at which it was last queried.
    asked_at: Vec<u32>,
    /// Per block, whether a query of this step needs its geometry (scratch).
    needed: Flags,
    /// The contacts of the bodies, when tracked.
    bodies: Option<Box<BodyTracking>>,
}

/// A pair's place in the order of the pieces: its bodies (smaller first), its parts (that of
/// the first body first).
type PairKey = ([u32; 2], [u32; 2]);

/// What a tracker keeps to report the contacts of the bodies ([`BlockSystem::detect_bodies`]).
#[derive(Clone, Debug, Default)]
struct BodyTracking {
    /// Per block, the first part of its body (parts of one body must share a pose).
    first_part: Vec<u32>,
    /// Per candidate pair, its piece when it is a contact.
    pieces: Vec<Option<Box<Piece>>>,
    /// The candidate pairs (indices) by pair of bodies, then oriented parts: the order of
    /// [`BlockSystem::detect_bodies`]' pieces.
    order: Vec<u32>,
    /// Per entry of `order`, its pair of bodies (smaller first).
    order_bodies: Vec<[u32; 2]>,
    /// The contacts of the bodies at the current poses.
    found: BodyContacts,
    /// The glued and covered faces (the glue never changes).
    marks: FaceMarks,
}

/// Which stale blocks [`ContactTracker::place`] places.
#[derive(Clone, Copy)]
enum Which {
    All,
    /// Those marked in `needed`.
    Needed,
}

/// One flag per block, set from several threads (scratch: all clear between uses, so a
/// clone is a set of clear flags).
#[derive(Debug, Default)]
struct Flags(Vec<AtomicBool>);

impl Flags {
    fn new(n: usize) -> Flags {
        Flags((0..n).map(|_| AtomicBool::new(false)).collect())
    }
}

impl Clone for Flags {
    fn clone(&self) -> Flags {
        Flags::new(self.0.len())
    }
}

impl ContactTracker {
    /// A tracker of `system`'s blocks, their current placement being the identity pose;
    /// `skin` (a length, ≥ 0) widens the broad phase's boxes so that it can be reused.
    /// Detects the contacts at once.
    ///
    /// For a system with concave blocks (parts sharing a body id,
    /// [`BlockSystem::with_bodies`]) the tracker also reports the contacts of the bodies, with
    /// their regions ([`ContactTracker::body_contacts`]), and pairs of parts of one body are
    /// never candidates: [`ContactTracker::contacts`] holds the contacts between parts of
    /// different bodies.
    pub fn new(system: &BlockSystem, tol: Tolerance, skin: f64) -> Result<Self, TrackerError> {
        Self::with_options(system, tol, skin, system.has_concave())
    }

    /// [`ContactTracker::new`], reporting the contacts of the bodies (with their regions)
    /// for any system: for convex blocks, [`BlockSystem::detect_bodies`]' regions, one per
    /// touching pair, with their normals, distances and areas. Each queried touching pair
    /// then costs its contact geometry too.
    pub fn tracking_bodies(
        system: &BlockSystem,
        tol: Tolerance,
        skin: f64,
    ) -> Result<Self, TrackerError> {
        Self::with_options(system, tol, skin, true)
    }

    fn with_options(
        system: &BlockSystem,
        tol: Tolerance,
        skin: f64,
        bodies: bool,
    ) -> Result<Self, TrackerError> {
        if !(skin.is_finite() && skin >= 0.0) {
            return Err(TrackerError::Skin(skin));
        }
        let reference = system.blocks().to_vec();
        let centre: Vec<DVec3> = reference.iter().map(ConvexBlock::centroid).collect();
        let radius = reference
            .iter()
            .zip(&centre)
            .map(|(b, c)| {
                b.vertices()
                    .iter()
                    .map(|v| v.distance(*c))
                    .fold(0.0, f64::max)
            })
            .collect();
        let reach = reference.par_iter().map(Reach::of).collect();
        let n = reference.len();
        let bodies = bodies.then(|| {
            let mut first_part: Vec<u32> = (0..n as u32).collect();
            for (_, parts) in system.body_parts() {
                for &k in &parts {
                    first_part[k as usize] = parts[0];
                }
            }
            Box::new(BodyTracking {
                first_part,
                marks: FaceMarks::of(system),
                ..BodyTracking::default()
            })
        });
        let mut current = BlockSystem::new(reference.clone());
        current.glue.clone_from(&system.glue);
        let mut tracker = ContactTracker {
            tol,
            skin,
            current,
            reference,
            centre,
            radius,
            reach,
            poses: vec![Pose::IDENTITY; n],
            built_at: vec![Pose::IDENTITY; n],
            travel: vec![0.0; n],
            last_step: vec![0.0; n],
            pairs: Vec::new(),
            deadlines: Vec::new(),
            results: Vec::new(),
            contacts: SystemContacts::default(),
            stale: vec![false; n],
            step: 0,
            moved_at: vec![0; n],
            asked_at: Vec::new(),
            needed: Flags::new(n),
            bodies,
        };
        tracker.rebuild();
        tracker.narrow_phase(true);
        Ok(tracker)
    }

    /// The contacts at the current poses.
    pub fn contacts(&self) -> &SystemContacts {
        &self.contacts
    }

    /// The contacts of the bodies at the current poses, with their regions, as
    /// [`BlockSystem::detect_bodies`] on the blocks at these poses; `None` when the tracker
    /// does not track them (a system of convex blocks made by [`ContactTracker::new`]).
    ///
    /// ```
    /// use penedge::block::Pose;
    /// use penedge::system::ContactTracker;
    /// use penedge::{BlockSystem, ConvexBlock, Tolerance};
    /// let tol = Tolerance::default();
    /// let c = |lo, hi| ConvexBlock::cuboid(lo, hi).unwrap();
    /// // A U-block of three parts (body 0) and a block sitting in its notch (body 1).
    /// let system = BlockSystem::new(vec![
    ///     c([0.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
    ///     c([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
    ///     c([2.0, 0.0, 1.0], [3.0, 1.0, 2.0]),
    ///     c([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
    /// ])
    /// .with_bodies(vec![0, 0, 0, 1], &tol)
    /// .unwrap();
    /// let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
    /// // The floor and the two walls of the notch: three regions of one pair of bodies.
    /// let regions = |t: &ContactTracker| {
    ///     let found = t.body_contacts().unwrap();
    ///     found.contacts.iter().map(|c| c.region).collect::<Vec<_>>()
    /// };
    /// assert_eq!(regions(&tracker), [0, 1, 2]);
    /// // Lift the block by 1 mm: it leaves the floor and keeps touching the walls.
    /// let mut poses = vec![Pose::IDENTITY; 4];
    /// poses[3].translation.z = 1e-3;
    /// tracker.update(&poses).unwrap();
    /// assert_eq!(regions(&tracker), [0, 1]);
    /// let full = tracker.system().detect_bodies(&tol);
    /// assert_eq!(tracker.body_contacts(), Some(&full));
    /// ```
    pub fn body_contacts(&self) -> Option<&BodyContacts> {
        self.bodies.as_ref().map(|b| &b.found)
    }

    /// The blocks at their current poses (placing those not placed yet: the updates place
    /// only what their queries need).
    pub fn system(&mut self) -> &BlockSystem {
        self.place(Which::All);
        &self.current
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.reference.len()
    }

    /// Whether the tracker has no block.
    pub fn is_empty(&self) -> bool {
        self.reference.is_empty()
    }

    /// The current poses (relative to the blocks given to [`ContactTracker::new`]).
    pub fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// Moves every block to its new pose (relative to the blocks given to
    /// [`ContactTracker::new`]) and updates the contacts.
    ///
    /// An error, and the tracker unchanged, when the poses are not one per block, when one
    /// is not finite or its rotation zero, when two parts of one body differ (in
    /// translation, or in rotation as [`Pose::same_placement`] compares them: `q`, `-q` and
    /// a multiple of `q` are one rotation, and the parts are then all placed at the first
    /// part's pose), or when a pose translates its block so far that its coordinates could
    /// pass the largest magnitude at which double precision keeps the block's closest
    /// vertices distinct (or 1e50): [`ConvexBlock::try_translated`]'s rule, checked per pose
    /// on a bound of the placed block's coordinates (its placed centroid's plus its radius;
    /// a pose without translation always passes), without a pass over its vertices.
    pub fn update(&mut self, poses: &[Pose]) -> Result<UpdateReport, TrackerError> {
        if poses.len() != self.reference.len() {
            return Err(TrackerError::PoseCount {
                given: poses.len(),
                blocks: self.reference.len(),
            });
        }
        if let Some(i) = poses
            .par_iter()
            .position_first(|p| Pose::new(p.rotation, p.translation).is_none())
        {
            return Err(TrackerError::Pose(i));
        }
        let normalised = |p: &Pose| Pose::new(p.rotation, p.translation).unwrap_or(*p);
        if let Some(block) = poses
            .par_iter()
            .zip(&self.reach)
            .position_first(|(p, r)| !r.admits(&normalised(p)))
        {
            let r = &self.reach[block];
            return Err(TrackerError::OutOfRange {
                block,
                magnitude: r.magnitude_at(&normalised(&poses[block])),
                limit: r.limit,
                spacing: r.spacing,
            });
        }
        // The parts of one body: one rotation, compared as a rotation (`q`, `-q` and `3 q`
        // are one: `Pose::same_placement`), and each part then placed at its first part's
        // pose, so that the parts stay glued bit for bit.
        let mut shared = None;
        if let Some(tracking) = self.bodies.as_ref().filter(|_| self.current.has_concave()) {
            let first = &tracking.first_part;
            if let Some(part) = (0..poses.len()).into_par_iter().position_first(|k| {
                let f = first[k] as usize;
                poses[k] != poses[f]
                    && !normalised(&poses[k]).same_placement(&normalised(&poses[f]))
            }) {
                return Err(TrackerError::BodyPose {
                    body: self.current.body_of(part as u32),
                    first: first[part],
                    part: part as u32,
                });
            }
            if (0..poses.len())
                .into_par_iter()
                .any(|k| poses[k] != poses[first[k] as usize])
            {
                let one: Vec<Pose> = first.par_iter().map(|&f| poses[f as usize]).collect();
                shared = Some(one);
            }
        }
        let poses = shared.as_deref().unwrap_or(poses);
        self.step = match self.step.checked_add(1) {
            Some(step) => step,
            None => self.restart_steps(),
        };
        let farthest = self.move_poses(poses);
        let rebuilt = farthest > 0.5 * self.skin;
        if rebuilt {
            self.place(Which::All);
            self.rebuild();
        }
        let (unmoved, certified, queried) = self.narrow_phase(rebuilt);
        Ok(UpdateReport {
            rebuilt,
            candidate_pairs: self.pairs.len(),
            certified,
            unmoved,
            queried,
        })
    }

    /// After `u32::MAX` updates: every block counts as moved since every pair's last query
    /// (each pair is queried or certified once more); returns the new update count.
    fn restart_steps(&mut self) -> u32 {
        self.moved_at.fill(1);
        self.asked_at.fill(0);
        1
    }

    /// Takes the new poses and adds each block's travel (the blocks are placed when needed,
    /// [`ContactTracker::place`]); returns the largest distance a block has moved since the
    /// broad phase was built.
    fn move_poses(&mut self, poses: &[Pose]) -> f64 {
        let (centre, radius, step) = (&self.centre, &self.radius, self.step);
        self.travel
            .par_iter_mut()
            .zip(&mut self.last_step)
            .zip(&mut self.poses)
            .zip(&mut self.stale)
            .zip(&mut self.moved_at)
            .zip(&self.built_at)
            .zip(poses)
            .enumerate()
            .map(
                |(i, ((((((travel, last), pose), stale), moved), built), given))| {
                    // Normalised again here rather than kept from the check: one pass, no buffer.
                    let new = &Pose::new(given.rotation, given.translation).unwrap_or(*pose);
                    // A pose equal to the last one places the block exactly where it was.
                    let changed = new != pose;
                    *last = if changed {
                        pose.displacement_bound(new, centre[i], radius[i])
                    } else {
                        0.0
                    };
                    *travel += *last;
                    if changed {
                        *stale = true;
                        *moved = step;
                    }
                    *pose = *new;
                    built.displacement_bound(new, centre[i], radius[i])
                },
            )
            .reduce(|| 0.0, f64::max)
    }

    /// Places at their poses the stale blocks, all of them or those marked as needed (the
    /// marks are cleared on the way).
    fn place(&mut self, which: Which) {
        let (reference, poses, needed) = (&self.reference, &self.poses, &self.needed.0);
        // The blocks to place, with their stale flags, their marks cleared on the way: a
        // load, and a store only where set (a swap on every block is dearer).
        let mut list: Vec<(usize, &mut ConvexBlock, &mut bool)> = self
            .current
            .blocks
            .par_iter_mut()
            .zip(&mut self.stale)
            .enumerate()
            .filter_map(|(i, (block, stale))| {
                let wanted = match which {
                    Which::All => true,
                    Which::Needed => {
                        let mark = needed[i].load(Ordering::Relaxed);
                        if mark {
                            needed[i].store(false, Ordering::Relaxed);
                        }
                        mark
                    }
                };
                (*stale && wanted).then_some((i, block, stale))
            })
            .collect();
        list.par_chunks_mut(256).for_each(|run| {
            const AHEAD: usize = 4;
            for k in 0..run.len() {
                if let Some((far, block, _)) = run.get(k + 2 * AHEAD) {
                    reference[*far].prefetch(Prefetch::Block);
                    block.prefetch(Prefetch::Block);
                }
                if let Some((near, block, _)) = run.get(k + AHEAD) {
                    reference[*near].prefetch(Prefetch::Coordinates);
                    block.prefetch(Prefetch::Coordinates);
                }
                let (i, block, stale) = &mut run[k];
                block.place_geometry(&reference[*i], &poses[*i]);
                **stale = false;
            }
        });
    }

    /// Whether pair `k`'s certificate answers it at the current travels.
    #[inline]
    fn certified(&self, k: usize) -> bool {
        let travel = self.pairs[k].map(|b| self.travel[b as usize]);
        holds(self.deadlines[k], travel)
    }

    /// Whether neither block of pair `k` has moved since the pair's last query: both are
    /// placed exactly as then, so its answer is the same.
    #[inline]
    fn unmoved(&self, k: usize) -> bool {
        let asked = self.asked_at[k];
        self.pairs[k]
            .iter()
            .all(|&b| self.moved_at[b as usize] <= asked)
    }

    /// The pairs (indices, ascending) that neither their blocks' stillness nor their
    /// certificates answer (all of them when `fresh`: new pairs have no answer yet), with
    /// their blocks placed; and how many were still.
    fn place_queried(&mut self, fresh: bool) -> (Vec<u32>, usize) {
        let queried: Vec<u32> = (0..self.pairs.len() as u32)
            .into_par_iter()
            .filter(|&k| fresh || !self.unmoved(k as usize) && !self.certified(k as usize))
            .collect();
        let unmoved = if queried.len() == self.pairs.len() {
            0
        } else {
            (0..self.pairs.len())
                .into_par_iter()
                .filter(|&k| self.unmoved(k))
                .count()
        };
        if self.dense(queried.len()) {
            // Most blocks are needed: placing the stale ones costs no more than marking.
            self.place(Which::All);
        } else {
            let (pairs, needed) = (&self.pairs, &self.needed.0);
            queried.par_iter().for_each(|&k| {
                for b in pairs[k as usize] {
                    needed[b as usize].store(true, Ordering::Relaxed);
                }
            });
            self.place(Which::Needed);
        }
        (queried, unmoved)
    }

    /// Whether a step that queries `queried` pairs builds its output anew (over an eighth of
    /// the pairs) rather than replacing the queried pairs' answers in the last one.
    fn dense(&self, queried: usize) -> bool {
        queried > self.pairs.len() / 8
    }

    fn rebuild(&mut self) {
        let half_skin = 0.5 * self.skin;
        let blocks = self.current.blocks();
        let boxes = WideBoxes::from_fn(blocks.len(), |i| {
            let aabb = blocks[i].aabb();
            (aabb, self.tol.for_box(&aabb).gap + half_skin)
        });
        self.pairs = boxes.pairs(BroadPhase::default());
        if self.current.has_concave() {
            let system = &self.current;
            self.pairs
                .retain(|&[i, j]| system.body_of(i) != system.body_of(j));
        }
        if let Some(tracking) = &mut self.bodies {
            let system = &self.current;
            // Each pair's key: its bodies, smaller first, and its parts in their order.
            let key = |&[i, j]: &[u32; 2]| {
                let (a, b) = (system.body_of(i), system.body_of(j));
                if a <= b {
                    ([a, b], [i, j])
                } else {
                    ([b, a], [j, i])
                }
            };
            let mut order: Vec<(PairKey, u32)> = self
                .pairs
                .par_iter()
                .enumerate()
                .map(|(k, pair)| (key(pair), k as u32))
                .collect();
            order.par_sort_unstable();
            tracking.order_bodies = order.par_iter().map(|((b, _), _)| *b).collect();
            tracking.order = order.into_par_iter().map(|(_, k)| k).collect();
            tracking.pieces = vec![None; self.pairs.len()];
        }
        self.deadlines = vec![f64::NEG_INFINITY; self.pairs.len()];
        self.results = vec![PairResult::Separated; self.pairs.len()];
        // Queried at once: the narrow phase after a rebuild queries every pair.
        self.asked_at = vec![0; self.pairs.len()];
        self.built_at.clone_from(&self.poses);
    }

    /// Answers every candidate pair (by stillness, certificate or query); returns (unmoved,
    /// certified, queried).
    /// `fresh`: the candidate pairs are new (the output is built from every pair's answer;
    /// otherwise the last output is kept but for the queried pairs).
    ///
    /// Each answer stays in its pair's certificate. The pairs to query are listed once, then
    /// queried a slice at a time: a small step reads the certificates of all pairs once and
    /// touches only the queried ones after that (on a 50^3 grid of cubes, 10,000 of 1.5
    /// million pairs, whose blocks are asked for ahead of their queries), and its output is
    /// the last one with those pairs' answers replaced.
    fn narrow_phase(&mut self, fresh: bool) -> (usize, usize, usize) {
        let (queried, unmoved) = self.place_queried(fresh);
        let dense = fresh || self.dense(queried.len());
        let system = &self.current;
        let blocks = system.blocks();
        let with_pieces = self.bodies.is_some();
        let (travel, last_step, radius) = (&self.travel, &self.last_step, &self.radius);
        let (pairs, tol) = (&self.pairs, self.tol);
        let blocks_of = |k: u32| pairs[k as usize].map(|b| &blocks[b as usize]);
        // Pair `k`'s answer and the deadline of its certificate.
        let answer = |det: &mut Detector, k: u32| {
            let [i, j] = pairs[k as usize].map(|b| b as usize);
            let (ti, tj) = (travel[i], travel[j]);
            let [a, b] = blocks_of(k);
            let (result, piece) = if with_pieces {
                system.query_parts(det, [i as u32, j as u32], a, b)
            } else {
                (det.detect(a, b), None)
            };
            let gap = det.thresholds(a, b).gap;
            let slope = det.tolerance().gap_slope();
            let margin = match result {
                PairResult::Separated => separation(a, b),
                PairResult::Penetrating => depth(a, b, det.penetration_edges()),
                PairResult::Contact(_) => f64::NEG_INFINITY,
            };
            let deadline = if result == PairResult::Separated && margin <= gap {
                // No separating face plane: try the certificate of a wider gap.
                let wider = EDGE_CERTIFICATE_STEPS * (last_step[i] + last_step[j]);
                let radii = [radius[i], radius[j]];
                edge_certificate(det, [a, b], radii, gap, wider).map_or(f64::NEG_INFINITY, |m| {
                    deadline(m + gap, gap, [ti, tj], slope)
                })
            } else {
                deadline(margin, gap, [ti, tj], slope)
            };
            (result, deadline, piece)
        };
        // The pairs of bodies whose contacts may have changed (sparse steps).
        let mut dirty: Vec<[u32; 2]> = Vec::new();
        let mut changed: Vec<([u32; 2], PairResult)> = Vec::new();
        let mut answers = Vec::new();
        for slice in queried.chunks(SLICE) {
            slice
                .par_iter()
                .enumerate()
                .map_init(
                    || Detector::new(tol),
                    |det, (n, &k)| {
                        if !dense {
                            // Scattered pairs: both blocks asked for (in a dense step
                            // consecutive pairs share blocks, which are then in cache).
                            let pair_at = |m: usize| slice.get(m).map(|&k| pairs[k as usize]);
                            ask_ahead(blocks, pair_at, n, true);
                        }
                        answer(det, k)
                    },
                )
                .collect_into_vec(&mut answers);
            for (&k, (result, deadline, piece)) in slice.iter().zip(&mut answers) {
                let (k, result, deadline) = (k as usize, *result, *deadline);
                if let Some(tracking) = &mut self.bodies {
                    let old = self.results[k];
                    if !dense && (old != PairResult::Separated || result != PairResult::Separated) {
                        let mut bodies = self.pairs[k].map(|b| system.body_of(b));
                        bodies.sort_unstable();
                        dirty.push(bodies);
                    }
                    tracking.pieces[k] = piece.take();
                }
                self.results[k] = result;
                self.deadlines[k] = deadline;
                self.asked_at[k] = self.step;
                if !dense {
                    changed.push((self.pairs[k], result));
                }
            }
        }
        if dense {
            let mut found = SystemContacts::default();
            found.extend_from(&self.pairs, &self.results);
            self.contacts = found;
        } else if !changed.is_empty() {
            self.contacts = self.contacts.with_changes(&changed);
        }
        if let Some(tracking) = &mut self.bodies {
            tracking.update(system, &self.results, dense, dirty);
        }
        let certified = self.pairs.len() - queried.len() - unmoved;
        (unmoved, certified, queried.len())
    }
}

impl BodyTracking {
    /// The contacts of the bodies after a step: built anew from every pair's piece in a
    /// dense step, else the last ones with those of the pairs of bodies in `dirty` (whose
    /// part pairs were queried and touch or penetrate, now or before) made anew. The regions
    /// of a pair of bodies are a function of its pieces (and its parts' current geometry),
    /// and a piece changes only when its pair is queried: the others keep theirs.
    fn update(
        &mut self,
        system: &BlockSystem,
        results: &[PairResult],
        dense: bool,
        mut dirty: Vec<[u32; 2]>,
    ) {
        let penetrates = |range: std::ops::Range<usize>| {
            self.order[range]
                .iter()
                .any(|&k| results[k as usize] == PairResult::Penetrating)
        };
        if dense {
            let pieces: Vec<&Piece> = self
                .order
                .iter()
                .filter_map(|&k| self.pieces[k as usize].as_deref())
                .collect();
            let mut penetrating: Vec<[u32; 2]> = self
                .order
                .iter()
                .zip(&self.order_bodies)
                .filter(|(&k, _)| results[k as usize] == PairResult::Penetrating)
                .map(|(_, &b)| b)
                .collect();
            penetrating.dedup();
            self.found = system.regions(&pieces, penetrating, &self.marks);
            return;
        }
        if dirty.is_empty() {
            return;
        }
        dirty.sort_unstable();
        dirty.dedup();
        let replaced: Vec<([u32; 2], BodyContacts)> = dirty
            .into_par_iter()
            .map(|bodies| {
                let start = self.order_bodies.partition_point(|b| *b < bodies);
                let end = start + self.order_bodies[start..].partition_point(|b| *b == bodies);
                let mut fresh = BodyContacts::empty();
                if penetrates(start..end) {
                    fresh.penetrating.push(bodies);
                } else {
                    let pieces: Vec<&Piece> = self.order[start..end]
                        .iter()
                        .filter_map(|&k| self.pieces[k as usize].as_deref())
                        .collect();
                    if !pieces.is_empty() {
                        system.add_pair(&pieces, &mut fresh, &self.marks);
                    }
                }
                (bodies, fresh)
            })
            .collect();
        self.found = self.found.with_pairs_replaced(&replaced);
    }
}

/// How many steps like the last one an edge certificate is sized for (see
/// [`edge_certificate`]): a wider gap costs nothing more but holds for fewer pairs.
pub(crate) const EDGE_CERTIFICATE_STEPS: f64 = 8.0;

/// A certificate for a pair separated at gap `gap` without a separating face plane (edges
/// or vertices facing each other): the travel sum, since now, below which it stays
/// separated; `None` when the pair is not separated at the gap widened by `wider`.
///
/// If no edge of either block meets the other widened by `gap + wider`, then no edge comes
/// within `wider` of the other widened by `gap` (moving every face plane out by `wider`
/// contains the ball of radius `wider` about every point). Moving the blocks by travels
/// `t_a`, `t_b` moves a point of an edge by at most its block's travel, and a point of the
/// block widened by `gap` by at most `f t` with `f = 1 + gap / ρ` (`ρ` the depth of the
/// centroid inside the block: the widened block lies in the block scaled by `1 + gap / ρ`
/// about its centroid, so within `f` times the radius that the travel bound uses). The gap's
/// own growth with the coordinates' magnitude (at most the rounding floor times the travel)
/// widens it by at most that growth times `r / ρ`. So the pair stays separated while
/// `f (t_a + t_b) < wider` with `f` the larger factor of the two blocks; a rounding allowance
/// is taken off.
pub(crate) fn edge_certificate(
    det: &mut Detector,
    [a, b]: [&ConvexBlock; 2],
    radii: [f64; 2],
    gap: f64,
    wider: f64,
) -> Option<f64> {
    let widens = wider > 0.0; // false for NaN too
    if !widens || !det.separated_at(a, b, gap + wider) {
        return None;
    }
    let factor = |x: &ConvexBlock, r: f64| {
        let c = x.centroid();
        let depth = x
            .planes()
            .iter()
            .map(|p| -p.distance(c))
            .fold(f64::INFINITY, f64::min);
        1.0 + gap / depth + ROUNDING_FLOOR * r / depth
    };
    let f = factor(a, radii[0]).max(factor(b, radii[1]));
    let magnitude = a.magnitude().max(b.magnitude()) + radii[0] + radii[1];
    let margin = wider / f - 64.0 * f64::EPSILON * magnitude;
    (margin > 0.0).then_some(margin)
}

/// The largest separation by a face plane of either block: every vertex of the other block
/// is at least this far beyond it (negative when no plane separates).
pub(crate) fn separation(a: &ConvexBlock, b: &ConvexBlock) -> f64 {
    let by = |x: &ConvexBlock, y: &ConvexBlock| {
        x.planes()
            .iter()
            .map(|p| {
                y.vertices()
                    .iter()
                    .map(|&v| p.distance(v))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    by(a, b).max(by(b, a))
}

/// A depth that some point of the pair's penetration edges (from the query just made)
/// reaches inside the other block: the largest, over the edges' ends and midpoints, of
/// `min_f -(n_f · (p - q_f))` (negative when none is inside). Any point inside is a valid
/// witness; the midpoints catch edges that cross the other block without a vertex inside it
/// (edge-edge penetrations), and cost a few dot products per edge.
fn depth(a: &ConvexBlock, b: &ConvexBlock, edges: &[PenetrationEdge]) -> f64 {
    let depth_in = |block: &ConvexBlock, p: DVec3| {
        block
            .planes()
            .iter()
            .map(|pl| -pl.distance(p))
            .fold(f64::INFINITY, f64::min)
    };
    edges
        .iter()
        .map(|pe| {
            let (owner, other) = match pe.side {
                Side::A => (a, b),
                Side::B => (b, a),
            };
            let [p, q] = pe.points(owner);
            depth_in(other, p)
                .max(depth_in(other, q))
                .max(depth_in(other, (p + q) * 0.5))
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    use crate::system::test_rng::Rng;

    impl Rng {
        fn small_pose(&mut self, shift: f64, angle: f64) -> Pose {
            let axis = DVec3::new(self.signed(), self.signed(), self.signed()).normalize();
            Pose {
                rotation: DQuat::from_axis_angle(axis, angle * self.signed()),
                translation: DVec3::new(self.signed(), self.signed(), self.signed()) * shift,
            }
        }
    }

    fn grid(n: usize) -> BlockSystem {
        BlockSystem::new(
            (0..n * n * n)
                .map(|k| {
                    let p = [(k % n) as f64, (k / n % n) as f64, (k / (n * n)) as f64];
                    ConvexBlock::cuboid(p, p.map(|c| c + 1.0)).unwrap()
                })
                .collect(),
        )
    }

    /// `system`'s blocks placed at `poses`, as a system of their own.
    fn moved_system(system: &BlockSystem, poses: &[Pose]) -> BlockSystem {
        let blocks = system.blocks().iter().zip(poses);
        BlockSystem::new(
            blocks
                .map(|(b, p)| b.transformed(p.rotation, p.translation, 1.0))
                .collect(),
        )
    }

    /// Each step's contacts equal a full detection on the moved blocks.
    fn check_steps(system: &BlockSystem, skin: f64, steps: &[(f64, f64)]) -> Vec<UpdateReport> {
        let tol = Tolerance::default();
        let mut tracker = ContactTracker::new(system, tol, skin).unwrap();
        assert_eq!(tracker.contacts(), &system.detect(&tol));
        let mut rng = Rng(7);
        let mut poses = vec![Pose::IDENTITY; system.len()];
        let mut reports = Vec::new();
        for &(shift, angle) in steps {
            for (pose, block) in poses.iter_mut().zip(system.blocks()) {
                // A small rotation about the block's centroid, then a small shift.
                let step = rng.small_pose(shift, angle);
                let c = pose.apply(block.centroid());
                *pose = Pose {
                    rotation: (step.rotation * pose.rotation).normalize(),
                    translation: step.rotation * (pose.translation - c) + c + step.translation,
                };
            }
            let report = tracker.update(&poses).unwrap();
            let moved = moved_system(system, &poses);
            assert_eq!(tracker.contacts(), &moved.detect(&tol), "{report:?}");
            // The blocks that no query placed are placed when the system is asked for.
            let placed = tracker.system().blocks();
            for (p, m) in placed.iter().zip(moved.blocks()) {
                let off = p.vertices().iter().zip(m.vertices());
                assert!(off.map(|(p, m)| p.distance(*m)).fold(0.0, f64::max) < 1e-12);
            }
            reports.push(report);
        }
        reports
    }

    /// Sparse steps (few pairs queried, the output made from the last one): one block of a
    /// loose grid moves onto a neighbour, into it, and back out, while the others stay.
    /// Contacts and penetrating pairs appear and go, and every step equals a full detection.
    #[test]
    fn sparse_steps_replace_only_the_queried_answers() {
        let n = 5;
        let spacing = 1.01;
        let system = BlockSystem::new(
            (0..n * n * n)
                .map(|k| {
                    let p = [k % n, k / n % n, k / (n * n)].map(|c| c as f64 * spacing);
                    ConvexBlock::cuboid(p, p.map(|c| c + 1.0)).unwrap()
                })
                .collect(),
        );
        let tol = Tolerance::default();
        let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
        assert!(tracker.contacts().contacts.is_empty());
        // Block 62, in the middle, along x towards block 63: touching, in, touching, away.
        let (mut touched, mut penetrated, mut sparse) = (false, false, 0);
        for shift in [0.005, 0.01, 0.012, 0.01, 0.004, 0.0] {
            let mut poses = vec![Pose::IDENTITY; system.len()];
            poses[62].translation.x = shift;
            let report = tracker.update(&poses).unwrap();
            assert!(!report.rebuilt);
            assert!(report.queried * 8 < report.candidate_pairs);
            sparse += (report.queried > 0) as usize;
            let moved = moved_system(&system, &poses);
            let found = moved.detect(&tol);
            assert_eq!(tracker.contacts(), &found, "shift {shift}");
            touched |= found.contacts.iter().any(|c| c.pair == [62, 63]);
            penetrated |= found.penetrating.contains(&[62, 63]);
        }
        assert!(
            touched && penetrated && sparse >= 4,
            "{touched} {penetrated} {sparse}"
        );
        assert!(
            tracker.contacts().contacts.is_empty() && tracker.contacts().penetrating.is_empty()
        );
    }

    /// Steps of a touching grid at a wide gap (every candidate pair touches, so no pair has a
    /// certificate), each moving a random share of the blocks by a jitter and leaving the
    /// others exactly where they were: every step equals a full detection, and the pairs
    /// skipped as unmoved are exactly those with neither block moved (counted here from the
    /// moved blocks); the others are all queried.
    fn check_partial_steps(n: usize, share: f64, steps: usize) -> Vec<UpdateReport> {
        let system = grid(n);
        let tol = Tolerance::with_gap(1e-3).unwrap();
        let mut tracker = ContactTracker::new(&system, tol, 0.05).unwrap();
        let mut rng = Rng(19);
        let mut poses = vec![Pose::IDENTITY; system.len()];
        let mut reports = Vec::new();
        for _ in 0..steps {
            let mut moved = vec![false; system.len()];
            for (i, (pose, block)) in poses.iter_mut().zip(system.blocks()).enumerate() {
                if rng.unit() < share {
                    let step = rng.small_pose(1e-5, 1e-5);
                    let c = pose.apply(block.centroid());
                    *pose = Pose {
                        rotation: (step.rotation * pose.rotation).normalize(),
                        translation: step.rotation * (pose.translation - c) + c + step.translation,
                    };
                    moved[i] = true;
                }
            }
            let report = tracker.update(&poses).unwrap();
            let full = moved_system(&system, &poses).detect(&tol);
            assert_eq!(tracker.contacts(), &full, "{report:?}");
            assert_eq!(full.contacts.len(), tracker.pairs.len(), "all pairs touch");
            let still = tracker
                .pairs
                .iter()
                .filter(|p| p.iter().all(|&b| !moved[b as usize]))
                .count();
            assert_eq!(report.unmoved, still, "{report:?}");
            assert_eq!(report.queried, tracker.pairs.len() - still, "{report:?}");
            assert!(!report.rebuilt);
            reports.push(report);
        }
        reports
    }

    #[test]
    fn a_step_queries_only_the_pairs_of_moved_blocks() {
        // 1 % of a 10^3 grid (about 10 blocks and 260 of 6,859 pairs per step), then 20 %.
        let reports = check_partial_steps(10, 0.01, 4);
        assert!(reports
            .iter()
            .all(|r| r.queried > 0 && r.queried * 10 < r.candidate_pairs));
        check_partial_steps(6, 0.2, 4);
    }

    #[test]
    fn every_block_jittered_or_none_moved_at_a_wide_gap() {
        // Every block moved: every pair queried, nothing skipped.
        let reports = check_partial_steps(5, 1.0, 3);
        assert!(reports.iter().all(|r| r.unmoved == 0));
        // No block moved: nothing queried.
        let reports = check_partial_steps(5, 0.0, 3);
        assert!(reports
            .iter()
            .all(|r| r.queried == 0 && r.unmoved == r.candidate_pairs));
    }

    /// A block moved and then put back at its former pose counts as moved: its pairs are
    /// queried again (the skip compares update counts, not poses).
    #[test]
    fn unmoved_pairs_keep_their_answers_while_others_change() {
        let system = grid(3);
        let tol = Tolerance::default();
        let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
        let mut poses = vec![Pose::IDENTITY; system.len()];
        // Block 13 (the centre) lifted off, then back, then left there: its pairs change
        // in the first two steps, nothing in the third.
        for (lift, moved) in [(1e-3, true), (0.0, true), (0.0, false)] {
            poses[13].translation.z = lift;
            let report = tracker.update(&poses).unwrap();
            assert_eq!(
                tracker.contacts(),
                &moved_system(&system, &poses).detect(&tol)
            );
            let of_13 = tracker.pairs.iter().filter(|p| p.contains(&13)).count();
            let still = tracker.pairs.len() - if moved { of_13 } else { 0 };
            assert_eq!(report.unmoved, still, "{lift} {moved}");
        }
    }

    /// Past `u32::MAX` updates the update numbers start again: every pair counts as moved
    /// once (queried or certified), and every step stays exact.
    #[test]
    fn the_update_count_starting_again_keeps_every_step_exact() {
        let system = grid(3);
        let tol = Tolerance::default();
        let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
        tracker.step = u32::MAX - 1;
        let mut poses = vec![Pose::IDENTITY; system.len()];
        let mut reports = Vec::new();
        for (block, lift) in [(0, 1e-3), (13, 1e-3), (13, 0.0), (4, 2e-3)] {
            poses[block].translation.z = lift;
            let report = tracker.update(&poses).unwrap();
            assert_eq!(
                tracker.contacts(),
                &moved_system(&system, &poses).detect(&tol)
            );
            reports.push(report);
        }
        // The second update starts again: nothing counts as unmoved; then it works as before.
        assert_eq!(reports[1].unmoved, 0, "{reports:?}");
        assert!(
            reports[2].unmoved > 0 && reports[3].unmoved > 0,
            "{reports:?}"
        );
        assert_eq!(tracker.step, 3);
    }

    #[test]
    fn every_step_agrees_with_a_full_detection() {
        let steps = [
            (1e-3, 1e-3),
            (1e-5, 1e-5),
            (1e-5, 1e-5),
            (0.2, 0.05),
            (1e-6, 0.0),
        ];
        let reports = check_steps(&grid(4), 0.1, &steps);
        // Small steps reuse the broad phase; the large one (0.2 > half the skin) rebuilds.
        let rebuilt: Vec<bool> = reports.iter().map(|r| r.rebuilt).collect();
        assert_eq!(rebuilt, [false, false, false, true, false]);
        // After the first motion most pairs are clearly apart or overlapping: the next
        // small steps certify many of them.
        assert!(
            reports[1].certified > reports[1].candidate_pairs / 3,
            "{reports:?}"
        );
        assert_eq!(reports[0].certified, 0);
    }

    /// Many small random steps after a first one that opens the grid: pairs close in and
    /// move apart again across the certificates' margins, and every step stays exact.
    #[test]
    fn many_small_random_steps_stay_exact() {
        let mut steps = vec![(1e-3, 1e-3)];
        steps.extend([(2e-4, 2e-4); 40]);
        let reports = check_steps(&grid(4), 0.1, &steps);
        let certified: usize = reports.iter().map(|r| r.certified).sum();
        assert!(certified > 0, "{reports:?}");
    }

    /// Two cubes on edge, their ridges crossed (no face plane separates them), closing in
    /// step by step until they overlap: every step agrees with a full detection, and while
    /// they are clearly apart the edge certificates spare most queries.
    #[test]
    fn crossed_ridges_closing_in_agree_and_are_certified() {
        let quarter = std::f64::consts::FRAC_PI_4;
        let cube = ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).unwrap();
        let top = 0.5 * std::f64::consts::SQRT_2;
        // A's ridge along x at height 0; B's ridge along y at height `apart` above it.
        let apart = 1e-3;
        let a = cube.transformed(DQuat::from_rotation_x(quarter), DVec3::Z * -top, 1.0);
        let b = cube.transformed(
            DQuat::from_rotation_y(quarter),
            DVec3::Z * (top + apart),
            1.0,
        );
        let system = BlockSystem::new(vec![a, b]);
        let tol = Tolerance::default();
        let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
        let mut det = Detector::new(tol);
        let [a, b] = [&system.blocks()[0], &system.blocks()[1]];
        assert_eq!(det.detect(a, b), PairResult::Separated);
        assert!(
            separation(a, b) < 0.0,
            "a face plane separates: not the case to test"
        );
        let (mut certified, mut outcomes) = (0, Vec::new());
        for k in 1..=100 {
            let down = Pose {
                rotation: DQuat::IDENTITY,
                translation: DVec3::Z * (-2e-5 * k as f64),
            };
            let report = tracker.update(&[Pose::IDENTITY, down]).unwrap();
            let moved = b.transformed(down.rotation, down.translation, 1.0);
            let full = BlockSystem::new(vec![a.clone(), moved.clone()]).detect(&tol);
            assert_eq!(tracker.contacts(), &full, "step {k}: {report:?}");
            let outcome = det.detect(a, &moved).name();
            // Certified while apart: by an edge certificate (no face plane separates).
            certified += if outcome == "separated" {
                report.certified
            } else {
                0
            };
            outcomes.push(outcome);
        }
        // Apart for about 50 steps (a certificate holds for about 8 of them once the pair is
        // more than the certificate's widening apart), then overlapping.
        assert!(
            outcomes[..45].iter().all(|&o| o == "separated"),
            "{outcomes:?}"
        );
        assert!(
            outcomes[55..].iter().all(|&o| o == "penetrating"),
            "{outcomes:?}"
        );
        assert!(certified >= 20, "{certified} steps apart certified");
    }

    #[test]
    fn a_zero_skin_rebuilds_every_step_and_stays_exact() {
        // Even a step without motion: the travel bound counts the rounding of the poses.
        let reports = check_steps(&grid(3), 0.0, &[(1e-4, 0.0), (0.0, 0.0)]);
        assert!(reports.iter().all(|r| r.rebuilt), "{reports:?}");
    }

    #[test]
    fn a_jointed_system_moving_step_by_step() {
        let system = crate::system::paper_example(crate::system::PaperExample::Three).unwrap();
        check_steps(&system, 0.5, &[(1e-3, 1e-4), (1e-4, 1e-4), (1e-2, 1e-3)]);
    }

    #[test]
    fn bad_input_is_an_error() {
        let system = grid(2);
        let tol = Tolerance::default();
        for skin in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                ContactTracker::new(&system, tol, skin),
                Err(TrackerError::Skin(_))
            ));
        }
        let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
        assert_eq!(
            tracker.update(&[Pose::IDENTITY; 3]),
            Err(TrackerError::PoseCount {
                given: 3,
                blocks: 8
            })
        );
        let mut poses = vec![Pose::IDENTITY; 8];
        poses[5].translation.y = f64::NAN;
        assert_eq!(tracker.update(&poses), Err(TrackerError::Pose(5)));
        poses[5] = Pose {
            rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            translation: DVec3::ZERO,
        };
        assert_eq!(tracker.update(&poses), Err(TrackerError::Pose(5)));
        // A failed update changes nothing.
        assert_eq!(tracker.contacts(), &system.detect(&tol));
    }

    /// A translation that would carry a block where double precision no longer holds it
    /// (1e300; 1e14 for a unit cube, whose corners round together there) is an error naming
    /// the block, as `try_translated` refuses the moved block; 1e13 is placed as before.
    #[test]
    fn a_pose_beyond_the_blocks_reach_is_an_error() {
        let system = grid(2);
        let tol = Tolerance::default();
        let mut tracker = ContactTracker::new(&system, tol, 0.1).unwrap();
        let mut poses = vec![Pose::IDENTITY; 8];
        for far in [1e300, -1e300, 1e14] {
            poses[3].translation.y = far;
            let err = tracker.update(&poses).unwrap_err();
            assert!(
                matches!(err, TrackerError::OutOfRange { block: 3, .. }),
                "{err:?}"
            );
            let message = err.to_string();
            assert!(
                message.starts_with("pose 3 moves block 3 too far"),
                "{message}"
            );
            assert!(system.blocks()[3].try_translated(DVec3::Y * far).is_err());
            // A failed update changes nothing.
            assert_eq!(tracker.contacts(), &system.detect(&tol));
        }
        poses[3].translation.y = 1e13;
        tracker.update(&poses).unwrap();
        assert!(system.blocks()[3].try_translated(DVec3::Y * 1e13).is_ok());
        assert_eq!(
            tracker.contacts(),
            &moved_system(&system, &poses).detect(&tol)
        );
    }

    #[test]
    fn depth_and_separation_witnesses() {
        let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let b = ConvexBlock::cuboid([0.75, 0.25, 0.25], [2.0, 0.75, 0.75]).unwrap();
        // b's end face at x = 0.75 is 0.25 inside a (its vertices 0.25 from faces y, z).
        let mut det = Detector::new(Tolerance::default());
        assert_eq!(det.detect(&a, &b), PairResult::Penetrating);
        assert!((depth(&a, &b, det.penetration_edges()) - 0.25).abs() < 1e-12);
        // Two bars crossing without a vertex inside the other: the edges' midpoints are.
        let x = ConvexBlock::cuboid([-2.0, -0.5, -0.5], [2.0, 0.5, 0.5]).unwrap();
        let y = ConvexBlock::cuboid([-0.4, -2.0, 0.3], [0.4, 2.0, 1.3]).unwrap();
        assert!(x
            .vertices()
            .iter()
            .all(|&v| y.planes().iter().any(|p| p.distance(v) > 0.0)));
        assert_eq!(det.detect(&x, &y), PairResult::Penetrating);
        let d = depth(&x, &y, det.penetration_edges());
        assert!((d - 0.2).abs() < 1e-12, "{d}");
        let c = ConvexBlock::cuboid([1.5, 0.0, 0.0], [2.5, 1.0, 1.0]).unwrap();
        assert!((separation(&a, &c) - 0.5).abs() < 1e-12);
    }
}

#[cfg(test)]
#[path = "tracker_bodies_tests.rs"]
mod bodies_tests;
