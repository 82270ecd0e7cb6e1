//! Excavating a block system: the rock inside an excavation's convex regions is removed, the
//! blocks its boundary crosses are cut, and what is left of a block stays one block (a
//! concave body of convex parts) while it is in one piece.
//!
//! A block minus a convex region `R` of faces `0..m` is the union of the convex pieces
//! `block ∩ outside(i) ∩ inside(0..i-1)`: the block is split by face 0's plane, the part
//! outside kept, the part inside split by face 1's, and so on; what is inside every face
//! is inside `R` and removed. When some plane leaves the rest wholly outside, the block and
//! `R` do not overlap and the block is kept as it was (no needless cuts). Splitting conserves
//! volume up to rounding (see [`crate::cutting`]), so the volume removed is the volume of
//! `R` within the blocks.

use super::concave::{meeting, Meeting};
use super::BlockSystem;
use crate::block::{ConvexBlock, FaceOrigin};
use crate::contact::Detector;
use crate::cutting::{Side, Splitter};
use crate::generation::Extent;
use crate::generation::{
    upward, Excavation, GenerationError, JointRecord, JointShape, Problem, SetKind, SetRecord,
    SpecError,
};
use crate::geometry::{Aabb, Plane};
use crate::system::BroadPhase;
use crate::tolerance::Tolerance;

/// What an excavation did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ExcavationReport {
    /// Blocks wholly inside the excavation, removed.
    pub removed_blocks: usize,
    /// Blocks cut by the excavation's boundary.
    pub cut_blocks: usize,
    /// The convex parts the cut blocks left.
    pub parts: usize,
    /// The volume removed: blocks' volume before less after.
    pub volume_removed: f64,
}

impl BlockSystem {
    /// This system with `excavation` removed: blocks inside it are removed, blocks its
    /// boundary crosses are cut into convex parts glued as one body per connected piece,
    /// with faces of origin `Joint { set, joint }` for a new entry of kind
    /// [`SetKind::Excavation`] and one joint record per face of its regions. Body ids are
    /// renumbered `0..` in the order of each body's first part.
    ///
    /// ```
    /// use penedge::generation::{Excavation, ExcavationShape};
    /// use penedge::{BlockSystem, ConvexBlock, Tolerance};
    /// let tol = Tolerance::default();
    /// let rock = BlockSystem::new(vec![ConvexBlock::cuboid([0.0; 3], [10.0; 3]).unwrap()]);
    /// let cavern = Excavation::new(ExcavationShape::Cavern {
    ///     center: [5.0, 5.0, 5.0], trend: 0.0, length: 20.0, width: 2.0, height: 3.0,
    /// });
    /// let (out, report) = rock.excavate(&cavern, &tol).unwrap();
    /// assert!((report.volume_removed - 60.0).abs() < 1e-9); // 10 x 2 x 3 within the rock
    /// assert_eq!(out.body_parts().len(), 1); // one block (a ring), in parts
    /// ```
    ///
    /// # Errors
    ///
    /// A bad excavation (the error names its field under `excavation`); one that removes no
    /// rock (outside the blocks, or in rock already excavated); a cut that cannot be made.
    /// One that removes all of the rock leaves an empty system (a spec's excavation may not:
    /// [`crate::generation::generate`] refuses it).
    pub fn excavate(
        &self,
        excavation: &Excavation,
        tol: &Tolerance,
    ) -> Result<(BlockSystem, ExcavationReport), GenerationError> {
        self.excavate_at(excavation, "excavation", tol)
    }

    /// [`BlockSystem::excavate`], naming fields under `prefix` (`excavations[2]`).
    pub(crate) fn excavate_at(
        &self,
        excavation: &Excavation,
        prefix: &str,
        tol: &Tolerance,
    ) -> Result<(BlockSystem, ExcavationReport), GenerationError> {
        self.excavate_watched(excavation, prefix, tol, &mut |_| Ok(()))
    }

    /// [`BlockSystem::excavate_at`], calling `watch` as it goes with the parts it holds
    /// (those made, those still to be cut and the blocks not reached yet): after each cut
    /// and each block, and now and then while it glues the parts into bodies. An error
    /// from `watch` (a block limit passed, a run cancelled) stops the excavation there.
    pub(crate) fn excavate_watched(
        &self,
        excavation: &Excavation,
        prefix: &str,
        tol: &Tolerance,
        watch: &mut Watch<'_>,
    ) -> Result<(BlockSystem, ExcavationReport), GenerationError> {
        let extent = Extent::of(&self.blocks).ok_or_else(|| misses(prefix))?;
        let regions = excavation.regions_at(prefix, Some(&extent))?;
        let set = self.sets.len() as u32;
        let first_joint = self.joints.len() as u32;
        let mut joints = self.joints.clone();
        for region in &regions {
            for f in 0..region.n_faces() {
                joints.push(face_record(
                    region,
                    f,
                    set,
                    joints.len() as u32 - first_joint,
                ));
            }
        }
        let name = self.excavation_name(excavation, prefix)?;
        let mut sets = self.sets.clone();
        sets.push(SetRecord {
            name,
            kind: SetKind::Excavation,
        });
        let Some(world) = self.blocks.iter().map(ConvexBlock::aabb).reduce(union) else {
            return Err(misses(prefix));
        };
        let eps = tol.for_box(&world).length;
        let mut splitter = Splitter::default();
        let mut report = ExcavationReport::default();
        // The pieces, each with the block it comes from.
        let mut pieces: Vec<(u32, ConvexBlock)> = Vec::with_capacity(self.len());
        // The first joint of each region's faces.
        let firsts: Vec<u32> = regions
            .iter()
            .scan(first_joint, |next, r| {
                let first = *next;
                *next += r.n_faces() as u32;
                Some(first)
            })
            .collect();
        let index = RegionIndex::new(&regions);
        // The parts still to be cut, each with the first region it may meet, last on top.
        let mut stack: Vec<(ConvexBlock, usize)> = Vec::new();
        for (k, block) in self.blocks.iter().enumerate() {
            // Each part goes through the regions in order, as a whole list of parts would
            // (region by region, each part replaced in place by what is left of it): a
            // part's pieces depend on that part and the regions alone, so taking the parts
            // depth first, the pieces of a part before the next part, makes the same pieces
            // in the same order. Only the regions whose box meets the part's are tried (a
            // slope or a surface has many regions, most far from any one part), found in
            // the index, and a region must meet the block's box too (as it always did).
            let block_box = block.aabb();
            let before = pieces.len();
            let mut touched = false;
            stack.push((block.clone(), 0));
            while let Some((part, from)) = stack.pop() {
                let part_box = part.aabb();
                let mut next = from;
                let left = loop {
                    let Some(r) = index.first(next, &part_box, -eps) else {
                        break None;
                    };
                    next = r + 1;
                    let region = &regions[r];
                    if !block_box.overlaps(&region.aabb(), eps) {
                        continue;
                    }
                    match subtract(&part, region, set, firsts[r], eps, &mut splitter) {
                        Ok(Some(left)) => break Some(left),
                        Ok(None) => {}
                        Err(source) => {
                            let joint = firsts[r];
                            return Err(GenerationError::Cut { set, joint, source });
                        }
                    }
                };
                match left {
                    None => pieces.push((k as u32, part)),
                    Some(left) => {
                        touched = true;
                        stack.extend(left.into_iter().rev().map(|p| (p, next)));
                        watch(pieces.len() + stack.len() + self.len() - k - 1)?;
                    }
                }
            }
            if touched {
                let parts = pieces.len() - before;
                if parts == 0 {
                    report.removed_blocks += 1;
                } else {
                    report.cut_blocks += 1;
                    report.parts += parts;
                }
            }
            watch(pieces.len() + self.len() - k - 1)?;
        }
        if report.removed_blocks + report.cut_blocks == 0 {
            return Err(misses(prefix));
        }
        let before: f64 = self.blocks.iter().map(ConvexBlock::volume).sum();
        let after: f64 = pieces.iter().map(|p| p.1.volume()).sum();
        report.volume_removed = before - after;
        let bodies: Vec<u32> = pieces.iter().map(|p| self.body_of(p.0)).collect();
        let blocks: Vec<ConvexBlock> = pieces.into_iter().map(|p| p.1).collect();
        let out = BlockSystem::with_provenance(blocks, self.domain.clone(), joints, sets)
            .with_unit(self.unit.clone());
        let pairs = part_pairs(&out, tol);
        watch(out.len())?;
        let ids = connected_bodies(&out, &bodies, &pairs, tol, watch)?;
        let out = out
            .with_bodies_among(ids, Some(&pairs), tol)
            .map_err(|e| SpecError::new(prefix, Problem::Invalid(e.to_string())))?;
        Ok((out, report))
    }
}

/// What [`BlockSystem::excavate_watched`] calls with the parts it holds; an error stops it.
pub(crate) type Watch<'a> = dyn FnMut(usize) -> Result<(), GenerationError> + 'a;

/// The regions' boxes in a tree over their order (a segment tree: each node holds the
/// union of its range's boxes), to find the first region from a given one on whose box
/// meets a part's box in time logarithmic in the regions (when there is one near).
struct RegionIndex {
    /// Leaves at `size..size + n` (padded with empty boxes), node `i`'s children at `2i`
    /// and `2i + 1`.
    nodes: Vec<Aabb>,
    size: usize,
}

impl RegionIndex {
    fn new(regions: &[ConvexBlock]) -> RegionIndex {
        let size = regions.len().next_power_of_two();
        let empty = Aabb {
            min: crate::geometry::DVec3::splat(f64::INFINITY),
            max: crate::geometry::DVec3::splat(f64::NEG_INFINITY),
        };
        let mut nodes = vec![empty; 2 * size];
        for (k, r) in regions.iter().enumerate() {
            nodes[size + k] = r.aabb();
        }
        for i in (1..size).rev() {
            nodes[i] = union(nodes[2 * i], nodes[2 * i + 1]);
        }
        RegionIndex { nodes, size }
    }

    /// The first region `r >= from` whose box `b.overlaps(box of r, margin)`: a union
    /// meets `b` whenever one of its boxes does, so a node whose union does not is skipped.
    fn first(&self, from: usize, b: &Aabb, margin: f64) -> Option<usize> {
        self.first_in(1, 0, self.size, from, b, margin)
    }

    fn first_in(
        &self,
        node: usize,
        lo: usize,
        hi: usize,
        from: usize,
        b: &Aabb,
        margin: f64,
    ) -> Option<usize> {
        if hi <= from || !b.overlaps(&self.nodes[node], margin) {
            return None;
        }
        if hi - lo == 1 {
            return Some(lo);
        }
        let mid = lo + (hi - lo) / 2;
        self.first_in(2 * node, lo, mid, from, b, margin)
            .or_else(|| self.first_in(2 * node + 1, mid, hi, from, b, margin))
    }
}

impl BlockSystem {
    /// The set name of `excavation`: its own, refused (at `{prefix}.name`) when it holds the
    /// contact table's separator or is already a joint set's or an earlier excavation's (a
    /// block file written with it would not read back: `io::json`); without one, `prefix`,
    /// or `prefix 2`, `prefix 3`, ... when that is taken (two unnamed excavations through
    /// the API).
    fn excavation_name(
        &self,
        excavation: &Excavation,
        prefix: &str,
    ) -> Result<String, GenerationError> {
        let taken = |name: &str| self.sets.iter().any(|s| s.name == name);
        match &excavation.name {
            Some(name) => {
                let names = self.sets.iter().map(|s| s.name.as_str());
                // In a spec (`excavations[k]`), the sets are its joints' entries and then its
                // earlier excavations': named as the spec names them.
                let in_spec = prefix.starts_with("excavations[");
                let label = |i: usize| {
                    let kind = self.sets.get(i).map(|s| s.kind);
                    if !in_spec {
                        format!("sets[{i}]")
                    } else if kind == Some(SetKind::Excavation) {
                        let k = self.sets[..i]
                            .iter()
                            .filter(|s| s.kind == SetKind::Excavation)
                            .count();
                        format!("excavations[{k}]")
                    } else {
                        format!("joints[{i}]")
                    }
                };
                crate::generation::check::entry_names_by(names.chain([name.as_str()]), label)
                    .map_err(|(_, why)| {
                        SpecError::new(format!("{prefix}.name"), Problem::Invalid(why))
                    })?;
                Ok(name.clone())
            }
            None => Ok((1..)
                .map(|k| {
                    if k == 1 {
                        prefix.to_string()
                    } else {
                        format!("{prefix} {k}")
                    }
                })
                .find(|name| !taken(name))
                .unwrap_or_else(|| prefix.to_string())),
        }
    }
}

fn misses(prefix: &str) -> GenerationError {
    let msg = "the excavation removes no rock: it lies outside the domain (outside every \
               block), or in rock already excavated";
    SpecError::new(prefix, Problem::Invalid(msg.to_string())).into()
}

fn union(a: Aabb, b: Aabb) -> Aabb {
    Aabb {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
    }
}

/// The joint record of face `f` of a region: its plane (upward normal) and its polygon
/// (counter-clockwise about that normal).
fn face_record(region: &ConvexBlock, f: usize, set: u32, member: u32) -> JointRecord {
    let plane = region.planes()[f];
    let normal = upward(plane.normal);
    let mut vertices: Vec<_> = region
        .face(f)
        .iter()
        .map(|&k| region.vertices()[k as usize])
        .collect();
    if normal != plane.normal {
        vertices.reverse();
    }
    JointRecord {
        set,
        member,
        plane: Plane {
            normal,
            point: plane.point,
        },
        shape: JointShape::Polygon { vertices },
    }
}

/// `part` minus the convex `region` (faces' joints numbered from `joint`): `None` when they
/// do not overlap, else the convex pieces left (none when `part` is inside `region`).
fn subtract(
    part: &ConvexBlock,
    region: &ConvexBlock,
    set: u32,
    joint: u32,
    eps: f64,
    splitter: &mut Splitter,
) -> Result<Option<Vec<ConvexBlock>>, crate::BlockError> {
    if !part.aabb().overlaps(&region.aabb(), -eps) {
        return Ok(None);
    }
    let mut rest = part.clone();
    let mut left = Vec::new();
    for (f, plane) in region.planes().iter().enumerate() {
        match splitter.prepare(&rest, plane, eps)? {
            Side::Below => {}
            Side::Above => return Ok(None),
            Side::Across => {
                let origin = FaceOrigin::Joint {
                    set,
                    joint: joint + f as u32,
                };
                let [below, above] = splitter.finish(origin)?;
                left.push(above);
                rest = below;
            }
        }
    }
    Ok(Some(left))
}

/// The broad phase's candidate pairs of the parts (the same pairs by either method, in
/// the same order): by the sweep where it compares few boxes (up to 1024 a part: a few
/// microseconds), as for the
/// thin columns of a topographic surface, which the grid (cells as large as the parts'
/// longest side) compares nearly all with one another; else by the grid.
fn part_pairs(system: &BlockSystem, tol: &Tolerance) -> Vec<[u32; 2]> {
    let boxes = system.wide_boxes(tol);
    let method = if boxes.sweep_work() <= 1024 * boxes.len() {
        BroadPhase::Sweep
    } else {
        BroadPhase::Grid
    };
    boxes.pairs(method)
}

/// Body ids after a cut: the parts of one body (`bodies`, per block) that are connected
/// through face-face contacts of positive area (not across a crack, [`BlockSystem::is_crack`])
/// stay one body; a body cut in two becomes two.
/// Ids are renumbered `0..` in the order of each body's first part.
fn connected_bodies(
    system: &BlockSystem,
    bodies: &[u32],
    pairs: &[[u32; 2]],
    tol: &Tolerance,
    watch: &mut Watch<'_>,
) -> Result<Vec<u32>, GenerationError> {
    let n = bodies.len();
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut k: usize) -> usize {
        while root[k] != k {
            root[k] = root[root[k]];
            k = root[k];
        }
        k
    }
    let mut det = Detector::new(*tol);
    for (k, &[i, j]) in pairs.iter().enumerate() {
        if k % 1024 == 1023 {
            watch(n)?;
        }
        let (i, j) = (i as usize, j as usize);
        if bodies[i] != bodies[j] {
            continue;
        }
        // Glued as `with_bodies` finds it (a penetration confirmed by its depth only), and
        // not across a crack: the pieces of a body held by rock bridges that touch only
        // there are apart once the excavation has removed the bridges.
        let glued = match meeting(&mut det, &system.blocks[i], &system.blocks[j]) {
            Meeting::Glued(faces, _) => !system.is_crack([i as u32, j as u32], faces),
            _ => false,
        };
        if glued {
            let (a, b) = (find(&mut root, i), find(&mut root, j));
            root[a.max(b)] = a.min(b);
        }
    }
    let mut ids = vec![u32::MAX; n];
    let mut next = 0;
    for k in 0..n {
        let r = find(&mut root, k);
        if ids[r] == u32::MAX {
            ids[r] = next;
            next += 1;
        }
        ids[k] = ids[r];
    }
    Ok(ids)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generation::{ExcavationShape, Profile};

    fn grid(n: usize, size: f64) -> BlockSystem {
        let h = size / n as f64;
        let mut blocks = Vec::new();
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let lo = [i as f64 * h, j as f64 * h, k as f64 * h];
                    let hi = [lo[0] + h, lo[1] + h, lo[2] + h];
                    blocks.push(ConvexBlock::cuboid(lo, hi).unwrap());
                }
            }
        }
        BlockSystem::new(blocks)
    }

    fn volume(s: &BlockSystem) -> f64 {
        s.blocks().iter().map(ConvexBlock::volume).sum()
    }

    /// A box tunnel 2 wide, 1.5 high, along y (trend 0), longer than the domain.
    fn box_tunnel(x: f64, z: f64) -> Excavation {
        Excavation::new(ExcavationShape::Tunnel {
            profile: Profile::Polygon {
                vertices: vec![[-1.0, -0.75], [1.0, -0.75], [1.0, 0.75], [-1.0, 0.75]],
            },
            start: [x, -5.0, z],
            trend: 0.0,
            plunge: 0.0,
            length: 30.0,
        })
    }

    #[test]
    fn a_box_tunnel_through_a_box_removes_its_section_times_the_width() {
        let tol = Tolerance::default();
        let rock = grid(3, 9.0); // 27 blocks of 3 m
        let (out, report) = rock.excavate(&box_tunnel(4.2, 4.6), &tol).unwrap();
        // Exact: section 2 x 1.5 times the domain's 9 m along y.
        let exact = 2.0 * 1.5 * 9.0;
        assert!((volume(&rock) - volume(&out) - exact).abs() < 1e-9 * exact);
        assert!((report.volume_removed - exact).abs() < 1e-9 * exact);
        // The tunnel lies within the middle column of blocks (x, z in 3..6): those three
        // blocks are each cut into a ring of parts; none is removed.
        assert_eq!((report.removed_blocks, report.cut_blocks), (0, 3));
        assert_eq!(out.body_parts().len(), 27, "every block stays one block");
        assert!(out.has_concave());
        // No part lies inside the tunnel.
        for b in out.blocks() {
            let c = b.centroid();
            assert!(
                !((c.x - 4.2).abs() < 1.0 && (c.z - 4.6).abs() < 0.75),
                "{c}"
            );
        }
        // The tunnel's faces are free faces of an excavation entry.
        assert_eq!(out.sets().last().unwrap().kind, SetKind::Excavation);
    }

    #[test]
    fn blocks_inside_are_removed_and_a_block_cut_through_becomes_two() {
        let tol = Tolerance::default();
        let rock = grid(3, 9.0);
        // A 3.5 m wide tunnel through x in 2.5..6: removes nothing whole (blocks are 3 m),
        // and a 4 m high one through the middle layer z in 2.5..6.5 cuts the middle column
        // through: each of its blocks (z in 3..6) is removed, the blocks above and below are
        // cut, and the side columns' middle blocks lose a slab.
        let tunnel = Excavation::new(ExcavationShape::Cavern {
            center: [4.5, 4.5, 4.5],
            trend: 0.0,
            length: 20.0,
            width: 3.5,
            height: 4.0,
        });
        let (out, report) = rock.excavate(&tunnel, &tol).unwrap();
        let exact = 3.5 * 4.0 * 9.0;
        assert!((volume(&rock) - volume(&out) - exact).abs() < 1e-9 * exact);
        assert_eq!(report.removed_blocks, 3);
        // A block of the middle column's left neighbour (x 0..3, z 3..6) loses x 2.75..3:
        // still one piece. The bodies: 27 - 3 removed.
        assert_eq!(out.body_parts().len(), 24);
        // Now a thin slot through a block cuts it in two separate bodies.
        let slot = Excavation::new(ExcavationShape::Cavern {
            center: [1.5, 4.5, 1.5],
            trend: 0.0,
            length: 20.0,
            width: 3.5,
            height: 0.5,
        });
        let (cut, _) = out.excavate(&slot, &tol).unwrap();
        // The three blocks of x 0..3, z 0..3 are each split into a lower and an upper part,
        // not glued: 3 more bodies.
        assert_eq!(cut.body_parts().len(), 27);
        // The slot: x from the domain's side (0) to 3.25, 0.5 high, 9 long.
        let exact2 = 3.25 * 0.5 * 9.0;
        assert!((volume(&out) - volume(&cut) - exact2).abs() < 1e-9 * exact2);
    }

    #[test]
    fn excavating_in_stages_conserves_volume_and_a_repeat_removes_nothing() {
        let tol = Tolerance::default();
        let rock = grid(2, 10.0);
        let circle = |x: f64, trend: f64| {
            Excavation::new(ExcavationShape::Tunnel {
                profile: Profile::Circle {
                    radius: 1.2,
                    segments: 12,
                },
                start: [x, 5.0, 5.0],
                trend,
                plunge: 0.0,
                length: 4.0,
            })
        };
        let first = circle(3.0, 0.0); // from y = 5 to 9: inside the domain
        let (one, r1) = rock.excavate(&first, &tol).unwrap();
        let v1 = first.volume().unwrap();
        assert!((r1.volume_removed - v1).abs() < 1e-9 * v1);
        // The second, from the first's start, at trend 180 (y from 5 to 1): disjoint.
        let second = circle(3.0, 180.0);
        let (two, r2) = one.excavate(&second, &tol).unwrap();
        assert!((r2.volume_removed - v1).abs() < 1e-9 * v1);
        assert!((volume(&rock) - volume(&two) - 2.0 * v1).abs() < 1e-9 * v1);
        assert_eq!(two.sets().len(), 2);
        let e = two.excavate(&first, &tol).unwrap_err();
        assert!(
            e.to_string()
                .contains("excavation: the excavation removes no rock"),
            "{e}"
        );
    }

    #[test]
    fn an_excavation_outside_the_domain_is_refused() {
        let tol = Tolerance::default();
        let rock = grid(1, 1.0);
        let e = rock.excavate(&box_tunnel(50.0, 0.5), &tol).unwrap_err();
        assert!(e.to_string().contains("outside the domain"), "{e}");
    }

    #[test]
    fn a_non_convex_profile_removes_its_area_times_the_length() {
        let tol = Tolerance::default();
        let rock = grid(2, 8.0);
        // A U-shaped profile of area 3 * 3 - 1 * 2 = 7, along x (trend 90) through the domain.
        let u = Profile::Polygon {
            vertices: vec![
                [-1.5, -1.5],
                [1.5, -1.5],
                [1.5, 1.5],
                [0.5, 1.5],
                [0.5, -0.5],
                [-0.5, -0.5],
                [-0.5, 1.5],
                [-1.5, 1.5],
            ],
        };
        let tunnel = Excavation::new(ExcavationShape::Tunnel {
            profile: u,
            start: [-1.0, 4.3, 3.9],
            trend: 90.0,
            plunge: 0.0,
            length: 10.0,
        });
        let (out, _) = rock.excavate(&tunnel, &tol).unwrap();
        let exact = 7.0 * 8.0;
        assert!((volume(&rock) - volume(&out) - exact).abs() < 1e-9 * exact);
        // The U's axis is at y 4.3, z 3.9, across the blocks' faces y = 4 and z = 4. The
        // rock between its arms (y 3.8..4.8, z 3.4..5.4) is cut by the face z = 4: its
        // lower part, in the two blocks below (z < 4) on either side of y = 4, is closed in by
        // the arms, the U's floor and the blocks' faces, apart from the rest of its block. So
        // each of those blocks becomes two, at both x: 8 + 4 bodies.
        assert_eq!(out.body_parts().len(), 12);
    }

    #[test]
    fn a_shaft_removes_its_area_times_the_depth() {
        let tol = Tolerance::default();
        let rock = grid(2, 8.0);
        let shaft = Excavation::new(ExcavationShape::Shaft {
            profile: Profile::Circle {
                radius: 1.0,
                segments: 10,
            },
            top: [4.0, 4.0, 8.0],
            depth: 6.0,
        });
        let (out, report) = rock.excavate(&shaft, &tol).unwrap();
        let exact = shaft.volume().unwrap();
        let polygon = 0.5 * 10.0 * (std::f64::consts::TAU / 10.0).sin() * 6.0;
        assert!((exact - polygon).abs() < 1e-12);
        assert!((volume(&rock) - volume(&out) - exact).abs() < 1e-9 * exact);
        assert_eq!(
            report.cut_blocks, 8,
            "the shaft at the centre cuts all 8 blocks"
        );
        assert_eq!(out.body_parts().len(), 8);
    }

    #[test]
    fn a_plunging_tunnel_inside_the_rock_removes_its_section_times_its_length() {
        let tol = Tolerance::default();
        let rock = grid(3, 12.0);
        // From (3, 3, 9), 8 m down along trend 40, plunge 35: it stays well inside the box.
        let (t, p) = (40f64.to_radians(), 35f64.to_radians());
        let end = [
            3.0 + 8.0 * t.sin() * p.cos(),
            3.0 + 8.0 * t.cos() * p.cos(),
            9.0 - 8.0 * p.sin(),
        ];
        assert!(end.iter().all(|&c| (2.0..10.0).contains(&c)), "{end:?}");
        let tunnel = Excavation::new(ExcavationShape::Tunnel {
            profile: Profile::Horseshoe {
                radius: 1.0,
                wall: 0.5,
                segments: 6,
            },
            start: [3.0, 3.0, 9.0],
            trend: 40.0,
            plunge: 35.0,
            length: 8.0,
        });
        let (out, report) = rock.excavate(&tunnel, &tol).unwrap();
        // A half 6-gon of radius 1 on walls 0.5 high and 2 wide, by hand.
        let section = 0.5 * 6.0 * (std::f64::consts::PI / 6.0).sin() + 2.0 * 0.5;
        let exact = section * 8.0;
        assert!((report.volume_removed - exact).abs() < 1e-9 * exact);
        assert!((volume(&rock) - volume(&out) - exact).abs() < 1e-9 * exact);
        assert_eq!(report.removed_blocks, 0);
    }
}
