//! Topographic surfaces: the rock below a triangulated height field kept, the air above it
//! removed (see `docs/generation.md`, "Slopes and topography").
//!
//! The air above a height field is the union of the vertical prisms above its triangles, up
//! to a level above the rock: each prism is convex (the triangle's plane below, three
//! vertical sides, a flat lid), the prisms of neighbouring triangles share a vertical side,
//! and when no two triangles overlap seen from above, no two prisms overlap. So the rock left
//! is exactly the rock below the surface, and the excavation code that removes tunnels
//! removes it. This needs the surface to be a height field over the whole rock: every
//! triangle seen from above has an area (no vertical or overhanging triangle), no two
//! overlap (no fold), and together they cover the rock's horizontal footprint (no hole).
//! Each is checked, and an error names what is wrong and where.

use super::error::{Problem, SpecError};
use super::excavation::{cross, signed_area};
use super::slope::Extent;
use crate::block::ConvexBlock;
use crate::geometry::DVec3;

/// A triangulated surface, read from a file ([`crate::io::surface`]) or built from a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// The triangles, each three points `[x, y, z]` (either sense).
    pub triangles: Vec<[[f64; 3]; 3]>,
    /// Where it comes from (a file name), for messages.
    pub source: String,
}

/// The most triangles of a surface.
pub const MAX_TRIANGLES: usize = 2_000_000;

impl Surface {
    /// A surface of triangles.
    pub fn new(triangles: Vec<[[f64; 3]; 3]>, source: impl Into<String>) -> Surface {
        Surface {
            triangles,
            source: source.into(),
        }
    }

    /// The surface moved by `offset` (added to every point): a surface in map coordinates
    /// (UTM eastings and northings) brought to the model's.
    pub fn shifted(mut self, offset: [f64; 3]) -> Surface {
        for p in self.triangles.iter_mut().flatten() {
            for (c, d) in p.iter_mut().zip(offset) {
                *c += d;
            }
        }
        self
    }

    /// The surface of a grid of elevations: `z[j * xs.len() + i]` at `(xs[i], ys[j])`, both
    /// increasing. Each cell is cut into two triangles along its diagonal from the
    /// `(xs[i], ys[j])` corner to the `(xs[i + 1], ys[j + 1])` corner.
    pub fn from_grid(xs: &[f64], ys: &[f64], z: &[f64], source: impl Into<String>) -> Surface {
        let nx = xs.len();
        let at = |i: usize, j: usize| [xs[i], ys[j], z[j * nx + i]];
        let mut triangles = Vec::with_capacity(2 * nx.saturating_sub(1) * ys.len());
        for j in 0..ys.len().saturating_sub(1) {
            for i in 0..nx.saturating_sub(1) {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        Surface::new(triangles, source)
    }
}

/// A triangle seen from above, counter-clockwise, with its elevations.
#[derive(Clone, Copy)]
struct Flat {
    p: [[f64; 2]; 3],
    z: [f64; 3],
}

impl Flat {
    fn aabb(&self) -> ([f64; 2], [f64; 2]) {
        let lo = [0, 1].map(|k| self.p[0][k].min(self.p[1][k]).min(self.p[2][k]));
        let hi = [0, 1].map(|k| self.p[0][k].max(self.p[1][k]).max(self.p[2][k]));
        (lo, hi)
    }

    /// The elevation of the triangle's plane above `q`.
    fn z_at(&self, q: [f64; 2]) -> f64 {
        let area = cross(self.p[0], self.p[1], self.p[2]);
        let w = [
            cross(self.p[1], self.p[2], q),
            cross(self.p[2], self.p[0], q),
            cross(self.p[0], self.p[1], q),
        ];
        (w[0] * self.z[0] + w[1] * self.z[1] + w[2] * self.z[2]) / area
    }
}

/// The convex regions of the air above `surface` over the rock of `extent`; errors name
/// `{prefix}.file`.
pub(super) fn regions(
    prefix: &str,
    surface: &Surface,
    extent: &Extent,
) -> Result<Vec<ConvexBlock>, SpecError> {
    let field = format!("{prefix}.file");
    let bad = |msg: String| {
        SpecError::new(
            field.as_str(),
            Problem::Invalid(format!("{}: {msg}", surface.source)),
        )
    };
    let n = surface.triangles.len();
    if n == 0 {
        return Err(bad("the surface has no triangles".into()));
    }
    if n > MAX_TRIANGLES {
        return Err(bad(format!(
            "the surface has {n} triangles, more than the limit of {MAX_TRIANGLES}"
        )));
    }
    let flats = flatten(surface).map_err(bad)?;
    if let Some((i, j)) = overlapping_pair(&flats) {
        let c = |k: usize| {
            let t = &flats[k].p;
            [
                (t[0][0] + t[1][0] + t[2][0]) / 3.0,
                (t[0][1] + t[1][1] + t[2][1]) / 3.0,
            ]
        };
        return Err(bad(format!(
            "triangles {i} and {j} overlap seen from above (near x = {}, y = {}): the surface \
             folds over itself (an overhang or a fold) or repeats a part of itself; a \
             topographic surface must be a height field, one elevation over each point",
            c(i)[0],
            c(i)[1]
        )));
    }
    // Coverage of the rock's footprint, and the surface's range over it.
    let footprint = &extent.footprint;
    let area = signed_area(footprint);
    let (mut covered, mut low, mut high) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
    let mut inside = Vec::with_capacity(n);
    for (k, t) in flats.iter().enumerate() {
        let clipped = clip(&t.p, footprint);
        if clipped.len() < 3 {
            continue;
        }
        let a = signed_area(&clipped);
        if a <= 0.0 {
            continue;
        }
        covered += a;
        for q in &clipped {
            let z = t.z_at(*q);
            low = low.min(z);
            high = high.max(z);
        }
        inside.push(k);
    }
    if covered < area * (1.0 - 1e-9) {
        let corner = footprint
            .iter()
            .find(|q| !flats.iter().any(|t| contains(&t.p, **q)))
            .map(|q| {
                format!(
                    "; the rock's corner x = {}, y = {} is not covered",
                    q[0], q[1]
                )
            })
            .unwrap_or_default();
        return Err(bad(format!(
            "the surface does not cover the rock: {} of the {} of the rock's horizontal \
             footprint has no surface above it (a hole in the surface, or a surface smaller \
             than the rock){corner}",
            area - covered,
            area
        )));
    }
    let (bottom, top) = (extent.aabb.min.z, extent.aabb.max.z);
    if low >= top {
        return Err(bad(format!(
            "the surface lies entirely above the rock (its lowest point over the rock is at \
             z = {low}, the rock's top at z = {top}): it removes nothing"
        )));
    }
    if high <= bottom {
        return Err(bad(format!(
            "the surface lies entirely below the rock (its highest point over the rock is at \
             z = {high}, the rock's bottom at z = {bottom}): it would remove all of it"
        )));
    }
    let lid = top.max(high) + extent.margin();
    inside
        .into_iter()
        .filter(|&k| flats[k].z.iter().cloned().fold(f64::INFINITY, f64::min) < top)
        .map(|k| prism(&flats[k], lid))
        .collect::<Result<_, _>>()
        .map_err(|e| SpecError::new(prefix, Problem::Invalid(e.to_string())))
}

/// The triangles seen from above, counter-clockwise; an error names a triangle that is not
/// finite or has no area seen from above (vertical, or degenerate).
fn flatten(surface: &Surface) -> Result<Vec<Flat>, String> {
    let scale = surface
        .triangles
        .iter()
        .flatten()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let mut flats = Vec::with_capacity(surface.triangles.len());
    for (k, t) in surface.triangles.iter().enumerate() {
        if t.iter().flatten().any(|x| !x.is_finite()) {
            return Err(format!(
                "triangle {k} has a coordinate that is not a number"
            ));
        }
        let mut p = t.map(|q| [q[0], q[1]]);
        let mut z = t.map(|q| q[2]);
        let twice = cross(p[0], p[1], p[2]);
        let corner = |q: [f64; 3]| DVec3::from_array(q);
        let normal = (corner(t[1]) - corner(t[0])).cross(corner(t[2]) - corner(t[0]));
        let edge = (0..3)
            .map(|e| (corner(t[e]) - corner(t[(e + 1) % 3])).length())
            .fold(0.0f64, f64::max);
        if !twice.is_finite() || !normal.is_finite() || !edge.is_finite() {
            return Err(format!(
                "triangle {k} is too large: its size overflows (coordinates near 1e308?)"
            ));
        }
        let corners = format!("(corners {:?}, {:?}, {:?})", t[0], t[1], t[2]);
        if normal.length() <= 1e-14 * edge * edge || normal.length() <= 1e-24 * scale * scale {
            return Err(format!(
                "triangle {k} {corners} has no area: its corners are on one line"
            ));
        }
        // Steeper than 90 - 6e-8 degrees: vertical.
        if twice.abs() <= 1e-9 * normal.length() {
            return Err(format!(
                "triangle {k} {corners} is vertical: it has no area seen from above; a \
                 topographic surface must be a height field, with no vertical or overhanging \
                 part"
            ));
        }
        if twice < 0.0 {
            p.swap(1, 2);
            z.swap(1, 2);
        }
        flats.push(Flat { p, z });
    }
    Ok(flats)
}

/// Two triangles whose interiors overlap seen from above (the first pair found), by
/// separating axes, the triangles bucketed on a grid so that only neighbours are compared.
fn overlapping_pair(flats: &[Flat]) -> Option<(usize, usize)> {
    let boxes: Vec<_> = flats.iter().map(Flat::aabb).collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (a, b) in &boxes {
        for k in 0..2 {
            lo[k] = lo[k].min(a[k]);
            hi[k] = hi[k].max(b[k]);
        }
    }
    let span = [hi[0] - lo[0], hi[1] - lo[1]];
    // Rounding only: neighbours share their corners bit for bit (grids, OBJ indices, STL's
    // repeated floats), and the distance of a shared corner to a shared edge is then 0.
    let tol = 1e-12
        * lo[0]
            .abs()
            .max(lo[1].abs())
            .max(hi[0].abs())
            .max(hi[1].abs());
    // Cells of about twice the mean triangle's size: at most 2048 along each axis, so a
    // surface of extreme proportions (or coordinates) makes a bounded grid.
    let side = 2.0 * ((span[0] * span[1]) / flats.len() as f64).sqrt();
    let count = |k: usize| {
        let c = (span[k] / side).ceil();
        if c.is_finite() {
            c.clamp(1.0, 2048.0) as usize
        } else {
            1
        }
    };
    let (nx, ny) = (count(0), count(1));
    let width = [0, 1].map(|k| {
        let n = [nx, ny][k] as f64;
        if span[k] > 0.0 {
            span[k] / n
        } else {
            1.0
        }
    });
    let cells = |k: usize, x: f64| {
        let c = ((x - lo[k]) / width[k]).floor();
        // NaN (from coordinates too large to subtract) goes to cell 0.
        let last = [nx, ny][k] - 1;
        if c >= 0.0 {
            (c.min(last as f64)) as usize
        } else {
            0
        }
    };
    let buckets = nx * ny;
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); buckets];
    let index = |i: usize, j: usize| j * nx + i;
    for (k, (a, b)) in boxes.iter().enumerate() {
        for j in cells(1, a[1])..=cells(1, b[1]) {
            for i in cells(0, a[0])..=cells(0, b[0]) {
                let at = index(i, j);
                grid[at].push(k as u32);
            }
        }
    }
    for (at, bucket) in grid.iter().enumerate() {
        for (x, &i) in bucket.iter().enumerate() {
            for &j in &bucket[x + 1..] {
                let (i, j) = (i as usize, j as usize);
                // Each pair once: in the cell of the low corner of their boxes' overlap.
                let (a, b) = (boxes[i], boxes[j]);
                let corner = [a.0[0].max(b.0[0]), a.0[1].max(b.0[1])];
                if index(cells(0, corner[0]), cells(1, corner[1])) != at {
                    continue;
                }
                if interiors_overlap(&flats[i].p, &flats[j].p, tol) {
                    return Some((i.min(j), i.max(j)));
                }
            }
        }
    }
    None
}

/// Whether two counter-clockwise triangles overlap by more than `tol` across every edge
/// (triangles that share an edge or a corner do not).
fn interiors_overlap(a: &[[f64; 2]; 3], b: &[[f64; 2]; 3], tol: f64) -> bool {
    for (s, t) in [(a, b), (b, a)] {
        for e in 0..3 {
            let (p, q) = (s[e], s[(e + 1) % 3]);
            let n = [q[1] - p[1], p[0] - q[0]];
            let len = (n[0] * n[0] + n[1] * n[1]).sqrt();
            // Outward normal of edge e of s: t is separated if it lies beyond that edge.
            let least = t
                .iter()
                .map(|r| (n[0] * (r[0] - p[0]) + n[1] * (r[1] - p[1])) / len)
                .fold(f64::INFINITY, f64::min);
            if least >= -tol {
                return false;
            }
        }
    }
    true
}

/// Whether `q` lies in the closed counter-clockwise triangle `t`, within rounding.
fn contains(t: &[[f64; 2]; 3], q: [f64; 2]) -> bool {
    let scale = t.iter().fold(q[0].abs().max(q[1].abs()), |m, p| {
        m.max(p[0].abs()).max(p[1].abs())
    });
    let tol = -1e-12 * scale * scale;
    (0..3).all(|e| cross(t[e], t[(e + 1) % 3], q) >= tol)
}

/// A counter-clockwise triangle clipped by a convex counter-clockwise polygon
/// (Sutherland-Hodgman).
fn clip(t: &[[f64; 2]; 3], by: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = t.to_vec();
    for e in 0..by.len() {
        if out.is_empty() {
            break;
        }
        let (a, b) = (by[e], by[(e + 1) % by.len()]);
        let input = std::mem::take(&mut out);
        for k in 0..input.len() {
            let (p, q) = (input[k], input[(k + 1) % input.len()]);
            let (sp, sq) = (cross(a, b, p), cross(a, b, q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let s = sp / (sp - sq);
                out.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
            }
        }
    }
    out
}

/// The air above one triangle up to `lid`: its three vertical sides, its plane below, the
/// lid above.
fn prism(t: &Flat, lid: f64) -> Result<ConvexBlock, crate::BlockError> {
    let at = |k: usize| DVec3::new(t.p[k][0], t.p[k][1], t.z[k]);
    let mut normals = Vec::with_capacity(5);
    let mut offsets = Vec::with_capacity(5);
    for e in 0..3 {
        let (p, q) = (t.p[e], t.p[(e + 1) % 3]);
        let n = DVec3::new(q[1] - p[1], p[0] - q[0], 0.0).normalize();
        normals.push(n.to_array());
        offsets.push(n.x * p[0] + n.y * p[1]);
    }
    let up = (at(1) - at(0)).cross(at(2) - at(0)).normalize();
    normals.push((-up).to_array());
    offsets.push(-up.dot(at(0)));
    normals.push([0.0, 0.0, 1.0]);
    offsets.push(lid);
    ConvexBlock::from_planes(&normals, &offsets)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn extent(min: [f64; 3], max: [f64; 3]) -> Extent {
        Extent::of(&[ConvexBlock::cuboid(min, max).unwrap()]).unwrap()
    }

    fn ramp(nx: usize, ny: usize) -> Surface {
        let xs: Vec<f64> = (0..nx).map(|i| i as f64 * 10.0 / (nx - 1) as f64).collect();
        let ys: Vec<f64> = (0..ny).map(|j| j as f64 * 10.0 / (ny - 1) as f64).collect();
        let z: Vec<f64> = (0..nx * ny)
            .map(|k| 2.0 + 0.3 * xs[k % nx] + 0.1 * ys[k / nx])
            .collect();
        Surface::from_grid(&xs, &ys, &z, "ramp")
    }

    #[test]
    fn the_prisms_above_a_plane_ramp_have_the_volume_above_it() {
        let rock = extent([0.0; 3], [10.0; 3]);
        let regions = regions("t", &ramp(4, 3), &rock).unwrap();
        assert_eq!(regions.len(), 2 * 3 * 2);
        let lid = 10.0 + rock.margin();
        // Above z = 2 + 0.3 x + 0.1 y over 10 x 10: the mean elevation is 2 + 1.5 + 0.5.
        let exact = 100.0 * (lid - 4.0);
        let v: f64 = regions.iter().map(ConvexBlock::volume).sum();
        assert!((v - exact).abs() < 1e-9 * exact, "{v} {exact}");
    }

    #[test]
    fn a_fold_a_hole_and_a_vertical_triangle_are_named() {
        let rock = extent([0.0; 3], [10.0; 3]);
        let mut folded = ramp(3, 3);
        let mut t = folded.triangles[0];
        t.iter_mut().for_each(|p| p[0] += 1.0);
        folded.triangles.push(t);
        let e = regions("x", &folded, &rock).unwrap_err();
        assert_eq!(e.field, "x.file");
        assert!(e.to_string().contains("overlap seen from above"), "{e}");
        let mut holed = ramp(3, 3);
        holed.triangles.remove(3);
        let e = regions("x", &holed, &rock).unwrap_err();
        assert!(
            e.to_string()
                .contains("does not cover the rock: 12.5 of the 100"),
            "{e}"
        );
        let mut wall = ramp(3, 3);
        wall.triangles
            .push([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 5.0]]);
        let e = regions("x", &wall, &rock).unwrap_err();
        assert!(e.to_string().contains("triangle 8 "), "{e}");
        assert!(e.to_string().contains("vertical"), "{e}");
    }

    #[test]
    fn a_surface_above_or_below_the_rock_or_too_small_is_an_error() {
        let high = extent([0.0, 0.0, -10.0], [10.0, 10.0, 1.0]);
        let e = regions("x", &ramp(3, 3), &high).unwrap_err();
        assert!(e.to_string().contains("entirely above the rock"), "{e}");
        let low = extent([0.0, 0.0, 8.0], [10.0, 10.0, 20.0]);
        let e = regions("x", &ramp(3, 3), &low).unwrap_err();
        assert!(e.to_string().contains("entirely below the rock"), "{e}");
        let wide = extent([-1.0, 0.0, 0.0], [10.0, 10.0, 10.0]);
        let e = regions("x", &ramp(3, 3), &wide).unwrap_err();
        assert!(
            e.to_string()
                .contains("does not cover the rock: 10 of the 110"),
            "{e}"
        );
        assert!(e.to_string().contains("corner x = -1, y = 0"), "{e}");
    }

    #[test]
    fn random_triangles_of_any_size_give_regions_or_an_error_never_a_panic() {
        let rock = extent([0.0; 3], [10.0; 3]);
        let mut state = 11u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 11
        };
        let scales = [1e-300, 1e-9, 1.0, 10.0, 1e9, 1e300];
        for round in 0..300 {
            let n = 1 + next() as usize % 12;
            let scale = scales[round % scales.len()];
            let mut coord = || (next() as f64 / (1u64 << 53) as f64 - 0.25) * 14.0 * scale;
            let triangles = (0..n)
                .map(|_| {
                    [
                        [coord(), coord(), coord()],
                        [coord(), coord(), coord()],
                        [coord(), coord(), coord()],
                    ]
                })
                .collect();
            let _ = regions("x", &Surface::new(triangles, "random"), &rock);
        }
        // Two long thin triangles, crossing: a fold, found on a grid of extreme proportions.
        let thin = Surface::new(
            vec![
                [[0.0, 0.0, 5.0], [1e6, 0.0, 5.0], [0.0, 1e-3, 5.0]],
                [[1.0, 0.0, 5.0], [1e6, 1e-3, 5.0], [0.0, 1e-3, 5.0]],
            ],
            "thin",
        );
        let e = regions("x", &thin, &rock).unwrap_err();
        assert!(e.to_string().contains("overlap"), "{e}");
    }

    #[test]
    fn triangles_that_share_an_edge_or_a_corner_do_not_overlap() {
        let a = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let b = [[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let c = [[1.0, 0.0], [2.0, 0.0], [1.0, 1.0]];
        assert!(!interiors_overlap(&a, &b, 1e-12));
        assert!(!interiors_overlap(&a, &c, 1e-12));
        let d = [[0.2, 0.2], [2.0, 0.2], [0.2, 2.0]];
        assert!(interiors_overlap(&a, &d, 1e-12));
        assert!(interiors_overlap(&a, &a, 1e-12));
    }
}
