//! A body's geometry in its own frame (see `docs/bodies.md`).

use super::{BodyError, MassProperties};
use crate::block::{ConvexBlock, Pose};
use crate::geometry::DVec3;
use glam::DQuat;

/// A rigid body's geometry, in the body frame: one or more convex parts (one for a convex
/// block; several, glued along faces, for a concave one), with the origin at the centroid of
/// the whole body and the axes along its principal axes of inertia.
///
/// Immutable; bodies of the same shape share one (`Arc<Shape>`). Mass properties are per unit
/// density: multiply by the body's density.
#[derive(Clone, Debug)]
pub struct Shape {
    parts: Vec<ConvexBlock>,
    volume: f64,
    moments: DVec3,
    radius: f64,
}

impl Shape {
    /// The shape of the body made of `parts` (world coordinates, as in a block system), and
    /// the pose that places it where the parts are: the centroid of the union and its
    /// principal axes (`x_world = pose.apply(x_body)`).
    ///
    /// The parts must not overlap (they are glued along faces): that is the caller's to check
    /// (concave blocks, issue 20); the mass properties are those of their union.
    pub fn from_parts(parts: &[ConvexBlock]) -> Result<(Shape, Pose), BodyError> {
        let mass = MassProperties::of_parts(parts).ok_or(BodyError::NoParts)?;
        let principal = mass.principal();
        let to_body = principal.axes.conjugate();
        let parts: Vec<ConvexBlock> = parts
            .iter()
            .map(|p| {
                // (x - c) first: the difference of nearby coordinates is exact or nearly so,
                // then the rotation of small numbers.
                p.transformed(DQuat::IDENTITY, -mass.centroid, 1.0)
                    .transformed(to_body, DVec3::ZERO, 1.0)
            })
            .collect();
        let radius = parts
            .iter()
            .flat_map(|p| p.vertices())
            .fold(0.0f64, |r, v| r.max(v.length()));
        let pose = Pose::new(principal.axes, mass.centroid).ok_or(BodyError::NotFinite)?;
        let shape = Shape {
            parts,
            volume: mass.volume,
            moments: principal.moments,
            radius,
        };
        Ok((shape, pose))
    }

    /// A shape as a restart file stores it (`mechanics::state`): its body-frame parts and
    /// mass properties, kept bit for bit rather than recomputed.
    pub(crate) fn from_stored(
        parts: Vec<ConvexBlock>,
        volume: f64,
        moments: DVec3,
        radius: f64,
    ) -> Result<Shape, BodyError> {
        if parts.is_empty() {
            return Err(BodyError::NoParts);
        }
        if !(volume.is_finite() && moments.is_finite() && radius.is_finite()) {
            return Err(BodyError::NotFinite);
        }
        Ok(Shape {
            parts,
            volume,
            moments,
            radius,
        })
    }

    /// The convex parts, in the body frame.
    pub fn parts(&self) -> &[ConvexBlock] {
        &self.parts
    }

    /// Volume (the mass at unit density).
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Principal moments of inertia per unit density, ascending, about the body axes x, y, z.
    pub fn principal_moments(&self) -> DVec3 {
        self.moments
    }

    /// The largest distance of a vertex from the centroid: every point of the body lies
    /// within it (a bound for how far a point moves under a rotation).
    pub fn radius(&self) -> f64 {
        self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat3, EulerRot};

    #[test]
    fn a_shape_is_centred_on_principal_axes_and_its_pose_places_it_back() {
        let q = DQuat::from_euler(EulerRot::XYZ, 0.7, 0.2, -1.3);
        let offset = DVec3::new(512345.5, 4012345.25, 1234.125);
        let world = ConvexBlock::cuboid([0.0; 3], [1.0, 2.0, 4.0])
            .unwrap()
            .transformed(q, offset, 1.0);
        let (shape, pose) = Shape::from_parts(std::slice::from_ref(&world)).unwrap();
        let part = &shape.parts()[0];
        // Centred: the body-frame centroid is the origin; on principal axes: the box's
        // sides lie along the body axes, the longest (smallest moment) along x.
        assert!(part.centroid().length() < 1e-9);
        let extent = part.aabb().max - part.aabb().min;
        for (got, want) in extent.to_array().iter().zip([4.0, 2.0, 1.0]) {
            assert!((got - want).abs() < 1e-9, "{extent:?}");
        }
        // The world vertices at 4e6 are rounded by ~5e-10: the volume by about that times
        // the area (28).
        assert!((shape.volume() - 8.0).abs() < 28.0 * 4e6 * f64::EPSILON);
        assert!((shape.radius() - 21f64.sqrt() / 2.0).abs() < 1e-9);
        // Placing the body-frame vertices at the pose gives the world vertices back, to the
        // rounding of coordinates of 4e6 (a few units in the last place).
        for (p, w) in part.vertices().iter().zip(world.vertices()) {
            assert!((pose.apply(*p) - *w).length() < 8.0 * 4e6 * f64::EPSILON);
        }
        let axes = DMat3::from_quat(pose.rotation);
        assert!((axes.determinant() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn no_parts_is_an_error() {
        assert_eq!(Shape::from_parts(&[]).unwrap_err(), BodyError::NoParts);
    }
}
