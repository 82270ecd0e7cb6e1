//! Rock bridges: the properties of contacts over bridge faces (the uncut part of a finite
//! joint's plane, docs/generation.md "Rock bridges"), and the choice of a contact's model
//! between the joint table and the bridge table (docs/mechanics.md, "Rock bridges").
//!
//! A bridge is a contact like any other: bonded where it touches at the start of the run,
//! failing by the joint law (tension cut-off, Mohr-Coulomb with cohesion) and taking the
//! residual values after failure (cohesion and tension zero). Only its properties differ:
//! those of the intact rock.

use super::joint::{contact_sets, JointModel, JointTable, SetChoice};
use super::MechanicsError;
use crate::block::ConvexBlock;
use crate::classify::Feature;
use std::collections::BTreeMap;

/// The strength of a bridge of a set without properties of its own, when no default was set:
/// a strong rock (friction 45°, cohesion 10 MPa, tensile strength 5 MPa, in SI units), with
/// the stiffness of the set's joint. Set the intact rock's own values
/// ([`Simulation::set_bridge`](super::Simulation::set_bridge)).
pub const BRIDGE_STRENGTH: (f64, f64, f64) = (45.0, 10e6, 5e6);

/// The bridge properties of a simulation: per joint set, and a default.
#[derive(Clone, Debug, Default)]
pub struct BridgeTable {
    default: Option<JointModel>,
    sets: BTreeMap<u32, JointModel>,
}

impl BridgeTable {
    /// The default bridge model, if one was set.
    pub fn default_model(&self) -> Option<&JointModel> {
        self.default.as_ref()
    }

    /// The sets with their own bridge model, in increasing set order.
    pub fn sets(&self) -> impl Iterator<Item = (u32, &JointModel)> + '_ {
        self.sets.iter().map(|(&s, m)| (s, m))
    }

    /// Sets the default bridge model (bridges of sets without their own).
    pub fn set_default(&mut self, model: JointModel) -> Result<(), MechanicsError> {
        self.default = Some(model.validated()?);
        Ok(())
    }

    /// Sets the bridge model of joint set `set` (the `set` of `FaceOrigin::Bridge`).
    pub fn set(&mut self, set: u32, model: JointModel) -> Result<(), MechanicsError> {
        self.sets.insert(set, model.validated()?);
        Ok(())
    }

    /// The bridge model of set `set`: its own, else the default set, else the set's joint
    /// stiffness with [`BRIDGE_STRENGTH`].
    pub fn of_set(&self, set: u32, joints: &JointTable) -> JointModel {
        if let Some(m) = self.sets.get(&set).or(self.default.as_ref()) {
            return *m;
        }
        let (friction, cohesion, tension) = BRIDGE_STRENGTH;
        JointModel {
            friction,
            cohesion,
            tension,
            ..*joints.of_set(Some(set))
        }
    }

    /// The largest stiffness of the models set (for the critical time step; the built-in
    /// default takes the joints' stiffness, already counted).
    pub fn max_stiffness(&self) -> f64 {
        self.default
            .iter()
            .chain(self.sets.values())
            .fold(0.0f64, |k, m| k.max(m.kn).max(m.ks))
    }
}

/// The model of a contact, and its set and whether it is a bridge. A face-face contact with
/// a bridge face on either side is a bridge (generation splits the faces on one side of the
/// plane only, so the overlap of the two faces is then wholly bridge): it takes the bridge
/// model of the set (of two sets, the weaker, as for joints). Any other contact takes its
/// joint model ([`JointTable::set_of_contact`], the same rule of sets), a bridge face
/// counting as a face of its set: an edge or a vertex against a bridge face, or two edges
/// along a bridge's plane (where pieces of a cut block meet along a line), holds no area of
/// intact rock, and once broken a bridge face is a fracture of its set.
#[cfg(test)]
pub(super) fn contact_model(
    joints: &JointTable,
    bridges: &BridgeTable,
    a: &ConvexBlock,
    fa: Feature,
    b: &ConvexBlock,
    fb: Feature,
) -> (Option<u32>, bool, JointModel) {
    ContactFaces::of(a, fa, b, fb).model(joints, bridges)
}

/// What a contact's model takes from its two features (the joint sets it chooses from,
/// [`contact_sets`], and whether the contact is face-face with a bridge face on either
/// side): the features are kept between two queries of a pair, so a contact keeps this
/// rather than reading its blocks' face origins at every step.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ContactFaces {
    sets: SetChoice,
    bridge_faces: bool,
}

impl ContactFaces {
    /// The faces of the contact between feature `fa` of `a` and feature `fb` of `b`.
    pub fn of(a: &ConvexBlock, fa: Feature, b: &ConvexBlock, fb: Feature) -> ContactFaces {
        let bridge_face = |block: &ConvexBlock, f: Feature| match f {
            Feature::Face(i) => block
                .face_origins()
                .get(i as usize)
                .is_some_and(|o| o.is_bridge()),
            _ => false,
        };
        let faces = matches!((fa, fb), (Feature::Face(_), Feature::Face(_)));
        ContactFaces {
            sets: contact_sets(a, fa, b, fb),
            bridge_faces: faces && (bridge_face(a, fa) || bridge_face(b, fb)),
        }
    }

    /// The contact's set, whether it is a bridge, and its model ([`contact_model`]).
    pub fn model(
        &self,
        joints: &JointTable,
        bridges: &BridgeTable,
    ) -> (Option<u32>, bool, JointModel) {
        match joints.weakest(self.sets.as_slice()) {
            Some(s) if self.bridge_faces => (Some(s), true, bridges.of_set(s, joints)),
            set => (set, false, *joints.of_set(set)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::FaceOrigin;

    fn cube(origin: FaceOrigin) -> ConvexBlock {
        let b = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        let n = b.n_faces();
        b.with_face_origins(vec![origin; n]).unwrap()
    }

    #[test]
    fn a_bridge_face_takes_the_bridge_model_else_the_joint_model() {
        let mut joints = JointTable::default();
        let weak = JointModel {
            friction: 20.0,
            ..JointModel::default()
        };
        joints.set(1, weak).unwrap();
        let mut bridges = BridgeTable::default();
        let bridge = |set| FaceOrigin::Bridge { set, joint: 0 };
        let (a, b) = (cube(bridge(1)), cube(bridge(1)));
        let f = Feature::Face(0);
        // Built-in: the joint's stiffness, the intact strength.
        let (set, is_bridge, m) = contact_model(&joints, &bridges, &a, f, &b, f);
        assert_eq!((set, is_bridge), (Some(1), true));
        assert_eq!((m.kn, m.friction, m.cohesion), (weak.kn, 45.0, 10e6));
        let mut intact = JointModel::default();
        (intact.kn, intact.ks, intact.friction) = (5e10, 5e10, 50.0);
        (intact.cohesion, intact.tension) = (2e6, 1e6);
        bridges.set(1, intact).unwrap();
        assert_eq!(contact_model(&joints, &bridges, &a, f, &b, f).2, intact);
        assert_eq!(bridges.max_stiffness(), 5e10);
        // A joint face keeps the joint model; so do two edges between bridge faces (a
        // point contact, of no area of intact rock: the joint model of their set).
        let j = cube(FaceOrigin::Joint { set: 1, joint: 0 });
        assert_eq!(
            contact_model(&joints, &bridges, &j, f, &j, f),
            (Some(1), false, weak)
        );
        let e = Feature::Edge(0);
        assert_eq!(
            contact_model(&joints, &bridges, &a, e, &b, e),
            (Some(1), false, weak)
        );
        let plain = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
        assert_eq!(
            contact_model(&joints, &bridges, &plain, e, &plain, e),
            (None, false, JointModel::default())
        );
        // A bridge face against a joint face: the bridge; against an edge: the joint model
        // of the set.
        assert!(contact_model(&joints, &bridges, &j, f, &b, f).1);
        assert_eq!(
            contact_model(&joints, &bridges, &a, e, &b, f),
            (Some(1), false, weak)
        );
        intact.kn = 0.0;
        assert!(bridges.set(2, intact).is_err());
    }
}
