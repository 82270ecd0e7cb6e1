//! The distance table of a pair: signed distances of one block's vertices to the other
//! block's face planes, computed once per pair and read by every edge.

use crate::block::{ConvexBlock, Quad, MASK_FACES};
use crate::geometry::{DVec3, Plane};
use crate::tolerance::Thresholds;

/// Signed distances of one block's vertices to the other block's face planes, vertex-major:
/// `table[v * row + f]`, with rows of the faces in groups of four (`row = 4 * ceil(F / 4)`),
/// and, when the other block has at most [`MASK_FACES`] faces, three bit masks per vertex
/// ([`VertexMasks`], bit `f` for face `f`): the faces it is outside of (`s > gap`), those it
/// is not deep inside of (`s >= -gap`) and those whose planes pass within the length
/// threshold of it (`|s| <= length`). The first two reject most edges with one `and` (for the
/// clipping and for the deeper-than-the-gap test) and let both visit only the faces that
/// cut an edge; the third gives the classification the faces that hold a vertex.
///
/// Vertex-major, because the masks are wanted per vertex: each vertex's coordinates are
/// broadcast once, its distances to four (eight) planes are one 256-bit (512-bit) vector
/// operation on processors with AVX (AVX-512), chosen at run time ([`Kernel`]), and the
/// comparisons of those distances come out as bits of that vertex's masks. The portable code
/// does the same operations in the same order without fused multiply-adds, so all give the
/// same bits.
/// A face plane with every vertex outside (the `and` of the `outside` masks) separates the
/// pair.
#[derive(Default, Clone, Debug)]
pub(crate) struct DistanceTable {
    table: Vec<f64>,
    row: usize,
    /// Per-vertex masks (when `masked`).
    vertices: Vec<VertexMasks>,
    /// The other block's planes, four at a time, in coordinates local to this block's
    /// origin (scratch, rebuilt per fill).
    planes: Vec<PlaneQuad>,
    masked: bool,
}

/// The masks of one vertex against the other block's faces, bit `f` for face `f` (32
/// bytes: a vertex's masks are found with a shift).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C, align(32))]
pub(crate) struct VertexMasks {
    /// Faces the vertex is outside of, beyond the gap (`s > gap`).
    pub(crate) outside: u64,
    /// Faces the vertex is not deeper than the gap inside of (`s >= -gap`).
    pub(crate) shallow: u64,
    /// Faces whose planes pass within the length threshold of the vertex (`|s| <= length`).
    pub(crate) near: u64,
}

/// Four planes `n · x = offset`, one array per component (a missing plane is `0 · x = ∞`,
/// which every vertex is far inside of).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
struct PlaneQuad {
    nx: [f64; 4],
    ny: [f64; 4],
    nz: [f64; 4],
    offset: [f64; 4],
}

/// The code that fills the tables, chosen once per [`crate::Detector`]: the portable code,
/// or the same operations on 256-bit vectors where the processor has AVX, or on 512-bit
/// vectors (eight planes at once, comparisons into mask registers) where it has AVX-512.
/// All give the same bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kernel {
    /// Plain Rust, vectorised by the compiler for the build's target (SSE2 on x86-64).
    Portable,
    /// AVX intrinsics (x86-64, checked at run time). The vector kernels serve blocks of
    /// up to 16 faces (the usual rock blocks), kept in registers; larger ones take the
    /// portable code.
    #[cfg(target_arch = "x86_64")]
    Avx,
    /// AVX-512 intrinsics (x86-64, checked at run time).
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Default for Kernel {
    fn default() -> Self {
        Kernel::detect()
    }
}

impl Kernel {
    /// The fastest kernel this processor runs.
    pub(crate) fn detect() -> Kernel {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Kernel::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx") {
                return Kernel::Avx;
            }
        }
        Kernel::Portable
    }

    /// Every kernel this processor runs (tests compare them).
    #[cfg(test)]
    pub(crate) fn available() -> Vec<Kernel> {
        let mut kernels = vec![Kernel::Portable];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx") {
                kernels.push(Kernel::Avx);
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                kernels.push(Kernel::Avx512);
            }
        }
        kernels
    }
}

impl DistanceTable {
    /// Fills the table with the distances of `of`'s vertices to `to`'s planes, and the
    /// masks at the thresholds `th`; returns `false` when one plane has every vertex
    /// farther than the gap (separation).
    pub(crate) fn fill(
        &mut self,
        kernel: Kernel,
        of: &ConvexBlock,
        to: &ConvexBlock,
        th: Thresholds,
    ) -> bool {
        let local = of.local();
        let planes = to.planes();
        // Room for the padded last group of four vertices (the vector kernels fill it).
        let rows = 4 * local.quads.len();
        self.masked = planes.len() <= MASK_FACES;
        #[cfg(target_arch = "x86_64")]
        let wide = kernel == Kernel::Avx512 && planes.len() <= 16;
        #[cfg(not(target_arch = "x86_64"))]
        let wide = false;
        self.row = if wide {
            8 * planes.len().div_ceil(8)
        } else {
            4 * planes.len().div_ceil(4)
        };
        let needed = rows * self.row;
        if self.table.len() < needed {
            self.table.resize(needed, 0.0);
        }
        if self.vertices.len() < rows {
            self.vertices.resize(rows, VertexMasks::default());
        }
        let table = &mut self.table[..needed];
        let masks = &mut self.vertices[..rows];
        let (quads, origin) = (&local.quads, local.origin);
        let outside_all = match kernel {
            // SAFETY: `Kernel::Avx512` is only chosen where the processor has AVX-512.
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 if wide => unsafe {
                match planes.len() {
                    ..=8 => avx512::fill_eights::<1>(planes, origin, quads, th, table, masks),
                    _ => avx512::fill_eights::<2>(planes, origin, quads, th, table, masks),
                }
            },
            // SAFETY: `Kernel::Avx` is only chosen where the processor has AVX.
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx if planes.len() <= 16 => unsafe {
                let fill = match planes.len().div_ceil(4) {
                    1 => avx::fill_quads::<1>,
                    2 => avx::fill_quads::<2>,
                    3 => avx::fill_quads::<3>,
                    _ => avx::fill_quads::<4>,
                };
                fill(planes, origin, quads, th, table, masks)
            },
            _ => {
                set_planes(&mut self.planes, planes, origin);
                fill_portable(quads, &self.planes, th, table, masks)
            }
        };
        if !self.masked {
            // No masks past 64 faces: the separation test face by face (the padded rows
            // repeat the last vertex, which changes no `all`).
            let row = self.row;
            return !(0..planes.len()).any(|f| table.chunks_exact(row).all(|d| d[f] > th.gap));
        }
        outside_all == 0
    }

    /// The distance of vertex `vertex` to face plane `face`: a vertex of the block the table
    /// was last filled for, and a face of the other.
    #[inline]
    pub(crate) fn get(&self, face: usize, vertex: u32) -> f64 {
        let k = vertex as usize * self.row + face;
        debug_assert!(face < self.row && k < self.table.len());
        // SAFETY: the table holds a row of `row` distances per vertex of the block it was
        // filled for (`fill`), and callers pass one of its vertices (an edge's end, checked
        // when the block was built) and a face of the other (below `row`).
        unsafe { *self.table.get_unchecked(k) }
    }

    /// Whether the masks were built (the other block has at most [`MASK_FACES`] faces).
    #[inline]
    pub(crate) fn masked(&self) -> bool {
        self.masked
    }

    /// Clipping without the masks (tests: the masks must change nothing).
    #[cfg(test)]
    pub(crate) fn unmask(&mut self) {
        self.masked = false;
    }

    /// The masks of `vertex` (of the block the table was last filled for); only with
    /// [`DistanceTable::masked`].
    #[inline]
    pub(crate) fn vertex_masks(&self, vertex: u32) -> VertexMasks {
        debug_assert!((vertex as usize) < self.vertices.len());
        // SAFETY: `fill` keeps a mask per vertex of the block, and callers pass one of its
        // vertices (an edge's end, checked when it was built).
        unsafe { *self.vertices.get_unchecked(vertex as usize) }
    }
}

/// `planes` four at a time, as `n · x = n · (p - origin)` in coordinates local to `origin`:
/// `n · (v - o) - n · (p - o)` keeps the accuracy of `n · (v - p)` (differences of nearby
/// coordinates) with one dot product per vertex.
fn set_planes(out: &mut Vec<PlaneQuad>, planes: &[Plane], origin: DVec3) {
    out.clear();
    for four in planes.chunks(4) {
        let mut q = PlaneQuad {
            offset: [f64::INFINITY; 4],
            ..PlaneQuad::default()
        };
        for (k, &Plane { normal: n, point }) in four.iter().enumerate() {
            (q.nx[k], q.ny[k], q.nz[k]) = (n.x, n.y, n.z);
            q.offset[k] = n.dot(point - origin);
        }
        out.push(q);
    }
}

/// The portable fill: one vertex after the other (`[x, y, z]` of vertex `v` are
/// `quads[v / 4].{x, y, z}[v % 4]`, the last group padded), four planes at a time; writes
/// the distances and the masks (of the first 64 faces) and returns the faces with every
/// vertex outside (nonzero: separated).
#[inline(always)]
fn fill_portable(
    quads: &[Quad],
    planes: &[PlaneQuad],
    th: Thresholds,
    table: &mut [f64],
    masks: &mut [VertexMasks],
) -> u64 {
    let Thresholds { gap, length, .. } = th;
    let mut outside_all = u64::MAX;
    for (v, (out, m)) in table
        .chunks_exact_mut(4 * planes.len())
        .zip(masks)
        .enumerate()
    {
        let quad = &quads[v / 4];
        let (x, y, z) = (quad.x[v % 4], quad.y[v % 4], quad.z[v % 4]);
        let mut bits = VertexMasks::default();
        for (pq, (p, s)) in planes.iter().zip(out.chunks_exact_mut(4)).enumerate() {
            let d: [f64; 4] =
                std::array::from_fn(|k| p.nx[k] * x + p.ny[k] * y + p.nz[k] * z - p.offset[k]);
            s.copy_from_slice(&d);
            let shift = 4 * pq as u32;
            if shift < 64 {
                bits.outside |= nibble(d.map(|s| s > gap)) << shift;
                bits.shallow |= nibble(d.map(|s| s >= -gap)) << shift;
                bits.near |= nibble(d.map(|s| s.abs() <= length)) << shift;
            }
        }
        outside_all &= bits.outside;
        *m = bits;
    }
    outside_all
}

/// The four comparisons of a vertex with four planes as the low four bits of a word.
#[inline(always)]
fn nibble(b: [bool; 4]) -> u64 {
    b[0] as u64 | (b[1] as u64) << 1 | (b[2] as u64) << 2 | (b[3] as u64) << 3
}

#[cfg(target_arch = "x86_64")]
mod avx {
    use super::VertexMasks;
    use crate::block::Quad;
    use crate::geometry::{DVec3, Plane};
    use crate::tolerance::Thresholds;
    use std::arch::x86_64::*;

    /// A plane that is not there (past the last of a quad): no normal, offset ∞ below.
    static NO_PLANE: Plane = Plane {
        normal: DVec3::ZERO,
        point: DVec3::ZERO,
    };

    /// Planes `4 q .. 4 q + 4` as four vectors `[nx, ny, nz, offset]` in coordinates local
    /// to `origin`, the offset `n · (p - origin)` computed as the portable code does it
    /// (`(nx dx + ny dy) + nz dz`); a missing plane is `0 · x = ∞`. Each plane's six numbers
    /// are loaded as a row of four and a pair, and transposed in registers.
    ///
    /// # Safety
    /// The processor must have AVX.
    #[inline]
    #[target_feature(enable = "avx")]
    pub(super) unsafe fn plane_quad(planes: &[Plane], q: usize, origin: DVec3) -> [__m256d; 4] {
        let plane = |k: usize| planes.get(4 * q + k).unwrap_or(&NO_PLANE) as *const Plane;
        let rows = [plane(0), plane(1), plane(2), plane(3)].map(|p| p as *const f64);
        // SAFETY: each pointer is to a `Plane`, six contiguous `f64` (`DVec3` is three).
        let ([r0, r1, r2, r3], [h0, h1, h2, h3]) = unsafe {
            (
                rows.map(|r| _mm256_loadu_pd(r)),
                rows.map(|r| _mm_loadu_pd(r.add(4))),
            )
        };
        // [nx ny nz px] rows to columns.
        let (t0, t1) = (_mm256_unpacklo_pd(r0, r1), _mm256_unpackhi_pd(r0, r1));
        let (t2, t3) = (_mm256_unpacklo_pd(r2, r3), _mm256_unpackhi_pd(r2, r3));
        let nx = _mm256_permute2f128_pd::<0x20>(t0, t2);
        let nz = _mm256_permute2f128_pd::<0x31>(t0, t2);
        let ny = _mm256_permute2f128_pd::<0x20>(t1, t3);
        let px = _mm256_permute2f128_pd::<0x31>(t1, t3);
        // [py pz] pairs to columns.
        let a = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(h0), h2);
        let b = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(h1), h3);
        let (py, pz) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
        let dx = _mm256_sub_pd(px, _mm256_set1_pd(origin.x));
        let dy = _mm256_sub_pd(py, _mm256_set1_pd(origin.y));
        let dz = _mm256_sub_pd(pz, _mm256_set1_pd(origin.z));
        let dot = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(nx, dx), _mm256_mul_pd(ny, dy)),
            _mm256_mul_pd(nz, dz),
        );
        let present = (planes.len().saturating_sub(4 * q)).min(4);
        // Lanes at and past `present` get the offset ∞.
        let missing = _mm256_cmp_pd::<_CMP_GE_OQ>(
            _mm256_set_pd(3.0, 2.0, 1.0, 0.0),
            _mm256_set1_pd(present as f64),
        );
        let offset = _mm256_blendv_pd(dot, _mm256_set1_pd(f64::INFINITY), missing);
        [nx, ny, nz, offset]
    }

    /// The fill for a block of at most `4 Q` planes (`Q` from 1 to 4), kept in registers
    /// for the whole table: the plane quads are made here from `planes` ([`plane_quad`]),
    /// and each vertex's distances and masks take `Q` vector steps with constant shifts.
    /// Vertices go four at a time (the last group padded with copies of the last vertex,
    /// which `table` and `masks` have room for), so that their coordinates are at constant
    /// offsets.
    ///
    /// # Safety
    /// The processor must have AVX.
    #[target_feature(enable = "avx")]
    pub(super) unsafe fn fill_quads<const Q: usize>(
        planes: &[Plane],
        origin: DVec3,
        quads: &[Quad],
        th: Thresholds,
        table: &mut [f64],
        masks: &mut [VertexMasks],
    ) -> u64 {
        let n = 4 * quads.len();
        assert!(planes.len() <= 4 * Q && table.len() >= n * 4 * Q && masks.len() >= n);
        // SAFETY: AVX (the caller's promise).
        let p: [[__m256d; 4]; Q] =
            std::array::from_fn(|q| unsafe { plane_quad(planes, q, origin) });
        let above = _mm256_set1_pd(th.gap);
        let below = _mm256_set1_pd(-th.gap);
        let length = _mm256_set1_pd(th.length);
        let sign = _mm256_set1_pd(-0.0);
        let mut outside_all = u64::MAX;
        for (c, quad) in quads.iter().enumerate() {
            for k in 0..4 {
                let v = 4 * c + k;
                // SAFETY: `v < n`, so its row is within `table` and its mask within `masks`
                // (asserted above).
                unsafe {
                    let x = _mm256_broadcast_sd(quad.x.get_unchecked(k));
                    let y = _mm256_broadcast_sd(quad.y.get_unchecked(k));
                    let z = _mm256_broadcast_sd(quad.z.get_unchecked(k));
                    let out = table.as_mut_ptr().add(v * 4 * Q);
                    let mut bits = VertexMasks::default();
                    for (q, [nx, ny, nz, offset]) in p.iter().enumerate() {
                        let xy = _mm256_add_pd(_mm256_mul_pd(*nx, x), _mm256_mul_pd(*ny, y));
                        let s = _mm256_sub_pd(_mm256_add_pd(xy, _mm256_mul_pd(*nz, z)), *offset);
                        _mm256_storeu_pd(out.add(4 * q), s);
                        let outside = _mm256_cmp_pd::<_CMP_GT_OQ>(s, above);
                        let shallow = _mm256_cmp_pd::<_CMP_GE_OQ>(s, below);
                        let near = _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_andnot_pd(sign, s), length);
                        let nibble = |m: __m256d| opaque(_mm256_movemask_pd(m) as u64) << (4 * q);
                        bits.outside |= nibble(outside);
                        bits.shallow |= nibble(shallow);
                        bits.near |= nibble(near);
                    }
                    outside_all &= bits.outside;
                    *masks.get_unchecked_mut(v) = bits;
                }
            }
        }
        outside_all
    }

    /// `x`, unknown to the optimiser: it would otherwise merge the sign masks of the plane
    /// quads into one wider mask through a long chain of packs (about three times the
    /// instructions of a shift and an `or` each).
    #[inline(always)]
    pub(super) fn opaque(mut x: u64) -> u64 {
        // SAFETY: an empty assembly block that only claims to change `x`.
        unsafe {
            std::arch::asm!("/* {0} */", inout(reg) x, options(pure, nomem, nostack, preserves_flags));
        }
        x
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::avx::{opaque, plane_quad};
    use super::VertexMasks;
    use crate::block::Quad;
    use crate::geometry::{DVec3, Plane};
    use crate::tolerance::Thresholds;
    use std::arch::x86_64::*;

    /// [`super::avx::fill_quads`] on 512-bit vectors: eight planes a step, `E` steps (up to
    /// 8 or 16 planes), kept in registers; the comparisons give mask registers directly.
    /// The same operations in the same order, so the same distances to the bit.
    ///
    /// # Safety
    /// The processor must have AVX-512F.
    #[target_feature(enable = "avx512f")]
    pub(super) unsafe fn fill_eights<const E: usize>(
        planes: &[Plane],
        origin: DVec3,
        quads: &[Quad],
        th: Thresholds,
        table: &mut [f64],
        masks: &mut [VertexMasks],
    ) -> u64 {
        let n = 4 * quads.len();
        assert!(planes.len() <= 8 * E && table.len() >= n * 8 * E && masks.len() >= n);
        // Two quads of planes side by side.
        let p: [[__m512d; 4]; E] = std::array::from_fn(|e| {
            // SAFETY: AVX-512F includes AVX (the caller's promise).
            let (lo, hi) = unsafe {
                (
                    plane_quad(planes, 2 * e, origin),
                    plane_quad(planes, 2 * e + 1, origin),
                )
            };
            std::array::from_fn(|k| _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo[k]), hi[k]))
        });
        let above = _mm512_set1_pd(th.gap);
        let below = _mm512_set1_pd(-th.gap);
        let length = _mm512_set1_pd(th.length);
        let mut outside_all = u64::MAX;
        for (c, quad) in quads.iter().enumerate() {
            for k in 0..4 {
                let v = 4 * c + k;
                // SAFETY: `v < n`, so its row is within `table` and its mask within `masks`
                // (asserted above).
                unsafe {
                    let x = _mm512_set1_pd(*quad.x.get_unchecked(k));
                    let y = _mm512_set1_pd(*quad.y.get_unchecked(k));
                    let z = _mm512_set1_pd(*quad.z.get_unchecked(k));
                    let out = table.as_mut_ptr().add(v * 8 * E);
                    let mut bits = VertexMasks::default();
                    for (e, [nx, ny, nz, offset]) in p.iter().enumerate() {
                        let xy = _mm512_add_pd(_mm512_mul_pd(*nx, x), _mm512_mul_pd(*ny, y));
                        let s = _mm512_sub_pd(_mm512_add_pd(xy, _mm512_mul_pd(*nz, z)), *offset);
                        _mm512_storeu_pd(out.add(8 * e), s);
                        let eight = |m: __mmask8| opaque(m as u64) << (8 * e);
                        bits.outside |= eight(_mm512_cmp_pd_mask::<_CMP_GT_OQ>(s, above));
                        bits.shallow |= eight(_mm512_cmp_pd_mask::<_CMP_GE_OQ>(s, below));
                        let magnitude = _mm512_abs_pd(s);
                        bits.near |= eight(_mm512_cmp_pd_mask::<_CMP_LE_OQ>(magnitude, length));
                    }
                    outside_all &= bits.outside;
                    *masks.get_unchecked_mut(v) = bits;
                }
            }
        }
        outside_all
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::test_rng::{polytope, Rng};

    /// Every kernel this processor runs gives the portable kernel's distances and masks,
    /// to the bit, with and without masks, separated or not; each distance is the plane's
    /// distance of the vertex and each mask says what it should.
    #[test]
    fn kernels_agree_to_the_bit() {
        let mut rng = Rng(5);
        let kernels = Kernel::available();
        let mut separated = 0;
        for round in 0..300 {
            let faces = [4, 6, 8, 9, 12, 16, 17, 30, 70][round % 9];
            let a = polytope(&mut rng, faces, [0.0; 3], None);
            let d = 1.0 + 2.0 * rng.unit();
            let centre = [d * rng.signed(), d * rng.signed(), d];
            let b = polytope(&mut rng, faces, centre, None);
            let gap = [0.0, 1e-9, 0.03][round % 3];
            let th = Thresholds {
                gap,
                length: 10.0 * gap,
                sine: 10.0 * gap,
            };
            let filled: Vec<(bool, DistanceTable)> = kernels
                .iter()
                .map(|&k| {
                    let mut t = DistanceTable::default();
                    let together = t.fill(k, &a, &b, th);
                    (together, t)
                })
                .collect();
            let (ok0, t0) = &filled[0];
            separated += !ok0 as usize;
            for (k, (ok1, t1)) in filled.iter().enumerate().skip(1) {
                let kernel = kernels[k];
                assert_eq!(ok0, ok1, "round {round} {kernel:?}");
                for v in 0..a.vertices().len() as u32 {
                    for f in 0..b.n_faces() {
                        let (s, s1) = (t0.get(f, v), t1.get(f, v));
                        assert_eq!(s.to_bits(), s1.to_bits(), "round {round} {kernel:?}");
                    }
                    if t0.masked {
                        let (m0, m1) = (t0.vertex_masks(v), t1.vertex_masks(v));
                        assert_eq!(m0, m1, "round {round} {kernel:?}");
                    }
                }
            }
            for v in 0..a.vertices().len() as u32 {
                for f in 0..b.n_faces() {
                    let s = t0.get(f, v);
                    let exact = b.planes()[f].distance(a.vertices()[v as usize]);
                    assert!((s - exact).abs() < 1e-12, "round {round}: {s} vs {exact}");
                }
            }
            if !t0.masked {
                continue;
            }
            for v in 0..a.vertices().len() as u32 {
                let m = t0.vertex_masks(v);
                for f in 0..b.n_faces() {
                    let (s, bit) = (t0.get(f, v), |mask: u64| mask >> f & 1 == 1);
                    assert_eq!(bit(m.outside), s > th.gap, "round {round}");
                    assert_eq!(bit(m.shallow), s >= -th.gap, "round {round}");
                    assert_eq!(bit(m.near), s.abs() <= th.length, "round {round}");
                }
                let beyond = u64::MAX.checked_shl(b.n_faces() as u32).unwrap_or(0);
                assert_eq!(
                    (m.outside | m.shallow | m.near) & beyond,
                    0,
                    "round {round}"
                );
            }
            let apart = (0..b.n_faces())
                .any(|f| (0..a.vertices().len() as u32).all(|v| t0.get(f, v) > th.gap));
            assert_eq!(apart, !ok0, "round {round}");
        }
        assert!(separated > 10 && separated < 290, "{separated} separated");
    }
}
