//! Rock bolts: axial springs between the bodies a bolt crosses (docs/mechanics.md, "Rock
//! bolts").
//!
//! A bolt is a segment (collar, direction, length) installed once: the bodies it crosses are
//! found from the segment at the bodies' poses of that moment, in order along it, and the
//! bolt becomes a chain of elements, one between each two consecutive bodies. Each element
//! joins two anchor points fixed in its bodies' frames: the point where the bolt enters the
//! first body (the face plate at the collar), the point where it leaves the last one (its
//! far end, normally inside the rock), and the middle of its run through every body in
//! between. So a bolt across one joint is one spring from its plate to its anchor (an
//! end-anchored bolt); across several joints, a chain whose total stiffness is the bolt's.
//!
//! The axial force is `k (e - e_p)` (tension positive) with `e` the element's elongation
//! and `e_p` its plastic elongation, up to the capacity in tension and in compression:
//! elastic, perfectly plastic, as the axial law of 3DEC's cable elements (yield strength,
//! no hardening). With a rupture strain, an element whose axial strain `e / l` exceeds it
//! breaks for good (force zero), as the tensile rupture strain of 3DEC's hybrid bolts.
//!
//! Optionally a bolt resists shear where it crosses a joint (a dowel, as the shear springs
//! of 3DEC's hybrid bolts and local reinforcement): at the crossing between each two
//! consecutive bodies, a spring on the two bodies' relative displacement across the bolt
//! (perpendicular to its current axis), elastic, perfectly plastic at the shear capacity.
//!
//! The state is plain data (`pub(crate)` fields) so that a saved run can store it.

use super::bodies::Bodies;
use super::MechanicsError;
use crate::block::ConvexBlock;
use crate::geometry::DVec3;
use std::collections::BTreeMap;

/// A rock bolt to install: the segment from `collar` along `direction` for `length`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bolt {
    /// The collar (the face plate).
    pub collar: DVec3,
    /// The direction into the rock (any length > 0).
    pub direction: DVec3,
    /// Length.
    pub length: f64,
    /// Axial stiffness of the whole bolt, `EA / length` (force per length).
    pub stiffness: f64,
    /// Axial capacity: the force at which it yields (tension and compression).
    pub capacity: f64,
    /// The axial strain at which an element breaks; `None`: it never breaks (perfectly
    /// plastic).
    pub rupture_strain: Option<f64>,
    /// Shear (dowel) resistance at each joint it crosses; `None`: axial only.
    pub dowel: Option<Dowel>,
}

/// The shear resistance of a bolt where it crosses a joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dowel {
    /// Shear stiffness (force per relative displacement across the bolt).
    pub stiffness: f64,
    /// Shear capacity: the shear force at which it yields.
    pub capacity: f64,
}

/// What a bolt element does now.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BoltState {
    /// Below its capacity.
    #[default]
    Elastic,
    /// At its capacity, elongating plastically.
    Yielding,
    /// Broken: no force any more.
    Broken,
}

impl BoltState {
    /// 0 elastic, 1 yielding, 2 broken.
    pub fn code(self) -> u8 {
        match self {
            BoltState::Elastic => 0,
            BoltState::Yielding => 1,
            BoltState::Broken => 2,
        }
    }
}

/// One element of a bolt: an axial spring between anchors fixed in two bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoltElement {
    /// The bolt it belongs to.
    pub(crate) bolt: u32,
    /// Its two bodies, in order along the bolt.
    pub(crate) bodies: [u32; 2],
    /// The anchors in their bodies' frames.
    pub(crate) anchors: [DVec3; 2],
    /// Length at installation (the distance between the anchors).
    pub(crate) rest: f64,
    /// Axial stiffness `EA / rest`.
    pub(crate) stiffness: f64,
    pub(crate) capacity: f64,
    /// Rupture strain (infinite: none).
    pub(crate) rupture: f64,
    /// Plastic elongation.
    pub(crate) plastic: f64,
    /// Elongation and axial force (tension > 0) at the last step.
    pub(crate) elongation: f64,
    pub(crate) force: f64,
    pub(crate) state: BoltState,
    /// The dowel at the joint crossing (stiffness 0: none): the crossing in both bodies'
    /// frames, its plastic slip and its shear force on the second body (world frame).
    pub(crate) dowel: Dowel,
    pub(crate) crossing: [DVec3; 2],
    pub(crate) slip: DVec3,
    pub(crate) shear: DVec3,
}

impl BoltElement {
    /// The bolt it belongs to.
    pub fn bolt(&self) -> usize {
        self.bolt as usize
    }

    /// Its two bodies, in order along the bolt.
    pub fn bodies(&self) -> [usize; 2] {
        [self.bodies[0] as usize, self.bodies[1] as usize]
    }

    /// Length at installation.
    pub fn rest_length(&self) -> f64 {
        self.rest
    }

    /// Elongation at the last step (negative: shortened).
    pub fn elongation(&self) -> f64 {
        self.elongation
    }

    /// Axial force at the last step (tension > 0).
    pub fn force(&self) -> f64 {
        self.force
    }

    /// Its state at the last step.
    pub fn state(&self) -> BoltState {
        self.state
    }

    /// The dowel's shear force on the second body at the last step (zero without a dowel).
    pub fn shear_force(&self) -> DVec3 {
        self.shear
    }

    /// The shear force of the dowel for the relative displacement `u` of the second body's
    /// crossing point from the first's, across the unit `axis`; updates the plastic slip.
    fn shear_load(&mut self, u: DVec3, axis: DVec3) -> DVec3 {
        let k = self.dowel.stiffness;
        if k == 0.0 || self.state == BoltState::Broken {
            self.shear = DVec3::ZERO;
            return self.shear;
        }
        let across = |v: DVec3| v - axis * v.dot(axis);
        let u = across(u);
        let mut elastic = u - across(self.slip);
        let trial = k * elastic.length();
        if trial > self.dowel.capacity {
            elastic *= self.dowel.capacity / trial;
        }
        self.slip = u - elastic;
        self.shear = -elastic * k;
        self.shear
    }

    /// The anchors in the world at the bodies' current poses.
    pub fn ends(&self, bodies: &Bodies) -> [DVec3; 2] {
        let poses = bodies.poses();
        [
            poses[self.bodies[0] as usize].apply(self.anchors[0]),
            poses[self.bodies[1] as usize].apply(self.anchors[1]),
        ]
    }

    /// The axial force for elongation `e`; updates the plastic elongation and the state.
    fn load(&mut self, e: f64) -> f64 {
        self.elongation = e;
        if self.state == BoltState::Broken {
            return 0.0;
        }
        if e > self.rupture * self.rest {
            self.state = BoltState::Broken;
            self.force = 0.0;
            return 0.0;
        }
        let trial = self.stiffness * (e - self.plastic);
        self.force = if trial.abs() > self.capacity {
            self.plastic = e - trial.signum() * self.capacity / self.stiffness;
            self.state = BoltState::Yielding;
            trial.signum() * self.capacity
        } else {
            self.state = BoltState::Elastic;
            trial
        };
        self.force
    }
}

/// The bolts of a simulation: what was installed and the state of every element.
#[derive(Clone, Debug, Default)]
pub struct Bolts {
    pub(crate) specs: Vec<Bolt>,
    /// Elements, bolt after bolt, in order along each bolt.
    pub(crate) elements: Vec<BoltElement>,
    /// Per body with a bolt, `[Σ k, Σ k |r|²]` of its elements (critical time step).
    pub(crate) stiffness: BTreeMap<u32, [f64; 2]>,
}

impl Bolts {
    /// Number of bolts.
    pub fn len(&self) -> usize {
        self.specs.len()
    }

    /// Whether there is no bolt.
    pub fn is_empty(&self) -> bool {
        self.specs.is_empty()
    }

    /// The bolts as installed.
    pub fn specs(&self) -> &[Bolt] {
        &self.specs
    }

    /// The elements, bolt after bolt, in order along each bolt.
    pub fn elements(&self) -> &[BoltElement] {
        &self.elements
    }

    /// Installs `bolt` across the bodies its segment crosses now (`placed`: the parts at
    /// their poses, `part_body` their bodies; `removed`: per body whether it was excavated,
    /// or empty); its id. Excavated bodies before the first body that stays are the opening
    /// the collar is in (skipped, as air); one further along is an error naming it.
    pub(super) fn install(
        &mut self,
        bolt: Bolt,
        bodies: &Bodies,
        placed: &[ConvexBlock],
        part_body: &[u32],
        removed: &[bool],
    ) -> Result<usize, MechanicsError> {
        check(&bolt)?;
        let d = bolt.direction.normalize();
        let end = bolt.collar + d * bolt.length;
        let mut runs = crossed(placed, part_body, bolt.collar, end);
        let text = |p: DVec3| format!("({}, {}, {})", p.x, p.y, p.z);
        let is_removed = |b: u32| removed.get(b as usize).copied().unwrap_or(false);
        // The excavated rock at the collar is the opening: the bolt starts at the rock face.
        let opening: Vec<u32> = runs
            .iter()
            .take_while(|r| is_removed(r.0))
            .map(|r| r.0)
            .collect();
        runs.drain(..opening.len());
        if let Some(&(b, _, _)) = runs.iter().find(|r| is_removed(r.0)) {
            return Err(MechanicsError::Bolt(format!(
                "the bolt from {} to {} crosses or ends in body {b}, which was excavated: a \
                 bolt cannot tie or be anchored in removed rock (install it before the \
                 excavation, or shorten it to end in rock that stays)",
                text(bolt.collar),
                text(end)
            )));
        }
        let bodies_crossed: Vec<u32> = runs.iter().map(|r| r.0).collect();
        // Named in the errors below: the excavated bodies the collar is in.
        let skipped = match opening.as_slice() {
            [] => String::new(),
            _ => {
                let ids: Vec<String> = opening.iter().map(u32::to_string).collect();
                format!(
                    " (excavated body {}, at its collar, is the opening, not rock)",
                    ids.join(", ")
                )
            }
        };
        match bodies_crossed.as_slice() {
            [] => {
                return Err(MechanicsError::Bolt(format!(
                    "the bolt from {} to {} is outside the rock (it meets no block that \
                     stays){skipped}",
                    text(bolt.collar),
                    text(end)
                )))
            }
            [b] => {
                return Err(MechanicsError::Bolt(format!(
                    "the bolt from {} to {} lies in one body (body {b}): it crosses no \
                     joint and ties nothing{skipped}",
                    text(bolt.collar),
                    text(end)
                )))
            }
            _ => {}
        }
        // One node per run: the entry into the first body, the exit from the last, the
        // middle of the run through every body in between.
        let last = runs.len() - 1;
        let nodes: Vec<(u32, f64)> = runs
            .iter()
            .enumerate()
            .map(|(k, &(b, t_in, t_out))| {
                let t = match k {
                    0 => t_in,
                    k if k == last => t_out,
                    _ => 0.5 * (t_in + t_out),
                };
                (b, t)
            })
            .collect();
        // The joint crossing between two consecutive runs: the middle of the gap between
        // them (none, in rock).
        let crossing_t: Vec<f64> = runs.windows(2).map(|w| 0.5 * (w[0].2 + w[1].1)).collect();
        let id = self.specs.len() as u32;
        let ea = bolt.stiffness * bolt.length;
        let dowel = bolt.dowel.unwrap_or(Dowel {
            stiffness: 0.0,
            capacity: 0.0,
        });
        let poses = bodies.poses();
        let local = |b: u32, t: f64| {
            let pose = poses[b as usize];
            pose.rotation.conjugate() * (bolt.collar + d * t - pose.translation)
        };
        let mut new = Vec::with_capacity(last);
        for (pair, &tc) in nodes.windows(2).zip(&crossing_t) {
            let [(a, ta), (b, tb)] = [pair[0], pair[1]];
            let rest = tb - ta;
            if a == b || rest <= 1e-12 * bolt.length {
                continue; // two parts of one body, or no length between them
            }
            new.push(BoltElement {
                bolt: id,
                bodies: [a, b],
                anchors: [local(a, ta), local(b, tb)],
                rest,
                stiffness: ea / rest,
                capacity: bolt.capacity,
                rupture: bolt.rupture_strain.unwrap_or(f64::INFINITY),
                plastic: 0.0,
                elongation: 0.0,
                force: 0.0,
                state: BoltState::Elastic,
                dowel,
                crossing: [local(a, tc), local(b, tc)],
                slip: DVec3::ZERO,
                shear: DVec3::ZERO,
            });
        }
        if new.is_empty() {
            return Err(MechanicsError::Bolt(format!(
                "the bolt from {} to {} ties no two blocks",
                text(bolt.collar),
                text(end)
            )));
        }
        for e in &new {
            self.add_stiffness(e);
        }
        self.elements.extend(new);
        self.specs.push(bolt);
        Ok(id as usize)
    }

    /// Drops the elements with an anchor in a body now removed (`removed`, per body: the
    /// excavated ones), and rebuilds the stiffness sums from the elements left, in element
    /// order (as installing and `from_stored` sum them). Returns, per element dropped that
    /// has one body staying, that body with the force and moment (about its centroid, at
    /// the current poses) the element exerted on it at the last step: its axial force along
    /// the current line between its anchors and its dowel's shear force, the loads
    /// excavation relaxes.
    pub(super) fn remove_bodies(
        &mut self,
        removed: &[bool],
        bodies: &Bodies,
    ) -> Vec<(usize, DVec3, DVec3)> {
        let gone = |b: u32| removed.get(b as usize).copied().unwrap_or(false);
        if !self
            .elements
            .iter()
            .any(|e| gone(e.bodies[0]) || gone(e.bodies[1]))
        {
            return Vec::new();
        }
        let poses = bodies.poses();
        let mut loads = Vec::new();
        for e in &self.elements {
            let [a, b] = e.bodies;
            let stays = match (gone(a), gone(b)) {
                (false, false) | (true, true) => continue,
                (true, false) => 1,
                (false, true) => 0,
            };
            let ends = e.ends(bodies);
            let span = ends[1] - ends[0];
            let length = span.length();
            // The axial force pulls the anchors together (tension > 0), at the anchors; the
            // dowel's shear force is `shear` on the second body, at the crossing.
            let pull = if length > 0.0 {
                span * (e.force / length)
            } else {
                DVec3::ZERO
            };
            let (axial, shear) = if stays == 0 {
                (pull, -e.shear)
            } else {
                (-pull, e.shear)
            };
            let body = e.bodies[stays] as usize;
            let centre = poses[body].translation;
            let crossing = poses[body].apply(e.crossing[stays]);
            let moment = (ends[stays] - centre).cross(axial) + (crossing - centre).cross(shear);
            loads.push((body, axial + shear, moment));
        }
        self.elements
            .retain(|e| !(gone(e.bodies[0]) || gone(e.bodies[1])));
        self.stiffness.clear();
        let elements = std::mem::take(&mut self.elements);
        for e in &elements {
            self.add_stiffness(e);
        }
        self.elements = elements;
        loads
    }

    /// Adds element `e`'s springs to its bodies' stiffness sums.
    fn add_stiffness(&mut self, e: &BoltElement) {
        for side in 0..2 {
            let s = self.stiffness.entry(e.bodies[side]).or_insert([0.0; 2]);
            let (r, rc) = (e.anchors[side], e.crossing[side]);
            s[0] += e.stiffness + e.dowel.stiffness;
            s[1] += e.stiffness * r.length_squared() + e.dowel.stiffness * rc.length_squared();
        }
    }

    /// The bolts as a restart file stores them (state.rs): the specs, checked as
    /// [`Bolts::install`] checks them (an error names the bolt), and the elements as they
    /// were; the stiffness sums are rebuilt in element order, as installing summed them, so
    /// the critical time step is the same bit for bit.
    pub(super) fn from_stored(
        specs: Vec<Bolt>,
        elements: Vec<BoltElement>,
    ) -> Result<Bolts, (usize, MechanicsError)> {
        for (i, bolt) in specs.iter().enumerate() {
            check(bolt).map_err(|e| (i, e))?;
        }
        let mut out = Bolts {
            specs,
            elements: Vec::new(),
            stiffness: BTreeMap::new(),
        };
        for e in &elements {
            out.add_stiffness(e);
        }
        out.elements = elements;
        Ok(out)
    }

    /// Updates every element's force at the bodies' poses and adds the forces and their
    /// moments (about the centroids) to the bodies' sums, in element order.
    pub(super) fn add_forces(
        &mut self,
        bodies: &Bodies,
        forces: &mut [DVec3],
        moments: &mut [DVec3],
    ) {
        let poses = bodies.poses();
        for e in &mut self.elements {
            let [pa, pb] = e.ends(bodies);
            let span = pb - pa;
            let length = span.length();
            let f = e.load(length - e.rest);
            let [a, b] = [e.bodies[0] as usize, e.bodies[1] as usize];
            if f != 0.0 && length > 0.0 {
                // Tension pulls the anchors towards each other.
                let pull = span * (f / length);
                forces[a] += pull;
                moments[a] += (pa - poses[a].translation).cross(pull);
                forces[b] -= pull;
                moments[b] -= (pb - poses[b].translation).cross(pull);
            }
            if e.dowel.stiffness > 0.0 && length > 0.0 {
                let ca = poses[a].apply(e.crossing[0]);
                let cb = poses[b].apply(e.crossing[1]);
                let v = e.shear_load(cb - ca, span / length);
                forces[b] += v;
                moments[b] += (cb - poses[b].translation).cross(v);
                forces[a] -= v;
                moments[a] -= (ca - poses[a].translation).cross(v);
            }
        }
    }

    /// The critical time step with the bolts, from `contacts`, the free bodies' smallest
    /// bound without them (docs/mechanics.md, "Critical time step"): a body's bolts add to
    /// its stiffness, `ω² ≤ ω_c² + max(2 Σk / m, 2 Σk r² / I_min)`; bounded here by the
    /// largest contact rate plus the largest bolt rate of a free body (at most √2 below the
    /// bound body by body, and only where a body's bolts are as stiff as another's contacts).
    pub(super) fn critical_step(&self, bodies: &Bodies, contacts: f64) -> f64 {
        if self.stiffness.is_empty() {
            return contacts;
        }
        let rate = self
            .stiffness
            .iter()
            .filter(|(&i, _)| bodies.is_free(i as usize))
            .map(|(&i, &[k, kr])| {
                let i = i as usize;
                (2.0 * k / bodies.inertial_mass(i))
                    .max(2.0 * kr / bodies.inertial_moments(i).min_element())
            })
            .fold(0.0, f64::max);
        2.0 / (4.0 / (contacts * contacts) + rate).sqrt()
    }
}

fn check(bolt: &Bolt) -> Result<(), MechanicsError> {
    if !(bolt.collar.is_finite() && bolt.direction.is_finite()) {
        return Err(MechanicsError::NotFinite("the bolt's collar or direction"));
    }
    if bolt.direction.length() == 0.0 {
        return Err(MechanicsError::Bolt("the bolt's direction is zero".into()));
    }
    let positive = [
        ("bolt length", bolt.length),
        ("bolt stiffness", bolt.stiffness),
        ("bolt capacity", bolt.capacity),
        ("bolt rupture_strain", bolt.rupture_strain.unwrap_or(1.0)),
        (
            "bolt shear_stiffness",
            bolt.dowel.map_or(1.0, |d| d.stiffness),
        ),
        (
            "bolt shear_capacity",
            bolt.dowel.map_or(1.0, |d| d.capacity),
        ),
    ];
    for (name, value) in positive {
        if !(value.is_finite() && value > 0.0) {
            return Err(MechanicsError::Parameter {
                name,
                range: "a finite number > 0",
                value,
            });
        }
    }
    Ok(())
}

/// The runs of the segment `start -> end` through the bodies, in order along it:
/// `(body, t_in, t_out)` with `t` the distance from `start`; consecutive runs through parts
/// of one body merged.
fn crossed(
    placed: &[ConvexBlock],
    part_body: &[u32],
    start: DVec3,
    end: DVec3,
) -> Vec<(u32, f64, f64)> {
    let length = start.distance(end);
    let d = (end - start) / length;
    let eps = 1e-9 * length;
    let mut runs: Vec<(u32, f64, f64)> = placed
        .iter()
        .enumerate()
        .filter_map(|(k, part)| {
            let (mut t_in, mut t_out) = (0.0f64, length);
            for plane in part.planes() {
                let dn = plane.normal.dot(d);
                let dist = plane.distance(start);
                if dn == 0.0 {
                    if dist > eps {
                        return None;
                    }
                } else if dn < 0.0 {
                    t_in = t_in.max(-dist / dn);
                } else {
                    t_out = t_out.min(-dist / dn);
                }
            }
            (t_out - t_in > eps).then_some((part_body[k], t_in, t_out))
        })
        .collect();
    runs.sort_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
    let mut merged: Vec<(u32, f64, f64)> = Vec::with_capacity(runs.len());
    for run in runs {
        match merged.last_mut() {
            Some(prev) if prev.0 == run.0 => prev.2 = prev.2.max(run.2),
            _ => merged.push(run),
        }
    }
    merged
}

#[cfg(test)]
mod tests {
    use super::*;

    fn element(capacity: f64, rupture: f64) -> BoltElement {
        BoltElement {
            bolt: 0,
            bodies: [0, 1],
            anchors: [DVec3::ZERO; 2],
            rest: 2.0,
            stiffness: 10.0,
            capacity,
            rupture,
            plastic: 0.0,
            elongation: 0.0,
            force: 0.0,
            state: BoltState::Elastic,
            dowel: Dowel {
                stiffness: 4.0,
                capacity: 2.0,
            },
            crossing: [DVec3::ZERO; 2],
            slip: DVec3::ZERO,
            shear: DVec3::ZERO,
        }
    }

    #[test]
    fn the_dowel_resists_shear_across_the_bolt_up_to_its_capacity() {
        let mut e = element(5.0, f64::INFINITY);
        let axis = DVec3::Z;
        // The axial part of the displacement is the element's, not the dowel's.
        let v = e.shear_load(DVec3::new(0.25, 0.0, 7.0), axis);
        assert_eq!(v, DVec3::new(-1.0, 0.0, 0.0));
        // Past the capacity it slips: the force stays at it.
        let v = e.shear_load(DVec3::new(0.0, 1.5, 0.0), axis);
        assert!((v - DVec3::new(0.0, -2.0, 0.0)).length() < 1e-15);
        assert!((e.slip - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-15);
        // Back by 0.25: elastic unloading from the slip.
        let v = e.shear_load(DVec3::new(0.0, 1.25, 0.0), axis);
        assert!((v - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-15);
    }

    /// The figure of docs/mechanics.md ("Rock bolts and applied loads").
    #[test]
    fn a_bolt_element_takes_the_bytes_the_docs_state() {
        assert_eq!(std::mem::size_of::<BoltElement>(), 232);
    }

    #[test]
    fn the_axial_law_is_elastic_perfectly_plastic() {
        let mut e = element(5.0, f64::INFINITY);
        assert_eq!(e.load(0.3), 3.0);
        assert_eq!(e.state, BoltState::Elastic);
        // Past the capacity: the force stays at it, the excess elongation is plastic.
        assert_eq!(e.load(0.8), 5.0);
        assert_eq!(e.state, BoltState::Yielding);
        assert!((e.plastic - 0.3).abs() < 1e-15);
        // Unloading is elastic from the plastic elongation.
        assert!((e.load(0.6) - 3.0).abs() < 1e-12);
        assert_eq!(e.state, BoltState::Elastic);
        // In compression, the same capacity.
        assert_eq!(e.load(-1.0), -5.0);
    }

    #[test]
    fn past_its_rupture_strain_an_element_breaks_for_good() {
        let mut e = element(1.0, 0.1); // yields at 0.1, breaks at an elongation of 0.2
        assert_eq!(e.load(0.19), 1.0);
        assert_eq!(e.state, BoltState::Yielding);
        assert_eq!(e.load(0.21), 0.0);
        assert_eq!(e.state, BoltState::Broken);
        assert_eq!(e.load(0.0), 0.0);
        assert_eq!(e.state, BoltState::Broken);
    }

    #[test]
    fn a_segment_crosses_the_blocks_in_order() {
        let blocks = vec![
            ConvexBlock::cuboid([0.0, 0.0, 2.0], [1.0, 1.0, 3.0]).unwrap(),
            ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap(),
            ConvexBlock::cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]).unwrap(),
            ConvexBlock::cuboid([5.0, 5.0, 0.0], [6.0, 6.0, 1.0]).unwrap(),
        ];
        let runs = crossed(
            &blocks,
            &[7, 8, 9, 10],
            DVec3::new(0.5, 0.5, -1.0),
            DVec3::new(0.5, 0.5, 2.5),
        );
        let want = [(8, 1.0, 2.0), (9, 2.0, 3.0), (7, 3.0, 3.5)];
        assert_eq!(runs.len(), 3);
        for (got, want) in runs.iter().zip(want) {
            assert_eq!(got.0, want.0);
            assert!((got.1 - want.1).abs() < 1e-12 && (got.2 - want.2).abs() < 1e-12);
        }
    }
}
