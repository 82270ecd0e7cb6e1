//! The paper's three examples (section 4): a 10 m cube cut by infinite planes, produced by
//! the generator from a spec (also in `examples/paper_example_*.toml`).

use super::{BlockSystem, SystemError};
use crate::generation::{generate, Discontinuity, Domain, Orientation, Spec};

/// One of the paper's examples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaperExample {
    /// Cut by x = 5, y = 5, z = 5 (8 blocks).
    One = 1,
    /// Cut by x + y = 10, y + z = 10, z + x = 10 (8 blocks).
    Two = 2,
    /// Cut by all six planes (26 blocks).
    Three = 3,
}

impl PaperExample {
    /// The example with number 1, 2 or 3.
    pub fn from_number(n: u32) -> Option<PaperExample> {
        match n {
            1 => Some(PaperExample::One),
            2 => Some(PaperExample::Two),
            3 => Some(PaperExample::Three),
            _ => None,
        }
    }

    /// The cutting planes `normal · x = offset`.
    pub fn planes(self) -> (Vec<[f64; 3]>, Vec<f64>) {
        let axes = (
            vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            vec![5.0; 3],
        );
        let diagonals = (
            vec![[1.0, 1.0, 0.0], [0.0, 1.0, 1.0], [1.0, 0.0, 1.0]],
            vec![10.0; 3],
        );
        match self {
            PaperExample::One => axes,
            PaperExample::Two => diagonals,
            PaperExample::Three => (
                [axes.0, diagonals.0].concat(),
                [axes.1, diagonals.1].concat(),
            ),
        }
    }
}

/// The generation spec of a paper example: the cube and its planes, each through a point
/// (`offset / |n|² · n`) with its normal.
pub fn paper_spec(example: PaperExample) -> Spec {
    let domain = Domain::cuboid([0.0; 3], [10.0; 3]).expect("a valid cube");
    let (normals, offsets) = example.planes();
    normals
        .iter()
        .zip(offsets)
        .enumerate()
        .fold(Spec::new(domain), |spec, (i, (n, d))| {
            let scale = d / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            let point = n.map(|c| c * scale);
            let plane = Discontinuity::plane(point, Orientation::Normal(*n));
            spec.with(plane.named(format!("plane {}", i + 1)))
        })
}

/// The block system of a paper example.
pub fn paper_example(example: PaperExample) -> Result<BlockSystem, SystemError> {
    Ok(generate(&paper_spec(example))?.system)
}

/// The counts printed in the paper's Table 3, in the order of
/// [`crate::ContactType::ALL`].
pub fn paper_table3(example: PaperExample) -> [usize; 7] {
    match example {
        PaperExample::One => [4, 0, 0, 12, 0, 0, 12],
        PaperExample::Two => [4, 0, 0, 4, 0, 0, 20],
        PaperExample::Three => [205, 0, 0, 78, 0, 0, 42],
    }
}

/// Every pair of blocks of the paper's three examples (tests).
#[cfg(test)]
pub(crate) fn paper_pairs() -> Vec<(crate::ConvexBlock, crate::ConvexBlock)> {
    let mut pairs = Vec::new();
    for example in [PaperExample::One, PaperExample::Two, PaperExample::Three] {
        let blocks = paper_example(example)
            .expect("the paper's examples")
            .blocks()
            .to_vec();
        for (i, a) in blocks.iter().enumerate() {
            pairs.extend(blocks[i + 1..].iter().map(|b| (a.clone(), b.clone())));
        }
    }
    pairs
}
