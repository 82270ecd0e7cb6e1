//! The normal of a contact whose common plane is not unique (vertex-vertex, vertex-edge,
//! edge-edge superposition): the valid normal closest to a symmetric bisector.
//!
//! Near a feature (vertex or edge) at point `p`, a convex block lies in `p + T`, with `T` the
//! cone of directions from the feature into the block (its tangent cone): spanned by the
//! edges leaving a vertex; by `±d` and the two directions into the faces for an edge `d`.
//! A plane through the contact with unit normal `n` has A behind it iff `n·t <= 0` for every
//! `t` of A's cone, and B in front of it iff `n·t >= 0` for every `t` of B's cone. The valid
//! normals form a convex cone `C`, non-empty for touching blocks (two convex bodies with
//! disjoint interiors have a separating plane, and it passes through the contact).
//!
//! The rule: `n` is the element of `C` closest in angle to the bisector
//! `m = normalize(mA - mB)`, `mA` the mean outward normal of the faces at A's feature (a
//! direction inside A's normal cone), likewise `mB`. The closest element of a convex cone
//! lies in the relative interior of one of its faces: `m` itself, the projection of `m` on
//! the plane `t·n = 0` of one constraint, or an extreme ray (a face normal of a feature, or
//! `±tA × tB`). Those candidates are tried, in that order of stages ([`cone_normal`]); the
//! valid one (within an angular slack of the relative gap) closest to `m` wins. If none is
//! valid (edges parallel only within the length threshold, or features lumped by it), the
//! candidate violating the constraints least wins.
//! Exact ties are broken by a key that does not depend on the sign, so that (B, A) gives
//! exactly the opposite choice.

use super::{edge_direction, face_normal};
use crate::block::ConvexBlock;
use crate::classify::{Contact, Feature};
use crate::contact_geometry::distance::separation;
use crate::geometry::DVec3;

/// The block seen from a feature: unit directions from the feature into the block, and the
/// outward unit normals of the faces at the feature.
struct LocalCone {
    into: Vec<DVec3>,
    normals: Vec<DVec3>,
}

/// The valid normal (from A to B) closest to the bisector of the features.
///
/// The closest element of `C` is the target itself when valid; else the projection of the
/// target on the plane of a constraint that the target violates, when that projection is
/// valid (it is then the closest point of the constraint's half-space, which contains `C`);
/// else an extreme ray. Each stage is tried only when the previous one found nothing.
pub(super) fn cone_normal(
    a: &ConvexBlock,
    fa: Feature,
    b: &ConvexBlock,
    fb: Feature,
    slack: f64,
) -> DVec3 {
    let (ca, cb) = (local_cone(a, fa), local_cone(b, fb));
    let target = (mean(&ca.normals) - mean(&cb.normals))
        .try_normalize()
        .or_else(|| (b.centroid() - a.centroid()).try_normalize())
        .unwrap_or(DVec3::Z);
    let mut choice = Choice::new(target, &ca, &cb, slack);
    choice.offer(target);
    if choice.valid.is_none() {
        let behind_a = ca.into.iter().filter(|t| -target.dot(**t) < -slack);
        let front_b = cb.into.iter().filter(|t| target.dot(**t) < -slack);
        for t in behind_a.chain(front_b) {
            choice.offer_vector(target - *t * target.dot(*t));
        }
    }
    if choice.valid.is_none() {
        offer_rays(&mut choice, &ca, &cb);
    }
    choice.best()
}

/// The extreme rays that `C` can have: the face normals at each feature (negated for B), and
/// `±tA × tB` (normalised, where it has a direction), where a facet of A's cone meets one of
/// B's; in that order, each cross product followed by its opposite.
fn extreme_rays<'a>(ca: &'a LocalCone, cb: &'a LocalCone) -> impl Iterator<Item = DVec3> + 'a {
    let crossings = ca.into.iter().flat_map(move |ta| {
        cb.into
            .iter()
            .filter_map(move |tb| ta.cross(*tb).try_normalize())
            .flat_map(|ray| [ray, -ray])
    });
    ca.normals
        .iter()
        .copied()
        .chain(cb.normals.iter().map(|&n| -n))
        .chain(crossings)
}

/// Offers every extreme ray that `C` can have ([`extreme_rays`]).
fn offer_rays(choice: &mut Choice, ca: &LocalCone, cb: &LocalCone) {
    extreme_rays(ca, cb).for_each(|n| choice.offer(n));
}

/// Of `current`, the face normals at the two features (negated for B) and `±tA × tB`, the
/// direction along which B is farthest from A ([`separation`]); exact ties to the larger
/// sign-free key, so that (B, A) gives exactly the opposite.
pub(in crate::contact_geometry) fn most_separating(
    a: &ConvexBlock,
    b: &ConvexBlock,
    contact: &Contact,
    current: DVec3,
) -> DVec3 {
    let (ca, cb) = (
        local_cone(a, contact.feature_a),
        local_cone(b, contact.feature_b),
    );
    let mut best = None;
    for n in std::iter::once(current).chain(extreme_rays(&ca, &cb)) {
        keep_better(&mut best, (separation(a, b, n), n));
    }
    best.map_or(current, |(_, n)| n)
}

/// The candidate extreme rays of `C` ([`extreme_rays`]: the face normals at the features,
/// negated for B, and `±tA × tB`) that are valid within `slack`, without repeats (closer
/// than `1e-9` rad) and without those along `normal`, in the order offered: besides the
/// normal, the directions along which a separation of the features is one of the blocks
/// (docs/mechanics.md, "Gaps of point contacts"). Any plane through A's feature with a
/// normal of `C` has A behind it and, moved by the offset of B's feature along it, B in
/// front of it (both blocks lie in their tangent cones): the offset's component along such a
/// direction, when positive, is a gap between the blocks (to within the slack, for a ray
/// valid only within it).
pub(super) fn valid_rays(
    a: &ConvexBlock,
    fa: Feature,
    b: &ConvexBlock,
    fb: Feature,
    normal: DVec3,
    slack: f64,
) -> Vec<DVec3> {
    let (ca, cb) = (local_cone(a, fa), local_cone(b, fb));
    let choice = Choice::new(normal, &ca, &cb, slack);
    let mut rays: Vec<DVec3> = Vec::new();
    for n in extreme_rays(&ca, &cb) {
        let same = |u: DVec3| u.dot(n) > 0.0 && u.cross(n).length() <= 1e-9;
        if choice.margin(n) >= -slack && !same(normal) && !rays.iter().any(|&u| same(u)) {
            rays.push(n);
        }
    }
    rays
}

fn mean(normals: &[DVec3]) -> DVec3 {
    normals
        .iter()
        .fold(DVec3::ZERO, |s, &n| s + n)
        .normalize_or_zero()
}

fn local_cone(block: &ConvexBlock, feature: Feature) -> LocalCone {
    match feature {
        Feature::Vertex(v) => vertex_cone(block, v),
        Feature::Edge(e) => edge_cone(block, e),
        Feature::Face(f) => face_cone(block, f),
    }
}

/// The edges leaving vertex `v`, and the faces around it: each face at `v` runs along
/// exactly one edge away from `v` (faces are counter-clockwise, and `Edge::faces[0]` runs
/// from `vertices[0]` to `vertices[1]`), so one pass over the edges gives each face once.
fn vertex_cone(block: &ConvexBlock, v: u32) -> LocalCone {
    let p = block.vertices()[v as usize];
    let mut cone = LocalCone {
        into: Vec::with_capacity(8),
        normals: Vec::with_capacity(8),
    };
    for e in block.edges().iter().filter(|e| e.vertices.contains(&v)) {
        let k = (e.vertices[0] != v) as usize;
        let w = e.vertices[1 - k];
        cone.into
            .push((block.vertices()[w as usize] - p).normalize());
        cone.normals.push(face_normal(block, e.faces[k]));
    }
    cone
}

/// `±d` for edge `e`, the direction into each of its two faces (perpendicular to `d`),
/// and the two faces' normals.
fn edge_cone(block: &ConvexBlock, e: u32) -> LocalCone {
    let edge = block.edges()[e as usize];
    let d = edge_direction(block, e);
    let p = block.vertices()[edge.vertices[0] as usize];
    let mut into = Vec::with_capacity(4);
    into.extend([d, -d]);
    for f in edge.faces {
        let off_edge = block
            .face(f as usize)
            .iter()
            .find(|w| !edge.vertices.contains(w));
        if let Some(&w) = off_edge {
            let t = block.vertices()[w as usize] - p;
            into.extend((t - d * t.dot(d)).try_normalize());
        }
    }
    let normals = edge.faces.iter().map(|&f| face_normal(block, f)).collect();
    LocalCone { into, normals }
}

/// The face's edge directions both ways and the inward normal: only the face normal is valid.
fn face_cone(block: &ConvexBlock, f: u32) -> LocalCone {
    let n = face_normal(block, f);
    let face = block.face(f as usize);
    let mut into = vec![-n];
    for (i, &v) in face.iter().enumerate() {
        let w = face[(i + 1) % face.len()];
        let d = (block.vertices()[w as usize] - block.vertices()[v as usize]).normalize();
        into.extend([d, -d]);
    }
    LocalCone {
        into,
        normals: vec![n],
    }
}

/// The best candidate so far: the valid one closest to the target, and the least invalid.
struct Choice<'a> {
    target: DVec3,
    a: &'a LocalCone,
    b: &'a LocalCone,
    slack: f64,
    valid: Option<(f64, DVec3)>,
    least_invalid: Option<(f64, DVec3)>,
}

impl<'a> Choice<'a> {
    fn new(target: DVec3, a: &'a LocalCone, b: &'a LocalCone, slack: f64) -> Self {
        Choice {
            target,
            a,
            b,
            slack,
            valid: None,
            least_invalid: None,
        }
    }

    /// Offers a vector, normalised if it has a direction.
    fn offer_vector(&mut self, v: DVec3) {
        if let Some(n) = v.try_normalize() {
            self.offer(n);
        }
    }

    /// Offers a unit vector.
    fn offer(&mut self, n: DVec3) {
        let margin = self.margin(n);
        if margin >= -self.slack {
            keep_better(&mut self.valid, (n.dot(self.target), n));
        } else {
            keep_better(&mut self.least_invalid, (margin, n));
        }
    }

    /// `min(-n·t for t into A, n·t for t into B)`: non-negative iff A is behind and B in
    /// front of the plane with normal `n` through the contact.
    fn margin(&self, n: DVec3) -> f64 {
        let behind_a = self.a.into.iter().map(|t| -n.dot(*t));
        let front_b = self.b.into.iter().map(|t| n.dot(*t));
        behind_a.chain(front_b).fold(f64::INFINITY, f64::min)
    }

    fn best(&self) -> DVec3 {
        self.valid
            .or(self.least_invalid)
            .map_or(self.target, |(_, n)| n)
    }
}

/// Keeps the candidate with the larger score; exact ties go to the larger sign-free key.
/// Scores are compared as numbers (`-0 == 0`: adding `0.0` makes a zero positive), since the
/// sign of a zero score can differ between (A, B) and (B, A).
fn keep_better(best: &mut Option<(f64, DVec3)>, candidate: (f64, DVec3)) {
    let candidate = (candidate.0 + 0.0, candidate.1);
    let better = match best {
        None => true,
        Some((score, n)) => candidate
            .0
            .total_cmp(score)
            .then_with(|| compare_keys(sign_free(candidate.1), sign_free(*n)))
            .is_gt(),
    };
    if better {
        *best = Some(candidate);
    }
}

/// `n` or `-n`, whichever has its first non-zero component positive: the same for both.
fn sign_free(n: DVec3) -> DVec3 {
    let first = n.to_array().into_iter().find(|&c| c != 0.0).unwrap_or(0.0);
    if first < 0.0 {
        -n
    } else {
        n
    }
}

/// Compares keys component by component as numbers (`-0 == 0`: negating a candidate turns
/// its zeros' signs, which must not break the tie differently for (B, A)).
fn compare_keys(p: DVec3, q: DVec3) -> std::cmp::Ordering {
    let (p, q) = (p + DVec3::ZERO, q + DVec3::ZERO);
    p.x.total_cmp(&q.x)
        .then(p.y.total_cmp(&q.y))
        .then(p.z.total_cmp(&q.z))
}
