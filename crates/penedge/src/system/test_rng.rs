//! A deterministic random generator (SplitMix64) for the crate's unit tests.

/// SplitMix64: the same sequence for the same seed, on every platform.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    pub(crate) fn signed(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}

/// A random convex block: `n` planes tangent to the unit sphere about `centre`, of random
/// outward normals, the first one `first` when given (drawn again until they bound a block).
pub(crate) fn polytope(
    rng: &mut Rng,
    n: usize,
    centre: [f64; 3],
    first: Option<[f64; 3]>,
) -> crate::ConvexBlock {
    loop {
        let mut normals: Vec<[f64; 3]> = (0..n)
            .map(|_| {
                let v = [rng.signed(), rng.signed(), rng.signed()];
                let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                v.map(|c| c / len)
            })
            .collect();
        if let Some(f) = first {
            normals[0] = f;
        }
        let offsets: Vec<f64> = normals
            .iter()
            .map(|m| 1.0 + m[0] * centre[0] + m[1] * centre[1] + m[2] * centre[2])
            .collect();
        if let Ok(block) = crate::ConvexBlock::from_planes(&normals, &offsets) {
            return block;
        }
    }
}
