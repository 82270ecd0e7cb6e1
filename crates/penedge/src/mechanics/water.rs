//! Water pressure in the joints (docs/mechanics.md, "Water pressure in the joints"): a
//! phreatic surface giving a hydrostatic pressure below it, or a uniform pressure per joint
//! set; the pressure acts on the face-face contacts' polygons, pushing the two blocks apart,
//! and the joint law's spring force is then the effective normal force (3DEC's convention).

use super::contacts::Contacts;
use super::MechanicsError;
use crate::block::Pose;
use crate::classify::ContactType;
use crate::geometry::DVec3;
use std::collections::BTreeMap;

/// The water in the joints: none (the default), a phreatic surface, pressures per joint set,
/// or both (a set's pressure then replaces the phreatic one on that set's contacts).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Water {
    /// The phreatic surface: a point on it and its unit normal (upward, `n.z > 0`), and the
    /// unit weight of water `ρw g` (pressure per depth).
    pub(super) surface: Option<(DVec3, DVec3, f64)>,
    /// Uniform pressures per joint set.
    pub(super) sets: BTreeMap<u32, f64>,
}

impl Water {
    /// No water.
    pub fn none() -> Water {
        Water::default()
    }

    /// A phreatic surface: the plane through `point` with normal `normal` (any length, not
    /// horizontal: `normal.z ≠ 0`), and the unit weight of water `unit_weight = ρw g` (Pa/m
    /// in SI: 9810 for fresh water). Below it the pressure is `unit_weight × depth`, the depth
    /// measured vertically (along z) to the plane; zero above.
    pub fn phreatic(
        point: DVec3,
        normal: DVec3,
        unit_weight: f64,
    ) -> Result<Water, MechanicsError> {
        if !(point.is_finite() && normal.is_finite()) {
            return Err(MechanicsError::NotFinite("the phreatic surface"));
        }
        let length = normal.length();
        if !(length > 0.0 && normal.z.abs() > 1e-6 * length) {
            return Err(MechanicsError::Parameter {
                name: "phreatic normal",
                range: "a vector with a vertical component (the surface cannot be vertical)",
                value: normal.z,
            });
        }
        positive("unit_weight", unit_weight)?;
        let n = normal / length;
        let n = if n.z < 0.0 { -n } else { n };
        Ok(Water {
            surface: Some((point, n, unit_weight)),
            sets: BTreeMap::new(),
        })
    }

    /// A horizontal water table at elevation `z`.
    pub fn level(z: f64, unit_weight: f64) -> Result<Water, MechanicsError> {
        Water::phreatic(DVec3::new(0.0, 0.0, z), DVec3::Z, unit_weight)
    }

    /// Adds a uniform pressure (≥ 0) on the contacts of joint set `set`.
    pub fn with_set_pressure(mut self, set: u32, pressure: f64) -> Result<Water, MechanicsError> {
        if !(pressure.is_finite() && pressure >= 0.0) {
            return Err(MechanicsError::Parameter {
                name: "water pressure",
                range: "a finite number >= 0",
                value: pressure,
            });
        }
        self.sets.insert(set, pressure);
        Ok(self)
    }

    /// Whether there is any water.
    pub fn is_dry(&self) -> bool {
        self.surface.is_none() && self.sets.values().all(|&p| p == 0.0)
    }

    /// The pressure at point `p` of a contact of joint set `set` (≥ 0).
    pub fn pressure(&self, set: Option<u32>, p: DVec3) -> f64 {
        match (set.and_then(|s| self.sets.get(&s)), self.surface) {
            (Some(&u), _) => u,
            (None, Some((point, n, gamma))) => gamma * depth(point, n, p).max(0.0),
            (None, None) => 0.0,
        }
    }

    /// The water force on a polygon (corners in order, on a plane of normal `n`) of joint set
    /// `set`: the pressure's integral `U` over it (exact: a pressure linear in the depth
    /// and cut at the surface) and its centre of pressure; `None` when `U = 0`.
    pub fn polygon_force(
        &self,
        set: Option<u32>,
        corners: &[DVec3],
        n: DVec3,
    ) -> Option<(f64, DVec3)> {
        if corners.len() < 3 {
            return None;
        }
        let uniform = set.and_then(|s| self.sets.get(&s)).copied();
        let (mut force, mut moment) = (0.0, DVec3::ZERO);
        let o = corners[0];
        for k in 1..corners.len() - 1 {
            let tri = [o, corners[k], corners[k + 1]];
            let (f, m) = match (uniform, self.surface) {
                (Some(u), _) => {
                    let area = triangle_area(tri, n);
                    (u * area, (tri[0] + tri[1] + tri[2]) * (u * area / 3.0))
                }
                (None, Some((point, normal, gamma))) => {
                    submerged_integral(tri, n, |q| gamma * depth(point, normal, q))
                }
                (None, None) => (0.0, DVec3::ZERO),
            };
            force += f;
            moment += m;
        }
        (force > 0.0).then(|| (force, moment / force))
    }

    /// The water force of each contact, in the order of `contacts.list`: `U` (≥ 0; 0 for a
    /// contact that carries none) and its centre of pressure.
    pub fn contact_forces(&self, contacts: &Contacts) -> Vec<(f64, DVec3)> {
        let mut out = vec![(0.0, DVec3::ZERO); contacts.list.len()];
        self.each_force(contacts, |i, u, at| out[i] = (u, at));
        out
    }

    /// Calls `f(i, U, centre)` for each contact `i` that carries a water force: the
    /// face-face contacts' polygons (docs/mechanics.md: open or closed alike; point, edge and
    /// strip contacts carry none), in contact order. The polygon is read from the contact's
    /// sub-contacts, which for a face-face polygon are its corners in order (contacts.rs);
    /// the tests of a block on a wet incline (tests/water.rs, the effective normal force)
    /// and of a cube under a water table (python/tests/test_mechanics.py, `u A`) fail if
    /// they are not.
    fn each_force(&self, contacts: &Contacts, mut f: impl FnMut(usize, f64, DVec3)) {
        if self.is_dry() {
            return;
        }
        let mut corners = Vec::new();
        for (i, c) in contacts.list.iter().enumerate() {
            if c.kind != ContactType::FaceFace || c.count < 3 {
                continue;
            }
            corners.clear();
            corners.extend(contacts.subs_of(i).iter().map(|s| s.point));
            if let Some((u, at)) = self.polygon_force(c.set, &corners, c.normal) {
                f(i, u, at);
            }
        }
    }

    /// Adds the water forces to the bodies' contact forces and moments (about their
    /// centroids): `U n` on B at the centre of pressure, `-U n` on A. In contact order on one
    /// thread, as the sub-contacts' forces.
    pub(super) fn add_forces(
        &self,
        contacts: &Contacts,
        poses: &[Pose],
        forces: &mut [DVec3],
        moments: &mut [DVec3],
    ) {
        self.each_force(contacts, |i, u, at| {
            let c = &contacts.list[i];
            let f = c.normal * u;
            let [a, b] = [c.bodies[0] as usize, c.bodies[1] as usize];
            forces[b] += f;
            moments[b] += (at - poses[b].translation).cross(f);
            forces[a] -= f;
            moments[a] -= (at - poses[a].translation).cross(f);
        });
    }
}

fn positive(name: &'static str, v: f64) -> Result<(), MechanicsError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(MechanicsError::Parameter {
            name,
            range: "a finite number > 0",
            value: v,
        })
    }
}

/// The depth of `p` below the plane through `point` with upward normal `n`, measured along z.
fn depth(point: DVec3, n: DVec3, p: DVec3) -> f64 {
    n.dot(point - p) / n.z
}

/// The area of a triangle projected on the plane of normal `n`.
fn triangle_area(t: [DVec3; 3], n: DVec3) -> f64 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).dot(n).abs()
}

/// `∫ u dA` and `∫ u x dA` over the part of triangle `t` where the linear function `u` is
/// positive (the triangle clipped at `u = 0`, then split into triangles on which `u` is
/// linear: `∫ u = A ū`, `∫ u x = A / 12 (Σ uᵢ xᵢ + Σ uᵢ Σ xᵢ)`).
fn submerged_integral(t: [DVec3; 3], n: DVec3, u: impl Fn(DVec3) -> f64) -> (f64, DVec3) {
    let values = t.map(&u);
    // Sutherland-Hodgman against u ≥ 0: at most 4 corners.
    let mut clipped: Vec<(DVec3, f64)> = Vec::with_capacity(4);
    for i in 0..3 {
        let j = (i + 1) % 3;
        let (p, up, q, uq) = (t[i], values[i], t[j], values[j]);
        if up >= 0.0 {
            clipped.push((p, up));
        }
        if (up >= 0.0) != (uq >= 0.0) {
            let s = up / (up - uq);
            clipped.push((p + (q - p) * s, 0.0));
        }
    }
    let (mut total, mut first) = (0.0, DVec3::ZERO);
    for k in 1..clipped.len().saturating_sub(1) {
        let tri = [clipped[0], clipped[k], clipped[k + 1]];
        let area = triangle_area(tri.map(|(p, _)| p), n);
        let sum_u: f64 = tri.iter().map(|&(_, v)| v).sum();
        let sum_x: DVec3 = tri.iter().map(|&(p, _)| p).sum();
        let cross: DVec3 = tri.iter().map(|&(p, v)| p * v).sum();
        total += area * sum_u / 3.0;
        first += (cross + sum_x * sum_u) * (area / 12.0);
    }
    (total, first)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square 2 × 2 in the plane x-z (normal y), from z = 0 to 2, under a water table
    /// at z = 1 (γ = 10): the pressure is 10 (1 − z) on its lower half; U = ∫₀¹ 10 (1 − z) 2
    /// dz = 10, centre of pressure at z = 1/3 (a triangle's centroid), x = 1.
    #[test]
    fn a_polygon_cut_by_the_water_table_gets_the_exact_force_and_centre() {
        let water = Water::level(1.0, 10.0).unwrap();
        let square = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 2.0),
            DVec3::new(0.0, 0.0, 2.0),
        ];
        let (u, at) = water.polygon_force(None, &square, DVec3::Y).unwrap();
        assert!((u - 10.0).abs() < 1e-12, "{u}");
        assert!(
            (at - DVec3::new(1.0, 0.0, 1.0 / 3.0)).length() < 1e-12,
            "{at:?}"
        );
        // All above the table: no force.
        let high: Vec<DVec3> = square.iter().map(|&p| p + DVec3::Z * 5.0).collect();
        assert!(water.polygon_force(None, &high, DVec3::Y).is_none());
        // A set pressure replaces the phreatic one: uniform, at the centroid.
        let water = water.with_set_pressure(3, 7.0).unwrap();
        let (u, at) = water.polygon_force(Some(3), &square, DVec3::Y).unwrap();
        assert!((u - 28.0).abs() < 1e-12 && (at - DVec3::new(1.0, 0.0, 1.0)).length() < 1e-12);
        assert_eq!(water.pressure(Some(3), DVec3::ZERO), 7.0);
        assert_eq!(water.pressure(Some(4), DVec3::new(5.0, 5.0, -1.0)), 20.0);
    }

    /// An inclined table: depth measured vertically to the plane.
    #[test]
    fn an_inclined_table_gives_the_vertical_depth() {
        // The plane z = 10 - x (normal (1, 0, 1)): at (4, 0, 0) the surface is at z = 6.
        let water =
            Water::phreatic(DVec3::new(0.0, 0.0, 10.0), DVec3::new(-1.0, 0.0, -1.0), 2.0).unwrap();
        assert!((water.pressure(None, DVec3::new(4.0, 3.0, 0.0)) - 12.0).abs() < 1e-12);
        assert_eq!(water.pressure(None, DVec3::new(4.0, 3.0, 7.0)), 0.0);
    }

    #[test]
    fn bad_water_is_named() {
        let e = Water::phreatic(DVec3::ZERO, DVec3::X, 9810.0).unwrap_err();
        assert!(e.to_string().contains("vertical"), "{e}");
        assert!(Water::level(0.0, 0.0)
            .unwrap_err()
            .to_string()
            .contains("unit_weight"));
        assert!(Water::level(f64::NAN, 1.0).is_err());
        let e = Water::none().with_set_pressure(0, -1.0).unwrap_err();
        assert!(e.to_string().contains("water pressure"), "{e}");
    }
}
