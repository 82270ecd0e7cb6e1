//! Small geometric primitives: points, planes, bounding boxes.

pub use glam::DVec3;

/// An oriented plane through `point` with unit `normal`.
///
/// The signed distance of `x` is `normal · (x - point)`: positive on the outer side.
/// Keeping a point of the plane rather than an offset keeps the distance accurate for
/// blocks far from the origin (mine-grid coordinates): the subtraction of two nearby
/// coordinates is exact up to one rounding of the (small) difference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal, pointing outwards.
    pub normal: DVec3,
    /// A point on the plane.
    pub point: DVec3,
}

impl Plane {
    /// Signed distance of `x` (positive outside).
    #[inline]
    pub fn distance(&self, x: DVec3) -> f64 {
        self.normal.dot(x - self.point)
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: DVec3,
    /// Upper corner.
    pub max: DVec3,
}

impl Aabb {
    /// The bounding box of a non-empty set of points.
    pub fn of_points(points: &[DVec3]) -> Aabb {
        let mut b = Aabb {
            min: DVec3::splat(f64::INFINITY),
            max: DVec3::splat(f64::NEG_INFINITY),
        };
        for &p in points {
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
        b
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }

    /// The largest absolute coordinate of the box.
    pub fn magnitude(&self) -> f64 {
        self.min.abs().max(self.max.abs()).max_element()
    }

    /// Whether the boxes, each widened by `margin`, overlap (touching counts).
    pub fn overlaps(&self, other: &Aabb, margin: f64) -> bool {
        (self.min - margin).cmple(other.max + margin).all()
            && (other.min - margin).cmple(self.max + margin).all()
    }
}

/// Newell's normal (not normalised) of a polygon; its length is twice the polygon's area.
pub fn newell_normal(points: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let first = points.clone().next().unwrap_or(DVec3::ZERO);
    let mut n = DVec3::ZERO;
    let local: Vec<DVec3> = points.map(|p| p - first).collect();
    for i in 0..local.len() {
        let a = local[i];
        let b = local[(i + 1) % local.len()];
        n += a.cross(b);
    }
    n
}

/// A number as people write it in messages: plain (`120`, `0.5`, `NaN`) unless very large or
/// very small, then in exponent form (`1e300`, not 301 digits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Short(pub(crate) f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-5..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}
