//! The overlap of two penetrating convex blocks, for soft-contact mechanics: a normal that
//! turns continuously as the blocks move, the depth along it, and the overlap region.
//!
//! In a soft-contact DEM the blocks overlap slightly, and a contact force needs a normal and
//! a depth. The separating-axis minimum (the shortest translation that separates the blocks)
//! is exact but jumps: its direction is a face normal of A, of B or an edge-edge cross
//! product, whichever is shallowest, and two of them trade places as the blocks tilt. Here:
//!
//! * **normal**: the *area vector* of the overlap `I = A ∩ B`. Its boundary is A's surface
//!   inside B (`S_A`) and B's surface inside A (`S_B`); `∫ n dS` over a closed surface is
//!   zero, so `V = ∫_{S_A} n_A dS = -∫_{S_B} n_B dS`, and the normal is `V / |V|` (computed
//!   as the mean of the two integrals). `V` is the gradient of the overlap volume with
//!   respect to a translation of B (moving B by `t` grows the overlap by `-V·t`), so the
//!   normal is the direction in which moving B reduces the overlap fastest. It moves
//!   continuously with the blocks (the pieces of the surfaces inside each other do), weighs
//!   both blocks' faces by their areas in the overlap (no choice between A's and B's face),
//!   and gives the face normal for a vertex or an edge in a face and the cross product of
//!   the two edges for a crossing, as the contact geometry does for touching blocks.
//! * **depth**: how far B must move along the normal to separate from A (then they touch):
//!   where the ray from the origin along the normal leaves the Minkowski difference `A - B`,
//!   exactly, over its support planes (the separating-axis candidates). It is at least the
//!   separating-axis minimum, and at most that minimum over the cosine of the angle between
//!   the two directions.
//! * **region**: the volume and centroid of `I` and, on the *common plane* (normal to the
//!   normal, through the centroid), the convex polygon that `I` projects to, with its area.
//!
//! The separating-axis minimum is given too ([`Overlap::min_translation`]); docs/contact-geometry.md
//! ("Overlapping blocks") gives the reasons and the tests.

use crate::block::ConvexBlock;
use crate::contact_geometry::{convex_polygon, extent, ContactPlane, ContactPoints};
use crate::geometry::DVec3;
use crate::tolerance::Tolerance;

#[cfg(test)]
mod tests;

/// The overlap of two penetrating blocks (see the module docs). Vectors point from A to B.
#[derive(Clone, Debug, PartialEq)]
pub struct Overlap {
    /// Unit normal from A to B: the overlap's area vector, normalised.
    pub normal: DVec3,
    /// The translation of B along [`Overlap::normal`] that separates the blocks (> 0): after
    /// it they touch.
    pub depth: f64,
    /// The shortest translation of B that separates the blocks (the separating-axis
    /// minimum over face normals and edge-edge cross products): its length is the minimum
    /// depth over all directions.
    pub min_translation: DVec3,
    /// Volume of `A ∩ B`.
    pub volume: f64,
    /// Centroid of `A ∩ B`.
    pub centroid: DVec3,
    /// `A ∩ B` projected on the common plane (through the centroid, normal to the normal):
    /// a convex polygon counter-clockwise about the normal, or a segment or a point when it
    /// collapses below the length threshold.
    pub region: ContactPoints,
    /// Area of the projected region (0 for a segment or a point).
    pub area: f64,
}

impl Overlap {
    /// The region's points: the polygon's vertices, a segment's two ends, or one point.
    pub fn points(&self) -> &[DVec3] {
        self.region.as_slice()
    }
}

/// The overlap of `a` and `b` when their interiors overlap; `None` when a separating-axis
/// candidate (a face normal or an edge-edge cross product) shows them apart or touching.
/// `tol` gives the length threshold below which the region's points are merged.
///
/// A pair that [`crate::Detector::detect`] finds penetrating always has an overlap: one of
/// its edges holds a point deeper than the gap inside the other block. For a contact
/// (overlapping by at most the gap) the contact geometry is the one to use.
///
/// ```
/// use penedge::{overlap::overlap, ConvexBlock, Tolerance};
/// let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
/// let b = ConvexBlock::cuboid([0.25, 0.25, 0.99], [0.75, 0.75, 1.99]).unwrap();
/// let o = overlap(&a, &b, &Tolerance::default()).unwrap();
/// assert!((o.normal - glam::DVec3::Z).length() < 1e-12);
/// assert!((o.depth - 0.01).abs() < 1e-12);
/// assert!((o.area - 0.25).abs() < 1e-12 && (o.volume - 0.0025).abs() < 1e-12);
/// ```
pub fn overlap(a: &ConvexBlock, b: &ConvexBlock, tol: &Tolerance) -> Option<Overlap> {
    // Coordinates relative to a point near both blocks keep their accuracy far from the
    // origin; the point is the same for (a, b) and (b, a).
    let r = (a.vertices()[0] + b.vertices()[0]) * 0.5;
    let axes = Axes::new(a, b, r);
    let (min_depth, min_axis) = axes.minimum();
    let overlapping = min_depth > 0.0; // false for NaN too
    if !overlapping {
        return None;
    }
    let region = Region::of(a, b, r);
    let normal = match region.area_vector.try_normalize() {
        Some(n) => n,
        None => min_axis, // no surface inside the other block: only in a deep containment
    };
    let depth = axes.exit(normal);
    let magnitude = a.magnitude().max(b.magnitude());
    let length = tol.at_scale(a.size().min(b.size()), magnitude).length;
    let centroid = region.centroid() + r;
    let plane = ContactPlane::through(centroid, normal, -depth);
    let points: Vec<DVec3> = region.points.iter().map(|&p| p + r).collect();
    let shape = convex_polygon(&points, &plane, length);
    let area = match &shape {
        ContactPoints::Polygon(p) => p.area(),
        _ => 0.0,
    };
    Some(Overlap {
        normal,
        depth,
        min_translation: min_axis * min_depth,
        volume: region.volume,
        centroid,
        region: shape,
        area,
    })
}

/// The separating-axis candidates of a pair with the blocks' extents along them: each
/// axis `u` stands for `u` and `-u`. For a unit `u`, the support of `A - B` is
/// `h(u) = max_A u·x - min_B u·y`, and `A - B` lies in `{z : u·z <= h(u)}`.
struct Axes {
    /// `(u, h(u), h(-u))`.
    axes: Vec<(DVec3, f64, f64)>,
}

impl Axes {
    /// Face normals of both blocks, and the cross products of their edge directions (each
    /// block's directions taken once: parallel edges give the same axis).
    fn new(a: &ConvexBlock, b: &ConvexBlock, r: DVec3) -> Axes {
        let (da, db) = (directions(a), directions(b));
        let faces = a.planes().iter().chain(b.planes()).map(|p| p.normal);
        let crosses = da
            .iter()
            .flat_map(|&u| db.iter().filter_map(move |&v| u.cross(v).try_normalize()));
        let axes = faces
            .chain(crosses)
            .map(|u| {
                let (lo_a, hi_a) = extent(a, u, r);
                let (lo_b, hi_b) = extent(b, u, r);
                (u, hi_a - lo_b, hi_b - lo_a)
            })
            .collect();
        Axes { axes }
    }

    /// The separating-axis minimum: the smallest `h` over the candidates (both signs) and
    /// its direction. Not above 0: a candidate separates or the blocks touch.
    fn minimum(&self) -> (f64, DVec3) {
        self.axes
            .iter()
            .flat_map(|&(u, plus, minus)| [(plus, u), (minus, -u)])
            .fold((f64::INFINITY, DVec3::ZERO), |best, (h, u)| {
                if h < best.0 {
                    (h, u)
                } else {
                    best
                }
            })
    }

    /// Where the ray `t n`, `t >= 0`, leaves `A - B`: the smallest `h(u) / (u·n)` over the
    /// candidates with `u·n > 0`. Every unit `u` gives a bound (`A - B` lies behind its
    /// support plane); the face of `A - B` the ray leaves through is a candidate, so the
    /// bound is reached.
    fn exit(&self, n: DVec3) -> f64 {
        self.axes
            .iter()
            .map(|&(u, plus, minus)| {
                let c = u.dot(n);
                if c > 0.0 {
                    plus / c
                } else if c < 0.0 {
                    minus / -c
                } else {
                    f64::INFINITY
                }
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// A block's edge directions, unit, each parallel family once (within a sine of 1e-12).
fn directions(block: &ConvexBlock) -> Vec<DVec3> {
    let v = block.vertices();
    let mut out: Vec<DVec3> = Vec::new();
    for e in block.edges() {
        let Some(d) = (v[e.vertices[1] as usize] - v[e.vertices[0] as usize]).try_normalize()
        else {
            continue;
        };
        if out.iter().all(|k| k.cross(d).length_squared() > 1e-24) {
            out.push(d);
        }
    }
    out
}

/// The boundary of `A ∩ B` as pieces of the two blocks' faces (relative to `r`): each face
/// of one block clipped by the other block's planes.
struct Region {
    /// `(∫_{S_A} n dS - ∫_{S_B} n dS) / 2`: the two are equal (up to rounding).
    area_vector: DVec3,
    volume: f64,
    /// `∫_I x dV` (relative to `r`).
    moment: DVec3,
    /// The pieces' vertices.
    points: Vec<DVec3>,
}

impl Region {
    fn of(a: &ConvexBlock, b: &ConvexBlock, r: DVec3) -> Region {
        let mut region = Region {
            area_vector: DVec3::ZERO,
            volume: 0.0,
            moment: DVec3::ZERO,
            points: Vec::new(),
        };
        let mut scratch = [Vec::new(), Vec::new()];
        // A point on a plane of the other block counts as inside for A's faces and outside
        // for B's: a face of A lying on a face plane of B (the side faces of two blocks in
        // a row) is counted once, as A's.
        let va = region.add_faces(a, b, r, Inside::Closed, &mut scratch);
        let vb = region.add_faces(b, a, r, Inside::Open, &mut scratch);
        region.area_vector = (va - vb) * 0.5;
        region
    }

    /// The centroid of `I` relative to `r` (the mean of the pieces' points when `I` has no
    /// volume).
    fn centroid(&self) -> DVec3 {
        if self.volume > 0.0 {
            self.moment / self.volume
        } else {
            let n = self.points.len().max(1) as f64;
            self.points.iter().copied().sum::<DVec3>() / n
        }
    }

    /// Adds the pieces of `owner`'s faces inside `other`; returns their area vector.
    fn add_faces(
        &mut self,
        owner: &ConvexBlock,
        other: &ConvexBlock,
        r: DVec3,
        inside: Inside,
        [piece, spare]: &mut [Vec<DVec3>; 2],
    ) -> DVec3 {
        let vertices = owner.vertices();
        let planes: Vec<(DVec3, f64)> = other
            .planes()
            .iter()
            .map(|p| (p.normal, p.normal.dot(p.point - r)))
            .collect();
        let mut area_vector = DVec3::ZERO;
        for face in owner.faces() {
            piece.clear();
            piece.extend(face.iter().map(|&k| vertices[k as usize] - r));
            for &(n, d) in &planes {
                clip(piece, spare, n, d, inside);
                if piece.len() < 3 {
                    break;
                }
            }
            if piece.len() < 3 {
                continue;
            }
            // Fanned from the first vertex: the area vector, and the tetrahedra on the
            // reference point for the volume and its moment (divergence theorem).
            let p0 = piece[0];
            for w in piece[1..].windows(2) {
                let (p1, p2) = (w[0], w[1]);
                area_vector += (p1 - p0).cross(p2 - p0) * 0.5;
                let six_v = p0.dot(p1.cross(p2));
                self.volume += six_v / 6.0;
                self.moment += (p0 + p1 + p2) * (six_v / 24.0);
            }
            self.points.extend_from_slice(piece);
        }
        area_vector
    }
}

/// Whether a point on the clipping plane is kept.
#[derive(Clone, Copy)]
pub(crate) enum Inside {
    /// A point on the plane is kept.
    Closed,
    /// A point on the plane is dropped.
    Open,
}

/// Clips the convex polygon `poly` by the half-space `n·x <= d` (Sutherland-Hodgman).
pub(crate) fn clip(poly: &mut Vec<DVec3>, out: &mut Vec<DVec3>, n: DVec3, d: f64, inside: Inside) {
    let keep = |s: f64| match inside {
        Inside::Closed => s <= 0.0,
        Inside::Open => s < 0.0,
    };
    let s: Vec<f64> = poly.iter().map(|&p| n.dot(p) - d).collect();
    if s.iter().all(|&x| keep(x)) {
        return;
    }
    out.clear();
    for i in 0..poly.len() {
        let j = (i + 1) % poly.len();
        let (p, q, sp, sq) = (poly[i], poly[j], s[i], s[j]);
        if keep(sp) {
            out.push(p);
        }
        if keep(sp) != keep(sq) {
            // The crossing, from the end inside towards the one outside.
            let t = sp / (sp - sq);
            out.push(p + (q - p) * t);
        }
    }
    std::mem::swap(poly, out);
}
