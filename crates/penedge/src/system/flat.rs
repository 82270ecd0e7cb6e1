//! A block system from flat arrays (the layout of [`super::SystemArrays`]): what a DEM code
//! holds, read without one object per block, the blocks built in parallel.

use super::{BlockSystem, SystemError};
use crate::block::{ConvexBlock, FaceOrigin};
use crate::tolerance::Tolerance;
use rayon::prelude::*;

/// Blocks as flat arrays, borrowed: block `i` owns the vertices
/// `vertices[vertex_offsets[i]..vertex_offsets[i + 1]]` and the faces
/// `face_offsets[i]..face_offsets[i + 1]`; face `f` is the loop
/// `face_vertices[loop_offsets[f]..loop_offsets[f + 1]]` of indices into `vertices` (each
/// among its own block's vertices), counter-clockwise seen from outside. The same layout as
/// [`BlockSystem::arrays`] gives back.
#[derive(Clone, Copy, Debug)]
pub struct FlatBlocks<'a> {
    /// All vertices, block after block.
    pub vertices: &'a [[f64; 3]],
    /// Per block, the start of its vertices (length: blocks + 1).
    pub vertex_offsets: &'a [u64],
    /// Per block, the start of its faces (length: blocks + 1).
    pub face_offsets: &'a [u64],
    /// Per face, the start of its vertex loop (length: faces + 1).
    pub loop_offsets: &'a [u64],
    /// The vertex loops of all faces (indices into `vertices`).
    pub face_vertices: &'a [u64],
    /// Per face, where it comes from (or `None`: unknown for every face). Kept only where a
    /// block's faces are kept as given (no adjacent coplanar faces merged).
    pub origins: Option<&'a [FaceOrigin]>,
}

/// Checks that `offsets` (named `name`) start at 0, never decrease and end at `end` (the
/// length of what they index, named `of`).
fn check_offsets(name: &str, offsets: &[u64], end: usize, of: &str) -> Result<(), SystemError> {
    let problem = if offsets.is_empty() {
        Some("is empty (it needs the number of entries + 1 values, starting at 0)".to_string())
    } else if offsets[0] != 0 {
        Some(format!("starts at {}, not 0", offsets[0]))
    } else if let Some(i) = offsets.windows(2).position(|w| w[1] < w[0]) {
        Some(format!(
            "decreases at position {} ({} then {})",
            i + 1,
            offsets[i],
            offsets[i + 1]
        ))
    } else if offsets[offsets.len() - 1] != end as u64 {
        Some(format!(
            "ends at {}, but {of} has {end} entries",
            offsets[offsets.len() - 1]
        ))
    } else {
        None
    };
    match problem {
        Some(problem) => Err(SystemError::Arrays {
            message: format!("{name} {problem}"),
        }),
        None => Ok(()),
    }
}

impl FlatBlocks<'_> {
    /// Checks that the offsets fit together and the arrays they index.
    fn check(&self) -> Result<(), SystemError> {
        check_offsets(
            "vertex_offsets",
            self.vertex_offsets,
            self.vertices.len(),
            "vertices",
        )?;
        let n_faces = self.loop_offsets.len().saturating_sub(1);
        check_offsets(
            "face_offsets",
            self.face_offsets,
            n_faces,
            "loop_offsets - 1",
        )?;
        check_offsets(
            "loop_offsets",
            self.loop_offsets,
            self.face_vertices.len(),
            "face_vertices",
        )?;
        if self.vertex_offsets.len() != self.face_offsets.len() {
            return Err(SystemError::Arrays {
                message: format!(
                    "vertex_offsets has {} values and face_offsets {}: one per block + 1 each",
                    self.vertex_offsets.len(),
                    self.face_offsets.len()
                ),
            });
        }
        if let Some(origins) = self.origins {
            if origins.len() != n_faces {
                return Err(SystemError::Arrays {
                    message: format!("{} face origins for {n_faces} faces", origins.len()),
                });
            }
        }
        Ok(())
    }

    /// Block `i`, built and validated as [`ConvexBlock::with_tolerance`] does.
    fn block(&self, i: usize, tol: &Tolerance) -> Result<ConvexBlock, SystemError> {
        let (v0, v1) = (self.vertex_offsets[i], self.vertex_offsets[i + 1]);
        let faces = self.face_offsets[i] as usize..self.face_offsets[i + 1] as usize;
        let mut loops = Vec::with_capacity(faces.len());
        for f in faces.clone() {
            let (s, e) = (
                self.loop_offsets[f] as usize,
                self.loop_offsets[f + 1] as usize,
            );
            let looped = self.face_vertices[s..e].iter().map(|&v| {
                if (v0..v1).contains(&v) {
                    Ok((v - v0) as usize)
                } else {
                    Err(SystemError::Arrays {
                        message: format!(
                            "face {f} (of block {i}) refers to vertex {v}, outside the block's \
                             vertices {v0}..{v1}"
                        ),
                    })
                }
            });
            loops.push(looped.collect::<Result<Vec<usize>, _>>()?);
        }
        let vertices = &self.vertices[v0 as usize..v1 as usize];
        let invalid = |source| SystemError::InvalidBlock { block: i, source };
        let block = ConvexBlock::with_tolerance(vertices, &loops, tol).map_err(invalid)?;
        match self.origins {
            Some(origins) if block.n_faces() == loops.len() => block
                .with_face_origins(origins[faces].to_vec())
                .map_err(invalid),
            _ => Ok(block),
        }
    }
}

impl BlockSystem {
    /// The blocks of flat arrays, built in parallel (each validated as
    /// [`ConvexBlock::with_tolerance`] does with `tol`). The first bad block (lowest id) is
    /// the error, whatever the threads' order.
    pub fn from_arrays(arrays: &FlatBlocks<'_>, tol: &Tolerance) -> Result<Self, SystemError> {
        arrays.check()?;
        let n = arrays.vertex_offsets.len() - 1;
        let built: Vec<Result<ConvexBlock, SystemError>> = (0..n)
            .into_par_iter()
            .map(|i| arrays.block(i, tol))
            .collect();
        let blocks = built.into_iter().collect::<Result<Vec<_>, _>>()?;
        Ok(BlockSystem::new(blocks))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{paper_example, PaperExample};

    fn flat(a: &super::super::SystemArrays) -> FlatBlocks<'_> {
        FlatBlocks {
            vertices: &a.vertices,
            vertex_offsets: &a.vertex_offsets,
            face_offsets: &a.face_offsets,
            loop_offsets: &a.loop_offsets,
            face_vertices: &a.face_vertices,
            origins: None,
        }
    }

    #[test]
    fn the_arrays_of_a_system_give_the_same_blocks_back() {
        let system = paper_example(PaperExample::Three).expect("example 3");
        let a = system.arrays();
        let back = BlockSystem::from_arrays(&flat(&a), &Tolerance::default()).expect("valid");
        assert_eq!(back.len(), system.len());
        for (b, s) in back.blocks().iter().zip(system.blocks()) {
            assert_eq!(b.vertices(), s.vertices());
            assert!(b.faces().eq(s.faces()));
            assert_eq!(b.volume(), s.volume());
        }
        let origins: Vec<FaceOrigin> = system
            .blocks()
            .iter()
            .flat_map(|b| b.face_origins().iter().copied())
            .collect();
        let with = FlatBlocks {
            origins: Some(&origins),
            ..flat(&a)
        };
        let back = BlockSystem::from_arrays(&with, &Tolerance::default()).expect("valid");
        for (b, s) in back.blocks().iter().zip(system.blocks()) {
            assert_eq!(b.face_origins(), s.face_origins());
        }
    }

    #[test]
    fn bad_arrays_are_named() {
        let a = paper_example(PaperExample::One)
            .expect("example 1")
            .arrays();
        let mut offsets = a.vertex_offsets.clone();
        offsets[0] = 1;
        let bad = FlatBlocks {
            vertex_offsets: &offsets,
            ..flat(&a)
        };
        let err = BlockSystem::from_arrays(&bad, &Tolerance::default()).unwrap_err();
        assert_eq!(err.to_string(), "vertex_offsets starts at 1, not 0");
        // Block 2's first face given a vertex of block 0.
        let mut loops = a.face_vertices.clone();
        let first_of_block_2 = a.loop_offsets[a.face_offsets[2] as usize] as usize;
        loops[first_of_block_2] = 0;
        let bad = FlatBlocks {
            face_vertices: &loops,
            ..flat(&a)
        };
        let err = BlockSystem::from_arrays(&bad, &Tolerance::default()).unwrap_err();
        assert!(
            err.to_string().contains("(of block 2) refers to vertex 0"),
            "{err}"
        );
        // Block 5 turned inside out (every loop reversed), and block 6 too: block 5 is named.
        let mut loops = a.face_vertices.clone();
        for b in [5, 6] {
            for f in a.face_offsets[b] as usize..a.face_offsets[b + 1] as usize {
                loops[a.loop_offsets[f] as usize..a.loop_offsets[f + 1] as usize].reverse();
            }
        }
        let bad = FlatBlocks {
            face_vertices: &loops,
            ..flat(&a)
        };
        let err = BlockSystem::from_arrays(&bad, &Tolerance::default()).unwrap_err();
        assert!(
            matches!(err, SystemError::InvalidBlock { block: 5, .. }),
            "{err}"
        );
        assert!(err.to_string().starts_with("block 5: "), "{err}");
    }
}
