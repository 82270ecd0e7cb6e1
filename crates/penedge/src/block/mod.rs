//! Convex blocks: vertices, edges, faces and their derived data.
//!
//! A [`ConvexBlock`] is immutable once built; every derived quantity (edges with their two
//! faces, outward unit face planes, volume, centroid, bounding box, size) is computed once,
//! by [`ConvexBlock::new`] (vertices + faces) or [`ConvexBlock::from_planes`] (half-spaces),
//! which validate the input and return a [`BlockError`] naming what is wrong.

mod assemble;
mod build;
mod clearance;
mod error;
mod halfspace;
mod hull;
mod origin;
mod pose;
mod reach;
mod stored;
pub(crate) use assemble::BlockParts;
pub(crate) use clearance::Clearance;
pub(crate) use hull::hull_volume_and_area;

pub(crate) use error::readable;
pub use error::BlockError;
#[cfg(test)]
pub(crate) use error::Readable;
pub use origin::FaceOrigin;
#[cfg(test)]
pub(crate) use pose::assert_same_placed;
pub use pose::Pose;
pub(crate) use pose::{prefetch_value, Prefetch};
pub(crate) use reach::Reach;

/// The largest coordinate magnitude of a block: beyond it, products of four lengths (the
/// volume's moments) would overflow `f64`.
pub const MAX_COORDINATE: f64 = 1e50;

/// How far from 1 the length of a rotation given to [`ConvexBlock::try_rotated`] and
/// [`ConvexBlock::try_transformed`] may be: far above the rounding of a normalised
/// quaternion (a few units in the last place), or of one composed from many, far below any
/// visible distortion.
pub const UNIT_ROTATION: f64 = 1e-9;
/// The smallest size (bounding-box diagonal) of a block: below it, squared lengths would
/// underflow `f64`.
pub const MIN_SIZE: f64 = 1e-50;
/// The most half-spaces [`ConvexBlock::from_planes`] takes: its work grows with the fourth
/// power of their number in the worst case (many planes through one corner).
pub const MAX_HALFSPACES: usize = 128;

use crate::geometry::{Aabb, DVec3, Plane};
use crate::tolerance::Tolerance;
use glam::DQuat;

/// An edge: its two end vertices and the two faces that meet along it.
///
/// `faces[0]` runs from `vertices[0]` to `vertices[1]` (counter-clockwise seen from outside),
/// `faces[1]` the other way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// End vertices.
    pub vertices: [u32; 2],
    /// The two faces along the edge.
    pub faces: [u32; 2],
}

/// A validated convex polyhedron.
#[derive(Clone, Debug)]
pub struct ConvexBlock {
    vertices: Vec<DVec3>,
    face_offsets: Vec<u32>,
    face_vertices: Vec<u32>,
    planes: Vec<Plane>,
    origins: Vec<FaceOrigin>,
    edges: Vec<Edge>,
    /// The faces at each vertex, bit `f` for face `f` (empty past [`MASK_FACES`]
    /// faces).
    vertex_faces: Vec<u64>,
    clearance: Clearance,
    volume: f64,
    centroid: DVec3,
    bounds: Bounds,
    local: LocalCoordinates,
}

/// Sets of faces are bit masks (a bit per face in a `u64`) for blocks of at most this many
/// faces: the faces at each vertex ([`ConvexBlock::vertex_faces`]), the masks of the pair
/// query's distance tables and those of the classification. Larger blocks take lists.
pub(crate) const MASK_FACES: usize = 64;

/// The members of such a set (or of any `u64` of bits), lowest first: bit `k` gives `k`.
pub(crate) struct Bits(pub(crate) u64);

impl Iterator for Bits {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        (self.0 != 0).then(|| {
            let k = self.0.trailing_zeros() as usize;
            self.0 &= self.0 - 1;
            k
        })
    }
}

/// The faces at each vertex as bit masks (bit `f` for face `f`); empty for a block of more
/// than [`MASK_FACES`] faces.
pub(crate) fn vertex_face_masks(
    n_vertices: usize,
    face_offsets: &[u32],
    face_vertices: &[u32],
) -> Vec<u64> {
    let n_faces = face_offsets.len().saturating_sub(1);
    if n_faces > MASK_FACES {
        return Vec::new();
    }
    let mut masks = vec![0u64; n_vertices];
    for (f, w) in face_offsets.windows(2).enumerate() {
        for &v in &face_vertices[w[0] as usize..w[1] as usize] {
            masks[v as usize] |= 1 << f;
        }
    }
    masks
}

/// The bounding box with the two numbers that every pair query derives from it (the size
/// takes a square root), computed once.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounds {
    aabb: Aabb,
    size: f64,
    magnitude: f64,
}

impl Bounds {
    pub(crate) fn of(vertices: &[DVec3]) -> Self {
        let aabb = Aabb::of_points(vertices);
        Bounds {
            aabb,
            size: aabb.diagonal(),
            magnitude: aabb.magnitude(),
        }
    }
}

/// Vertex coordinates relative to vertex 0, in groups of four (each a structure of
/// arrays, the last group padded by repeating the last vertex), so that the distances of
/// all vertices to a plane are a few fixed-width loops that vectorise without run-time
/// length or aliasing checks. A repeated vertex changes neither a minimum nor a maximum.
#[derive(Clone, Debug, Default)]
pub(crate) struct LocalCoordinates {
    pub(crate) origin: DVec3,
    pub(crate) quads: Vec<Quad>,
}

/// Four vertices, one array per axis.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Quad {
    pub(crate) x: [f64; 4],
    pub(crate) y: [f64; 4],
    pub(crate) z: [f64; 4],
}

impl LocalCoordinates {
    pub(crate) fn of(vertices: &[DVec3]) -> Self {
        let origin = vertices[0];
        let last = vertices.len() - 1;
        let quads = (0..vertices.len().div_ceil(4))
            .map(|c| {
                let mut q = Quad::default();
                for k in 0..4 {
                    let v = vertices[(4 * c + k).min(last)] - origin;
                    (q.x[k], q.y[k], q.z[k]) = (v.x, v.y, v.z);
                }
                q
            })
            .collect();
        LocalCoordinates { origin, quads }
    }
}

impl ConvexBlock {
    /// Vertex positions.
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.planes.len()
    }

    /// The vertex indices of face `f`, counter-clockwise seen from outside.
    ///
    /// # Panics
    ///
    /// If there is no face `f` (`f >= self.n_faces()`).
    pub fn face(&self, f: usize) -> &[u32] {
        let (s, e) = (self.face_offsets[f], self.face_offsets[f + 1]);
        &self.face_vertices[s as usize..e as usize]
    }

    /// All faces, as vertex index lists.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> + '_ {
        (0..self.n_faces()).map(|f| self.face(f))
    }

    /// Outward unit face planes, one per face.
    pub fn planes(&self) -> &[Plane] {
        &self.planes
    }

    /// Where each face comes from (domain boundary or joint), one per face.
    pub fn face_origins(&self) -> &[FaceOrigin] {
        &self.origins
    }

    /// The block with its face origins replaced (one per face, in face order).
    pub fn with_face_origins(mut self, origins: Vec<FaceOrigin>) -> Result<Self, BlockError> {
        if origins.len() != self.n_faces() {
            return Err(BlockError::OriginCount {
                expected: self.n_faces(),
                got: origins.len(),
            });
        }
        self.origins = origins;
        Ok(self)
    }

    pub(crate) fn local(&self) -> &LocalCoordinates {
        &self.local
    }

    /// The faces at each vertex, bit `f` for face `f`; empty for a block of more than
    /// [`MASK_FACES`] faces.
    pub(crate) fn vertex_faces(&self) -> &[u64] {
        &self.vertex_faces
    }

    /// How the block's own face planes pass its vertices ([`Clearance`]).
    pub(crate) fn clearance(&self) -> Clearance {
        self.clearance
    }

    /// Edges, each with its two faces.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Volume.
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Centroid (centre of volume).
    pub fn centroid(&self) -> DVec3 {
        self.centroid
    }

    /// Axis-aligned bounding box.
    pub fn aabb(&self) -> Aabb {
        self.bounds.aabb
    }

    /// Characteristic length: the diagonal of the bounding box. Tolerances scale with it.
    pub fn size(&self) -> f64 {
        self.bounds.size
    }

    /// The largest absolute coordinate of the bounding box ([`Aabb::magnitude`]).
    pub(crate) fn magnitude(&self) -> f64 {
        self.bounds.magnitude
    }

    /// A rectangular box with the given corners.
    ///
    /// Each coordinate of `min` must be below the same coordinate of `max`.
    pub fn cuboid(min: [f64; 3], max: [f64; 3]) -> Result<ConvexBlock, BlockError> {
        if let Some(axis) =
            (0..3).find(|&k| min[k].partial_cmp(&max[k]) != Some(std::cmp::Ordering::Less))
        {
            return Err(BlockError::EmptyBox { axis });
        }
        let (a, b) = (min, max);
        let v = [
            [a[0], a[1], a[2]],
            [b[0], a[1], a[2]],
            [b[0], b[1], a[2]],
            [a[0], b[1], a[2]],
            [a[0], a[1], b[2]],
            [b[0], a[1], b[2]],
            [b[0], b[1], b[2]],
            [a[0], b[1], b[2]],
        ];
        let f: [&[usize]; 6] = [
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[3, 0, 4, 7],
        ];
        ConvexBlock::new(&v, &f)
    }

    /// The block moved by `offset` (a copy; topology, ids and face origins kept).
    pub fn translated(&self, offset: DVec3) -> ConvexBlock {
        self.transformed(DQuat::IDENTITY, offset, 1.0)
    }

    /// The block turned by `rotation` about the point `about` (the centroid, say): a point
    /// `x` goes to `about + rotation (x - about)`. A copy; topology, ids and face origins
    /// kept. `rotation` must be a unit quaternion (not checked: [`ConvexBlock::try_rotated`]
    /// checks it).
    pub fn rotated(&self, rotation: DQuat, about: DVec3) -> ConvexBlock {
        self.transformed(rotation, about - rotation * about, 1.0)
    }

    /// The block moved rigidly (rotation about the origin, then translation) and scaled
    /// about the origin by `scale` (> 0). Topology and ids are kept.
    pub fn transformed(&self, rotation: DQuat, translation: DVec3, scale: f64) -> ConvexBlock {
        let rigid = pose::Rigid::new(rotation, translation, scale);
        let vertices: Vec<DVec3> = self.vertices.iter().map(|&p| rigid.point(p)).collect();
        let planes: Vec<Plane> = self.planes.iter().map(|pl| rigid.plane(pl)).collect();
        ConvexBlock {
            clearance: Clearance::of(&vertices, &planes, &self.vertex_faces),
            bounds: Bounds::of(&vertices),
            local: LocalCoordinates::of(&vertices),
            vertices,
            face_offsets: self.face_offsets.clone(),
            face_vertices: self.face_vertices.clone(),
            planes,
            origins: self.origins.clone(),
            edges: self.edges.clone(),
            vertex_faces: self.vertex_faces.clone(),
            volume: self.volume * scale.powi(3),
            centroid: rigid.point(self.centroid),
        }
    }

    /// [`ConvexBlock::translated`], checked as a block is when it is built: an error, not a
    /// block, when the move leaves a coordinate NaN or infinite, beyond
    /// [`MAX_COORDINATE`], or rounds vertices together (a unit cube moved by 1e17: its
    /// coordinates are 16 apart there) or off their faces' planes. The checked form for a
    /// caller that moves blocks by amounts it does not control (the Python bindings);
    /// [`ConvexBlock::translated`] itself, and the mechanics' placing of blocks, do not check.
    pub fn try_translated(&self, offset: DVec3) -> Result<ConvexBlock, BlockError> {
        self.try_transformed(DQuat::IDENTITY, offset, 1.0)
    }

    /// [`ConvexBlock::rotated`], checked as [`ConvexBlock::try_translated`] is.
    pub fn try_rotated(&self, rotation: DQuat, about: DVec3) -> Result<ConvexBlock, BlockError> {
        self.try_transformed(rotation, about - rotation * about, 1.0)
    }

    /// [`ConvexBlock::transformed`], checked as [`ConvexBlock::try_translated`] is (a scale
    /// that is zero, negative or not finite fails the same checks), and the rotation must be
    /// a unit quaternion (its length within [`UNIT_ROTATION`] of 1: the rounding of a
    /// normalised one; another would scale and shear the block, whose volume and centroid,
    /// carried over, would then be wrong). The block returned is the unchecked one's, bit
    /// for bit.
    pub fn try_transformed(
        &self,
        rotation: DQuat,
        translation: DVec3,
        scale: f64,
    ) -> Result<ConvexBlock, BlockError> {
        let length = rotation.length();
        if !(length.is_finite() && (length - 1.0).abs() <= UNIT_ROTATION) {
            return Err(BlockError::NotUnitRotation { length });
        }
        let block = self.transformed(rotation, translation, scale);
        block.check_moved()?;
        Ok(block)
    }

    /// The checks of a block built from vertices and faces that a rigid move (or a scale)
    /// can break: finite coordinates within range, distinct vertices, every face vertex on
    /// its plane and every vertex inside every plane, at the default tolerance.
    fn check_moved(&self) -> Result<(), BlockError> {
        if let Some(vertex) = self.vertices.iter().position(|v| !v.is_finite()) {
            return Err(BlockError::NonFiniteVertex { vertex });
        }
        build::check_range(&self.vertices)?;
        let eps = Tolerance::default()
            .for_box(&Aabb::of_points(&self.vertices))
            .length;
        build::check_repeated_vertices(&self.vertices, eps)?;
        if let Some(face) = self
            .planes
            .iter()
            .position(|p| !(p.normal.is_finite() && p.point.is_finite()))
        {
            return Err(BlockError::BadPlane { face });
        }
        if !(self.volume.is_finite() && self.volume > 0.0) {
            return Err(BlockError::ZeroVolume);
        }
        stored::check_on_planes(self, eps)
    }
}

/// Equality by value: the same vertices (bit for bit, in the same order) and the same faces
/// (the same vertex loops, in the same order). Everything else of a block derives from these,
/// except where its faces come from ([`ConvexBlock::face_origins`]), which is provenance, not
/// shape, and not compared; nor are the face planes, which a block read back from a file
/// or made from half-spaces may carry with a different rounding.
impl PartialEq for ConvexBlock {
    fn eq(&self, other: &Self) -> bool {
        self.vertices == other.vertices
            && self.face_offsets == other.face_offsets
            && self.face_vertices == other.face_vertices
    }
}

#[cfg(test)]
mod tests;
