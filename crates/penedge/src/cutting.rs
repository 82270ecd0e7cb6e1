//! Splitting a convex block by a plane.
//!
//! Each vertex is classified by its signed distance `s = n · (x - p)` to the plane: within
//! `eps` it is *on* the plane and goes to both pieces, otherwise below (`s < 0`) or above.
//! Each edge whose ends lie strictly on opposite sides gets one cut point, interpolated from
//! its end with the lexicographically smaller coordinates, so that two blocks sharing the edge
//! get the same point, bit for bit. Each face is split into its part below and its part above;
//! the cap (the section of the block by the plane) is chained from the on-plane edges of the
//! faces below, so no angle sorting is involved. Pieces keep the parent's face planes and
//! origins; the cap gets the cutting plane (outward `+n` below, `-n` above) and the cut's
//! origin. Cost: linear in the size of the block; the caller owns the scratch buffers.

use crate::block::{BlockError, BlockParts, ConvexBlock, FaceOrigin};
use crate::geometry::{DVec3, Plane};
use crate::tolerance::Tolerance;

/// The two pieces of a block split by a plane; a side is `None` when nothing of the block
/// lies strictly on it.
#[derive(Clone, Debug)]
pub struct Split {
    /// The piece on the negative side (`normal · (x - point) <= 0`).
    pub below: Option<ConvexBlock>,
    /// The piece on the positive side.
    pub above: Option<ConvexBlock>,
}

/// Where a block lies relative to a plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// No vertex more than `eps` above the plane.
    Below,
    /// No vertex more than `eps` below the plane.
    Above,
    /// Vertices on both sides: the plane cuts the block.
    Across,
}

/// Splits `block` by `plane` (unit normal), with the length threshold of `tol` at the
/// block's own scale; the cap faces get an unknown origin.
///
/// A plane whose normal is not a finite unit vector (within 1e-12) or whose point is not
/// finite is refused ([`BlockError::DegenerateCut`]): the caps would carry it.
pub fn split_block(
    block: &ConvexBlock,
    plane: &Plane,
    tol: &Tolerance,
) -> Result<Split, BlockError> {
    let unit = (plane.normal.length() - 1.0).abs() <= 1e-12;
    if !(unit && plane.normal.is_finite() && plane.point.is_finite()) {
        return Err(BlockError::DegenerateCut {
            reason: "the cutting plane needs a finite unit normal and a finite point",
        });
    }
    let eps = tol.for_box(&block.aabb()).length;
    let mut splitter = Splitter::default();
    Ok(match splitter.prepare(block, plane, eps)? {
        Side::Below => Split {
            below: Some(block.clone()),
            above: None,
        },
        Side::Above => Split {
            below: None,
            above: Some(block.clone()),
        },
        Side::Across => {
            let [below, above] = splitter.finish(FaceOrigin::Unknown)?;
            Split {
                below: Some(below),
                above: Some(above),
            }
        }
    })
}

/// Scratch buffers for splitting blocks, reused from one cut to the next.
#[derive(Clone, Debug, Default)]
pub struct Splitter {
    plane: Option<Plane>,
    side: Vec<i8>,
    n_vertices: usize,
    points: Vec<DVec3>,
    cuts: Vec<(u32, u32, u32)>,
    below: BlockParts,
    above: BlockParts,
    cap: Vec<u32>,
    cap_edges: Vec<(u32, u32)>,
    scratch: Scratch,
}

/// Buffers for tidying and assembling a piece.
#[derive(Clone, Debug, Default)]
struct Scratch {
    vertices: Vec<u32>,
    half_edges: Vec<(u64, u32, u32)>,
}

impl Splitter {
    /// Classifies the block against the plane; when it lies across, prepares both pieces'
    /// faces and the section (see [`Splitter::section`]), to be finished by
    /// [`Splitter::finish`].
    pub fn prepare(
        &mut self,
        block: &ConvexBlock,
        plane: &Plane,
        eps: f64,
    ) -> Result<Side, BlockError> {
        let side = self.classify(block, plane, eps);
        if side == Side::Across {
            self.plane = Some(*plane);
            self.split_faces(block);
            self.chain_cap()?;
        }
        Ok(side)
    }

    /// The section of the block prepared last by the plane: a convex polygon,
    /// counter-clockwise about the plane's normal.
    pub fn section(&self) -> impl Iterator<Item = DVec3> + '_ {
        self.cap.iter().map(|&i| self.points[i as usize])
    }

    /// The two pieces (below, above) of the block prepared last; the cap faces get `origin`.
    pub fn finish(&mut self, origin: FaceOrigin) -> Result<[ConvexBlock; 2], BlockError> {
        let plane = self.plane.take().ok_or(BlockError::DegenerateCut {
            reason: "no block prepared",
        })?;
        let flipped = Plane {
            normal: -plane.normal,
            point: plane.point,
        };
        let scratch = &mut self.scratch;
        let below = close_piece(
            &mut self.below,
            &self.points,
            &self.cap,
            plane,
            origin,
            scratch,
        );
        // Reversed from the same first vertex: both caps are fanned into the same triangles,
        // so the pieces' volumes add up to the block's even where the cap is not quite flat
        // (vertices within the threshold of the plane count as on it).
        self.cap[1..].reverse();
        let above = close_piece(
            &mut self.above,
            &self.points,
            &self.cap,
            flipped,
            origin,
            scratch,
        );
        self.cap[1..].reverse();
        Ok([below?, above?])
    }

    fn classify(&mut self, block: &ConvexBlock, plane: &Plane, eps: f64) -> Side {
        self.side.clear();
        let (mut any_below, mut any_above) = (false, false);
        for &v in block.vertices() {
            let s = plane.distance(v);
            let side = if s < -eps {
                -1
            } else if s > eps {
                1
            } else {
                0
            };
            any_below |= side < 0;
            any_above |= side > 0;
            self.side.push(side);
        }
        match (any_below, any_above) {
            (true, true) => Side::Across,
            (_, false) => Side::Below,
            (false, true) => Side::Above,
        }
    }

    /// Splits every face into its parts below and above, adding cut points.
    fn split_faces(&mut self, block: &ConvexBlock) {
        let plane = self.plane.expect("plane set by prepare");
        self.n_vertices = block.vertices().len();
        self.points.clear();
        self.points.extend_from_slice(block.vertices());
        self.cuts.clear();
        for parts in [&mut self.below, &mut self.above] {
            parts.face_offsets.clear();
            parts.face_offsets.push(0);
            parts.face_vertices.clear();
            parts.planes.clear();
            parts.origins.clear();
        }
        for f in 0..block.n_faces() {
            let face = block.face(f);
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                let sa = self.side[a as usize];
                if sa <= 0 {
                    self.below.face_vertices.push(a);
                }
                if sa >= 0 {
                    self.above.face_vertices.push(a);
                }
                if sa * self.side[b as usize] < 0 {
                    let c = self.cut_point(a, b, &plane);
                    self.below.face_vertices.push(c);
                    self.above.face_vertices.push(c);
                }
            }
            let (plane_f, origin) = (block.planes()[f], block.face_origins()[f]);
            close_face(&mut self.below, plane_f, origin);
            close_face(&mut self.above, plane_f, origin);
        }
    }

    /// The cut point of edge (a, b), shared by the faces on either side of it.
    fn cut_point(&mut self, a: u32, b: u32, plane: &Plane) -> u32 {
        let key = (a.min(b), a.max(b));
        if let Some(&(_, _, c)) = self.cuts.iter().find(|c| (c.0, c.1) == key) {
            return c;
        }
        let (mut p, mut q) = (self.points[a as usize], self.points[b as usize]);
        if q.to_array() < p.to_array() {
            std::mem::swap(&mut p, &mut q);
        }
        let (sp, sq) = (plane.distance(p), plane.distance(q));
        let c = self.points.len() as u32;
        self.points.push(p + (q - p) * (sp / (sp - sq)));
        self.cuts.push((key.0, key.1, c));
        c
    }

    fn on_plane(&self, i: u32) -> bool {
        i as usize >= self.n_vertices || self.side[i as usize] == 0
    }

    /// Chains the on-plane edges of the faces below into the cap loop (counter-clockwise
    /// about the plane's normal: each face below runs such an edge x -> y, the cap y -> x).
    fn chain_cap(&mut self) -> Result<(), BlockError> {
        self.cap_edges.clear();
        let parts = &self.below;
        for f in 0..parts.n_faces() {
            let (s, e) = (parts.face_offsets[f], parts.face_offsets[f + 1]);
            let face = &parts.face_vertices[s as usize..e as usize];
            if face.len() < 3 {
                continue;
            }
            for k in 0..face.len() {
                let (x, y) = (face[k], face[(k + 1) % face.len()]);
                if self.on_plane(x) && self.on_plane(y) {
                    self.cap_edges.push((y, x));
                }
            }
        }
        self.cap = chain_loop(&self.cap_edges).ok_or(BlockError::DegenerateCut {
            reason: "the section of the block by the plane is not one polygon",
        })?;
        Ok(())
    }
}

fn close_face(parts: &mut BlockParts, plane: Plane, origin: FaceOrigin) {
    let start = *parts.face_offsets.last().expect("offsets start with 0") as usize;
    if parts.face_vertices.len() - start < 3 {
        parts.face_vertices.truncate(start);
        return;
    }
    parts.face_offsets.push(parts.face_vertices.len() as u32);
    parts.planes.push(plane);
    parts.origins.push(origin);
}

/// The directed edges as one closed loop visiting each edge once, if they form one.
fn chain_loop(edges: &[(u32, u32)]) -> Option<Vec<u32>> {
    let (start, mut next) = *edges.first()?;
    let mut loop_ = vec![start];
    while next != start {
        if loop_.len() >= edges.len() || loop_.contains(&next) {
            return None;
        }
        loop_.push(next);
        let from = next;
        let mut out = edges.iter().filter(|e| e.0 == from);
        next = out.next()?.1;
        if out.next().is_some() {
            return None;
        }
    }
    (loop_.len() == edges.len() && loop_.len() >= 3).then_some(loop_)
}

/// Adds the cap to one piece's faces and assembles the piece.
fn close_piece(
    parts: &mut BlockParts,
    points: &[DVec3],
    cap: &[u32],
    plane: Plane,
    origin: FaceOrigin,
    scratch: &mut Scratch,
) -> Result<ConvexBlock, BlockError> {
    let mut piece = BlockParts {
        vertices: Vec::with_capacity(points.len()),
        face_offsets: std::mem::take(&mut parts.face_offsets),
        face_vertices: std::mem::take(&mut parts.face_vertices),
        planes: std::mem::take(&mut parts.planes),
        origins: std::mem::take(&mut parts.origins),
    };
    piece.face_vertices.extend_from_slice(cap);
    close_face(&mut piece, plane, origin);
    piece.tidy(points, &mut scratch.vertices);
    ConvexBlock::assemble_with(piece, &mut scratch.half_edges)
}

#[cfg(test)]
mod tests;
