//! Contacts and sub-contacts of a step: from the detection's contacts (type, normal,
//! points) to sub-contacts with area shares, gaps, matched shear history and forces
//! (docs/mechanics.md, steps 2 to 4).

use super::bodies::Bodies;
use super::bridge::{contact_model, BridgeTable};
use super::joint::{joint_law, JointTable, SubState};
use super::stress::InitialStress;
use crate::block::{ConvexBlock, Pose};
use crate::classify::{Contact, ContactType, Feature};
use crate::contact_geometry::{ContactGeometry, ContactPoints};
use crate::geometry::DVec3;
use glam::Vec3;

/// A contact between two bodies' convex parts, as the mechanics keeps it.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyContact {
    /// The two parts (global part ids; for convex bodies, the body ids), smaller first.
    pub parts: [u32; 2],
    /// The bodies of the two parts (A, B).
    pub bodies: [u32; 2],
    /// The contact type.
    pub kind: ContactType,
    /// Unit normal from A to B.
    pub normal: DVec3,
    /// The joint set whose properties apply (`None`: the default).
    pub set: Option<u32>,
    /// Whether it is over a rock bridge (the bridge properties of `set` apply).
    pub bridge: bool,
    /// The first of its sub-contacts in [`Contacts::subs`].
    pub first: u32,
    /// How many sub-contacts it has.
    pub count: u32,
}

/// A sub-contact: one point of a contact with its share of the area and its own forces and
/// history.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SubContact {
    /// Where it is (world).
    pub point: DVec3,
    /// Where it is in A's body frame (moves with A; matches sub-contacts across steps), in
    /// single precision: it only picks the nearest sub-contact of the last step, among points
    /// a body size apart at most, and its 12 bytes keep a sub-contact at 112 (docs/mechanics.md,
    /// "Memory").
    pub local: Vec3,
    /// Its share of the contact area.
    pub area: f64,
    /// Gap along the normal (> 0 apart, < 0 overlapping).
    pub gap: f64,
    /// Normal force on B, positive in compression.
    pub normal_force: f64,
    /// Shear force on B, in the contact plane.
    pub shear_force: DVec3,
    /// Accumulated shear displacement of B relative to A, in the contact plane.
    pub shear_displacement: DVec3,
    /// Mohr-Coulomb state.
    pub state: SubState,
    /// Whether its bond (cohesion, tension) is intact.
    pub bonded: bool,
}

impl SubContact {
    /// The force on B (world).
    pub fn force(&self, normal: DVec3) -> DVec3 {
        normal * self.normal_force + self.shear_force
    }
}

/// The contacts of a step, sorted by pair of parts, and their sub-contacts, contact after
/// contact.
#[derive(Clone, Debug, Default)]
pub struct Contacts {
    /// Contacts, sorted by `parts`.
    pub list: Vec<BodyContact>,
    /// Sub-contacts, in the contacts' order.
    pub subs: Vec<SubContact>,
    /// Per sub-contact, the normal stress an initial stress installed (compression
    /// positive), carried besides the elastic `-kn gap` until the sub-contact opens
    /// (`stress.rs`); empty when no sub-contact has one (a side table: only runs with an
    /// initial stress pay its 8 bytes per sub-contact). Read it with [`Contacts::prestress`].
    pub prestresses: Vec<f64>,
}

impl Contacts {
    /// The sub-contacts of contact `i`.
    pub fn subs_of(&self, i: usize) -> &[SubContact] {
        let c = &self.list[i];
        &self.subs[c.first as usize..(c.first + c.count) as usize]
    }

    /// The installed normal stress of sub-contact `k` (0 when none).
    pub fn prestress(&self, k: usize) -> f64 {
        self.prestresses.get(k).copied().unwrap_or(0.0)
    }

    /// The sub-contacts of the contact of `parts`, and the index of its first.
    fn find(&self, parts: [u32; 2]) -> Option<(usize, &[SubContact])> {
        let i = self.list.binary_search_by_key(&parts, |c| c.parts).ok()?;
        Some((self.list[i].first as usize, self.subs_of(i)))
    }
}

/// A contact found by the detection, with its geometry.
#[derive(Clone, Debug)]
pub(super) struct Found {
    pub parts: [u32; 2],
    pub contact: Contact,
    pub geometry: ContactGeometry,
    /// The carrying of the contact between queries (docs/mechanics.md, "Carried contacts").
    pub carry: Carry,
}

/// What carries a contact's geometry with its bodies between two queries of the pair: the
/// bodies' poses and travels at the query, which body each point and the normal move with,
/// and the travel sum past which the pair is queried again.
#[derive(Clone, Debug)]
pub(super) struct Carry {
    /// The poses of the two bodies (A, B) at the query.
    pub poses: [Pose; 2],
    /// Their travels (sums of motion bounds) at the query.
    pub travels: [f64; 2],
    /// Bit `k` set: point `k` moves with B (one of B's vertices, to within the gap, and nearer
    /// to it than to any of A's), else with A.
    pub with_b: u64,
    /// Whether the normal moves with B (B's feature is a face and A's is not).
    pub normal_with_b: bool,
    /// The travel sum since the query past which the pair is queried again (tau; 0: every
    /// step its bodies move).
    pub tolerance: f64,
}

impl Carry {
    /// The carrying of `found`'s geometry, queried with A and B placed at `poses`.
    pub fn new(
        [a, b]: [&ConvexBlock; 2],
        gap: f64,
        contact: &Contact,
        geometry: &ContactGeometry,
        poses: [Pose; 2],
        travels: [f64; 2],
        tolerance: f64,
    ) -> Carry {
        let mut with_b = 0u64;
        if tolerance > 0.0 {
            // A contact point is on the contact plane, within the overlap (below the gap) of
            // the vertex it comes from.
            let nearest = |block: &ConvexBlock, p: DVec3| {
                block
                    .vertices()
                    .iter()
                    .map(|v| v.distance(p))
                    .fold(f64::INFINITY, f64::min)
            };
            for (k, &p) in geometry.points().iter().take(64).enumerate() {
                let to_b = nearest(b, p);
                if to_b <= gap && to_b < nearest(a, p) {
                    with_b |= 1 << k;
                }
            }
        }
        let normal_with_b = matches!(
            (contact.feature_a, contact.feature_b),
            (Feature::Vertex(_) | Feature::Edge(_), Feature::Face(_))
        );
        Carry {
            poses,
            travels,
            with_b,
            normal_with_b,
            tolerance,
        }
    }
}

/// What a new contact's sub-contacts need besides the geometry.
pub(super) struct StepInput<'a> {
    pub bodies: &'a Bodies,
    pub part_body: &'a [u32],
    pub placed: &'a [ConvexBlock],
    pub joints: &'a JointTable,
    pub bridges: &'a BridgeTable,
    pub previous: &'a Contacts,
    pub dt: f64,
    /// Whether new pairs are bonded (the first detection of a run).
    pub initial: bool,
    /// Width of point contacts relative to the smaller block's size.
    pub point_width: f64,
    /// The stress installed on the first detection's touching sub-contacts.
    pub initial_stress: Option<&'a InitialStress>,
}

/// Buffers of [`build_contact`], one per thread, so that a contact allocates nothing once
/// they have grown.
#[derive(Default)]
pub(super) struct Scratch {
    areas: Vec<f64>,
    floors: Vec<f64>,
    gaps: Vec<f64>,
    points: Vec<DVec3>,
}

/// How many sub-contacts the contact of `found` has: one per contact point.
pub(super) fn sub_count(found: &Found) -> usize {
    found.geometry.points().len()
}

/// The contact, its sub-contacts with their forces for this step written to `subs` (of
/// length [`sub_count`]), and their installed normal stresses to `prestresses` (of the same
/// length, or empty when the step keeps none: no initial stress in the run).
pub(super) fn build_contact(
    input: &StepInput,
    found: &Found,
    scratch: &mut Scratch,
    subs: &mut [SubContact],
    prestresses: &mut [f64],
) -> BodyContact {
    let Scratch {
        areas,
        floors,
        gaps,
        points,
    } = scratch;
    let [pa, pb] = found.parts;
    let (a, b) = (&input.placed[pa as usize], &input.placed[pb as usize]);
    let bodies = [input.part_body[pa as usize], input.part_body[pb as usize]];
    let g = &found.geometry;
    let poses = bodies.map(|i| input.bodies.pose[i as usize]);
    // Between queries the geometry moves with the bodies (docs/mechanics.md, "Carried
    // contacts"): the motion of each body since the query, `None` at the query's poses.
    let carried = (0..2)
        .any(|k| !super::same_bits(&found.carry.poses[k], &poses[k]))
        .then(|| {
            [0, 1].map(|k| {
                let (q, p) = (found.carry.poses[k], poses[k]);
                let rotation = p.rotation * q.rotation.conjugate();
                Pose {
                    rotation,
                    translation: p.translation - rotation * q.translation,
                }
            })
        });
    let n = match carried {
        Some(m) => (m[usize::from(found.carry.normal_with_b)].rotation * g.normal()).normalize(),
        None => g.normal(),
    };
    let (fa, fb) = (found.contact.feature_a, found.contact.feature_b);
    let (set, bridge, model) = contact_model(input.joints, input.bridges, a, fa, b, fb);
    let model = &model;
    // The smaller body's diameter (twice its radius about the centroid): the same whatever
    // its orientation, unlike a bounding box.
    let diameter = 2.0
        * input
            .bodies
            .shape(bodies[0] as usize)
            .radius()
            .min(input.bodies.shape(bodies[1] as usize).radius());
    let width = input.point_width * diameter;
    // The rounding of a gap of zero, far above it (and above the rounding of coordinates
    // far from the origin): a bond at zero gap is not broken by it.
    let magnitude = a.magnitude().max(b.magnitude());
    let slack = (1e-9 * diameter).max(crate::tolerance::ROUNDING_FLOOR * magnitude);
    // The shares of the geometry at the query: a rigid motion keeps them.
    area_shares(g.shape(), g.normal(), width, areas, floors);
    let pose_a = poses[0];
    let previous = input.previous.find(found.parts);
    points.clear();
    match carried {
        None => points.extend_from_slice(g.points()),
        Some(m) => points.extend(g.points().iter().enumerate().map(|(k, &p)| {
            let with_b = k < 64 && found.carry.with_b & (1 << k) != 0;
            m[usize::from(with_b)].apply(p)
        })),
    }
    gaps.clear();
    match (g.shape(), carried) {
        (ContactPoints::Point(_), None) => gaps.push(g.distance()),
        _ => gaps.extend(points.iter().map(|&p| {
            let sa = feature_height(a, found.contact.feature_a, p, n);
            let sb = feature_height(b, found.contact.feature_b, p, n);
            sb - sa
        })),
    };
    if let (ContactType::FaceFace, 2, Feature::Face(fa), Feature::Face(fb)) = (
        found.contact.kind,
        gaps.len(),
        found.contact.feature_a,
        found.contact.feature_b,
    ) {
        // A face-face polygon narrower than the length threshold, given as a segment: a
        // strip along an edge (a block rocking onto it), whose two points the detection
        // gives to within the threshold, one of them possibly across the strip where the
        // faces have opened. The shallower end is moved across the strip, along the gap's
        // gradient on the contact plane, to the deeper end's depth: both ends then lie on
        // the edge, as the segment of the edge-face contact the strip becomes.
        let (na, nb) = (
            a.planes()[fa as usize].normal,
            b.planes()[fb as usize].normal,
        );
        let grad = na / na.dot(n) - nb / nb.dot(n);
        let grad = grad - n * grad.dot(n);
        let (deep, shallow) = if gaps[0] <= gaps[1] { (0, 1) } else { (1, 0) };
        if grad.length_squared() > 0.0 {
            points[shallow] -= grad * ((gaps[shallow] - gaps[deep]) / grad.length_squared());
        }
        gaps[shallow] = gaps[deep];
    }
    // The bodies' motion, once per contact: velocities, spins and centroids.
    let motion = bodies.map(|i| {
        let i = i as usize;
        (
            input.bodies.velocity(i),
            input.bodies.spin(i),
            input.bodies.pose[i].translation,
        )
    });
    let mean_spin = 0.5 * (motion[0].1 + motion[1].1);
    // Rotated with the contact plane: onto the new plane, and about the normal by the
    // bodies' mean spin over the step (3DEC's rule).
    let twist = glam::DQuat::from_axis_angle(n, mean_spin.dot(n) * input.dt);
    let point_velocity = |(v, w, c): (DVec3, DVec3, DVec3), p: DVec3| v + w.cross(p - c);
    debug_assert_eq!(subs.len(), points.len());
    debug_assert!(prestresses.is_empty() || prestresses.len() == subs.len());
    for (k_sub, (((&p, &area), &gap), sub)) in points
        .iter()
        .zip(&*areas)
        .zip(&*gaps)
        .zip(subs.iter_mut())
        .enumerate()
    {
        let local = to_body(&pose_a, p);
        // History: the nearest sub-contact of the same pair at the last step; its shear
        // stress carries over (the area shares change as the polygon does).
        let (mut shear, mut slip, bonded, prestress) = match previous {
            Some((first, old)) => {
                let (k, o) = old
                    .iter()
                    .enumerate()
                    .min_by(|(_, x), (_, y)| {
                        x.local
                            .as_dvec3()
                            .distance_squared(local)
                            .total_cmp(&y.local.as_dvec3().distance_squared(local))
                    })
                    .expect("a contact has at least one sub-contact");
                (
                    o.shear_force * (area / o.area),
                    o.shear_displacement,
                    o.bonded,
                    input.previous.prestress(first + k),
                )
            }
            // Bonds, and the initial stress, on the initial configuration's touching
            // sub-contacts only: a joint open at the start has neither. The stress acts
            // across joint faces: face-face contacts only (a vertex or an edge touching has
            // no real area to carry it).
            None => {
                let touching = input.initial && gap <= slack;
                let (normal, shear) = match input.initial_stress {
                    Some(field) if touching && found.contact.kind == ContactType::FaceFace => {
                        field.traction(p, n)
                    }
                    _ => (0.0, DVec3::ZERO),
                };
                (shear * area, DVec3::ZERO, touching, normal)
            }
        };
        shear = twist * onto_plane(shear, n);
        slip = twist * onto_plane(slip, n);
        let relative = point_velocity(motion[1], p) - point_velocity(motion[0], p);
        let du = relative * input.dt;
        let du_s = du - n * du.dot(n);
        slip += du_s;
        shear -= du_s * (model.ks * area);
        // The installed normal stress as an offset of the gap: (σn - kn gap) A.
        let out = joint_law(
            model,
            area,
            gap - prestress / model.kn,
            shear,
            bonded,
            slack,
        );
        if let Some(slot) = prestresses.get_mut(k_sub) {
            *slot = if out.state == SubState::Open {
                0.0
            } else {
                prestress
            };
        }
        *sub = SubContact {
            point: p,
            local: local.as_vec3(),
            area,
            gap,
            normal_force: out.normal_force,
            shear_force: out.shear_force,
            shear_displacement: slip,
            state: out.state,
            bonded: out.bonded,
        };
    }
    BodyContact {
        parts: found.parts,
        bodies,
        kind: found.contact.kind,
        normal: n,
        set,
        bridge,
        first: 0,
        count: subs.len() as u32,
    }
}

/// A point in the body frame of the pose.
fn to_body(pose: &Pose, p: DVec3) -> DVec3 {
    pose.rotation.conjugate() * (p - pose.translation)
}

/// `v` projected on the plane normal to `n`, keeping its length (a vector of the old
/// contact plane rotated onto the new one).
fn onto_plane(v: DVec3, n: DVec3) -> DVec3 {
    let length = v.length();
    let p = v - n * v.dot(n);
    let lp = p.length();
    if lp > 0.0 {
        p * (length / lp)
    } else {
        DVec3::ZERO
    }
}

/// The area share of each contact point (docs/mechanics.md, "Areas of sub-contacts"): a
/// polygon's corners share its area, each at least `w max(e₁, e₂) / 4` (`e₁`, `e₂` its two
/// edges); a segment's ends `w l / 4` each; a point `w² / 2`. A polygon narrowing to a
/// segment (a block rocking onto an edge) thus keeps the stiffness of its corners on that
/// edge, and a segment shrinking to a point tends to the point's.
/// The shares are written to `shares`; `floors` is a buffer.
fn area_shares(
    shape: &ContactPoints,
    n: DVec3,
    width: f64,
    shares: &mut Vec<f64>,
    floors: &mut Vec<f64>,
) {
    shares.clear();
    match shape {
        ContactPoints::Point(_) => shares.push(0.5 * width * width),
        ContactPoints::Segment([p, q]) => shares.extend([0.25 * width * p.distance(*q); 2]),
        ContactPoints::Polygon(poly) => {
            let v = poly.vertices();
            let c = v.iter().copied().sum::<DVec3>() / v.len() as f64;
            shares.resize(v.len(), 0.0);
            floors.clear();
            floors.resize(v.len(), 0.0);
            for i in 0..v.len() {
                let j = (i + 1) % v.len();
                let half = 0.25 * (v[i] - c).cross(v[j] - c).dot(n).abs();
                shares[i] += half;
                shares[j] += half;
                let edge = 0.25 * width * v[i].distance(v[j]);
                floors[i] = f64::max(floors[i], edge);
                floors[j] = f64::max(floors[j], edge);
            }
            for (s, &f) in shares.iter_mut().zip(&*floors) {
                *s = s.max(f);
            }
        }
    }
}

/// Where the line through `p` along `n` meets the feature `f` of `block`, as `s` in
/// `p + s n`: a face's plane, the point of an edge's line nearest the line, a vertex's
/// height (docs/mechanics.md, "Normal force").
fn feature_height(block: &ConvexBlock, f: Feature, p: DVec3, n: DVec3) -> f64 {
    match f {
        Feature::Vertex(v) => n.dot(block.vertices()[v as usize] - p),
        Feature::Face(k) => {
            let plane = &block.planes()[k as usize];
            let cos = plane.normal.dot(n);
            if cos.abs() > 1e-6 {
                plane.normal.dot(plane.point - p) / cos
            } else {
                // A face along the normal: its centroid's height (not met in practice: the
                // contact normal of a face feature is close to the face's normal).
                n.dot(plane.point - p)
            }
        }
        Feature::Edge(e) => {
            let edge = block.edges()[e as usize];
            let e0 = block.vertices()[edge.vertices[0] as usize];
            let e1 = block.vertices()[edge.vertices[1] as usize];
            let d = e1 - e0;
            // The edge's direction within the contact plane; its point nearest the line
            // p + s n is where its projection passes nearest p.
            let dp = d - n * d.dot(n);
            let w = e0 - p;
            let wp = w - n * w.dot(n);
            let len2 = dp.length_squared();
            let t = if len2 > 1e-24 * d.length_squared() {
                -wp.dot(dp) / len2
            } else {
                0.5
            };
            n.dot(w + d * t)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Detector;
    use crate::Tolerance;

    #[test]
    fn a_tilted_face_gives_gaps_that_grow_along_the_tilt_and_areas_that_sum() {
        // B rests on A with its bottom face tilted by 1e-4 about y: the gap grows along x.
        let a = ConvexBlock::cuboid([-2.0, -2.0, -1.0], [2.0, 2.0, 0.0]).unwrap();
        let tilt = glam::DQuat::from_rotation_y(-1e-4);
        let b = ConvexBlock::cuboid([-0.5, -0.5, 0.0], [0.5, 0.5, 1.0])
            .unwrap()
            .transformed(tilt, DVec3::ZERO, 1.0);
        let tol = Tolerance::with_gap(1e-3).unwrap();
        let (result, geometry) = Detector::new(tol).detect_with_geometry(&a, &b);
        let contact = match result {
            crate::PairResult::Contact(c) => c,
            other => panic!("{other:?}"),
        };
        let g = geometry.unwrap();
        assert_eq!(contact.kind, ContactType::FaceFace);
        // A face of 1 m²: the corners' shares (0.25 each) are above the floor
        // (0.1 × 1 / 4 = 0.025) and sum to the area.
        let (mut shares, mut floors) = (Vec::new(), Vec::new());
        area_shares(g.shape(), g.normal(), 0.1, &mut shares, &mut floors);
        assert!((shares.iter().sum::<f64>() - g.area()).abs() < 1e-12);
        // A segment's ends get w l / 4, as the corners of a thin strip l × s do.
        area_shares(
            &ContactPoints::Segment([DVec3::ZERO, DVec3::X]),
            DVec3::Z,
            0.1,
            &mut shares,
            &mut floors,
        );
        assert_eq!(shares, vec![0.025; 2]);
        assert!((g.area() - 1.0).abs() < 1e-6);
        for &p in g.points() {
            let sa = feature_height(&a, contact.feature_a, p, g.normal());
            let sb = feature_height(&b, contact.feature_b, p, g.normal());
            // B's bottom at x: z = x tan(1e-4) (rotation about y by -1e-4 lifts +x).
            let expected = p.x * 1e-4f64.tan();
            assert!(
                (sb - sa - expected).abs() < 1e-9,
                "{p:?}: {} vs {expected}",
                sb - sa
            );
        }
    }
}
