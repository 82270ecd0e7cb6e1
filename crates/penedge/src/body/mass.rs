//! Mass properties of polyhedra of uniform unit density: volume, centroid and inertia tensor,
//! exact up to rounding, by the divergence theorem.
//!
//! Each face is fanned into triangles from its first vertex; each triangle and a common apex
//! make a (signed) tetrahedron, and the integrals over the block are the sums over the
//! tetrahedra. For a tetrahedron with vertices `v0 .. v3` and volume `V`:
//!
//! ```text
//! ∫ x dV     = V (v0 + v1 + v2 + v3) / 4
//! ∫ x xᵀ dV  = V / 20 (Σ vᵢ vᵢᵀ + (Σ vᵢ)(Σ vᵢ)ᵀ)
//! ```
//!
//! The apex is the block's first vertex and every coordinate is taken relative to it, so the
//! sums keep their accuracy far from the origin (mine-grid coordinates). The inertia tensor
//! about the centroid is `I = tr(S) 1 - S`, with `S = ∫ (x - c)(x - c)ᵀ dV`.

use crate::block::ConvexBlock;
use crate::geometry::DVec3;
use glam::{DMat3, DQuat};

/// Volume, centroid and inertia of a solid of unit density (multiply the volume and the
/// inertia by the density for mass and moments of inertia).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Volume (the mass at unit density).
    pub volume: f64,
    /// Centroid (centre of mass at uniform density), in the block's coordinates.
    pub centroid: DVec3,
    /// Inertia tensor about the centroid, axes of the block's coordinates, per unit density:
    /// `I = ∫ (|r|² 1 - r rᵀ) dV`, `r = x - centroid`.
    pub inertia: DMat3,
}

/// Principal moments and axes of an inertia tensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principal {
    /// Principal moments, ascending.
    pub moments: DVec3,
    /// The rotation whose columns (as a matrix) are the principal axes, in the order of
    /// `moments`, right-handed: it maps the principal frame to the block's frame.
    pub axes: DQuat,
}

/// Sums of a solid's integrals relative to an origin: volume, first and second moments.
#[derive(Clone, Copy, Debug)]
struct Moments {
    volume: f64,
    first: DVec3,
    second: DMat3,
}

impl Default for Moments {
    /// Zero (glam's default matrix is the identity, not zero).
    fn default() -> Self {
        Moments {
            volume: 0.0,
            first: DVec3::ZERO,
            second: DMat3::ZERO,
        }
    }
}

impl Moments {
    /// The integrals over `block`, in coordinates relative to `origin`.
    fn of_block(block: &ConvexBlock, origin: DVec3) -> Moments {
        let v = block.vertices();
        let mut m = Moments::default();
        for face in block.faces() {
            let a = v[face[0] as usize] - origin;
            for w in face[1..].windows(2) {
                let (b, c) = (v[w[0] as usize] - origin, v[w[1] as usize] - origin);
                m.add_tetrahedron(a, b, c);
            }
        }
        m
    }

    /// Adds the tetrahedron (0, a, b, c), signed by its orientation.
    fn add_tetrahedron(&mut self, a: DVec3, b: DVec3, c: DVec3) {
        let volume = a.dot(b.cross(c)) / 6.0;
        let sum = a + b + c;
        self.volume += volume;
        self.first += volume / 4.0 * sum;
        let squares = outer(a, a) + outer(b, b) + outer(c, c) + outer(sum, sum);
        self.second += squares * (volume / 20.0);
    }

    /// The same integrals relative to an origin shifted by `-shift` (`x' = x + shift`).
    fn shifted(&self, shift: DVec3) -> Moments {
        Moments {
            volume: self.volume,
            first: self.first + self.volume * shift,
            second: self.second
                + outer(self.first, shift)
                + outer(shift, self.first)
                + outer(shift, shift) * self.volume,
        }
    }

    fn into_properties(self, origin: DVec3) -> MassProperties {
        let c = self.first / self.volume;
        let spread = self.second - outer(c, c) * self.volume;
        let trace = spread.x_axis.x + spread.y_axis.y + spread.z_axis.z;
        MassProperties {
            volume: self.volume,
            centroid: origin + c,
            inertia: DMat3::from_diagonal(DVec3::splat(trace)) - spread,
        }
    }
}

/// The matrix `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

impl MassProperties {
    /// The mass properties of a convex block.
    pub fn of_block(block: &ConvexBlock) -> MassProperties {
        let origin = block.vertices()[0];
        Moments::of_block(block, origin).into_properties(origin)
    }

    /// The mass properties of the union of `parts`, solids that do not overlap (convex parts
    /// of one body, glued along faces). `None` for no parts.
    pub fn of_parts(parts: &[ConvexBlock]) -> Option<MassProperties> {
        let origin = parts.first()?.vertices()[0];
        let mut sum = Moments::default();
        for part in parts {
            let own = part.vertices()[0];
            let m = Moments::of_block(part, own).shifted(own - origin);
            sum.volume += m.volume;
            sum.first += m.first;
            sum.second += m.second;
        }
        Some(sum.into_properties(origin))
    }

    /// Principal moments (ascending) and axes of the inertia tensor.
    pub fn principal(&self) -> Principal {
        principal_axes(&self.inertia)
    }
}

/// Eigenvalues (ascending) and eigenvectors of a symmetric 3 × 3 matrix, by cyclic Jacobi
/// rotations: accurate to rounding for symmetric matrices, including repeated eigenvalues
/// (a cube's inertia), where any orthonormal axes of the repeated space are returned.
///
/// Written here rather than taken from nalgebra: it is the only linear algebra the crate
/// needs beyond glam's, and 40 lines of a textbook method.
pub fn principal_axes(m: &DMat3) -> Principal {
    let mut a = m.to_cols_array_2d(); // a[col][row]; symmetric, so the same as [row][col]
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // columns
    let scale = a.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    for _sweep in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= f64::EPSILON * f64::EPSILON * scale || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            jacobi_rotate(&mut a, &mut v, p, q);
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let column = |k: usize| DVec3::from_array(v[order[k]]);
    let (x, y) = (column(0), column(1));
    let axes = DMat3::from_cols(x, y, x.cross(y)); // right-handed
    Principal {
        moments: DVec3::new(
            a[order[0]][order[0]],
            a[order[1]][order[1]],
            a[order[2]][order[2]],
        ),
        axes: DQuat::from_mat3(&axes).normalize(),
    }
}

/// One Jacobi rotation in the plane (p, q), zeroing `a[p][q]` (Golub and Van Loan, 8.5):
/// `a ← Jᵀ a J`, `v ← v J`, with `a[row][col]` and `v[col]` the eigenvector columns.
fn jacobi_rotate(a: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize) {
    if a[p][q] == 0.0 {
        return;
    }
    let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
    let t = if theta == 0.0 { 1.0 } else { t };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    for row in a.iter_mut() {
        let (kp, kq) = (row[p], row[q]);
        row[p] = c * kp - s * kq;
        row[q] = s * kp + c * kq;
    }
    rotate_pair(a, p, q, c, s);
    rotate_pair(v, p, q, c, s);
    // Zero by construction; set exactly so that the sweeps end.
    a[p][q] = 0.0;
    a[q][p] = 0.0;
}

/// `(m[p], m[q]) ← (c m[p] - s m[q], s m[p] + c m[q])`.
fn rotate_pair(m: &mut [[f64; 3]; 3], p: usize, q: usize, c: f64, s: f64) {
    let (mp, mq) = (m[p], m[q]);
    m[p] = std::array::from_fn(|k| c * mp[k] - s * mq[k]);
    m[q] = std::array::from_fn(|k| s * mp[k] + c * mq[k]);
}

#[cfg(test)]
mod tests;
