//! Restart files: the whole state of a [`Simulation`] as a versioned JSON file, written
//! atomically, from which a run continues bit for bit as if it had not stopped
//! (docs/mechanics.md, "Restart files").
//!
//! What a step reads is in the file: the bodies' shapes (body-frame parts, bit for bit) and
//! state, the joint properties and every setting, the contacts with their sub-contacts'
//! forces, shear histories and states, the candidate pairs and the poses they were built
//! at, the clock and the flags of the leapfrog. What a step derives from them (the parts
//! placed at the poses, masses and inertias, the stiffness bounds) is recomputed by the same
//! code, with the same result. Numbers are written in the shortest form that reads back to
//! the same `f64` (serde_json's `float_roundtrip`).
//!
//! Each struct goes through one function each way (`*_file` and `*_of`) whose struct
//! literal or pattern lists every field: a field added to the simulation, a body, a contact
//! or a sub-contact fails to compile here until the file has it too.

use super::excavation::{Excavation, Relaxation};
use super::{Bodies, BodyContact, Contacts, Damping, Fixity, JointModel, Simulation, SubContact};
use super::{Bolt, BoltElement, BoltState, Bolts, Dowel, Water, WetJoint};
use super::{InitialStress, JointTable, SubState, Synced, SystemLabels};
use crate::block::{ConvexBlock, Edge, FaceOrigin, Pose};
use crate::body::Shape;
use crate::classify::ContactType;
use crate::generation::SetRecord;
use crate::geometry::{Aabb, DVec3, Plane};
use crate::io::json::{self as blocks_json, record_of};
use crate::io::{read_text, write_atomic, IoError};
use crate::tolerance::Tolerance;
use glam::DQuat;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;
use std::sync::Arc;

/// The value of the `format` field of a restart file.
pub const FORMAT: &str = "penedge-state";
/// The version of the restart file written (and the only one read).
pub const VERSION: u32 = 1;

type V3 = [f64; 3];

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StateFile {
    format: String,
    version: u32,
    settings: SettingsFile,
    clock: ClockFile,
    shapes: Vec<ShapeFile>,
    bodies: Vec<BodyFile>,
    /// Per block of the system the simulation was made of, its body (absent in files
    /// written before penedge stored it: per part, in body order).
    #[serde(default)]
    block_bodies: Vec<u32>,
    contacts: Vec<ContactFile>,
    /// Per body, the sum of its contact forces and moments at the last step.
    forces: Vec<V3>,
    moments: Vec<V3>,
    excavation: ExcavationFile,
    /// The rock bolts with the state of their elements (absent in files written before
    /// penedge stored bolts: none).
    #[serde(default)]
    bolts: Vec<BoltFile>,
    /// The simulation's joint sets ([`Simulation::joint_sets`]: with those of the faces,
    /// the entries of a generated system's spec that cut no block), increasing (absent in
    /// files written before penedge stored them: the faces' sets and those with properties).
    #[serde(default)]
    sets: Vec<u32>,
    /// What the simulation keeps of the system it was made of ([`SystemLabels`]: its spec
    /// entries, unit and body ids; absent in files written before 2026-11-29: none known).
    #[serde(default)]
    system: SystemFile,
    /// The wet joints ([`WetJoint`]: the face-face contacts carrying water and the joints
    /// opened beyond the detection gap that keep it), sorted by parts (absent in files
    /// written before 2026-11-29: none, and an opened joint's water is lost at the restart).
    #[serde(default)]
    wet: Vec<WetJointFile>,
    /// Free text for the caller (`penedge simulate` keeps where its run stands there).
    note: Option<String>,
}

/// A wet joint ([`WetJoint`]) in a restart file: its force is computed again at the next
/// step.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WetJointFile {
    parts: [u32; 2],
    faces: [u32; 2],
    set: Option<u32>,
    opened: bool,
}

#[derive(Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SystemFile {
    /// Per entry of the generation spec, its `name` and `kind` (empty: not known).
    #[serde(default)]
    sets: Vec<SetRecord>,
    /// The joint table, as a block file has it (empty: not known, or none).
    #[serde(default)]
    joints: Vec<blocks_json::JointFile>,
    /// The length unit (`null`: not named, or not known).
    #[serde(default)]
    unit: Option<String>,
    /// Per block, its body id in the system (empty: not known).
    #[serde(default)]
    body_ids: Vec<u32>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ExcavationFile {
    /// The bodies excavated, increasing.
    removed: Vec<u32>,
    relaxations: Vec<RelaxationFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RelaxationFile {
    steps: u64,
    done: u64,
    bodies: Vec<u32>,
    forces: Vec<V3>,
    moments: Vec<V3>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SettingsFile {
    gravity: V3,
    damping: DampingFile,
    tolerance: Tolerance,
    point_width: f64,
    skin: f64,
    /// The time step set (`null`: automatic, `safety` × critical).
    timestep: Option<f64>,
    safety: f64,
    joints: JointsFile,
    /// The intact rock's properties over rock bridges: `default` (`null`: none set) and
    /// per set.
    bridges: BridgesFile,
    /// The stress the first step installs (`null`: none).
    initial_stress: Option<StressFile>,
    /// Every candidate pair queried at every step (a switch for comparisons).
    full_detection: bool,
    /// The update tolerance of touching pairs, a fraction of their detection gap
    /// (`Simulation::set_update_fraction`; absent in older files: the default).
    #[serde(default = "default_update_fraction")]
    update_fraction: f64,
    /// Whether carried open contacts may stay dormant (`Simulation::set_dormant_contacts`;
    /// absent in older files: on, the default).
    #[serde(default = "default_dormant_contacts")]
    dormant_contacts: bool,
    /// Whether mass scaling is on (`Simulation::set_mass_scaling`; absent in older files:
    /// on when some body's `scale` is above 1, off otherwise).
    #[serde(default)]
    mass_scaling: Option<bool>,
    /// Applied moments (world frame): `[body, [x, y, z]]` per body that has one.
    applied_moments: Vec<(u32, V3)>,
    /// The water in the joints (absent in files written before penedge stored water: dry).
    #[serde(default)]
    water: WaterFile,
}

#[derive(Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WaterFile {
    /// The phreatic surface (`null`: none).
    #[serde(default)]
    surface: Option<SurfaceFile>,
    /// Uniform pressures per joint set, by increasing set.
    #[serde(default)]
    sets: Vec<SetPressureFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SurfaceFile {
    /// A point on the surface.
    point: V3,
    /// Its unit normal, upward.
    normal: V3,
    /// The unit weight of water `ρw g`.
    unit_weight: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SetPressureFile {
    set: u32,
    pressure: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoltFile {
    collar: V3,
    direction: V3,
    length: f64,
    stiffness: f64,
    capacity: f64,
    /// `null`: it never breaks.
    rupture_strain: Option<f64>,
    /// `null`: axial only.
    dowel: Option<DowelFile>,
    /// Its elements, in order along it.
    elements: Vec<ElementFile>,
}

#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DowelFile {
    stiffness: f64,
    capacity: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ElementFile {
    bodies: [u32; 2],
    /// The anchors in their bodies' frames.
    anchors: [V3; 2],
    /// Length at installation.
    rest: f64,
    stiffness: f64,
    capacity: f64,
    /// Rupture strain (`null`: none).
    rupture: Option<f64>,
    /// Plastic elongation.
    plastic: f64,
    elongation: f64,
    force: f64,
    state: BoltStateCode,
    /// The dowel (stiffness 0: none), the crossing in both bodies' frames, its plastic slip
    /// and its shear force on the second body.
    dowel: DowelFile,
    crossing: [V3; 2],
    slip: V3,
    shear: V3,
}

#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum BoltStateCode {
    Elastic,
    Yielding,
    Broken,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StressFile {
    base: [f64; 6],
    per_depth: [f64; 6],
    surface: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DampingFile {
    local: f64,
    viscous: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointsFile {
    default: JointFile,
    sets: Vec<SetJointFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BridgesFile {
    default: Option<JointFile>,
    sets: Vec<SetJointFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SetJointFile {
    set: u32,
    model: JointFile,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointFile {
    kn: f64,
    ks: f64,
    friction: f64,
    cohesion: f64,
    tension: f64,
    residual_friction: Option<f64>,
    residual_cohesion: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ClockFile {
    time: f64,
    steps: u64,
    /// The unbalanced-force ratio of the last step (`null`: none yet, infinite).
    ratio: Option<f64>,
    /// Every body's velocity at the whole step (the next step starts with a half kick).
    synced: bool,
    /// Else these bodies' (their velocities set since the last step); absent when none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    synced_bodies: Vec<u32>,
    /// The next detection is the first (its touching sub-contacts get bonds).
    initial: bool,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ShapeFile {
    parts: Vec<PartFile>,
    volume: f64,
    moments: V3,
    radius: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PartFile {
    vertices: Vec<V3>,
    faces: Vec<Vec<u32>>,
    /// Per face, the outward unit normal and a point.
    planes: Vec<[f64; 6]>,
    origins: Vec<FaceOrigin>,
    /// Per edge, its two vertices and its two faces.
    edges: Vec<[u32; 4]>,
    volume: f64,
    centroid: V3,
    /// The largest distance of a face vertex off its plane, relative to the part's box
    /// diagonal, the part was made with (the check on reading allows twice it).
    flatness: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyFile {
    shape: u32,
    density: f64,
    pose: PoseFile,
    velocity: V3,
    /// Angular momentum, world frame.
    momentum: V3,
    fixity: FixityFile,
    applied: V3,
    /// Mass-scaling factor.
    scale: f64,
}

#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseFile {
    /// Unit quaternion `[x, y, z, w]`.
    rotation: [f64; 4],
    translation: V3,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum FixityFile {
    Free,
    Fixed,
    Prescribed { velocity: V3, spin: V3 },
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ContactFile {
    parts: [u32; 2],
    bodies: [u32; 2],
    kind: KindFile,
    normal: V3,
    set: Option<u32>,
    /// Over a rock bridge (the bridge properties of `set` apply).
    bridge: bool,
    subs: Vec<SubFile>,
}

#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum KindFile {
    VertexVertex,
    VertexEdge,
    EdgeEdge,
    EdgeEdgeSuperposition,
    VertexFace,
    EdgeFace,
    FaceFace,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SubFile {
    point: V3,
    local: V3,
    area: f64,
    gap: f64,
    normal_force: f64,
    shear_force: V3,
    shear_displacement: V3,
    state: StateCode,
    bonded: bool,
    prestress: f64,
}

#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum StateCode {
    Elastic,
    Sliding,
    Open,
}

fn default_dormant_contacts() -> bool {
    true
}

fn default_update_fraction() -> f64 {
    super::DEFAULT_UPDATE_FRACTION
}

/// Only the header, to say what a file that is not a restart file is.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u32>,
}

impl Simulation {
    /// Writes the whole state to `path` (a restart file, docs/mechanics.md "Restart
    /// files"): atomically, through a temporary file in the same folder renamed over
    /// `path`, so that a crash leaves the old file or the new one, never half of one.
    pub fn save_state(&self, path: &Path) -> Result<(), IoError> {
        self.save_state_noted(path, None)
    }

    /// [`Simulation::save_state`] with a free text `note` stored in the file for the
    /// caller ([`Simulation::load_state_noted`] gives it back).
    pub fn save_state_noted(&self, path: &Path, note: Option<&str>) -> Result<(), IoError> {
        let mut file = file_of(self);
        file.note = note.map(str::to_string);
        write_atomic(path, |w: &mut dyn Write| {
            serde_json::to_writer(&mut *w, &file).map_err(std::io::Error::other)?;
            w.write_all(b"\n")
        })
    }

    /// The whole state as a JSON string (the content of [`Simulation::save_state`]'s file).
    pub fn to_state_string(&self) -> Result<String, IoError> {
        Ok(serde_json::to_string(&file_of(self)).expect("plain data always serialises"))
    }

    /// A simulation read back from a restart file: its next step is the one the saved
    /// simulation would have taken, bit for bit. A file that is not a restart file, of
    /// another version, cut short or with a bad field is an error naming the field.
    pub fn load_state(path: &Path) -> Result<Simulation, IoError> {
        Simulation::load_state_noted(path).map(|(sim, _)| sim)
    }

    /// [`Simulation::load_state`] with the note the file was saved with.
    pub fn load_state_noted(path: &Path) -> Result<(Simulation, Option<String>), IoError> {
        let text = read_text(path)?;
        Simulation::from_state_str_noted(&text).map_err(|e| match e {
            IoError::Syntax { message, .. } => IoError::Syntax {
                path: path.to_path_buf(),
                message,
            },
            IoError::Format { field, message } => IoError::Syntax {
                path: path.to_path_buf(),
                message: format!("field `{field}`: {message}"),
            },
            other => other,
        })
    }

    /// [`Simulation::load_state`] from a string.
    pub fn from_state_str(text: &str) -> Result<Simulation, IoError> {
        Simulation::from_state_str_noted(text).map(|(sim, _)| sim)
    }

    fn from_state_str_noted(text: &str) -> Result<(Simulation, Option<String>), IoError> {
        let mut file: StateFile = serde_json::from_str(text).map_err(|e| syntax_error(text, e))?;
        check_header(Some(&file.format), Some(file.version))?;
        let note = file.note.take();
        Ok((simulation_of(file)?, note))
    }
}

fn bad(field: impl Into<String>, message: impl Into<String>) -> IoError {
    IoError::Format {
        field: field.into(),
        message: message.into(),
    }
}

/// What is wrong with a file serde could not read: its header if that is wrong (another
/// kind of file, another version), else what the parser said (cut short, a bad field).
fn syntax_error(text: &str, e: serde_json::Error) -> IoError {
    let header = serde_json::from_str::<Header>(text).ok();
    if let Some(h) = &header {
        if let Err(wrong) = check_header(h.format.as_deref(), h.version) {
            return wrong;
        }
    }
    let cut = if e.is_eof() {
        " (the file is cut short: a copy or a write that did not finish?)"
    } else {
        ""
    };
    IoError::Syntax {
        path: "<string>".into(),
        message: format!("not a readable penedge restart file: {e}{cut}"),
    }
}

fn check_header(format: Option<&str>, version: Option<u32>) -> Result<(), IoError> {
    match format {
        Some(FORMAT) => {}
        Some(other) => {
            let msg = format!("this is a `{other}` file, not a restart file (`{FORMAT}`)");
            return Err(bad("format", msg));
        }
        None => {
            return Err(bad(
                "format",
                format!("missing: not a restart file (`{FORMAT}`)"),
            ))
        }
    }
    match version {
        Some(VERSION) => Ok(()),
        Some(v) => Err(bad(
            "version",
            format!("restart files of version {v} cannot be read by this penedge (it reads version {VERSION})"),
        )),
        None => Err(bad("version", "missing")),
    }
}

// ---- writing --------------------------------------------------------------------------

fn file_of(sim: &Simulation) -> StateFile {
    let Simulation {
        bodies,
        block_bodies,
        // Derived from the shapes and poses (recomputed by `Simulation::from_bodies`).
        part_body: _,
        part_index: _,
        placed: _,
        complete: _,
        // Stored whole: the faces' sets come back from the shapes, but not the spec's
        // entries without faces.
        sets,
        joints,
        bridges,
        water,
        bolts,
        gravity,
        damping,
        tolerance,
        point_width,
        // Not saved: a restart's first step computes every contact's shares afresh.
        shares_width: _,
        skin,
        // Caches of the contact update, rebuilt at the first step after loading: the
        // candidate pairs, their last answers and the bodies' travel since. They decide
        // which pairs are queried, never what a query answers: the contacts are the same
        // bit for bit (docs/mechanics.md, "Contact updates").
        pairs: _,
        memo: _,
        frames: _,
        open_frames: _,
        moved_at: _,
        travel: _,
        last_step: _,
        built_at: _,
        skin_passed: _,
        spare: _,
        current: _,
        full_detection,
        update_fraction,
        dormancy,
        applied_moments,
        // Wall-clock diagnostics, not state.
        timings: _,
        contacts,
        forces,
        moments,
        dt,
        safety,
        time,
        steps,
        ratio,
        synced,
        initial,
        excavation,
        initial_stress,
        wet,
        mass_scaling,
        origin,
    } = sim;
    let (shapes, shape_ids) = shape_files(bodies);
    StateFile {
        format: FORMAT.to_string(),
        version: VERSION,
        settings: SettingsFile {
            gravity: gravity.to_array(),
            damping: damping_file(damping),
            tolerance: *tolerance,
            point_width: *point_width,
            skin: *skin,
            timestep: *dt,
            safety: *safety,
            joints: joints_file(joints),
            bridges: BridgesFile {
                default: bridges.default_model().map(joint_file),
                sets: bridges
                    .sets()
                    .map(|(set, m)| SetJointFile {
                        set,
                        model: joint_file(m),
                    })
                    .collect(),
            },
            full_detection: *full_detection,
            update_fraction: *update_fraction,
            dormant_contacts: *dormancy,
            mass_scaling: Some(*mass_scaling),
            applied_moments: applied_moments
                .iter()
                .map(|(&b, m)| (b, m.to_array()))
                .collect(),
            water: water_file(water),
            initial_stress: initial_stress.as_ref().map(|f| {
                let InitialStress {
                    base,
                    per_depth,
                    surface,
                } = *f;
                StressFile {
                    base,
                    per_depth,
                    surface,
                }
            }),
        },
        clock: ClockFile {
            time: *time,
            steps: *steps,
            ratio: ratio.is_finite().then_some(*ratio),
            synced: *synced == Synced::All,
            synced_bodies: match synced {
                Synced::Bodies(set) => set.iter().copied().collect(),
                _ => Vec::new(),
            },
            initial: *initial,
        },
        shapes,
        bodies: (0..bodies.len())
            .map(|i| body_file(bodies, i, shape_ids[i]))
            .collect(),
        block_bodies: block_bodies.clone(),
        contacts: contacts_file(contacts),
        forces: forces.iter().map(|f| f.to_array()).collect(),
        moments: moments.iter().map(|m| m.to_array()).collect(),
        excavation: excavation_file(excavation),
        bolts: bolts_file(bolts),
        sets: sets.iter().copied().collect(),
        system: SystemFile {
            sets: origin.sets.clone(),
            joints: origin
                .joints
                .iter()
                .enumerate()
                .map(blocks_json::joint_file)
                .collect(),
            unit: origin.unit.clone(),
            body_ids: origin.body_ids.clone(),
        },
        wet: wet
            .iter()
            .map(|j| WetJointFile {
                parts: j.parts,
                faces: j.faces,
                set: j.set,
                opened: j.opened,
            })
            .collect(),
        note: None,
    }
}

fn excavation_file(e: &Excavation) -> ExcavationFile {
    let Excavation {
        removed,
        relaxations,
    } = e;
    let rows = |v: &[DVec3]| v.iter().map(|x| x.to_array()).collect();
    ExcavationFile {
        removed: (0..removed.len())
            .filter(|&i| removed[i])
            .map(|i| i as u32)
            .collect(),
        relaxations: relaxations
            .iter()
            .map(|r| {
                let Relaxation {
                    steps,
                    done,
                    bodies,
                    forces,
                    moments,
                } = r;
                RelaxationFile {
                    steps: *steps,
                    done: *done,
                    bodies: bodies.clone(),
                    forces: rows(forces),
                    moments: rows(moments),
                }
            })
            .collect(),
    }
}

fn water_file(w: &Water) -> WaterFile {
    let Water { surface, sets } = w;
    WaterFile {
        surface: surface.map(|(point, normal, unit_weight)| SurfaceFile {
            point: point.to_array(),
            normal: normal.to_array(),
            unit_weight,
        }),
        sets: sets
            .iter()
            .map(|(&set, &pressure)| SetPressureFile { set, pressure })
            .collect(),
    }
}

fn bolts_file(bolts: &Bolts) -> Vec<BoltFile> {
    let Bolts {
        specs,
        elements,
        // Derived from the elements (rebuilt by `Bolts::from_stored`).
        stiffness: _,
    } = bolts;
    let dowel_file = |d: Dowel| {
        let Dowel {
            stiffness,
            capacity,
        } = d;
        DowelFile {
            stiffness,
            capacity,
        }
    };
    specs
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let Bolt {
                collar,
                direction,
                length,
                stiffness,
                capacity,
                rupture_strain,
                dowel,
            } = *b;
            BoltFile {
                collar: collar.to_array(),
                direction: direction.to_array(),
                length,
                stiffness,
                capacity,
                rupture_strain,
                dowel: dowel.map(dowel_file),
                elements: elements
                    .iter()
                    .filter(|e| e.bolt as usize == i)
                    .map(|e| element_file(e, dowel_file(e.dowel)))
                    .collect(),
            }
        })
        .collect()
}

fn element_file(e: &BoltElement, dowel: DowelFile) -> ElementFile {
    let BoltElement {
        // The bolt it lies in the file under.
        bolt: _,
        bodies,
        anchors,
        rest,
        stiffness,
        capacity,
        rupture,
        plastic,
        elongation,
        force,
        state,
        dowel: _,
        crossing,
        slip,
        shear,
    } = *e;
    ElementFile {
        bodies,
        anchors: anchors.map(|a| a.to_array()),
        rest,
        stiffness,
        capacity,
        rupture: rupture.is_finite().then_some(rupture),
        plastic,
        elongation,
        force,
        state: match state {
            BoltState::Elastic => BoltStateCode::Elastic,
            BoltState::Yielding => BoltStateCode::Yielding,
            BoltState::Broken => BoltStateCode::Broken,
        },
        dowel,
        crossing: crossing.map(|c| c.to_array()),
        slip: slip.to_array(),
        shear: shear.to_array(),
    }
}

fn damping_file(d: &Damping) -> DampingFile {
    let Damping { local, viscous } = *d;
    DampingFile { local, viscous }
}

fn joint_file(m: &JointModel) -> JointFile {
    let JointModel {
        kn,
        ks,
        friction,
        cohesion,
        tension,
        residual_friction,
        residual_cohesion,
    } = *m;
    JointFile {
        kn,
        ks,
        friction,
        cohesion,
        tension,
        residual_friction,
        residual_cohesion,
    }
}

fn joints_file(joints: &JointTable) -> JointsFile {
    JointsFile {
        default: joint_file(joints.default_model()),
        sets: joints
            .sets()
            .map(|(set, m)| SetJointFile {
                set,
                model: joint_file(m),
            })
            .collect(),
    }
}

/// The distinct shapes (bodies of one shape share it) and each body's shape index.
fn shape_files(bodies: &Bodies) -> (Vec<ShapeFile>, Vec<u32>) {
    let mut index: HashMap<*const Shape, u32> = HashMap::new();
    let mut files = Vec::new();
    let ids = (0..bodies.len())
        .map(|i| {
            let shape = bodies.shape(i);
            *index.entry(Arc::as_ptr(shape)).or_insert_with(|| {
                files.push(shape_file(shape));
                (files.len() - 1) as u32
            })
        })
        .collect();
    (files, ids)
}

fn shape_file(shape: &Shape) -> ShapeFile {
    ShapeFile {
        parts: shape.parts().iter().map(part_file).collect(),
        volume: shape.volume(),
        moments: shape.principal_moments().to_array(),
        radius: shape.radius(),
    }
}

fn part_file(b: &ConvexBlock) -> PartFile {
    let diagonal = b.aabb().diagonal();
    PartFile {
        vertices: b.vertices().iter().map(|v| v.to_array()).collect(),
        faces: b.faces().map(<[u32]>::to_vec).collect(),
        planes: b
            .planes()
            .iter()
            .map(|p| {
                let (n, q) = (p.normal, p.point);
                [n.x, n.y, n.z, q.x, q.y, q.z]
            })
            .collect(),
        origins: b.face_origins().to_vec(),
        edges: b
            .edges()
            .iter()
            .map(|e| [e.vertices[0], e.vertices[1], e.faces[0], e.faces[1]])
            .collect(),
        volume: b.volume(),
        centroid: b.centroid().to_array(),
        flatness: crate::io::json::off_planes(b) / diagonal,
    }
}

/// Body `i` through the accessors of `Bodies` (its fields are private to bodies.rs: a
/// per-body quantity added there needs a line here and in `body_of`). Masses, inertias and
/// stiffness bounds derive from the shape and the density.
fn body_file(bodies: &Bodies, i: usize, shape: u32) -> BodyFile {
    BodyFile {
        shape,
        density: bodies.densities()[i],
        pose: pose_file(&bodies.pose[i]),
        velocity: bodies.velocity[i].to_array(),
        momentum: bodies.momentum[i].to_array(),
        fixity: match bodies.fixity(i) {
            Fixity::Free => FixityFile::Free,
            Fixity::Fixed => FixityFile::Fixed,
            Fixity::Prescribed { velocity, spin } => FixityFile::Prescribed {
                velocity: velocity.to_array(),
                spin: spin.to_array(),
            },
        },
        applied: bodies.applied_force(i).to_array(),
        scale: bodies.mass_scale(i),
    }
}

fn pose_file(p: &Pose) -> PoseFile {
    PoseFile {
        rotation: p.rotation.to_array(),
        translation: p.translation.to_array(),
    }
}

fn contacts_file(contacts: &Contacts) -> Vec<ContactFile> {
    contacts
        .list
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let BodyContact {
                parts,
                bodies,
                kind,
                normal,
                set,
                bridge,
                // Derived from the order of the sub-contacts.
                first: _,
                count: _,
            } = c;
            ContactFile {
                parts: *parts,
                bodies: *bodies,
                kind: kind_file(*kind),
                normal: normal.to_array(),
                set: *set,
                bridge: *bridge,
                subs: contacts
                    .subs_of(i)
                    .iter()
                    .enumerate()
                    .map(|(k, sub)| sub_file(sub, contacts.prestress(c.first as usize + k)))
                    .collect(),
            }
        })
        .collect()
}

fn sub_file(s: &SubContact, prestress: f64) -> SubFile {
    let SubContact {
        point,
        local,
        area,
        gap,
        normal_force,
        shear_force,
        shear_displacement,
        state,
        bonded,
    } = *s;
    SubFile {
        point: point.to_array(),
        local: local.as_dvec3().to_array(),
        area,
        gap,
        normal_force,
        shear_force: shear_force.to_array(),
        shear_displacement: shear_displacement.to_array(),
        state: match state {
            SubState::Elastic => StateCode::Elastic,
            SubState::Sliding => StateCode::Sliding,
            SubState::Open => StateCode::Open,
        },
        bonded,
        prestress,
    }
}

fn kind_file(kind: ContactType) -> KindFile {
    match kind {
        ContactType::VertexVertex => KindFile::VertexVertex,
        ContactType::VertexEdge => KindFile::VertexEdge,
        ContactType::EdgeEdge => KindFile::EdgeEdge,
        ContactType::EdgeEdgeSuperposition => KindFile::EdgeEdgeSuperposition,
        ContactType::VertexFace => KindFile::VertexFace,
        ContactType::EdgeFace => KindFile::EdgeFace,
        ContactType::FaceFace => KindFile::FaceFace,
    }
}

// ---- reading --------------------------------------------------------------------------

fn finite(field: impl Into<String>, v: f64) -> Result<f64, IoError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(bad(field, "must be a finite number"))
    }
}

fn vec3(field: impl Into<String>, v: V3) -> Result<DVec3, IoError> {
    let out = DVec3::from_array(v);
    if out.is_finite() {
        Ok(out)
    } else {
        Err(bad(field, "must have finite components"))
    }
}

/// A pose as stored: a unit quaternion (kept as it is, not normalised again: a resumed
/// run needs the same bits) and a translation.
fn pose_of(field: &str, p: &PoseFile) -> Result<Pose, IoError> {
    let rotation = DQuat::from_array(p.rotation);
    let translation = vec3(format!("{field}.translation"), p.translation)?;
    if !(rotation.is_finite() && (rotation.length_squared() - 1.0).abs() <= 1e-12) {
        return Err(bad(
            format!("{field}.rotation"),
            format!(
                "must be a unit quaternion [x, y, z, w], got {:?}",
                p.rotation
            ),
        ));
    }
    Ok(Pose {
        rotation,
        translation,
    })
}

fn mechanics(field: impl Into<String>) -> impl FnOnce(super::MechanicsError) -> IoError {
    let field = field.into();
    move |e| bad(field, e.to_string())
}

fn joint_of(field: &str, f: &JointFile) -> Result<JointModel, IoError> {
    let JointFile {
        kn,
        ks,
        friction,
        cohesion,
        tension,
        residual_friction,
        residual_cohesion,
    } = *f;
    JointModel {
        kn,
        ks,
        friction,
        cohesion,
        tension,
        residual_friction,
        residual_cohesion,
    }
    .validated()
    .map_err(mechanics(field))
}

fn shape_of(i: usize, f: &ShapeFile) -> Result<Shape, IoError> {
    let field = format!("shapes[{i}]");
    let parts = f
        .parts
        .iter()
        .enumerate()
        .map(|(k, p)| part_of(&format!("{field}.parts[{k}]"), p))
        .collect::<Result<Vec<_>, _>>()?;
    let moments = vec3(format!("{field}.moments"), f.moments)?;
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(bad(
                format!("{field}.{name}"),
                "must be a finite number > 0",
            ))
        }
    };
    positive("volume", f.volume)?;
    positive("radius", f.radius)?;
    if moments.min_element() <= 0.0 {
        return Err(bad(format!("{field}.moments"), "must be > 0"));
    }
    Shape::from_stored(parts, f.volume, moments, f.radius).map_err(|e| bad(field, e.to_string()))
}

fn part_of(field: &str, f: &PartFile) -> Result<ConvexBlock, IoError> {
    let planes: Vec<Plane> = f
        .planes
        .iter()
        .map(|p| Plane {
            normal: DVec3::new(p[0], p[1], p[2]),
            point: DVec3::new(p[3], p[4], p[5]),
        })
        .collect();
    let flatness = finite(format!("{field}.flatness"), f.flatness)?;
    let length = (2.0 * flatness).max(Tolerance::default().length());
    let tol = Tolerance::new(0.0, length.min(0.5 * crate::tolerance::MAX_LENGTH))
        .map_err(|e| bad(format!("{field}.flatness"), e.to_string()))?;
    let block = ConvexBlock::from_parts(&f.vertices, &f.faces, &planes, &f.origins, &tol)
        .map_err(|e| bad(field, e.to_string()))?;
    let edges = f
        .edges
        .iter()
        .map(|e| Edge {
            vertices: [e[0], e[1]],
            faces: [e[2], e[3]],
        })
        .collect();
    let centroid = vec3(format!("{field}.centroid"), f.centroid)?;
    let within = Aabb::of_points(block.vertices());
    if centroid.cmplt(within.min).any() || centroid.cmpgt(within.max).any() {
        return Err(bad(format!("{field}.centroid"), "lies outside the part"));
    }
    block
        .with_stored(edges, f.volume, centroid)
        .map_err(|e| bad(field, e))
}

fn body_of(
    bodies: &mut Bodies,
    i: usize,
    f: &BodyFile,
    shapes: &[Arc<Shape>],
) -> Result<(), IoError> {
    let field = |name: &str| format!("bodies[{i}].{name}");
    let shape = shapes.get(f.shape as usize).ok_or_else(|| {
        let msg = format!("no shape {}: the file has {}", f.shape, shapes.len());
        bad(field("shape"), msg)
    })?;
    if !(f.density.is_finite() && f.density > 0.0) {
        return Err(bad(field("density"), "must be a finite number > 0"));
    }
    let pose = pose_of(&field("pose"), &f.pose)?;
    let id = bodies
        .push(shape.clone(), pose, f.density)
        .map_err(mechanics(field("pose")))?;
    if !(f.scale.is_finite() && f.scale >= 1.0) {
        return Err(bad(field("scale"), "must be a finite number >= 1"));
    }
    bodies.set_scale(id, f.scale);
    let fixity = match f.fixity {
        FixityFile::Free => Fixity::Free,
        FixityFile::Fixed => Fixity::Fixed,
        FixityFile::Prescribed { velocity, spin } => Fixity::Prescribed {
            velocity: vec3(field("fixity.velocity"), velocity)?,
            spin: vec3(field("fixity.spin"), spin)?,
        },
    };
    bodies
        .set_fixity(id, fixity)
        .map_err(mechanics(field("fixity")))?;
    bodies
        .set_applied(id, vec3(field("applied"), f.applied)?)
        .map_err(mechanics(field("applied")))?;
    // Last: the state as it was (`set_scale` rescales the momentum).
    bodies.velocity[id] = vec3(field("velocity"), f.velocity)?;
    bodies.momentum[id] = vec3(field("momentum"), f.momentum)?;
    Ok(())
}

/// Two part ids of a file's pair list (contacts, wet joints), smaller first and below
/// `n`, after the list's `last` (sorted by parts, one entry per pair).
fn check_parts(
    parts: [u32; 2],
    last: Option<[u32; 2]>,
    n: usize,
    what: &str,
    field: &str,
) -> Result<(), IoError> {
    let [p, q] = parts;
    if !(p < q && (q as usize) < n) {
        let msg = format!("must be two part ids, smaller first, below {n}; got {parts:?}");
        return Err(bad(field, msg));
    }
    if last.is_some_and(|last| last >= parts) {
        return Err(bad(
            field,
            format!("{what} must be sorted by their parts, one per pair"),
        ));
    }
    Ok(())
}

/// The wet joints of a file: two parts, smaller first, and a face of each that exists,
/// sorted by parts.
fn wet_of(files: &[WetJointFile], placed: &[ConvexBlock]) -> Result<Vec<WetJoint>, IoError> {
    let mut out: Vec<WetJoint> = Vec::with_capacity(files.len());
    for (i, f) in files.iter().enumerate() {
        let field = |name: &str| format!("wet[{i}].{name}");
        let last = out.last().map(|j| j.parts);
        check_parts(f.parts, last, placed.len(), "wet joints", &field("parts"))?;
        for (k, (&part, &face)) in f.parts.iter().zip(&f.faces).enumerate() {
            let faces = placed[part as usize].n_faces();
            if face as usize >= faces {
                let msg = format!("part {part} has {faces} faces; got face {face}");
                return Err(bad(field(&format!("faces[{k}]")), msg));
            }
        }
        out.push(WetJoint {
            parts: f.parts,
            faces: f.faces,
            set: f.set,
            opened: f.opened,
            force: 0.0,
            normal: DVec3::ZERO,
            centre: DVec3::ZERO,
        });
    }
    Ok(out)
}

fn contacts_of(files: &[ContactFile], part_body: &[u32]) -> Result<Contacts, IoError> {
    let mut out = Contacts::default();
    for (i, f) in files.iter().enumerate() {
        let field = |name: &str| format!("contacts[{i}].{name}");
        let last = out.list.last().map(|c| c.parts);
        check_parts(f.parts, last, part_body.len(), "contacts", &field("parts"))?;
        let [p, q] = f.parts;
        let bodies = [part_body[p as usize], part_body[q as usize]];
        if f.bodies != bodies {
            let msg = format!("must be the parts' bodies {bodies:?}, got {:?}", f.bodies);
            return Err(bad(field("bodies"), msg));
        }
        let normal = vec3(field("normal"), f.normal)?;
        if (normal.length_squared() - 1.0).abs() > 1e-9 {
            return Err(bad(field("normal"), "must be a unit vector"));
        }
        if f.subs.is_empty() {
            return Err(bad(field("subs"), "a contact has at least one sub-contact"));
        }
        let first = out.subs.len() as u32;
        for (k, s) in f.subs.iter().enumerate() {
            let field = format!("contacts[{i}].subs[{k}]");
            out.subs.push(sub_of(&field, s)?);
            out.prestresses
                .push(finite(format!("{field}.prestress"), s.prestress)?);
        }
        out.list.push(BodyContact {
            parts: f.parts,
            bodies,
            kind: kind_of(f.kind),
            normal,
            set: f.set,
            bridge: f.bridge,
            first,
            count: f.subs.len() as u32,
        });
    }
    // The side table only when a sub-contact has an installed stress, as a step leaves it.
    if out.prestresses.iter().all(|&p| p == 0.0) {
        out.prestresses.clear();
    }
    Ok(out)
}

fn sub_of(field: &str, s: &SubFile) -> Result<SubContact, IoError> {
    let v = |name: &str, x: V3| vec3(format!("{field}.{name}"), x);
    let x = |name: &str, x: f64| finite(format!("{field}.{name}"), x);
    Ok(SubContact {
        point: v("point", s.point)?,
        local: v("local", s.local)?.as_vec3(),
        area: x("area", s.area)?,
        gap: x("gap", s.gap)?,
        normal_force: x("normal_force", s.normal_force)?,
        shear_force: v("shear_force", s.shear_force)?,
        shear_displacement: v("shear_displacement", s.shear_displacement)?,
        state: match s.state {
            StateCode::Elastic => SubState::Elastic,
            StateCode::Sliding => SubState::Sliding,
            StateCode::Open => SubState::Open,
        },
        bonded: s.bonded,
    })
}

fn water_of(f: &WaterFile) -> Result<Water, IoError> {
    let WaterFile { surface, sets } = f;
    let mut water = Water::none();
    if let Some(s) = surface {
        let field = |name: &str| format!("settings.water.surface.{name}");
        let point = vec3(field("point"), s.point)?;
        let normal = vec3(field("normal"), s.normal)?;
        if (normal.length_squared() - 1.0).abs() > 1e-9 || normal.z <= 0.0 {
            return Err(bad(field("normal"), "must be a unit vector with z > 0"));
        }
        // The checks of the setter; then the stored values as they are (the setter would
        // normalise the normal again, which need not give the same bits).
        Water::phreatic(point, normal, s.unit_weight)
            .map_err(mechanics("settings.water.surface"))?;
        water.surface = Some((point, normal, s.unit_weight));
    }
    for (k, p) in sets.iter().enumerate() {
        let field = format!("settings.water.sets[{k}]");
        if k > 0 && sets[k - 1].set >= p.set {
            return Err(bad(field, "the sets must be increasing"));
        }
        water = water
            .with_set_pressure(p.set, p.pressure)
            .map_err(mechanics(field))?;
    }
    Ok(water)
}

/// The bolts of a file with `n` bodies; `excavated`: whether it has removed bodies (only
/// then may a bolt have no element left).
fn bolts_of(files: &[BoltFile], n: usize, excavated: bool) -> Result<Bolts, IoError> {
    let mut specs = Vec::with_capacity(files.len());
    let mut elements = Vec::new();
    for (i, f) in files.iter().enumerate() {
        let field = |name: &str| format!("bolts[{i}].{name}");
        let dowel_of = |d: DowelFile| Dowel {
            stiffness: d.stiffness,
            capacity: d.capacity,
        };
        specs.push(Bolt {
            collar: vec3(field("collar"), f.collar)?,
            direction: vec3(field("direction"), f.direction)?,
            length: f.length,
            stiffness: f.stiffness,
            capacity: f.capacity,
            rupture_strain: f.rupture_strain,
            dowel: f.dowel.map(dowel_of),
        });
        // A bolt is installed across two bodies at least; it has no element left only when
        // excavation ended every one (each anchored in removed rock).
        if f.elements.is_empty() && !excavated {
            return Err(bad(
                field("elements"),
                "a bolt has at least one element (none only once excavation removed the rock \
                 they were anchored in, and no body is removed)",
            ));
        }
        for (k, e) in f.elements.iter().enumerate() {
            let field = format!("bolts[{i}].elements[{k}]");
            elements.push(element_of(&field, i as u32, e, n, dowel_of(e.dowel))?);
        }
    }
    Bolts::from_stored(specs, elements).map_err(|(i, e)| bad(format!("bolts[{i}]"), e.to_string()))
}

fn element_of(
    field: &str,
    bolt: u32,
    f: &ElementFile,
    n: usize,
    dowel: Dowel,
) -> Result<BoltElement, IoError> {
    let name = |name: &str| format!("{field}.{name}");
    let [a, b] = f.bodies;
    if a == b || a as usize >= n || b as usize >= n {
        let msg = format!("must be two distinct bodies below {n}, got {:?}", f.bodies);
        return Err(bad(name("bodies"), msg));
    }
    let positive = |key: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(bad(name(key), "must be a finite number > 0"))
        }
    };
    let not_negative = |key: &str, v: f64| {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(bad(name(key), "must be a finite number >= 0"))
        }
    };
    let v = |key: &str, x: V3| vec3(name(key), x);
    let x = |key: &str, x: f64| finite(name(key), x);
    Ok(BoltElement {
        bolt,
        bodies: f.bodies,
        anchors: [
            v("anchors[0]", f.anchors[0])?,
            v("anchors[1]", f.anchors[1])?,
        ],
        rest: positive("rest", f.rest)?,
        stiffness: positive("stiffness", f.stiffness)?,
        capacity: positive("capacity", f.capacity)?,
        rupture: match f.rupture {
            None => f64::INFINITY,
            Some(r) => positive("rupture", r)?,
        },
        plastic: x("plastic", f.plastic)?,
        elongation: x("elongation", f.elongation)?,
        force: x("force", f.force)?,
        state: match f.state {
            BoltStateCode::Elastic => BoltState::Elastic,
            BoltStateCode::Yielding => BoltState::Yielding,
            BoltStateCode::Broken => BoltState::Broken,
        },
        dowel: Dowel {
            stiffness: not_negative("dowel.stiffness", dowel.stiffness)?,
            capacity: not_negative("dowel.capacity", dowel.capacity)?,
        },
        crossing: [
            v("crossing[0]", f.crossing[0])?,
            v("crossing[1]", f.crossing[1])?,
        ],
        slip: v("slip", f.slip)?,
        shear: v("shear", f.shear)?,
    })
}

fn kind_of(kind: KindFile) -> ContactType {
    match kind {
        KindFile::VertexVertex => ContactType::VertexVertex,
        KindFile::VertexEdge => ContactType::VertexEdge,
        KindFile::EdgeEdge => ContactType::EdgeEdge,
        KindFile::EdgeEdgeSuperposition => ContactType::EdgeEdgeSuperposition,
        KindFile::VertexFace => ContactType::VertexFace,
        KindFile::EdgeFace => ContactType::EdgeFace,
        KindFile::FaceFace => ContactType::FaceFace,
    }
}

fn excavation_of(f: &ExcavationFile, n: usize) -> Result<Excavation, IoError> {
    let mut out = Excavation::default();
    if !f.removed.is_empty() {
        out.removed = vec![false; n];
    }
    for (k, &i) in f.removed.iter().enumerate() {
        let field = format!("excavation.removed[{k}]");
        match out.removed.get_mut(i as usize) {
            Some(r) if !*r => *r = true,
            Some(_) => return Err(bad(field, format!("body {i} is listed twice"))),
            None => return Err(bad(field, format!("no body {i}: the file has {n}"))),
        }
    }
    for (k, r) in f.relaxations.iter().enumerate() {
        let field = format!("excavation.relaxations[{k}]");
        if r.done >= r.steps {
            let msg = format!("`done` ({}) must be below `steps` ({})", r.done, r.steps);
            return Err(bad(field, msg));
        }
        let m = r.bodies.len();
        if let Some(&b) = r.bodies.iter().find(|&&b| b as usize >= n) {
            return Err(bad(
                format!("{field}.bodies"),
                format!("no body {b}: the file has {n}"),
            ));
        }
        out.relaxations.push(Relaxation {
            steps: r.steps,
            done: r.done,
            bodies: r.bodies.clone(),
            forces: per_body(&format!("{field}.forces"), &r.forces, m)?,
            moments: per_body(&format!("{field}.moments"), &r.moments, m)?,
        });
    }
    Ok(out)
}

/// A tolerance as stored, if it is one the setters accept.
fn tolerance_of(t: Tolerance) -> Result<Tolerance, IoError> {
    let rebuilt = match t.absolute_gap() {
        None => Tolerance::new(t.gap(), t.length()),
        Some(gap) => Tolerance::new(0.0, t.length()).and_then(|r| r.and_absolute_gap(gap)),
    }
    .map_err(|e| bad("settings.tolerance", e.to_string()))?;
    if rebuilt != t {
        return Err(bad("settings.tolerance", "not a tolerance penedge makes"));
    }
    // As `Simulation::set_gap` refuses it: a contact carries its force by overlapping, up to
    // the gap, so no gap carries no load.
    if t.absolute_gap().unwrap_or(t.gap()) == 0.0 {
        return Err(bad(
            "settings.tolerance",
            "a detection gap of 0: no contact could carry a load (the gap must be > 0)",
        ));
    }
    Ok(t)
}

fn per_body(field: &str, values: &[V3], n: usize) -> Result<Vec<DVec3>, IoError> {
    if values.len() != n {
        let msg = format!("must have one entry per body ({n}), has {}", values.len());
        return Err(bad(field, msg));
    }
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| vec3(format!("{field}[{i}]"), v))
        .collect()
}

/// Whose velocities are at the whole step, from the clock of a file with `n` bodies: all
/// (`synced`), else the bodies listed, by increasing id (as written: the file reads back to
/// the same file).
fn synced_of(c: &ClockFile, n: usize) -> Result<Synced, IoError> {
    let ids = &c.synced_bodies;
    if c.synced {
        return if ids.is_empty() {
            Ok(Synced::All)
        } else {
            Err(bad(
                "clock.synced_bodies",
                "must be absent when clock.synced is true (every body's velocity is at the whole step)",
            ))
        };
    }
    if ids.is_empty() {
        return Ok(Synced::None);
    }
    if let Some(&id) = ids.iter().find(|&&id| id as usize >= n) {
        return Err(bad(
            "clock.synced_bodies",
            format!("body {id} is not one of the {n} bodies"),
        ));
    }
    if ids.windows(2).any(|w| w[0] >= w[1]) {
        return Err(bad("clock.synced_bodies", "must be increasing"));
    }
    Ok(Synced::Bodies(ids.iter().copied().collect()))
}

/// The system labels of a file, `blocks` blocks (its body ids, when given, one per block;
/// its unit, when given, a unit's name as a spec's; its joints checked as a block file's).
fn labels_of(f: SystemFile, blocks: usize) -> Result<SystemLabels, IoError> {
    if !f.body_ids.is_empty() && f.body_ids.len() != blocks {
        let msg = format!(
            "{} ids for the {blocks} blocks: one per block, or none",
            f.body_ids.len()
        );
        return Err(bad("system.body_ids", msg));
    }
    let unit = f
        .unit
        .as_deref()
        .map(crate::generation::check::unit_name)
        .transpose()
        .map_err(|why| bad("system.unit", why))?;
    let sets = f.sets.len();
    let joints = f
        .joints
        .into_iter()
        .enumerate()
        .map(|(i, j)| {
            record_of(i, j, sets).map_err(|e| match e {
                IoError::Format { field, message } => bad(format!("system.{field}"), message),
                other => other,
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(SystemLabels {
        sets: f.sets,
        joints,
        unit,
        body_ids: f.body_ids,
    })
}

/// The block-to-body map of a file: every body of the `n` a block's.
fn block_bodies_of(ids: &[u32], n: usize) -> Result<Vec<u32>, IoError> {
    let mut seen = vec![false; n];
    for (k, &b) in ids.iter().enumerate() {
        let Some(s) = seen.get_mut(b as usize) else {
            let field = format!("block_bodies[{k}]");
            return Err(bad(field, format!("no body {b}: the file has {n}")));
        };
        *s = true;
    }
    if let Some(b) = seen.iter().position(|s| !s) {
        return Err(bad("block_bodies", format!("body {b} has no block")));
    }
    Ok(ids.to_vec())
}

fn simulation_of(mut file: StateFile) -> Result<Simulation, IoError> {
    let shapes = file
        .shapes
        .iter()
        .enumerate()
        .map(|(i, s)| shape_of(i, s).map(Arc::new))
        .collect::<Result<Vec<_>, _>>()?;
    if file.bodies.is_empty() {
        return Err(bad("bodies", "a simulation has at least one body"));
    }
    let mut bodies = Bodies::default();
    for (i, b) in file.bodies.iter().enumerate() {
        body_of(&mut bodies, i, b, &shapes)?;
    }
    let n = bodies.len();
    let mut sim = Simulation::from_bodies(bodies);
    let s = &file.settings;
    let gravity = vec3("settings.gravity", s.gravity)?;
    let damping = Damping {
        local: s.damping.local,
        viscous: s.damping.viscous,
    };
    sim.set_damping(damping)
        .map_err(mechanics("settings.damping"))?;
    sim.set_point_width(s.point_width)
        .map_err(mechanics("settings.point_width"))?;
    sim.set_safety(s.safety)
        .map_err(mechanics("settings.safety"))?;
    let mut joints = JointTable::default();
    joints
        .set_default(joint_of("settings.joints.default", &s.joints.default)?)
        .map_err(mechanics("settings.joints.default"))?;
    for (k, j) in s.joints.sets.iter().enumerate() {
        let field = format!("settings.joints.sets[{k}]");
        joints
            .set(j.set, joint_of(&field, &j.model)?)
            .map_err(mechanics(field))?;
    }
    if !(s.skin.is_finite() && s.skin > 0.0) {
        return Err(bad("settings.skin", "must be a finite number > 0"));
    }
    if let Some(dt) = s.timestep {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(bad(
                "settings.timestep",
                "must be a finite number > 0 or null",
            ));
        }
    }
    let c = &file.clock;
    finite("clock.time", c.time)?;
    if let Some(r) = c.ratio {
        if !(r.is_finite() && r >= 0.0) {
            return Err(bad("clock.ratio", "must be a finite number >= 0 or null"));
        }
    }
    let mut bridge_table = super::bridge::BridgeTable::default();
    if let Some(d) = &s.bridges.default {
        bridge_table
            .set_default(joint_of("settings.bridges.default", d)?)
            .map_err(mechanics("settings.bridges.default"))?;
    }
    for (k, b) in s.bridges.sets.iter().enumerate() {
        let field = format!("settings.bridges.sets[{k}]");
        bridge_table
            .set(b.set, joint_of(&field, &b.model)?)
            .map_err(mechanics(field))?;
    }
    let mut moments_applied = std::collections::BTreeMap::new();
    for (k, &(b, m)) in s.applied_moments.iter().enumerate() {
        let field = format!("settings.applied_moments[{k}]");
        if b as usize >= n {
            return Err(bad(field, format!("no body {b}: the file has {n}")));
        }
        moments_applied.insert(b, vec3(field, m)?);
    }
    let contacts = contacts_of(&file.contacts, &sim.part_body)?;
    let wet = wet_of(&file.wet, &sim.placed)?;
    let forces = per_body("forces", &file.forces, n)?;
    let moments = per_body("moments", &file.moments, n)?;
    let tolerance = tolerance_of(s.tolerance)?;
    let excavation = excavation_of(&file.excavation, n)?;
    let water = water_of(&s.water)?;
    let bolt_set = bolts_of(&file.bolts, n, !file.excavation.removed.is_empty())?;
    let initial_stress = match &s.initial_stress {
        None => None,
        Some(f) => Some(
            InitialStress {
                base: f.base,
                per_depth: f.per_depth,
                surface: f.surface,
            }
            .validated()
            .map_err(mechanics("settings.initial_stress"))?,
        ),
    };
    {
        // Every field of the simulation, so that one added to it is not forgotten here.
        let Simulation {
            bodies: _,
            block_bodies: bb,
            part_body: _,
            part_index: _,
            placed: _,
            complete: _,
            // The faces' sets, found by `from_bodies`, and the file's (the spec's entries
            // without faces).
            sets: st,
            joints: j,
            bridges: br,
            water: w,
            bolts: bo,
            pairs: _,
            memo: _,
            frames: _,
            open_frames: _,
            moved_at: _,
            travel: _,
            last_step: _,
            built_at: _,
            skin_passed: _,
            spare: _,
            current: _,
            full_detection,
            update_fraction,
            dormancy,
            applied_moments,
            timings: _,
            gravity: g,
            damping: _,
            tolerance: t,
            point_width: _,
            shares_width: sw,
            skin,
            contacts: cs,
            forces: f,
            moments: m,
            dt,
            safety: _,
            time,
            steps,
            ratio,
            synced,
            initial,
            excavation: ex,
            initial_stress: stress,
            wet: wj,
            mass_scaling,
            origin,
        } = &mut sim;
        if !file.block_bodies.is_empty() {
            *bb = block_bodies_of(&file.block_bodies, n)?;
        }
        st.extend(file.sets.iter().copied());
        *j = joints;
        *br = bridge_table;
        *g = gravity;
        *t = tolerance;
        *skin = s.skin;
        *full_detection = s.full_detection;
        if !(s.update_fraction.is_finite() && s.update_fraction >= 0.0) {
            return Err(bad(
                "settings.update_fraction",
                "must be a finite number >= 0",
            ));
        }
        *update_fraction = s.update_fraction;
        *dormancy = s.dormant_contacts;
        *applied_moments = moments_applied;
        *cs = contacts;
        // The loaded contacts' shares are not known to come from this run's answers.
        *sw = None;
        *f = forces;
        *m = moments;
        *dt = s.timestep;
        *time = c.time;
        *steps = c.steps;
        *ratio = c.ratio.unwrap_or(f64::INFINITY);
        *synced = synced_of(c, n)?;
        *initial = c.initial;
        *ex = excavation;
        *stress = initial_stress;
        *w = water;
        *bo = bolt_set;
        *mass_scaling = match s.mass_scaling {
            Some(on) => on,
            // A file from before the setting was kept: it was on if it scaled a body.
            None => file.bodies.iter().any(|b| b.scale > 1.0),
        };
        *origin = labels_of(std::mem::take(&mut file.system), bb.len())?;
        *wj = wet;
    }
    // A file written before excavation ended the bolts anchored in removed bodies may hold
    // elements with an anchor in one: they go, as the excavation drops them now (their last
    // force released at once: the file has no relaxation for it). None in a newer file.
    let removed = sim.removed();
    sim.bolts.remove_bodies(&removed, &sim.bodies);
    sim.refresh_opened_joints();
    Ok(sim)
}
