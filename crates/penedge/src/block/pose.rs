//! Rigid placements of a block: a block at a new pose, computed into an existing block
//! without allocating (the time-stepping path of [`crate::system::ContactTracker`]).

use super::{Bounds, Clearance, ConvexBlock, LocalCoordinates, Quad};
use crate::geometry::{DVec3, Plane};
use glam::{DMat3, DQuat};

/// A rigid placement: a rotation about the origin, then a translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Unit quaternion.
    pub rotation: DQuat,
    /// Translation.
    pub translation: DVec3,
}

/// How far two normalised quaternions of one rotation may differ in a component
/// ([`Pose::same_placement`]).
pub const ROTATION_ROUNDING: f64 = 4.0 * f64::EPSILON;

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}

impl Pose {
    /// No motion.
    pub const IDENTITY: Pose = Pose {
        rotation: DQuat::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// A pose from a rotation (normalised here) and a translation; `None` when either has a
    /// NaN or infinite component or the rotation is zero. Any finite non-zero multiple of a
    /// quaternion is its rotation: one whose length is not finite (its square overflows,
    /// `1e200 q`) or below 1e-150 (its square underflows or loses bits, `1e-200 q`) is
    /// first divided by its largest component, where dividing by its length gave the zero
    /// quaternion (every block placed at its translation) or was refused as zero. Others
    /// (every quaternion of length at least 1e-150) are divided by their length as before,
    /// bit for bit.
    pub fn new(rotation: DQuat, translation: DVec3) -> Option<Pose> {
        if !(rotation.is_finite() && translation.is_finite()) {
            return None;
        }
        let mut rotation = rotation;
        let mut len = rotation.length();
        if !(len.is_finite() && len >= 1e-150) {
            let largest = glam::DVec4::from(rotation).abs().max_element();
            if largest == 0.0 {
                return None;
            }
            rotation /= largest;
            len = rotation.length();
        }
        (len > 0.0).then(|| Pose {
            rotation: rotation / len,
            translation,
        })
    }

    /// Whether `self` and `other` place a block alike: equal translations and the same
    /// rotation. A rotation is compared, not its quaternion: `q` and `-q` are one rotation,
    /// and so are `q` and any positive multiple of it once normalised ([`Pose::new`]). The
    /// rule, on the normalised quaternions: `other`'s is turned into the hemisphere of
    /// `self`'s (negated when their dot product is negative, an exact step), and then every
    /// component must agree within `ROTATION_ROUNDING` (4 units of `2^-52`: the rounding of
    /// normalising two multiples of one quaternion, a few units in the last place of
    /// components at most 1). The relative angle of two such rotations is at most about
    /// `2 × 4 × 2^-52 × 2` radians, 4e-15: below the rounding of the placed coordinates.
    /// Both poses should come from [`Pose::new`] (unit quaternions).
    pub fn same_placement(&self, other: &Pose) -> bool {
        if self.translation != other.translation {
            return false;
        }
        let (a, b) = (self.rotation, other.rotation);
        let b = if a.dot(b) < 0.0 { -b } else { b };
        glam::DVec4::from(a - b).abs().max_element() <= ROTATION_ROUNDING
    }

    /// The image of point `p`.
    #[inline]
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }

    /// An upper bound of how far any point within `radius` of `centre` moves from pose
    /// `self` to pose `to`: the centre's displacement plus `2 sin(θ / 2) radius`, `θ` the
    /// angle of the relative rotation.
    pub fn displacement_bound(&self, to: &Pose, centre: DVec3, radius: f64) -> f64 {
        // About the origin (the mechanics' bodies, about their centroids), a finite rotation
        // turns the centre into zeros of either sign: the images are the translations but
        // for the signs of zero coordinates, which neither the distance nor the rounding
        // below sees (the same bits without the two rotations of a zero vector).
        let (from, image) =
            if centre == DVec3::ZERO && self.rotation.is_finite() && to.rotation.is_finite() {
                (self.translation, to.translation)
            } else {
                (self.apply(centre), to.apply(centre))
            };
        let shift = image.distance(from);
        // The relative rotation's vector part has length sin(θ / 2): a point at distance r
        // from the axis moves along a chord of 2 sin(θ / 2) r.
        let relative = to.rotation * self.rotation.conjugate();
        let sin_half = relative.xyz().length().min(1.0);
        // Rounding of the rotated coordinates: a few units in the last place of each.
        let rounding = 8.0 * f64::EPSILON * (image.abs().max_element() + radius);
        shift + 2.0 * sin_half * radius + rounding
    }
}

impl ConvexBlock {
    /// Overwrites this block with `reference` placed at `pose`, reusing this block's buffers
    /// (no allocation once both have the same topology, the usual case in time stepping).
    /// Topology, face origins and volume are copied from `reference`.
    pub fn place_from(&mut self, reference: &ConvexBlock, pose: &Pose) {
        if self.face_offsets != reference.face_offsets
            || self.face_vertices != reference.face_vertices
            || self.edges != reference.edges
        {
            self.face_offsets.clone_from(&reference.face_offsets);
            self.face_vertices.clone_from(&reference.face_vertices);
            self.edges.clone_from(&reference.edges);
            self.vertex_faces.clone_from(&reference.vertex_faces);
        }
        self.origins.clone_from(&reference.origins);
        self.volume = reference.volume;
        self.place_geometry(reference, pose);
    }

    /// Starts loading part of this block ([`Prefetch`]). A hint to the processor, with no
    /// effect on any result: placing the scattered blocks of a tracker's step, and querying
    /// their pairs, wait on memory, one dependent load after another.
    #[inline(always)]
    pub(crate) fn prefetch(&self, what: Prefetch) {
        match what {
            Prefetch::Block => prefetch_bytes(std::slice::from_ref(self)),
            Prefetch::Points => {
                prefetch_bytes(&self.vertices);
                prefetch_bytes(&self.planes);
            }
            Prefetch::Coordinates | Prefetch::Query => {
                prefetch_bytes(&self.vertices);
                prefetch_bytes(&self.planes);
                prefetch_bytes(&self.local.quads);
                if what == Prefetch::Query {
                    prefetch_bytes(&self.edges);
                    prefetch_bytes(&self.vertex_faces);
                }
            }
        }
    }

    /// [`ConvexBlock::place_from`] for a block that already has `reference`'s topology, face
    /// origins and volume (a block placed from it before, as in the tracker): only the
    /// coordinates and what derives from them are written. Placing is bound by memory
    /// traffic, and the topology is a third of a block's bytes.
    pub(crate) fn place_geometry(&mut self, reference: &ConvexBlock, pose: &Pose) {
        self.place_coordinates(reference, pose);
        self.place_query_data();
    }

    /// The first half of [`ConvexBlock::place_geometry`]: the coordinates (vertices, face
    /// planes, centroid, box), without what only the pair query reads (the clearance and the
    /// vertices' local coordinates), which [`ConvexBlock::place_query_data`] then derives
    /// from them. Until it is called the block must not be queried; the two halves give the
    /// same block, bit for bit, as [`ConvexBlock::place_geometry`] (the mechanics places
    /// every moved body's parts but completes only those of the pairs it queries).
    pub(crate) fn place_coordinates(&mut self, reference: &ConvexBlock, pose: &Pose) {
        debug_assert!(
            self.edges == reference.edges && self.face_vertices == reference.face_vertices
        );
        let rigid = Rigid::new(pose.rotation, pose.translation, 1.0);
        self.vertices.clear();
        self.vertices
            .extend(reference.vertices.iter().map(|&p| rigid.point(p)));
        self.planes.clear();
        self.planes
            .extend(reference.planes.iter().map(|pl| rigid.plane(pl)));
        self.centroid = rigid.point(reference.centroid);
        self.bounds = Bounds::of(&self.vertices);
    }

    /// The second half of [`ConvexBlock::place_geometry`]: the clearance and the local
    /// coordinates, from the block's own (placed) vertices and planes.
    pub(crate) fn place_query_data(&mut self) {
        // Recomputed as `ConvexBlock::transformed` does (the same block, bit for bit): it
        // lets the classification read the faces at a vertex from the topology instead of
        // computing their distances, in every query of the pairs of this block. Leaving it
        // unknown made each query of a placed block dearer than of a built one (a tracker
        // step querying every pair of a 50^3 grid: 1.2 times a full detection of built
        // blocks; about 1 with it, docs/benchmarks.md "Tracker steps").
        self.clearance = Clearance::of(&self.vertices, &self.planes, &self.vertex_faces);
        self.local.fill(&self.vertices);
    }
}

/// A rotation (as a matrix: fewer operations per point than rotating by the quaternion,
/// for the dozens of points of a block), a scale and a translation, as [`ConvexBlock::transformed`]
/// and [`ConvexBlock::place_from`] apply them, in the same way so that both give the same
/// block.
pub(super) struct Rigid {
    matrix: DMat3,
    scale: f64,
    translation: DVec3,
}

impl Rigid {
    pub(super) fn new(rotation: DQuat, translation: DVec3, scale: f64) -> Rigid {
        Rigid {
            matrix: DMat3::from_quat(rotation),
            scale,
            translation,
        }
    }

    #[inline]
    pub(super) fn point(&self, p: DVec3) -> DVec3 {
        self.matrix * (p * self.scale) + self.translation
    }

    /// The plane through the image of its point, with the rotated normal made unit again.
    #[inline]
    pub(super) fn plane(&self, plane: &Plane) -> Plane {
        Plane {
            normal: (self.matrix * plane.normal).normalize(),
            point: self.point(plane.point),
        }
    }
}

impl LocalCoordinates {
    /// Recomputes the coordinates of `vertices` into the existing buffers.
    fn fill(&mut self, vertices: &[DVec3]) {
        self.origin = vertices[0];
        let last = vertices.len() - 1;
        self.quads
            .resize(vertices.len().div_ceil(4), Quad::default());
        for (c, q) in self.quads.iter_mut().enumerate() {
            for k in 0..4 {
                let v = vertices[(4 * c + k).min(last)] - self.origin;
                (q.x[k], q.y[k], q.z[k]) = (v.x, v.y, v.z);
            }
        }
    }
}

/// Asserts that `block` is `expected` bit for bit in everything placing writes: coordinates,
/// box, centroid and the pair query's data (clearance, local coordinates).
#[cfg(test)]
pub(crate) fn assert_same_placed(block: &ConvexBlock, expected: &ConvexBlock) {
    assert_eq!(block.vertices(), expected.vertices());
    assert_eq!(block.planes(), expected.planes());
    assert_eq!(block.aabb(), expected.aabb());
    assert_eq!(block.centroid(), expected.centroid());
    assert_eq!(block.clearance(), expected.clearance());
    let local = |b: &ConvexBlock| format!("{:?}", b.local());
    assert_eq!(local(block), local(expected));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 x 2 x 3 box and a pose that turns it about three axes and moves it.
    fn box_and_pose() -> (ConvexBlock, Pose) {
        let reference = ConvexBlock::cuboid([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]).unwrap();
        let pose = Pose::new(
            DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.2, 1.1),
            DVec3::new(5.0, -1.0, 2.0),
        )
        .unwrap();
        (reference, pose)
    }

    #[test]
    fn placing_matches_transformed_and_the_bound_holds() {
        let (reference, pose) = box_and_pose();
        let mut placed = reference.clone();
        placed.place_from(&reference, &pose);
        let expected = reference.transformed(pose.rotation, pose.translation, 1.0);
        assert_eq!(placed.vertices(), expected.vertices());
        assert_eq!(placed.planes(), expected.planes());
        assert_eq!(placed.aabb(), expected.aabb());
        assert_eq!(placed.centroid(), expected.centroid());
        assert_eq!(placed.clearance(), expected.clearance());
        assert_ne!(placed.clearance(), Clearance::UNKNOWN);
        let (c, r) = (reference.centroid(), 14f64.sqrt() / 2.0);
        let bound = Pose::IDENTITY.displacement_bound(&pose, c, r);
        let moved = reference
            .vertices()
            .iter()
            .map(|&v| pose.apply(v).distance(v))
            .fold(0.0, f64::max);
        assert!(moved <= bound * (1.0 + 1e-12), "{moved} > {bound}");
        assert!(
            bound < moved * 1.5 + 1.0,
            "bound too loose: {bound} vs {moved}"
        );
    }

    /// About a zero centre (of either sign) the bound skips rotating it: the same bits as
    /// the rotated images give, for translations with zeros of either sign, rotations by
    /// zero and by large angles, tiny and huge coordinates, and rotations that are not
    /// finite (their images are NaN: the fast path is not theirs).
    #[test]
    fn the_bound_about_the_origin_is_the_rotated_images_bound_bit_for_bit() {
        let general = |from: &Pose, to: &Pose, centre: DVec3, radius: f64| {
            let shift = to.apply(centre).distance(from.apply(centre));
            let relative = to.rotation * from.rotation.conjugate();
            let sin_half = relative.xyz().length().min(1.0);
            let rounding = 8.0 * f64::EPSILON * (to.apply(centre).abs().max_element() + radius);
            shift + 2.0 * sin_half * radius + rounding
        };
        let rotations = [
            DQuat::IDENTITY,
            -DQuat::IDENTITY,
            DQuat::from_xyzw(-0.0, 0.0, -0.0, 1.0),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.2, 1.1),
            DQuat::from_euler(glam::EulerRot::XYZ, 1e-9, 2e-12, -3.0),
            DQuat::from_rotation_z(std::f64::consts::PI),
            // Not finite (a state that fails its step): the rotated images, NaN included.
            DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0),
            DQuat::from_xyzw(0.0, f64::INFINITY, 0.0, 0.0),
        ];
        let translations = [
            DVec3::ZERO,
            DVec3::new(-0.0, 0.0, -0.0),
            DVec3::new(5.0, -0.0, 2.0),
            DVec3::new(1e-300, -1e300, 0.0),
            DVec3::new(0.1, 0.2, 0.3),
        ];
        let poses: Vec<Pose> = rotations
            .iter()
            .flat_map(|&rotation| {
                translations.iter().map(move |&translation| Pose {
                    rotation,
                    translation,
                })
            })
            .collect();
        for from in &poses {
            for to in &poses {
                for centre in [DVec3::ZERO, DVec3::new(-0.0, -0.0, 0.0)] {
                    for radius in [0.0, 0.87, 1e5] {
                        let bound = from.displacement_bound(to, centre, radius);
                        let expected = general(from, to, centre, radius);
                        assert_eq!(bound.to_bits(), expected.to_bits(), "{from:?} {to:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn placing_in_two_halves_gives_the_block_placed_at_once() {
        let (reference, pose) = box_and_pose();
        let first = Pose::new(DQuat::from_rotation_y(0.2), DVec3::new(1.0, 2.0, 3.0)).unwrap();
        let mut halves = reference.clone();
        halves.place_from(&reference, &first);
        halves.place_coordinates(&reference, &pose);
        // The coordinates moved, the query data not yet.
        let expected = reference.transformed(pose.rotation, pose.translation, 1.0);
        assert_eq!(halves.vertices(), expected.vertices());
        assert_ne!(halves.clearance(), expected.clearance());
        halves.place_query_data();
        let mut whole = reference.clone();
        whole.place_geometry(&reference, &pose);
        for block in [&halves, &whole] {
            assert_same_placed(block, &expected);
        }
    }

    #[test]
    fn poses_with_nan_or_a_zero_rotation_are_refused() {
        assert!(Pose::new(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0), DVec3::ZERO).is_none());
        assert!(Pose::new(DQuat::IDENTITY, DVec3::new(f64::NAN, 0.0, 0.0)).is_none());
        assert!(Pose::new(DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0), DVec3::ZERO).is_some());
    }

    /// A quaternion far from unit length is its rotation all the same: `1e200 q` (whose
    /// squared length overflows) and `1e-200 q` (subnormal) were the zero rotation and a
    /// refusal.
    #[test]
    fn a_huge_or_tiny_multiple_of_a_quaternion_is_its_rotation() {
        let q = DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 0.7);
        let unit = Pose::new(q, DVec3::ZERO).unwrap();
        for scale in [1e200, -1e300, 1e-200, -1e-300, f64::MAX] {
            let pose = Pose::new(q * scale, DVec3::ZERO).expect("a rotation");
            assert!(pose.same_placement(&unit), "{scale}: {:?}", pose.rotation);
            assert!((pose.rotation.length() - 1.0).abs() < 1e-15);
        }
        // Within the usual range, the division by the length is as it was.
        assert_eq!(
            Pose::new(q * 3.0, DVec3::ZERO).unwrap().rotation,
            (q * 3.0) / (q * 3.0).length()
        );
    }
}

/// What [`ConvexBlock::prefetch`] asks for.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Prefetch {
    /// The block itself (where its buffers are, its box, its clearance): first, so that
    /// the buffers' addresses can be read when they are asked for.
    Block,
    /// The buffers that placing reads (of the reference) and writes (of the placed block).
    Coordinates,
    /// The vertices and planes alone: what [`ConvexBlock::place_coordinates`] reads and
    /// writes.
    Points,
    /// The buffers a pair query reads most.
    Query,
}

/// Asks for the cache lines of `item` (a hint, as [`ConvexBlock::prefetch`]: no effect on
/// any result), for what is not a block (a body's shape, before its parts are read).
#[inline(always)]
pub(crate) fn prefetch_value<T>(item: &T) {
    prefetch_bytes(std::slice::from_ref(item));
}

/// Asks for the cache lines of `items` (never faults, whatever the address).
#[inline(always)]
fn prefetch_bytes<T>(items: &[T]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // Offsets from the first byte: a buffer that straddles one more line than its length
        // gets its last line late (asking for every line it touches measured 3 % slower on
        // the 100^3 grid, one more prefetch per buffer).
        let p = items.as_ptr() as *const i8;
        for offset in (0..std::mem::size_of_val(items)).step_by(64) {
            // SAFETY: a prefetch is a hint; it reads nothing and faults on no address.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(offset)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = items;
}
