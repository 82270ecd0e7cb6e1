//! Water pressure in the joints (docs/mechanics.md, "Water pressure in the joints"): a
//! phreatic surface giving a hydrostatic pressure below it, or a uniform pressure per joint
//! set; the pressure acts on the face-face contacts' polygons, pushing the two blocks apart,
//! and the joint law's spring force is then the effective normal force (3DEC's convention).

use super::contacts::Contacts;
use super::{MechanicsError, Simulation};
use crate::block::{ConvexBlock, Pose};
use crate::classify::ContactType;
use crate::classify::Feature;
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

/// A wet joint: two faces, of parts A and B, that met in a face-face contact carrying water.
/// While the contact lasts, its water is the contact's; once the faces have opened beyond
/// the detection gap (no contact), the joint stays full of water and keeps pushing them
/// apart, over the part of A's face that B's face still covers, while the joint stays
/// narrow and the faces face each other ([`opened_polygon`]; docs/mechanics.md, "Water
/// pressure in the joints", "Opened joints"). Without it, the water of a tension crack
/// vanished once the sliding block had opened the crack by the detection gap (a
/// centimetre for 10 m blocks), and a factor of safety by strength reduction came out that
/// of a dry crack: a slope failing by limit equilibrium was found stable.
#[derive(Clone, Debug, PartialEq)]
pub struct WetJoint {
    /// The two parts (A, B), as the contact's (global part ids).
    pub parts: [u32; 2],
    /// The face of A and the face of B.
    pub faces: [u32; 2],
    /// The joint set (the contact's): its pressure, when it has one of its own.
    pub set: Option<u32>,
    /// Whether the faces have opened: the pair has no contact this step, and the water
    /// force below is the opened joint's (else the contact carries its water).
    pub opened: bool,
    /// An opened joint's water force this step: `U` (≥ 0), pushing B along `normal` and A
    /// against it, at `centre` (0 for a joint that is a contact; not stored in restart
    /// files: computed at each step from the poses).
    pub force: f64,
    /// An opened joint's normal: A's face normal (A towards B).
    pub normal: DVec3,
    /// An opened joint's centre of pressure, on A's face.
    pub centre: DVec3,
}

/// How far the faces of an opened joint may part, as a fraction of the smaller block's size
/// (its bounding box's diagonal, the size that scales the detection gap): a joint opened
/// wider is taken as drained, and its water force goes. One block size: a sliding block
/// that limit equilibrium finds failing keeps its crack's water until it has slid out of
/// the crack (the faces no longer face each other), as limit equilibrium assumes; a tenth
/// of it let such a block stop after sliding 1.5 m, its crack taken as drained, and a
/// factor of safety by strength reduction found it stable. The bound is there for a block
/// that water lifts off its joint (a pressure above its weight's): it is pushed at most a
/// block size away, not for ever.
pub const OPENED_JOINT_WIDTH: f64 = 1.0;

/// The cosine of the largest angle between an opened joint's face normals (A's and B's
/// reversed, 10°): turned further apart, the faces no longer bound one joint.
pub const OPENED_JOINT_COS: f64 = 0.984_807_753_012_208; // cos 10°

/// The part of face `fa` of `a` (placed in the world) that face `fb` of `b` covers, seen
/// along B's face normal: A's face polygon clipped by the planes through B's face edges
/// parallel to B's normal. `None` when the faces no longer bound one opened joint: their
/// normals more than 10° from opposite ([`OPENED_JOINT_COS`]), the cover empty, or a corner
/// of it farther from B's face than [`OPENED_JOINT_WIDTH`] of the smaller block's size.
pub fn opened_polygon(a: &ConvexBlock, fa: u32, b: &ConvexBlock, fb: u32) -> Option<Vec<DVec3>> {
    let (pa, pb) = (a.planes().get(fa as usize)?, b.planes().get(fb as usize)?);
    if -pa.normal.dot(pb.normal) < OPENED_JOINT_COS {
        return None;
    }
    let mut polygon: Vec<DVec3> = a
        .face(fa as usize)
        .iter()
        .map(|&v| a.vertices()[v as usize])
        .collect();
    let cover: Vec<DVec3> = b
        .face(fb as usize)
        .iter()
        .map(|&v| b.vertices()[v as usize])
        .collect();
    let mut next = Vec::with_capacity(polygon.len() + cover.len());
    for k in 0..cover.len() {
        let (q0, q1) = (cover[k], cover[(k + 1) % cover.len()]);
        // B's face is counter-clockwise seen from outside B (along its normal): its inside
        // is to the left of each edge.
        let inward = pb.normal.cross(q1 - q0);
        let side = |x: DVec3| inward.dot(x - q0);
        next.clear();
        for i in 0..polygon.len() {
            let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                next.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                next.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        std::mem::swap(&mut polygon, &mut next);
        if polygon.len() < 3 {
            return None;
        }
    }
    let width = OPENED_JOINT_WIDTH * a.size().min(b.size());
    if polygon.iter().any(|&x| pb.distance(x) > width) {
        return None;
    }
    Some(polygon)
}

impl Simulation {
    /// The wet joints after this step's contacts are built ([`WetJoint`]): every face-face
    /// contact that carries water now, then every joint of the last step's list whose pair
    /// has no face-face contact now (none, or one of an edge or a vertex), with a body that
    /// moves, and whose faces still bound an opened joint ([`opened_polygon`]), with its
    /// water force; sorted by parts. Nothing without water (the list is emptied).
    pub(super) fn update_wet_joints(&mut self) {
        if self.water.is_dry() {
            self.wet.clear();
            return;
        }
        let old = std::mem::take(&mut self.wet);
        let mut wet = Vec::new();
        // The contacts that carry water now, as the forces are summed ([`Water::each_force`]).
        let (contacts, current, memo) = (&self.contacts, &self.current, &self.memo);
        self.water.each_force(contacts, |i, _, _| {
            let c = &contacts.list[i];
            let found = memo[current[i].pair as usize].found.as_deref();
            if let Some((Feature::Face(fa), Feature::Face(fb))) =
                found.map(|f| (f.contact.feature_a, f.contact.feature_b))
            {
                wet.push(WetJoint {
                    parts: c.parts,
                    faces: [fa, fb],
                    set: c.set,
                    opened: false,
                    force: 0.0,
                    normal: DVec3::ZERO,
                    centre: DVec3::ZERO,
                });
            }
        });
        for joint in old {
            // A pair with a face-face contact now: the contact carries its water (the first
            // loop). With no contact, or a contact of an edge or a vertex (a crack opening
            // as a V about a hinge, or a block tilting off its joint), the joint is open.
            let polygon_contact = self.contacts.find(joint.parts).is_some_and(|k| {
                let c = &self.contacts.list[k];
                c.kind == ContactType::FaceFace && c.count >= 3
            });
            // A pair of two bodies that do not move (fixed, prescribed or removed since) is
            // no candidate pair and has no contact, though its faces may touch: no joint.
            let moves = |p: u32| {
                let b = self.part_body[p as usize] as usize;
                self.bodies.is_free(b) && !self.is_removed(b)
            };
            let [pa, pb] = joint.parts;
            if polygon_contact || !(moves(pa) || moves(pb)) {
                continue;
            }
            if let Some(opened) = self.opened_joint(&joint) {
                wet.push(opened);
            }
        }
        wet.sort_by_key(|j| j.parts);
        self.wet = wet;
    }

    /// `joint` opened: its water force at the current poses, or `None` when its faces no
    /// longer bound one joint ([`opened_polygon`]) or a part of it was removed.
    fn opened_joint(&self, joint: &WetJoint) -> Option<WetJoint> {
        let [pa, pb] = joint.parts.map(|p| p as usize);
        let removed = |p: usize| self.is_removed(self.part_body[p] as usize);
        if removed(pa) || removed(pb) {
            return None;
        }
        let (a, b) = (&self.placed[pa], &self.placed[pb]);
        let [fa, fb] = joint.faces;
        let polygon = opened_polygon(a, fa, b, fb)?;
        let normal = a.planes()[fa as usize].normal;
        let (force, centre) = self
            .water
            .polygon_force(joint.set, &polygon, normal)
            .unwrap_or((0.0, DVec3::ZERO));
        Some(WetJoint {
            opened: true,
            force,
            normal,
            centre,
            ..joint.clone()
        })
    }

    /// After a restart file is read: the opened joints' forces at the file's poses (what
    /// [`Simulation::wet_joints`] reports until the next step, which computes them again).
    pub(super) fn refresh_opened_joints(&mut self) {
        let wet = std::mem::take(&mut self.wet);
        self.wet = wet
            .into_iter()
            .map(|j| match j.opened {
                true => self.opened_joint(&j).unwrap_or(j),
                false => j,
            })
            .collect();
    }

    /// Adds the opened joints' water forces to the bodies' sums: `U n` on B at the centre
    /// of pressure, `-U n` on A (after the contacts', in the joints' order: deterministic).
    pub(super) fn add_opened_joint_forces(&mut self) {
        let poses = &self.bodies.pose;
        for j in self.wet.iter().filter(|j| j.opened && j.force > 0.0) {
            let [a, b] = j.parts.map(|p| self.part_body[p as usize] as usize);
            let f = j.normal * j.force;
            self.forces[b] += f;
            self.moments[b] += (j.centre - poses[b].translation).cross(f);
            self.forces[a] -= f;
            self.moments[a] -= (j.centre - poses[a].translation).cross(f);
        }
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

    /// The covered part of an opened joint: a 2 × 2 face under a 1 × 1 face shifted by
    /// (0.5, 0.25) and lifted by `h` covers 1 × 1 (the whole smaller face) until it slides
    /// off the edge, half of it beyond; none when the faces turn 11° apart (10° is the
    /// bound) or part by more than the smaller block's size.
    #[test]
    fn an_opened_joint_covers_what_the_faces_still_share() {
        let a = ConvexBlock::cuboid([0.0, 0.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
        let top = |x: f64, y: f64, h: f64| {
            ConvexBlock::cuboid([x, y, h], [x + 1.0, y + 1.0, h + 1.0]).unwrap()
        };
        let up = |block: &ConvexBlock| {
            (0..block.n_faces() as u32)
                .find(|&f| block.planes()[f as usize].normal.z > 0.5)
                .unwrap()
        };
        let down = |block: &ConvexBlock| {
            (0..block.n_faces() as u32)
                .find(|&f| block.planes()[f as usize].normal.z < -0.5)
                .unwrap()
        };
        let area = |poly: &[DVec3]| {
            (1..poly.len() - 1)
                .map(|k| triangle_area([poly[0], poly[k], poly[k + 1]], DVec3::Z))
                .sum::<f64>()
        };
        let b = top(0.5, 0.25, 0.3);
        let poly = opened_polygon(&a, up(&a), &b, down(&b)).unwrap();
        assert!((area(&poly) - 1.0).abs() < 1e-12, "{poly:?}");
        assert!(poly.iter().all(|p| p.z == 0.0));
        let b = top(1.5, 0.25, 0.3);
        let poly = opened_polygon(&a, up(&a), &b, down(&b)).unwrap();
        assert!((area(&poly) - 0.5).abs() < 1e-12, "{poly:?}");
        // Apart by more than the smaller block's size (its diagonal, √3): drained.
        let b = top(0.5, 0.25, 1.8);
        assert!(opened_polygon(&a, up(&a), &b, down(&b)).is_none());
        let b = top(0.5, 0.25, 1.7);
        assert!(opened_polygon(&a, up(&a), &b, down(&b)).is_some());
        // Off the face: nothing covered.
        let b = top(2.5, 0.25, 0.3);
        assert!(opened_polygon(&a, up(&a), &b, down(&b)).is_none());
        // Turned 11° (about x, through the face's centre) and 9°.
        let turned = |deg: f64| {
            top(0.5, 0.5, 0.3).transformed(
                glam::DQuat::from_rotation_x(deg.to_radians()),
                DVec3::ZERO,
                1.0,
            )
        };
        for (deg, holds) in [(11.0, false), (9.0, true)] {
            let b = turned(deg);
            let got = opened_polygon(&a, up(&a), &b, down(&b));
            assert_eq!(got.is_some(), holds, "{deg}°");
        }
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
