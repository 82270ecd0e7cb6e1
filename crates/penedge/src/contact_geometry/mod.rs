//! Contact geometry for mechanics: normal, contact points or polygon, area, signed distance.
//!
//! Derived for every contact type from the data the classification already has: the
//! features of each block ([`Contact::feature_a`], [`Contact::feature_b`]) and the
//! representative points of the penetration edges (the vertices of A ∩ B, see
//! [`crate::classify`]). Nothing is clipped a second time.
//!
//! Conventions (docs/contact-geometry.md gives the reasons):
//!
//! * **normal**: unit, from A to B (B lies on its positive side). Face normal of the face
//!   for vertex-face and edge-face (negated when the face is B's); `normalize(nA - nB)` for
//!   face-face; the cross product of the two edges for an edge-edge crossing; for
//!   vertex-vertex, vertex-edge and edge-edge superposition, the separating normal closest
//!   to the bisector of the two features' mean outward normals. Swapping A and B gives
//!   exactly the opposite normal. Should the distance along that normal be a depth beyond
//!   the gap (features lumped by a coarse length threshold), the most separating of the
//!   features' separating-axis candidates is used instead.
//! * **distance**: `min_B n·y - max_A n·x` over the blocks' vertices: the gap (positive)
//!   or the depth (negative) along the normal. Moving B by `t n` adds `t`.
//! * **points**: on the *contact plane*, the plane normal to `n` halfway between the two
//!   blocks: one point, the two ends of a segment (edge-face, edge-edge superposition), or
//!   the convex polygon of a face-face contact, counter-clockwise about `n`.

mod distance;
mod normal;
mod points;
mod polygon;

pub(crate) use distance::extent;
pub use distance::ContactPlane;
pub(crate) use polygon::convex_polygon;

use crate::block::ConvexBlock;
use crate::classify::{Contact, PairResult};
use crate::contact::Detector;
use crate::geometry::DVec3;
use crate::tolerance::Thresholds;

pub(crate) use normal::cone_rays;

/// Where the contact forces act: what A ∩ B reduces to on the contact plane.
#[derive(Clone, Debug, PartialEq)]
pub enum ContactPoints {
    /// One point (vertex-vertex, vertex-edge, edge-edge crossing, vertex-face).
    Point(DVec3),
    /// The two ends of a segment (edge-face, edge-edge superposition).
    Segment([DVec3; 2]),
    /// A convex polygon (face-face).
    Polygon(ContactPolygon),
}

/// A convex polygon with at least three vertices, counter-clockwise about the contact
/// normal, no two vertices within the length threshold, none on the chord of its neighbours.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPolygon {
    vertices: Vec<DVec3>,
    area: f64,
}

impl ContactPolygon {
    /// The vertices, counter-clockwise about the contact normal.
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// The area.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// A polygon of the given vertices and area (checked by its maker).
    pub(crate) fn from_parts(vertices: Vec<DVec3>, area: f64) -> Self {
        ContactPolygon { vertices, area }
    }
}

impl ContactPoints {
    /// The points: one, two (segment ends) or the polygon's vertices.
    pub fn as_slice(&self) -> &[DVec3] {
        match self {
            ContactPoints::Point(p) => std::slice::from_ref(p),
            ContactPoints::Segment(s) => s,
            ContactPoints::Polygon(p) => p.vertices(),
        }
    }
}

/// The geometry of one contact (see the module docs for the conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactGeometry {
    plane: ContactPlane,
    points: ContactPoints,
}

impl ContactGeometry {
    /// Unit normal from A to B.
    pub fn normal(&self) -> DVec3 {
        self.plane.normal()
    }

    /// Signed distance along the normal: gap (> 0) when apart, depth (< 0) when overlapping.
    pub fn distance(&self) -> f64 {
        self.plane.distance()
    }

    /// The contact plane: normal to the contact normal, halfway between the blocks.
    pub fn plane(&self) -> &ContactPlane {
        &self.plane
    }

    /// The contact points as one point, a segment or a polygon.
    pub fn shape(&self) -> &ContactPoints {
        &self.points
    }

    /// The contact points: one, the two ends of a segment, or the polygon's vertices.
    pub fn points(&self) -> &[DVec3] {
        self.points.as_slice()
    }

    /// The contact points, taken out of the geometry.
    pub(crate) fn into_shape(self) -> ContactPoints {
        self.points
    }

    /// Area of a polygon contact, 0 for a point or a segment.
    ///
    /// It is measured with the gap band: the polygon is the overlap of the two faces with the
    /// blocks widened by the detection gap `g` (docs/contact-geometry.md, "Accuracy and
    /// deviations"; docs/tolerance.md), so it can exceed the faces' exact overlap by about
    /// `g` along its edges (`g / sin α` where faces meet at an angle α): an exact 0.56 m²
    /// overlap reads 0.5614 at a gap of 1e-3.
    pub fn area(&self) -> f64 {
        match &self.points {
            ContactPoints::Polygon(p) => p.area(),
            _ => 0.0,
        }
    }
}

impl Detector {
    /// Detects and classifies the contact of `a` and `b` ([`Detector::detect`]) and, for a
    /// contact, computes its geometry from the same penetration edges.
    ///
    /// ```
    /// use penedge::{ConvexBlock, Detector, Tolerance};
    /// let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    /// let b = ConvexBlock::cuboid([0.5, 0.5, 1.0], [1.5, 1.5, 2.0]).unwrap();
    /// let (_, geometry) = Detector::new(Tolerance::default()).detect_with_geometry(&a, &b);
    /// let g = geometry.unwrap();
    /// assert_eq!(g.normal(), glam::DVec3::Z);
    /// assert_eq!(g.points().len(), 4);
    /// assert!((g.area() - 0.25).abs() < 1e-12 && g.distance().abs() < 1e-12);
    /// ```
    pub fn detect_with_geometry(
        &mut self,
        a: &ConvexBlock,
        b: &ConvexBlock,
    ) -> (PairResult, Option<ContactGeometry>) {
        let result = self.detect(a, b);
        let geometry = match &result {
            PairResult::Contact(contact) => {
                let th = self.thresholds(a, b);
                // A face-face polygon is the overlap of the faces widened by the gap: the
                // pieces as clipped, the gap's band included (docs/tolerance.md, "Lies in").
                let widened = contact.kind == crate::classify::ContactType::FaceFace;
                Some(contact_geometry(
                    a,
                    b,
                    contact,
                    self.representative_points(a, b, widened),
                    th,
                ))
            }
            _ => None,
        };
        (result, geometry)
    }
}

/// The geometry of a contact of `a` and `b`, from its features and the representative
/// points of its penetration edges.
fn contact_geometry(
    a: &ConvexBlock,
    b: &ConvexBlock,
    contact: &Contact,
    representative: &[DVec3],
    th: Thresholds,
) -> ContactGeometry {
    let mut plane = ContactPlane::between(a, b, normal::contact_normal(a, b, contact, th));
    if plane.distance() < -th.gap {
        // Features found within a coarse length threshold can be off the true contact:
        // keep a plane that separates the blocks to within the gap if one exists.
        plane = ContactPlane::between(a, b, normal::most_separating(a, b, contact, plane.normal()));
    }
    let points = points::contact_points(a, b, contact, representative, &plane, th.length);
    ContactGeometry { plane, points }
}
