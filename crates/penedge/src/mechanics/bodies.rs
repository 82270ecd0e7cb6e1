//! The state of the bodies, one array per quantity (structure of arrays), addressed by body
//! id (the index).

use super::MechanicsError;
use crate::block::{ConvexBlock, Pose};
use crate::body::Shape;
use crate::geometry::DVec3;
use glam::{DMat3, DQuat};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

/// How a body moves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Fixity {
    /// Moved by the forces on it.
    #[default]
    Free,
    /// Does not move.
    Fixed,
    /// Moves at a given velocity and spin (world frame), whatever the forces.
    Prescribed {
        /// Velocity of the centroid.
        velocity: DVec3,
        /// Angular velocity.
        spin: DVec3,
    },
}

/// The bodies of a simulation: shapes in their own frames and their state.
///
/// Velocities are those of the leapfrog's half step (`t - dt/2` before a step, as 3DEC
/// reports them), except right after they are set: then they are at `t`, and those bodies'
/// next step starts with a half kick (the `Simulation` keeps which).
///
/// Memory (docs/mechanics.md, "Memory"): 128 bytes per body, one entry in each of the six
/// arrays below. Mass and moments are the shape's (per unit density) times the density,
/// computed when asked (the same product as a stored one, so the same bits); the few bodies
/// with a prescribed motion or an applied force have them in side tables; the stiffness bounds
/// of the critical time step are computed from the shape when the time step is, and the time
/// step is kept until a body's density, scaling or fixity changes.
#[derive(Clone, Debug, Default)]
pub struct Bodies {
    pub(super) shapes: Vec<Arc<Shape>>,
    density: Vec<f64>,
    pub(super) pose: Vec<Pose>,
    pub(super) velocity: Vec<DVec3>,
    /// Angular momentum, world frame.
    pub(super) momentum: Vec<DVec3>,
    /// Per body, the factor of its inertia (mass and moments) in the equations of motion: 1,
    /// or more under mass scaling (quasi-static runs; gravity keeps the true mass). Negated
    /// for a body that is not free (fixed, or prescribed when in `prescribed`): the sign is
    /// the fixity, so that it takes no byte of its own.
    scale: Vec<f64>,
    /// The prescribed velocity and spin (world frame) of the bodies that have one.
    prescribed: BTreeMap<u32, [DVec3; 2]>,
    /// Applied forces on the centroids, besides gravity and contacts (world frame), of the
    /// bodies that have one.
    applied: BTreeMap<u32, DVec3>,
    /// The last critical time step computed: `(k, step)` for the largest joint stiffness
    /// `k`; cleared when a density, scaling factor or fixity changes.
    critical: CriticalCache,
}

/// A cached critical time step (a mutex so that `Bodies` stays `Sync` and can be read while
/// the step is computed from `&self`).
#[derive(Debug, Default)]
struct CriticalCache(Mutex<Option<(f64, Option<f64>)>>);

impl CriticalCache {
    fn get(&self) -> Option<(f64, Option<f64>)> {
        *self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn set(&self, value: Option<(f64, Option<f64>)>) {
        *self.0.lock().unwrap_or_else(|e| e.into_inner()) = value;
    }
}

impl Clone for CriticalCache {
    fn clone(&self) -> Self {
        CriticalCache(Mutex::new(self.get()))
    }
}

impl Bodies {
    /// One body per block, each of density `density`, at rest where the block is.
    pub fn from_blocks(blocks: &[ConvexBlock], density: f64) -> Result<Bodies, MechanicsError> {
        check_density(density)?;
        let mut bodies = Bodies::default();
        for (i, block) in blocks.iter().enumerate() {
            let (shape, pose) = Shape::from_parts(std::slice::from_ref(block))
                .map_err(|e| MechanicsError::Body(i, e))?;
            bodies.push(Arc::new(shape), pose, density)?;
        }
        Ok(bodies)
    }

    /// Adds a body of `shape` at `pose`, at rest and free; returns its id. The density must
    /// be a finite number > 0 ([`MechanicsError::Density`]), the pose finite with a unit
    /// quaternion (its squared length within 1e-12 of 1, as a restart file's:
    /// [`MechanicsError::Parameter`]), as [`Simulation::new`](super::Simulation::new)'s
    /// are: unchecked, a NaN density ran to a NaN state, and a quaternion of length 2 to a
    /// penetration of blocks that touched.
    pub fn push(
        &mut self,
        shape: Arc<Shape>,
        pose: Pose,
        density: f64,
    ) -> Result<usize, MechanicsError> {
        check_density(density)?;
        check_mass(self.len(), &shape, density)?;
        if !pose.translation.is_finite() {
            return Err(MechanicsError::NotFinite("the pose's translation"));
        }
        let squared = pose.rotation.length_squared();
        if !(pose.rotation.is_finite() && (squared - 1.0).abs() <= 1e-12) {
            return Err(MechanicsError::Parameter {
                name: "pose rotation's length",
                range: "1 (a unit quaternion)",
                value: squared.sqrt(),
            });
        }
        self.shapes.push(shape);
        self.density.push(density);
        self.pose.push(pose);
        self.velocity.push(DVec3::ZERO);
        self.momentum.push(DVec3::ZERO);
        self.scale.push(1.0);
        self.critical.set(None);
        Ok(self.len() - 1)
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether there is no body.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// The shape of body `i`.
    pub fn shape(&self, i: usize) -> &Arc<Shape> {
        &self.shapes[i]
    }

    /// Poses (body frame to world).
    pub fn poses(&self) -> &[Pose] {
        &self.pose
    }

    /// Velocities of the centroids.
    pub fn velocities(&self) -> &[DVec3] {
        &self.velocity
    }

    /// Angular momenta (world frame).
    pub fn angular_momenta(&self) -> &[DVec3] {
        &self.momentum
    }

    /// The mass of body `i` (its shape's volume times its density).
    ///
    /// # Panics
    ///
    /// If there is no body `i` (`i >= self.len()`), as the other accessors of one body by
    /// id (`shape`, `moments`, `is_free`, `fixity`, `mass_scale`, `inertial_mass`,
    /// `inertial_moments`, `spin`, `velocity`, `kinetic_energy`, `world_inertia`); the
    /// [`super::Simulation`] methods that take a body id return
    /// [`MechanicsError::UnknownBody`] instead.
    pub fn mass(&self, i: usize) -> f64 {
        self.inertia().mass(i)
    }

    /// The principal moments of inertia of body `i` about its axes (mass, not per unit
    /// density).
    pub fn moments(&self, i: usize) -> DVec3 {
        self.inertia().moments(i)
    }

    /// Masses.
    pub fn masses(&self) -> Vec<f64> {
        (0..self.len()).map(|i| self.mass(i)).collect()
    }

    /// Principal moments of inertia (about the body axes).
    pub fn principal_inertia(&self) -> Vec<DVec3> {
        (0..self.len()).map(|i| self.moments(i)).collect()
    }

    /// Densities.
    pub fn densities(&self) -> &[f64] {
        &self.density
    }

    /// Whether body `i` is free (moved by the forces on it).
    pub fn is_free(&self, i: usize) -> bool {
        self.inertia().is_free(i)
    }

    /// How body `i` moves.
    ///
    /// # Panics
    ///
    /// If there is no body `i` (`i >= self.len()`).
    pub fn fixity(&self, i: usize) -> Fixity {
        self.inertia().fixity(i)
    }

    /// How each body moves.
    pub fn fixities(&self) -> Vec<Fixity> {
        (0..self.len()).map(|i| self.fixity(i)).collect()
    }

    /// The applied force on body `i` (zero when none was applied).
    pub fn applied_force(&self, i: usize) -> DVec3 {
        self.inertia().applied_force(i)
    }

    /// Applied forces.
    pub fn applied_forces(&self) -> Vec<DVec3> {
        (0..self.len()).map(|i| self.applied_force(i)).collect()
    }

    /// The mass-scaling factor of body `i` (1 without mass scaling).
    pub fn mass_scale(&self, i: usize) -> f64 {
        self.inertia().mass_scale(i)
    }

    /// The mass of body `i` in its equation of motion: its mass times its mass-scaling factor.
    pub fn inertial_mass(&self, i: usize) -> f64 {
        self.inertia().inertial_mass(i)
    }

    /// The principal moments of body `i` in its equation of motion (times its mass-scaling
    /// factor).
    pub fn inertial_moments(&self, i: usize) -> DVec3 {
        self.inertia().inertial_moments(i)
    }

    /// Mass-scaling factors (1 without mass scaling).
    pub fn mass_scales(&self) -> Vec<f64> {
        (0..self.len()).map(|i| self.mass_scale(i)).collect()
    }

    /// Sets body `i`'s mass-scaling factor (≥ 1), keeping its velocity and spin.
    pub(super) fn set_scale(&mut self, i: usize, scale: f64) {
        let old = self.mass_scale(i);
        self.momentum[i] *= scale / old;
        self.scale[i] = scale.copysign(self.scale[i]);
        self.critical.set(None);
    }

    /// Sets how body `i` moves (its velocity and momentum stay as they are).
    pub(super) fn set_fixity(&mut self, i: usize, fixity: Fixity) -> Result<(), MechanicsError> {
        self.check(i)?;
        let id = i as u32;
        let scale = self.mass_scale(i);
        match fixity {
            Fixity::Free => {
                self.scale[i] = scale;
                self.prescribed.remove(&id);
            }
            Fixity::Fixed => {
                self.scale[i] = -scale;
                self.prescribed.remove(&id);
            }
            Fixity::Prescribed { velocity, spin } => {
                self.scale[i] = -scale;
                self.prescribed.insert(id, [velocity, spin]);
            }
        }
        self.critical.set(None);
        Ok(())
    }

    /// Sets the applied force on body `i` (zero removes it).
    pub(super) fn set_applied(&mut self, i: usize, force: DVec3) -> Result<(), MechanicsError> {
        self.check(i)?;
        if !force.is_finite() {
            return Err(MechanicsError::NotFinite("applied force"));
        }
        if force == DVec3::ZERO {
            self.applied.remove(&(i as u32));
        } else {
            self.applied.insert(i as u32, force);
        }
        Ok(())
    }

    /// The angular velocity of body `i` (world frame): `ω = R I⁻¹ Rᵀ L` for a free body,
    /// the prescribed spin or zero otherwise.
    pub fn spin(&self, i: usize) -> DVec3 {
        self.inertia()
            .spin(i, self.pose[i].rotation, self.momentum[i])
    }

    /// The velocity of body `i`'s centroid: its own when free, else fixed or prescribed.
    ///
    /// # Panics
    ///
    /// If there is no body `i` (`i >= self.len()`).
    pub fn velocity(&self, i: usize) -> DVec3 {
        match self.fixity(i) {
            Fixity::Free => self.velocity[i],
            Fixity::Fixed => DVec3::ZERO,
            Fixity::Prescribed { velocity, .. } => velocity,
        }
    }

    /// Kinetic energy of body `i` (translation and rotation; with its scaled inertia under
    /// mass scaling).
    pub fn kinetic_energy(&self, i: usize) -> f64 {
        let v = self.velocity(i);
        let q = self.pose[i].rotation;
        let body_momentum = q.conjugate() * self.momentum[i];
        let rot = if self.is_free(i) {
            (body_momentum * body_momentum / self.inertial_moments(i)).element_sum()
        } else {
            let w = q.conjugate() * self.spin(i);
            (self.inertial_moments(i) * w * w).element_sum()
        };
        0.5 * (self.inertial_mass(i) * v.length_squared() + rot)
    }

    pub(super) fn check(&self, i: usize) -> Result<(), MechanicsError> {
        if i < self.len() {
            Ok(())
        } else {
            Err(MechanicsError::UnknownBody {
                id: i,
                bodies: self.len(),
            })
        }
    }

    pub(super) fn set_density(&mut self, i: usize, density: f64) -> Result<(), MechanicsError> {
        self.check(i)?;
        check_density(density)?;
        check_mass(i, &self.shapes[i], density)?;
        let old = self.inertial_moments(i);
        self.density[i] = density;
        // The angular velocity stays: scale the momentum with the inertia.
        let q = self.pose[i].rotation;
        let w = q.conjugate() * self.momentum[i] / old;
        self.momentum[i] = q * (w * self.inertial_moments(i));
        self.critical.set(None);
        Ok(())
    }

    pub(super) fn set_velocity(
        &mut self,
        i: usize,
        velocity: DVec3,
        spin: DVec3,
    ) -> Result<(), MechanicsError> {
        self.check(i)?;
        if !(velocity.is_finite() && spin.is_finite()) {
            return Err(MechanicsError::NotFinite("velocity"));
        }
        self.velocity[i] = velocity;
        let q = self.pose[i].rotation;
        self.momentum[i] = q * (self.inertial_moments(i) * (q.conjugate() * spin));
        Ok(())
    }

    /// The inertia tensor of body `i` in the world frame (of its equation of motion).
    pub fn world_inertia(&self, i: usize) -> DMat3 {
        self.inertia().world_inertia(i, self.pose[i].rotation)
    }

    /// What the bodies are, apart from their motion (shapes, densities, fixities, loads).
    pub(super) fn inertia(&self) -> Inertia<'_> {
        Inertia {
            shapes: &self.shapes,
            density: &self.density,
            scale: &self.scale,
            prescribed: &self.prescribed,
            applied: &self.applied,
        }
    }

    /// The bodies split into what a step reads ([`Inertia`]) and their motion, which it
    /// writes in place, body by body in parallel: poses, velocities, angular momenta.
    pub(super) fn split_motion(&mut self) -> (Inertia<'_>, Motions<'_>) {
        let inertia = Inertia {
            shapes: &self.shapes,
            density: &self.density,
            scale: &self.scale,
            prescribed: &self.prescribed,
            applied: &self.applied,
        };
        let motions = Motions {
            pose: &mut self.pose,
            velocity: &mut self.velocity,
            momentum: &mut self.momentum,
        };
        (inertia, motions)
    }

    /// The critical time step for the largest joint stiffness `k`: the smallest bound of the
    /// free bodies with their inertia as scaled (`None` when no body is free). Computed from
    /// the shapes once, then kept while `k` and the bodies' densities, scaling factors and
    /// fixities stay (poses and velocities do not enter it).
    pub(super) fn critical_timestep(&self, k: f64) -> Option<f64> {
        if let Some((cached_k, step)) = self.critical.get() {
            if cached_k.to_bits() == k.to_bits() {
                return step;
            }
        }
        let step = (0..self.len())
            .filter(|&i| self.is_free(i))
            .map(|i| super::integrate::critical_step(self, i, k, self.mass_scale(i)))
            .reduce(f64::min);
        self.critical.set(Some((k, step)));
        step
    }
}

/// The motion of the bodies, one slice per quantity ([`Bodies::split_motion`]).
pub(super) struct Motions<'a> {
    pub pose: &'a mut [Pose],
    pub velocity: &'a mut [DVec3],
    /// Angular momentum, world frame.
    pub momentum: &'a mut [DVec3],
}

/// What the bodies are, apart from their motion: the quantities of their equations of
/// motion. The one place their formulas are written ([`Bodies`] asks it), so that the step,
/// which reads it while it writes the motion, computes the same bits.
#[derive(Clone, Copy)]
pub(super) struct Inertia<'a> {
    shapes: &'a [Arc<Shape>],
    density: &'a [f64],
    scale: &'a [f64],
    prescribed: &'a BTreeMap<u32, [DVec3; 2]>,
    applied: &'a BTreeMap<u32, DVec3>,
}

impl Inertia<'_> {
    /// The shape of body `i`.
    #[inline]
    pub(super) fn shape(&self, i: usize) -> &Arc<Shape> {
        &self.shapes[i]
    }

    /// Asks for body `i`'s shape (its mass properties and radius) ahead of its use, if there
    /// is such a body: a hint, with no effect on any result. Each shape is a separate
    /// allocation, one wait on memory per body in a step's loop over the bodies.
    #[inline(always)]
    pub(super) fn prefetch_shape(&self, i: usize) {
        if let Some(shape) = self.shapes.get(i) {
            crate::block::prefetch_value(&**shape);
        }
    }

    #[inline]
    pub(super) fn mass(&self, i: usize) -> f64 {
        self.shapes[i].volume() * self.density[i]
    }

    #[inline]
    pub(super) fn moments(&self, i: usize) -> DVec3 {
        self.shapes[i].principal_moments() * self.density[i]
    }

    #[inline]
    pub(super) fn is_free(&self, i: usize) -> bool {
        self.scale[i] > 0.0
    }

    #[inline]
    pub(super) fn fixity(&self, i: usize) -> Fixity {
        if self.is_free(i) {
            return Fixity::Free;
        }
        match self.prescribed.get(&(i as u32)) {
            Some(&[velocity, spin]) => Fixity::Prescribed { velocity, spin },
            None => Fixity::Fixed,
        }
    }

    #[inline]
    pub(super) fn applied_force(&self, i: usize) -> DVec3 {
        if self.applied.is_empty() {
            return DVec3::ZERO;
        }
        self.applied
            .get(&(i as u32))
            .copied()
            .unwrap_or(DVec3::ZERO)
    }

    #[inline]
    pub(super) fn mass_scale(&self, i: usize) -> f64 {
        self.scale[i].abs()
    }

    #[inline]
    pub(super) fn inertial_mass(&self, i: usize) -> f64 {
        self.mass(i) * self.mass_scale(i)
    }

    #[inline]
    pub(super) fn inertial_moments(&self, i: usize) -> DVec3 {
        self.moments(i) * self.mass_scale(i)
    }

    /// The angular velocity of body `i` at orientation `q` with angular momentum
    /// `momentum` ([`Bodies::spin`]).
    #[inline]
    pub(super) fn spin(&self, i: usize, q: DQuat, momentum: DVec3) -> DVec3 {
        match self.fixity(i) {
            Fixity::Free => q * (q.conjugate() * momentum / self.inertial_moments(i)),
            Fixity::Fixed => DVec3::ZERO,
            Fixity::Prescribed { spin, .. } => spin,
        }
    }

    /// The world inertia tensor of body `i` at orientation `q` ([`Bodies::world_inertia`]).
    pub(super) fn world_inertia(&self, i: usize, q: DQuat) -> DMat3 {
        let r = DMat3::from_quat(q);
        r * DMat3::from_diagonal(self.inertial_moments(i)) * r.transpose()
    }
}

fn check_density(density: f64) -> Result<(), MechanicsError> {
    if density.is_finite() && density > 0.0 {
        Ok(())
    } else {
        Err(MechanicsError::Density(density))
    }
}

/// Whether `shape` at `density` (valid) has a mass and principal moments that are finite
/// numbers > 0: a density of 1e308 on a 10 m cube gave an infinite mass, taken, and a step
/// that failed with a NaN state.
fn check_mass(body: usize, shape: &Shape, density: f64) -> Result<(), MechanicsError> {
    let mass = shape.volume() * density;
    let moments = shape.principal_moments() * density;
    let fine = |x: f64| x.is_finite() && x > 0.0;
    if fine(mass) && moments.to_array().into_iter().all(fine) {
        return Ok(());
    }
    Err(MechanicsError::Mass {
        body,
        density,
        mass,
        moment: moments.max_element(),
    })
}

/// `[S, Σ_f A_f max_v |r_v|²]` of a shape: its surface area, and the bound of its rotational
/// stiffness per unit stiffness (docs/mechanics.md, "Critical time step").
pub(super) fn stiffness_bounds(shape: &Shape) -> [f64; 2] {
    let mut out = [0.0; 2];
    for part in shape.parts() {
        let v = part.vertices();
        for face in part.faces() {
            let p0 = v[face[0] as usize];
            let mut twice = DVec3::ZERO;
            for w in face[1..].windows(2) {
                twice += (v[w[0] as usize] - p0).cross(v[w[1] as usize] - p0);
            }
            let area = 0.5 * twice.length();
            let r2 = face
                .iter()
                .map(|&k| v[k as usize].length_squared())
                .fold(0.0, f64::max);
            out[0] += area;
            out[1] += area * r2;
        }
    }
    out
}

impl Bodies {
    /// One rigid body per rigid body of `system` ([`crate::BlockSystem::rigid_body_ids`], in
    /// the order of their first block): a concave block (parts sharing a body id,
    /// [`crate::BlockSystem::with_bodies`]) is one rigid body of all its parts, with the mass,
    /// centroid and inertia of their union ([`Shape::from_parts`]), except that parts glued
    /// only across rock bridges (or a finite joint's crack) stay separate bodies, held by
    /// their bonded bridge contacts (docs/mechanics.md, "Rock bridges"); each block of a
    /// system without concave blocks is its own body, in block order (as
    /// [`Bodies::from_blocks`]). Density `density`, at rest.
    pub fn from_system(
        system: &crate::BlockSystem,
        density: f64,
    ) -> Result<Bodies, MechanicsError> {
        Ok(Bodies::of_system(system, density)?.0)
    }

    /// [`Bodies::from_system`], and per block of `system` its body.
    pub(super) fn of_system(
        system: &crate::BlockSystem,
        density: f64,
    ) -> Result<(Bodies, Vec<u32>), MechanicsError> {
        if !system.has_concave() {
            let bodies = Bodies::from_blocks(system.blocks(), density)?;
            return Ok((bodies, (0..system.len() as u32).collect()));
        }
        check_density(density)?;
        let ids = system.rigid_body_ids();
        let n = ids.iter().max().map_or(0, |&m| m as usize + 1);
        let mut parts: Vec<Vec<ConvexBlock>> = vec![Vec::new(); n];
        for (block, &b) in system.blocks().iter().zip(&ids) {
            parts[b as usize].push(block.clone());
        }
        let mut bodies = Bodies::default();
        for (i, blocks) in parts.iter().enumerate() {
            let (shape, pose) =
                Shape::from_parts(blocks).map_err(|e| MechanicsError::Body(i, e))?;
            bodies.push(Arc::new(shape), pose, density)?;
        }
        Ok((bodies, ids))
    }
}
