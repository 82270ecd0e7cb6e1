//! Excavation of a running simulation: bodies removed, and the forces they exerted on the
//! rock that stays relaxed to zero over a number of steps (3DEC's gradual release), rather
//! than at once (docs/mechanics.md, "Excavation").

use super::{Fixity, MechanicsError, Simulation};
use crate::geometry::DVec3;

/// The excavation state of a simulation: which bodies are removed, and the loads being
/// relaxed.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Excavation {
    /// Per body, whether it was removed (empty: none was).
    pub removed: Vec<bool>,
    /// The relaxations under way, oldest first.
    pub relaxations: Vec<Relaxation>,
}

/// The forces removed bodies exerted on the bodies that stay, at the moment of removal,
/// applied again at each step and reduced linearly to zero over `steps` steps.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Relaxation {
    /// Over how many steps the loads go to zero.
    pub steps: u64,
    /// Steps taken since the excavation.
    pub done: u64,
    /// The bodies loaded, increasing.
    pub bodies: Vec<u32>,
    /// Per loaded body, the force (world frame) and its moment about the body's centroid.
    pub forces: Vec<DVec3>,
    pub moments: Vec<DVec3>,
}

impl Relaxation {
    /// The fraction of the loads the next step applies: `1 - done / steps` (the first step
    /// after the excavation applies the whole load, the `steps`-th `1 / steps` of it, the
    /// ones after none).
    pub fn factor(&self) -> f64 {
        (1.0 - self.done as f64 / self.steps as f64).max(0.0)
    }
}

/// What [`Simulation::excavate`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct ExcavationReport {
    /// The bodies removed.
    pub removed: Vec<usize>,
    /// The bodies that stay and that the removed ones pushed on (their contacts at the last
    /// step) or pulled on (bolt elements anchored in them), increasing; with the force on
    /// each (world frame), the load that relaxes. Only bodies with a load: a force or a
    /// moment not zero (a contact without force, open or before any step, or a slack bolt
    /// element, loads nothing).
    pub loaded: Vec<(usize, DVec3)>,
}

impl Simulation {
    /// Removes the bodies `ids` (the rock excavated): from the next step they take no part
    /// (no contacts, no bolts, no motion, not in the unbalanced-force ratio nor the critical
    /// time step; their ids stay, fixed where they were). Every bolt element with an anchor
    /// in a removed body goes (its bolt's elements between bodies that stay go on). The
    /// forces they exerted on the bodies that stay, through the contacts and those bolt
    /// elements of the last step, are applied to those bodies again
    /// at each step, reduced linearly to zero over `relax_steps` steps: the `j`-th step
    /// after the excavation applies `1 - (j - 1) / relax_steps` of them (the moment about
    /// each body's centroid kept as it was, in the world frame); `relax_steps = 0` releases
    /// them at once. Only loads not zero are relaxed and reported: before any step no contact
    /// and no bolt has a force yet, so an excavation then relaxes nothing and its report's
    /// `loaded` is empty (the rock goes as if the model had been built without it). With
    /// mass scaling on, the factors are computed again from the free bodies that stay
    /// ([`Simulation::set_mass_scaling`]).
    pub fn excavate(
        &mut self,
        ids: &[usize],
        relax_steps: u64,
    ) -> Result<ExcavationReport, MechanicsError> {
        let n = self.bodies.len();
        if self.excavation.removed.is_empty() {
            self.excavation.removed = vec![false; n];
        }
        let mut gone = vec![false; n];
        for &i in ids {
            self.bodies.check(i)?;
            if self.excavation.removed[i] {
                return Err(MechanicsError::Removed(i));
            }
            gone[i] = true;
        }
        // The forces of the removed bodies on the others, contact after contact.
        let mut force = vec![DVec3::ZERO; n];
        let mut moment = vec![DVec3::ZERO; n];
        for (k, c) in self.contacts.list.iter().enumerate() {
            let [a, b] = [c.bodies[0] as usize, c.bodies[1] as usize];
            let (on, sign) = match (gone[a], gone[b]) {
                (true, false) => (b, 1.0), // the force on B
                (false, true) => (a, -1.0),
                _ => continue,
            };
            let centre = self.bodies.pose[on].translation;
            for s in self.contacts.subs_of(k) {
                let f = s.force(c.normal) * sign;
                force[on] += f;
                moment[on] += (s.point - centre).cross(f);
            }
        }
        // The rock bolts anchored in them stop acting: their elements with an anchor in a
        // removed body go, and the forces those exerted on the bodies that stay relax with
        // the contacts' (docs/mechanics.md, "Excavation").
        let mut now_removed = self.removed();
        for (r, &g) in now_removed.iter_mut().zip(&gone) {
            *r |= g;
        }
        for (on, f, m) in self.bolts.remove_bodies(&now_removed, &self.bodies) {
            force[on] += f;
            moment[on] += m;
        }
        // A body counts as loaded only if the load is not zero: contacts without force
        // (open, or none computed yet: before the first step) and slack bolt elements
        // exert none, and there is nothing to relax or report (a body nothing pushed on
        // keeps its zero sums).
        let bodies: Vec<u32> = (0..n)
            .filter(|&i| force[i] != DVec3::ZERO || moment[i] != DVec3::ZERO)
            .map(|i| i as u32)
            .collect();
        let report = ExcavationReport {
            removed: (0..n).filter(|&i| gone[i]).collect(),
            loaded: bodies
                .iter()
                .map(|&i| (i as usize, force[i as usize]))
                .collect(),
        };
        if relax_steps > 0 && !bodies.is_empty() {
            self.excavation.relaxations.push(Relaxation {
                steps: relax_steps,
                done: 0,
                forces: bodies.iter().map(|&i| force[i as usize]).collect(),
                moments: bodies.iter().map(|&i| moment[i as usize]).collect(),
                bodies,
            });
        }
        for i in report.removed.iter().copied() {
            self.excavation.removed[i] = true;
            self.bodies.set_fixity(i, Fixity::Fixed)?;
            self.bodies.set_applied(i, DVec3::ZERO)?;
            self.bodies.velocity[i] = DVec3::ZERO;
            self.bodies.momentum[i] = DVec3::ZERO;
            self.applied_moments.remove(&(i as u32));
        }
        // Their contacts go now (the pairs are rebuilt without them at the next step).
        let removed = &self.excavation.removed;
        let old = std::mem::take(&mut self.contacts);
        for (k, c) in old.list.iter().enumerate() {
            if !(removed[c.bodies[0] as usize] || removed[c.bodies[1] as usize]) {
                let mut kept = c.clone();
                kept.first = self.contacts.subs.len() as u32;
                self.contacts.subs.extend_from_slice(old.subs_of(k));
                if !old.prestresses.is_empty() {
                    let range = c.first as usize..(c.first + c.count) as usize;
                    self.contacts
                        .prestresses
                        .extend_from_slice(&old.prestresses[range]);
                }
                self.contacts.list.push(kept);
            }
        }
        self.built_at = None;
        if self.mass_scaling {
            // The free bodies changed: the median and the factors follow.
            self.rescale();
        }
        Ok(report)
    }

    /// Per body, whether it was excavated ([`Simulation::excavate`]).
    pub fn removed(&self) -> Vec<bool> {
        let mut out = self.excavation.removed.clone();
        out.resize(self.bodies.len(), false);
        out
    }

    /// Whether body `i` was excavated.
    pub(super) fn is_removed(&self, i: usize) -> bool {
        self.excavation.removed.get(i).copied().unwrap_or(false)
    }

    /// Adds this step's share of the relaxing loads to the bodies' contact forces and
    /// moments, and counts the step (a finished relaxation is dropped).
    pub(super) fn apply_relaxation(&mut self) {
        for r in &mut self.excavation.relaxations {
            let factor = r.factor();
            for (k, &b) in r.bodies.iter().enumerate() {
                self.forces[b as usize] += r.forces[k] * factor;
                self.moments[b as usize] += r.moments[k] * factor;
            }
            r.done += 1;
        }
        self.excavation.relaxations.retain(|r| r.done < r.steps);
    }
}
