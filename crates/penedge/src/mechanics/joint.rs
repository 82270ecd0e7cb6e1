//! The joint law: Mohr-Coulomb with tension cut-off and residual strength, per sub-contact,
//! and the joint properties per set (docs/mechanics.md, "Joint law").

use super::MechanicsError;
use crate::block::{ConvexBlock, FaceOrigin};
use crate::classify::Feature;
use crate::geometry::DVec3;
use std::collections::BTreeMap;

/// The properties of a joint (any consistent units; SI: Pa/m, degrees, Pa).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointModel {
    /// Normal stiffness, stress per displacement (> 0).
    pub kn: f64,
    /// Shear stiffness, stress per displacement (> 0).
    pub ks: f64,
    /// Friction angle in degrees, in [0, 90).
    pub friction: f64,
    /// Cohesion, a stress (≥ 0); 0 after failure.
    pub cohesion: f64,
    /// Tensile strength, a stress (≥ 0); 0 after failure.
    pub tension: f64,
    /// Friction angle after failure, in degrees in [0, 90); `None`: the friction angle.
    pub residual_friction: Option<f64>,
    /// Cohesion after failure, a stress (≥ 0; 3DEC's default 0).
    pub residual_cohesion: f64,
}

impl Default for JointModel {
    /// A stiff frictional joint without bond: kn = ks = 1e10 Pa/m, 30°, no cohesion or tension.
    fn default() -> Self {
        JointModel {
            kn: 1e10,
            ks: 1e10,
            friction: 30.0,
            cohesion: 0.0,
            tension: 0.0,
            residual_friction: None,
            residual_cohesion: 0.0,
        }
    }
}

impl JointModel {
    /// The model if every property is in range, else the error naming the first that is not.
    pub fn validated(self) -> Result<JointModel, MechanicsError> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(MechanicsError::Stiffness { name, value: v })
            }
        };
        positive("kn", self.kn)?;
        positive("ks", self.ks)?;
        let angle_ok = |a: f64| a.is_finite() && (0.0..90.0).contains(&a);
        if !angle_ok(self.friction) {
            return Err(MechanicsError::Friction(self.friction));
        }
        if let Some(a) = self.residual_friction.filter(|&a| !angle_ok(a)) {
            return Err(MechanicsError::Parameter {
                name: "residual_friction",
                range: "in [0, 90) degrees",
                value: a,
            });
        }
        for (name, v) in [
            ("cohesion", self.cohesion),
            ("tension", self.tension),
            ("residual_cohesion", self.residual_cohesion),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(MechanicsError::Strength { name, value: v });
            }
        }
        Ok(self)
    }

    /// tan φ.
    pub fn tan_friction(&self) -> f64 {
        self.friction.to_radians().tan()
    }

    /// The shear strength of a sub-contact: `(tan φ, c)` while its bond is intact, the
    /// residual `(tan φr, cr)` once it has failed (or for a contact formed during the run).
    pub fn strength(&self, bonded: bool) -> (f64, f64) {
        self.strength_with(bonded, &mut Tangents::default())
    }

    /// [`JointModel::strength`], its tangent taken from `tangents`.
    pub(super) fn strength_with(&self, bonded: bool, tangents: &mut Tangents) -> (f64, f64) {
        if bonded {
            (tangents.of(self.friction), self.cohesion)
        } else {
            let phi = self.residual_friction.unwrap_or(self.friction);
            (tangents.of(phi), self.residual_cohesion)
        }
    }
}

/// The tangents of the last two angles asked (degrees), remembered: the sub-contacts of a
/// step ask for the same one or two friction angles again and again, and a tangent costs
/// more than the rest of the joint law. The same values as `angle.to_radians().tan()`, bit
/// for bit.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Tangents {
    /// The angles' bits (0: 0°, whose tangent is 0, the default `values`).
    angles: [u64; 2],
    values: [f64; 2],
    /// The slot the next new angle replaces.
    next: usize,
}

impl Tangents {
    /// `tan` of `degrees`.
    pub fn of(&mut self, degrees: f64) -> f64 {
        let bits = degrees.to_bits();
        if let Some(k) = self.angles.iter().position(|&a| a == bits) {
            return self.values[k];
        }
        let value = degrees.to_radians().tan();
        self.angles[self.next] = bits;
        self.values[self.next] = value;
        self.next ^= 1;
        value
    }
}

/// The joint properties of a simulation: a default, and properties per joint set.
#[derive(Clone, Debug, Default)]
pub struct JointTable {
    default: JointModel,
    sets: BTreeMap<u32, JointModel>,
}

impl JointTable {
    /// The default model (contacts with no joint face, or of a set without its own).
    pub fn default_model(&self) -> &JointModel {
        &self.default
    }

    /// Sets the default model.
    pub fn set_default(&mut self, model: JointModel) -> Result<(), MechanicsError> {
        self.default = model.validated()?;
        Ok(())
    }

    /// Sets the model of joint set `set` (the `set` of `FaceOrigin::Joint`).
    pub fn set(&mut self, set: u32, model: JointModel) -> Result<(), MechanicsError> {
        self.sets.insert(set, model.validated()?);
        Ok(())
    }

    /// The sets with their own model, in increasing set order.
    pub fn sets(&self) -> impl Iterator<Item = (u32, &JointModel)> + '_ {
        self.sets.iter().map(|(&s, m)| (s, m))
    }

    /// The model of set `set` (the default when it has none).
    pub fn of_set(&self, set: Option<u32>) -> &JointModel {
        set.and_then(|s| self.sets.get(&s)).unwrap_or(&self.default)
    }

    /// The largest stiffness of any model (for the critical time step).
    pub fn max_stiffness(&self) -> f64 {
        std::iter::once(&self.default)
            .chain(self.sets.values())
            .fold(0.0f64, |k, m| k.max(m.kn).max(m.ks))
    }

    /// The joint set of a contact from its features' face origins (docs/mechanics.md): a
    /// face feature's set; for two faces of different sets, the weaker one; none without
    /// a joint face.
    pub fn set_of_contact(
        &self,
        a: &ConvexBlock,
        fa: Feature,
        b: &ConvexBlock,
        fb: Feature,
    ) -> Option<u32> {
        self.set_of_faces([face_set(a, fa), face_set(b, fb)])
    }

    /// The joint set of a contact whose two features have the sets `sets` ([`face_set`]):
    /// of two different sets, the weaker one (as [`JointTable::set_of_contact`]). A contact
    /// keeps its features between queries, so it keeps their sets and asks only this.
    pub(super) fn set_of_faces(&self, sets: [Option<u32>; 2]) -> Option<u32> {
        match sets {
            [Some(x), Some(y)] if x != y => {
                let (mx, my) = (self.of_set(Some(x)), self.of_set(Some(y)));
                let key = |m: &JointModel| (m.tan_friction(), m.cohesion);
                Some(if key(my) < key(mx) { y } else { x })
            }
            [Some(x), _] => Some(x),
            [None, y] => y,
        }
    }
}

/// The joint set of feature `f` of `block`: its face's set, none for an edge, a vertex or a
/// face of no set.
pub(super) fn face_set(block: &ConvexBlock, f: Feature) -> Option<u32> {
    match f {
        Feature::Face(i) => block
            .face_origins()
            .get(i as usize)
            .copied()
            .and_then(FaceOrigin::set),
        _ => None,
    }
}

/// The Mohr-Coulomb state of a sub-contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SubState {
    /// In contact, within the strength.
    #[default]
    Elastic,
    /// In contact, at the shear strength.
    Sliding,
    /// Apart, or failed in tension: no force.
    Open,
}

impl SubState {
    /// 0 elastic, 1 sliding, 2 open (for arrays).
    pub fn code(self) -> u8 {
        self as u8
    }
}

/// The force of one sub-contact after a step of the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LawOutcome {
    pub normal_force: f64,
    pub shear_force: DVec3,
    pub state: SubState,
    pub bonded: bool,
}

/// One step of the joint law for a sub-contact of area `area` and gap `gap`, with the shear
/// force `shear` already on the contact plane plus its elastic increment (docs/mechanics.md,
/// steps 2 to 4). A bond does not fail in tension while its gap is within `slack` (the
/// rounding of a gap of zero) beyond its strength.
pub(super) fn joint_law(
    model: &JointModel,
    area: f64,
    gap: f64,
    shear: DVec3,
    bonded: bool,
    slack: f64,
    tangents: &mut Tangents,
) -> LawOutcome {
    let fn_ = -model.kn * area * gap;
    let tension_held = bonded && gap <= model.tension / model.kn + slack;
    if fn_ < 0.0 && !tension_held || fn_ == 0.0 && !bonded {
        // Apart, or a bond failed in tension: no force, and the bond is gone for good.
        return LawOutcome {
            normal_force: 0.0,
            shear_force: DVec3::ZERO,
            state: SubState::Open,
            bonded: false,
        };
    }
    let (tan_phi, cohesion) = model.strength_with(bonded, tangents);
    // Friction from compression only: tension on a bond leaves its cohesion.
    let limit = cohesion * area + fn_.max(0.0) * tan_phi;
    let magnitude = shear.length();
    if magnitude > limit {
        // Shear failure: the force at the strength; the bond fails for good, and the
        // residual strength applies from the next step (3DEC's rule: cohesion and tension
        // lost, friction to its residual value). Except a bond without cohesion held in
        // tension: its shear strength is zero, so any rounding of its shear force would
        // break it; it keeps its tension.
        LawOutcome {
            normal_force: fn_,
            shear_force: shear * (limit / magnitude),
            state: SubState::Sliding,
            bonded: bonded && cohesion == 0.0 && fn_ <= 0.0,
        }
    } else {
        LawOutcome {
            normal_force: fn_,
            shear_force: shear,
            state: SubState::Elastic,
            bonded,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One step of the joint law, without slack, its tangents computed afresh.
    fn law(m: &JointModel, area: f64, gap: f64, shear: DVec3, bonded: bool) -> LawOutcome {
        joint_law(m, area, gap, shear, bonded, 0.0, &mut Tangents::default())
    }

    fn model() -> JointModel {
        JointModel {
            kn: 100.0,
            ks: 50.0,
            friction: 45.0,
            cohesion: 2.0,
            tension: 3.0,
            ..JointModel::default()
        }
    }

    #[test]
    fn the_law_follows_mohr_coulomb_with_residual_strength() {
        let m = model();
        // Compression 100 * 2 * 0.01 = 2; strength c A + Fn tan φ = 4 + 2 = 6.
        let held = law(&m, 2.0, -0.01, DVec3::new(5.0, 0.0, 0.0), true);
        assert_eq!(held.state, SubState::Elastic);
        assert!((held.normal_force - 2.0).abs() < 1e-12);
        let slid = law(&m, 2.0, -0.01, DVec3::new(7.0, 0.0, 0.0), true);
        assert_eq!(slid.state, SubState::Sliding);
        assert!((slid.shear_force.x - 6.0).abs() < 1e-12);
        assert!(!slid.bonded, "a bond that slides loses its cohesion");
        // Unbonded: friction only.
        let residual = law(&m, 2.0, -0.01, DVec3::new(7.0, 0.0, 0.0), false);
        assert!((residual.shear_force.x - 2.0).abs() < 1e-12);
        // Tension 100 * 2 * 0.02 = 4 < T A = 6 holds; 0.04 -> 8 > 6 fails.
        let pulled = law(&m, 2.0, 0.02, DVec3::ZERO, true);
        assert!((pulled.normal_force + 4.0).abs() < 1e-12 && pulled.bonded);
        let broken = law(&m, 2.0, 0.04, DVec3::ZERO, true);
        assert_eq!((broken.state, broken.bonded), (SubState::Open, false));
        let apart = law(&m, 2.0, 0.02, DVec3::ZERO, false);
        assert_eq!(apart.state, SubState::Open);
        // A bond of tension only that slides in compression fails too (3DEC): it no longer
        // holds tension; held in tension (no shear strength) it keeps its bond.
        let tension_only = JointModel { cohesion: 0.0, ..m };
        let pulled = law(&tension_only, 2.0, 0.01, DVec3::X * 1e-9, true);
        assert_eq!((pulled.state, pulled.bonded), (SubState::Sliding, true));
        let slid = law(&tension_only, 2.0, -0.01, DVec3::new(3.0, 0.0, 0.0), true);
        assert_eq!((slid.state, slid.bonded), (SubState::Sliding, false));
    }

    /// The remembered tangents are those computed, bit for bit, whichever angles were asked
    /// before (two slots, replaced in turn).
    #[test]
    fn remembered_tangents_are_the_computed_ones() {
        let mut t = Tangents::default();
        for &a in &[
            0.0, 30.0, 30.0, 20.0, 30.0, 45.0, 20.0, -0.0, 89.9, 30.0, 0.0,
        ] {
            assert_eq!(
                t.of(a).to_bits(),
                f64::to_radians(a).tan().to_bits(),
                "{a}°"
            );
        }
    }

    /// After failure the residual friction and cohesion apply: tan φr = tan 20°, cr = 0.5.
    #[test]
    fn a_failed_sub_contact_has_the_residual_strength() {
        let m = JointModel {
            residual_friction: Some(20.0),
            residual_cohesion: 0.5,
            ..model()
        };
        // Compression 2: peak strength 2 × 2 + 2 tan 45° = 6; residual 0.5 × 2 + 2 tan 20°.
        let residual = 1.0 + 2.0 * 20f64.to_radians().tan();
        let intact = law(&m, 2.0, -0.01, DVec3::new(5.0, 0.0, 0.0), true);
        assert_eq!((intact.state, intact.bonded), (SubState::Elastic, true));
        let failed = law(&m, 2.0, -0.01, DVec3::new(5.0, 0.0, 0.0), false);
        assert_eq!(failed.state, SubState::Sliding);
        assert!((failed.shear_force.x - residual).abs() < 1e-12);
        // Without residual values: the friction angle, no cohesion.
        let plain = law(&model(), 2.0, -0.01, DVec3::new(5.0, 0.0, 0.0), false);
        assert!((plain.shear_force.x - 2.0).abs() < 1e-12);
    }

    /// A contact takes its faces' joint set; between two sets, the weaker; with no joint
    /// face, none (the default).
    #[test]
    fn a_contact_takes_the_set_of_its_faces_and_the_weaker_of_two() {
        let joint = |set| FaceOrigin::Joint { set, joint: 0 };
        let tagged = |b: ConvexBlock, set| {
            let n = b.n_faces();
            b.with_face_origins(vec![joint(set); n]).unwrap()
        };
        let a = tagged(ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap(), 1);
        let b = tagged(
            ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap(),
            2,
        );
        let plain = ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
        let mut table = JointTable::default();
        let weak = JointModel {
            friction: 20.0,
            ..JointModel::default()
        };
        table.set(2, weak).unwrap();
        let (f, e, v) = (Feature::Face(0), Feature::Edge(0), Feature::Vertex(0));
        // Set 2 is weaker than set 1 (which has the default 30°).
        assert_eq!(table.set_of_contact(&a, f, &b, f), Some(2));
        assert_eq!(table.set_of_contact(&b, f, &a, f), Some(2));
        table
            .set(
                1,
                JointModel {
                    friction: 10.0,
                    ..weak
                },
            )
            .unwrap();
        assert_eq!(table.set_of_contact(&a, f, &b, f), Some(1));
        // One joint face: its set; edges and vertices have none.
        assert_eq!(table.set_of_contact(&a, f, &plain, f), Some(1));
        assert_eq!(table.set_of_contact(&plain, f, &b, e), None);
        assert_eq!(table.set_of_contact(&a, e, &b, v), None);
        assert_eq!(table.of_set(Some(2)).friction, 20.0);
        assert_eq!(table.of_set(Some(7)), table.default_model());
    }

    #[test]
    fn bad_properties_are_named() {
        let bad = |f: fn(&mut JointModel)| {
            let mut m = model();
            f(&mut m);
            m.validated().unwrap_err().to_string()
        };
        assert!(bad(|m| m.kn = 0.0).contains("kn"));
        assert!(bad(|m| m.ks = -1.0).contains("ks"));
        assert!(bad(|m| m.kn = f64::NAN).contains("kn"));
        assert!(bad(|m| m.friction = 90.0).contains("friction"));
        assert!(bad(|m| m.friction = -1.0).contains("friction"));
        assert!(bad(|m| m.cohesion = -1.0).contains("cohesion"));
        assert!(bad(|m| m.tension = f64::NAN).contains("tension"));
        assert!(bad(|m| m.residual_friction = Some(90.0)).contains("residual_friction"));
        assert!(bad(|m| m.residual_cohesion = -1.0).contains("residual_cohesion"));
    }
}
