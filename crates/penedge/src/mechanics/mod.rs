//! Rigid-block mechanics: an explicit distinct element method (3DEC-style) on penedge's
//! contacts. See `docs/mechanics.md` for the algorithm, the sign conventions and the units.
//!
//! One step ([`Simulation::step`]) is the algorithm: bodies at their poses -> contacts ->
//! sub-contacts -> forces -> integration -> new poses.
//!
//! ```
//! use penedge::mechanics::{JointModel, Simulation};
//! use penedge::{BlockSystem, ConvexBlock};
//! // A 1 m cube resting on a fixed base.
//! let base = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
//! let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
//! let mut sim = Simulation::new(&BlockSystem::new(vec![base, cube]), 2500.0).unwrap();
//! sim.fix(0).unwrap();
//! sim.set_default_joint(JointModel { kn: 1e9, ks: 1e9, ..JointModel::default() }).unwrap();
//! let report = sim.solve(1e-5, 100_000).unwrap();
//! assert!(report.converged);
//! // It sank by its weight over kn A: 2500 * 9.81 / 1e9.
//! let z = sim.bodies().poses()[1].translation.z;
//! assert!((z - (0.5 - 2500.0 * 9.81 / 1e9)).abs() < 1e-8);
//! ```

mod bodies;
mod bridge;
mod contacts;
mod excavation;
mod integrate;
mod joint;
mod state;
mod stress;
mod water;

pub use bodies::{Bodies, Fixity};
pub use bridge::{BridgeTable, BRIDGE_STRENGTH};
pub use contacts::{BodyContact, Contacts, SubContact};
pub use excavation::ExcavationReport;
pub use integrate::{free_rotation, Damping};
pub use joint::{JointModel, JointTable, SubState};
pub use state::{FORMAT as STATE_FORMAT, VERSION as STATE_VERSION};
pub use stress::InitialStress;
pub use water::{opened_polygon, Water, WetJoint, OPENED_JOINT_COS, OPENED_JOINT_WIDTH};

/// The default update tolerance of touching pairs, as a fraction of their detection gap
/// ([`Simulation::set_update_fraction`]; docs/mechanics.md, "Carried contacts"): 0, every
/// touching pair queried at every step one of its bodies moves. Exact, and what restart files
/// resume bit for bit (a carried contact's query geometry is not in the file);
/// [`FAST_UPDATE_FRACTION`] trades that for speed.
pub const DEFAULT_UPDATE_FRACTION: f64 = 0.0;

/// The update fraction of fast runs (the mechanics benchmark's): touching pairs carried with
/// their bodies until they have moved a tenth of the detection gap.
pub const FAST_UPDATE_FRACTION: f64 = 0.1;

use crate::block::{readable, ConvexBlock, Pose, Prefetch, MAX_COORDINATE};
use crate::body::BodyError;
use crate::classify::PairResult;
use crate::contact::Detector;
use crate::generation::{JointRecord, SetRecord};
use crate::geometry::DVec3;
use crate::system::{
    deadline, edge_certificate, holds, separation, BlockSystem, BroadPhase, WideBoxes,
    EDGE_CERTIFICATE_STEPS, SIZE_GROWTH, TRAVEL_SLACK,
};
use crate::tolerance::{Tolerance, ToleranceError};
use contacts::{build_contact, counts_and_previous, Carry, Found, OpenCert, Scratch, StepInput};
use glam::DQuat;
use rayon::prelude::*;
use std::collections::BTreeSet;
use std::time::Instant;
use thiserror::Error;

mod bolts;
pub use bolts::{Bolt, BoltElement, BoltState, Bolts, Dowel};

/// Why a simulation cannot be set up or stepped.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum MechanicsError {
    /// A stiffness that is zero, negative or not finite.
    #[error("joint stiffness `{name}` must be a finite number > 0, got {value}")]
    Stiffness {
        /// Which stiffness.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A friction angle outside [0°, 90°).
    #[error("the friction angle must be in [0, 90) degrees, got {0}")]
    Friction(f64),
    /// A cohesion or tensile strength that is negative or not finite.
    #[error("joint `{name}` must be a finite number >= 0, got {value}")]
    Strength {
        /// Which strength.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A density that is not a finite number > 0.
    #[error("the density must be a finite number > 0, got {0}")]
    Density(f64),
    /// A damping coefficient out of range.
    #[error("damping `{name}` must be {range}, got {value}")]
    Damping {
        /// Which coefficient.
        name: &'static str,
        /// Its range.
        range: &'static str,
        /// The value given.
        value: f64,
    },
    /// A parameter out of range.
    #[error("`{name}` must be {range}, got {value}")]
    Parameter {
        /// Which parameter.
        name: &'static str,
        /// Its range.
        range: &'static str,
        /// The value given.
        value: f64,
    },
    /// A time step that is not positive, or above the critical one.
    #[error(
        "the time step {dt} is not in (0, {critical}] (the critical time step, with viscous \
         damping's bound when there is some)"
    )]
    TimeStep {
        /// The step given.
        dt: f64,
        /// The critical step.
        critical: f64,
    },
    /// A time step below [`MIN_STEP_FRACTION`] of the undamped critical step: given
    /// ([`Simulation::set_timestep`]), or the automatic one lowered that far by the safety
    /// factor or viscous damping. A run would take more than 2^52 times the steps the
    /// stiffness needs (`set_timestep(Some(1e-300))` was taken: `run_until(1.0)` never ended).
    #[error("{}", small_step_text(*.dt, *.smallest, *.given, *.safety, *.viscous))]
    TimeStepTooSmall {
        /// The step.
        dt: f64,
        /// The smallest allowed: [`MIN_STEP_FRACTION`] times the undamped critical step.
        smallest: f64,
        /// Whether the step was given (else the automatic one).
        given: bool,
        /// The safety factor.
        safety: f64,
        /// The viscous damping rate.
        viscous: f64,
    },
    /// Every body is fixed or prescribed: nothing to solve.
    #[error("no free body: every body is fixed or has a prescribed velocity")]
    NoFreeBody,
    /// A NaN or infinite value.
    #[error("{0} has a NaN or infinite component")]
    NotFinite(&'static str),
    /// A body id out of range.
    #[error("no body {id}: the simulation has {bodies} bodies")]
    UnknownBody {
        /// The id given.
        id: usize,
        /// Number of bodies.
        bodies: usize,
    },
    /// Two bodies overlap deeper than the detection gap: at the first detection, in the input
    /// (`initial`); later, because the contact law let one into the other.
    #[error("{}", penetration_text(*.bodies, *.step, *.depth, *.gap, *.initial))]
    Penetration {
        /// The two bodies.
        bodies: [u32; 2],
        /// The step.
        step: u64,
        /// How deep they overlap: the shortest translation that separates the two parts
        /// found (`overlap::overlap`); `None` where it finds none (never, for a pair the
        /// detection finds penetrating).
        depth: Option<f64>,
        /// The detection gap of the pair (absolute).
        gap: f64,
        /// Whether it was found by the first detection, before any contact force acted: the
        /// bodies overlap in the input.
        initial: bool,
    },
    /// A body that was excavated cannot be fixed, freed, moved, loaded or excavated again.
    #[error("body {0} was excavated: it can no longer be fixed, freed, moved or loaded")]
    Removed(usize),
    /// An initial stress set after the first step (it is installed by the first one).
    #[error("initial stresses are installed by the first step: set them before it")]
    InitialStressTooLate,
    /// A block cannot be made a body.
    #[error("block {0} cannot be a body: {1}")]
    Body(usize, BodyError),
    /// A rock bolt that cannot be installed (outside the rock, tying nothing).
    #[error("{0}")]
    Bolt(String),
    /// A bad detection tolerance.
    #[error("{0}")]
    Tolerance(#[from] ToleranceError),
    /// A joint set the simulation has no face of (and that is no entry of its system's
    /// generation spec): properties given for it would reach no contact.
    #[error("no joint set {set}: {known}")]
    UnknownSet {
        /// The set given.
        set: u32,
        /// The sets the simulation has, in words.
        known: String,
    },
    /// A simulation of a block system without blocks.
    #[error("the block system has no blocks")]
    NoBlocks,
    /// A density that gives a body a mass or a principal moment of inertia that is not a
    /// finite number > 0 (beyond double precision's range).
    #[error(
        "body {body}: the density {} gives it a mass of {} (largest principal moment of \
         inertia {}), not a finite number > 0 in double precision; give the density (or the \
         lengths) in other units",
        readable(.density), readable(.mass), readable(.moment)
    )]
    Mass {
        /// The body.
        body: usize,
        /// The density given.
        density: f64,
        /// Its mass at that density.
        mass: f64,
        /// Its largest principal moment of inertia at that density.
        moment: f64,
    },
    /// A pose or velocity out of the range the detection works in
    /// ([`Simulation::set_pose`], [`Simulation::set_velocity`]).
    #[error("{}", out_of_range_text(*.body, .what, *.magnitude, *.limit))]
    OutOfRange {
        /// The body.
        body: usize,
        /// `"pose"` or `"velocity"`.
        what: &'static str,
        /// A pose: the largest coordinate magnitude a part of the body could have there; a
        /// velocity: the largest speed of a point of the body (`|v| + |ω| r`).
        magnitude: f64,
        /// The largest allowed.
        limit: f64,
    },
    /// A free body moved farther in one step than [`TRAVEL_LIMIT`] times its radius: at
    /// such a step it could pass through another body between two detections, unseen
    /// (docs/mechanics.md, "Travel in one step").
    #[error("{}", travel_text(*.body, *.step, *.travel, *.radius, *.dt))]
    Travel {
        /// The body (the smallest id of those that moved too far).
        body: u32,
        /// The step.
        step: u64,
        /// How far its points moved in the step (a bound: translation plus rotation).
        travel: f64,
        /// Its radius (the largest distance of its points from its centroid).
        radius: f64,
        /// The time step.
        dt: f64,
    },
}

/// The message of [`MechanicsError::TimeStepTooSmall`].
fn small_step_text(dt: f64, smallest: f64, given: bool, safety: f64, viscous: f64) -> String {
    let short = |x: f64| readable(&x).to_string();
    let cause = if given {
        "the step given (set_timestep)".to_string()
    } else {
        format!(
            "the automatic step, lowered by the safety factor {} and the viscous damping rate \
             {} (a rate β bounds the step by about 2 / β)",
            short(safety),
            short(viscous)
        )
    };
    format!(
        "the time step {} is below {}, 2^-52 of the undamped critical step (the rounding of \
         that step): a run would take more than 2^52 times the steps the stiffness needs and \
         might never end; it is {cause}",
        short(dt),
        short(smallest)
    )
}

/// The message of [`MechanicsError::OutOfRange`].
fn out_of_range_text(body: usize, what: &str, magnitude: f64, limit: f64) -> String {
    let short = |x: f64| readable(&x).to_string();
    if what == "pose" {
        return format!(
            "the pose of body {body} places it too far: its coordinates could reach {} in \
             magnitude, beyond {}, the most at which double precision keeps its closest \
             vertices distinct (and at most 1e50)",
            short(magnitude),
            short(limit)
        );
    }
    format!(
        "the {what} of body {body} moves its points at up to {} per unit of time, beyond {}, \
         the largest coordinate a block may have: within a unit of time it would leave the \
         range of coordinates",
        short(magnitude),
        short(limit)
    )
}

/// The message of [`MechanicsError::Travel`].
fn travel_text(body: u32, step: u64, travel: f64, radius: f64, dt: f64) -> String {
    let short = |x: f64| {
        let rounded = format!("{x:.2e}").parse().unwrap_or(x);
        crate::geometry::Short(rounded).to_string()
    };
    format!(
        "body {body} moved up to {} in one step (step {step}, time step {}), more than {} of \
         its radius ({}): at such a step a body can pass through another between two \
         detections, unseen; the joints are likely too soft for the time step (the automatic \
         step grows as the square root of mass over stiffness: very small kn and ks, or \
         stiffness in other units than the lengths and masses, give steps of seconds); raise \
         kn and ks, or set a smaller time step",
        short(travel),
        short(dt),
        TRAVEL_LIMIT,
        short(radius)
    )
}

/// The message of [`MechanicsError::Penetration`].
fn penetration_text(
    [a, b]: [u32; 2],
    step: u64,
    depth: Option<f64>,
    gap: f64,
    initial: bool,
) -> String {
    // Three significant digits, as people write them.
    let short = |x: f64| {
        let rounded = format!("{x:.2e}").parse().unwrap_or(x);
        crate::geometry::Short(rounded).to_string()
    };
    let by = depth.map_or(String::new(), |d| format!(" by {}", short(d)));
    if initial {
        return format!(
            "bodies {a} and {b} overlap in the input{by}, deeper than the detection gap ({}), \
             before any contact force has acted: the blocks given must not overlap; move or \
             cut them so that they touch or lie apart (an overlap within the gap is taken as \
             a touching contact), or give them as one body",
            short(gap)
        );
    }
    format!(
        "bodies {a} and {b} overlap{by}, deeper than the detection gap ({}), at step {step}: \
         the contact law let one into the other (an impact or a load too large for the \
         stiffness, e.g. an undamped block rocking onto an edge); raise kn and ks, add local \
         damping (0.8 for a quasi-static run) or widen the gap; a smaller time step helps only \
         when a body moves more than the gap in one step",
        short(gap)
    )
}

/// What [`Simulation::solve`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveReport {
    /// Steps taken.
    pub steps: u64,
    /// The unbalanced-force ratio at the end.
    pub ratio: f64,
    /// Whether the ratio fell below the target.
    pub converged: bool,
}

/// Cumulative wall time of each part of [`Simulation::step`], in seconds, since the
/// simulation was made (or [`Simulation::reset_timings`]): one clock reading per part and
/// step, none per pair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepTimings {
    /// Candidate pairs: the check of the bodies' travel, and the broad phase when rebuilt.
    pub pairs: f64,
    /// The pair queries (contacts, types, features, geometry).
    pub detect: f64,
    /// Sub-contacts: geometry, matching to the last step's, joint law.
    pub contacts: f64,
    /// The sums of the contact forces and moments per body.
    pub forces: f64,
    /// Damping and integration of every body.
    pub integration: f64,
    /// Placing the moving bodies' parts at their new poses.
    pub placement: f64,
    /// Steps timed.
    pub steps: u64,
    /// Broad phases built.
    pub rebuilds: u64,
    /// Candidate pairs queried, summed over the steps.
    pub queried: u64,
    /// Candidate pairs whose two bodies had not moved since their last query (answer kept).
    pub unmoved: u64,
    /// Candidate pairs certified separated (answer kept).
    pub certified: u64,
    /// Touching pairs carried: their contact geometry moved with the bodies, not queried
    /// (their relative motion since the query below the update tolerance).
    pub carried: u64,
    /// Of the carried pairs, the dormant ones: open contacts certified to stay open, whose
    /// sub-contacts were kept rather than updated.
    pub dormant: u64,
}

impl StepTimings {
    /// The sum of the parts.
    pub fn total(&self) -> f64 {
        self.pairs + self.detect + self.contacts + self.forces + self.integration + self.placement
    }
}

/// A rigid-block simulation: bodies, joint properties, contacts and the time stepping.
#[derive(Clone, Debug)]
pub struct Simulation {
    bodies: Bodies,
    /// Per block of the system it was made of, its body (`from_bodies`: per part, in body
    /// order); a body held by rock bridges is several bodies (`Bodies::of_system`).
    block_bodies: Vec<u32>,
    /// Per convex part: its body and its index among the body's parts.
    part_body: Vec<u32>,
    part_index: Vec<u32>,
    /// The parts placed at their bodies' poses (a cache for the detection).
    placed: Vec<ConvexBlock>,
    /// Per part, whether its placed copy is complete: the data only the pair query reads
    /// (clearance, local coordinates) derived from its current coordinates. A moved part's
    /// coordinates are placed at every step; the rest only when a pair of it is queried
    /// (docs/mechanics.md, "Placing the moved bodies").
    complete: Vec<bool>,
    /// The joint sets of the simulation: the sets of its bodies' joint and rock-bridge faces
    /// and, for a simulation of a generated system, every entry of its spec (an entry may
    /// cut no block). Properties for another set are refused ([`Simulation::check_set`]).
    sets: BTreeSet<u32>,
    joints: JointTable,
    water: Water,
    bridges: BridgeTable,
    gravity: DVec3,
    damping: Damping,
    tolerance: Tolerance,
    point_width: f64,
    /// The point width of the last step's contacts (its bits; `None` before the first step
    /// and after a restart): while it is unchanged, a contact built from the same answer as
    /// at the last step keeps its area shares ([`contacts::build_contact`]).
    shares_width: Option<u64>,
    skin: f64,
    pairs: Vec<[u32; 2]>,
    /// Per candidate pair, its last query's answer (docs/mechanics.md, "Contact updates").
    memo: Vec<PairMemo>,
    /// Per candidate pair, where its certificate was made (when it has one): a separated
    /// pair's, or a dormant contact's.
    frames: Vec<Frame>,
    /// One bit per candidate pair, set where its frame may be a dormant contact's
    /// (`Frame::Open`; clear: it is not). The step's test of every carried contact and the
    /// contact update read a pair's frame only where its bit is set: the frames take 120
    /// bytes each, and reading every carried contact's was a cache line per contact and
    /// step (docs/mechanics.md, "The sub-contact update").
    open_frames: Vec<u64>,
    /// Per body: the step whose detection first sees its current pose (the pose last changed
    /// in any bit in the step before), the sum of the bounds of its motions (travel), and
    /// the bound of its last step's motion.
    moved_at: Vec<u64>,
    travel: Vec<f64>,
    last_step: Vec<f64>,
    /// Whether every candidate pair is queried every step (no answer kept).
    full_detection: bool,
    /// The update tolerance, a fraction of each pair's detection gap (docs/mechanics.md,
    /// "Carried contacts").
    update_fraction: f64,
    /// Whether carried open contacts may stay dormant (docs/mechanics.md, "Dormant
    /// contacts").
    dormancy: bool,
    built_at: Option<Vec<Pose>>,
    /// Whether a body has moved more than half the skin from its pose at the last build of
    /// the candidate pairs (`update_pairs`' test, evaluated by the integration for each body
    /// it moves and at the build for every body).
    skin_passed: bool,
    contacts: Contacts,
    /// The buffers of the contacts of the step before last, refilled in place by the next
    /// step's contacts: at 10^5 blocks a step's contacts take hundreds of megabytes, which
    /// fresh allocations would take from the system page by page at every step (no state:
    /// its contents are never read).
    spare: Contacts,
    /// The list of the step's contacts before they are built ([`gather_contacts`]), kept
    /// from step to step for the same reason: at 10^5 blocks it takes some 30 MB.
    current: Vec<contacts::Current>,
    /// Per body, the sum of its contact forces and moments (about the centroid) last step.
    forces: Vec<DVec3>,
    moments: Vec<DVec3>,
    /// Rock bolts (docs/mechanics.md, "Rock bolts and applied loads").
    bolts: Bolts,
    /// Applied moments (world frame), per body that has one.
    applied_moments: std::collections::BTreeMap<u32, DVec3>,
    dt: Option<f64>,
    safety: f64,
    time: f64,
    steps: u64,
    ratio: f64,
    /// Whose velocities are at the whole step (just set): their next kick is a half one.
    synced: Synced,
    /// Whether the next detection is the first: its contacts are bonded.
    initial: bool,
    /// Bodies removed and the loads they leave relaxing (`excavation.rs`).
    excavation: excavation::Excavation,
    /// The stress installed on the first detection's contacts (`stress.rs`).
    initial_stress: Option<InitialStress>,
    /// The wet joints: the face-face contacts carrying water, and the joints they left
    /// when their faces opened beyond the detection gap (`water.rs`, [`WetJoint`]).
    wet: Vec<WetJoint>,
    /// Whether mass scaling is on ([`Simulation::set_mass_scaling`]; the factors are the
    /// bodies').
    mass_scaling: bool,
    /// What the simulation keeps of the system it was made of besides its blocks, for
    /// restart files and the system of a loaded simulation (empty for `from_bodies`).
    origin: SystemLabels,
    timings: StepTimings,
}

/// The labels of the system a simulation was made of ([`Simulation::new`]): the entries of
/// its generation spec (their name and kind; a face's joint set is an index into them), its
/// joint table (a face's joint is an index into it), its length unit and its body ids (per
/// block, [`BlockSystem::body_ids`]). None of them takes part in a step; a restart file
/// keeps them (absent in files written before 2026-11-29: all empty or `None`). Not the
/// domain.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SystemLabels {
    /// One record per spec entry (empty: not known).
    pub sets: Vec<SetRecord>,
    /// The joint table ([`BlockSystem::joints`]; empty: not known, or none).
    pub joints: Vec<JointRecord>,
    /// The length unit (`None`: not named, or not known).
    pub unit: Option<String>,
    /// Per block, its body id in the system (empty: not known).
    pub body_ids: Vec<u32>,
}

impl Simulation {
    /// A simulation of `system`'s blocks, one body each (a concave block, parts sharing a
    /// body id, is one rigid body of its parts unless rock bridges hold them:
    /// [`Bodies::from_system`], bodies in the order of their first block;
    /// [`Simulation::block_bodies`] maps blocks to bodies), all of density `density`, free and at rest, with the default joint model,
    /// gravity `(0, 0, -9.81)`, no damping, a detection gap of 1e-3 (relative), point
    /// contacts 0.2 of the smaller body's diameter wide and the automatic time step.
    pub fn new(system: &BlockSystem, density: f64) -> Result<Simulation, MechanicsError> {
        if system.is_empty() {
            return Err(MechanicsError::NoBlocks);
        }
        let (bodies, block_bodies) = Bodies::of_system(system, density)?;
        let mut sim = Simulation::from_bodies(bodies);
        sim.block_bodies = block_bodies;
        sim.sets.extend(0..system.sets().len() as u32);
        sim.origin = SystemLabels {
            sets: system.sets().to_vec(),
            joints: system.joints().to_vec(),
            unit: system.unit().map(str::to_string),
            body_ids: system.body_ids(),
        };
        Ok(sim)
    }

    /// A simulation of the given bodies (settings as [`Simulation::new`]).
    pub fn from_bodies(bodies: Bodies) -> Simulation {
        let mut part_body = Vec::new();
        let mut part_index = Vec::new();
        let mut placed = Vec::new();
        let mut sets = BTreeSet::new();
        for b in 0..bodies.len() {
            for (k, part) in bodies.shape(b).parts().iter().enumerate() {
                sets.extend(part.face_origins().iter().filter_map(|o| o.set()));
                part_body.push(b as u32);
                part_index.push(k as u32);
                let mut p = part.clone();
                p.place_from(part, &bodies.pose[b]);
                placed.push(p);
            }
        }
        let mean_size =
            placed.iter().map(ConvexBlock::size).sum::<f64>() / placed.len().max(1) as f64;
        let n = bodies.len();
        Simulation {
            bodies,
            block_bodies: part_body.clone(),
            part_body,
            part_index,
            complete: vec![true; placed.len()],
            placed,
            sets,
            joints: JointTable::default(),
            water: Water::none(),
            bridges: BridgeTable::default(),
            gravity: DVec3::new(0.0, 0.0, -9.81),
            damping: Damping::default(),
            tolerance: Tolerance::with_gap(1e-3).expect("a valid gap"),
            point_width: 0.2,
            shares_width: None,
            skin: 0.05 * mean_size,
            pairs: Vec::new(),
            memo: Vec::new(),
            frames: Vec::new(),
            open_frames: Vec::new(),
            moved_at: vec![0; n],
            travel: vec![0.0; n],
            last_step: vec![0.0; n],
            full_detection: false,
            update_fraction: DEFAULT_UPDATE_FRACTION,
            dormancy: true,
            built_at: None,
            skin_passed: false,
            contacts: Contacts::default(),
            spare: Contacts::default(),
            current: Vec::new(),
            forces: vec![DVec3::ZERO; n],
            moments: vec![DVec3::ZERO; n],
            bolts: Bolts::default(),
            applied_moments: Default::default(),
            dt: None,
            safety: 0.5,
            time: 0.0,
            steps: 0,
            ratio: f64::INFINITY,
            synced: Synced::All,
            initial: true,
            excavation: excavation::Excavation::default(),
            initial_stress: None,
            wet: Vec::new(),
            mass_scaling: false,
            origin: SystemLabels::default(),
            timings: StepTimings::default(),
        }
    }

    // ---- settings -------------------------------------------------------------------

    /// The bodies and their state.
    pub fn bodies(&self) -> &Bodies {
        &self.bodies
    }

    /// Per block of the system the simulation was made of ([`Simulation::new`]), the body it
    /// is a part of: the bodies are not the system's bodies when rock bridges hold some of
    /// them (docs/mechanics.md, "Rock bridges"). For [`Simulation::from_bodies`], per part in
    /// body order.
    pub fn block_bodies(&self) -> &[u32] {
        &self.block_bodies
    }

    /// The body of block `block` of the system ([`Simulation::block_bodies`]); `None` for no
    /// such block.
    pub fn body_of_block(&self, block: usize) -> Option<u32> {
        self.block_bodies.get(block).copied()
    }

    /// What the simulation keeps of the system it was made of: its spec entries, unit and
    /// body ids ([`SystemLabels`]; empty for [`Simulation::from_bodies`], or for one read
    /// from a restart file written before they were kept).
    pub fn system_labels(&self) -> &SystemLabels {
        &self.origin
    }

    /// The contacts and sub-contacts of the last step: those of the candidate pairs, pairs
    /// of bodies of which at least one is free. Two bodies neither of which is free (fixed
    /// or with a prescribed velocity) have no contact here, however they touch (their forces
    /// would move nothing; docs/mechanics.md, "Integration"): a full detection of
    /// [`Simulation::placed_system`] finds these pairs' contacts too, this list does not.
    pub fn contacts(&self) -> &Contacts {
        &self.contacts
    }

    /// The joint properties.
    pub fn joints(&self) -> &JointTable {
        &self.joints
    }

    /// Sets the default joint model.
    pub fn set_default_joint(&mut self, model: JointModel) -> Result<(), MechanicsError> {
        self.joints.set_default(model)
    }

    /// The joint sets the simulation has: those of its bodies' joint and rock-bridge faces,
    /// every entry of the generation spec of the system it was made of ([`Simulation::new`];
    /// an entry may cut no block), and the sets given joint, bridge or water properties
    /// already (a simulation read from a restart file keeps its sets so).
    pub fn joint_sets(&self) -> BTreeSet<u32> {
        let mut sets = self.sets.clone();
        sets.extend(self.joints.sets().map(|(s, _)| s));
        sets.extend(self.bridges.sets().map(|(s, _)| s));
        sets.extend(self.water.sets.keys().copied());
        sets
    }

    /// Whether `set` is one of the simulation's joint sets ([`Simulation::joint_sets`]):
    /// else an error naming it and the sets there are. The setters do not ask (a set without
    /// faces is harmless to the step: its properties reach no contact); the Python bindings
    /// do, so that a mistyped set id is not silently a set of default properties.
    pub fn check_set(&self, set: u32) -> Result<(), MechanicsError> {
        let sets = self.joint_sets();
        if sets.contains(&set) {
            return Ok(());
        }
        let known = match sets.len() {
            0 => "the block system has no joint sets (no block face is on a joint)".to_string(),
            _ => {
                let ids: Vec<String> = sets.iter().map(u32::to_string).collect();
                format!("the block system's joint sets are {}", ids.join(", "))
            }
        };
        Err(MechanicsError::UnknownSet { set, known })
    }

    /// Sets the joint model of joint set `set`.
    pub fn set_joint(&mut self, set: u32, model: JointModel) -> Result<(), MechanicsError> {
        self.joints.set(set, model)
    }

    /// The water in the joints.
    pub fn water(&self) -> &Water {
        &self.water
    }

    /// Sets the water in the joints (docs/mechanics.md, "Water pressure in the joints").
    pub fn set_water(&mut self, water: Water) {
        self.water = water;
    }

    /// The rock-bridge properties (docs/mechanics.md, "Rock bridges").
    pub fn bridges(&self) -> &BridgeTable {
        &self.bridges
    }

    /// Sets the intact rock's properties for the bridges of joint set `set` (contacts over
    /// faces of origin `Bridge { set, .. }`).
    pub fn set_bridge(&mut self, set: u32, model: JointModel) -> Result<(), MechanicsError> {
        self.bridges.set(set, model)
    }

    /// Sets the default bridge model (bridges of sets without their own).
    pub fn set_default_bridge(&mut self, model: JointModel) -> Result<(), MechanicsError> {
        self.bridges.set_default(model)
    }

    /// The largest contact stiffness any model can give (joints and bridges).
    fn max_stiffness(&self) -> f64 {
        self.joints
            .max_stiffness()
            .max(self.bridges.max_stiffness())
    }

    /// Gravity (acceleration vector).
    pub fn gravity(&self) -> DVec3 {
        self.gravity
    }

    /// Sets gravity.
    pub fn set_gravity(&mut self, g: DVec3) -> Result<(), MechanicsError> {
        if !g.is_finite() {
            return Err(MechanicsError::NotFinite("gravity"));
        }
        self.gravity = g;
        Ok(())
    }

    /// The damping.
    pub fn damping(&self) -> Damping {
        self.damping
    }

    /// Sets the damping: local in [0, 1), viscous ≥ 0.
    pub fn set_damping(&mut self, damping: Damping) -> Result<(), MechanicsError> {
        if !(damping.local.is_finite() && (0.0..1.0).contains(&damping.local)) {
            return Err(MechanicsError::Damping {
                name: "local",
                range: "in [0, 1)",
                value: damping.local,
            });
        }
        if !(damping.viscous.is_finite() && damping.viscous >= 0.0) {
            return Err(MechanicsError::Damping {
                name: "viscous",
                range: "a finite number >= 0",
                value: damping.viscous,
            });
        }
        self.set_if_step_kept(|sim| &mut sim.damping, damping)
    }

    /// Sets the detection gap (relative to block size, as [`Tolerance::with_gap`]): the
    /// deepest overlap the contacts can carry, in `(0, 0.01)` (both ends excluded). A gap of
    /// 0 is refused: a soft contact carries its force by overlapping, and an overlap deeper
    /// than the gap stops the run, so with no gap no contact could carry a load (the first
    /// resting contact would stop it). Other values out of range are a
    /// [`MechanicsError::Tolerance`].
    pub fn set_gap(&mut self, gap: f64) -> Result<(), MechanicsError> {
        if gap == 0.0 {
            return Err(MechanicsError::Parameter {
                name: "gap",
                range: "in (0, 0.01), both ends excluded (a soft contact carries its force \
                        by overlapping, and an overlap deeper than the gap stops the run: a \
                        gap of 0 can carry no load, the first resting contact would stop the \
                        run; the default 1e-3 suits most models)",
                value: gap,
            });
        }
        self.tolerance = Tolerance::with_gap(gap)?;
        self.built_at = None;
        Ok(())
    }

    /// Sets the width of point contacts relative to the smaller block's size (in (0, 1]).
    /// A contact of edges or vertices where two joints cross bears only past half the
    /// detection gap of overlap (docs/mechanics.md, "Where joints cross").
    pub fn set_point_width(&mut self, width: f64) -> Result<(), MechanicsError> {
        if !(width.is_finite() && width > 0.0 && width <= 1.0) {
            return Err(MechanicsError::Parameter {
                name: "point_width",
                range: "in (0, 1]",
                value: width,
            });
        }
        self.point_width = width;
        Ok(())
    }

    /// Sets the density of body `i` (its mass and inertia follow; its velocities stay).
    pub fn set_density(&mut self, i: usize, density: f64) -> Result<(), MechanicsError> {
        self.bodies.set_density(i, density)
    }

    /// Fixes body `i`: it no longer moves.
    pub fn fix(&mut self, i: usize) -> Result<(), MechanicsError> {
        self.set_fixity(i, Fixity::Fixed)
    }

    /// Frees body `i`, fixed or moving at a prescribed velocity, at rest at the current
    /// time (as [`Simulation::set_velocity`] with zeros: its next step starts with a half
    /// kick). A body already free is left as it is, moving on (a boundary condition set
    /// on some bodies does not stop the others).
    pub fn free(&mut self, i: usize) -> Result<(), MechanicsError> {
        self.check_present(i)?;
        if self.bodies.fixities()[i] == Fixity::Free {
            return Ok(());
        }
        self.set_fixity(i, Fixity::Free)?;
        self.bodies.set_velocity(i, DVec3::ZERO, DVec3::ZERO)?;
        self.synced.add(i);
        Ok(())
    }

    /// Gives body `i` a prescribed velocity and spin (world frame). A velocity or spin not
    /// finite is a [`MechanicsError::NotFinite`]; one that moves a point of the body faster
    /// than [`MAX_COORDINATE`] per unit of time a [`MechanicsError::OutOfRange`] (as
    /// [`Simulation::set_velocity`]).
    pub fn prescribe(
        &mut self,
        i: usize,
        velocity: DVec3,
        spin: DVec3,
    ) -> Result<(), MechanicsError> {
        if !(velocity.is_finite() && spin.is_finite()) {
            return Err(MechanicsError::NotFinite("prescribed velocity"));
        }
        self.check_speed(i, velocity, spin)?;
        self.set_fixity(i, Fixity::Prescribed { velocity, spin })
    }

    fn set_fixity(&mut self, i: usize, fixity: Fixity) -> Result<(), MechanicsError> {
        self.check_present(i)?;
        self.bodies.set_fixity(i, fixity)?;
        self.built_at = None; // the pairs kept depend on which bodies move
        Ok(())
    }

    /// Sets the velocity and spin of free body `i` at the current time (its next step
    /// starts with a half kick; the other bodies' velocities stay the leapfrog's half-step
    /// values, and their next kick is a whole one).
    ///
    /// A velocity or spin not finite is a [`MechanicsError::NotFinite`]; one that moves a
    /// point of the body faster than [`MAX_COORDINATE`] (1e50, the largest coordinate a
    /// block may have) per unit of time, `|v| + |ω| r > 1e50` with `r` the body's radius, a
    /// [`MechanicsError::OutOfRange`]: such a body leaves the range of coordinates within
    /// a unit of time. (A slower one that moves more than [`TRAVEL_LIMIT`] of its radius in
    /// a step is refused by the step: [`MechanicsError::Travel`].)
    pub fn set_velocity(
        &mut self,
        i: usize,
        velocity: DVec3,
        spin: DVec3,
    ) -> Result<(), MechanicsError> {
        self.check_present(i)?;
        if velocity.is_finite() && spin.is_finite() {
            self.check_speed(i, velocity, spin)?;
        }
        self.bodies.set_velocity(i, velocity, spin)?;
        self.synced.add(i);
        Ok(())
    }

    /// Sets a constant force on body `i`'s centroid, besides gravity and contacts.
    pub fn apply_force(&mut self, i: usize, force: DVec3) -> Result<(), MechanicsError> {
        self.check_present(i)?;
        self.bodies.set_applied(i, force)
    }

    /// Sets a constant moment on body `i` (world frame), besides its contacts' (a dead
    /// load: it does not turn with the body).
    pub fn apply_moment(&mut self, i: usize, moment: DVec3) -> Result<(), MechanicsError> {
        self.check_present(i)?;
        if !moment.is_finite() {
            return Err(MechanicsError::NotFinite("applied moment"));
        }
        if moment == DVec3::ZERO {
            self.applied_moments.remove(&(i as u32));
        } else {
            self.applied_moments.insert(i as u32, moment);
        }
        Ok(())
    }

    /// Sets a constant force on body `i` acting at `point` (world, at the body's current
    /// pose): the force on its centroid ([`Simulation::apply_force`]) and its moment about
    /// the centroid ([`Simulation::apply_moment`]), both constant in the world frame after.
    pub fn apply_force_at(
        &mut self,
        i: usize,
        force: DVec3,
        point: DVec3,
    ) -> Result<(), MechanicsError> {
        self.bodies.check(i)?;
        if !point.is_finite() {
            return Err(MechanicsError::NotFinite("point of the applied force"));
        }
        let arm = point - self.bodies.poses()[i].translation;
        self.apply_force(i, force)?;
        self.apply_moment(i, arm.cross(force))
    }

    /// The applied moments: `(body, moment)` for each body that has one.
    pub fn applied_moments(&self) -> impl Iterator<Item = (usize, DVec3)> + '_ {
        self.applied_moments.iter().map(|(&i, &m)| (i as usize, m))
    }

    /// Installs a rock bolt across the bodies its segment crosses now (docs/mechanics.md,
    /// "Rock bolts"); its id. An error when the segment meets no body or one only, or
    /// crosses or ends in an excavated body (excavated rock before the first body that stays
    /// is the opening the collar is in, and is skipped).
    pub fn add_bolt(&mut self, bolt: Bolt) -> Result<usize, MechanicsError> {
        let removed = &self.excavation.removed;
        self.bolts
            .install(bolt, &self.bodies, &self.placed, &self.part_body, removed)
    }

    /// The rock bolts and the state of their elements.
    pub fn bolts(&self) -> &Bolts {
        &self.bolts
    }

    /// Sets body `i`'s pose: the map from the body's own frame (origin at its centroid, axes
    /// its principal axes of inertia, the frame its shape is stored in) to the world, as
    /// [`Bodies::poses`] (docs/bodies.md). It is not a displacement of the block as given: a
    /// new simulation starts each body at the pose that places its shape where its block
    /// was, `(principal axes, centroid)`, so `Pose::new(DQuat::IDENTITY, c)` turns a block
    /// whose principal axes are not the world's. The rotation is normalised. The pose must
    /// keep the body clear of the others by the gap (an overlap deeper is a
    /// [`MechanicsError::Penetration`] at the next step).
    ///
    /// # Errors
    ///
    /// [`MechanicsError::NotFinite`] for a NaN or infinite component or a zero rotation;
    /// [`MechanicsError::OutOfRange`] for a pose that places a part of the body where double
    /// precision no longer holds it (the rule of [`ContactTracker::update`]: coordinates
    /// beyond the magnitude at which its closest vertices stay distinct, at most 1e50);
    /// [`MechanicsError::UnknownBody`] or [`MechanicsError::Removed`] for a body that is
    /// not there.
    ///
    /// [`ContactTracker::update`]: crate::system::ContactTracker::update
    pub fn set_pose(&mut self, i: usize, pose: Pose) -> Result<(), MechanicsError> {
        self.check_present(i)?;
        let pose =
            Pose::new(pose.rotation, pose.translation).ok_or(MechanicsError::NotFinite("pose"))?;
        for part in self.bodies.shape(i).parts() {
            let reach = crate::block::Reach::of(part);
            if !reach.admits(&pose) {
                return Err(MechanicsError::OutOfRange {
                    body: i,
                    what: "pose",
                    magnitude: reach.magnitude_at(&pose),
                    limit: reach.limit.max(reach.home),
                });
            }
        }
        self.bodies.pose[i] = pose;
        self.place_body(i);
        self.built_at = None;
        Ok(())
    }

    /// Whether the points of body `i` move at most [`MAX_COORDINATE`] per unit of time at
    /// this velocity and spin (finite).
    fn check_speed(&self, i: usize, velocity: DVec3, spin: DVec3) -> Result<(), MechanicsError> {
        self.bodies.check(i)?;
        // Lengths scaled by the largest component: 1e200 is 1e200, not an overflowed square.
        let length = |v: DVec3| {
            let big = v.abs().max_element();
            if big > 0.0 {
                big * (v / big).length()
            } else {
                0.0
            }
        };
        let speed = length(velocity) + length(spin) * self.bodies.shape(i).radius();
        if speed <= MAX_COORDINATE {
            return Ok(());
        }
        Err(MechanicsError::OutOfRange {
            body: i,
            what: "velocity",
            magnitude: speed,
            limit: MAX_COORDINATE,
        })
    }

    /// Body `i` exists and was not excavated.
    fn check_present(&self, i: usize) -> Result<(), MechanicsError> {
        self.bodies.check(i)?;
        if self.is_removed(i) {
            return Err(MechanicsError::Removed(i));
        }
        Ok(())
    }

    /// Sets the initial stress (`None`: none) that the first step installs on the contacts
    /// touching then (docs/mechanics.md, "Initial stresses"); an error after the first step.
    pub fn set_initial_stress(
        &mut self,
        stress: Option<InitialStress>,
    ) -> Result<(), MechanicsError> {
        if !self.initial {
            return Err(MechanicsError::InitialStressTooLate);
        }
        self.initial_stress = stress.map(InitialStress::validated).transpose()?;
        Ok(())
    }

    /// The initial stress set.
    pub fn initial_stress(&self) -> Option<&InitialStress> {
        self.initial_stress.as_ref()
    }

    /// With `on`, every candidate pair is queried at every step, as before the contact
    /// updates (docs/mechanics.md, "Contact updates"); off (the default), a pair whose two
    /// bodies have not moved since its last query, or that is certified separated, keeps its
    /// answer. Both give the same contacts, bit for bit: the switch is for comparisons.
    pub fn set_full_detection(&mut self, on: bool) {
        self.full_detection = on;
    }

    /// Whether every candidate pair is queried at every step.
    pub fn full_detection(&self) -> bool {
        self.full_detection
    }

    /// Sets the update tolerance of touching pairs, as a fraction of each pair's detection
    /// gap (absolute length): a touching pair is queried again once the motion bounds of its
    /// two bodies since its last query sum to more than `fraction × gap`, and its contact
    /// is carried with the bodies until then (docs/mechanics.md, "Carried contacts").
    /// `0` queries a touching pair at every step that moves one of its bodies.
    pub fn set_update_fraction(&mut self, fraction: f64) -> Result<(), MechanicsError> {
        if !(fraction.is_finite() && fraction >= 0.0) {
            return Err(MechanicsError::Parameter {
                name: "update fraction",
                range: "a finite number >= 0",
                value: fraction,
            });
        }
        self.update_fraction = fraction;
        Ok(())
    }

    /// The update tolerance of touching pairs, a fraction of their detection gap.
    pub fn update_fraction(&self) -> f64 {
        self.update_fraction
    }

    /// With `on` (the default), a carried contact between two faces, two edges or two vertices,
    /// open at every sub-contact, keeps its sub-contacts without updating them while a certificate
    /// shows that none can have closed (docs/mechanics.md, "Dormant contacts"): the forces and the
    /// motion are the same bit for bit, but its normal and its sub-contacts' points, gaps, areas
    /// and shear displacements are those of its last update (a shear displacement missed then stays
    /// missed). Only carried contacts can be dormant, so this changes nothing with an update
    /// fraction of 0 (the default), nor with water in the joints (certificates made before are not
    /// used once water is set or this is off). Off, for comparisons.
    pub fn set_dormant_contacts(&mut self, on: bool) {
        self.dormancy = on;
    }

    /// Whether carried open contacts may stay dormant.
    pub fn dormant_contacts(&self) -> bool {
        self.dormancy
    }

    /// Sets the time step; `None` for the automatic one (safety × critical). A step must be
    /// in `(0, critical]` ([`MechanicsError::TimeStep`]) and at least [`MIN_STEP_FRACTION`]
    /// of the undamped critical step ([`MechanicsError::TimeStepTooSmall`]: a step of 1e-300
    /// would make `run_until(1.0)` run for ever).
    pub fn set_timestep(&mut self, dt: Option<f64>) -> Result<(), MechanicsError> {
        if let Some(dt) = dt {
            let critical = self.critical_timestep()?;
            if !(dt.is_finite() && dt > 0.0 && dt <= critical) {
                return Err(MechanicsError::TimeStep { dt, critical });
            }
        }
        self.set_if_step_kept(|sim| &mut sim.dt, dt)
    }

    /// Sets the safety factor of the automatic time step (in (0, 1]; the step must stay at
    /// least [`MIN_STEP_FRACTION`] of the undamped critical one,
    /// [`MechanicsError::TimeStepTooSmall`]).
    pub fn set_safety(&mut self, safety: f64) -> Result<(), MechanicsError> {
        if !(safety.is_finite() && safety > 0.0 && safety <= 1.0) {
            return Err(MechanicsError::Parameter {
                name: "safety",
                range: "in (0, 1]",
                value: safety,
            });
        }
        self.set_if_step_kept(|sim| &mut sim.safety, safety)
    }

    /// Sets the setting `field` (of the time step) to `value`, unless the time step it gives
    /// is below its floor ([`Simulation::check_small_step`]): then the setting stays as it
    /// was, and the error says why.
    fn set_if_step_kept<V>(
        &mut self,
        field: fn(&mut Simulation) -> &mut V,
        value: V,
    ) -> Result<(), MechanicsError> {
        let old = std::mem::replace(field(self), value);
        let checked = self.check_small_step();
        if checked.is_err() {
            *field(self) = old;
        }
        checked
    }

    /// Whether the time step is at least [`MIN_STEP_FRACTION`] of the undamped critical
    /// step, where there is one now (no free body: nothing to check until there is).
    fn check_small_step(&self) -> Result<(), MechanicsError> {
        match self.timestep() {
            Err(e @ MechanicsError::TimeStepTooSmall { .. }) => Err(e),
            _ => Ok(()),
        }
    }

    /// Mass scaling for quasi-static runs (3DEC's density scaling): with `on`, each free body
    /// whose critical step is below the median of the free bodies' gets its inertia (mass and
    /// moments, not its weight) scaled up until its step is the median, so that slivers no
    /// longer set the time step. The equilibrium is the same; the motion towards it is not
    /// physical. Off: true inertia. Velocities and spins are kept.
    ///
    /// The factors are those of the free bodies and the joints' stiffness of the moment.
    /// While it is on, [`Simulation::excavate`] computes them again from the free bodies
    /// that stay (the removed ones, fixed, go back to 1), as 3DEC recomputes its density
    /// scaling when the model changes; after other changes of the free bodies, their
    /// densities or the joints' stiffness (`fix`, `free`, `prescribe`, `set_density`,
    /// `set_joint`, ...), call it again (docs/mechanics.md, "Mass scaling"). Whether it is
    /// on is kept in restart files. No free body: an error, and nothing changes.
    pub fn set_mass_scaling(&mut self, on: bool) -> Result<(), MechanicsError> {
        if !(0..self.bodies.len()).any(|i| self.bodies.is_free(i)) {
            return Err(MechanicsError::NoFreeBody);
        }
        self.mass_scaling = on;
        self.rescale();
        Ok(())
    }

    /// Whether mass scaling is on ([`Simulation::set_mass_scaling`]).
    pub fn mass_scaling(&self) -> bool {
        self.mass_scaling
    }

    /// Sets every body's mass-scaling factor by the rule of [`Simulation::set_mass_scaling`]
    /// (1 for all when it is off, or when no body is free).
    fn rescale(&mut self) {
        let k = self.max_stiffness();
        let mut steps: Vec<f64> = (0..self.bodies.len())
            .filter(|&i| self.bodies.is_free(i))
            .map(|i| integrate::critical_step(&self.bodies, i, k, 1.0))
            .collect();
        steps.sort_by(f64::total_cmp);
        let target = steps.get(steps.len() / 2).copied();
        for i in 0..self.bodies.len() {
            let scale = match (self.bodies.fixity(i), target) {
                (Fixity::Free, Some(target)) if self.mass_scaling => {
                    let own = integrate::critical_step(&self.bodies, i, k, 1.0);
                    (target / own).powi(2).max(1.0)
                }
                _ => 1.0,
            };
            self.bodies.set_scale(i, scale);
        }
    }

    /// The critical time step (docs/mechanics.md, "Integration"): the smallest bound of the
    /// free bodies, with their bolts, lowered for viscous damping (`integrate::damped_step`:
    /// a rate β above `2 / dt` makes the explicit step unstable, whatever the stiffness).
    pub fn critical_timestep(&self) -> Result<f64, MechanicsError> {
        self.undamped_timestep()
            .map(|undamped| integrate::damped_step(undamped, self.damping.viscous))
    }

    /// The critical time step without viscous damping's bound.
    fn undamped_timestep(&self) -> Result<f64, MechanicsError> {
        let k = self.max_stiffness();
        self.bodies
            .critical_timestep(k)
            .ok_or(MechanicsError::NoFreeBody)
            .map(|contacts| self.bolts.critical_step(&self.bodies, contacts))
    }

    /// The time step the next step takes: an error for a step given above the critical
    /// step ([`MechanicsError::TimeStep`], after the stiffness or damping changed), or
    /// below [`MIN_STEP_FRACTION`] of the undamped one
    /// ([`MechanicsError::TimeStepTooSmall`], after the stiffness changed).
    pub fn timestep(&self) -> Result<f64, MechanicsError> {
        let undamped = self.undamped_timestep()?;
        let critical = integrate::damped_step(undamped, self.damping.viscous);
        let dt = match self.dt {
            Some(dt) if dt > critical => return Err(MechanicsError::TimeStep { dt, critical }),
            Some(dt) => dt,
            None => self.safety * critical,
        };
        let smallest = MIN_STEP_FRACTION * undamped;
        if dt < smallest {
            return Err(MechanicsError::TimeStepTooSmall {
                dt,
                smallest,
                given: self.dt.is_some(),
                safety: self.safety,
                viscous: self.damping.viscous,
            });
        }
        Ok(dt)
    }

    /// Simulated time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The unbalanced-force ratio of the last step: the largest unbalanced force of a free
    /// body over the largest of its gravity plus applied force (infinite before a step).
    pub fn unbalanced_ratio(&self) -> f64 {
        self.ratio
    }

    /// The body of each part, in the order of the parts ([`Simulation::placed_system`]).
    pub fn part_bodies(&self) -> &[u32] {
        &self.part_body
    }

    /// The convex parts at the bodies' current poses, as a block system (for files and
    /// pictures; the parts of one body are consecutive).
    pub fn placed_system(&self) -> BlockSystem {
        let mut blocks = self.placed.clone();
        for (block, &complete) in blocks.iter_mut().zip(&self.complete) {
            if !complete {
                block.place_query_data();
            }
        }
        BlockSystem::new(blocks)
    }

    /// Per body, the sum of its contact and bolt forces at the last step.
    pub fn contact_forces(&self) -> &[DVec3] {
        &self.forces
    }

    /// The wet joints at the last step ([`WetJoint`], docs/mechanics.md "Water pressure in
    /// the joints"): the face-face contacts carrying water (`opened` false: their water is
    /// the contact's, [`Water::contact_forces`]) and the joints opened beyond the detection
    /// gap that keep their water (`opened` true, with its force), sorted by parts.
    pub fn wet_joints(&self) -> &[WetJoint] {
        &self.wet
    }

    /// Per body, the sum of the moments of its contact and bolt forces about its centroid,
    /// and of its applied moment.
    pub fn contact_moments(&self) -> &[DVec3] {
        &self.moments
    }

    /// The wall time spent in each part of the step so far.
    pub fn timings(&self) -> StepTimings {
        self.timings
    }

    /// Sets the timings to zero.
    pub fn reset_timings(&mut self) {
        self.timings = StepTimings::default();
    }

    // ---- running ----------------------------------------------------------------------

    /// One step: bodies at their poses -> contacts -> sub-contacts -> forces ->
    /// integration -> new poses (docs/mechanics.md, "One step").
    ///
    /// # Errors
    ///
    /// A step that fails is not undone (that would cost every step a copy of the state);
    /// what it leaves depends on where it failed:
    ///
    /// - the time step ([`MechanicsError::TimeStep`], [`MechanicsError::TimeStepTooSmall`],
    ///   [`MechanicsError::NoFreeBody`]): nothing has changed;
    /// - the detection ([`MechanicsError::Penetration`]), before any force: the bodies'
    ///   poses, velocities and angular momenta, the last step's contacts and forces, the time
    ///   and the step count are as they were. The overlap is in the poses the last step (or
    ///   [`Simulation::set_pose`]) left, which can be read and saved; the next step builds
    ///   the candidate pairs afresh and finds it again;
    /// - the integration ([`MechanicsError::NotFinite`], [`MechanicsError::Travel`]), after
    ///   the forces: the contacts, their joint states and the contact forces are this step's
    ///   (at the poses before it), and every body's pose, velocity and angular momentum has
    ///   been advanced (not finite for `NotFinite`; the far body where the step took it for
    ///   `Travel`), but the time and the step count have not, and the placed parts
    ///   ([`Simulation::placed_system`]) are still at the poses before. This is no state to
    ///   go on from: set the poses and velocities again, or start again from a restart file
    ///   ([`Simulation::load_state`]) or a new simulation.
    pub fn step(&mut self) -> Result<(), MechanicsError> {
        let dt = self.timestep()?;
        let mut clock = Instant::now();
        let mut lap = |slot: &mut f64| {
            let now = Instant::now();
            *slot += (now - clock).as_secs_f64();
            clock = now;
        };
        let mut t = self.timings;
        self.update_pairs();
        lap(&mut t.pairs);
        let (asked, counts, outcomes) = self.kept_answers();
        lap(&mut t.detect);
        self.complete_queried(&asked);
        lap(&mut t.placement);
        let detected = self.detect(&asked);
        lap(&mut t.detect);
        if detected.is_err() {
            // The step stops before its contacts are built, but the memos of its queries
            // are written (the penetrating pair's among them): the next step must not take
            // them for answers (it would skip the penetrating pair as unmoved, and read
            // another answer's area shares back). It builds the candidate pairs afresh, with
            // new memos, and queries every one of them, so a penetration stays an error.
            self.built_at = None;
        }
        detected?;
        let [queried, unmoved, certified, carried, dormant] = counts;
        self.update_contacts(dt, &outcomes);
        self.update_wet_joints();
        lap(&mut t.contacts);
        self.sum_forces();
        self.apply_relaxation();
        lap(&mut t.forces);
        let integrated = self.integrate(dt);
        lap(&mut t.integration);
        integrated?;
        self.place_moving();
        lap(&mut t.placement);
        t.steps += 1;
        t.rebuilds = self.timings.rebuilds;
        t.queried += queried;
        t.unmoved += unmoved;
        t.certified += certified;
        t.carried += carried;
        t.dormant += dormant;
        self.timings = t;
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    /// `n` steps.
    pub fn cycle(&mut self, n: u64) -> Result<(), MechanicsError> {
        for _ in 0..n {
            self.step()?;
        }
        Ok(())
    }

    /// Steps until the time reaches `t` (the last step may pass it by less than a step).
    pub fn run_until(&mut self, t: f64) -> Result<(), MechanicsError> {
        if !t.is_finite() {
            return Err(MechanicsError::NotFinite("the end time"));
        }
        while self.time < t {
            self.step()?;
        }
        Ok(())
    }

    /// Steps until the unbalanced-force ratio is below `ratio` (3DEC's default 1e-5), at
    /// most `max_steps`. With no damping at all (local and viscous both 0, as by default),
    /// it steps with local damping 0.8 (3DEC's) and sets the damping back after; any damping
    /// set, even local 0 with some viscous damping, is used as it is.
    pub fn solve(&mut self, ratio: f64, max_steps: u64) -> Result<SolveReport, MechanicsError> {
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(MechanicsError::Parameter {
                name: "ratio",
                range: "a finite number > 0",
                value: ratio,
            });
        }
        let saved = self.damping;
        if saved == Damping::default() {
            self.damping.local = 0.8;
        }
        let mut taken = 0;
        let result = loop {
            if taken >= max_steps {
                break Ok(false);
            }
            if let Err(e) = self.step() {
                break Err(e);
            }
            taken += 1;
            if self.ratio < ratio {
                break Ok(true);
            }
        };
        self.damping = saved;
        Ok(SolveReport {
            steps: taken,
            ratio: self.ratio,
            converged: result?,
        })
    }

    // ---- the step's parts -------------------------------------------------------------

    fn place_body(&mut self, b: usize) {
        for k in 0..self.placed.len() {
            if self.part_body[k] as usize == b {
                let part = &self.bodies.shape(b).parts()[self.part_index[k] as usize];
                self.placed[k].place_from(part, &self.bodies.pose[b]);
                self.complete[k] = true;
            }
        }
    }

    /// Places the coordinates of the parts of every body whose pose changed in this step's
    /// integration (in parallel; each part is its own), leaving them incomplete until a pair
    /// of theirs is queried ([`Simulation::complete_queried`]). A part at an unchanged pose
    /// would be placed to the same bits. The topology, face origins and volume of a placed
    /// part are its reference's from the start and never change: only the coordinates are
    /// written.
    fn place_moving(&mut self) {
        let (bodies, part_body, part_index) = (&self.bodies, &self.part_body, &self.part_index);
        let (moved_at, next) = (&self.moved_at, self.steps + 1);
        let body = |k: usize| part_body[k] as usize;
        let reference = |k: usize| &bodies.shape(body(k)).parts()[part_index[k] as usize];
        // Each part's reference is three dependent loads away (the body's shape, its parts,
        // their coordinates), all scattered in memory: asked for ahead, one level a few parts
        // before the next (as the tracker's placing does; hints only, no effect on any bit).
        const AHEAD: usize = 4;
        let first = |run: usize| run * PLACE_RUN;
        self.placed
            .par_chunks_mut(PLACE_RUN)
            .zip(self.complete.par_chunks_mut(PLACE_RUN))
            .enumerate()
            .for_each(|(run, (placed, complete))| {
                let (start, n) = (first(run), placed.len());
                for j in 0..n {
                    let k = start + j;
                    if j + 3 * AHEAD < n {
                        crate::block::prefetch_value(&**bodies.shape(body(k + 3 * AHEAD)));
                    }
                    if j + 2 * AHEAD < n {
                        crate::block::prefetch_value(reference(k + 2 * AHEAD));
                    }
                    if j + AHEAD < n && moved_at[body(k + AHEAD)] == next {
                        reference(k + AHEAD).prefetch(Prefetch::Points);
                        placed[j + AHEAD].prefetch(Prefetch::Points);
                    }
                    let b = body(k);
                    if moved_at[b] == next {
                        placed[j].place_coordinates(reference(k), &bodies.pose[b]);
                        complete[j] = false;
                    }
                }
            });
    }

    /// Completes the placing of the parts of the pairs to query this step (`asked`, their
    /// indices): their clearance and local coordinates, from the coordinates placed after
    /// their last motion. The same block, bit for bit, as placing it whole.
    fn complete_queried(&mut self, asked: &[u32]) {
        let mut needed = vec![false; self.placed.len()];
        for &k in asked {
            let [i, j] = self.pairs[k as usize];
            needed[i as usize] = true;
            needed[j as usize] = true;
        }
        self.placed
            .par_iter_mut()
            .zip(&mut self.complete)
            .zip(needed)
            .for_each(|((p, complete), needed)| {
                if needed && !*complete {
                    p.place_query_data();
                    *complete = true;
                }
            });
    }

    /// The candidate pairs, rebuilt when a body has travelled more than half the skin
    /// since the last build (boxes widened by gap + skin / 2: until then every pair within
    /// its gap is among them). The test of each body ([`passed_skin`]) is made when its
    /// pose changes: by the integration for the bodies it moves, here at the build for all
    /// (every other change of a pose drops the build); a body whose pose keeps its bits keeps
    /// its answer.
    fn update_pairs(&mut self) {
        if self.built_at.is_some() && !self.skin_passed {
            return;
        }
        let half = 0.5 * self.skin;
        let (placed, tol) = (&self.placed, &self.tolerance);
        let boxes = WideBoxes::from_fn(placed.len(), |k| {
            let aabb = placed[k].aabb();
            (aabb, tol.for_box(&aabb).gap + half)
        });
        let moves = |k: u32| self.bodies.is_free(self.part_body[k as usize] as usize);
        self.pairs = boxes
            .pairs(BroadPhase::default())
            .into_iter()
            .filter(|&[i, j]| {
                let [a, b] = [self.part_body[i as usize], self.part_body[j as usize]];
                a != b
                    && (moves(i) || moves(j))
                    && !self.is_removed(a as usize)
                    && !self.is_removed(b as usize)
            })
            .collect();
        self.memo = vec![PairMemo::default(); self.pairs.len()];
        self.frames = vec![Frame::default(); self.pairs.len()];
        self.open_frames = vec![0; self.pairs.len().div_ceil(64)];
        let poses = &self.bodies.pose;
        self.skin_passed = (0..self.bodies.len())
            .into_par_iter()
            .any(|b| passed_skin(&poses[b], &poses[b], self.bodies.shape(b).radius(), half));
        self.built_at = Some(poses.clone());
        self.timings.rebuilds += 1;
    }

    /// What each candidate pair does this step, from its memo and its bodies' motion alone
    /// (in parallel; no geometry read): it keeps its last answer when its two bodies have
    /// not moved since (unmoved) or it is certified separated (docs/mechanics.md, "Contact
    /// updates"), or carries its contact when its bodies moved less than the update
    /// tolerance since its query (docs/mechanics.md, "Carried contacts"), dormant when its
    /// carried contact is certified open ("Dormant contacts"); else it is queried.
    /// The indices of the pairs to query, in order, the numbers of pairs queried, unmoved,
    /// certified, carried (dormant included) and dormant, and each pair's outcome.
    fn kept_answers(&mut self) -> (Vec<u32>, [u64; 5], Vec<Outcome>) {
        let part_body = &self.part_body;
        let (moved_at, travel) = (&self.moved_at, &self.travel);
        let poses = &self.bodies.pose;
        let full = self.full_detection;
        // Certificates of open contacts made earlier are used only while dormancy is on and
        // the joints are dry (water set since pushes on open joints: their points must move).
        let dormancy = self.dormancy && self.water.is_dry();
        // How much a turning body widens its pairs' gap per unit of its vertices' motion.
        let growth = SIZE_GROWTH * self.tolerance.gap_slope();
        let open_frames = &self.open_frames;
        let outcomes: Vec<Outcome> = self
            .pairs
            .par_iter()
            .zip(&mut self.memo)
            .zip(&mut self.frames)
            .enumerate()
            .map(|(k, ((&[i, j], memo), frame))| {
                // The bits' invariant, checked in the debug profile (every test run).
                debug_assert!(
                    may_be_open(open_frames, k) == matches!(frame, Frame::Open(_)),
                    "pair {k}: its bit and its frame disagree on whether it is open"
                );
                let [bi, bj] = [part_body[i as usize], part_body[j as usize]].map(|b| b as usize);
                let asked = memo.asked_at;
                if asked != NEVER_ASKED && !full {
                    if moved_at[bi] <= asked && moved_at[bj] <= asked {
                        return Outcome::Unmoved;
                    }
                    let travels = [travel[bi], travel[bj]];
                    let now = [&poses[bi], &poses[bj]];
                    if memo.found.is_none()
                        && (holds(memo.deadline, travels)
                            || match frame {
                                Frame::Separated(s) => memo.renew(s, now, travels, growth),
                                _ => false,
                            })
                    {
                        return Outcome::Certified;
                    }
                    // A contact's tolerance and travels at the query are in its memo.
                    let tolerance = memo.deadline;
                    match &memo.found {
                        Some(_) if tolerance > 0.0 => {
                            // The travels' sum, not the net relative motion: it grows with
                            // every motion, so a carried contact is queried again in the end
                            // even when its bodies move back and forth (docs/mechanics.md,
                            // "Carried contacts").
                            let [ti, tj] = memo.travels;
                            if (travel[bi] - ti) + (travel[bj] - tj) <= tolerance {
                                if !may_be_open(open_frames, k) {
                                    return Outcome::Carried;
                                }
                                return match frame {
                                    Frame::Open(cert) if dormancy && cert.holds(now) => {
                                        Outcome::Dormant
                                    }
                                    _ => Outcome::Carried,
                                };
                            }
                        }
                        _ => {}
                    }
                }
                Outcome::Queried
            })
            .collect();
        // Counted and listed in parallel (integer counts, and the indices collected in
        // order: the same for any number of threads); one loop on one thread before
        // 2026-11-29.
        let counts = outcomes
            .par_iter()
            .fold(
                || [0u64; 5],
                |mut counts, outcome| {
                    match outcome {
                        Outcome::Queried => counts[0] += 1,
                        Outcome::Unmoved => counts[1] += 1,
                        Outcome::Certified => counts[2] += 1,
                        Outcome::Carried => counts[3] += 1,
                        Outcome::Dormant => {
                            counts[3] += 1;
                            counts[4] += 1;
                        }
                    }
                    counts
                },
            )
            .reduce(|| [0u64; 5], |a, b| std::array::from_fn(|k| a[k] + b[k]));
        let asked: Vec<u32> = outcomes
            .par_iter()
            .enumerate()
            .filter(|(_, &outcome)| outcome == Outcome::Queried)
            .map(|(k, _)| k as u32)
            .collect();
        (asked, counts, outcomes)
    }

    /// Queries the candidate pairs `asked` (their indices, ascending; in parallel) and keeps
    /// the answers in their memos; the first pair (in pair order) found penetrating is an
    /// error.
    fn detect(&mut self, asked: &[u32]) -> Result<(), MechanicsError> {
        let tol = self.tolerance;
        let (placed, part_body, pairs) = (&self.placed, &self.part_body, &self.pairs);
        let (travel, last_step) = (&self.travel, &self.last_step);
        let (step, full, fraction) = (self.steps, self.full_detection, self.update_fraction);
        let bodies = &self.bodies;
        let answers: Vec<(PairMemo, Frame, bool)> = asked
            .par_iter()
            .map_init(
                || Detector::new(tol),
                |det, &k| {
                    let [i, j] = pairs[k as usize];
                    let [bi, bj] =
                        [part_body[i as usize], part_body[j as usize]].map(|b| b as usize);
                    let (a, b) = (&placed[i as usize], &placed[j as usize]);
                    let (result, geometry) = det.detect_with_geometry(a, b);
                    let mut memo = PairMemo {
                        asked_at: step,
                        ..PairMemo::default()
                    };
                    let mut frame = Frame::default();
                    match (result, geometry) {
                        (PairResult::Contact(contact), Some(geometry)) => {
                            let contact =
                                contacts::facing_faces(contact, geometry.normal(), [a, b]);
                            let gap = det.thresholds(a, b).gap;
                            let tolerance = if full { 0.0 } else { fraction * gap };
                            let carry = Carry::new(
                                [a, b],
                                gap,
                                &contact,
                                &geometry,
                                [bodies.pose[bi], bodies.pose[bj]],
                                tolerance,
                            );
                            (memo.deadline, memo.travels) = (tolerance, [travel[bi], travel[bj]]);
                            memo.found = Some(Box::new(Found {
                                parts: [i, j],
                                contact,
                                geometry,
                                carry,
                            }));
                        }
                        (PairResult::Penetrating, _) => return (memo, frame, true),
                        _ if !full => {
                            memo.deadline =
                                certificate(det, [a, b], [bi, bj], bodies, travel, last_step);
                            frame = Frame::Separated(Separation {
                                b_in_a: contacts::b_in_a(&bodies.pose[bi], &bodies.pose[bj]),
                                rotation_a: bodies.pose[bi].rotation,
                                travels: travel[bi] + travel[bj],
                                radii: [bi, bj].map(|b| bodies.shape(b).radius()),
                            });
                        }
                        _ => {}
                    }
                    (memo, frame, false)
                },
            )
            .collect();
        let mut penetrating = None;
        for (&k, (memo, frame, deep)) in asked.iter().zip(answers) {
            if deep && penetrating.is_none() {
                penetrating = Some(k);
            }
            self.memo[k as usize] = memo;
            self.frames[k as usize] = frame;
            self.open_frames[k as usize / 64] &= !(1u64 << (k % 64));
        }
        match penetrating {
            None => Ok(()),
            Some(k) => {
                let [i, j] = self.pairs[k as usize];
                let (a, b) = (&self.placed[i as usize], &self.placed[j as usize]);
                let depth = crate::overlap::overlap(a, b, &tol).map(|o| o.min_translation.length());
                Err(MechanicsError::Penetration {
                    bodies: [part_body[i as usize], part_body[j as usize]],
                    step: self.steps,
                    depth,
                    gap: Detector::new(tol).thresholds(a, b).gap,
                    // The first detection: no contact force has acted yet.
                    initial: self.initial,
                })
            }
        }
    }

    /// Sub-contacts with their forces (in parallel, by chunks of contacts), matched to the
    /// last step's; a dormant contact (`outcomes`: each pair's this step) keeps its last
    /// step's.
    fn update_contacts(&mut self, dt: f64, outcomes: &[Outcome]) {
        let motions = contacts::motions(&self.bodies);
        let input = StepInput {
            bodies: &self.bodies,
            motions: &motions,
            part_body: &self.part_body,
            placed: &self.placed,
            joints: &self.joints,
            bridges: &self.bridges,
            previous: &self.contacts,
            dt,
            initial: self.initial,
            point_width: self.point_width,
            initial_stress: self.initial_stress.as_ref(),
            dormancy: self.dormancy && self.water.is_dry(),
        };
        // The contacts of this step, in pair order: the pair's index, its parts (from the
        // pair list, so that a dormant contact does not read its answer) and whether it is
        // dormant (its answer is its pair's memo's); then their counts and last step's
        // contacts.
        let same_width = self.shares_width == Some(self.point_width.to_bits());
        let mut current = std::mem::take(&mut self.current);
        gather_contacts(&self.memo, &self.pairs, outcomes, same_width, &mut current);
        let found = current.as_mut_slice();
        let memo = &self.memo;
        let answer = |pair: u32| {
            memo[pair as usize]
                .found
                .as_deref()
                .expect("every contact of the step is a pair with an answer")
        };
        counts_and_previous(&self.contacts, found, answer);
        let found = &*found;
        // The contacts are updated by chunks (below): each chunk's sub-contact count.
        const CHUNK: usize = 512;
        let chunk_counts: Vec<u32> = found
            .par_chunks(CHUNK)
            .map(|chunk| chunk.iter().map(|f| f.count).sum())
            .collect();
        let total: usize = chunk_counts.iter().map(|&n| n as usize).sum();
        let keep_stress = self.initial_stress.is_some() || !self.contacts.prestresses.is_empty();
        // The buffers of the step before last (`spare`), refilled in place. Every contact
        // and sub-contact of them is written below (built, or copied for a dormant contact),
        // so only the slots beyond their old lengths are filled first: filling all of them
        // wrote each sub-contact's 112 bytes twice (docs/mechanics.md, "The sub-contact
        // update").
        let Contacts {
            mut list,
            mut subs,
            mut prestresses,
        } = std::mem::take(&mut self.spare);
        subs.truncate(total);
        let grown = total - subs.len();
        subs.par_extend(rayon::iter::repeat_n(SubContact::default(), grown));
        prestresses.clear();
        prestresses.resize(if keep_stress { total } else { 0 }, 0.0);
        list.truncate(found.len());
        let placeholder = BodyContact {
            parts: [0; 2],
            bodies: [0; 2],
            kind: crate::ContactType::FaceFace,
            normal: DVec3::Z,
            set: None,
            bridge: false,
            first: 0,
            count: 0,
        };
        list.resize(found.len(), placeholder);
        // The contacts by chunks, each with its own slices of the contacts, sub-contacts,
        // installed stresses and pair frames (a chunk's pairs are a range of them: the
        // contacts are in pair order), updated in parallel chunk by chunk.
        let mut work = Vec::with_capacity(found.len().div_ceil(CHUNK));
        let mut rest = (
            list.as_mut_slice(),
            subs.as_mut_slice(),
            prestresses.as_mut_slice(),
            self.frames.as_mut_slice(),
        );
        let (mut first, mut frames_at) = (0u32, 0usize);
        for (chunk, &count) in found.chunks(CHUNK).zip(&chunk_counts) {
            let (list, list_tail) = std::mem::take(&mut rest.0).split_at_mut(chunk.len());
            let (subs, subs_tail) = std::mem::take(&mut rest.1).split_at_mut(count as usize);
            let stress_count = if keep_stress { count as usize } else { 0 };
            let (stress, stress_tail) = std::mem::take(&mut rest.2).split_at_mut(stress_count);
            let (from, to) = (
                chunk[0].pair as usize,
                chunk[chunk.len() - 1].pair as usize + 1,
            );
            let (_, frames_tail) = std::mem::take(&mut rest.3).split_at_mut(from - frames_at);
            let (frames, frames_tail) = frames_tail.split_at_mut(to - from);
            rest = (list_tail, subs_tail, stress_tail, frames_tail);
            frames_at = to;
            work.push((chunk, first, list, subs, stress, frames));
            first += count;
        }
        let old = &self.contacts;
        let open_frames = &self.open_frames;
        // Each chunk gives the pairs whose frame it wrote, and whether the frame is open
        // now: their bits are set or cleared after (a word of bits can span two chunks).
        let written: Vec<Vec<(u32, bool)>> = work
            .into_par_iter()
            .map_init(
                Scratch::default,
                |scratch, (chunk, mut first, list, mut subs, mut stress, frames)| {
                    let from = chunk[0].pair as usize;
                    let mut written = Vec::new();
                    for (f, slot) in chunk.iter().zip(list) {
                        let n = f.count as usize;
                        let (out, tail) = std::mem::take(&mut subs).split_at_mut(n);
                        subs = tail;
                        let (out_p, tail) = std::mem::take(&mut stress)
                            .split_at_mut(if keep_stress { n } else { 0 });
                        stress = tail;
                        let mut contact = match f.previous {
                            // Dormant: the last step's contact and sub-contacts, its frame kept.
                            Some(i) if f.dormant => {
                                let i = i as usize;
                                let at = old.list[i].first as usize;
                                out.copy_from_slice(old.subs_of(i));
                                for (k, p) in out_p.iter_mut().enumerate() {
                                    *p = old.prestress(at + k);
                                }
                                old.list[i].clone()
                            }
                            previous => {
                                let (contact, cert) = build_contact(
                                    &input,
                                    answer(f.pair),
                                    previous,
                                    f.same_answer,
                                    scratch,
                                    out,
                                    out_p,
                                );
                                // Not rewritten for a contact without a certificate that had
                                // none (most of them): writing the slot dirtied its cache line
                                // at every step.
                                // (A contact's frame is open or none: the query that found it
                                // wrote none. Its bit says which: set exactly when it is open.)
                                if cert.is_some() || may_be_open(open_frames, f.pair as usize) {
                                    written.push((f.pair, cert.is_some()));
                                    frames[f.pair as usize - from] =
                                        cert.map_or(Frame::None, Frame::Open);
                                }
                                contact
                            }
                        };
                        contact.first = first;
                        first += f.count;
                        *slot = contact;
                    }
                    written
                },
            )
            .collect();
        for &(pair, open) in written.iter().flatten() {
            let (word, bit) = (pair as usize / 64, 1u64 << (pair % 64));
            if open {
                self.open_frames[word] |= bit;
            } else {
                self.open_frames[word] &= !bit;
            }
        }
        // The side table only while a sub-contact has an installed stress.
        if prestresses.iter().all(|&p| p == 0.0) {
            prestresses.clear();
        }
        let last = std::mem::replace(
            &mut self.contacts,
            Contacts {
                list,
                subs,
                prestresses,
            },
        );
        self.spare = last;
        self.current = current;
        self.initial = false;
        self.shares_width = Some(self.point_width.to_bits());
    }

    /// The contact (and bolt) forces and moments per body: each body's sum receives the same
    /// additions in the same order for any number of threads ([`add_contact_forces`]).
    fn sum_forces(&mut self) {
        self.forces.iter_mut().for_each(|f| *f = DVec3::ZERO);
        self.moments.iter_mut().for_each(|m| *m = DVec3::ZERO);
        self.add_bolts_and_moments();
        let poses = &self.bodies.pose;
        add_contact_forces(&self.contacts, poses, &mut self.forces, &mut self.moments);
        self.water
            .add_forces(&self.contacts, poses, &mut self.forces, &mut self.moments);
        self.add_opened_joint_forces();
    }

    /// Adds the bolts' forces and the applied moments to the bodies' sums (docs/mechanics.md,
    /// "Rock bolts and applied loads").
    fn add_bolts_and_moments(&mut self) {
        self.bolts
            .add_forces(&self.bodies, &mut self.forces, &mut self.moments);
        for (&i, &m) in &self.applied_moments {
            self.moments[i as usize] += m;
        }
    }

    /// Damps and integrates every body, in place and in parallel (each body's new state is
    /// a function of its own); the unbalanced-force ratio (a largest value: the same in any
    /// order). A body whose new state is not finite fails the step, after every body has
    /// been advanced.
    fn integrate(&mut self, dt: f64) -> Result<(), MechanicsError> {
        let synced = &self.synced;
        let (forces, moments) = (&self.forces, &self.moments);
        let (gravity, damping) = (self.gravity, &self.damping);
        let (built, half) = (self.built_at.as_deref(), 0.5 * self.skin);
        let next = self.steps + 1;
        let (inertia, motions) = self.bodies.split_motion();
        let bookkeeping = (&mut self.last_step, &mut self.travel, &mut self.moved_at);
        let summary = motions
            .pose
            .par_iter_mut()
            .zip(motions.velocity.par_iter_mut())
            .zip(motions.momentum.par_iter_mut())
            .zip(bookkeeping.0.par_iter_mut())
            .zip(bookkeeping.1.par_iter_mut())
            .zip(bookkeeping.2.par_iter_mut())
            .enumerate()
            .map(|(i, (((((pose, v), l), last_step), travel), moved_at))| {
                // A task takes its bodies in ascending order: the shape of a body a few
                // ahead is asked for now (hides a wait on memory per body).
                inertia.prefetch_shape(i + 4);
                let unbalanced = if inertia.is_free(i) {
                    let load = gravity * inertia.mass(i) + inertia.applied_force(i);
                    [(forces[i] + load).length(), load.length()]
                } else {
                    [0.0; 2]
                };
                let before = integrate::Motion {
                    pose: *pose,
                    velocity: *v,
                    momentum: *l,
                };
                let (f, m) = integrate::damped(
                    &inertia,
                    i,
                    &before,
                    [forces[i], moments[i]],
                    gravity,
                    damping,
                );
                let kick = synced.kick(i);
                let after = integrate::advanced(&inertia, i, before, [f, m], dt, kick);
                let (mut passed, mut far) = (false, None);
                *last_step = if same_bits(&before.pose, &after.pose) {
                    0.0
                } else {
                    let radius = inertia.shape(i).radius();
                    passed = built.is_some_and(|b| passed_skin(&b[i], &after.pose, radius, half));
                    // The detection of the next step is the first to see this pose.
                    *moved_at = next;
                    let moved = before
                        .pose
                        .displacement_bound(&after.pose, DVec3::ZERO, radius);
                    if moved > TRAVEL_LIMIT * radius && inertia.is_free(i) {
                        far = Some(FarBody {
                            body: i as u32,
                            travel: moved,
                            radius,
                        });
                    }
                    moved
                };
                *travel += *last_step;
                (*pose, *v, *l) = (after.pose, after.velocity, after.momentum);
                Summary {
                    largest: unbalanced[0],
                    reference: unbalanced[1],
                    passed,
                    far,
                    finite: pose.translation.is_finite()
                        && pose.rotation.is_finite()
                        && v.is_finite()
                        && l.is_finite(),
                }
            })
            .reduce(Summary::default, Summary::merge);
        self.skin_passed |= summary.passed;
        // Every body has been advanced: all velocities are at the half step now.
        self.synced = Synced::None;
        if !summary.finite {
            return Err(MechanicsError::NotFinite("a body's state after the step"));
        }
        let (largest, reference) = (summary.largest, summary.reference);
        // Forces beyond about 1e154 newtons have finite components but an infinite length:
        // their ratio would be infinite over infinite, a NaN that no solve would ever take
        // below its target (it ran its whole budget). An error, as a state that is not finite.
        if !(largest.is_finite() && reference.is_finite()) {
            return Err(MechanicsError::NotFinite("a free body's unbalanced force"));
        }
        if let Some(far) = summary.far {
            return Err(MechanicsError::Travel {
                body: far.body,
                step: self.steps,
                travel: far.travel,
                radius: far.radius,
                dt,
            });
        }
        self.ratio = if reference > 0.0 {
            largest / reference
        } else if largest == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        Ok(())
    }
}

/// Whose velocities are at the whole step rather than the leapfrog's half step: set at
/// the current time (at the start, or by [`Simulation::set_velocity`] and
/// [`Simulation::free`] since the last step). Their next kick is half a step's (central
/// difference started from `v(t)`: `v(t + dt/2) = v(t) + dt/2 F/m`); every other body's
/// velocity is already at `t - dt/2`, and its kick is a whole step's. (A single flag for
/// all bodies, before 2026-11-28, gave every moving body half a kick too few when one body's
/// velocity was set during a run: a lasting error of `dt/2 F/m` in its velocity.)
#[derive(Clone, Debug, Default, PartialEq)]
enum Synced {
    /// None: every velocity is at the half step.
    #[default]
    None,
    /// Every body (a new simulation: all at rest at time 0).
    All,
    /// These bodies.
    Bodies(std::collections::BTreeSet<u32>),
}

impl Synced {
    /// Marks body `i`'s velocity as at the whole step.
    fn add(&mut self, i: usize) {
        match self {
            Synced::All => {}
            Synced::None => *self = Synced::Bodies([i as u32].into()),
            Synced::Bodies(set) => {
                set.insert(i as u32);
            }
        }
    }

    /// The fraction of the step of body `i`'s next kick.
    fn kick(&self, i: usize) -> f64 {
        let whole = match self {
            Synced::None => false,
            Synced::All => true,
            Synced::Bodies(set) => set.contains(&(i as u32)),
        };
        if whole {
            0.5
        } else {
            1.0
        }
    }
}

/// What the integration of the bodies found, merged over them in any order.
#[derive(Clone, Copy, Debug)]
struct Summary {
    /// The largest unbalanced force of a free body, and the largest of its gravity and
    /// applied force (the ratio's reference).
    largest: f64,
    reference: f64,
    /// Whether a body moved more than half the skin since the candidate pairs were built.
    passed: bool,
    /// The free body of smallest id that moved farther than [`TRAVEL_LIMIT`] times its
    /// radius, if any.
    far: Option<FarBody>,
    /// Whether every body's new state is finite.
    finite: bool,
}

/// A free body that moved too far in one step ([`MechanicsError::Travel`]).
#[derive(Clone, Copy, Debug)]
struct FarBody {
    body: u32,
    /// The bound of its points' displacement in the step.
    travel: f64,
    /// Its radius ([`crate::body::Shape::radius`]).
    radius: f64,
}

/// The farthest a free body may move in one step, as a fraction of its radius (the largest
/// distance of its points from its centroid): a body moving farther could pass through
/// another between two detections (docs/mechanics.md, "Travel in one step").
pub const TRAVEL_LIMIT: f64 = 0.1;

/// The smallest time step, as a fraction of the undamped critical step (docs/mechanics.md,
/// "The smallest time step"): a step given below it, or an automatic one that the safety
/// factor or viscous damping takes below it, is a [`MechanicsError::TimeStepTooSmall`].
/// It is the rounding of the critical step (2^-52, 2.2e-16): no stiffness, mass or damping
/// of the model asks for a step that small beside it. (A bound relative to the critical
/// step cannot be much larger: tests step a body made a billion times heavier, or given
/// joints of 1e-6 Pa/m to keep contacts out of a free flight, at 5e-10 of their critical
/// step.)
pub const MIN_STEP_FRACTION: f64 = f64::EPSILON;

impl Default for Summary {
    fn default() -> Self {
        Summary {
            largest: 0.0,
            reference: 0.0,
            passed: false,
            far: None,
            finite: true,
        }
    }
}

impl Summary {
    fn merge(self, other: Summary) -> Summary {
        Summary {
            largest: self.largest.max(other.largest),
            reference: self.reference.max(other.reference),
            passed: self.passed || other.passed,
            // The smallest id: the same body whatever the order of the merges.
            far: match (self.far, other.far) {
                (Some(a), Some(b)) => Some(if a.body < b.body { a } else { b }),
                (a, b) => a.or(b),
            },
            finite: self.finite && other.finite,
        }
    }
}

/// What the last query of a candidate pair found, and when.
#[derive(Clone, Debug)]
struct PairMemo {
    /// The step of the last query ([`NEVER_ASKED`]: never queried since the broad phase was
    /// built; a sentinel rather than an `Option`, which would take 16 bytes).
    asked_at: u64,
    /// The contact found then (`None`: separated); boxed, so that the many separated pairs
    /// take 40 bytes each.
    found: Option<Box<Found>>,
    /// A separated pair's certificate: the travel sum of its two bodies below which it stays
    /// separated (`-∞`: none). For a contact, its carry's tolerance (the growth of the
    /// travels' sum since the query up to which it is carried).
    deadline: f64,
    /// For a contact, its two bodies' travels at the query (its carry's): with `deadline`,
    /// what the step's test of every carried contact reads, without the contact's box (a
    /// cache miss per pair and step: docs/mechanics.md, "Carried contacts").
    travels: [f64; 2],
}

/// [`PairMemo::asked_at`] of a pair never queried.
const NEVER_ASKED: u64 = u64::MAX;

/// What a candidate pair keeps beside its [`PairMemo`], apart (read only for the pairs whose
/// travels have used up their certificate, and for carried contacts): where a separated
/// pair's certificate was made, or a carried contact's certificate of being open.
#[derive(Clone, Copy, Debug, Default)]
enum Frame {
    #[default]
    None,
    Separated(Separation),
    Open(OpenCert),
}

/// A separated pair's two bodies when its certificate was made.
#[derive(Clone, Copy, Debug)]
struct Separation {
    /// B's pose in A's body frame ([`contacts::b_in_a`]).
    b_in_a: Pose,
    /// A's world rotation (B's is A's times `b_in_a`'s): a common turn of the two bodies
    /// moves neither relative to the other but turns their boxes, whose diagonals set the
    /// gap.
    rotation_a: DQuat,
    /// The sum of the two bodies' travels.
    travels: f64,
    /// The two bodies' radii (A, B).
    radii: [f64; 2],
}

impl Default for PairMemo {
    fn default() -> Self {
        PairMemo {
            asked_at: NEVER_ASKED,
            found: None,
            deadline: f64::NEG_INFINITY,
            travels: [0.0; 2],
        }
    }
}

impl PairMemo {
    /// Renews the separated pair's certificate by its bodies' relative motion since it was
    /// made, when their travels have used it up (docs/mechanics.md, "Contact updates"):
    /// `true` if it still holds, with the certificate made anew at the current poses.
    ///
    /// The certificate allows the two bodies' travels to grow by `allowed`, its deadline less
    /// the travels when it was made (its margin less the gap, over `1 + growth`, less
    /// rounding: [`deadline`]). What closes the pair is the motion `d` of B relative to A
    /// ([`contacts::motion_in_a`]), at most that travel and zero when the two move as one.
    /// What widens the gap is the turn of either body in the world (its box's diagonal, the
    /// size that sets the gap, grows by at most `SIZE_GROWTH` times how far its vertices
    /// move relative to its centroid, `2 sin(θ / 2) r`) and the coordinates' magnitude (the
    /// rounding floor, by at most `TRAVEL_SLACK - 1` times the travels `t`). So it holds while
    /// `d + w + (TRAVEL_SLACK - 1) t < allowed`, `w` the gap's growth by the turns; then
    /// `allowed - d - w` is left from here, and the certificate is written again at the
    /// current poses and travels: the travels' test serves it again for the steps that follow
    /// (the relative motion and the turns since the renewal are at most the travel since),
    /// rather than this test at every step.
    fn renew(
        &mut self,
        frame: &mut Separation,
        now: [&Pose; 2],
        travel: [f64; 2],
        growth: f64,
    ) -> bool {
        let allowed = self.deadline - frame.travels;
        if allowed <= 0.0 {
            return false;
        }
        let travels = travel[0] + travel[1];
        let [ra, rb] = frame.radii;
        // How far each body's vertices have moved about its centroid: its turn alone.
        let turned = |then: DQuat, now: DQuat, r: f64| {
            let at = |rotation| Pose {
                rotation,
                translation: DVec3::ZERO,
            };
            at(then).displacement_bound(&at(now), DVec3::ZERO, r)
        };
        let rotation_b = frame.rotation_a * frame.b_in_a.rotation;
        let w = growth
            * turned(frame.rotation_a, now[0].rotation, ra).max(turned(
                rotation_b,
                now[1].rotation,
                rb,
            ));
        let (d, b_in_a) = contacts::motion_in_a(&frame.b_in_a, now, rb);
        let holds = d + w + (TRAVEL_SLACK - 1.0) * travels < allowed;
        if holds {
            let left = allowed - d - w;
            self.deadline = left + travels - 4.0 * f64::EPSILON * (allowed + d + w + travels);
            *frame = Separation {
                b_in_a,
                rotation_a: now[0].rotation,
                travels,
                ..*frame
            };
        }
        holds
    }
}

/// What the detection did with one candidate pair this step.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Outcome {
    Queried,
    Unmoved,
    Carried,
    /// Carried, and its contact certified open: its sub-contacts are kept.
    Dormant,
    Certified,
}

/// Whether candidate pair `k`'s frame is a dormant contact's (its bit in
/// [`Simulation::open_frames`], set exactly when the frame is `Frame::Open`: checked on every
/// pair at every step in the debug profile).
fn may_be_open(open_frames: &[u64], k: usize) -> bool {
    open_frames[k / 64] & (1u64 << (k % 64)) != 0
}

/// The contacts of a step, in pair order, written to `out` (its old contents dropped, its
/// memory kept): each candidate pair with an answer, its parts (from the pair list, so that a
/// dormant contact does not read its answer), and whether it is dormant and built from the
/// same answer as at the last step (`outcomes`: the step's test of each pair; `same_width`:
/// whether the point width is the last step's). In two passes over chunks of the pairs, in
/// parallel: how many contacts each chunk has, then each chunk's written to its own slice.
/// (Collected afresh at every step, this list took its memory from the system page by page:
/// docs/mechanics.md, "The sub-contact update".)
fn gather_contacts(
    memo: &[PairMemo],
    pairs: &[[u32; 2]],
    outcomes: &[Outcome],
    same_width: bool,
    out: &mut Vec<contacts::Current>,
) {
    const CHUNK: usize = 4096;
    let counts: Vec<usize> = memo
        .par_chunks(CHUNK)
        .map(|chunk| chunk.iter().filter(|m| m.found.is_some()).count())
        .collect();
    let total = counts.iter().sum();
    // Only the slots beyond the old length are filled first; every slot is written below.
    out.truncate(total);
    out.resize(total, contacts::Current::default());
    let mut rest = out.as_mut_slice();
    let mut slices = Vec::with_capacity(counts.len());
    for &n in &counts {
        let (slice, tail) = std::mem::take(&mut rest).split_at_mut(n);
        slices.push(slice);
        rest = tail;
    }
    slices
        .into_par_iter()
        .zip(memo.par_chunks(CHUNK))
        .zip(outcomes.par_chunks(CHUNK))
        .enumerate()
        .for_each(|(c, ((slice, memo), outcomes))| {
            let mut slots = slice.iter_mut();
            for (j, (m, &outcome)) in memo.iter().zip(outcomes).enumerate() {
                if m.found.is_none() {
                    continue;
                }
                let Some(slot) = slots.next() else { break };
                let k = c * CHUNK + j;
                *slot = contacts::Current {
                    pair: k as u32,
                    parts: pairs[k],
                    // A dormant contact keeps its last step's sub-contacts, areas
                    // included: not across a change of the point width, whose step rebuilds
                    // every contact (so that no later step reads old shares back).
                    dormant: outcome == Outcome::Dormant && same_width,
                    same_answer: same_width && outcome != Outcome::Queried,
                    count: 0,
                    previous: None,
                };
            }
        });
}

/// The certificate of a pair of parts found separated (docs/mechanics.md, "Contact
/// updates", as the `ContactTracker`'s): a face plane separating them by more than the gap,
/// else no edge of either within the gap widened by [`EDGE_CERTIFICATE_STEPS`] times their
/// bodies' last motions; the deadline of [`deadline`] (`-∞`: none).
fn certificate(
    det: &mut Detector,
    [a, b]: [&ConvexBlock; 2],
    [bi, bj]: [usize; 2],
    bodies: &Bodies,
    travel: &[f64],
    last_step: &[f64],
) -> f64 {
    let gap = det.thresholds(a, b).gap;
    let slope = det.tolerance().gap_slope();
    let margin = separation(a, b);
    let travels = [travel[bi], travel[bj]];
    if margin > gap {
        return deadline(margin, gap, travels, slope);
    }
    let wider = EDGE_CERTIFICATE_STEPS * (last_step[bi] + last_step[bj]);
    let radii = [bodies.shape(bi).radius(), bodies.shape(bj).radius()];
    edge_certificate(det, [a, b], radii, gap, wider).map_or(f64::NEG_INFINITY, |m| {
        deadline(m + gap, gap, travels, slope)
    })
}

/// Adds the sub-contacts' forces and moments to their bodies' sums (`forces`, `moments`, per
/// body): on B the force, on A its opposite, each about the body's centroid at `poses`, in
/// contact order and then sub-contact order. In parallel over ranges of bodies, one range per
/// thread: each range's task reads every contact in order and adds only to its own bodies,
/// so every body receives the same additions in the same order as one loop over the
/// contacts would give it, whatever the ranges (the same bits for any number of threads).
/// The sub-contacts of a contact are read by the task of each of its bodies, once when both
/// are in one range. (Summed on one thread before 2026-11-29: 18 ms of a 95,220-block
/// step.) An open sub-contact adds nothing: it is skipped, so that a dormant contact's kept
/// normal, whose zero force may differ in the signs of its zeros, gives the same sums bit for
/// bit.
fn add_contact_forces(
    contacts: &Contacts,
    poses: &[Pose],
    forces: &mut [DVec3],
    moments: &mut [DVec3],
) {
    let ranges = rayon::current_num_threads();
    add_contact_forces_in(ranges, contacts, poses, forces, moments);
}

/// [`add_contact_forces`] over `ranges` ranges of bodies (the same bits for any number).
fn add_contact_forces_in(
    ranges: usize,
    contacts: &Contacts,
    poses: &[Pose],
    forces: &mut [DVec3],
    moments: &mut [DVec3],
) {
    let per = forces.len().div_ceil(ranges.max(1)).max(1);
    forces
        .par_chunks_mut(per)
        .zip(moments.par_chunks_mut(per))
        .enumerate()
        .for_each(|(range, (forces, moments))| {
            let (first, len) = (range * per, forces.len());
            // The index of body `b` in this range's slices, if it is in the range.
            let own = |b: usize| {
                let k = b.wrapping_sub(first);
                (k < len).then_some(k)
            };
            for (i, c) in contacts.list.iter().enumerate() {
                let [a, b] = [c.bodies[0] as usize, c.bodies[1] as usize];
                let (ka, kb) = (own(a), own(b));
                if ka.is_none() && kb.is_none() {
                    continue;
                }
                let (ca, cb) = (poses[a].translation, poses[b].translation);
                for s in contacts.subs_of(i) {
                    if s.normal_force == 0.0 && s.shear_force == DVec3::ZERO {
                        continue;
                    }
                    let f = s.force(c.normal);
                    if let Some(kb) = kb {
                        forces[kb] += f;
                        moments[kb] += (s.point - cb).cross(f);
                    }
                    if let Some(ka) = ka {
                        forces[ka] -= f;
                        moments[ka] -= (s.point - ca).cross(f);
                    }
                }
            }
        });
}

/// Parts per task of [`Simulation::place_moving`].
const PLACE_RUN: usize = 256;

/// Whether a body of radius `radius` (about its centroid) at `pose`, at `built` when the
/// candidate pairs were built, may have moved more than `half` (half the skin) since.
fn passed_skin(built: &Pose, pose: &Pose, radius: f64, half: f64) -> bool {
    built.displacement_bound(pose, DVec3::ZERO, radius) > half
}

/// Whether two poses are equal bit for bit (placing a block at either gives the same bits).
pub(super) fn same_bits(p: &Pose, q: &Pose) -> bool {
    let bits = |p: &Pose| {
        let (r, t) = (p.rotation.to_array(), p.translation.to_array());
        [r[0], r[1], r[2], r[3], t[0], t[1], t[2]].map(f64::to_bits)
    };
    // The differences or-ed together: one test, where `==` on the arrays called `memcmp`
    // (2 % of a step of the mechanics benchmark, once per body and twice per contact).
    let (a, b) = (bits(p), bits(q));
    a.iter().zip(&b).fold(0, |acc, (x, y)| acc | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sets a simulation has are its faces' and its system's spec entries; a set
    /// given properties joins them (a restart file keeps its sets so); another is refused by
    /// `check_set` with the set given and those there are.
    #[test]
    fn a_simulation_knows_its_joint_sets_and_refuses_another() {
        use crate::block::FaceOrigin;
        use crate::generation::{SetKind, SetRecord};
        let tagged = |b: ConvexBlock, origin: FaceOrigin| {
            let n = b.n_faces();
            b.with_face_origins(vec![origin; n]).unwrap()
        };
        let base = tagged(
            ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap(),
            FaceOrigin::Joint { set: 2, joint: 0 },
        );
        let cube = tagged(
            ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap(),
            FaceOrigin::Bridge { set: 5, joint: 1 },
        );
        let blocks = vec![base.clone(), cube.clone()];
        let mut sim = Simulation::new(&BlockSystem::new(blocks.clone()), 2500.0).unwrap();
        assert_eq!(sim.joint_sets(), BTreeSet::from([2, 5]));
        assert!(sim.check_set(2).is_ok() && sim.check_set(5).is_ok());
        let refused = sim.check_set(3).unwrap_err();
        assert!(matches!(refused, MechanicsError::UnknownSet { set: 3, .. }));
        let message = refused.to_string();
        assert!(
            message.contains('3') && message.contains("2, 5"),
            "{message}"
        );
        // A set given properties (a restart file's, or a caller's without the check) is one.
        sim.set_joint(3, JointModel::default()).unwrap();
        assert!(sim.check_set(3).is_ok());
        // The spec's entries are sets even when they cut no block.
        let record = |name: &str| SetRecord {
            name: name.to_string(),
            kind: SetKind::Plane,
        };
        let records = vec![record("a"), record("b"), record("c"), record("d")];
        let generated = BlockSystem::with_provenance(blocks, Vec::new(), Vec::new(), records);
        let sim = Simulation::new(&generated, 2500.0).unwrap();
        assert_eq!(sim.joint_sets(), BTreeSet::from([0, 1, 2, 3, 5]));
        // A restart file keeps them, those that cut no block included.
        let text = sim.to_state_string().unwrap();
        let loaded = Simulation::from_state_str(&text).unwrap();
        assert_eq!(loaded.joint_sets(), BTreeSet::from([0, 1, 2, 3, 5]));
        assert!(loaded.check_set(1).is_ok());
        // Blocks of no joint: no set at all, said so.
        let bare = BlockSystem::new(vec![ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap()]);
        let message = Simulation::new(&bare, 2500.0)
            .unwrap()
            .check_set(0)
            .unwrap_err()
            .to_string();
        assert!(message.contains("no joint sets"), "{message}");
    }

    #[test]
    fn contact_sums_are_the_serial_sums_for_any_ranges() {
        // A small random case: 40 bodies, 300 contacts of random bodies (some of one body
        // with itself, as the serial loop would take them), 0 to 4 sub-contacts each, open
        // ones among them (zero forces of either sign, skipped), forces over many orders of
        // magnitude so that another order of additions gives other bits.
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let real = |next: &mut dyn FnMut() -> u64| {
            let unit = (next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            unit * 10f64.powi((next() % 12) as i32 - 4)
        };
        let vector = |next: &mut dyn FnMut() -> u64| DVec3::new(real(next), real(next), real(next));
        let n = 40;
        let poses: Vec<Pose> = (0..n)
            .map(|_| Pose {
                rotation: DQuat::IDENTITY,
                translation: vector(&mut next),
            })
            .collect();
        let mut contacts = Contacts::default();
        for _ in 0..300 {
            let bodies = [(next() % n as u64) as u32, (next() % n as u64) as u32];
            let count = (next() % 5) as u32;
            contacts.list.push(BodyContact {
                parts: bodies,
                bodies,
                kind: crate::classify::ContactType::FaceFace,
                normal: vector(&mut next).normalize(),
                set: None,
                bridge: false,
                first: contacts.subs.len() as u32,
                count,
            });
            for _ in 0..count {
                let open = next() % 4 == 0;
                let zero = if next() % 2 == 0 { 0.0 } else { -0.0 };
                contacts.subs.push(SubContact {
                    point: vector(&mut next),
                    normal_force: if open { zero } else { real(&mut next) },
                    shear_force: if open {
                        DVec3::splat(zero)
                    } else {
                        vector(&mut next)
                    },
                    ..SubContact::default()
                });
            }
        }
        // Sums that do not start at zero (bolts and applied moments come first).
        let start: Vec<[DVec3; 2]> = (0..n)
            .map(|_| [vector(&mut next), vector(&mut next)])
            .collect();
        // The serial loop the step had until 2026-11-29.
        let (mut forces, mut moments): (Vec<DVec3>, Vec<DVec3>) =
            start.iter().map(|&[f, m]| (f, m)).unzip();
        for (i, c) in contacts.list.iter().enumerate() {
            let [a, b] = [c.bodies[0] as usize, c.bodies[1] as usize];
            let (ca, cb) = (poses[a].translation, poses[b].translation);
            for s in contacts.subs_of(i) {
                if s.normal_force == 0.0 && s.shear_force == DVec3::ZERO {
                    continue;
                }
                let f = s.force(c.normal);
                forces[b] += f;
                moments[b] += (s.point - cb).cross(f);
                forces[a] -= f;
                moments[a] -= (s.point - ca).cross(f);
            }
        }
        let bits = |v: &[DVec3]| -> Vec<[u64; 3]> {
            v.iter().map(|x| x.to_array().map(f64::to_bits)).collect()
        };
        for ranges in [1, 2, 3, 7, 40, 41, 100] {
            let (mut f, mut m): (Vec<DVec3>, Vec<DVec3>) =
                start.iter().map(|&[f, m]| (f, m)).unzip();
            add_contact_forces_in(ranges, &contacts, &poses, &mut f, &mut m);
            assert_eq!(bits(&f), bits(&forces), "{ranges} ranges");
            assert_eq!(bits(&m), bits(&moments), "{ranges} ranges");
        }
        // And on thread pools of 1 to 3 threads, as the step calls it.
        for threads in 1..=3 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let (mut f, mut m): (Vec<DVec3>, Vec<DVec3>) =
                start.iter().map(|&[f, m]| (f, m)).unzip();
            pool.install(|| add_contact_forces(&contacts, &poses, &mut f, &mut m));
            assert_eq!(bits(&f), bits(&forces), "{threads} threads");
            assert_eq!(bits(&m), bits(&moments), "{threads} threads");
        }
    }

    #[test]
    fn a_simulation_of_no_blocks_is_refused() {
        let empty = BlockSystem::new(Vec::new());
        assert_eq!(
            Simulation::new(&empty, 2500.0).unwrap_err(),
            MechanicsError::NoBlocks
        );
    }

    #[test]
    fn the_timings_count_every_step_and_its_parts() {
        let base = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
        let cube = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]).unwrap();
        let mut sim = Simulation::new(&BlockSystem::new(vec![base, cube]), 2500.0).unwrap();
        sim.fix(0).unwrap();
        sim.cycle(5).unwrap();
        let t = sim.timings();
        assert_eq!((t.steps, t.rebuilds), (5, 1));
        let parts = [
            t.pairs,
            t.detect,
            t.contacts,
            t.forces,
            t.integration,
            t.placement,
        ];
        assert!(parts.iter().all(|&s| s >= 0.0));
        assert_eq!(t.total(), parts.iter().sum::<f64>());
        sim.reset_timings();
        assert_eq!(sim.timings(), StepTimings::default());
    }

    /// A unit cube from height `z` over a fixed base, with a velocity and a spin.
    fn thrown_cube(z: f64, velocity: DVec3, spin: DVec3) -> Simulation {
        let base = ConvexBlock::cuboid([-3.0, -3.0, -1.0], [3.0, 3.0, 0.0]).unwrap();
        let cube = ConvexBlock::cuboid([-0.5, -0.5, z], [0.5, 0.5, z + 1.0]).unwrap();
        let mut sim = Simulation::new(&BlockSystem::new(vec![base, cube]), 2500.0).unwrap();
        sim.fix(0).unwrap();
        sim.set_velocity(1, velocity, spin).unwrap();
        sim.set_update_fraction(0.1).unwrap();
        sim
    }

    #[test]
    fn the_pairs_are_rebuilt_when_a_body_may_have_passed_half_the_skin() {
        // Flying and spinning, 2 m above the base.
        let v = DVec3::new(2.0, 1.0, -1.0);
        let mut sim = thrown_cube(2.0, v, DVec3::new(1.0, -2.0, 4.0));
        // The rule, from the poses alone: rebuilt at the first step, then at each step that
        // starts with a body whose motion bound since the last build exceeds half the skin
        // (0.05 of the mean box diagonal).
        let sizes = [(6.0f64 * 6.0 * 2.0 + 1.0).sqrt(), 3f64.sqrt()];
        let half = 0.5 * 0.05 * (sizes[0] + sizes[1]) / 2.0;
        let radius = 0.5 * 3f64.sqrt();
        let mut built: Option<Vec<Pose>> = None;
        let mut expected = Vec::new();
        let mut found = Vec::new();
        for step in 0..1000 {
            let poses = sim.bodies().poses().to_vec();
            let stale = built.as_ref().is_none_or(|b| {
                (0..2).any(|i| {
                    let r = if i == 0 { 0.0 } else { radius };
                    // The base's radius does not matter: it never moves.
                    b[i].displacement_bound(&poses[i], DVec3::ZERO, r) > half
                })
            });
            if stale {
                expected.push(step);
                built = Some(poses);
            }
            let before = sim.timings().rebuilds;
            sim.step().unwrap();
            if sim.timings().rebuilds > before {
                found.push(step);
            }
        }
        // Some 0.9 m of motion bound in 1000 steps (0.14 s), half the skin 0.13 m.
        assert!(expected.len() >= 4, "{expected:?}");
        assert_eq!(found, expected);
    }

    #[test]
    fn the_placed_parts_are_those_placed_at_once_at_the_bodies_poses() {
        // Sliding and turning on the base.
        let mut sim = thrown_cube(0.0, DVec3::new(1.0, 0.5, 0.0), DVec3::new(0.0, 0.0, 0.5));
        for _ in 0..400 {
            sim.step().unwrap();
            // The cube moved at every step and was placed; it is queried only at some.
            let placed = sim.placed_system();
            for (b, block) in placed.blocks().iter().enumerate() {
                let pose = sim.bodies().poses()[b];
                let part = &sim.bodies().shape(b).parts()[0];
                let expected = part.transformed(pose.rotation, pose.translation, 1.0);
                crate::block::assert_same_placed(block, &expected);
            }
        }
        // Some steps left the cube's placing incomplete (carried contact, no query).
        assert!(sim.timings().carried > 100, "{:?}", sim.timings());
        assert!(sim.complete.iter().any(|&c| !c));
    }

    /// The bytes docs/mechanics.md ("Memory") states: a body's state, a contact and a
    /// sub-contact.
    #[test]
    fn the_memory_figures_of_the_docs_hold() {
        use std::mem::size_of;
        // One entry per array of `Bodies` (the side tables hold only the bodies with a
        // prescribed motion or an applied force).
        let body = size_of::<std::sync::Arc<crate::body::Shape>>() // shape
            + size_of::<f64>() // density
            + size_of::<Pose>()
            + 2 * size_of::<DVec3>() // velocity, angular momentum
            + size_of::<f64>(); // mass-scaling factor, signed by the fixity
        assert_eq!(body, 128);
        assert_eq!(size_of::<BodyContact>(), 64);
        assert_eq!(size_of::<SubContact>(), 112);
        // Per candidate pair (docs/mechanics.md, "Memory"): the memo and, apart, the frame
        // of its certificate (a separated pair's or a dormant contact's, and its tag).
        assert_eq!(size_of::<PairMemo>(), 40);
        assert_eq!(size_of::<Frame>(), 120);
        // A face-face contact of two quadrilaterals: within the issue's 512 bytes (an
        // initial stress adds 8 per sub-contact in a side table, in the runs that have one).
        assert_eq!(size_of::<BodyContact>() + 4 * size_of::<SubContact>(), 512);
        // The contact updates: per candidate pair; per body, `moved_at`, `travel`, `last_step`.
        assert_eq!(size_of::<PairMemo>(), 40);
    }
}
