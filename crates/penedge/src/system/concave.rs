//! Concave blocks: a body made of convex parts glued along internal faces (see
//! `docs/bodies.md` for why, `docs/concave-blocks.md` for the rules).
//!
//! A [`BlockSystem`] keeps one body id per convex block; blocks that share an id are the parts
//! of one concave block. [`BlockSystem::with_bodies`] checks that the parts of each body are
//! glued face to face (connected through face-face contacts of positive area) and do not
//! overlap, and finds the *internal faces*: the overlaps of the faces of two parts of one body
//! that coincide with opposite normals. A part face covered entirely by such overlaps is
//! inside the body and never makes a contact; a face covered in part (the taller part of an
//! L-block cut vertically) is a real face of the block where it is not covered.

use super::BlockSystem;
use crate::block::ConvexBlock;
use crate::body::MassProperties;
use crate::classify::{Feature, PairResult};
use crate::contact::Detector;
use crate::geometry::{newell_normal, DVec3};
use crate::overlap::{clip, overlap, Inside};
use crate::tolerance::{Thresholds, Tolerance};
use thiserror::Error;

/// The overlap of two faces, of two parts of one body, that coincide with opposite normals:
/// the glue between the parts.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InternalFace {
    /// The two parts (block ids), smaller first.
    pub parts: [u32; 2],
    /// The face of each part, in the order of `parts`.
    pub faces: [u32; 2],
    /// The area of the overlap.
    pub area: f64,
}

/// Why the body ids of a system are refused.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ConcaveError {
    /// Not one body id per block.
    #[error("{given} body ids given for {blocks} blocks (one per block is needed)")]
    Count {
        /// Ids given.
        given: usize,
        /// Blocks in the system.
        blocks: usize,
    },
    /// Two parts of one body overlap.
    #[error(
        "body {body}: its parts (blocks) {a} and {b} overlap; the parts of a concave block \
         may only touch, face to face"
    )]
    Overlap {
        /// The body.
        body: u32,
        /// One part.
        a: u32,
        /// The other part.
        b: u32,
    },
    /// Some parts of a body are not glued to the rest of it.
    #[error(
        "body {body}: its parts (blocks) {detached:?} do not touch the rest of the body \
         along a face; the parts of a concave block must be glued face to face"
    )]
    Detached {
        /// The body.
        body: u32,
        /// The parts not connected, through face-face contacts, to the body's first part.
        detached: Vec<u32>,
    },
}

/// A face of a part: `(block, face)`.
type PartFace = (u32, u32);

/// The body ids and glue of a system with concave blocks (absent: each block its own body).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Glue {
    /// Per block, its body id.
    pub(super) ids: Vec<u32>,
    /// The internal faces, sorted by parts.
    pub(super) internal: Vec<InternalFace>,
    /// `(block, face)` of the part faces covered entirely by internal faces, sorted.
    pub(super) covered: Vec<PartFace>,
    /// `(block, face)` of every part face with some internal face on it, sorted.
    pub(super) glued: Vec<PartFace>,
    /// Per block, whether its body has more than one part.
    pub(super) multi: Vec<bool>,
}

impl BlockSystem {
    /// This system with the given body id per block: blocks that share an id are the convex
    /// parts of one (concave) block. Checks that the parts of each body touch face to face,
    /// all connected, and do not overlap, and finds the internal faces (at the thresholds of
    /// `tol` for each pair of parts).
    ///
    /// ```
    /// use penedge::{BlockSystem, ConvexBlock, Tolerance};
    /// // An L-block of two boxes, and a box on it.
    /// let system = BlockSystem::new(vec![
    ///     ConvexBlock::cuboid([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap(),
    ///     ConvexBlock::cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]).unwrap(),
    ///     ConvexBlock::cuboid([1.5, 0.0, 1.0], [2.5, 1.0, 2.0]).unwrap(),
    /// ]);
    /// let system = system.with_bodies(vec![0, 0, 1], &Tolerance::default()).unwrap();
    /// assert_eq!(system.body_parts(), vec![(0, vec![0, 1]), (1, vec![2])]);
    /// assert_eq!(system.internal_faces().len(), 1); // the top of part 0 under part 1
    /// assert!((system.internal_faces()[0].area - 1.0).abs() < 1e-9);
    /// ```
    pub fn with_bodies(self, ids: Vec<u32>, tol: &Tolerance) -> Result<Self, ConcaveError> {
        self.with_bodies_among(ids, None, tol)
    }

    /// [`BlockSystem::with_bodies`], with the broad phase's candidate pairs when the caller
    /// has them already (an excavation), else found here.
    pub(crate) fn with_bodies_among(
        mut self,
        ids: Vec<u32>,
        pairs: Option<&[[u32; 2]]>,
        tol: &Tolerance,
    ) -> Result<Self, ConcaveError> {
        if ids.len() != self.len() {
            return Err(ConcaveError::Count {
                given: ids.len(),
                blocks: self.len(),
            });
        }
        self.glue = None;
        if ids.iter().enumerate().all(|(i, &b)| b as usize == i) {
            return Ok(self);
        }
        let mut counts = std::collections::HashMap::<u32, u32>::new();
        for &b in &ids {
            *counts.entry(b).or_default() += 1;
        }
        let found;
        let pairs = match pairs {
            Some(pairs) => pairs,
            None => {
                found = self.candidate_pairs(tol);
                &found
            }
        };
        let multi: Vec<bool> = ids.iter().map(|b| counts[b] > 1).collect();
        let mut det = Detector::new(*tol);
        let mut internal = Vec::new();
        // Pairs of parts of one body: within the broad phase's candidates (boxes that touch).
        for &[i, j] in pairs {
            if ids[i as usize] != ids[j as usize] {
                continue;
            }
            let (a, b) = (&self.blocks[i as usize], &self.blocks[j as usize]);
            match meeting(&mut det, a, b) {
                Meeting::Overlap => {
                    return Err(ConcaveError::Overlap {
                        body: ids[i as usize],
                        a: i,
                        b: j,
                    })
                }
                Meeting::Glued(faces, area) => internal.push(InternalFace {
                    parts: [i, j],
                    faces,
                    area,
                }),
                Meeting::Other => {}
            }
        }
        check_connected(&ids, &internal)?;
        let (covered, glued) = self.covered_faces(&internal, tol);
        self.glue = Some(Glue {
            ids,
            internal,
            covered,
            glued,
            multi,
        });
        Ok(self)
    }

    /// This system without the bodies `drop` (body ids; every part of each), the others'
    /// glue kept as it was (their internal faces are within a body): the blocks renumbered
    /// in order, the body ids `0..` in the order of each body's first part.
    pub(crate) fn without_bodies(mut self, drop: &[u32]) -> BlockSystem {
        let ids = self.body_ids();
        let mut dropped = drop.to_vec();
        dropped.sort_unstable();
        let keep: Vec<bool> = ids
            .iter()
            .map(|b| dropped.binary_search(b).is_err())
            .collect();
        // The new index of each kept block.
        let mut index = vec![u32::MAX; ids.len()];
        let mut n = 0u32;
        for (k, &kept) in keep.iter().enumerate() {
            if kept {
                index[k] = n;
                n += 1;
            }
        }
        let blocks: Vec<ConvexBlock> = std::mem::take(&mut self.blocks)
            .into_iter()
            .zip(&keep)
            .filter_map(|(b, &kept)| kept.then_some(b))
            .collect();
        let glue = self.glue.take().and_then(|g| {
            let mut renumber = std::collections::HashMap::new();
            let ids: Vec<u32> = g
                .ids
                .iter()
                .zip(&keep)
                .filter(|(_, &kept)| kept)
                .map(|(&b, _)| {
                    let next = renumber.len() as u32;
                    *renumber.entry(b).or_insert(next)
                })
                .collect();
            // Each block its own body: no glue, as `with_bodies` leaves it.
            if ids.iter().enumerate().all(|(i, &b)| b as usize == i) {
                return None;
            }
            let part = |(block, face): PartFace| {
                keep[block as usize].then(|| (index[block as usize], face))
            };
            Some(Glue {
                ids,
                internal: g
                    .internal
                    .iter()
                    .filter(|f| keep[f.parts[0] as usize])
                    .map(|f| InternalFace {
                        parts: f.parts.map(|p| index[p as usize]),
                        ..*f
                    })
                    .collect(),
                covered: g.covered.iter().filter_map(|&f| part(f)).collect(),
                glued: g.glued.iter().filter_map(|&f| part(f)).collect(),
                multi: g
                    .multi
                    .iter()
                    .zip(&keep)
                    .filter_map(|(&m, &kept)| kept.then_some(m))
                    .collect(),
            })
        });
        BlockSystem {
            blocks,
            glue,
            ..self
        }
    }

    /// The body id of each block (by default, its own index).
    pub fn body_ids(&self) -> Vec<u32> {
        match &self.glue {
            Some(g) => g.ids.clone(),
            None => (0..self.len() as u32).collect(),
        }
    }

    /// The body id of block `block`.
    ///
    /// # Panics
    ///
    /// If the system has no block `block`, as indexing [`BlockSystem::blocks`] does (with
    /// or without concave bodies: without them it returned the id given, for a block that
    /// does not exist).
    pub fn body_of(&self, block: u32) -> u32 {
        let n = self.len();
        assert!(
            (block as usize) < n,
            "block {block} out of range: the system has {n} blocks"
        );
        match &self.glue {
            Some(g) => g.ids[block as usize],
            None => block,
        }
    }

    /// Whether some body has more than one part.
    pub fn has_concave(&self) -> bool {
        self.glue.is_some()
    }

    /// Whether block `block` is one of several parts of a body.
    pub(super) fn is_part_of_concave(&self, block: u32) -> bool {
        self.glue.as_ref().is_some_and(|g| g.multi[block as usize])
    }

    /// The bodies, by ascending id, each with its parts (block ids, ascending).
    pub fn body_parts(&self) -> Vec<(u32, Vec<u32>)> {
        let mut order: Vec<(u32, u32)> = (0..self.len() as u32)
            .map(|k| (self.body_of(k), k))
            .collect();
        order.sort_unstable();
        let mut out: Vec<(u32, Vec<u32>)> = Vec::new();
        for (body, block) in order {
            match out.last_mut() {
                Some((b, parts)) if *b == body => parts.push(block),
                _ => out.push((body, vec![block])),
            }
        }
        out
    }

    /// The mass properties (volume, centroid, inertia per unit density) of each body of
    /// [`BlockSystem::body_parts`], exact for the union of its parts (divergence theorem).
    pub fn body_mass_properties(&self) -> Vec<(u32, MassProperties)> {
        self.body_parts()
            .into_iter()
            .map(|(body, parts)| {
                let parts: Vec<_> = parts
                    .iter()
                    .map(|&k| self.blocks[k as usize].clone())
                    .collect();
                let mass = MassProperties::of_parts(&parts).expect("a body has a part");
                (body, mass)
            })
            .collect()
    }

    /// The internal faces (glue between parts of one body), sorted by parts.
    pub fn internal_faces(&self) -> &[InternalFace] {
        self.glue.as_ref().map_or(&[], |g| &g.internal)
    }

    /// Whether face `face` of block `block` is inside its body: covered entirely by
    /// internal faces.
    pub fn is_internal_face(&self, block: u32, face: u32) -> bool {
        self.glue
            .as_ref()
            .is_some_and(|g| g.covered.binary_search(&(block, face)).is_ok())
    }

    /// Whether face `face` of block `block` has some internal face on it.
    pub(super) fn is_glued_face(&self, block: u32, face: u32) -> bool {
        self.glue
            .as_ref()
            .is_some_and(|g| g.glued.binary_search(&(block, face)).is_ok())
    }

    /// The part faces with glue on them, and those of them covered entirely: the overlaps'
    /// areas add up to the face's area within the length threshold times its perimeter.
    fn covered_faces(
        &self,
        internal: &[InternalFace],
        tol: &Tolerance,
    ) -> (Vec<PartFace>, Vec<PartFace>) {
        let mut sums: Vec<(PartFace, f64)> = internal
            .iter()
            .flat_map(|g| [0, 1].map(|s| ((g.parts[s], g.faces[s]), g.area)))
            .collect();
        sums.sort_unstable_by_key(|s| s.0);
        // Summed per face (the list is sorted by face).
        let mut totals: Vec<(PartFace, f64)> = Vec::new();
        for (key, area) in sums {
            match totals.last_mut() {
                Some((k, total)) if *k == key => *total += area,
                _ => totals.push((key, area)),
            }
        }
        let mut glued = Vec::with_capacity(totals.len());
        let mut covered = Vec::new();
        for (key, total) in totals {
            glued.push(key);
            let block = &self.blocks[key.0 as usize];
            let face = block.face(key.1 as usize);
            let v = block.vertices();
            let points = face.iter().map(|&k| v[k as usize]);
            let face_area = newell_normal(points.clone()).length() / 2.0;
            let perimeter: f64 = (0..face.len())
                .map(|k| (v[face[k] as usize] - v[face[(k + 1) % face.len()] as usize]).length())
                .sum();
            let length = tol.for_box(&block.aabb()).length;
            if total >= face_area - length * perimeter {
                covered.push(key);
            }
        }
        (covered, glued)
    }
}

/// How two parts of one body meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Meeting {
    /// Their interiors overlap: a penetration deeper than the pair's gap.
    Overlap,
    /// They touch face to face: the face of each (in the order asked) and the area of the
    /// overlap of the two faces.
    Glued([u32; 2], f64),
    /// Apart, or touching along an edge or at a vertex.
    Other,
}

/// How parts `a` and `b` of one body meet (docs/concave-blocks.md, "A valid concave block").
///
/// The detection's answer, but for `Penetrating`, which is confirmed by the depth of the
/// overlap before the parts are refused: the shortest translation that separates them
/// ([`crate::overlap::Overlap::min_translation`], over the separating-axis candidates with
/// both blocks' extents taken from their vertices) must be longer than the pair's gap, the
/// policy's own line between touching and penetrating (docs/tolerance.md, rule 3). The
/// classification also says `Penetrating` when no face of a block passes within the length
/// threshold of every point of the contact; the parts of a fine excavation are long needles
/// whose stored face planes are tilted by more than that over their length (a vertex 1.3e-8
/// off the plane of its own face, with a length threshold of 1.0e-8), and parts glued along
/// such a face touch although no face of the pair holds all the contact's points. Parts not
/// confirmed to overlap touch: their internal face, if any, is found from the faces' own
/// vertices ([`coplanar_faces`]).
pub(super) fn meeting(det: &mut Detector, a: &ConvexBlock, b: &ConvexBlock) -> Meeting {
    match det.detect_with_geometry(a, b) {
        (PairResult::Contact(c), Some(g)) if g.area() > 0.0 => match (c.feature_a, c.feature_b) {
            (Feature::Face(fa), Feature::Face(fb)) => Meeting::Glued([fa, fb], g.area()),
            _ => Meeting::Other,
        },
        (PairResult::Penetrating, _) => {
            let th = det.thresholds(a, b);
            let depth = overlap(a, b, det.tolerance()).map_or(0.0, |o| o.min_translation.length());
            if depth > th.gap {
                Meeting::Overlap
            } else {
                coplanar_faces(a, b, th)
            }
        }
        _ => Meeting::Other,
    }
}

/// The faces of `a` and `b` that lie on each other with opposite normals, from their
/// vertices alone (the stored planes are what the classification could not settle): the
/// faces' Newell normals opposite within the sine of "lies in", every vertex of each face
/// within the length threshold of the other face's plane, and the overlap of the two
/// polygons (one clipped by the other's sides) wider than the length threshold (its area
/// above the threshold times half its perimeter; a narrower strip is an edge, as in the
/// classification). The largest such overlap; `Other` when there is none.
fn coplanar_faces(a: &ConvexBlock, b: &ConvexBlock, th: Thresholds) -> Meeting {
    let face = |block: &ConvexBlock, f: usize| -> (Vec<DVec3>, DVec3) {
        let v = block.vertices();
        let points: Vec<DVec3> = block.face(f).iter().map(|&k| v[k as usize]).collect();
        let normal = newell_normal(points.iter().copied()).normalize_or_zero();
        (points, normal)
    };
    let on = |points: &[DVec3], normal: DVec3, origin: DVec3| {
        points
            .iter()
            .all(|&p| normal.dot(p - origin).abs() <= th.length)
    };
    let faces_b: Vec<_> = (0..b.n_faces()).map(|f| face(b, f)).collect();
    let mut best = Meeting::Other;
    let mut best_area = 0.0;
    let (mut piece, mut spare) = (Vec::new(), Vec::new());
    for fa in 0..a.n_faces() {
        let (pa, na) = face(a, fa);
        for (fb, (pb, nb)) in faces_b.iter().enumerate() {
            let nb = *nb;
            if (na + nb).length() > th.sine || !on(pb, na, pa[0]) || !on(&pa, nb, pb[0]) {
                continue;
            }
            // Relative to a vertex of A's face; B's face is counter-clockwise about `nb`,
            // so A's side of its edge p -> q is behind the plane of normal (q - p) x nb.
            let r = pa[0];
            piece.clear();
            piece.extend(pa.iter().map(|&p| p - r));
            for k in 0..pb.len() {
                let (p, q) = (pb[k] - r, pb[(k + 1) % pb.len()] - r);
                let n = (q - p).cross(nb);
                clip(&mut piece, &mut spare, n, n.dot(p), Inside::Closed);
                if piece.len() < 3 {
                    break;
                }
            }
            if piece.len() < 3 {
                continue;
            }
            let area = newell_normal(piece.iter().copied()).length() / 2.0;
            let perimeter: f64 = (0..piece.len())
                .map(|k| (piece[(k + 1) % piece.len()] - piece[k]).length())
                .sum();
            if area > th.length * perimeter / 2.0 && area > best_area {
                best_area = area;
                best = Meeting::Glued([fa as u32, fb as u32], area);
            }
        }
    }
    best
}

/// Checks that the parts of every body are connected through internal faces.
fn check_connected(ids: &[u32], internal: &[InternalFace]) -> Result<(), ConcaveError> {
    let mut root: Vec<u32> = (0..ids.len() as u32).collect();
    fn find(root: &mut [u32], mut k: u32) -> u32 {
        while root[k as usize] != k {
            root[k as usize] = root[root[k as usize] as usize];
            k = root[k as usize];
        }
        k
    }
    for g in internal {
        let (a, b) = (find(&mut root, g.parts[0]), find(&mut root, g.parts[1]));
        root[a.max(b) as usize] = a.min(b);
    }
    // The first part of each body, by block id.
    let mut first = std::collections::HashMap::<u32, u32>::new();
    let mut detached = std::collections::BTreeMap::<u32, Vec<u32>>::new();
    for (k, &body) in ids.iter().enumerate() {
        let k = k as u32;
        let head = *first.entry(body).or_insert(k);
        if find(&mut root, k) != find(&mut root, head) {
            detached.entry(body).or_default().push(k);
        }
    }
    match detached.into_iter().next() {
        Some((body, detached)) => Err(ConcaveError::Detached { body, detached }),
        None => Ok(()),
    }
}
