//! A slow, independent reference for the contact of two convex blocks, from their
//! half-spaces only: the polytope A ∩ B (widened or shrunk) by brute-force vertex enumeration
//! (every triple of planes), its dimension, and the smallest face of each block that holds it.
//! Nothing of the engine is used here but [`ConvexBlock::from_planes`], to hand the same
//! half-spaces to the engine.
//!
//! Also here: random convex polytopes, and *constructed* touching placements: B turned so that
//! the outward normal `m` of a chosen feature of B (a vertex, edge or face, with `m` in its
//! normal cone) becomes `-n`, `n` in the normal cone of a chosen feature of A, then moved so
//! that a chosen point of B's feature lands on a chosen point of A's. The plane through that
//! point with normal `n` then separates the blocks (A behind it, B in front), and A ∩ B is the
//! intersection of the two features: a point, a segment or a polygon by construction.

use glam::{DQuat, DVec3};
use penedge::generation::rng::SplitMix64;
use penedge::{ContactType, ConvexBlock, Feature};

/// The half-space `n · x <= d`, `n` unit.
#[derive(Clone, Copy, Debug)]
pub struct HalfSpace {
    pub n: DVec3,
    pub d: f64,
}

impl HalfSpace {
    /// How far `x` lies outside (negative: inside).
    pub fn excess(&self, x: DVec3) -> f64 {
        self.n.dot(x) - self.d
    }

    fn offset(&self, by: f64) -> HalfSpace {
        HalfSpace {
            n: self.n,
            d: self.d + by,
        }
    }
}

/// The point where three planes meet, if they are clearly independent.
fn meet(a: &HalfSpace, b: &HalfSpace, c: &HalfSpace) -> Option<DVec3> {
    let det = a.n.dot(b.n.cross(c.n));
    if det.abs() < 1e-6 {
        return None;
    }
    let p = (b.n.cross(c.n) * a.d + c.n.cross(a.n) * b.d + a.n.cross(b.n) * c.d) / det;
    p.is_finite().then_some(p)
}

/// The vertices of `{x : n_i · x <= d_i}` (every triple of planes, kept if it violates no
/// plane by more than `slack`); empty when the set is.
pub fn enumerate(planes: &[HalfSpace], slack: f64) -> Vec<DVec3> {
    let mut out = Vec::new();
    let m = planes.len();
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                if let Some(p) = meet(&planes[i], &planes[j], &planes[k]) {
                    if planes.iter().all(|h| h.excess(p) <= slack) {
                        out.push(p);
                    }
                }
            }
        }
    }
    out
}

/// A bounded simple convex polytope: its half-spaces, vertices (each on exactly three
/// planes), edges and faces, all found by enumeration.
#[derive(Clone, Debug)]
pub struct Polytope {
    pub planes: Vec<HalfSpace>,
    pub vertices: Vec<DVec3>,
    /// The three planes at each vertex.
    pub at: Vec<[usize; 3]>,
    /// Edges: two vertices and the two planes along the edge.
    pub edges: Vec<([usize; 2], [usize; 2])>,
    /// Faces: a plane and the vertices on it (three or more).
    pub faces: Vec<(usize, Vec<usize>)>,
    /// Diagonal of the bounding box.
    pub size: f64,
}

impl Polytope {
    /// The polytope of the half-spaces, if it is bounded, simple (three planes at every
    /// vertex), with every plane either a face or clear of the polytope, and not slender (no
    /// edge shorter than 5% of the size, no plane nearly through a vertex not on it).
    pub fn new(planes: Vec<HalfSpace>) -> Option<Polytope> {
        if !bounded(&planes) {
            return None;
        }
        let raw = enumerate(&planes, 1e-12);
        let size = bbox_diagonal(&raw);
        if raw.len() < 4 || size.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let on = 1e-9 * size;
        let mut vertices: Vec<DVec3> = Vec::new();
        let mut at = Vec::new();
        for p in raw {
            if vertices.iter().any(|q| q.distance(p) <= 1e-6 * size) {
                // The same vertex from another triple: more than three planes meet there.
                return None;
            }
            let active: Vec<usize> = (0..planes.len())
                .filter(|&i| planes[i].excess(p).abs() <= on)
                .collect();
            let near = (0..planes.len())
                .any(|i| !active.contains(&i) && planes[i].excess(p).abs() <= 1e-6 * size);
            if active.len() != 3 || near {
                return None;
            }
            vertices.push(p);
            at.push([active[0], active[1], active[2]]);
        }
        let mut edges = Vec::new();
        for u in 0..vertices.len() {
            for v in u + 1..vertices.len() {
                let shared: Vec<usize> = at[u]
                    .iter()
                    .copied()
                    .filter(|i| at[v].contains(i))
                    .collect();
                if shared.len() == 2 {
                    if vertices[u].distance(vertices[v]) < 0.01 * size {
                        return None;
                    }
                    edges.push(([u, v], [shared[0], shared[1]]));
                }
            }
        }
        let mut faces = Vec::new();
        for i in 0..planes.len() {
            let on_it: Vec<usize> = (0..vertices.len())
                .filter(|&v| at[v].contains(&i))
                .collect();
            match on_it.len() {
                0 => {}
                1 | 2 => return None,
                _ => faces.push((i, on_it)),
            }
        }
        // Euler: a closed simple polytope.
        if vertices.len() + faces.len() != edges.len() + 2 || faces.len() < 4 {
            return None;
        }
        Some(Polytope {
            planes,
            vertices,
            at,
            edges,
            faces,
            size,
        })
    }

    /// A random polytope: 5 to 10 random planes at 0.5 to 1 times `radius` from `center`.
    pub fn random(r: &mut SplitMix64, center: DVec3, radius: f64) -> Polytope {
        loop {
            let k = 5 + r.next_u64() % 6;
            let planes = (0..k)
                .map(|_| {
                    let n = unit(r);
                    HalfSpace {
                        n,
                        d: n.dot(center) + radius * (0.5 + 0.5 * r.unit()),
                    }
                })
                .collect();
            if let Some(p) = Polytope::new(planes) {
                return p;
            }
        }
    }

    /// The polytope rotated about the origin by `q`, then translated by `t`.
    pub fn moved(&self, q: DQuat, t: DVec3) -> Option<Polytope> {
        let planes = self
            .planes
            .iter()
            .map(|h| {
                let n = q * h.n;
                HalfSpace {
                    n,
                    d: h.d + n.dot(t),
                }
            })
            .collect();
        Polytope::new(planes)
    }

    /// The engine's block of the same half-spaces.
    pub fn block(&self) -> ConvexBlock {
        let normals: Vec<[f64; 3]> = self.planes.iter().map(|h| h.n.to_array()).collect();
        let offsets: Vec<f64> = self.planes.iter().map(|h| h.d).collect();
        ConvexBlock::from_planes(&normals, &offsets).expect("a valid polytope")
    }

    fn face_points(&self, f: usize) -> Vec<DVec3> {
        self.faces[f].1.iter().map(|&v| self.vertices[v]).collect()
    }
}

/// Whether the half-spaces bound a region: no direction `u` with `n_i · u <= 0` for all `i`.
/// Such a recession cone, if any, has an extreme ray on the line of two planes' normals'
/// cross product.
fn bounded(planes: &[HalfSpace]) -> bool {
    for i in 0..planes.len() {
        for j in i + 1..planes.len() {
            let c = planes[i].n.cross(planes[j].n);
            if c.length() < 1e-9 {
                continue;
            }
            let c = c.normalize();
            for u in [c, -c] {
                if planes.iter().all(|h| h.n.dot(u) <= 1e-9) {
                    return false;
                }
            }
        }
    }
    planes.len() >= 4
}

fn bbox_diagonal(points: &[DVec3]) -> f64 {
    let lo = points
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |a, &p| a.min(p));
    let hi = points
        .iter()
        .fold(DVec3::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
    (hi - lo).length()
}

/// A random unit vector.
pub fn unit(r: &mut SplitMix64) -> DVec3 {
    loop {
        let v = DVec3::new(r.symmetric(1.0), r.symmetric(1.0), r.symmetric(1.0));
        if v.length() > 0.2 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A random rotation.
pub fn rotation(r: &mut SplitMix64) -> DQuat {
    DQuat::from_axis_angle(unit(r), std::f64::consts::PI * r.symmetric(1.0))
}

/// The planes of A and of B, each moved out by `widen` (negative: in).
fn both(a: &Polytope, b: &Polytope, widen: f64) -> Vec<HalfSpace> {
    a.planes
        .iter()
        .chain(&b.planes)
        .map(|h| h.offset(widen))
        .collect()
}

/// Whether A and B, each moved out by `widen` (in, if negative), meet.
pub fn meet_widened(a: &Polytope, b: &Polytope, widen: f64) -> bool {
    let scale = a.size.min(b.size);
    !enumerate(&both(a, b, widen), 1e-13 * scale).is_empty()
}

/// What the reference says of a pair that touches.
#[derive(Clone, Debug, PartialEq)]
pub struct Touch {
    /// Dimension of A ∩ B: 0 point, 1 segment, 2 polygon.
    pub dim: usize,
    /// Dimension of the smallest face of A, of B, holding A ∩ B (0 vertex, 1 edge, 2 face).
    pub feature_dims: [usize; 2],
    /// The planes of A, of B, through A ∩ B.
    pub active: [Vec<usize>; 2],
    /// The vertices of A ∩ B (widened by a hair).
    pub points: Vec<DVec3>,
}

impl Touch {
    /// The contact type of these dimensions.
    pub fn kind(&self) -> ContactType {
        use ContactType::*;
        let [fa, fb] = self.feature_dims;
        let kind = match (fa.min(fb), fa.max(fb)) {
            (0, 0) => VertexVertex,
            (0, 1) => VertexEdge,
            (0, _) => VertexFace,
            (1, 1) if self.dim == 1 => EdgeEdgeSuperposition,
            (1, 1) => EdgeEdge,
            (1, _) => EdgeFace,
            _ => FaceFace,
        };
        // The set and its features agree by geometry: a point in vertices, a segment along
        // edges or in a face, a polygon in two faces.
        let dim = match kind {
            EdgeEdgeSuperposition | EdgeFace => 1,
            FaceFace => 2,
            _ => 0,
        };
        assert_eq!(
            dim, self.dim,
            "reference: {kind} with a set of dimension {}",
            self.dim
        );
        kind
    }
}

/// Relative thresholds of the reference: distances below `LOW` are zero (rounding), above
/// `HIGH` they are real; between, the case is too close to call and is skipped.
pub const LOW: f64 = 1e-8;
pub const HIGH: f64 = 1e-3;

/// A ∩ B for touching blocks: its dimension and the features that hold it; `Err` with a
/// reason when the blocks do not touch or a distance falls between `LOW` and `HIGH`.
pub fn touch(a: &Polytope, b: &Polytope) -> Result<Touch, String> {
    let scale = a.size.min(b.size);
    let (low, high) = (LOW * scale, HIGH * scale);
    if meet_widened(a, b, -low) {
        return Err("the blocks overlap".into());
    }
    // A ∩ B widened by a hair (1e-10 of the size, far above rounding and far below LOW).
    let points = enumerate(&both(a, b, 1e-10 * scale), 1e-13 * scale);
    if points.is_empty() {
        return Err("the blocks do not touch".into());
    }
    let dim = dimension(&points, low, high)?;
    let mut active = [Vec::new(), Vec::new()];
    let mut feature_dims = [0; 2];
    for (k, p) in [a, b].into_iter().enumerate() {
        for (i, h) in p.planes.iter().enumerate() {
            let far = points
                .iter()
                .map(|&x| h.excess(x).abs())
                .fold(0.0, f64::max);
            if far <= low {
                active[k].push(i);
            } else if far < high {
                return Err(format!(
                    "plane {i} of block {k} at {far:e} from the contact"
                ));
            }
        }
        let normals: Vec<DVec3> = active[k].iter().map(|&i| p.planes[i].n).collect();
        feature_dims[k] = match rank(&normals)? {
            0 => return Err("the contact reaches into a block".into()),
            r => 3 - r,
        };
    }
    Ok(Touch {
        dim,
        feature_dims,
        active,
        points,
    })
}

/// The dimension of a point cloud: 0 if its diameter is below `low`, 1 if it stays within
/// `low` of the line through its two farthest points, 2 within `low` of a plane, else 3.
fn dimension(points: &[DVec3], low: f64, high: f64) -> Result<usize, String> {
    let call = |d: f64, what: &str| -> Result<bool, String> {
        if d <= low {
            Ok(true)
        } else if d >= high {
            Ok(false)
        } else {
            Err(format!("{what} {d:e}"))
        }
    };
    let (mut p, mut q, mut best) = (points[0], points[0], 0.0);
    for &x in points {
        for &y in points {
            if x.distance(y) > best {
                (p, q, best) = (x, y, x.distance(y));
            }
        }
    }
    if call(best, "diameter")? {
        return Ok(0);
    }
    let axis = (q - p).normalize();
    let off_line = |x: DVec3| (x - p).reject_from_normalized(axis).length();
    let (r, width) = points
        .iter()
        .map(|&x| (x, off_line(x)))
        .fold((p, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    if call(width, "width")? {
        return Ok(1);
    }
    let normal = axis.cross(r - p).normalize();
    let thickness = points
        .iter()
        .map(|&x| normal.dot(x - p).abs())
        .fold(0.0, f64::max);
    Ok(if call(thickness, "thickness")? { 2 } else { 3 })
}

/// The rank of a set of unit normals (0 to 3), `Err` when nearly dependent.
fn rank(normals: &[DVec3]) -> Result<usize, String> {
    let clear = |s: f64| -> Result<bool, String> {
        if s <= 1e-9 {
            Ok(false)
        } else if s >= 1e-4 {
            Ok(true)
        } else {
            Err(format!("normals nearly dependent ({s:e})"))
        }
    };
    let Some(&first) = normals.first() else {
        return Ok(0);
    };
    let mut second = None;
    for &n in &normals[1..] {
        if clear(first.cross(n).length())? {
            second = Some(n);
            break;
        }
    }
    let Some(second) = second else {
        return Ok(1);
    };
    let plane = first.cross(second).normalize();
    for &n in normals {
        if clear(plane.dot(n).abs())? {
            return Ok(3);
        }
    }
    Ok(2)
}

/// Whether the engine's feature of `block` is the reference's: the face on the one active
/// plane, the edge on both active planes, the vertex on all of them.
pub fn same_feature(block: &ConvexBlock, feature: Feature, p: &Polytope, active: &[usize]) -> bool {
    let tol = 1e-9 * p.size;
    let on_all = |x: DVec3| active.iter().all(|&i| p.planes[i].excess(x).abs() <= tol);
    match feature {
        Feature::Face(f) => {
            let plane = block.planes()[f as usize];
            active.len() == 1
                && plane.normal.dot(p.planes[active[0]].n) > 1.0 - 1e-12
                && on_all(plane.point)
        }
        Feature::Edge(e) => {
            let [u, v] = block.edges()[e as usize].vertices;
            on_all(block.vertices()[u as usize]) && on_all(block.vertices()[v as usize])
        }
        Feature::Vertex(v) => on_all(block.vertices()[v as usize]),
    }
}

/// Whether an edge of one block leaves the contact at a grazing angle to the other block's
/// planes through it: `0 < max_i n_i · d < sine` for a direction `d` along the edge. Below the
/// rule's sine (docs/tolerance.md, "Lies in": the relative length threshold) the edge lies in
/// the face and the type is one rank higher than the exact one; the properties skip edges
/// within a few times that sine of it, where rounding decides.
pub fn grazing(a: &Polytope, b: &Polytope, t: &Touch, sine: f64) -> bool {
    let scale = a.size.min(b.size);
    let pairs = [(a, b, &t.active[1]), (b, a, &t.active[0])];
    pairs.into_iter().any(|(x, y, active)| {
        x.edges.iter().any(|&([u, v], _)| {
            let (p, q) = (x.vertices[u], x.vertices[v]);
            if !segment_meets(p, q, &y.planes, LOW * scale) {
                return false;
            }
            let d = (q - p).normalize();
            [d, -d].into_iter().any(|d| {
                let m = active
                    .iter()
                    .map(|&i| y.planes[i].n.dot(d))
                    .fold(f64::NEG_INFINITY, f64::max);
                m > 1e-9 && m < sine
            })
        })
    })
}

/// The parameter interval of segment `p q` inside every half-space moved out by `widen`.
fn clip(p: DVec3, q: DVec3, planes: &[HalfSpace], widen: f64) -> Option<[f64; 2]> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for h in planes {
        let (e0, e1) = (h.excess(p) - widen, h.excess(q) - widen);
        match (e0 > 0.0, e1 > 0.0) {
            (true, true) => return None,
            (false, false) => {}
            (true, false) => lo = lo.max(e0 / (e0 - e1)),
            (false, true) => hi = hi.min(e0 / (e0 - e1)),
        }
    }
    (lo <= hi).then_some([lo, hi])
}

fn segment_meets(p: DVec3, q: DVec3, planes: &[HalfSpace], widen: f64) -> bool {
    clip(p, q, planes, widen).is_some()
}

/// The policy's contact rule, naively (docs/tolerance.md): the blocks touch when no face plane
/// of either block has the whole other block farther than `gap` outside it, and an edge of one
/// meets the other with its face planes moved out by `gap` (the paper's penetration edges).
pub fn edges_meet(a: &Polytope, b: &Polytope, gap: f64) -> bool {
    !face_separates(a, b, gap) && paper_edges_meet(a, b, gap)
}

/// Whether a face plane of one block has every vertex of the other farther than `gap`.
pub fn face_separates(a: &Polytope, b: &Polytope, gap: f64) -> bool {
    [(a, b), (b, a)].into_iter().any(|(x, y)| {
        x.planes
            .iter()
            .any(|h| y.vertices.iter().all(|&v| h.excess(v) > gap))
    })
}

/// The paper's rule alone: an edge of one block meets the other with its face planes moved
/// out by `gap`.
pub fn paper_edges_meet(a: &Polytope, b: &Polytope, gap: f64) -> bool {
    [(a, b), (b, a)].into_iter().any(|(x, y)| {
        x.edges
            .iter()
            .any(|&([u, v], _)| segment_meets(x.vertices[u], x.vertices[v], &y.planes, gap))
    })
}

/// The paper's penetration beyond the gap, naively: part of an edge of one block (of positive
/// length) lies deeper than `gap` inside the other.
pub fn edges_deep(a: &Polytope, b: &Polytope, gap: f64) -> bool {
    [(a, b), (b, a)].into_iter().any(|(x, y)| {
        x.edges.iter().any(|&([u, v], _)| {
            clip(x.vertices[u], x.vertices[v], &y.planes, -gap).is_some_and(|[lo, hi]| hi > lo)
        })
    })
}

/// Which feature of a block to bring into contact: 0 a vertex, 1 an edge, 2 a face.
/// Returns a unit normal in the feature's normal cone (strictly inside it), a point of the
/// feature (inside it), and the edge's ends for an edge.
#[allow(clippy::type_complexity)]
fn feature(r: &mut SplitMix64, p: &Polytope, dim: usize) -> (DVec3, DVec3, Option<(DVec3, DVec3)>) {
    let pick = |r: &mut SplitMix64, n: usize| (r.next_u64() % n as u64) as usize;
    let w = |r: &mut SplitMix64| 0.2 + 0.8 * r.unit();
    match dim {
        0 => {
            let v = pick(r, p.vertices.len());
            let n: DVec3 = p.at[v].iter().map(|&i| p.planes[i].n * w(r)).sum();
            (n.normalize(), p.vertices[v], None)
        }
        1 => {
            let ([u, v], [i, j]) = p.edges[pick(r, p.edges.len())];
            let n = (p.planes[i].n * w(r) + p.planes[j].n * w(r)).normalize();
            let (a, b) = (p.vertices[u], p.vertices[v]);
            let at = a + (b - a) * (0.25 + 0.5 * r.unit());
            (n, at, Some((a, b)))
        }
        _ => {
            let f = pick(r, p.faces.len());
            let points = p.face_points(f);
            let weights: Vec<f64> = points.iter().map(|_| w(r)).collect();
            let total: f64 = weights.iter().sum();
            let at = points
                .iter()
                .zip(&weights)
                .map(|(&x, &k)| x * k)
                .sum::<DVec3>()
                / total;
            (p.planes[p.faces[f].0].n, at, None)
        }
    }
}

/// The seven target types: features of A and B (0 vertex, 1 edge, 2 face); the two
/// edge-edge targets differ by the edges' directions (crossing, or parallel and overlapping).
pub const TARGETS: [(ContactType, usize, usize); 7] = [
    (ContactType::VertexVertex, 0, 0),
    (ContactType::VertexEdge, 0, 1),
    (ContactType::EdgeEdge, 1, 1),
    (ContactType::EdgeEdgeSuperposition, 1, 1),
    (ContactType::VertexFace, 0, 2),
    (ContactType::EdgeFace, 1, 2),
    (ContactType::FaceFace, 2, 2),
];

/// A touching placement built for the target type: A around the origin (radius 1), B (radius
/// 0.3 to 2) turned and moved onto it. Returns A, B and the unit normal `n` of the separating
/// plane (from A to B); `None` when B's moved half-spaces are not a clean polytope.
pub fn touching(r: &mut SplitMix64, target: usize) -> Option<(Polytope, Polytope, DVec3)> {
    let (kind, fa, fb) = TARGETS[target];
    let a = Polytope::random(r, DVec3::ZERO, 1.0);
    let radius = 0.3 + 1.7 * r.unit();
    let b = Polytope::random(r, DVec3::ZERO, radius);
    let (n, pa, ea) = feature(r, &a, fa);
    let (m, pb, eb) = feature(r, &b, fb);
    let direction = |e: Option<(DVec3, DVec3)>| e.map(|(s, t)| (t - s).normalize());
    let (da, db) = (direction(ea), direction(eb));
    // Turn m onto -n, then spin about n.
    let turn = DQuat::from_rotation_arc(m, -n);
    let spin = match (kind, da, db) {
        (ContactType::EdgeEdgeSuperposition, Some(da), Some(db)) => {
            // Align B's edge with A's (either sense).
            let db = turn * db;
            let angle = db.cross(da).dot(n).atan2(db.dot(da));
            angle
                + if r.unit() < 0.5 {
                    0.0
                } else {
                    std::f64::consts::PI
                }
        }
        (ContactType::EdgeEdge, Some(da), Some(db)) => {
            // Crossing at 20° to 160°.
            let db = turn * db;
            let angle = db.cross(da).dot(n).atan2(db.dot(da));
            angle + 0.35 + (std::f64::consts::PI - 0.7) * r.unit()
        }
        _ => std::f64::consts::TAU * r.unit(),
    };
    let q = DQuat::from_axis_angle(n, spin) * turn;
    // The point of B's feature that lands on A's: for a superposition, an end of B's edge, so
    // that the edges overlap over part of each.
    let pb = match (kind, eb) {
        (ContactType::EdgeEdgeSuperposition, Some((start, _))) => q * start,
        _ => q * pb,
    };
    let moved = b.moved(q, pa - pb)?;
    Some((a, moved, n))
}
