//! The state of the bodies, one array per quantity (structure of arrays), addressed by body
//! id (the index).

use super::MechanicsError;
use crate::block::{ConvexBlock, Pose};
use crate::body::Shape;
use crate::geometry::DVec3;
use glam::DMat3;
use std::sync::Arc;

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
/// reports them), except right after they are set: then they are at `t` and the next step
/// starts with a half kick.
#[derive(Clone, Debug, Default)]
pub struct Bodies {
    pub(super) shapes: Vec<Arc<Shape>>,
    pub(super) density: Vec<f64>,
    pub(super) mass: Vec<f64>,
    /// Principal moments of inertia (mass, not per unit density), about the body axes.
    pub(super) inertia: Vec<DVec3>,
    pub(super) pose: Vec<Pose>,
    pub(super) velocity: Vec<DVec3>,
    /// Angular momentum, world frame.
    pub(super) momentum: Vec<DVec3>,
    pub(super) fixity: Vec<Fixity>,
    /// An applied force on the centroid, besides gravity and contacts (world frame).
    pub(super) applied: Vec<DVec3>,
    /// Per body `[S, Σ_f A_f max_v |r_v|²]` per unit stiffness (critical time step).
    pub(super) stiffness_bounds: Vec<[f64; 2]>,
    /// Per body, the factor of its inertia (mass and moments) in the equations of motion:
    /// 1, or more under mass scaling (quasi-static runs; gravity keeps the true mass).
    pub(super) scale: Vec<f64>,
}

impl Bodies {
    /// One body per block, each of density `density`, at rest where the block is.
    pub fn from_blocks(blocks: &[ConvexBlock], density: f64) -> Result<Bodies, MechanicsError> {
        check_density(density)?;
        let mut bodies = Bodies::default();
        for (i, block) in blocks.iter().enumerate() {
            let (shape, pose) = Shape::from_parts(std::slice::from_ref(block))
                .map_err(|e| MechanicsError::Body(i, e))?;
            bodies.push(Arc::new(shape), pose, density);
        }
        Ok(bodies)
    }

    /// Adds a body of `shape` at `pose`, at rest and free; returns its id.
    pub fn push(&mut self, shape: Arc<Shape>, pose: Pose, density: f64) -> usize {
        let bounds = stiffness_bounds(&shape);
        self.shapes.push(shape);
        self.density.push(density);
        self.mass.push(0.0);
        self.inertia.push(DVec3::ZERO);
        self.pose.push(pose);
        self.velocity.push(DVec3::ZERO);
        self.momentum.push(DVec3::ZERO);
        self.fixity.push(Fixity::Free);
        self.applied.push(DVec3::ZERO);
        self.stiffness_bounds.push(bounds);
        self.scale.push(1.0);
        let id = self.len() - 1;
        self.update_mass(id);
        id
    }

    fn update_mass(&mut self, i: usize) {
        let s = &self.shapes[i];
        self.mass[i] = s.volume() * self.density[i];
        self.inertia[i] = s.principal_moments() * self.density[i];
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

    /// Masses.
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Principal moments of inertia (about the body axes).
    pub fn principal_inertia(&self) -> &[DVec3] {
        &self.inertia
    }

    /// Densities.
    pub fn densities(&self) -> &[f64] {
        &self.density
    }

    /// How each body moves.
    pub fn fixities(&self) -> &[Fixity] {
        &self.fixity
    }

    /// Applied forces.
    pub fn applied_forces(&self) -> &[DVec3] {
        &self.applied
    }

    /// The mass of body `i` in its equation of motion: its mass times its mass-scaling factor.
    pub fn inertial_mass(&self, i: usize) -> f64 {
        self.mass[i] * self.scale[i]
    }

    /// The principal moments of body `i` in its equation of motion (times its mass-scaling
    /// factor).
    pub fn inertial_moments(&self, i: usize) -> DVec3 {
        self.inertia[i] * self.scale[i]
    }

    /// Mass-scaling factors (1 without mass scaling).
    pub fn mass_scales(&self) -> &[f64] {
        &self.scale
    }

    /// Sets body `i`'s mass-scaling factor, keeping its velocity and spin.
    pub(super) fn set_scale(&mut self, i: usize, scale: f64) {
        self.momentum[i] *= scale / self.scale[i];
        self.scale[i] = scale;
    }

    /// The angular velocity of body `i` (world frame): `ω = R I⁻¹ Rᵀ L` for a free body,
    /// the prescribed spin or zero otherwise.
    pub fn spin(&self, i: usize) -> DVec3 {
        match self.fixity[i] {
            Fixity::Free => {
                let q = self.pose[i].rotation;
                q * (q.conjugate() * self.momentum[i] / self.inertial_moments(i))
            }
            Fixity::Fixed => DVec3::ZERO,
            Fixity::Prescribed { spin, .. } => spin,
        }
    }

    /// The velocity of body `i`'s centroid: its own when free, else fixed or prescribed.
    pub fn velocity(&self, i: usize) -> DVec3 {
        match self.fixity[i] {
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
        let rot = match self.fixity[i] {
            Fixity::Free => {
                (body_momentum * body_momentum / self.inertial_moments(i)).element_sum()
            }
            _ => {
                let w = q.conjugate() * self.spin(i);
                (self.inertial_moments(i) * w * w).element_sum()
            }
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
        let old = self.inertial_moments(i);
        self.density[i] = density;
        self.update_mass(i);
        // The angular velocity stays: scale the momentum with the inertia.
        let q = self.pose[i].rotation;
        let w = q.conjugate() * self.momentum[i] / old;
        self.momentum[i] = q * (w * self.inertial_moments(i));
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
        let r = DMat3::from_quat(self.pose[i].rotation);
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

/// `[S, Σ_f A_f max_v |r_v|²]` of a shape: its surface area, and the bound of its rotational
/// stiffness per unit stiffness (docs/mechanics.md, "Critical time step").
fn stiffness_bounds(shape: &Shape) -> [f64; 2] {
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
    /// One body per body of `system` ([`crate::BlockSystem::body_parts`], by ascending body
    /// id): a concave block (parts sharing a body id, [`crate::BlockSystem::with_bodies`]) is
    /// one rigid body of all its parts, with the mass, centroid and inertia of their union
    /// ([`Shape::from_parts`]); each block of a system without concave blocks is its own
    /// body, in block order (as [`Bodies::from_blocks`]). Density `density`, at rest.
    pub fn from_system(
        system: &crate::BlockSystem,
        density: f64,
    ) -> Result<Bodies, MechanicsError> {
        if !system.has_concave() {
            return Bodies::from_blocks(system.blocks(), density);
        }
        check_density(density)?;
        let mut bodies = Bodies::default();
        for (i, (_, parts)) in system.body_parts().into_iter().enumerate() {
            let blocks: Vec<ConvexBlock> = parts
                .iter()
                .map(|&k| system.blocks()[k as usize].clone())
                .collect();
            let (shape, pose) =
                Shape::from_parts(&blocks).map_err(|e| MechanicsError::Body(i, e))?;
            bodies.push(Arc::new(shape), pose, density);
        }
        Ok(bodies)
    }
}
