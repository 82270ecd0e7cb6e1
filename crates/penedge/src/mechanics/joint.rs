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

    /// The joint set of a contact from its features' face origins (docs/mechanics.md,
    /// "Properties per joint set"): the weakest of `contact_sets`, none when there is none.
    pub fn set_of_contact(
        &self,
        a: &ConvexBlock,
        fa: Feature,
        b: &ConvexBlock,
        fb: Feature,
    ) -> Option<u32> {
        self.weakest(contact_sets(a, fa, b, fb).as_slice())
    }

    /// The weakest of `sets` (the smallest `tan φ`, then the smallest cohesion; of equals,
    /// the first), none when `sets` is empty: a contact between two sets is only as strong as
    /// its weaker side. A contact keeps its features between queries, so it keeps their sets
    /// ([`contact_sets`]) and asks only this, with the properties of the step.
    pub(super) fn weakest(&self, sets: &[u32]) -> Option<u32> {
        let (&first, rest) = sets.split_first()?;
        if rest.is_empty() {
            return Some(first);
        }
        let key = |s: u32| {
            let m = self.of_set(Some(s));
            (m.tan_friction(), m.cohesion)
        };
        let (mut best, mut best_key) = (first, key(first));
        for &s in rest {
            let k = key(s);
            if k < best_key {
                (best, best_key) = (s, k);
            }
        }
        Some(best)
    }
}

/// The joint sets a contact chooses from ([`contact_sets`]), distinct, in the order found:
/// up to four inline (every contact but one at a vertex where faces of many sets meet), more
/// in a list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum SetChoice {
    /// The first `len` of `sets`.
    Few { len: u8, sets: [u32; 4] },
    /// More than four.
    Many(Box<[u32]>),
}

impl Default for SetChoice {
    fn default() -> Self {
        SetChoice::Few {
            len: 0,
            sets: [0; 4],
        }
    }
}

impl SetChoice {
    /// The sets.
    pub fn as_slice(&self) -> &[u32] {
        match self {
            SetChoice::Few { len, sets } => &sets[..*len as usize],
            SetChoice::Many(sets) => sets,
        }
    }

    /// Adds `set` unless it is there already.
    fn push(&mut self, set: u32) {
        if self.as_slice().contains(&set) {
            return;
        }
        match self {
            SetChoice::Few { len, sets } if (*len as usize) < sets.len() => {
                sets[*len as usize] = set;
                *len += 1;
            }
            _ => {
                let mut all = self.as_slice().to_vec();
                all.push(set);
                *self = SetChoice::Many(all.into_boxed_slice());
            }
        }
    }
}

/// The joint sets a contact between feature `fa` of `a` and feature `fb` of `b` chooses
/// from (its set is the weakest of them, [`JointTable::weakest`]; the default when there
/// is none), by the rule of docs/mechanics.md ("Properties per joint set"):
///
/// - **A face on either side** (face-face, edge-face, vertex-face): the contact lies in that
///   face, and takes the sets of its face features (A's first).
/// - **Edges and vertices only** (edge-edge, edge-vertex, vertex-vertex: the line or point
///   where faces of each block meet): the contact lies in a joint when a face at A's feature
///   and a face at B's are that joint's two sides: faces of the same joint plane (the same
///   `joint` of their origins, [`FaceOrigin::Joint`] or [`FaceOrigin::Bridge`]) with
///   opposite normals (their cosine below −1/2: a bridge's seam, whose faces have the
///   joint's origin but lie across its plane, is not a side of it). It takes the sets of
///   those joints: the wedge's lower edge, on the line where its two joint planes meet the
///   rock below them, lies in both. Otherwise, the sets of all the joint faces at the two
///   features: the surfaces that meet there, of which the contact is only as strong as the
///   weakest.
///
/// Faces of unknown or boundary origin have no set. A bridge face counts as a face of its
/// set (a point contact is never a bridge, `bridge.rs`).
pub(super) fn contact_sets(
    a: &ConvexBlock,
    fa: Feature,
    b: &ConvexBlock,
    fb: Feature,
) -> SetChoice {
    let mut sets = SetChoice::default();
    if matches!(fa, Feature::Face(_)) || matches!(fb, Feature::Face(_)) {
        for s in [face_set(a, fa), face_set(b, fb)].into_iter().flatten() {
            sets.push(s);
        }
        return sets;
    }
    joints_lying_in(a, fa, b, fb, |(set, _)| sets.push(set));
    if sets.as_slice().is_empty() {
        for (block, f) in [(a, fa), (b, fb)] {
            for_faces_at(block, f, |i| {
                if let Some(s) = origin(block, i).and_then(FaceOrigin::set) {
                    sets.push(s);
                }
            });
        }
    }
    sets
}

/// The origin of face `f` of `block` (none past its faces).
fn origin(block: &ConvexBlock, f: usize) -> Option<FaceOrigin> {
    block.face_origins().get(f).copied()
}

/// Calls `visit` with the joint (set, joint plane) of each pair of faces, one at feature
/// `fa` of `a` and one at `fb` of `b`, that are that joint's two sides: the same joint plane
/// with opposite normals (cosine below −1/2). The joints a contact of edges or vertices lies
/// in ([`contact_sets`], [`crosses_joints`]); a joint met by several pairs is visited for each.
fn joints_lying_in(
    a: &ConvexBlock,
    fa: Feature,
    b: &ConvexBlock,
    fb: Feature,
    mut visit: impl FnMut((u32, u32)),
) {
    for_faces_at(a, fa, |i| {
        let Some(joint) = origin(a, i).and_then(joint_of) else {
            return;
        };
        let normal = a.planes()[i].normal;
        for_faces_at(b, fb, |j| {
            if origin(b, j).and_then(joint_of) == Some(joint)
                && normal.dot(b.planes()[j].normal) < -0.5
            {
                visit(joint);
            }
        });
    });
}

/// Whether the contact between feature `fa` of `a` and feature `fb` of `b`, neither a face,
/// lies in two joints or more ([`contact_sets`]'s rule: at each feature a face of the joint,
/// the two on opposite sides of its plane): the line or point where joint planes cross,
/// the blocks around it meeting there. Each of those joints has its faces on both sides of
/// the crossing, so the blocks across one joint from each of the two carry it there; the
/// two blocks diagonally across meet on the line alone, of no area. Such a contact bears
/// only past an overlap of half the detection gap (docs/mechanics.md, "Where joints
/// cross"): bearing from the first overlap, its strip of `point_width` took, along the cone
/// rule's normal between the joints', a share of a wedge's load without the wedging of its
/// two faces (a roof wedge's factor of safety 0.91 for limit equilibrium's 1.14), and keyed
/// blocks sliding over a joint of their base.
pub(super) fn crosses_joints(a: &ConvexBlock, fa: Feature, b: &ConvexBlock, fb: Feature) -> bool {
    if matches!(fa, Feature::Face(_)) || matches!(fb, Feature::Face(_)) {
        return false;
    }
    let mut first: Option<(u32, u32)> = None;
    let mut crossing = false;
    joints_lying_in(a, fa, b, fb, |joint| match first {
        None => first = Some(joint),
        Some(other) => crossing |= other != joint,
    });
    crossing
}

/// The set and joint plane of a joint or bridge face's origin.
fn joint_of(origin: FaceOrigin) -> Option<(u32, u32)> {
    match origin {
        FaceOrigin::Joint { set, joint } | FaceOrigin::Bridge { set, joint } => Some((set, joint)),
        _ => None,
    }
}

/// Calls `visit` with each face of `block` at feature `f`: the face itself, an edge's two
/// faces, the faces around a vertex.
fn for_faces_at(block: &ConvexBlock, f: Feature, mut visit: impl FnMut(usize)) {
    match f {
        Feature::Face(i) => visit(i as usize),
        Feature::Edge(e) => {
            if let Some(edge) = block.edges().get(e as usize) {
                edge.faces.iter().for_each(|&i| visit(i as usize));
            }
        }
        Feature::Vertex(v) => match block.vertex_faces().get(v as usize) {
            Some(&mask) => crate::block::Bits(mask).for_each(visit),
            None => (0..block.n_faces())
                .filter(|&i| block.face(i).contains(&v))
                .for_each(visit),
        },
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
        // One joint face: its set (whatever the other side's edge or vertex); a face of
        // no set against an edge: none.
        assert_eq!(table.set_of_contact(&a, f, &plain, f), Some(1));
        assert_eq!(table.set_of_contact(&a, f, &b, e), Some(1));
        assert_eq!(table.set_of_contact(&plain, f, &b, e), None);
        assert_eq!(table.set_of_contact(&plain, e, &plain, v), None);
        assert_eq!(table.of_set(Some(2)).friction, 20.0);
        assert_eq!(table.of_set(Some(7)), table.default_model());
    }

    /// A block `{x : n · x <= d}` of the half-spaces `planes`, each face's origin that of
    /// its half-space.
    fn block_of(planes: &[([f64; 3], f64, FaceOrigin)]) -> ConvexBlock {
        let normals: Vec<[f64; 3]> = planes.iter().map(|p| p.0).collect();
        let offsets: Vec<f64> = planes.iter().map(|p| p.1).collect();
        let block = ConvexBlock::from_planes(&normals, &offsets).unwrap();
        let origins = block
            .planes()
            .iter()
            .map(|face| {
                let unit = |n: [f64; 3]| DVec3::from(n).normalize();
                planes
                    .iter()
                    .find(|p| unit(p.0).dot(face.normal) > 1.0 - 1e-9)
                    .unwrap()
                    .2
            })
            .collect();
        block.with_face_origins(origins).unwrap()
    }

    /// The feature of `block` that is the edge from `p` to `q` (either way round).
    fn edge(block: &ConvexBlock, p: [f64; 3], q: [f64; 3]) -> Feature {
        let at = |v: u32, x: [f64; 3]| block.vertices()[v as usize].distance(x.into()) < 1e-9;
        let k = block.edges().iter().position(|e| {
            let [u, w] = e.vertices;
            at(u, p) && at(w, q) || at(u, q) && at(w, p)
        });
        Feature::Edge(k.unwrap() as u32)
    }

    /// The feature of `block` that is the vertex at `p`.
    fn vertex(block: &ConvexBlock, p: [f64; 3]) -> Feature {
        let k = block
            .vertices()
            .iter()
            .position(|v| v.distance(p.into()) < 1e-9);
        Feature::Vertex(k.unwrap() as u32)
    }

    /// Point contacts (edges and vertices on both sides) take the joint they lie in: a
    /// wedge on two joint planes A (`z = x`) and B (`z = -x`), whose line of intersection is
    /// the y axis, touches the block below both planes along that line only (an edge-edge
    /// contact, as in Hoek & Bray's wedge). Both of the wedge's faces there and both of the
    /// lower block's are the two sides of A and of B: the contact lies in both joints and
    /// takes the weaker. A lower block whose second face is another joint C lies in A only
    /// and takes A, even when C is weaker; with no shared joint plane, the weakest of the
    /// joints at the two features. Before 2026-11-29 every such contact took the default.
    #[test]
    fn a_point_contact_takes_the_joint_its_features_lie_in() {
        let joint = |set, joint| FaceOrigin::Joint { set, joint };
        let side = FaceOrigin::Boundary { part: 0, face: 0 };
        let (a, b, c, d) = (joint(0, 0), joint(1, 1), joint(2, 2), joint(3, 3));
        // The y-range [0, 1] and a top or a bottom at |z| = 1, of no joint.
        let slab = |top: [f64; 3]| {
            [
                ([0.0, -1.0, 0.0], 0.0, side),
                ([0.0, 1.0, 0.0], 1.0, side),
                (top, 1.0, side),
            ]
        };
        // Above A and B: z >= x, z >= -x.
        let mut planes = slab([0.0, 0.0, 1.0]).to_vec();
        planes.extend([([1.0, 0.0, -1.0], 0.0, a), ([-1.0, 0.0, -1.0], 0.0, b)]);
        let wedge = block_of(&planes);
        // Below A and B: z <= x, z <= -x.
        let mut planes = slab([0.0, 0.0, -1.0]).to_vec();
        planes.extend([([-1.0, 0.0, 1.0], 0.0, a), ([1.0, 0.0, 1.0], 0.0, b)]);
        let below = block_of(&planes);
        // Below A and below C (z <= -3x): it meets the wedge along the same line.
        let mut planes = slab([0.0, 0.0, -1.0]).to_vec();
        planes.extend([([-1.0, 0.0, 1.0], 0.0, a), ([3.0, 0.0, 1.0], 0.0, c)]);
        let below_c = block_of(&planes);
        // The same block with its face on A's plane from another joint, D: no shared joint.
        planes[3].2 = d;
        let unshared = block_of(&planes);

        let (o, y) = ([0.0; 3], [0.0, 1.0, 0.0]);
        let line = |block| edge(block, o, y);
        let model = |friction| JointModel {
            friction,
            ..JointModel::default()
        };
        let mut table = JointTable::default();
        table.set_default(model(45.0)).unwrap();
        for (set, friction) in [(0, 30.0), (1, 20.0), (2, 10.0), (3, 25.0)] {
            table.set(set, model(friction)).unwrap();
        }
        let of = |table: &JointTable, p, fp, q, fq| {
            (
                table.set_of_contact(p, fp, q, fq),
                table.set_of_contact(q, fq, p, fp),
            )
        };
        // The wedge's lower edge on the lower block's upper edge: in A and B, B weaker.
        assert_eq!(
            of(&table, &wedge, line(&wedge), &below, line(&below)),
            (Some(1), Some(1))
        );
        // The wedge's apex against the lower block's edge or vertex at the origin.
        assert_eq!(
            of(&table, &wedge, vertex(&wedge, o), &below, line(&below)),
            (Some(1), Some(1))
        );
        assert_eq!(
            of(&table, &wedge, vertex(&wedge, o), &below, vertex(&below, o)),
            (Some(1), Some(1))
        );
        // In A only: A (30°), though B (20°) and C (10°) are at the features too.
        assert_eq!(
            of(&table, &wedge, line(&wedge), &below_c, line(&below_c)),
            (Some(0), Some(0))
        );
        // No shared joint plane: the weakest of A, B, C and D at the two edges, C.
        assert_eq!(
            of(&table, &wedge, line(&wedge), &unshared, line(&unshared)),
            (Some(2), Some(2))
        );
        // The weaker of the two joints as the properties change: A once it is weaker than B.
        table.set(0, model(15.0)).unwrap();
        assert_eq!(
            of(&table, &wedge, line(&wedge), &below, line(&below)),
            (Some(0), Some(0))
        );
        // A bridge face counts as a face of its set and joint (its plane is the joint's).
        let mut planes = slab([0.0, 0.0, -1.0]).to_vec();
        let bridge = FaceOrigin::Bridge { set: 0, joint: 0 };
        planes.extend([([-1.0, 0.0, 1.0], 0.0, bridge), ([3.0, 0.0, 1.0], 0.0, c)]);
        let bridged = block_of(&planes);
        assert_eq!(
            of(&table, &wedge, line(&wedge), &bridged, line(&bridged)),
            (Some(0), Some(0))
        );
        // Two faces of the same joint facing the same way (two blocks on one side of A) are
        // not its two sides: the wedge against itself has no shared joint, the weakest of
        // its own, A.
        assert_eq!(
            of(&table, &wedge, line(&wedge), &wedge, line(&wedge)),
            (Some(0), Some(0))
        );
        // Blocks of no joint face: none (the default).
        let plain = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        assert_eq!(
            of(&table, &plain, Feature::Edge(0), &plain, Feature::Vertex(0)),
            (None, None)
        );
        // A face on either side: as before, the face's set (B's face against C's edge: B).
        let b_face = |block: &ConvexBlock| {
            let k = block.face_origins().iter().position(|&o| o == b).unwrap();
            Feature::Face(k as u32)
        };
        assert_eq!(
            of(&table, &wedge, b_face(&wedge), &below_c, line(&below_c)),
            (Some(1), Some(1))
        );
        // Where joints cross (docs/mechanics.md, "Where joints cross"): the contacts lying
        // in A and B, of edges or vertices, bear only past half the gap; those lying in one
        // joint or none, or with a face on either side, from the first overlap.
        let crossing = |p, fp, q, fq| (crosses_joints(p, fp, q, fq), crosses_joints(q, fq, p, fp));
        for (p, fp, q, fq, expected) in [
            (&wedge, line(&wedge), &below, line(&below), true),
            (&wedge, vertex(&wedge, o), &below, line(&below), true),
            (&wedge, vertex(&wedge, o), &below, vertex(&below, o), true),
            (&wedge, line(&wedge), &below_c, line(&below_c), false),
            (&wedge, line(&wedge), &unshared, line(&unshared), false),
            (&wedge, line(&wedge), &bridged, line(&bridged), false),
            (&wedge, line(&wedge), &wedge, line(&wedge), false),
            (&wedge, b_face(&wedge), &below, line(&below), false),
            (&plain, Feature::Edge(0), &plain, Feature::Vertex(0), false),
        ] {
            assert_eq!(
                crossing(p, fp, q, fq),
                (expected, expected),
                "{fp:?} {fq:?}"
            );
        }
    }

    /// Many sets at one vertex: the list grows past its four inline entries.
    #[test]
    fn the_choice_keeps_every_set() {
        let mut sets = SetChoice::default();
        for s in [5, 3, 5, 9, 1, 3, 7, 2] {
            sets.push(s);
        }
        assert_eq!(sets.as_slice(), &[5, 3, 9, 1, 7, 2]);
        let mut table = JointTable::default();
        table
            .set(
                7,
                JointModel {
                    friction: 10.0,
                    ..JointModel::default()
                },
            )
            .unwrap();
        assert_eq!(table.weakest(sets.as_slice()), Some(7));
        assert_eq!(table.weakest(&[]), None);
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
