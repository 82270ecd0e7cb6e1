//! Contacts between bodies (concave blocks made of convex parts, docs/concave-blocks.md).
//!
//! The parts are detected pair by pair with the penetration-edge method, as any convex
//! blocks (two parts of one body are never a pair). Their contacts, the *pieces*, are then
//! grouped per pair of bodies into *regions*, the contacts of the bodies:
//!
//! 1. pieces that touch (a point of one within the length threshold of the other's point,
//!    segment or polygon) and lie on one plane (both face-bearing, types 5 to 7, with
//!    parallel normals) are one region: a face-face contact across a glue face is one polygon
//!    region whose area is the sum of its pieces';
//! 2. pieces without a face (types 1 to 4) that touch are one region, joined to the first
//!    face-bearing region they touch, if any;
//! 3. a region of one piece whose features touch no glue keeps the piece's type (so a system
//!    of convex blocks gets exactly [`BlockSystem::detect_with_geometry`]'s answers); any other
//!    region is typed by the real features of each body: the distinct planes of its
//!    non-internal part faces that hold every contact point of the region's pieces
//!    (one: a face, two: an edge, three or more: a vertex), so that a part edge lying inside a
//!    real face of the block is not an edge of the block.
//!
//! Two bodies can touch in several regions (a block sitting in a notch touches its floor and
//! walls): each is one [`BodyContact`] with its `region` index.

use super::detect::{narrow_phase, Cancelled, DetectProgress, PairContact};
use super::BlockSystem;
use crate::block::ConvexBlock;
use crate::classify::{contact_type, Contact, ContactType, Feature, PairResult};
use crate::contact::Detector;
use crate::contact_geometry::ContactPoints;
use crate::geometry::{Aabb, DVec3};
use crate::tolerance::Tolerance;
use rayon::prelude::*;
use std::ops::ControlFlow;

/// Faces whose normals make an angle with a sine below this are parallel for grouping: the
/// coplanar faces of two parts of one body come from one cutting plane and agree to
/// rounding (about 1e-15), while distinct faces of rock blocks are degrees apart.
const PARALLEL_SINE: f64 = 1e-6;

/// One contact region of two bodies.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct BodyContact {
    /// The two body ids, smaller first.
    pub bodies: [u32; 2],
    /// The region's index among the regions of this pair of bodies (0, 1, ...).
    pub region: u32,
    /// The type, by the real features of the bodies.
    pub kind: ContactType,
    /// Unit normal from `bodies[0]` to `bodies[1]`.
    pub normal: [f64; 3],
    /// Signed distance along the normal (the smallest of its pieces'): gap (> 0) or depth.
    pub distance: f64,
    /// Area of a face-face region: the sum of its pieces' polygons; 0 otherwise.
    pub area: f64,
}

/// Every contact of the bodies of a system ([`BlockSystem::detect_bodies`]).
///
/// Region `i` is made of the part contacts `pieces[piece_offsets[i]..piece_offsets[i + 1]]`;
/// piece `k` has the points `piece_points[piece_point_offsets[k]..piece_point_offsets[k + 1]]`
/// (one point, a segment's two ends or a convex polygon, as
/// [`super::ContactGeometries::points`]).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct BodyContacts {
    /// The contact regions, sorted by pair of bodies, then region.
    pub contacts: Vec<BodyContact>,
    /// Pairs of bodies with two parts that penetrate beyond the tolerance, sorted.
    pub penetrating: Vec<[u32; 2]>,
    /// The part contacts of the regions, region after region: `pair` holds the part of
    /// `bodies[0]` first (not necessarily the smaller block id), features in that order.
    pub pieces: Vec<PairContact>,
    /// Start of each region's pieces (length: regions + 1).
    pub piece_offsets: Vec<u64>,
    /// Start of each piece's points (length: pieces + 1).
    pub piece_point_offsets: Vec<u64>,
    /// The points of all pieces.
    pub piece_points: Vec<[f64; 3]>,
}

impl BodyContacts {
    /// No contact.
    pub(super) fn empty() -> Self {
        BodyContacts {
            piece_offsets: vec![0],
            piece_point_offsets: vec![0],
            ..BodyContacts::default()
        }
    }

    /// Appends the contacts of `other` (their offsets moved past this one's).
    fn append(&mut self, other: BodyContacts) {
        let (pieces, points) = (self.pieces.len() as u64, self.piece_points.len() as u64);
        self.contacts.extend(other.contacts);
        self.pieces.extend(other.pieces);
        self.piece_points.extend(other.piece_points);
        let moved = |o: &[u64], by: u64| o[1..].iter().map(move |x| x + by).collect::<Vec<_>>();
        self.piece_offsets
            .extend(moved(&other.piece_offsets, pieces));
        self.piece_point_offsets
            .extend(moved(&other.piece_point_offsets, points));
    }

    /// Appends regions `range` of `other` (their pieces and points).
    fn append_regions(&mut self, other: &BodyContacts, range: std::ops::Range<usize>) {
        if range.is_empty() {
            return;
        }
        let pieces =
            other.piece_offsets[range.start] as usize..other.piece_offsets[range.end] as usize;
        let points = other.piece_point_offsets[pieces.start] as usize
            ..other.piece_point_offsets[pieces.end] as usize;
        // An offset `x` of `other` (at least the copied stretch's start, offsets being
        // sorted) moves from `start` in `other` to this one's end: `x - start + end`. The
        // stretch can start past this one's end (earlier regions of `other` dropped), so the
        // shift `end - start` can be negative and is not computed alone.
        let (start, end) = (pieces.start as u64, self.pieces.len() as u64);
        self.piece_offsets.extend(
            other.piece_offsets[range.start + 1..=range.end]
                .iter()
                .map(|&x| x - start + end),
        );
        let (start, end) = (points.start as u64, self.piece_points.len() as u64);
        self.piece_point_offsets.extend(
            other.piece_point_offsets[pieces.start + 1..=pieces.end]
                .iter()
                .map(|&x| x - start + end),
        );
        self.contacts.extend_from_slice(&other.contacts[range]);
        self.pieces.extend_from_slice(&other.pieces[pieces]);
        self.piece_points
            .extend_from_slice(&other.piece_points[points]);
    }

    /// These contacts with those of some pairs of bodies replaced: `replaced` holds those
    /// pairs, sorted and distinct, each with its new regions and, if it penetrates, itself in
    /// `penetrating`. A step of [`super::ContactTracker`] that changes few pairs of bodies
    /// builds its regions this way, copying the others' stretches whole.
    pub(super) fn with_pairs_replaced(&self, replaced: &[([u32; 2], BodyContacts)]) -> Self {
        debug_assert!(replaced.windows(2).all(|w| w[0].0 < w[1].0));
        let mut out = BodyContacts::empty();
        let (mut at, mut pen) = (0, 0);
        for (bodies, fresh) in replaced {
            let before = at + self.contacts[at..].partition_point(|c| c.bodies < *bodies);
            out.append_regions(self, at..before);
            at = before + self.contacts[before..].partition_point(|c| c.bodies == *bodies);
            out.append(fresh.clone());
            let p = pen + self.penetrating[pen..].partition_point(|b| b < bodies);
            out.penetrating.extend_from_slice(&self.penetrating[pen..p]);
            pen = p + usize::from(self.penetrating.get(p) == Some(bodies));
            out.penetrating.extend_from_slice(&fresh.penetrating);
        }
        out.append_regions(self, at..self.contacts.len());
        out.penetrating.extend_from_slice(&self.penetrating[pen..]);
        out
    }

    /// The pieces of region `i`.
    pub fn pieces_of(&self, i: usize) -> &[PairContact] {
        &self.pieces[self.piece_offsets[i] as usize..self.piece_offsets[i + 1] as usize]
    }

    /// The points of piece `k`.
    pub fn piece_points_of(&self, k: usize) -> &[[f64; 3]] {
        let (s, e) = (self.piece_point_offsets[k], self.piece_point_offsets[k + 1]);
        &self.piece_points[s as usize..e as usize]
    }
}

/// Per block, its glued faces and its faces covered by glue, as bit masks (faces 0 to 63; a
/// face beyond is looked up in the glue's sorted lists): the regions ask for them for every
/// part face they look at, where the binary searches of the lists took a fifth of
/// `detect_bodies` on the tunnel benchmark (docs/benchmarks.md).
#[derive(Clone, Debug, Default)]
pub(super) struct FaceMarks {
    glued: Vec<u64>,
    covered: Vec<u64>,
}

impl FaceMarks {
    /// The marks of `system`'s glue (empty without concave blocks).
    pub(super) fn of(system: &BlockSystem) -> FaceMarks {
        let Some(glue) = &system.glue else {
            return FaceMarks::default();
        };
        let mark = |list: &[(u32, u32)]| {
            let mut masks = vec![0u64; system.len()];
            for &(block, face) in list.iter().filter(|(_, f)| *f < 64) {
                masks[block as usize] |= 1 << face;
            }
            masks
        };
        FaceMarks {
            glued: mark(&glue.glued),
            covered: mark(&glue.covered),
        }
    }

    /// Whether face `f` of `block` has glue on it ([`BlockSystem::is_glued_face`]).
    fn glued(&self, system: &BlockSystem, block: u32, f: u32) -> bool {
        match self.glued.get(block as usize) {
            Some(mask) if f < 64 => mask >> f & 1 != 0,
            Some(_) => system.is_glued_face(block, f),
            None => false,
        }
    }

    /// Whether face `f` of `block` is covered by glue ([`BlockSystem::is_internal_face`]).
    fn covered(&self, system: &BlockSystem, block: u32, f: u32) -> bool {
        match self.covered.get(block as usize) {
            Some(mask) if f < 64 => mask >> f & 1 != 0,
            Some(_) => system.is_internal_face(block, f),
            None => false,
        }
    }
}

/// A part contact, oriented from the first body to the second.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Piece {
    /// The bodies, smaller first.
    pub(super) bodies: [u32; 2],
    /// The parts, of `bodies[0]` first.
    pub(super) parts: [u32; 2],
    contact: Contact,
    normal: DVec3,
    distance: f64,
    area: f64,
    points: ContactPoints,
    /// The pair's length threshold.
    length: f64,
}

/// The outcome of a part pair.
enum Outcome {
    Separated,
    Penetrating([u32; 2]),
    Contact(Box<Piece>),
}

impl BlockSystem {
    /// Detects every contact of the bodies of the system: the parts pair by pair, then their
    /// contacts grouped into regions per pair of bodies (module docs). For a system where
    /// each block is its own body, the regions are [`BlockSystem::detect_with_geometry`]'s
    /// contacts, in the same order, each region 0.
    ///
    /// ```
    /// use penedge::{BlockSystem, ConvexBlock, ContactType, Tolerance};
    /// let tol = Tolerance::default();
    /// // An L-block of two boxes (glued at x = 1) and a box lying across the glue.
    /// let system = BlockSystem::new(vec![
    ///     ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap(),
    ///     ConvexBlock::cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap(),
    ///     ConvexBlock::cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]).unwrap(),
    ///     ConvexBlock::cuboid([0.5, 0.0, 2.0], [1.5, 1.0, 3.0]).unwrap(),
    /// ])
    /// .with_bodies(vec![0, 0, 0, 1], &tol)
    /// .unwrap();
    /// let found = system.detect_bodies(&tol);
    /// // The box touches the top of part 2 only: one face-face region of area 0.5.
    /// assert_eq!(found.contacts.len(), 1);
    /// assert_eq!(found.contacts[0].kind, ContactType::FaceFace);
    /// assert!((found.contacts[0].area - 0.5).abs() < 1e-9);
    /// ```
    pub fn detect_bodies(&self, tol: &Tolerance) -> BodyContacts {
        match self.detect_bodies_with_progress(tol, &mut |_| ControlFlow::Continue(())) {
            Ok(found) => found,
            Err(Cancelled) => unreachable!("never cancelled"),
        }
    }

    /// [`BlockSystem::detect_bodies`] with progress reports and cancellation, as
    /// [`BlockSystem::detect_with_progress`].
    pub fn detect_bodies_with_progress(
        &self,
        tol: &Tolerance,
        progress: &mut dyn FnMut(DetectProgress) -> ControlFlow<()>,
    ) -> Result<BodyContacts, Cancelled> {
        let pairs = self.contact_pairs(tol);
        let mut pieces: Vec<Piece> = Vec::new();
        let mut penetrating: Vec<[u32; 2]> = Vec::new();
        narrow_phase(
            self,
            &pairs,
            tol,
            progress,
            |det, pair, a, b| match self.query_parts(det, pair, a, b) {
                (_, Some(piece)) => Outcome::Contact(piece),
                (PairResult::Penetrating, None) => {
                    let mut bodies = pair.map(|k| self.body_of(k));
                    bodies.sort_unstable();
                    Outcome::Penetrating(bodies)
                }
                _ => Outcome::Separated,
            },
            |_, outcomes| {
                for outcome in outcomes {
                    match std::mem::replace(outcome, Outcome::Separated) {
                        Outcome::Contact(piece) => pieces.push(*piece),
                        Outcome::Penetrating(bodies) => penetrating.push(bodies),
                        Outcome::Separated => {}
                    }
                }
            },
        )?;
        penetrating.sort_unstable();
        penetrating.dedup();
        let ordered: Vec<&Piece> = if self.has_concave() {
            sorted(&pieces)
                .into_iter()
                .map(|k| &pieces[k as usize])
                .collect()
        } else {
            pieces.iter().collect()
        };
        Ok(self.regions(&ordered, penetrating, &FaceMarks::of(self)))
    }

    /// The part query of blocks `pair` (`a`, `b`), as [`BlockSystem::detect_bodies`] asks it:
    /// the answer and, for a contact, its piece (oriented from the first body to the second).
    pub(super) fn query_parts(
        &self,
        det: &mut Detector,
        pair: [u32; 2],
        a: &ConvexBlock,
        b: &ConvexBlock,
    ) -> (PairResult, Option<Box<Piece>>) {
        let (result, geometry) = det.detect_with_geometry(a, b);
        let piece = match (&result, geometry) {
            (PairResult::Contact(contact), Some(g)) => Some(Box::new(
                Piece {
                    bodies: pair.map(|k| self.body_of(k)),
                    parts: pair,
                    contact: *contact,
                    normal: g.normal(),
                    distance: g.distance(),
                    area: g.area(),
                    length: det.thresholds(a, b).length,
                    points: g.into_shape(),
                }
                .oriented(),
            )),
            _ => None,
        };
        (result, piece)
    }

    /// The regions of the pieces, given in order (by bodies, then parts), less the pairs of
    /// bodies in `penetrating` (sorted): stretches of whole pairs of bodies in parallel, then
    /// joined in order.
    pub(super) fn regions(
        &self,
        pieces: &[&Piece],
        penetrating: Vec<[u32; 2]>,
        marks: &FaceMarks,
    ) -> BodyContacts {
        let bodies_at = |k: usize| pieces[k].bodies;
        const STRETCH: usize = 1 << 12;
        let mut bounds = vec![0];
        while *bounds.last().expect("not empty") < pieces.len() {
            let start = *bounds.last().expect("not empty");
            let mut end = (start + STRETCH).min(pieces.len());
            while end < pieces.len() && bodies_at(end) == bodies_at(end - 1) {
                end += 1;
            }
            bounds.push(end);
        }
        let stretches: Vec<BodyContacts> = bounds
            .par_windows(2)
            .map(|w| {
                let mut out = BodyContacts::empty();
                let mut group: Vec<&Piece> = Vec::new();
                let mut start = w[0];
                while start < w[1] {
                    let bodies = bodies_at(start);
                    group.clear();
                    let mut end = start;
                    while end < w[1] && bodies_at(end) == bodies {
                        group.push(pieces[end]);
                        end += 1;
                    }
                    if penetrating.binary_search(&bodies).is_err() {
                        self.add_pair(&group, &mut out, marks);
                    }
                    start = end;
                }
                out
            })
            .collect();
        let mut out = BodyContacts::empty();
        out.penetrating = penetrating;
        for part in stretches {
            out.append(part);
        }
        out
    }

    /// Adds the regions of one pair of bodies (its pieces in order).
    pub(super) fn add_pair(&self, pieces: &[&Piece], out: &mut BodyContacts, marks: &FaceMarks) {
        if let [p] = pieces {
            if !self.touches_glue(p, marks) {
                // The common case (convex blocks): the piece is the region.
                let area = if p.contact.kind == ContactType::FaceFace {
                    p.area
                } else {
                    0.0
                };
                return push_region(out, pieces, 0, p.contact.kind, p.normal, area);
            }
        }
        for (region, members) in group(pieces).iter().enumerate() {
            let members: Vec<&Piece> = members.iter().map(|&k| pieces[k]).collect();
            let (kind, face_normal) = match members[..] {
                [p] if !self.touches_glue(p, marks) => (p.contact.kind, Some(p.normal)),
                _ => self.region_type(&members, marks),
            };
            let faced: Vec<&&Piece> = members.iter().filter(|p| bears_face(p)).collect();
            let largest = faced.iter().max_by(|p, q| p.area.total_cmp(&q.area));
            let normal = match (face_normal, largest) {
                (Some(n), _) => n,
                (None, Some(p)) => p.normal,
                (None, None) => members
                    .iter()
                    .map(|p| p.normal)
                    .sum::<DVec3>()
                    .normalize_or(members[0].normal),
            };
            let area = if kind == ContactType::FaceFace {
                members.iter().map(|p| p.area).sum()
            } else {
                0.0
            };
            push_region(out, &members, region as u32, kind, normal, area);
        }
    }

    /// Whether a feature of the piece is a face with glue on it, or an edge or vertex of
    /// such a face: the part's feature may then not be the body's.
    fn touches_glue(&self, piece: &Piece, marks: &FaceMarks) -> bool {
        let features = [piece.contact.feature_a, piece.contact.feature_b];
        piece.parts.iter().zip(features).any(|(&part, feature)| {
            if !self.is_part_of_concave(part) {
                return false;
            }
            let block = &self.blocks()[part as usize];
            let glued = |f: u32| marks.glued(self, part, f);
            match feature {
                Feature::Face(_) => false,
                Feature::Edge(e) => block.edges()[e as usize].faces.into_iter().any(glued),
                Feature::Vertex(v) => match block.vertex_faces().get(v as usize) {
                    // The faces at the vertex, from its mask (blocks of at most 64 faces).
                    Some(&mask) => (0..64).filter(|f| mask >> f & 1 != 0).any(glued),
                    None => (0..block.n_faces() as u32)
                        .filter(|&f| block.face(f as usize).contains(&v))
                        .any(glued),
                },
            }
        })
    }

    /// The type of a region from the real features of both bodies (module docs, step 3),
    /// and its normal when a body holds it with a face: that face's (from the first body to
    /// the second), or `normalize(n0 - n1)` for two faces.
    fn region_type(&self, members: &[&Piece], marks: &FaceMarks) -> (ContactType, Option<DVec3>) {
        let points: Vec<DVec3> = members
            .iter()
            .flat_map(|p| p.points.as_slice().iter().copied())
            .collect();
        let length = members.iter().map(|p| p.length).fold(0.0, f64::max);
        let planes = [0, 1].map(|side| {
            let mut parts: Vec<u32> = members.iter().map(|p| p.parts[side]).collect();
            parts.sort_unstable();
            parts.dedup();
            // Per point, the face of this side's part that its piece lies on, if any.
            let own: Vec<Option<(u32, u32)>> = members
                .iter()
                .flat_map(|p| {
                    let feature = [p.contact.feature_a, p.contact.feature_b][side];
                    let face = match feature {
                        Feature::Face(f) => Some((p.parts[side], f)),
                        _ => None,
                    };
                    std::iter::repeat_n(face, p.points.as_slice().len())
                })
                .collect();
            self.holding_planes(&parts, &points, &own, length, marks)
        });
        let feature = |n: &[DVec3]| match n.len() {
            1 => Feature::Face(0),
            2 => Feature::Edge(0),
            _ => Feature::Vertex(0),
        };
        let superposed = || {
            let [a, b] = [&planes[0], &planes[1]].map(|n| n[0].cross(n[1]).normalize_or_zero());
            a.cross(b).length() <= PARALLEL_SINE && spread(&points) > length
        };
        let kind = contact_type(feature(&planes[0]), feature(&planes[1]), superposed);
        let normal = match (&planes[0][..], &planes[1][..]) {
            ([n0], [n1]) => Some((*n0 - *n1).normalize()),
            ([n0], _) => Some(*n0),
            (_, [n1]) => Some(-*n1),
            _ => None,
        };
        (kind, normal)
    }

    /// The normals of the distinct planes of the non-internal faces of `parts` that hold
    /// every point: each point within `length` of the plane and of one of its faces.
    /// `own` names, per point, the part face its piece lies on (if any), which is tried
    /// first: it holds the point unless rounding says otherwise, and the other faces of the
    /// plane are then not tried (the answer is the same in any order).
    fn holding_planes(
        &self,
        parts: &[u32],
        points: &[DVec3],
        own: &[Option<(u32, u32)>],
        length: f64,
        marks: &FaceMarks,
    ) -> Vec<DVec3> {
        let mut planes: Vec<crate::geometry::Plane> = Vec::new();
        // Per plane found, per point, whether a face of the plane holds it (one array,
        // `points.len()` per plane).
        let mut holds: Vec<bool> = Vec::new();
        let m = points.len();
        // The faces on the planes: (part, face, plane).
        let mut on_planes: Vec<(u32, u32, usize)> = Vec::new();
        for &part in parts {
            let block = &self.blocks()[part as usize];
            for (f, plane) in block.planes().iter().enumerate() {
                // The distances first: most faces fail them at the first point.
                if points.iter().any(|&x| plane.distance(x).abs() > length)
                    || marks.covered(self, part, f as u32)
                {
                    continue;
                }
                let k = match planes.iter().position(|q| {
                    q.normal.dot(plane.normal) > 0.0
                        && q.normal.cross(plane.normal).length() <= PARALLEL_SINE
                        && q.distance(plane.point).abs() <= length
                }) {
                    Some(k) => k,
                    None => {
                        planes.push(*plane);
                        holds.resize(holds.len() + m, false);
                        planes.len() - 1
                    }
                };
                on_planes.push((part, f as u32, k));
            }
        }
        // Each point on its own face first; then, for the points not held yet, every face
        // of each plane (a point held by one face of the plane needs no other).
        for (i, owner) in own.iter().enumerate() {
            let Some(&(part, f, k)) =
                owner.and_then(|o| on_planes.iter().find(|c| (c.0, c.1) == o))
            else {
                continue;
            };
            holds[k * m + i] =
                in_face(&self.blocks()[part as usize], f as usize, points[i], length);
        }
        for &(part, f, k) in &on_planes {
            let block = &self.blocks()[part as usize];
            for (held, &x) in holds[k * m..(k + 1) * m].iter_mut().zip(points) {
                if !*held {
                    *held = in_face(block, f as usize, x, length);
                }
            }
        }
        planes
            .iter()
            .zip(holds.chunks(m.max(1)))
            .filter(|(_, h)| h.iter().all(|&x| x))
            .map(|(p, _)| p.normal)
            .collect()
    }
}

impl Piece {
    /// The piece from the first body to the second (the pair query runs from the smaller
    /// block id, whose body may be the larger).
    fn oriented(mut self) -> Piece {
        if self.bodies[0] > self.bodies[1] {
            self.bodies.swap(0, 1);
            self.parts.swap(0, 1);
            let c = &mut self.contact;
            std::mem::swap(&mut c.feature_a, &mut c.feature_b);
            self.normal = -self.normal;
            if let ContactPoints::Polygon(_) = self.points {
                // The polygon runs counter-clockwise about the normal: reversed with it.
                let mut vertices = self.points.as_slice().to_vec();
                vertices.reverse();
                self.points = polygon_of(vertices, self.area);
            }
        }
        self
    }
}

/// Appends a region of the given pieces.
fn push_region(
    out: &mut BodyContacts,
    members: &[&Piece],
    region: u32,
    kind: ContactType,
    normal: DVec3,
    area: f64,
) {
    out.contacts.push(BodyContact {
        bodies: members[0].bodies,
        region,
        kind,
        normal: normal.to_array(),
        distance: members.iter().map(|p| p.distance).fold(f64::MAX, f64::min),
        area,
    });
    for p in members {
        out.pieces.push(PairContact {
            pair: p.parts,
            contact: p.contact,
        });
        let points = p.points.as_slice().iter().map(|x| x.to_array());
        out.piece_points.extend(points);
        out.piece_point_offsets.push(out.piece_points.len() as u64);
    }
    out.piece_offsets.push(out.pieces.len() as u64);
}

/// The order of the pieces by bodies, then parts (indices sorted; the pieces stay).
fn sorted(pieces: &[Piece]) -> Vec<u32> {
    let mut keys: Vec<([u32; 2], [u32; 2], u32)> = pieces
        .iter()
        .enumerate()
        .map(|(k, p)| (p.bodies, p.parts, k as u32))
        .collect();
    keys.par_sort_unstable();
    keys.into_iter().map(|(_, _, k)| k).collect()
}

/// A polygon of contact points (counter-clockwise about its normal) and its area.
fn polygon_of(vertices: Vec<DVec3>, area: f64) -> ContactPoints {
    ContactPoints::Polygon(crate::contact_geometry::ContactPolygon::from_parts(
        vertices, area,
    ))
}

/// Whether a piece bears a face (vertex-face, edge-face, face-face): its normal is a face's.
fn bears_face(p: &Piece) -> bool {
    p.contact.kind.code() >= ContactType::VertexFace.code()
}

/// The pieces of one pair of bodies grouped into regions (module docs, steps 1 and 2), each
/// group in piece order, groups by their first piece.
fn group(pieces: &[&Piece]) -> Vec<Vec<usize>> {
    let n = pieces.len();
    if n == 1 {
        return vec![vec![0]];
    }
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut k: usize) -> usize {
        while root[k] != k {
            root[k] = root[root[k]];
            k = root[k];
        }
        k
    }
    let join = |root: &mut Vec<usize>, a: usize, b: usize| {
        let (a, b) = (find(root, a), find(root, b));
        root[a.max(b)] = a.min(b);
    };
    // The boxes of the pieces' points: two pieces touch only if their boxes, widened by
    // the length threshold, overlap (most pairs of pieces of two large bodies do not).
    let boxes: Vec<Aabb> = pieces
        .iter()
        .map(|p| Aabb::of_points(p.points.as_slice()))
        .collect();
    let near = |a: usize, b: usize| {
        boxes[a].overlaps(&boxes[b], pieces[a].length.max(pieces[b].length))
            && touch(pieces[a], pieces[b])
    };
    for a in 0..n {
        for b in a + 1..n {
            let (p, q) = (pieces[a], pieces[b]);
            let same_plane = bears_face(p)
                && bears_face(q)
                && p.normal.cross(q.normal).length() <= PARALLEL_SINE
                && p.normal.dot(q.normal) > 0.0;
            let both_pointlike = !bears_face(p) && !bears_face(q);
            if (same_plane || both_pointlike) && near(a, b) {
                join(&mut root, a, b);
            }
        }
    }
    // Point-like groups join the first face-bearing piece they touch.
    for a in 0..n {
        if bears_face(pieces[a]) || find(&mut root, a) != a {
            continue;
        }
        let members: Vec<usize> = (0..n).filter(|&k| find(&mut root, k) == a).collect();
        let host = (0..n).find(|&b| bears_face(pieces[b]) && members.iter().any(|&k| near(k, b)));
        if let Some(b) = host {
            join(&mut root, a, b);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut index = vec![usize::MAX; n];
    for k in 0..n {
        let r = find(&mut root, k);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index[r]].push(k);
    }
    groups
}

/// Whether two pieces touch: a point of one within the length threshold of the other.
fn touch(p: &Piece, q: &Piece) -> bool {
    let length = p.length.max(q.length);
    let near = |from: &Piece, to: &Piece| {
        from.points
            .as_slice()
            .iter()
            .any(|&x| distance_to(&to.points, to.normal, x) <= length)
    };
    near(p, q) || near(q, p)
}

/// The distance from `x` to a point, a segment or a convex polygon (counter-clockwise about
/// `normal`).
fn distance_to(points: &ContactPoints, normal: DVec3, x: DVec3) -> f64 {
    match points {
        ContactPoints::Point(p) => (x - *p).length(),
        ContactPoints::Segment([p, q]) => segment_distance(*p, *q, x),
        ContactPoints::Polygon(polygon) => {
            let v = polygon.vertices();
            let inside = (0..v.len()).all(|k| {
                let (p, q) = (v[k], v[(k + 1) % v.len()]);
                normal.cross(q - p).dot(x - p) >= 0.0
            });
            if inside {
                normal.dot(x - v[0]).abs()
            } else {
                (0..v.len())
                    .map(|k| segment_distance(v[k], v[(k + 1) % v.len()], x))
                    .fold(f64::MAX, f64::min)
            }
        }
    }
}

/// The distance from `x` to the segment `pq`.
fn segment_distance(p: DVec3, q: DVec3, x: DVec3) -> f64 {
    let d = q - p;
    let t = if d.length_squared() > 0.0 {
        ((x - p).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x - (p + d * t)).length()
}

/// Whether `x` lies within `length` of face `f` of `block`, in the face's plane: inside
/// every edge of the face widened by `length`.
///
/// With `c = n × (q - p)` (inward, of length |pq|), the test `c/|c| · (x - p) ≥ -length` is
/// taken as `d ≥ 0 or d² ≤ length² |c|²` (`d = c · (x - p)`): no square root or division,
/// which this loop, run for every point of a region on every face that holds them, spent
/// most of its time on.
fn in_face(block: &ConvexBlock, f: usize, x: DVec3, length: f64) -> bool {
    let face = block.face(f);
    let v = block.vertices();
    let n = block.planes()[f].normal;
    let Some(&last) = face.last() else {
        return false;
    };
    let mut p = v[last as usize];
    face.iter().all(|&k| {
        let q = v[k as usize];
        let c = n.cross(q - p);
        let d = c.dot(x - p);
        p = q;
        d >= 0.0 || d * d <= length * length * c.length_squared()
    })
}

/// The largest distance between two of the points.
fn spread(points: &[DVec3]) -> f64 {
    let mut d: f64 = 0.0;
    for (k, &p) in points.iter().enumerate() {
        for &q in &points[k + 1..] {
            d = d.max((p - q).length());
        }
    }
    d
}
