//! The broad phase: every pair of blocks whose bounding boxes, each widened by its block's
//! gap, overlap (touching counts). Only these *candidate pairs* go to the narrow phase.
//!
//! Widening each box by its own block's absolute gap (the policy of [`crate::tolerance`] at
//! the block's size) is conservative: the gap of a pair is the policy at the *smaller*
//! block's size, never more than either block's own gap, so a pair within its gap always has
//! overlapping widened boxes.
//!
//! Three methods give exactly the same pairs (the tests check it on random systems):
//!
//! - [`BroadPhase::Grid`] (the default): a hierarchical uniform grid. The base cell is the
//!   median box extent; a block lives in the coarsest-needed level, whose cell is at least
//!   its extent, in the cell of its lower corner. Two overlapping boxes of the same level
//!   then have lower corners in neighbouring cells, and a block meets the blocks of coarser
//!   levels in the cells around its lower corner's cell there (at most 27: from one below
//!   to its upper corner's, along each axis). Linear in the number of
//!   blocks and pairs for any mix of sizes (slivers beside big blocks cost one more level).
//! - [`BroadPhase::Sweep`]: sort-and-sweep along the axis of largest spread. Good for
//!   elongated systems, quadratic when many blocks share a slab (a cubic grid of blocks:
//!   every slab of the sweep axis holds a whole layer).
//! - [`BroadPhase::BruteForce`]: all `n (n - 1) / 2` pairs; the reference in tests.
//!
//! `penedge-bench system` measures them (docs/benchmarks.md). The pairs come back sorted,
//! whatever the number of threads.

use super::append_in_parallel;
use crate::geometry::{Aabb, DVec3};
use rayon::prelude::*;

/// How candidate pairs are found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BroadPhase {
    /// Hierarchical uniform grid (the default).
    #[default]
    Grid,
    /// Sort-and-sweep along the axis of largest spread.
    Sweep,
    /// Every pair: quadratic, for tests on small systems.
    BruteForce,
}

impl BroadPhase {
    /// Every method, the default first.
    pub const ALL: [BroadPhase; 3] = [BroadPhase::Grid, BroadPhase::Sweep, BroadPhase::BruteForce];

    /// The method's name: `grid`, `sweep` or `brute-force`.
    pub fn name(self) -> &'static str {
        match self {
            BroadPhase::Grid => "grid",
            BroadPhase::Sweep => "sweep",
            BroadPhase::BruteForce => "brute-force",
        }
    }

    /// The method of a name given by [`BroadPhase::name`].
    pub fn from_name(name: &str) -> Option<BroadPhase> {
        BroadPhase::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// Bounding boxes widened by a margin each: the broad phase's input.
#[derive(Clone, Debug, Default)]
pub struct WideBoxes {
    min: Vec<DVec3>,
    max: Vec<DVec3>,
}

impl WideBoxes {
    /// Boxes `aabb` widened by `margin` on every side (finite boxes, margins ≥ 0).
    pub fn new(boxes: impl IntoIterator<Item = (Aabb, f64)>) -> Self {
        let (min, max) = boxes
            .into_iter()
            .map(|(b, m)| (b.min - m, b.max + m))
            .unzip();
        WideBoxes { min, max }
    }

    /// [`WideBoxes::new`] in parallel, box `i` being `boxes(i)` for `i < n` (reading a
    /// million blocks' boxes is bound by memory latency: two threads halve it).
    pub fn from_fn(n: usize, boxes: impl Fn(usize) -> (Aabb, f64) + Sync) -> Self {
        let (min, max) = (0..n)
            .into_par_iter()
            .map(|i| {
                let (b, m) = boxes(i);
                (b.min - m, b.max + m)
            })
            .unzip();
        WideBoxes { min, max }
    }

    /// Number of boxes.
    pub fn len(&self) -> usize {
        self.min.len()
    }

    /// Whether there is no box.
    pub fn is_empty(&self) -> bool {
        self.min.is_empty()
    }

    /// Whether widened boxes `i` and `j` overlap (touching counts): the one predicate every
    /// method applies.
    #[inline]
    pub fn overlap(&self, i: usize, j: usize) -> bool {
        self.min[i].cmple(self.max[j]).all() && self.min[j].cmple(self.max[i]).all()
    }

    /// [`WideBoxes::overlap`] without branches.
    #[inline]
    fn overlap_mask(&self, i: usize, j: usize) -> bool {
        (self.min[i].cmple(self.max[j]) & self.min[j].cmple(self.max[i])).bitmask() == 0b111
    }

    /// The candidate pairs `[i, j]`, `i < j`, sorted, by the given method.
    pub fn pairs(&self, method: BroadPhase) -> Vec<[u32; 2]> {
        let mut pairs = match method {
            BroadPhase::Grid => Grid::new(self).pairs(self),
            BroadPhase::Sweep => self.sweep(),
            BroadPhase::BruteForce => self.brute_force(),
        };
        pairs.par_sort_unstable_by_key(|&[i, j]| (u64::from(i) << 32) | u64::from(j));
        pairs
    }

    fn brute_force(&self) -> Vec<[u32; 2]> {
        (0..self.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                (i + 1..self.len())
                    .filter(move |&j| self.overlap(i, j))
                    .map(move |j| key(i, j))
            })
            .collect()
    }

    /// The boxes [`BroadPhase::Sweep`] would compare (each with those after it in its
    /// order, up to the first that starts past its end), counted without comparing them:
    /// few where the boxes are thin across the axis of largest spread (the columns a
    /// topographic surface leaves), on which the grid, whose cells are as large as the
    /// boxes' longest side, compares nearly every pair.
    pub(crate) fn sweep_work(&self) -> usize {
        let n = self.len();
        if n < 2 {
            return 0;
        }
        let axis = self.sweep_axis();
        let mut starts: Vec<f64> = self.min.iter().map(|m| m[axis]).collect();
        starts.par_sort_unstable_by(f64::total_cmp);
        // The box at `k` in the order compares those after it that start by its end: those
        // that do, `k + 1` of them before it or itself; summed over the boxes, those that
        // start by each end less `n (n + 1) / 2`.
        let before: usize = self
            .max
            .par_iter()
            .map(|e| starts.partition_point(|&s| s <= e[axis]))
            .sum();
        before.saturating_sub(n * (n + 1) / 2)
    }

    /// The axis along which [`BroadPhase::Sweep`] sorts: of the boxes' centres' largest
    /// spread.
    fn sweep_axis(&self) -> usize {
        let n = self.len();
        let centre = |i: usize| (self.min[i] + self.max[i]) * 0.5;
        let mean = (0..n).map(centre).sum::<DVec3>() / n as f64;
        let spread = (0..n)
            .map(|i| (centre(i) - mean) * (centre(i) - mean))
            .sum::<DVec3>();
        spread.max_position()
    }

    fn sweep(&self) -> Vec<[u32; 2]> {
        let n = self.len();
        if n < 2 {
            return Vec::new();
        }
        let axis = self.sweep_axis();
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.par_sort_unstable_by(|&i, &j| {
            self.min[i as usize][axis].total_cmp(&self.min[j as usize][axis])
        });
        (0..n)
            .into_par_iter()
            .flat_map_iter(|k| {
                let i = order[k] as usize;
                let end = self.max[i][axis];
                order[k + 1..]
                    .iter()
                    .map(|&j| j as usize)
                    .take_while(move |&j| self.min[j][axis] <= end)
                    .filter(move |&j| self.overlap(i, j))
                    .map(move |j| key(i, j))
            })
            .collect()
    }
}

/// Appends the pair of `i` with each block of `js` whose widened box overlaps `i`'s, without
/// a branch per candidate: whether two neighbouring boxes overlap is unpredictable (a mispredicted
/// branch costs more than the test), so every candidate's pair is written at the end of the
/// list and the length grows by the outcome.
#[inline]
fn push_overlapping(boxes: &WideBoxes, i: usize, js: &[u32], found: &mut Vec<[u32; 2]>) {
    if js.len() <= 2 {
        // A cell of one or two blocks (a regular grid of blocks): branches, which are
        // predictable there (most neighbours overlap), cost less than the set-up below.
        for &j in js {
            if boxes.overlap(i, j as usize) {
                found.push(key(i, j as usize));
            }
        }
        return;
    }
    found.reserve(js.len());
    let start = found.len();
    let spare = &mut found.spare_capacity_mut()[..js.len()];
    let mut n = 0;
    for &j in js {
        let j = j as usize;
        spare[n].write(key(i, j));
        n += boxes.overlap_mask(i, j) as usize;
    }
    // SAFETY: slot `k < n` was written when `n` was `k` (it grows by at most one after each
    // write), and `n <= js.len()` slots are within the reserved capacity.
    unsafe { found.set_len(start + n) };
}

/// The pair, smaller id first.
#[inline]
fn key(i: usize, j: usize) -> [u32; 2] {
    [i.min(j) as u32, i.max(j) as u32]
}

/// A cell's extent over the largest box extent of its level: cells slightly larger than
/// their boxes keep "lower corners of overlapping boxes lie in neighbouring cells" true
/// through the rounding of the cell coordinates.
const CELL_SLACK: f64 = 1.0 + 1e-6;

/// Most cells along one axis of a level (coarser cells cost speed, never pairs).
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 20) as f64;

/// The hierarchical grid: one level per cell size in use.
struct Grid {
    origin: DVec3,
    levels: Vec<Level>,
}

/// One level: its blocks sorted by cell, and where each cell's blocks start.
struct Level {
    cell: f64,
    dims: [u64; 3],
    /// Block ids, sorted by cell index.
    blocks: Vec<u32>,
    /// Cell index of each entry of `blocks`.
    cells: Vec<u64>,
    lookup: Lookup,
}

/// From a cell index to the range of `Level::blocks` in that cell.
enum Lookup {
    /// `starts[c]..starts[c + 1]`, for levels with few cells per block.
    Dense(Vec<u32>),
    /// Binary search in `Level::cells`, for sparse levels.
    Sparse,
}

impl Grid {
    fn new(boxes: &WideBoxes) -> Grid {
        let n = boxes.len();
        // A box with a NaN coordinate (a block left with one by an unchecked move) overlaps
        // nothing, as the brute force's comparisons say: it is in no level, and takes no
        // part in the grid's origin, span and median (which it made NaN, the base cell the
        // smallest number, and the grid lose the other blocks' pairs).
        let valid: Vec<bool> = (0..n)
            .into_par_iter()
            .map(|i| !(boxes.min[i].is_nan() || boxes.max[i].is_nan()))
            .collect();
        let extent: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|i| (boxes.max[i] - boxes.min[i]).max_element())
            .collect();
        let origin = (0..n)
            .into_par_iter()
            .filter(|&i| valid[i])
            .map(|i| boxes.min[i])
            .reduce(|| DVec3::INFINITY, DVec3::min);
        let top = (0..n)
            .into_par_iter()
            .filter(|&i| valid[i])
            .map(|i| boxes.max[i])
            .reduce(|| DVec3::NEG_INFINITY, DVec3::max);
        let span = top - origin;
        let mut median: Vec<f64> = (0..n).filter(|&i| valid[i]).map(|i| extent[i]).collect();
        // No box, or none to place.
        if median.is_empty() {
            return Grid {
                origin: DVec3::ZERO,
                levels: Vec::new(),
            };
        }
        let mid = median.len() / 2;
        let (_, &mut m, _) = median.select_nth_unstable_by(mid, f64::total_cmp);
        // The base cell: the median extent, or coarser where the domain would need too many
        // cells along an axis; never zero (a box may be flat when its margin is zero).
        let base = (m * CELL_SLACK)
            .max(span.max_element() / MAX_CELLS_PER_AXIS)
            .max(f64::MIN_POSITIVE);
        // At most `MAX_LEVEL` levels: a finite extent needs far fewer (the base cell is at
        // least the span over `MAX_CELLS_PER_AXIS`); an infinite one, from a block left with
        // a NaN or infinite coordinate by an unchecked move, would double the cell until it
        // overflowed (and the level's `u8` before it).
        const MAX_LEVEL: u8 = 64;
        let level_of = |e: f64| {
            let mut level = 0;
            let mut cell = base;
            while e * CELL_SLACK > cell && level < MAX_LEVEL {
                cell *= 2.0;
                level += 1;
            }
            level
        };
        // (`u8::MAX`, above every level: a box with a NaN coordinate, in none.)
        let assigned: Vec<u8> = extent
            .par_iter()
            .zip(&valid)
            .map(|(&e, &ok)| if ok { level_of(e) } else { u8::MAX })
            .collect();
        let top_level = assigned
            .iter()
            .copied()
            .filter(|&l| l != u8::MAX)
            .max()
            .unwrap_or(0) as usize;
        let levels = (0..=top_level)
            .map(|l| {
                let members: Vec<u32> = (0..n as u32)
                    .into_par_iter()
                    .filter(|&i| assigned[i as usize] as usize == l)
                    .collect();
                Level::new(boxes, origin, span, base * 2f64.powi(l as i32), members)
            })
            .collect();
        Grid { origin, levels }
    }

    fn pairs(&self, boxes: &WideBoxes) -> Vec<[u32; 2]> {
        /// Entries per parallel task.
        const CHUNK: usize = 1024;
        let mut parts: Vec<Vec<[u32; 2]>> = Vec::new();
        for (l, level) in self.levels.iter().enumerate() {
            let coarser: Vec<&Level> = self.levels[l + 1..]
                .iter()
                .filter(|c| !c.blocks.is_empty())
                .collect();
            let n = level.blocks.len();
            let found: Vec<Vec<[u32; 2]>> = (0..n.div_ceil(CHUNK))
                .into_par_iter()
                .map(|c| {
                    let mut found = Vec::new();
                    for p in c * CHUNK..(c * CHUNK + CHUNK).min(n) {
                        level.same_level(boxes, self.origin, p, &mut found);
                        let i = level.blocks[p] as usize;
                        for other in &coarser {
                            let home = other.coordinates(boxes.min[i], self.origin);
                            let top = other.coordinates(boxes.max[i], self.origin);
                            other.around(home, top, 0, |js| {
                                push_overlapping(boxes, i, js, &mut found)
                            });
                        }
                    }
                    found
                })
                .collect();
            parts.extend(found);
        }
        let mut out = Vec::new();
        append_in_parallel(
            &mut out,
            &parts.iter().map(Vec::as_slice).collect::<Vec<_>>(),
        );
        out
    }
}

impl Level {
    fn new(boxes: &WideBoxes, origin: DVec3, span: DVec3, cell: f64, members: Vec<u32>) -> Level {
        let axis = |s: f64| ((s / cell).floor() + 1.0).min(MAX_CELLS_PER_AXIS) as u64;
        let dims = [axis(span.x), axis(span.y), axis(span.z)];
        let mut level = Level {
            cell,
            dims,
            blocks: Vec::new(),
            cells: Vec::new(),
            lookup: Lookup::Sparse,
        };
        let mut entries: Vec<(u64, u32)> = members
            .par_iter()
            .map(|&i| {
                (
                    level.index(level.coordinates(boxes.min[i as usize], origin)),
                    i,
                )
            })
            .collect();
        entries.par_sort_unstable();
        let n_cells = dims.iter().map(|&d| d as u128).product::<u128>();
        if n_cells <= 4 * entries.len() as u128 + 1024 {
            let mut starts = vec![0u32; n_cells as usize + 1];
            for &(c, _) in &entries {
                starts[c as usize + 1] += 1;
            }
            for c in 0..n_cells as usize {
                starts[c + 1] += starts[c];
            }
            level.lookup = Lookup::Dense(starts);
        }
        (level.cells, level.blocks) = entries.into_iter().unzip();
        level
    }

    /// Cell coordinates of a point (clamped into the level).
    #[inline]
    fn coordinates(&self, p: DVec3, origin: DVec3) -> [u64; 3] {
        let c = ((p - origin) / self.cell).floor();
        let clamp = |v: f64, d: u64| (v.max(0.0) as u64).min(d - 1);
        [
            clamp(c.x, self.dims[0]),
            clamp(c.y, self.dims[1]),
            clamp(c.z, self.dims[2]),
        ]
    }

    #[inline]
    fn index(&self, c: [u64; 3]) -> u64 {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Range of `blocks` in cell `c`.
    #[inline]
    fn range(&self, c: u64) -> std::ops::Range<usize> {
        match &self.lookup {
            Lookup::Dense(starts) => starts[c as usize] as usize..starts[c as usize + 1] as usize,
            Lookup::Sparse => {
                let s = self.cells.partition_point(|&x| x < c);
                let e = s + self.cells[s..].partition_point(|&x| x <= c);
                s..e
            }
        }
    }

    /// Calls `f` with each block of the cells around `home` (the cell of a box's lower
    /// corner; `top`, that of its upper corner) whose cell index is at least `from_index`
    /// (0: all of them): the blocks of this level whose boxes may overlap that box.
    ///
    /// A box of this level overlapping it has its lower corner at most a cell below the
    /// box's lower corner (its extent is under a cell) and not above its upper corner, so in
    /// a cell from `home - 1` to `top` along each axis: the 27 cells around `home`, less the
    /// upper ones where the box ends within its cell (for blocks of a finer level, most
    /// of them: about 10 cells instead of 27). The cell coordinates grow with the point
    /// (a difference and a division by the cell, both monotonic under rounding), so the
    /// upper bound holds exactly; the lower one has the slack of the cell size.
    #[inline]
    fn around(&self, home: [u64; 3], top: [u64; 3], from_index: u64, mut f: impl FnMut(&[u32])) {
        let span = |k: usize| home[k].saturating_sub(1)..=(home[k] + 1).min(top[k]);
        for z in span(2) {
            for y in span(1) {
                for x in span(0) {
                    let c = self.index([x, y, z]);
                    if c >= from_index {
                        f(&self.blocks[self.range(c)]);
                    }
                }
            }
        }
    }

    /// The pairs of entry `p` with the entries after it in the cells around its own
    /// ([`Level::around`]): each same-level pair once.
    fn same_level(&self, boxes: &WideBoxes, origin: DVec3, p: usize, found: &mut Vec<[u32; 2]>) {
        let i = self.blocks[p] as usize;
        let own = self.cells[p];
        let home = [
            own % self.dims[0],
            own / self.dims[0] % self.dims[1],
            own / (self.dims[0] * self.dims[1]),
        ];
        let own_range = self.range(own);
        push_overlapping(boxes, i, &self.blocks[p + 1..own_range.end], found);
        let top = self.coordinates(boxes.max[i], origin);
        self.around(home, top, own + 1, |js| {
            push_overlapping(boxes, i, js, found)
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::system::test_rng::Rng;

    fn random_boxes(seed: u64, n: usize, sizes: &[f64]) -> WideBoxes {
        let mut rng = Rng(seed);
        WideBoxes::new((0..n).map(|k| {
            let size = sizes[k % sizes.len()];
            let p = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 10.0;
            let e = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * size;
            (Aabb { min: p, max: p + e }, 1e-3 * rng.unit())
        }))
    }

    fn check_all_methods(boxes: &WideBoxes) -> usize {
        let reference = boxes.pairs(BroadPhase::BruteForce);
        for method in [BroadPhase::Grid, BroadPhase::Sweep] {
            assert_eq!(boxes.pairs(method), reference, "{}", method.name());
        }
        reference.len()
    }

    #[test]
    fn every_method_finds_the_pairs_of_the_brute_force_one() {
        for (seed, sizes) in [
            (1, &[1.0][..]),
            (2, &[0.3, 0.5, 2.0][..]),
            (3, &[1e-4, 0.01, 1.0, 6.0][..]), // slivers beside big blocks: several levels
            (4, &[20.0][..]),                 // every block overlaps most others
        ] {
            let found = check_all_methods(&random_boxes(seed, 600, sizes));
            assert!(found > 100, "seed {seed}: only {found} pairs");
        }
    }

    #[test]
    fn touching_boxes_are_pairs_and_boxes_just_apart_are_not() {
        let cube = |x: f64, m: f64| {
            (
                Aabb {
                    min: DVec3::new(x, 0.0, 0.0),
                    max: DVec3::new(x + 1.0, 1.0, 1.0),
                },
                m,
            )
        };
        // A regular row of unit cubes: neighbours touch exactly.
        let row = WideBoxes::new((0..50).map(|k| cube(k as f64, 0.0)));
        let expected: Vec<[u32; 2]> = (0..49).map(|k| [k, k + 1]).collect();
        for method in BroadPhase::ALL {
            assert_eq!(row.pairs(method), expected, "{}", method.name());
        }
        // 0.25 apart (exact binary fractions): a pair once the margins reach across.
        for (m, pairs) in [(0.0625, 0), (0.125, 1), (0.25, 1)] {
            let two = WideBoxes::new([cube(0.0, m), cube(1.25, m)]);
            for method in BroadPhase::ALL {
                assert_eq!(two.pairs(method).len(), pairs, "{} {m}", method.name());
            }
        }
    }

    #[test]
    fn a_regular_grid_of_cubes_has_every_neighbour_pair() {
        let n = 6;
        let boxes = WideBoxes::new((0..n * n * n).map(|k| {
            let p = DVec3::new((k % n) as f64, (k / n % n) as f64, (k / (n * n)) as f64);
            (
                Aabb {
                    min: p,
                    max: p + 1.0,
                },
                1e-12,
            )
        }));
        // 3 (n-1) n^2 face, 6 (n-1)^2 n edge and 4 (n-1)^3 vertex neighbours.
        let expected = 3 * 5 * 36 + 6 * 25 * 6 + 4 * 125;
        assert_eq!(check_all_methods(&boxes), expected);
    }

    #[test]
    fn degenerate_inputs() {
        for method in BroadPhase::ALL {
            assert!(WideBoxes::default().pairs(method).is_empty());
            let one = WideBoxes::new([(
                Aabb {
                    min: DVec3::ZERO,
                    max: DVec3::ONE,
                },
                0.0,
            )]);
            assert!(one.pairs(method).is_empty());
            // Identical boxes: all pairs.
            let same = WideBoxes::new((0..5).map(|_| {
                (
                    Aabb {
                        min: DVec3::ZERO,
                        max: DVec3::ONE,
                    },
                    0.0,
                )
            }));
            assert_eq!(same.pairs(method).len(), 10, "{}", method.name());
        }
        // Far-apart clusters: the grid goes coarse rather than exhausting memory.
        let far = WideBoxes::new((0..40).map(|k| {
            let p = DVec3::splat(if k % 2 == 0 { 0.0 } else { 1e12 }) + k as f64 * 1e-3;
            (
                Aabb {
                    min: p,
                    max: p + 1e-3,
                },
                0.0,
            )
        }));
        check_all_methods(&far);
    }

    #[test]
    fn names_round_trip() {
        for method in BroadPhase::ALL {
            assert_eq!(BroadPhase::from_name(method.name()), Some(method));
        }
        assert_eq!(BroadPhase::from_name("octree"), None);
    }
}
