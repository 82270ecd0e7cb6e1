//! Contacts and sub-contacts of a step: from the detection's contacts (type, normal,
//! points) to sub-contacts with area shares, gaps, matched shear history and forces
//! (docs/mechanics.md, steps 2 to 4).

use super::bodies::Bodies;
use super::bridge::{BridgeTable, ContactFaces};
use super::joint::{crosses_joints, joint_law, JointTable, SubState, Tangents};
use super::stress::InitialStress;
use crate::block::{ConvexBlock, Pose};
use crate::classify::{Contact, ContactType, Feature};
use crate::contact_geometry::{ContactGeometry, ContactPoints};
use crate::geometry::{DVec3, Plane};
use glam::Vec3;
use std::sync::OnceLock;

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
    /// Gap along the normal (> 0 apart, < 0 overlapping); for a contact of two vertices or
    /// edges, the largest along the normal and the cone's other valid directions
    /// (docs/mechanics.md, "Gaps of point contacts").
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

    /// The index of the contact of `parts`.
    pub(super) fn find(&self, parts: [u32; 2]) -> Option<usize> {
        self.list.binary_search_by_key(&parts, |c| c.parts).ok()
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
/// bodies' poses at the query, which body each point and the normal move with,
/// and the travel sum past which the pair is queried again.
#[derive(Clone, Debug)]
pub(super) struct Carry {
    /// The poses of the two bodies (A, B) at the query.
    pub poses: [Pose; 2],
    /// Bit `k` set: point `k` moves with B (one of B's vertices, to within the gap, and nearer
    /// to it than to any of A's), else with A.
    pub with_b: u64,
    /// Whether the normal moves with B (B's feature is a face and A's is not).
    pub normal_with_b: bool,
    /// The travel sum since the query past which the pair is queried again (tau; 0: every
    /// step its bodies move).
    pub tolerance: f64,
    /// What the contact's joint model takes from its features (kept with them).
    pub faces: ContactFaces,
    /// The overlap past which the contact bears: half the detection gap where joints cross
    /// ([`crosses_joints`]; docs/mechanics.md, "Where joints cross"), else 0.
    pub engage: f64,
    /// The two features (A's, B's) as placed at the query: a carried contact measures its gaps
    /// in A's frame at the query, where A's is as it was and B's is moved by B's motion
    /// relative to A, rather than reading the placed blocks.
    pub features: [FeatureAt; 2],
    /// The larger of the two blocks' magnitudes at the query (for the rounding slack of a
    /// carried contact's gaps).
    pub magnitude: f64,
    /// The smaller body's diameter, once a step has asked for it (the bodies' shapes do not
    /// change; read from them at every step, it cost a cache miss per body).
    pub diameter: OnceLock<f64>,
    /// For a contact of two vertices or edges (the cone rule's normal), the other valid
    /// directions along which its gaps are measured, as at the query (moving with A like
    /// the normal); empty for the others ([`crate::contact_geometry::cone_rays`];
    /// docs/mechanics.md, "Gaps of point contacts").
    pub axes: Box<[DVec3]>,
}

impl Carry {
    /// The carrying of `found`'s geometry, queried with A and B placed at `poses`.
    pub fn new(
        [a, b]: [&ConvexBlock; 2],
        gap: f64,
        contact: &Contact,
        geometry: &ContactGeometry,
        poses: [Pose; 2],
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
        let (fa, fb) = (contact.feature_a, contact.feature_b);
        Carry {
            poses,
            with_b,
            normal_with_b,
            tolerance,
            engage: if crosses_joints(a, fa, b, fb) {
                0.5 * gap
            } else {
                0.0
            },
            faces: ContactFaces::of(a, fa, b, fb),
            features: [
                FeatureAt::of(a, contact.feature_a),
                FeatureAt::of(b, contact.feature_b),
            ],
            magnitude: a.magnitude().max(b.magnitude()),
            diameter: OnceLock::new(),
            axes: crate::contact_geometry::cone_rays(a, b, contact, geometry.normal(), gap)
                .into_boxed_slice(),
        }
    }
}

/// B's pose in A's body frame: where B's body-frame points are, seen from A.
pub(super) fn b_in_a(a: &Pose, b: &Pose) -> Pose {
    let to_a = a.rotation.conjugate();
    Pose {
        rotation: to_a * b.rotation,
        translation: to_a * (b.translation - a.translation),
    }
}

/// An upper bound of how far any point of B (within `radius_b` of B's centroid) has moved
/// relative to A since B was at `before` in A's frame ([`b_in_a`]), A and B now at `now`
/// (docs/mechanics.md, "Contact updates"): seen in A's frame, A is still and B has moved by a
/// rigid motion, so a plane fixed in A's frame that separated them by `s` still separates them
/// by `s` less this bound. Zero, up to rounding, for two bodies moved by the same rigid motion
/// (a stack falling or sliding as one), whose travels grow all the same. With the bound, B's
/// pose in A's frame now.
pub(super) fn motion_in_a(before: &Pose, now: [&Pose; 2], radius_b: f64) -> (f64, Pose) {
    let after = b_in_a(now[0], now[1]);
    // The frames were composed from world coordinates: their rounding, a few units in the
    // last place of the largest world coordinate, on top of `displacement_bound`'s own.
    let world = now[0]
        .translation
        .abs()
        .max_element()
        .max(now[1].translation.abs().max_element());
    let bound = before.displacement_bound(&after, DVec3::ZERO, radius_b)
        + 32.0 * f64::EPSILON * (world + radius_b);
    (bound, after)
}

/// The certificate of an open contact (docs/mechanics.md, "Dormant contacts"): a carried
/// contact whose sub-contacts are all open (unbonded, positive gap, no force) keeps them,
/// without updating them, while its carried gaps cannot have reached zero.
///
/// Between two queries a carried contact's gaps are a function of B's pose in A's frame
/// alone (its points, normal and features move rigidly with A or B). From B's pose `P` in A's
/// frame at the update that made the certificate to its pose now, let `T + s r` bound the
/// motion of B's points within `r` of its centroid (`s = 2 sin(θ / 2)`, `θ` the turn). A gap
/// is measured along the normal `n` (moving with A) at a point `p`, from A's feature to B's
/// ([`FeatureAt::height`]). With `reach` and `base` of its features ([`open_terms`]), every
/// gap changes by at most
///
/// - two faces: `(T + s reach) / (base - s)`, `reach = ρ + H` (`ρ` bounds the distances from
///   B's centroid of the points and of where the normal through them meets B's plane, `H` the
///   heights of B's plane above the points), `base` the smaller of `|n · n_A|`, `|n · n_B|`;
/// - two edges: `2 (T + s reach) / (base - s)²`, `reach = ρ + W` (`ρ` bounds the distances
///   from B's centroid of the points and of the points of B's edge line whose heights they
///   take, `W` the distances from the points to those), `base = 1 -` the larger of
///   `|n · u_A|`, `|n · u_B|` (the edges' unit directions);
/// - two vertices: `(T + s reach) / (1 - s)`, `reach = ρ + V` (`ρ` bounds the distances from
///   B's centroid of the points and of B's vertex, `V` the distances from B's vertex to the
///   points), `base = 1`;
///
/// the proofs are in docs/mechanics.md. The certificate holds while that bound stays below
/// the smallest gap less a rounding margin: every gap is then still positive, so every
/// sub-contact would be open, unbonded and without force, the same forces as those kept.
#[derive(Clone, Copy, Debug)]
pub(super) struct OpenCert {
    /// B's pose in A's body frame at the update ([`b_in_a`]).
    pub b_in_a: Pose,
    /// The smallest gap then, plus the depth at which the contact bears ([`Carry::engage`]),
    /// less the rounding margin.
    pub min_gap: f64,
    /// `reach` of the features.
    pub reach: f64,
    /// `base` of the features.
    pub base: f64,
    /// Whether the features are two edges (the bound of two edges), else two faces or two
    /// vertices.
    pub edges: bool,
}

impl OpenCert {
    /// An upper bound of how much any gap of the contact has changed since the update, A
    /// and B at `now` (above); `None` when the turn is too large for it (`s` above half of
    /// `base`: never for a carried contact, which has moved less than its update tolerance).
    pub fn gap_change(&self, now: [&Pose; 2]) -> Option<f64> {
        let (numerator, after) = motion_in_a(&self.b_in_a, now, self.reach);
        let relative = after.rotation * self.b_in_a.rotation.conjugate();
        let s = 2.0 * relative.xyz().length().min(1.0);
        let base = self.base - s;
        (base > 0.5 * self.base).then(|| {
            if self.edges {
                2.0 * numerator / (base * base)
            } else {
                numerator / base
            }
        })
    }

    /// Whether every gap of the contact is still above the depth at which it bears (positive,
    /// or above minus half the detection gap where joints cross) with A and B at `now`.
    pub fn holds(&self, now: [&Pose; 2]) -> bool {
        self.gap_change(now).is_some_and(|d| d < self.min_gap)
    }
}

/// The terms of [`OpenCert`] for a contact's points `points` with normal `n` between
/// features `features` (A's, B's), B's centroid at `centre`, all in one frame (a carried
/// contact's: A's at the query): the smallest gap, `reach`, `base`
/// and whether they are edges; `None` for other pairs of features (a face and an edge, a
/// vertex and a face, ...: not certified). The gaps are the features' heights, as a carried
/// contact computes them (at its query, a point contact's gap is the detection's distance
/// instead: not the function the certificate bounds).
fn open_terms(
    points: &[DVec3],
    n: DVec3,
    features: [FeatureAt; 2],
    centre: DVec3,
) -> Option<(f64, f64, f64, bool)> {
    let [fa, fb] = features;
    let mut min_gap = f64::INFINITY;
    // ρ, and the largest of H, W or V.
    let (mut rho, mut extra) = (0.0f64, 0.0f64);
    for &p in points {
        let h = fb.height(p, n);
        min_gap = min_gap.min(h - fa.height(p, n));
        // Where B's feature is, seen from `p`: the point of its plane on the normal through
        // `p`, the point of its edge's line whose height is taken, its vertex.
        let on_b = match fb {
            FeatureAt::Face(_) => p + n * h,
            FeatureAt::Edge(_) => fb.foot(p, n),
            FeatureAt::Vertex(v) => v,
        };
        rho = rho.max(p.distance(centre)).max(on_b.distance(centre));
        extra = extra.max(match fb {
            FeatureAt::Face(_) => h.abs(),
            _ => p.distance(on_b),
        });
    }
    let reach = rho + extra;
    match features {
        [FeatureAt::Face(a), FeatureAt::Face(b)] => {
            let base = a.normal.dot(n).abs().min(b.normal.dot(n).abs());
            Some((min_gap, reach, base, false))
        }
        [FeatureAt::Edge(a), FeatureAt::Edge(b)] => {
            let slope = |[e0, e1]: [DVec3; 2]| n.dot((e1 - e0).normalize()).abs();
            Some((min_gap, reach, 1.0 - slope(a).max(slope(b)), true))
        }
        [FeatureAt::Vertex(_), FeatureAt::Vertex(_)] => Some((min_gap, reach, 1.0, false)),
        _ => None,
    }
}

/// A body's pose, velocity and spin at the step, side by side: a contact reads its two
/// bodies' from one place (computed once per body, rather than per contact from the
/// bodies' scattered arrays and shapes).
#[derive(Clone, Copy, Debug)]
pub(super) struct Motion {
    pub pose: Pose,
    pub velocity: DVec3,
    pub spin: DVec3,
}

/// The motions of all bodies ([`Motion`]), in parallel.
pub(super) fn motions(bodies: &Bodies) -> Vec<Motion> {
    use rayon::prelude::*;
    (0..bodies.len())
        .into_par_iter()
        .map(|i| Motion {
            pose: bodies.pose[i],
            velocity: bodies.velocity(i),
            spin: bodies.spin(i),
        })
        .collect()
}

/// What a new contact's sub-contacts need besides the geometry.
pub(super) struct StepInput<'a> {
    pub bodies: &'a Bodies,
    /// The bodies' motions ([`motions`]).
    pub motions: &'a [Motion],
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
    /// Whether open contacts may be left dormant ([`OpenCert`]): on, and no water in the
    /// joints (water pushes on open joints too).
    pub dormancy: bool,
}

/// Buffers of [`build_contact`], one per thread, so that a contact allocates nothing once
/// they have grown.
#[derive(Default)]
pub(super) struct Scratch {
    areas: Vec<f64>,
    floors: Vec<f64>,
    gaps: Vec<f64>,
    points: Vec<DVec3>,
    /// The points in the frame A had at the query (below).
    frame: Vec<DVec3>,
    tangents: Tangents,
}

/// A face-face contact's two faces as the contact plane has them: A's face whose outward
/// normal is nearest the contact normal `n` (from A to B), B's nearest `-n`. The
/// classification gives these but for a block thinner than the length threshold (a layer
/// a few centimetres thick between blocks of metres, at the mechanics' threshold of 1 % of
/// the block size): there its two large faces are within the threshold of each other, and
/// it may give the far one, whose normal is `-n`. The gaps, measured from that face, read
/// the layer's thickness, and the joint set was the far face's (docs/mechanics.md, "Thin
/// layers"). Other contacts, and a face that is already the nearest, are left as they are.
pub(super) fn facing_faces(
    mut contact: crate::classify::Contact,
    n: DVec3,
    [a, b]: [&ConvexBlock; 2],
) -> crate::classify::Contact {
    if contact.kind != ContactType::FaceFace {
        return contact;
    }
    let nearest = |block: &ConvexBlock, face: u32, n: DVec3| -> u32 {
        let planes = block.planes();
        let mut best = face;
        let mut cos = planes
            .get(face as usize)
            .map_or(f64::NEG_INFINITY, |p| p.normal.dot(n));
        for (k, p) in planes.iter().enumerate() {
            if p.normal.dot(n) > cos + 1e-9 {
                (best, cos) = (k as u32, p.normal.dot(n));
            }
        }
        best
    };
    if let Feature::Face(f) = contact.feature_a {
        contact.feature_a = Feature::Face(nearest(a, f, n));
    }
    if let Feature::Face(f) = contact.feature_b {
        contact.feature_b = Feature::Face(nearest(b, f, -n));
    }
    contact
}

/// How many sub-contacts the contact of `found` has: one per contact point.
pub(super) fn sub_count(found: &Found) -> usize {
    found.geometry.points().len()
}

/// A contact of this step, before its sub-contacts: its candidate pair (index and parts; the
/// detection's answer is the pair's memo's), and whether it is dormant (its sub-contacts kept
/// from the last step: docs/mechanics.md, "Dormant contacts"); then, from
/// [`counts_and_previous`], its sub-contact count and the index of the same pair's contact at
/// the last step. No reference to the answer, so that the step's list of them is a buffer
/// kept from step to step (docs/mechanics.md, "The sub-contact update").
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Current {
    pub pair: u32,
    pub parts: [u32; 2],
    pub dormant: bool,
    /// Whether the last step's contact of the pair (if any) was built from this same answer
    /// at the same point width: then its sub-contacts' area shares are this step's
    /// ([`build_contact`]).
    pub same_answer: bool,
    pub count: u32,
    pub previous: Option<u32>,
}

/// For each contact found this step (in pair order), its sub-contact count, the index of
/// the same pair's contact in `previous` (if it had one) and whether it is dormant (a
/// dormant contact without one in `previous` is not: it is updated), written to it: a merge
/// of the two lists, both sorted by pair, rather than a binary search per contact (in
/// parallel, by chunks that each search where they start; a pair not met by the merge is
/// searched, so the answer does not depend on the order). A contact built from the same
/// answer as at the last step (a dormant one among them) takes its count from the last
/// step's contact, and does not read its answer.
/// `answer` gives the answer of a candidate pair that has one (every [`Current`]'s).
pub(super) fn counts_and_previous<'a>(
    previous: &Contacts,
    found: &mut [Current],
    answer: impl Fn(u32) -> &'a Found + Sync,
) {
    use rayon::prelude::*;
    let list = &previous.list;
    found.par_chunks_mut(4096).for_each(|chunk| {
        let mut j = list.partition_point(|c| c.parts < chunk[0].parts);
        for f in chunk {
            while j < list.len() && list[j].parts < f.parts {
                j += 1;
            }
            let at = if j < list.len() && list[j].parts == f.parts {
                Some(j)
            } else {
                previous.find(f.parts)
            };
            f.previous = at.map(|i| i as u32);
            match at {
                // Built from the same answer at the last step (a dormant contact always
                // is): as many sub-contacts as then, one per point of that answer. Read from
                // the last step's contact rather than from the answer's box, a cache miss
                // per contact (the build reads the box later anyway, but that miss was a
                // twentieth of the step: docs/benchmarks.md, "Thirteenth run").
                Some(i) if f.same_answer => f.count = list[i].count,
                _ => {
                    f.count = sub_count(answer(f.pair)) as u32;
                    f.dormant = false;
                }
            }
        }
    });
}

/// The contact, its sub-contacts with their forces for this step written to `subs` (of length
/// [`sub_count`]; `previous`: the index of the pair's contact at the last step), and their
/// installed normal stresses to `prestresses` (of the same length, or empty when the step keeps
/// none: no initial stress in the run). With it, the certificate that lets the contact stay dormant
/// at the next steps, when it is a carried contact of two faces, edges or vertices open at every
/// sub-contact ([`OpenCert`]).
pub(super) fn build_contact(
    input: &StepInput,
    found: &Found,
    previous: Option<u32>,
    same_answer: bool,
    scratch: &mut Scratch,
    subs: &mut [SubContact],
    prestresses: &mut [f64],
) -> (BodyContact, Option<OpenCert>) {
    let Scratch {
        areas,
        floors,
        gaps,
        points,
        frame,
        tangents,
    } = scratch;
    let [pa, pb] = found.parts;
    let (a, b) = (&input.placed[pa as usize], &input.placed[pb as usize]);
    let bodies = [input.part_body[pa as usize], input.part_body[pb as usize]];
    let g = &found.geometry;
    let motion = bodies.map(|i| &input.motions[i as usize]);
    let poses = motion.map(|m| m.pose);
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
    let (set, bridge, mut model) = found.carry.faces.model(input.joints, input.bridges);
    // The smaller body's diameter (twice its radius about the centroid): the same whatever
    // its orientation, unlike a bounding box.
    let diameter = *found.carry.diameter.get_or_init(|| {
        let radius = |i: u32| input.bodies.shape(i as usize).radius();
        2.0 * radius(bodies[0]).min(radius(bodies[1]))
    });
    let width = input.point_width * diameter;
    // Where joints cross (two edges or vertices, each in both joints' planes), the contact
    // bears only past an overlap of half the detection gap (`Carry::engage`; 0 elsewhere):
    // the blocks across each single joint carry the line while they are there, and a block
    // pivoting on it at a free face still finds it (docs/mechanics.md, "Where joints cross").
    let engage = found.carry.engage;
    // The gaps are measured in the frame A had at the query, A's motion since undone (a
    // rigid motion of both bodies changes no gap): there A's feature, the points moving with
    // A, the normal (when it moves with A) and the cone's other directions are as they were
    // at the query, and only B's feature and points have moved, by B's motion relative to A
    // since the query. (Measured in the world, all of them would be moved, and the
    // directions renormalised, at every step.) At the query's poses that frame is the world.
    let relative = carried.map(|[ma, mb]| {
        let back = ma.rotation.conjugate();
        Pose {
            rotation: back * mb.rotation,
            translation: back * (mb.translation - ma.translation),
        }
    });
    let frame_normal = match relative {
        Some(r) if found.carry.normal_with_b => (r.rotation * g.normal()).normalize(),
        _ => g.normal(),
    };
    // The two features there: read from the placed blocks at the query's poses, else B's
    // moved from where it was at the query as its points are (docs/mechanics.md, "Carried
    // contacts": the same rigid motion, so a carried contact reads neither block).
    let features = match relative {
        None => [
            FeatureAt::of(a, found.contact.feature_a),
            FeatureAt::of(b, found.contact.feature_b),
        ],
        Some(r) => [found.carry.features[0], found.carry.features[1].moved(&r)],
    };
    // The rounding of a gap of zero, far above it (and above the rounding of coordinates
    // far from the origin): a bond at zero gap is not broken by it. (A carried contact takes
    // its blocks' magnitude at the query: they have moved by less than tau since.)
    let magnitude = match carried {
        None => a.magnitude().max(b.magnitude()),
        Some(_) => found.carry.magnitude,
    };
    let slack = (1e-9 * diameter).max(crate::tolerance::ROUNDING_FLOOR * magnitude);
    let pose_a = poses[0];
    let previous = previous.map(|i| {
        let i = i as usize;
        (
            input.previous.list[i].first as usize,
            input.previous.subs_of(i),
        )
    });
    // The shares of the geometry at the query: a rigid motion keeps them. The last step's
    // contact built from this same answer at the same width computed them already, point by
    // point: they are read back (the same bits), not computed again.
    areas.clear();
    match previous {
        Some((_, old)) if same_answer && old.len() == g.points().len() => {
            areas.extend(old.iter().map(|o| o.area));
        }
        _ => area_shares(g.shape(), g.normal(), width, areas, floors),
    }
    // The strengths act on the polygon's own area (docs/mechanics.md, "Areas of
    // sub-contacts"): where the corners' floor has raised the shares above it (a polygon
    // narrower than the point width), the stresses of cohesion and tension are scaled by the
    // polygon's area over the shares', so that the sub-contacts together hold `c A` and
    // `T A`; the floor stays a stiffness (for continuity as the polygon narrows to a
    // segment), not more rock to glue. The model is left as it is (the same bits) elsewhere.
    // So is an initial stress installed on it (its tractions, below).
    // Only where something reads it (a strength to scale, an initial stress to install): a
    // frictional joint without bonds skips it (the same bits: the ratio scales zeros).
    let scaled = model.cohesion != 0.0
        || model.tension != 0.0
        || model.residual_cohesion != 0.0
        || (input.initial && input.initial_stress.is_some());
    let own_share = match g.shape() {
        ContactPoints::Polygon(poly) if scaled => {
            let shares: f64 = areas.iter().sum();
            let own = polygon_area(poly.vertices(), g.normal());
            (shares > own * (1.0 + 1e-9)).then(|| own / shares)
        }
        _ => None,
    };
    if let Some(r) = own_share {
        model.cohesion *= r;
        model.tension *= r;
        model.residual_cohesion *= r;
    }
    let model = &model;
    let moves_with_b = |k: usize| k < 64 && found.carry.with_b & (1 << k) != 0;
    points.clear();
    match carried {
        None => points.extend_from_slice(g.points()),
        Some(m) => points.extend(
            g.points()
                .iter()
                .enumerate()
                .map(|(k, &p)| m[usize::from(moves_with_b(k))].apply(p)),
        ),
    }
    // The points in A's frame at the query.
    let frame: &[DVec3] = match relative {
        None => g.points(),
        Some(r) => {
            frame.clear();
            frame.extend(g.points().iter().enumerate().map(|(k, &p)| {
                if moves_with_b(k) {
                    r.apply(p)
                } else {
                    p
                }
            }));
            frame
        }
    };
    // A point contact at its query takes the detection's distance; every other gap is the
    // features' heights (the function the open-contact certificate bounds).
    let from_distance = matches!((g.shape(), carried), (ContactPoints::Point(_), None));
    gaps.clear();
    if from_distance {
        gaps.push(g.distance());
    } else {
        separations(features, frame_normal, frame, |_, s| gaps.push(s));
    }
    // A contact of two vertices or edges: the largest separation along the normal and the
    // cone's other valid directions (docs/mechanics.md, "Gaps of point contacts"), so that
    // features that slid past each other without overlapping (diagonal neighbours in a grid
    // of blocks settling) are apart, not pushed along the normal.
    for &axis in found.carry.axes.iter() {
        separations(features, axis, frame, |k, s| {
            if let Some(gap) = gaps.get_mut(k) {
                *gap = gap.max(s);
            }
        });
    }
    // What a certificate of the open contact needs, from the gaps before the strip's
    // adjustment below (which only lowers the shallower gap to the deeper one): the smallest
    // gap, and the terms of `OpenCert`. Only with the normal moving with A (the proofs'), and
    // only when every gap is positive: a gap at or below zero stays so through the adjustment
    // (the smallest gap is kept), its sub-contact is not open and the contact gets no
    // certificate, so its terms are not computed (most contacts of a mass at rest).
    // The rounding margin a certificate's smallest gap must clear (below).
    let margin = |min_gap: f64| min_gap - 2.0 * slack - 512.0 * f64::EPSILON * magnitude;
    // Nor are they when the smallest gap cannot clear it: the certificate's smallest gap,
    // the features' heights along the normal, is at most the gaps computed from those
    // heights (the largest of them and of the heights along the cone's other directions),
    // and the margin is monotone in it (a point contact open only by rounding, as the
    // diagonal neighbours in a grid of blocks at rest are: most of the open contacts).
    // Open means bearing nothing: a gap above the depth at which the contact starts to bear
    // (`engage`: 0, or half the detection gap where joints cross), so a contact where joints
    // cross stays dormant while its overlap stays below that depth (docs/mechanics.md,
    // "Dormant contacts").
    let open = (input.dormancy
        && found.carry.tolerance > 0.0
        && !found.carry.normal_with_b
        && gaps.iter().all(|&g| g + engage > 0.0)
        && (from_distance
            || margin(gaps.iter().copied().fold(f64::INFINITY, f64::min) + engage) > 0.0))
        .then(|| {
            // B's centroid in A's frame at the query.
            let centre = found.carry.poses[1].translation;
            let centre = relative.map_or(poses[1].translation, |r| r.apply(centre));
            open_terms(frame, frame_normal, features, centre)
        })
        .flatten();
    if let (ContactType::FaceFace, 2, FeatureAt::Face(plane_a), FeatureAt::Face(plane_b)) =
        (found.contact.kind, gaps.len(), features[0], features[1])
    {
        // A face-face polygon narrower than the length threshold, given as a segment: a
        // strip along an edge (a block rocking onto it), whose two points the detection
        // gives to within the threshold, one of them possibly across the strip where the
        // faces have opened. The shallower end is moved across the strip, along the gap's
        // gradient on the contact plane, to the deeper end's depth: both ends then lie on
        // the edge, as the segment of the edge-face contact the strip becomes.
        // The gradient in A's frame at the query, turned into the world.
        let (na, nb, nf) = (plane_a.normal, plane_b.normal, frame_normal);
        let grad = na / na.dot(nf) - nb / nb.dot(nf);
        let grad = grad - nf * grad.dot(nf);
        let grad = carried.map_or(grad, |m| m[0].rotation * grad);
        let (deep, shallow) = if gaps[0] <= gaps[1] { (0, 1) } else { (1, 0) };
        if grad.length_squared() > 0.0 {
            points[shallow] -= grad * ((gaps[shallow] - gaps[deep]) / grad.length_squared());
        }
        gaps[shallow] = gaps[deep];
    }
    let mean_spin = 0.5 * (motion[0].spin + motion[1].spin);
    // Rotated with the contact plane: onto the new plane, and about the normal by the
    // bodies' mean spin over the step (3DEC's rule).
    let twist = glam::DQuat::from_axis_angle(n, mean_spin.dot(n) * input.dt);
    let point_velocity = |m: &Motion, p: DVec3| m.velocity + m.spin.cross(p - m.pose.translation);
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
                let k = nearest(old, local);
                let o = &old[k];
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
                let touching = input.initial && gap + engage <= slack;
                let (normal, shear) = match input.initial_stress {
                    Some(field) if touching && found.contact.kind == ContactType::FaceFace => {
                        let (normal, shear) = field.traction(p, n);
                        match own_share {
                            Some(r) => (normal * r, shear * r),
                            None => (normal, shear),
                        }
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
        // The installed normal stress as an offset of the gap: (σn - kn gap) A; and where
        // joints cross, the depth at which the contact starts to bear.
        let out = joint_law(
            model,
            area,
            gap + engage - prestress / model.kn,
            shear,
            bonded,
            slack,
            tangents,
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
    // Dormant from the next step while every gap stays above the rounding margin: twice the
    // rounding slack, and the rounding of two gaps computed from world coordinates (tens of
    // units in the last place of the largest, over a cosine above 1/4), far below the slack
    // but for coordinates some 10^5 block sizes from the origin.
    let cert = open.and_then(|(min_gap, reach, base, edges)| {
        let min_gap = margin(min_gap + engage);
        let all_open = subs
            .iter()
            .all(|s| s.state == SubState::Open && !s.bonded && s.gap + engage > 0.0);
        (all_open && min_gap > 0.0 && base > 0.5).then(|| OpenCert {
            b_in_a: b_in_a(&poses[0], &poses[1]),
            min_gap,
            reach,
            base,
            edges,
        })
    });
    let contact = BodyContact {
        parts: found.parts,
        bodies,
        kind: found.contact.kind,
        normal: n,
        set,
        bridge,
        first: 0,
        count: subs.len() as u32,
    };
    (contact, cert)
}

/// A feature ([`FeatureAt`]) made ready to give its heights along one direction `n` at many
/// points: what does not depend on the point is computed once (an edge's direction and its
/// projection on the plane normal to `n`, a face's cosine to `n`): the heights are the same
/// bits as when these were computed again for each point. A contact's gaps take them at each
/// of its points, along its normal and the cone's other directions (docs/mechanics.md, "The
/// sub-contact update").
#[derive(Clone, Copy, Debug)]
struct Along {
    /// The direction.
    n: DVec3,
    feature: Ready,
}

/// A feature made ready for a direction ([`Along`]).
#[derive(Clone, Copy, Debug)]
enum Ready {
    Vertex(DVec3),
    /// A face's plane and the cosine of its normal to the direction.
    Face(Plane, f64),
    Edge(EdgeAlong),
}

/// An edge made ready for a direction `n` ([`Along`]).
#[derive(Clone, Copy, Debug)]
struct EdgeAlong {
    /// Its first end.
    e0: DVec3,
    /// From its first end to its second.
    d: DVec3,
    /// `d` projected on the plane normal to `n`.
    dp: DVec3,
    /// `|dp|²`.
    len2: f64,
    /// Whether `len2` is large enough to divide by (else the edge is along `n`).
    slanted: bool,
}

impl EdgeAlong {
    fn new([e0, e1]: [DVec3; 2], n: DVec3) -> EdgeAlong {
        let d = e1 - e0;
        // The edge's direction within the plane normal to `n`: its point nearest the line
        // p + s n is where its projection passes nearest p.
        let dp = d - n * d.dot(n);
        let len2 = dp.length_squared();
        EdgeAlong {
            e0,
            d,
            dp,
            len2,
            slanted: len2 > 1e-24 * d.length_squared(),
        }
    }

    /// `e0 - p` and the parameter `t` of the edge line's point whose projection along `n`
    /// (the direction it was made for) passes nearest `p` (`0.5`, the middle, for an edge
    /// along `n`).
    fn foot(&self, p: DVec3, n: DVec3) -> (DVec3, f64) {
        let w = self.e0 - p;
        let t = if self.slanted {
            let wp = w - n * w.dot(n);
            -wp.dot(self.dp) / self.len2
        } else {
            0.5
        };
        (w, t)
    }
}

impl Along {
    /// `feature` made ready for direction `n`.
    fn new(feature: FeatureAt, n: DVec3) -> Along {
        let feature = match feature {
            FeatureAt::Vertex(v) => Ready::Vertex(v),
            FeatureAt::Face(plane) => Ready::Face(plane, plane.normal.dot(n)),
            FeatureAt::Edge(ends) => Ready::Edge(EdgeAlong::new(ends, n)),
        };
        Along { n, feature }
    }

    /// The height ([`FeatureAt::height`]) at `p` along the direction.
    fn height(&self, p: DVec3) -> f64 {
        let n = self.n;
        match self.feature {
            Ready::Vertex(v) => n.dot(v - p),
            Ready::Face(plane, cos) => {
                if cos.abs() > 1e-6 {
                    plane.normal.dot(plane.point - p) / cos
                } else {
                    // A face along the normal: its centroid's height (not met in practice:
                    // the contact normal of a face feature is close to the face's normal).
                    n.dot(plane.point - p)
                }
            }
            Ready::Edge(edge) => {
                let (w, t) = edge.foot(p, n);
                n.dot(w + edge.d * t)
            }
        }
    }
}

/// The separations along `n` of the two features (A's, B's) at each of `points`, B's height
/// less A's ([`FeatureAt::height`]), given to `each` with the point's index.
fn separations(
    [fa, fb]: [FeatureAt; 2],
    n: DVec3,
    points: &[DVec3],
    mut each: impl FnMut(usize, f64),
) {
    let (a, b) = (Along::new(fa, n), Along::new(fb, n));
    for (k, &p) in points.iter().enumerate() {
        let sa = a.height(p);
        let sb = b.height(p);
        each(k, sb - sa);
    }
}

/// The index of the sub-contact of `old` whose `local` is nearest `p` (the first of equals).
fn nearest(old: &[SubContact], p: DVec3) -> usize {
    let distance = |o: &SubContact| o.local.as_dvec3().distance_squared(p);
    let (mut best, mut smallest) = (0, distance(&old[0]));
    for (k, o) in old.iter().enumerate().skip(1) {
        let d = distance(o);
        if d.total_cmp(&smallest).is_lt() {
            (best, smallest) = (k, d);
        }
    }
    best
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
            shares.resize(v.len(), 0.0);
            floors.clear();
            floors.resize(v.len(), 0.0);
            for (i, j, triangle) in triangles(v, n) {
                let half = 0.5 * triangle;
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

/// The triangles of the convex polygon `v` (its corners in order) from its centroid, seen
/// along `n`: for each side, its two corners' indices and the triangle's area.
fn triangles(v: &[DVec3], n: DVec3) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let c = v.iter().copied().sum::<DVec3>() / v.len() as f64;
    (0..v.len()).map(move |i| {
        let j = (i + 1) % v.len();
        (i, j, 0.5 * (v[i] - c).cross(v[j] - c).dot(n).abs())
    })
}

/// The area of the convex polygon `v` seen along `n`: the sum of its [`triangles`], which
/// [`area_shares`] splits between their corners (the shares before their floor sum to it).
fn polygon_area(v: &[DVec3], n: DVec3) -> f64 {
    triangles(v, n).map(|(_, _, area)| area).sum()
}

/// A contact feature of a placed block, where it is: a vertex, a face's plane, or an edge's
/// two ends (all that [`FeatureAt::height`] reads of the block).
#[derive(Clone, Copy, Debug)]
pub(super) enum FeatureAt {
    Vertex(DVec3),
    Face(Plane),
    Edge([DVec3; 2]),
}

impl FeatureAt {
    /// Feature `f` of `block`.
    fn of(block: &ConvexBlock, f: Feature) -> FeatureAt {
        match f {
            Feature::Vertex(v) => FeatureAt::Vertex(block.vertices()[v as usize]),
            Feature::Face(k) => FeatureAt::Face(block.planes()[k as usize]),
            Feature::Edge(e) => {
                let edge = block.edges()[e as usize];
                FeatureAt::Edge(edge.vertices.map(|v| block.vertices()[v as usize]))
            }
        }
    }

    /// The feature moved rigidly by `m`.
    fn moved(self, m: &Pose) -> FeatureAt {
        match self {
            FeatureAt::Vertex(v) => FeatureAt::Vertex(m.apply(v)),
            FeatureAt::Face(plane) => FeatureAt::Face(Plane {
                normal: m.rotation * plane.normal,
                point: m.apply(plane.point),
            }),
            FeatureAt::Edge(ends) => FeatureAt::Edge(ends.map(|v| m.apply(v))),
        }
    }

    /// Where the line through `p` along `n` meets the feature, as `s` in `p + s n`: a face's
    /// plane, the point of an edge's line nearest the line, a vertex's height
    /// (docs/mechanics.md, "Normal force").
    fn height(&self, p: DVec3, n: DVec3) -> f64 {
        Along::new(*self, n).height(p)
    }

    /// The point of an edge's line whose height [`FeatureAt::height`] takes: where its
    /// projection along `n` passes nearest `p` (its middle for an edge along `n`); for a
    /// vertex, the vertex; for a face, where the line through `p` along `n` meets its plane.
    fn foot(&self, p: DVec3, n: DVec3) -> DVec3 {
        match *self {
            FeatureAt::Edge(ends) => {
                let edge = EdgeAlong::new(ends, n);
                let (_, t) = edge.foot(p, n);
                edge.e0 + edge.d * t
            }
            FeatureAt::Vertex(v) => v,
            FeatureAt::Face(_) => p + n * self.height(p, n),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Detector;
    use crate::Tolerance;

    /// The lemma of [`OpenCert`], by brute force, for unit cubes A and B at `pose_a`,
    /// `pose_b` (B's centroid at `pose_b`'s translation) in open contact of type `kind`: B
    /// moved by random small rigid motions about its centroid (1 µm to 0.3 mm, 1e-6 to 3e-4
    /// rad); the carried gaps (the points moving with B moved, B's feature moved, the normal
    /// with A) change by at most `gap_change`. The proof holds whichever body each point
    /// moves with: every assignment is tried (400 motions each), not only the carrying's.
    /// Returns the smallest ratio of the bound to the largest change, and how many points
    /// the carrying moves with B.
    fn lemma(pose_a: Pose, pose_b: Pose, kind: ContactType) -> (f64, usize) {
        let unit = ConvexBlock::cuboid([-0.5; 3], [0.5; 3]).unwrap();
        let placed = |pose: &Pose| {
            let mut block = unit.clone();
            block.place_from(&unit, pose);
            block
        };
        let (a, b) = (placed(&pose_a), placed(&pose_b));
        let mut detector = Detector::new(Tolerance::with_gap(1e-3).unwrap());
        let (result, geometry) = detector.detect_with_geometry(&a, &b);
        let contact = match result {
            crate::PairResult::Contact(c) => c,
            other => panic!("{other:?}"),
        };
        assert_eq!(contact.kind, kind);
        let g = geometry.unwrap();
        let gap = detector.thresholds(&a, &b).gap;
        let carry = Carry::new([&a, &b], gap, &contact, &g, [pose_a, pose_b], 0.1 * gap);
        assert!(!carry.normal_with_b);
        let with_b = (0..g.points().len())
            .filter(|k| carry.with_b & (1 << k) != 0)
            .count();
        let [fa, fb] = carry.features;
        let n = g.normal();
        let gaps = |m: &Pose, mask: u64| -> Vec<f64> {
            let moved = fb.moved(m);
            g.points()
                .iter()
                .enumerate()
                .map(|(k, &p)| {
                    let p = if mask & (1 << k) != 0 { m.apply(p) } else { p };
                    moved.height(p, n) - fa.height(p, n)
                })
                .collect()
        };
        let before = gaps(&Pose::IDENTITY, 0);
        let min_gap = before.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(min_gap > 1e-4 && min_gap < gap, "gaps {before:?}");
        let (smallest, reach, base, edges) =
            open_terms(g.points(), n, carry.features, pose_b.translation).unwrap();
        assert_eq!(smallest, min_gap);
        let cert = OpenCert {
            b_in_a: b_in_a(&pose_a, &pose_b),
            min_gap,
            reach,
            base,
            edges,
        };
        let mut uniform = {
            let mut seed = 18u64;
            move || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            }
        };
        let mut tightest = f64::INFINITY;
        let masks = 1u64 << g.points().len();
        for trial in 0..400 * masks as usize {
            let mask = trial as u64 % masks;
            let scale = [1e-6, 1e-5, 1e-4, 3e-4][trial / masks as usize % 4];
            let axis = DVec3::new(uniform(), uniform(), uniform()).normalize();
            let q = glam::DQuat::from_axis_angle(axis, scale * uniform());
            let t = DVec3::new(uniform(), uniform(), uniform()) * scale;
            // About B's centroid: x -> q (x - c) + c + t.
            let c = pose_b.translation;
            let m = Pose {
                rotation: q,
                translation: c + t - q * c,
            };
            let now_b = Pose {
                rotation: q * pose_b.rotation,
                translation: c + t,
            };
            let bound = cert.gap_change([&pose_a, &now_b]).unwrap();
            let change = gaps(&m, mask)
                .iter()
                .zip(&before)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(change <= bound, "trial {trial}: {change} > {bound}");
            tightest = tightest.min(bound / change);
        }
        (tightest, with_b)
    }

    /// A's pose in general orientation, and B's beside it: B's centroid at `offset` in A's
    /// frame, B turned by `tilt` (about an oblique axis) from A's orientation.
    fn beside(offset: DVec3, tilt: f64) -> (Pose, Pose) {
        let turn = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let pose_a = Pose {
            rotation: turn,
            translation: DVec3::new(3.0, -2.0, 5.0),
        };
        let tilt = glam::DQuat::from_axis_angle(DVec3::new(1.0, -1.0, 0.2).normalize(), tilt);
        let pose_b = Pose {
            rotation: turn * tilt,
            translation: pose_a.apply(offset),
        };
        (pose_a, pose_b)
    }

    /// Two faces 0.6 mm apart, B tilted and shifted so that the polygon has corners of both
    /// (the carrying moves some with A, some with B): the bound holds, within 2 % of the
    /// largest change for some motion (the test asks for a factor of 10; halving the reach
    /// fails it).
    #[test]
    fn an_open_face_face_contacts_gaps_change_by_at_most_the_certificates_bound() {
        let (a, b) = beside(DVec3::new(0.3, 0.2, 1.0006), 4e-4);
        let (tightest, with_b) = lemma(a, b, ContactType::FaceFace);
        assert!(with_b > 0 && with_b < 4, "{with_b} corners with B");
        assert!(
            tightest < 10.0,
            "the bound is {tightest} times the change at best"
        );
    }

    /// Diagonal neighbours: two parallel edges 0.85 mm apart (across the diagonal), B shifted
    /// along them and tilted.
    #[test]
    fn an_open_edge_superposition_s_gaps_change_by_at_most_the_certificates_bound() {
        let (a, b) = beside(DVec3::new(1.0006, 1.0006, 0.3), 2e-4);
        let (tightest, _) = lemma(a, b, ContactType::EdgeEdgeSuperposition);
        assert!(
            tightest < 10.0,
            "the bound is {tightest} times the change at best"
        );
    }

    /// Corner neighbours: two vertices 0.87 mm apart.
    #[test]
    fn an_open_vertex_vertex_contacts_gap_changes_by_at_most_the_certificates_bound() {
        let (a, b) = beside(DVec3::new(1.0005, 1.0005, 1.0005), 2e-4);
        let (tightest, _) = lemma(a, b, ContactType::VertexVertex);
        assert!(
            tightest < 10.0,
            "the bound is {tightest} times the change at best"
        );
    }

    /// A feature's height at `p` along `n`, everything computed for this one point.
    fn afresh(feature: FeatureAt, p: DVec3, n: DVec3) -> f64 {
        match feature {
            FeatureAt::Vertex(v) => n.dot(v - p),
            FeatureAt::Face(plane) => {
                let cos = plane.normal.dot(n);
                if cos.abs() > 1e-6 {
                    plane.normal.dot(plane.point - p) / cos
                } else {
                    n.dot(plane.point - p)
                }
            }
            FeatureAt::Edge([e0, e1]) => {
                let d = e1 - e0;
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

    /// The heights of [`FeatureAt::height`], made ready for a direction ([`Along`]), against
    /// where the line `p + s n` meets the feature, computed otherwise: a vertex's projection;
    /// a plane's intersection; for an edge, the closest points of two lines from the cross
    /// products (`s = ((e0 - p) × d) · (n × d) / |n × d|²`); an edge along `n` at its middle.
    #[test]
    fn heights_are_where_the_line_along_the_direction_meets_the_feature() {
        let mut rng = crate::system::test_rng::Rng(7);
        let mut vector = || DVec3::new(rng.signed(), rng.signed(), rng.signed());
        for _ in 0..200 {
            let n = vector().normalize();
            let (v, e0, e1) = (vector(), vector(), vector());
            let plane = Plane {
                normal: (n + 0.5 * vector()).normalize(),
                point: vector(),
            };
            let features = [
                FeatureAt::Vertex(v),
                FeatureAt::Face(plane),
                FeatureAt::Edge([e0, e1]),
                FeatureAt::Edge([e0, e0 + 0.7 * n]),
            ];
            let d = e1 - e0;
            let points: Vec<DVec3> = (0..3).map(|_| vector()).collect();
            for (k, feature) in features.into_iter().enumerate() {
                let mut heights = Vec::new();
                separations(
                    [FeatureAt::Vertex(DVec3::ZERO), feature],
                    n,
                    &points,
                    |_, s| heights.push(s),
                );
                for (&p, &h) in points.iter().zip(&heights) {
                    let along = Along::new(feature, n).height(p);
                    let expected = match k {
                        0 => n.dot(v - p),
                        1 => plane.normal.dot(plane.point - p) / plane.normal.dot(n),
                        2 => (e0 - p).cross(d).dot(n.cross(d)) / n.cross(d).length_squared(),
                        _ => n.dot(e0 + 0.35 * n - p),
                    };
                    // The same bits as the heights computed afresh for each point (the
                    // formulas as they were before `Along`).
                    assert_eq!(along.to_bits(), afresh(feature, p, n).to_bits());
                    assert!(
                        (along - expected).abs() < 1e-9 * (1.0 + expected.abs()),
                        "feature {k}: {along} vs {expected}"
                    );
                    // Separations are B's height less A's (A: a vertex at the origin).
                    assert!((h - (along - n.dot(-p))).abs() < 1e-12 * (1.0 + h.abs()));
                }
            }
        }
    }

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
            let sa = FeatureAt::of(&a, contact.feature_a).height(p, g.normal());
            let sb = FeatureAt::of(&b, contact.feature_b).height(p, g.normal());
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
