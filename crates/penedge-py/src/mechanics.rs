//! `Simulation` (core `mechanics`): rigid-block DEM on a block system.

use crate::arrays::{self, Count, Real, Whole};
use crate::errors::{input_error, to_py_err, Error};
use crate::io::file_error;
use crate::system::BlockSystem;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use penedge::generation::{JointRecord, SetRecord};
use penedge::geometry::DVec3;
use penedge::mechanics::{self, Damping, Fixity, JointModel, Water};
use penedge::{ConvexBlock, Tolerance};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A rigid-block simulation (3DEC-style distinct element method) of a block system.
///
/// Each block is a rigid body (mass and inertia exact from its polyhedron) moved by gravity
/// and its contact forces, step after step: detection -> sub-contacts (polygon corners,
/// segment ends or one point, each with its own forces and Mohr-Coulomb state) -> forces ->
/// central-difference integration (rotation with full inertia). ``docs/mechanics.md`` gives
/// the algorithm, the sign conventions and the units (any consistent set; SI in examples).
///
/// Parameters
/// ----------
/// system : BlockSystem
///     The blocks, at rest and free: one body each, except that a concave block (parts sharing
///     a body id, :meth:`BlockSystem.with_bodies`) is one rigid body of all its parts, with
///     the mass, centroid and inertia of their union, unless rock bridges hold the parts (the
///     pieces a bridged finite joint cut through stay separate bodies held by bonded bridge
///     contacts, so that the bridge can break); bodies go in the order of their first block,
///     and :attr:`block_bodies` gives each block's body.
/// density : float, default 2700.0
///     Density of every block (mass per volume; :meth:`set_density` per block).
/// gap : float, default 1e-3
///     Relative detection gap, in (0, 0.01) (both ends excluded): the deepest overlap a
///     contact can carry, relative to the smaller block's size (a deeper one stops the run
///     with an error). Not 0: a soft contact carries its load by overlapping; and not
///     below ``16 * 2**-52`` (3.6e-15), the detection's smallest gap above 0.
/// point_width : float, default 0.2
///     Width of point and edge contacts relative to the smaller body's diameter: a point
///     contact is a patch of ``w² / 2``, a segment of length ``l`` a strip of ``w l / 2``
///     (``docs/mechanics.md``). The softer they are, the deeper they sink under a load.
///     A contact of edges or vertices where two joints of the rock cross (faces of joint
///     origin on both sides) bears only past half the detection gap of overlap
///     (``docs/mechanics.md``, "Where joints cross").
///
/// Raises
/// ------
/// InputError
///     A bool for `density`, `gap` or `point_width` (kind ``dtype``): a bool is no number,
///     here or in any number argument of a simulation's methods.
/// MechanicsError
///     A density that is not a finite number > 0, a point width not in (0, 1], a gap of 0
///     (kind ``parameter``).
/// ToleranceError
///     Any other gap out of range (below ``16 * 2**-52``: kind ``gap_below_rounding``).
///
/// Examples
/// --------
/// >>> import penedge
/// >>> base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
/// >>> cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
/// >>> sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0)
/// >>> sim.fix([0])
/// >>> sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
/// >>> report = sim.solve()
/// >>> report["converged"]
/// True
/// >>> round(float(sim.positions[1, 2]), 6)  # sunk by m g / (kn A)
/// 0.499975
#[pyclass(module = "penedge", name = "Simulation")]
pub struct Simulation {
    inner: mechanics::Simulation,
    /// The note of the restart file it was read from (:meth:`load`).
    note: Option<String>,
    /// What the bodies do not keep of the system the simulation was made of, for
    /// :meth:`system` (`None` for one read from a restart file, which does not hold it).
    origin: Option<Arc<Origin>>,
}

/// The system a simulation was made of, less its blocks (the bodies hold them): its body
/// ids, provenance (domain, joint table, spec entries) and unit.
#[derive(Debug)]
struct Origin {
    body_ids: Vec<u32>,
    domain: Vec<ConvexBlock>,
    joints: Vec<JointRecord>,
    sets: Vec<SetRecord>,
    unit: Option<String>,
}

impl Origin {
    fn of(system: &penedge::BlockSystem) -> Origin {
        Origin {
            body_ids: system.body_ids(),
            domain: system.domain().to_vec(),
            joints: system.joints().to_vec(),
            sets: system.sets().to_vec(),
            unit: system.unit().map(str::to_string),
        }
    }
}

/// Per block (its simulation body in `block_bodies`), the index of its part among the parts
/// of [`mechanics::Simulation::placed_system`], which go body by body, each body's parts in
/// the order of its blocks (`Bodies::of_system`; a restart file keeps them so). `None` if
/// `part_bodies` (the body of each part) does not fit.
fn part_of_block(block_bodies: &[u32], part_bodies: &[u32]) -> Option<Vec<usize>> {
    if block_bodies.len() != part_bodies.len() {
        return None;
    }
    let mut next = Vec::new(); // per body, the index of its next part
    for (k, &b) in part_bodies.iter().enumerate() {
        let b = b as usize;
        if b == next.len() {
            next.push(k);
        } else if b + 1 != next.len() {
            return None; // the parts are not body by body
        }
    }
    let mut parts = Vec::with_capacity(block_bodies.len());
    for &b in block_bodies {
        let k = next.get_mut(b as usize)?;
        if part_bodies.get(*k) != Some(&b) {
            return None;
        }
        parts.push(*k);
        *k += 1;
    }
    Some(parts)
}

/// Per block, the body id :meth:`Simulation.system` gives it: the system's own id
/// (`system_ids`), except that a system body the simulation splits into several bodies
/// (`block_bodies`: the pieces rock bridges hold) has one id per piece, the piece of its
/// first block keeping the system's id and the others numbered on from the system's largest
/// id, in the order of their first block.
fn placed_body_ids(system_ids: &[u32], block_bodies: &[u32]) -> Vec<u32> {
    use std::collections::HashMap;
    // Saturating, not overflowing, for ids near 2**32 - 1 (allowed, beyond any real system:
    // there, the pieces' new ids would collide).
    let mut fresh = system_ids.iter().max().map_or(0, |&m| m.saturating_add(1));
    let mut first_piece: HashMap<u32, u32> = HashMap::new(); // system id -> its first piece
    let mut id_of_piece: HashMap<u32, u32> = HashMap::new(); // simulation body -> id
    system_ids
        .iter()
        .zip(block_bodies)
        .map(|(&id, &body)| {
            *id_of_piece.entry(body).or_insert_with(|| {
                if *first_piece.entry(id).or_insert(body) == body {
                    id
                } else {
                    let id = fresh;
                    fresh = fresh.saturating_add(1);
                    id
                }
            })
        })
        .collect()
}

/// A joint model as a dict of its properties.
fn model_dict<'py>(py: Python<'py>, m: &JointModel) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("kn", m.kn)?;
    out.set_item("ks", m.ks)?;
    out.set_item("friction", m.friction)?;
    out.set_item("cohesion", m.cohesion)?;
    out.set_item("tension", m.tension)?;
    out.set_item(
        "residual_friction",
        m.residual_friction.unwrap_or(m.friction),
    )?;
    out.set_item("residual_cohesion", m.residual_cohesion)?;
    Ok(out)
}

/// The body ids given as `ids` (any array-like of whole numbers >= 0; one past the bodies
/// is the core's `MechanicsError`).
fn body_ids(ids: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    Ok(arrays::indices(ids, "ids")?
        .into_iter()
        .map(|i| usize::try_from(i).unwrap_or(usize::MAX))
        .collect())
}

/// A whole number of 0 or more given as argument `name`: a negative one, or one beyond
/// 2**63 - 1, is an `InputError` naming it (kind ``negative`` or ``out_of_range``), where
/// the conversion would raise a bare `OverflowError`.
fn natural(value: Whole, name: &str) -> PyResult<u64> {
    match value.value().map(u64::try_from) {
        Some(Ok(n)) => Ok(n),
        _ if value.is_negative() => {
            let message = format!("{name} must be a whole number of 0 or more, got {value}");
            Err(input_error("negative", message))
        }
        _ => {
            let message = format!("{name} must be a whole number up to 2**63 - 1, got {value}");
            Err(input_error("out_of_range", message))
        }
    }
}

/// An id (of a body or a joint set) given as argument `name`: a whole number as [`Whole`]
/// takes it, but not a bool (an `int` to Python): ``True`` is not body 1, as ``fix([True])``
/// refuses it (an `InputError` of kind ``dtype`` naming the argument).
fn whole_id(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Whole> {
    if arrays::is_bool(value) {
        return Err(arrays::bool_error(name, "an integer", value));
    }
    value.extract().map_err(|e: PyErr| {
        if e.is_instance_of::<pyo3::exceptions::PyTypeError>(value.py()) {
            // A float (even 1.0) or an array is no id: named, not a bare TypeError.
            let kind = value
                .get_type()
                .name()
                .map_or(String::new(), |n| n.to_string());
            let message = format!("{name} must be an integer, got the {kind} {value}");
            input_error("dtype", message)
        } else {
            e
        }
    })
}

/// A body id given as argument `name` ([`whole_id`], [`natural`]; one past the bodies is
/// the core's `MechanicsError`).
fn body_id(value: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    let value = whole_id(value, name)?;
    Ok(usize::try_from(natural(value, name)?).unwrap_or(usize::MAX))
}

/// A joint (or bridge) model from the arguments of `set_joint` and `set_bridge`, each
/// refused by its name when it is a bool ([`Real`]); the ranges are the engine's to check.
fn joint_model(
    [kn, ks, friction, cohesion, tension]: [Real; 5],
    residual_friction: Option<Real>,
    residual_cohesion: Real,
) -> PyResult<JointModel> {
    Ok(JointModel {
        kn: kn.get("kn")?,
        ks: ks.get("ks")?,
        friction: friction.get("friction")?,
        cohesion: cohesion.get("cohesion")?,
        tension: tension.get("tension")?,
        residual_friction: Real::optional(residual_friction, "residual_friction")?,
        residual_cohesion: residual_cohesion.get("residual_cohesion")?,
    })
}

/// A joint set id given as argument `name` ([`whole_id`]): a whole number from 0 to
/// `u32::MAX`, else an `InputError` naming it.
fn set_id(value: &Bound<'_, PyAny>, name: &str) -> PyResult<u32> {
    set_number(whole_id(value, name)?, name)
}

/// [`set_id`] of a whole number.
fn set_number(value: Whole, name: &str) -> PyResult<u32> {
    match value.value().map(u32::try_from) {
        Some(Ok(set)) => Ok(set),
        _ => {
            let kind = if value.is_negative() {
                "negative"
            } else {
                "out_of_range"
            };
            let message = format!(
                "{name} must be a joint set id from 0 to {}, got {value}",
                u32::MAX
            );
            Err(input_error(kind, message))
        }
    }
}

/// A [`Whole`] as a key of a dict argument, in the order of the keys' values (those beyond
/// 64 bits after the others, by their text: any error names one of them).
#[derive(Clone, Debug)]
struct WholeKey(Whole);

impl WholeKey {
    fn rank(&self) -> (bool, i64, &str) {
        match &self.0 {
            Whole::Fits(n) => (false, *n, ""),
            Whole::Beyond(_, text) => (true, 0, text),
        }
    }
}

impl PartialEq for WholeKey {
    fn eq(&self, other: &Self) -> bool {
        self.rank() == other.rank()
    }
}

impl Eq for WholeKey {}

impl PartialOrd for WholeKey {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for WholeKey {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.rank().cmp(&other.rank())
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for WholeKey {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        whole_id(&obj, "a set of pressures").map(WholeKey)
    }
}

/// A velocity and an optional spin (zero when not given) as vectors.
fn motion(
    velocity: &Bound<'_, PyAny>,
    spin: Option<&Bound<'_, PyAny>>,
) -> PyResult<(DVec3, DVec3)> {
    let v = DVec3::from_array(arrays::point(velocity, "velocity")?);
    let w = match spin {
        Some(s) => DVec3::from_array(arrays::point(s, "spin")?),
        None => DVec3::ZERO,
    };
    Ok((v, w))
}

/// The wall time of a run's work between two checks for signals (Ctrl-C).
const CHUNK: Duration = Duration::from_millis(100);

/// Runs `next` without the GIL until it says the run is over, in chunks of about [`CHUNK`]
/// of wall time, checking for signals between them: a KeyboardInterrupt (or whatever a
/// Python signal handler raises) stops the run there, after a whole step. `next` takes the
/// run's next step if it has one and says whether the run is over; chunks change when the
/// steps are taken, never what they compute, so the run is the same bit for bit.
fn in_chunks(
    py: Python<'_>,
    sim: &mut mechanics::Simulation,
    mut next: impl FnMut(&mut mechanics::Simulation) -> Result<bool, mechanics::MechanicsError> + Send,
) -> PyResult<()> {
    loop {
        let over = py
            .detach(|| -> Result<bool, mechanics::MechanicsError> {
                let start = Instant::now();
                loop {
                    if next(sim)? {
                        return Ok(true);
                    }
                    if start.elapsed() >= CHUNK {
                        return Ok(false);
                    }
                }
            })
            .map_err(to_py_err)?;
        if over {
            return Ok(());
        }
        py.check_signals()?;
    }
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (system, density = Real::Value(2700.0), gap = Real::Value(1e-3),
        point_width = Real::Value(0.2)),
        text_signature = "(system, density=2700.0, gap=1e-3, point_width=0.2)")]
    fn new(system: &BlockSystem, density: Real, gap: Real, point_width: Real) -> PyResult<Self> {
        let density = density.get("density")?;
        let gap = gap.get("gap")?;
        let point_width = point_width.get("point_width")?;
        let mut inner = mechanics::Simulation::new(&system.inner, density).map_err(to_py_err)?;
        inner.set_gap(gap).map_err(to_py_err)?;
        inner.set_point_width(point_width).map_err(to_py_err)?;
        let origin = Some(Arc::new(Origin::of(&system.inner)));
        Ok(Simulation {
            inner,
            note: None,
            origin,
        })
    }

    /// Number of bodies.
    fn __len__(&self) -> usize {
        self.inner.bodies().len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation({} bodies, {} contacts, t = {})",
            self.inner.bodies().len(),
            self.inner.contacts().list.len(),
            self.inner.time()
        )
    }

    // ---- settings ---------------------------------------------------------------------

    /// Sets the joint properties of joint set `set` (the ``set`` of the faces' origins, as
    /// in :attr:`BlockSystem.sets`), or the default ones (``set=None``: every contact with
    /// no joint face, or of a set without its own). A contact between faces of two sets takes
    /// the weaker set; see ``docs/mechanics.md``. Until set, the default joint is ``kn = ks
    /// = 1e10`` (stress per displacement), friction 30°, no cohesion or tension, residual
    /// friction 30° and residual cohesion 0 (:meth:`joint`).
    ///
    /// Parameters
    /// ----------
    /// kn, ks : float
    ///     Normal and shear stiffness, stress per displacement (> 0).
    /// friction : float
    ///     Friction angle in degrees, in [0, 90).
    /// cohesion, tension : float, default 0.0
    ///     Cohesion and tensile strength (stresses ≥ 0), held by the contacts found at the
    ///     start of the run until they fail (then 0).
    /// set : int, optional
    ///     The joint set; None for the default.
    /// residual_friction : float, optional
    ///     Friction angle after failure (degrees, in [0, 90)); None: `friction`.
    /// residual_cohesion : float, default 0.0
    ///     Cohesion after failure (3DEC's default 0). A sub-contact whose bond failed (in
    ///     shear or tension), and one formed during the run, has the residual strength.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A property out of range (the error names it), or a set the system does not have
    ///     (no block face of it and no entry of its generation spec: kind ``unknown_set``).
    #[pyo3(signature = (kn, ks, friction, cohesion = Real::Value(0.0), tension = Real::Value(0.0),
        set = None, residual_friction = None, residual_cohesion = Real::Value(0.0)),
        text_signature = "($self, kn, ks, friction, cohesion=0.0, tension=0.0, set=None, \
                          residual_friction=None, residual_cohesion=0.0)")]
    #[allow(clippy::too_many_arguments)]
    fn set_joint(
        &mut self,
        kn: Real,
        ks: Real,
        friction: Real,
        cohesion: Real,
        tension: Real,
        set: Option<&Bound<'_, PyAny>>,
        residual_friction: Option<Real>,
        residual_cohesion: Real,
    ) -> PyResult<()> {
        let model = joint_model(
            [kn, ks, friction, cohesion, tension],
            residual_friction,
            residual_cohesion,
        )?;
        let set = set.map(|s| set_id(s, "set")).transpose()?;
        match set {
            None => self.inner.set_default_joint(model),
            Some(s) => self
                .inner
                .check_set(s)
                .and_then(|()| self.inner.set_joint(s, model)),
        }
        .map_err(to_py_err)
    }

    /// Sets the intact rock's properties for the rock bridges of joint set `set` (contacts
    /// over faces of origin kind 3, "bridge", made by a finite joint generated with
    /// ``bridge = true``), or the default for bridges of sets without their own
    /// (``set=None``). Bridges bond where they touch at the start of the run and, once they
    /// fail, keep friction only; without a call, a set's bridges have its joint stiffness and
    /// friction 45°, cohesion 10 MPa, tension 5 MPa. See ``docs/mechanics.md``, "Rock
    /// bridges".
    ///
    /// Parameters
    /// ----------
    /// kn, ks : float
    ///     Normal and shear stiffness, stress per displacement (> 0).
    /// friction : float
    ///     Friction angle in degrees, in [0, 90).
    /// cohesion, tension : float
    ///     The intact rock's cohesion and tensile strength (stresses ≥ 0).
    /// set : int, optional
    ///     The joint set; None for the default.
    /// residual_friction : float, optional
    ///     Friction angle after failure (default: `friction`).
    /// residual_cohesion : float, default 0.0
    ///     Cohesion after failure.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A property out of range (the error names it), or a set the system does not have.
    #[pyo3(signature = (kn, ks, friction, cohesion, tension, set = None,
        residual_friction = None, residual_cohesion = Real::Value(0.0)),
        text_signature = "($self, kn, ks, friction, cohesion, tension, set=None, \
                          residual_friction=None, residual_cohesion=0.0)")]
    #[allow(clippy::too_many_arguments)]
    fn set_bridge(
        &mut self,
        kn: Real,
        ks: Real,
        friction: Real,
        cohesion: Real,
        tension: Real,
        set: Option<&Bound<'_, PyAny>>,
        residual_friction: Option<Real>,
        residual_cohesion: Real,
    ) -> PyResult<()> {
        let model = joint_model(
            [kn, ks, friction, cohesion, tension],
            residual_friction,
            residual_cohesion,
        )?;
        let set = set.map(|s| set_id(s, "set")).transpose()?;
        match set {
            None => self.inner.set_default_bridge(model),
            Some(s) => self
                .inner
                .check_set(s)
                .and_then(|()| self.inner.set_bridge(s, model)),
        }
        .map_err(to_py_err)
    }

    /// The bridge properties of joint set `set` (its own, else the default), as a dict.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A set the system does not have (kind ``unknown_set``), as :meth:`set_bridge`.
    fn bridge<'py>(&self, py: Python<'py>, set: &Bound<'_, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let set = set_id(set, "set")?;
        self.inner.check_set(set).map_err(to_py_err)?;
        model_dict(py, &self.inner.bridges().of_set(set, self.inner.joints()))
    }

    /// The joint properties of joint set `set` (its own, else the default), or the default
    /// ones (``set=None``), as a dict.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A set the system does not have (kind ``unknown_set``), as :meth:`set_joint`.
    #[pyo3(signature = (set = None))]
    fn joint<'py>(
        &self,
        py: Python<'py>,
        set: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let set = set.map(|s| set_id(s, "set")).transpose()?;
        if let Some(s) = set {
            self.inner.check_set(s).map_err(to_py_err)?;
        }
        model_dict(py, self.inner.joints().of_set(set))
    }

    /// Sets the water pressure in the joints (``docs/mechanics.md``, "Water pressure in the
    /// joints"): a phreatic surface, pressures per joint set, or both (a set's pressure
    /// replaces the phreatic one on its contacts); with no argument, dry joints. The
    /// pressure acts on the face-face contacts' polygons, pushing the blocks apart; the
    /// joints' normal force is then the effective one.
    ///
    /// Parameters
    /// ----------
    /// level : float, optional
    ///     A horizontal water table at this elevation (z).
    /// point, normal : array_like (3,), optional
    ///     An inclined phreatic surface: a point on it and its normal (not horizontal).
    /// pressures : dict[int, float], optional
    ///     A uniform pressure (≥ 0) on the contacts of each joint set.
    /// unit_weight : float, default 9810.0
    ///     ``ρw g``, the pressure per depth below the surface (depth measured along z).
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A vertical surface, a negative pressure, a unit weight not > 0, a set the system
    ///     does not have.
    /// ValueError
    ///     Both `level` and `point`, or `point` without `normal`.
    #[pyo3(signature = (level = None, point = None, normal = None, pressures = None,
        unit_weight = Real::Value(9810.0)),
        text_signature = "($self, level=None, point=None, normal=None, pressures=None, \
                          unit_weight=9810.0)")]
    fn set_water(
        &mut self,
        level: Option<Real>,
        point: Option<&Bound<'_, PyAny>>,
        normal: Option<&Bound<'_, PyAny>>,
        pressures: Option<std::collections::BTreeMap<WholeKey, Real>>,
        unit_weight: Real,
    ) -> PyResult<()> {
        let level = Real::optional(level, "level")?;
        let unit_weight = unit_weight.get("unit_weight")?;
        let mut water = match (level, point, normal) {
            (None, None, None) => Water::none(),
            (Some(z), None, None) => Water::level(z, unit_weight).map_err(to_py_err)?,
            (None, Some(p), Some(n)) => Water::phreatic(
                DVec3::from_array(arrays::point(p, "point")?),
                DVec3::from_array(arrays::point(n, "normal")?),
                unit_weight,
            )
            .map_err(to_py_err)?,
            _ => {
                return Err(pyo3::exceptions::PyValueError::new_err(
                    "set_water: give `level`, or `point` and `normal`, or neither",
                ))
            }
        };
        for (WholeKey(set), p) in pressures.unwrap_or_default() {
            let p = p.get(&format!("pressures[{set}]"))?;
            let set = set_number(set, "a set of pressures")?;
            self.inner.check_set(set).map_err(to_py_err)?;
            water = water.with_set_pressure(set, p).map_err(to_py_err)?;
        }
        self.inner.set_water(water);
        Ok(())
    }

    /// Gravity, an acceleration vector (default ``(0, 0, -9.81)``): a read-only copy, as
    /// the state arrays; set it by assigning a whole vector (``sim.gravity = [0, 0, -1]``).
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        arrays::read_only(arrays::vector(py, self.inner.gravity().to_array().to_vec()))
    }

    #[setter]
    fn set_gravity(&mut self, g: &Bound<'_, PyAny>) -> PyResult<()> {
        let g = arrays::point(g, "gravity")?;
        self.inner
            .set_gravity(DVec3::from_array(g))
            .map_err(to_py_err)
    }

    /// Sets the initial stress the first step installs on the contacts touching then
    /// (``docs/mechanics.md``, "Initial stresses"): tension positive, components ``xx, yy,
    /// zz, xy, yz, zx`` (Pa), ``base + depth * per_depth`` with ``depth = max(0, surface -
    /// z)``. Each touching sub-contact gets the normal stress ``-n·σ·n`` (kept until it
    /// opens) and the shear force of the traction. No argument: none.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     `base` or `per_depth` not six real numbers.
    /// MechanicsError
    ///     After the first step, or a NaN.
    #[pyo3(signature = (base = None, per_depth = None, surface = Real::Value(0.0)),
        text_signature = "($self, base=None, per_depth=None, surface=0.0)")]
    fn set_initial_stress(
        &mut self,
        base: Option<&Bound<'_, PyAny>>,
        per_depth: Option<&Bound<'_, PyAny>>,
        surface: Real,
    ) -> PyResult<()> {
        let surface = surface.get("surface")?;
        let base = base.map(|b| arrays::six(b, "base")).transpose()?;
        let per_depth = per_depth.map(|p| arrays::six(p, "per_depth")).transpose()?;
        let stress = (base.is_some() || per_depth.is_some()).then(|| mechanics::InitialStress {
            base: base.unwrap_or([0.0; 6]),
            per_depth: per_depth.unwrap_or([0.0; 6]),
            surface,
        });
        self.inner.set_initial_stress(stress).map_err(to_py_err)
    }

    /// Sets the damping: local non-viscous (3DEC's, in [0, 1)) and mass-proportional
    /// viscous (a rate ≥ 0, in 1/s); both 0 until set. :meth:`solve` replaces the pair
    /// ``(0, 0)`` by local 0.8 for its steps, whether or not it was set so: see there.
    #[pyo3(signature = (local = Real::Value(0.0), viscous = Real::Value(0.0)),
        text_signature = "($self, local=0.0, viscous=0.0)")]
    fn set_damping(&mut self, local: Real, viscous: Real) -> PyResult<()> {
        let (local, viscous) = (local.get("local")?, viscous.get("viscous")?);
        self.inner
            .set_damping(Damping { local, viscous })
            .map_err(to_py_err)
    }

    /// The damping: ``(local, viscous)``.
    #[getter]
    fn damping(&self) -> (f64, f64) {
        let d = self.inner.damping();
        (d.local, d.viscous)
    }

    /// Sets the density of the given bodies (all when `ids` is None).
    #[pyo3(signature = (density, ids = None))]
    fn set_density(&mut self, density: Real, ids: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let density = density.get("density")?;
        let ids = match ids {
            Some(ids) => body_ids(ids)?,
            None => (0..self.inner.bodies().len()).collect(),
        };
        for i in ids {
            self.inner.set_density(i, density).map_err(to_py_err)?;
        }
        Ok(())
    }

    /// Fixes the given bodies: they no longer move.
    fn fix(&mut self, ids: &Bound<'_, PyAny>) -> PyResult<()> {
        for i in body_ids(ids)? {
            self.inner.fix(i).map_err(to_py_err)?;
        }
        Ok(())
    }

    /// Frees the given bodies, at rest now (their first step starts with a half kick); a
    /// body already free is left as it is.
    fn free(&mut self, ids: &Bound<'_, PyAny>) -> PyResult<()> {
        for i in body_ids(ids)? {
            self.inner.free(i).map_err(to_py_err)?;
        }
        Ok(())
    }

    /// Moves body `id` at a prescribed velocity and spin (world frame), whatever the forces.
    #[pyo3(signature = (id, velocity, spin = None))]
    fn prescribe(
        &mut self,
        id: &Bound<'_, PyAny>,
        velocity: &Bound<'_, PyAny>,
        spin: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let id = body_id(id, "id")?;
        let (v, w) = motion(velocity, spin)?;
        self.inner.prescribe(id, v, w).map_err(to_py_err)
    }

    /// Sets the velocity and spin of free body `id` now.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     An unknown or excavated body, or one that is not free (kind ``not_free``): a
    ///     fixed body does not move, and a prescribed one moves at its prescribed velocity
    ///     (:meth:`prescribe` changes it; :meth:`free` frees a body, at rest).
    #[pyo3(signature = (id, velocity, spin = None))]
    fn set_velocity(
        &mut self,
        id: &Bound<'_, PyAny>,
        velocity: &Bound<'_, PyAny>,
        spin: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let id = body_id(id, "id")?;
        let (v, w) = motion(velocity, spin)?;
        let bodies = self.inner.bodies();
        // An unknown or excavated body: the core's error, below.
        if id < bodies.len() && !self.inner.removed()[id] {
            let why = match bodies.fixity(id) {
                Fixity::Free => None,
                Fixity::Fixed => Some(String::from("is fixed")),
                Fixity::Prescribed { .. } => Some(format!(
                    "moves at a prescribed velocity (prescribe({id}, ...) changes it)"
                )),
            };
            if let Some(why) = why {
                let message = format!(
                    "set_velocity: body {id} {why}, and only a free body's velocity can be \
                     set (free([{id}]) frees it, at rest)"
                );
                return Err(to_py_err(Error::Mechanics("not_free".into(), message)));
            }
        }
        self.inner.set_velocity(id, v, w).map_err(to_py_err)
    }

    /// Applies a constant force on body `id` (besides gravity and contacts), at its centroid,
    /// or at `point` (world, at the body's current pose): then also the force's moment about
    /// the centroid, replacing any applied moment. Both stay constant in the world frame.
    ///
    /// Each call replaces the applied force; without `point` it leaves the applied moment
    /// as it was: after ``apply_force(i, F, point=p)``, ``apply_force(i, F)`` keeps the
    /// moment ``(p - c) × F`` of the first call, and the body goes on turning. To act at
    /// the centroid only, remove the moment with ``apply_moment(i, [0, 0, 0])``.
    #[pyo3(signature = (id, force, point = None))]
    fn apply_force(
        &mut self,
        id: &Bound<'_, PyAny>,
        force: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let id = body_id(id, "id")?;
        let f = DVec3::from_array(arrays::point(force, "force")?);
        match point {
            None => self.inner.apply_force(id, f),
            Some(p) => {
                let p = DVec3::from_array(arrays::point(p, "point")?);
                self.inner.apply_force_at(id, f, p)
            }
        }
        .map_err(to_py_err)
    }

    /// Applies a constant moment on body `id` (world frame, about its centroid; replaces the
    /// one set before; zero removes it).
    fn apply_moment(&mut self, id: &Bound<'_, PyAny>, moment: &Bound<'_, PyAny>) -> PyResult<()> {
        let id = body_id(id, "id")?;
        let m = DVec3::from_array(arrays::point(moment, "moment")?);
        self.inner.apply_moment(id, m).map_err(to_py_err)
    }

    /// Installs a rock bolt from `point` along `direction` for `length`, across the bodies
    /// its segment crosses now (``docs/mechanics.md``, "Rock bolts"): one axial spring
    /// between each two consecutive bodies, anchored at the plate (where it enters the first
    /// body), the far end (where it leaves the last) and the middle of its run through each
    /// body between.
    ///
    /// Parameters
    /// ----------
    /// point, direction : array_like, shape (3,)
    ///     The collar, and the direction into the rock (any length).
    /// length : float
    ///     The bolt's length.
    /// stiffness : float
    ///     Axial stiffness of the whole bolt, ``EA / length`` (an element of length ``l``
    ///     gets ``EA / l``).
    /// capacity : float
    ///     The axial force at which it yields (elastic, perfectly plastic, in tension and in
    ///     compression).
    /// rupture_strain : float, optional
    ///     The axial strain at which an element breaks for good; None: never.
    /// shear_stiffness, shear_capacity : float, optional
    ///     A dowel at each joint the bolt crosses: shear stiffness (force per relative
    ///     displacement across the bolt) and capacity (elastic, perfectly plastic); both or
    ///     neither (None: axial only).
    ///
    /// Returns
    /// -------
    /// int
    ///     The bolt's id.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A bolt outside the rock, in one body only, or a value out of range.
    #[pyo3(signature = (
        point, direction, length, stiffness, capacity, rupture_strain = None,
        shear_stiffness = None, shear_capacity = None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn add_bolt(
        &mut self,
        point: &Bound<'_, PyAny>,
        direction: &Bound<'_, PyAny>,
        length: Real,
        stiffness: Real,
        capacity: Real,
        rupture_strain: Option<Real>,
        shear_stiffness: Option<Real>,
        shear_capacity: Option<Real>,
    ) -> PyResult<usize> {
        let length = length.get("length")?;
        let stiffness = stiffness.get("stiffness")?;
        let capacity = capacity.get("capacity")?;
        let rupture_strain = Real::optional(rupture_strain, "rupture_strain")?;
        let shear_stiffness = Real::optional(shear_stiffness, "shear_stiffness")?;
        let shear_capacity = Real::optional(shear_capacity, "shear_capacity")?;
        let dowel = match (shear_stiffness, shear_capacity) {
            (None, None) => None,
            (Some(stiffness), Some(capacity)) => Some(mechanics::Dowel {
                stiffness,
                capacity,
            }),
            _ => {
                return Err(crate::errors::input_error(
                    "dowel",
                    "give both shear_stiffness and shear_capacity, or neither",
                ))
            }
        };
        let bolt = mechanics::Bolt {
            collar: DVec3::from_array(arrays::point(point, "point")?),
            direction: DVec3::from_array(arrays::point(direction, "direction")?),
            length,
            stiffness,
            capacity,
            rupture_strain,
            dowel,
        };
        self.inner.add_bolt(bolt).map_err(to_py_err)
    }

    /// The bolt elements at the last step, as arrays (k elements, bolt after bolt, in order
    /// along each bolt).
    ///
    /// Returns
    /// -------
    /// dict
    ///     ``bolt`` (k,) int64 the bolt id of each element, ``pairs`` (k, 2) int64 its
    ///     bodies in order along the bolt, ``starts`` and ``ends`` (k, 3) its anchors now,
    ///     ``rest_lengths``, ``elongations`` and ``forces`` (k,) (axial, tension > 0),
    ///     ``states`` (k,) 0 elastic, 1 yielding, 2 broken, ``shear_forces`` (k, 3) the
    ///     dowel's force on the second body (zero without a dowel).
    fn bolts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let elements = self.inner.bolts().elements();
        let bodies = self.inner.bodies();
        let out = PyDict::new(py);
        let ids: Vec<i64> = elements.iter().map(|e| e.bolt() as i64).collect();
        out.set_item("bolt", arrays::vector(py, ids))?;
        let pairs: Vec<[i64; 2]> = elements
            .iter()
            .map(|e| e.bodies().map(|b| b as i64))
            .collect();
        out.set_item("pairs", arrays::pairs(py, &pairs))?;
        let ends: Vec<[DVec3; 2]> = elements.iter().map(|e| e.ends(bodies)).collect();
        let column = |k: usize| -> Vec<[f64; 3]> { ends.iter().map(|p| p[k].to_array()).collect() };
        out.set_item("starts", arrays::rows3(py, &column(0)))?;
        out.set_item("ends", arrays::rows3(py, &column(1)))?;
        let values = |f: &dyn Fn(&mechanics::BoltElement) -> f64| -> Vec<f64> {
            elements.iter().map(f).collect()
        };
        out.set_item(
            "rest_lengths",
            arrays::vector(py, values(&|e| e.rest_length())),
        )?;
        out.set_item(
            "elongations",
            arrays::vector(py, values(&|e| e.elongation())),
        )?;
        out.set_item("forces", arrays::vector(py, values(&|e| e.force())))?;
        let states: Vec<u8> = elements.iter().map(|e| e.state().code()).collect();
        out.set_item("states", arrays::vector(py, states))?;
        let shear: Vec<[f64; 3]> = elements
            .iter()
            .map(|e| e.shear_force().to_array())
            .collect();
        out.set_item("shear_forces", arrays::rows3(py, &shear))?;
        Ok(out)
    }

    /// Sets the time step (None: automatic, `safety` × the critical step).
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A step not positive or above the critical one, or no free body.
    #[pyo3(signature = (dt = None, safety = None))]
    fn set_timestep(&mut self, dt: Option<Real>, safety: Option<Real>) -> PyResult<()> {
        let dt = Real::optional(dt, "dt")?;
        let safety = Real::optional(safety, "safety")?;
        if let Some(s) = safety {
            self.inner.set_safety(s).map_err(to_py_err)?;
        }
        self.inner.set_timestep(dt).map_err(to_py_err)
    }

    /// Mass scaling for quasi-static runs (3DEC's density scaling): with True, free bodies
    /// whose critical step is below the median get their inertia (not their weight) scaled up
    /// to it, so that slivers no longer set the time step. Same equilibrium, non-physical
    /// motion towards it: for :meth:`solve`, not for dynamics. While on, :meth:`excavate`
    /// computes the factors again from the free bodies that stay; after :meth:`fix`,
    /// :meth:`free`, :meth:`prescribe`, :meth:`set_density` or :meth:`set_joint`, call it
    /// again (``docs/mechanics.md``, "Mass scaling"). Kept in restart files.
    fn set_mass_scaling(&mut self, on: bool) -> PyResult<()> {
        self.inner.set_mass_scaling(on).map_err(to_py_err)
    }

    /// Whether mass scaling is on (:meth:`set_mass_scaling`).
    #[getter]
    fn mass_scaling(&self) -> bool {
        self.inner.mass_scaling()
    }

    /// The time step the next step takes.
    #[getter]
    fn timestep(&self) -> PyResult<f64> {
        self.inner.timestep().map_err(to_py_err)
    }

    /// The critical time step: a bound from the masses, inertias, the largest joint stiffness
    /// and the bolts' stiffnesses, lowered by viscous damping when there is some
    /// (``docs/mechanics.md``, "Integration").
    #[getter]
    fn critical_timestep(&self) -> PyResult<f64> {
        self.inner.critical_timestep().map_err(to_py_err)
    }

    // ---- running ----------------------------------------------------------------------

    /// Takes `n` steps (without the GIL; Ctrl-C stops them after a whole step).
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     No free body, a time step above the critical one, two bodies overlapping deeper
    ///     than the gap, a NaN state. The steps before stay taken.
    /// KeyboardInterrupt
    ///     A signal (Ctrl-C) during the run: the steps taken stay taken, the simulation is
    ///     after a whole step and can go on.
    #[pyo3(signature = (n = Count::Value(Whole::Fits(1))), text_signature = "($self, n=1)")]
    fn step(&mut self, py: Python<'_>, n: Count) -> PyResult<()> {
        let mut left = natural(n.get("n")?, "n")?;
        in_chunks(py, &mut self.inner, |sim| {
            if left == 0 {
                return Ok(true);
            }
            sim.step()?;
            left -= 1;
            Ok(left == 0)
        })
    }

    /// Steps until the simulated time reaches `t` (the last step may pass it by less than a
    /// step; Ctrl-C stops them after a whole step, as for :meth:`step`).
    ///
    /// Raises
    /// ------
    /// InputError
    ///     `t` not finite, or so far ahead that it takes more steps, ``(t - time) /
    ///     timestep``, than :meth:`step` takes (2**63 - 1): kind ``out_of_range``, before
    ///     any step.
    fn run_until(&mut self, py: Python<'_>, t: Real) -> PyResult<()> {
        let t = t.get("t")?;
        if !t.is_finite() {
            // The core's refusal, before any step.
            return self.inner.run_until(t).map_err(to_py_err);
        }
        if let Ok(dt) = self.inner.timestep() {
            // (Without a time step, no free body: the first step's error says so.)
            let steps = (t - self.inner.time()) / dt;
            if steps > i64::MAX as f64 {
                let message = format!(
                    "run_until({t:e}) takes {steps:.3e} steps of {dt:e} s from time {:e}, more \
                     than step(n) takes (2**63 - 1): a time step or an end time typed wrong?",
                    self.inner.time()
                );
                return Err(input_error("out_of_range", message));
            }
        }
        in_chunks(py, &mut self.inner, |sim| {
            if sim.time() >= t {
                return Ok(true);
            }
            sim.step()?;
            Ok(sim.time() >= t)
        })
    }

    /// Steps until the unbalanced-force ratio is below `ratio`, at most `max_steps`.
    ///
    /// The damping of its steps: when local and viscous damping are both 0 (as they are
    /// until :meth:`set_damping`), local damping 0.8 (viscous 0), and the damping is set
    /// back to 0 after; otherwise the damping as set, unchanged. So
    /// ``set_damping(local=0.0)`` still gets 0.8, and ``set_damping(viscous=10.0)`` gets no
    /// local damping at all (give both to have both).
    ///
    /// Returns
    /// -------
    /// dict
    ///     ``steps``, ``ratio`` (at the end) and ``converged``.
    ///
    /// Raises
    /// ------
    /// KeyboardInterrupt
    ///     A signal (Ctrl-C) during the run, as for :meth:`step` (the damping set back).
    #[pyo3(signature = (ratio = Real::Value(1e-5), max_steps = Count::Value(Whole::Fits(100_000))),
        text_signature = "($self, ratio=1e-5, max_steps=100000)")]
    fn solve<'py>(
        &mut self,
        py: Python<'py>,
        ratio: Real,
        max_steps: Count,
    ) -> PyResult<Bound<'py, PyDict>> {
        let ratio = ratio.get("ratio")?;
        let max_steps = natural(max_steps.get("max_steps")?, "max_steps")?;
        // The core's `solve` one step at a time (it sets the damping for the step and back):
        // the same steps, tests and report as in one call.
        let mut report = self.inner.solve(ratio, 0).map_err(to_py_err)?;
        in_chunks(py, &mut self.inner, |sim| {
            if report.converged || report.steps >= max_steps {
                return Ok(true);
            }
            let one = sim.solve(ratio, 1)?;
            report.steps += one.steps;
            report.ratio = one.ratio;
            report.converged = one.converged;
            Ok(report.converged || report.steps >= max_steps)
        })?;
        let out = PyDict::new(py);
        out.set_item("steps", report.steps)?;
        out.set_item("ratio", report.ratio)?;
        out.set_item("converged", report.converged)?;
        Ok(out)
    }

    /// Simulated time.
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    /// The unbalanced-force ratio of the last step (largest unbalanced force of a free body
    /// over the largest gravity plus applied force).
    #[getter]
    fn unbalanced_ratio(&self) -> f64 {
        self.inner.unbalanced_ratio()
    }

    /// Sets the update tolerance of touching pairs, as a fraction of each pair's detection
    /// gap (``docs/mechanics.md``, "Carried contacts"): a touching pair is queried again once
    /// its two bodies have moved more than ``fraction`` × the gap since its last query, and its
    /// contact is carried with the bodies until then. ``0`` (the default) queries it at every
    /// step one of its bodies moves: exact, and resumed bit for bit from a restart file;
    /// ``0.1`` is the benchmark's faster setting.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     A fraction that is negative or not finite.
    fn set_update_fraction(&mut self, fraction: Real) -> PyResult<()> {
        let fraction = fraction.get("fraction")?;
        self.inner.set_update_fraction(fraction).map_err(to_py_err)
    }

    /// The update tolerance of touching pairs, a fraction of their detection gap.
    #[getter]
    fn update_fraction(&self) -> f64 {
        self.inner.update_fraction()
    }

    /// Whether carried open contacts may stay dormant (``docs/mechanics.md``, "Dormant contacts";
    /// default ``True``): a carried contact of two faces, edges or vertices, open at every
    /// sub-contact (positive gaps, no bond, no force) keeps its sub-contacts without updating them
    /// while a certificate shows that none can have closed. The motion and the forces are the same
    /// bit for bit; a dormant contact's points, normal, gaps, areas and shear displacements are
    /// those of its last update (a shear displacement missed then stays missed). Only carried
    /// contacts can be dormant: nothing changes with an update fraction of ``0`` (the default) or
    /// with water in the joints.
    #[getter]
    fn dormant_contacts(&self) -> bool {
        self.inner.dormant_contacts()
    }

    #[setter]
    fn set_dormant_contacts(&mut self, on: bool) {
        self.inner.set_dormant_contacts(on);
    }

    /// Cumulative wall time (seconds) of each part of the step since the simulation was made:
    /// ``pairs`` (candidate pairs, broad phase when rebuilt), ``detect`` (pair queries),
    /// ``contacts`` (sub-contacts and joint law), ``forces`` (sums per body), ``integration``,
    /// ``placement`` (placing the moved blocks), ``total``; and the counts ``steps``,
    /// ``rebuilds`` (broad phases built) and, summed over the steps, the candidate pairs
    /// ``queried``, kept ``unmoved`` (neither body moved since their query), kept
    /// ``certified`` separated (``docs/mechanics.md``, "Contact updates in the step") and
    /// touching pairs ``carried`` with their bodies ("Carried contacts"), of them ``dormant``
    /// (open contacts kept: "Dormant contacts"). One clock reading per part and step.
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    /// >>> cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    /// >>> sim = penedge.Simulation(penedge.BlockSystem([base, cube]))
    /// >>> sim.fix([0])
    /// >>> sim.step(3)
    /// >>> t = sim.timings()
    /// >>> t["steps"], t["total"] >= t["detect"] >= 0.0
    /// (3, True)
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.inner.timings();
        let out = PyDict::new(py);
        for (key, value) in [
            ("pairs", t.pairs),
            ("detect", t.detect),
            ("contacts", t.contacts),
            ("forces", t.forces),
            ("integration", t.integration),
            ("placement", t.placement),
            ("total", t.total()),
        ] {
            out.set_item(key, value)?;
        }
        for (key, value) in [
            ("steps", t.steps),
            ("rebuilds", t.rebuilds),
            ("queried", t.queried),
            ("unmoved", t.unmoved),
            ("certified", t.certified),
            ("carried", t.carried),
            ("dormant", t.dormant),
        ] {
            out.set_item(key, value)?;
        }
        Ok(out)
    }

    // ---- state as arrays (copies, read-only) ------------------------------------------

    /// Centroid positions, shape (n, 3).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<[f64; 3]> = self
            .inner
            .bodies()
            .poses()
            .iter()
            .map(|p| p.translation.to_array())
            .collect();
        arrays::read_only(arrays::rows3(py, &rows))
    }

    /// Orientations as unit quaternions ``x, y, z, w`` (body frame to world; the body frame
    /// is the centroid and principal axes), shape (n, 4).
    #[getter]
    fn quaternions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let poses = self.inner.bodies().poses();
        let array =
            Array2::from_shape_fn((poses.len(), 4), |(i, k)| poses[i].rotation.to_array()[k]);
        arrays::read_only(array.into_pyarray(py))
    }

    /// Velocities of the centroids (at the half step, as 3DEC reports them; at the current
    /// time for a body given one since the last step), shape (n, 3).
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let b = self.inner.bodies();
        let rows: Vec<[f64; 3]> = (0..b.len()).map(|i| b.velocity(i).to_array()).collect();
        arrays::read_only(arrays::rows3(py, &rows))
    }

    /// Angular velocities (world frame), shape (n, 3).
    #[getter]
    fn spins<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let b = self.inner.bodies();
        let rows: Vec<[f64; 3]> = (0..b.len()).map(|i| b.spin(i).to_array()).collect();
        arrays::read_only(arrays::rows3(py, &rows))
    }

    /// Per block of the system the simulation was made of, the body it is a part of (the row
    /// of :attr:`positions`, the id of :meth:`fix`), shape (number of blocks,), int64. A concave block is one body of several blocks, except
    /// that the pieces rock bridges hold are separate bodies (so that a bridge can break:
    /// ``docs/mechanics.md``, "Rock bridges"), so neither the blocks nor the system's bodies
    /// are the simulation's bodies in general. For a simulation read from an older restart
    /// file, per convex part in body order.
    ///
    /// >>> import penedge
    /// >>> a = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    /// >>> b = penedge.Block.cuboid([1, 0, 0], [2, 1, 1])
    /// >>> c = penedge.Block.cuboid([0, 0, 1], [1, 1, 2])
    /// >>> system = penedge.BlockSystem([a, b, c]).with_bodies([1, 0, 1])
    /// >>> penedge.Simulation(system).block_bodies.tolist()
    /// [0, 1, 0]
    #[getter]
    fn block_bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let ids = self
            .inner
            .block_bodies()
            .iter()
            .map(|&b| i64::from(b))
            .collect();
        arrays::read_only(arrays::vector(py, ids))
    }

    /// Masses, shape (n,).
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        arrays::read_only(arrays::vector(py, self.inner.bodies().masses().to_vec()))
    }

    /// Principal moments of inertia (ascending, about the body axes), shape (n, 3).
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<[f64; 3]> = self
            .inner
            .bodies()
            .principal_inertia()
            .iter()
            .map(|m| m.to_array())
            .collect();
        arrays::read_only(arrays::rows3(py, &rows))
    }

    /// Removes the given bodies (the rock excavated): from the next step they take no part
    /// (ids kept, fixed where they were; :attr:`removed`). A rock bolt's elements anchored
    /// in a removed body stop acting (they leave :meth:`bolts`; the bolt's other elements
    /// go on), and a bolt can no longer be installed into removed rock. The forces the
    /// removed bodies and those bolt elements exerted on the bodies that stay are applied
    /// again and reduced linearly to zero over `relax_steps` steps (the j-th step applies
    /// ``1 - (j - 1) / relax_steps`` of them; 0: at once). Only loads not zero: before
    /// any step no contact or bolt has a force, and nothing relaxes. With mass scaling on
    /// (:meth:`set_mass_scaling`), its factors are computed again from the free bodies that
    /// stay. ``docs/mechanics.md``, "Excavation".
    ///
    /// Returns
    /// -------
    /// dict
    ///     ``removed`` (int64 ids), ``loaded`` (int64 ids of the bodies the removed ones
    ///     pushed on or their bolts pulled on, with a force or moment not zero) and
    ///     ``forces`` (k, 3), the load on each, which relaxes.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     An unknown body, or one removed already.
    #[pyo3(signature = (ids, relax_steps = Count::Value(Whole::Fits(0))),
        text_signature = "($self, ids, relax_steps=0)")]
    fn excavate<'py>(
        &mut self,
        py: Python<'py>,
        ids: &Bound<'_, PyAny>,
        relax_steps: Count,
    ) -> PyResult<Bound<'py, PyDict>> {
        let ids = body_ids(ids)?;
        let relax_steps = natural(relax_steps.get("relax_steps")?, "relax_steps")?;
        let report = self.inner.excavate(&ids, relax_steps).map_err(to_py_err)?;
        let out = PyDict::new(py);
        let removed: Vec<i64> = report.removed.iter().map(|&i| i as i64).collect();
        out.set_item("removed", arrays::vector(py, removed))?;
        let loaded: Vec<i64> = report.loaded.iter().map(|l| l.0 as i64).collect();
        out.set_item("loaded", arrays::vector(py, loaded))?;
        let forces: Vec<[f64; 3]> = report.loaded.iter().map(|l| l.1.to_array()).collect();
        out.set_item("forces", arrays::rows3(py, &forces))?;
        Ok(out)
    }

    /// Whether each body was excavated (:meth:`excavate`), shape (n,).
    #[getter]
    fn removed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<bool>>> {
        arrays::read_only(arrays::vector(py, self.inner.removed()))
    }

    /// Whether each body is fixed, shape (n,).
    #[getter]
    fn fixed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let f = self.inner.bodies().fixities();
        let v = f.iter().map(|x| *x == Fixity::Fixed).collect();
        arrays::read_only(arrays::vector(py, v))
    }

    /// Per body, the sum of its contact (and bolt) forces at the last step, shape (n, 3).
    #[getter]
    fn contact_forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<[f64; 3]> = self
            .inner
            .contact_forces()
            .iter()
            .map(|f| f.to_array())
            .collect();
        arrays::read_only(arrays::rows3(py, &rows))
    }

    /// Total kinetic energy (translation and rotation) of the bodies.
    fn kinetic_energy(&self) -> f64 {
        let b = self.inner.bodies();
        (0..b.len()).map(|i| b.kinetic_energy(i)).sum()
    }

    /// The contacts and sub-contacts of the last step as arrays.
    ///
    /// Returns
    /// -------
    /// dict
    ///     Per contact (m rows): ``pairs`` (m, 2) int64 body ids A < B, ``types`` (m,) contact type
    ///     codes 1..7, ``normals`` (m, 3) from A to B, ``sets`` (m,) the joint set whose
    ///     properties apply (-1: the default), ``bridges`` (m,) whether it is over a rock
    ///     bridge (the set's bridge properties apply), ``sub_offsets`` (m + 1,) int64:
    ///     contact ``i`` has sub-contacts ``sub_offsets[i]:sub_offsets[i + 1]``. Per sub-contact: ``points``
    ///     (k, 3), ``areas``, ``gaps`` (> 0 apart), ``normal_forces`` (on B, > 0 in
    ///     compression; the joint's effective force, without the water's: see
    ///     :meth:`set_water`), ``shear_forces`` (k, 3) on B, ``shear_displacements`` (k, 3),
    ///     ``states`` (0 elastic, 1 sliding, 2 open), ``bonded`` (cohesion and tension
    ///     intact; False: failed, the residual strength applies), ``prestresses`` (the
    ///     normal stress an initial stress installed, > 0 in compression;
    ///     :meth:`set_initial_stress`). Per contact also ``water_forces`` (m,): the water
    ///     force pushing B from A along the normal (0 for none; :meth:`set_water`).
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.inner.contacts();
        let out = PyDict::new(py);
        let pairs: Vec<[i64; 2]> = c.list.iter().map(|c| c.bodies.map(i64::from)).collect();
        out.set_item("pairs", arrays::pairs(py, &pairs))?;
        let types: Vec<i8> = c.list.iter().map(|c| c.kind.code() as i8).collect();
        out.set_item("types", arrays::vector(py, types))?;
        let normals: Vec<[f64; 3]> = c.list.iter().map(|c| c.normal.to_array()).collect();
        out.set_item("normals", arrays::rows3(py, &normals))?;
        let sets: Vec<i64> = c.list.iter().map(|c| c.set.map_or(-1, i64::from)).collect();
        out.set_item("sets", arrays::vector(py, sets))?;
        let bridges: Vec<bool> = c.list.iter().map(|c| c.bridge).collect();
        out.set_item("bridges", arrays::vector(py, bridges))?;
        let mut offsets: Vec<i64> = c.list.iter().map(|c| i64::from(c.first)).collect();
        offsets.push(c.subs.len() as i64);
        out.set_item("sub_offsets", arrays::vector(py, offsets))?;
        let rows = |f: &dyn Fn(&mechanics::SubContact) -> DVec3| -> Vec<[f64; 3]> {
            c.subs.iter().map(|s| f(s).to_array()).collect()
        };
        out.set_item("points", arrays::rows3(py, &rows(&|s| s.point)))?;
        out.set_item("shear_forces", arrays::rows3(py, &rows(&|s| s.shear_force)))?;
        out.set_item(
            "shear_displacements",
            arrays::rows3(py, &rows(&|s| s.shear_displacement)),
        )?;
        let column = |f: &dyn Fn(&mechanics::SubContact) -> f64| -> Vec<f64> {
            c.subs.iter().map(f).collect()
        };
        out.set_item("areas", arrays::vector(py, column(&|s| s.area)))?;
        out.set_item("gaps", arrays::vector(py, column(&|s| s.gap)))?;
        out.set_item(
            "normal_forces",
            arrays::vector(py, column(&|s| s.normal_force)),
        )?;
        let states: Vec<u8> = c.subs.iter().map(|s| s.state.code()).collect();
        out.set_item("states", arrays::vector(py, states))?;
        let bonded: Vec<bool> = c.subs.iter().map(|s| s.bonded).collect();
        out.set_item("bonded", arrays::vector(py, bonded))?;
        let prestresses: Vec<f64> = (0..c.subs.len()).map(|k| c.prestress(k)).collect();
        out.set_item("prestresses", arrays::vector(py, prestresses))?;
        let water: Vec<f64> = self
            .inner
            .water()
            .contact_forces(c)
            .iter()
            .map(|w| w.0)
            .collect();
        out.set_item("water_forces", arrays::vector(py, water))?;
        Ok(out)
    }

    /// The joints opened beyond the detection gap that keep their water (``docs/mechanics.md``,
    /// "Water pressure in the joints", "Opened joints"): a face-face contact that carried
    /// water leaves one when its faces part; while the faces still face each other, within
    /// the smaller block's size, the water pushes them apart. Their water is not in
    /// :meth:`contacts` (no contact is there).
    ///
    /// Returns
    /// -------
    /// dict
    ///     Per opened joint at the last step (m rows): ``pairs`` (m, 2) int64 body ids (A, B),
    ///     ``sets`` (m,) the joint set (-1: none), ``water_forces`` (m,) the water force
    ///     pushing B from A along ``normals`` (m, 3) (A's face normal), at ``centres`` (m, 3)
    ///     (its centre of pressure, on A's face).
    fn opened_joints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let bodies = self.inner.part_bodies();
        let opened: Vec<&mechanics::WetJoint> = self
            .inner
            .wet_joints()
            .iter()
            .filter(|j| j.opened)
            .collect();
        let out = PyDict::new(py);
        let pairs: Vec<[i64; 2]> = opened
            .iter()
            .map(|j| j.parts.map(|p| i64::from(bodies[p as usize])))
            .collect();
        out.set_item("pairs", arrays::pairs(py, &pairs))?;
        let sets: Vec<i64> = opened.iter().map(|j| j.set.map_or(-1, i64::from)).collect();
        out.set_item("sets", arrays::vector(py, sets))?;
        let forces: Vec<f64> = opened.iter().map(|j| j.force).collect();
        out.set_item("water_forces", arrays::vector(py, forces))?;
        let normals: Vec<[f64; 3]> = opened.iter().map(|j| j.normal.to_array()).collect();
        out.set_item("normals", arrays::rows3(py, &normals))?;
        let centres: Vec<[f64; 3]> = opened.iter().map(|j| j.centre.to_array()).collect();
        out.set_item("centres", arrays::rows3(py, &centres))?;
        Ok(out)
    }

    /// An independent copy of the simulation in its current state (settings, bodies,
    /// contacts and their history): trials from one state, as a factor of safety by strength
    /// reduction runs them.
    fn copy(&self) -> Simulation {
        Simulation {
            inner: self.inner.clone(),
            note: self.note.clone(),
            origin: self.origin.clone(),
        }
    }

    /// Writes the whole state to a restart file (``docs/mechanics.md``, "Restart files"):
    /// bodies and their shapes, settings, joint properties, contacts with their
    /// sub-contacts' forces, shear histories and states, water pressures, rock bolts with
    /// their elements' state (forces, plastic elongations, yielding or broken), time and
    /// step count. Atomic: a
    /// temporary file renamed over `path`, never half a file. :meth:`load` gives back a
    /// simulation whose next steps are bit for bit those this one would take with the
    /// default update fraction 0 (:meth:`set_update_fraction`); with a fraction above 0,
    /// the loaded one queries every touching pair again at its first step and goes on within
    /// a bound of this run, not bit for bit (``docs/mechanics.md``, "Restart files").
    ///
    /// Parameters
    /// ----------
    /// path : str or os.PathLike
    /// note : str, optional
    ///     Free text kept in the file for the caller (:attr:`note` of the loaded simulation):
    ///     ``penedge simulate`` keeps where its run stands there.
    #[pyo3(signature = (path, note = None))]
    fn save(&self, py: Python<'_>, path: PathBuf, note: Option<String>) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| inner.save_state_noted(&path, note.as_deref()))
            .map_err(file_error(&path))
    }

    /// The note of the restart file this simulation was read from (None if none).
    #[getter]
    fn note(&self) -> Option<String> {
        self.note.clone()
    }

    /// The simulation saved by :meth:`save`, ready to go on.
    ///
    /// Parameters
    /// ----------
    /// path : str or os.PathLike
    ///
    /// Raises
    /// ------
    /// FileFormatError
    ///     Not a restart file, another version, cut short, or a bad field (named).
    /// OSError
    ///     The file cannot be read.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Simulation> {
        py.detach(|| mechanics::Simulation::load_state_noted(&path))
            .map(|(inner, note)| Simulation {
                inner,
                note,
                origin: None,
            })
            .map_err(file_error(&path))
    }

    /// The blocks at their current poses, as a :class:`BlockSystem` (for files, pictures
    /// and detection): block ``i`` is block ``i`` of the system the simulation was made of,
    /// moved with its body (:attr:`block_bodies`), with that system's body ids, joint sets
    /// (:attr:`BlockSystem.sets`, its provenance) and :attr:`BlockSystem.unit`. A body that
    /// rock bridges hold is several bodies in the simulation (so that a bridge can break):
    /// its pieces are separate bodies here too, the piece of its first block keeping the
    /// system's id and the others numbered on from the system's largest id. A simulation
    /// read from a restart file (:meth:`load`) has the blocks in the same order, with the
    /// sets (:attr:`BlockSystem.sets`), joint table, unit and body ids the file kept, but
    /// no domain; a file written before 2026-11-29 kept none of them: no sets, no unit,
    /// and :attr:`block_bodies` as the body ids.
    ///
    /// :meth:`BlockSystem.detect` on it sees what the simulation sees only at the
    /// simulation's gap (``gap=`` as given to :class:`Simulation`, default 1e-3): the joints
    /// carry their load by overlapping a little (``m g / (kn A)`` under a block's weight),
    /// and at detect's own default gap (1e-12) a block resting on another reads as
    /// penetrating. The system does not carry the gap; pass it.
    ///
    /// Raises
    /// ------
    /// MechanicsError
    ///     The parts of a body no longer fit together as its blocks (never expected: the
    ///     bodies are rigid); kind ``concave``.
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    /// >>> cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    /// >>> sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0)
    /// >>> sim.fix([0])
    /// >>> sim.solve()["converged"]
    /// True
    /// >>> placed = sim.system()
    /// >>> placed.detect(gap=1e-3).types.tolist(), len(placed.detect().penetrating)
    /// ([7], 1)
    fn system(&self, py: Python<'_>) -> PyResult<BlockSystem> {
        let placed = self.inner.placed_system();
        let block_bodies = self.inner.block_bodies();
        let Some(parts) = part_of_block(block_bodies, self.inner.part_bodies()) else {
            // Never: a simulation's blocks are its bodies' parts (checked on reading a
            // restart file); the parts as they are rather than a wrong order.
            let message = "the simulation's blocks do not match its bodies' parts";
            return Err(to_py_err(Error::Mechanics(
                "internal".into(),
                message.into(),
            )));
        };
        let blocks: Vec<ConvexBlock> = parts.iter().map(|&k| placed.blocks()[k].clone()).collect();
        let (system, ids) = match self.origin.as_deref() {
            Some(o) if o.body_ids.len() == blocks.len() => (
                penedge::BlockSystem::with_provenance(
                    blocks,
                    o.domain.clone(),
                    o.joints.clone(),
                    o.sets.clone(),
                )
                .with_unit(o.unit.clone()),
                placed_body_ids(&o.body_ids, block_bodies),
            ),
            _ => {
                // Read from a restart file: the sets, joint table, unit and body ids it
                // kept (none in a file written before 2026-11-29), no domain.
                let labels = self.inner.system_labels();
                let ids = if labels.body_ids.len() == blocks.len() {
                    placed_body_ids(&labels.body_ids, block_bodies)
                } else {
                    block_bodies.to_vec()
                };
                let (sets, joints) = (labels.sets.clone(), labels.joints.clone());
                let system =
                    penedge::BlockSystem::with_provenance(blocks, Vec::new(), joints, sets)
                        .with_unit(labels.unit.clone());
                (system, ids)
            }
        };
        // The glue of the concave bodies, found again at their poses (nothing to find when
        // every block is its own body).
        py.detach(|| system.with_bodies(ids, &Tolerance::default()))
            .map(BlockSystem::wrap)
            .map_err(|e| {
                let message = format!("the blocks at their current poses: {e}");
                to_py_err(Error::Mechanics("concave".into(), message))
            })
    }
}
