//! Initial stresses of a rigid-block rock mass: a stress field installed as contact forces
//! at the first detection (docs/mechanics.md, "Initial stresses").
//!
//! Rigid blocks have no stress inside; what a stressed rock mass means for them is the
//! forces across its joints. So an initial stress `σ(p)` is installed on each sub-contact
//! of a face-face contact found touching at the first detection (a vertex or an edge
//! touching has no real area to carry a stress), at its point `p`, as the traction `σ n` across
//! the contact plane (normal `n` from A to B): a **normal stress** `σn = -n·σ·n`
//! (compression positive, as the normal forces) kept by the sub-contact besides its elastic
//! `-kn gap` (its normal force is `(σn - kn gap) A`), and a **shear force** `-(σ n - (n·σ·n)
//! n) A` on B, which the shear law then carries and updates as any shear force. The
//! installed normal stress goes when the sub-contact opens. A block whose faces all touch
//! others in a uniform field is then in equilibrium at the first step (`∮ σ m dA = 0`).

use super::MechanicsError;
use crate::geometry::DVec3;
use glam::DMat3;

/// A stress field, tension positive (Pa), linear in depth: `σ(p) = base + d(p) per_depth`
/// with `d(p) = max(0, surface - p.z)` the depth below the surface. Components in the order
/// `xx, yy, zz, xy, yz, zx`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialStress {
    /// The stress at the surface (and above it).
    pub base: [f64; 6],
    /// Its increase per unit depth below the surface.
    pub per_depth: [f64; 6],
    /// The elevation of the surface (z).
    pub surface: f64,
}

impl InitialStress {
    /// The same stress everywhere (tension positive): `xx, yy, zz, xy, yz, zx`.
    pub fn uniform(components: [f64; 6]) -> InitialStress {
        InitialStress {
            base: components,
            per_depth: [0.0; 6],
            surface: 0.0,
        }
    }

    /// The stress of an overburden of unit weight `unit_weight` (ρ g, N/m³) above the
    /// elevation `surface`: `σzz = -unit_weight (surface - z)`, `σxx = k0_x σzz`,
    /// `σyy = k0_y σzz`, no shear; zero above the surface.
    pub fn overburden(surface: f64, unit_weight: f64, k0_x: f64, k0_y: f64) -> InitialStress {
        InitialStress {
            base: [0.0; 6],
            per_depth: [
                -unit_weight * k0_x,
                -unit_weight * k0_y,
                -unit_weight,
                0.0,
                0.0,
                0.0,
            ],
            surface,
        }
    }

    /// The field if its numbers are finite.
    pub fn validated(self) -> Result<InitialStress, MechanicsError> {
        let finite = self
            .base
            .iter()
            .chain(&self.per_depth)
            .all(|v| v.is_finite());
        if !(finite && self.surface.is_finite()) {
            return Err(MechanicsError::NotFinite("the initial stress"));
        }
        Ok(self)
    }

    /// The stress tensor at `p`.
    pub fn at(&self, p: DVec3) -> DMat3 {
        let depth = (self.surface - p.z).max(0.0);
        let c: [f64; 6] = std::array::from_fn(|k| self.base[k] + depth * self.per_depth[k]);
        let [xx, yy, zz, xy, yz, zx] = c;
        DMat3::from_cols(
            DVec3::new(xx, xy, zx),
            DVec3::new(xy, yy, yz),
            DVec3::new(zx, yz, zz),
        )
    }

    /// At a contact point `p` with normal `n` (A to B): the normal stress (compression
    /// positive) and the shear stress on B (in the contact plane).
    pub fn traction(&self, p: DVec3, n: DVec3) -> (f64, DVec3) {
        let t = self.at(p) * n;
        let normal = n.dot(t);
        (-normal, -(t - n * normal))
    }
}
