//! How far each body of a system is from a convex block: its convex hull's excess volume and
//! the cracks between its parts (docs/concave-blocks.md, "How concave a body is").
//!
//! Two measures, reported apart because they say different things:
//!
//! - **non-convex by volume**: the union of the parts is smaller than its convex hull by more
//!   than a layer of the length threshold's thickness over the hull's surface
//!   (`V_hull - V > l A_hull`, `l` the length threshold for the body's bounding box), so the
//!   excess is not a matter of rounding: an L-block, a block with a notch, the rock left
//!   around the corner of a tunnel;
//! - **cracked**: two parts of the body touch face to face on a real face: over faces that
//!   both lie on a joint (origin [`FaceOrigin::Joint`] of a joint, not of an excavation's
//!   cut; glued or not), or over more area than the glue between them (by more than the
//!   length threshold times the perimeter of their contact polygon). There a real face of a
//!   part lies inside the union, not on its boundary: a joint that ends inside the block,
//!   held by a rock bridge. Generation glues the crack of a finite joint with bridges for the
//!   detection (no other block can reach it), hence the test on the faces' origins. The
//!   union can be convex (a block cut through by a joint on part of its section and held by
//!   the bridge on the rest).

use super::BlockSystem;
use crate::block::{hull_volume_and_area, BlockError, ConvexBlock, FaceOrigin};
use crate::generation::SetKind;
use crate::geometry::Aabb;
use crate::tolerance::Tolerance;

/// How one body departs from a convex block ([`BlockSystem::body_shapes`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyShape {
    /// The body id.
    pub body: u32,
    /// Its number of convex parts.
    pub parts: u32,
    /// The volume of the union of its parts.
    pub volume: f64,
    /// Its convex hull's volume minus its own (0 for a body of one part).
    pub hull_excess: f64,
    /// Whether `hull_excess` is beyond the tolerance: more than the length threshold times
    /// the hull's surface area.
    pub non_convex: bool,
    /// The area over which two of its parts touch face to face on a real face (module docs:
    /// joint faces on both sides, or no glue), summed over the pairs of parts.
    pub crack_area: f64,
}

impl BodyShape {
    /// Whether the body has a crack: a real face of a part inside it.
    pub fn cracked(&self) -> bool {
        self.crack_area > 0.0
    }

    /// Whether the body is concave: non-convex by volume, or cracked (the rock is the open
    /// set inside the body's real faces, and a segment across a crack leaves it).
    pub fn concave(&self) -> bool {
        self.non_convex || self.cracked()
    }
}

impl BlockSystem {
    /// How each body (in the order of [`BlockSystem::body_parts`]) departs from a convex
    /// block: its hull's excess volume and its cracks, at the thresholds of `tol` (module
    /// docs). A body of one convex part is convex and has no crack.
    ///
    /// ```
    /// use penedge::{BlockSystem, ConvexBlock, Tolerance};
    /// let tol = Tolerance::default();
    /// let c = |lo, hi| ConvexBlock::cuboid(lo, hi).unwrap();
    /// // An L-block (body 0) and a box cut in two (body 1).
    /// let system = BlockSystem::new(vec![
    ///     c([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
    ///     c([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
    ///     c([5.0, 0.0, 0.0], [6.0, 1.0, 1.0]),
    ///     c([5.0, 0.0, 1.0], [6.0, 1.0, 2.0]),
    /// ])
    /// .with_bodies(vec![0, 0, 1, 1], &tol)
    /// .unwrap();
    /// let shapes = system.body_shapes(&tol).unwrap();
    /// assert!(shapes[0].non_convex && (shapes[0].hull_excess - 0.5).abs() < 1e-12);
    /// assert!(!shapes[1].non_convex && !shapes[1].cracked());
    /// ```
    ///
    /// # Errors
    /// The hull of a body's vertices cannot be made (out-of-range coordinates; see
    /// [`ConvexBlock::hull_with_tolerance`]).
    pub fn body_shapes(&self, tol: &Tolerance) -> Result<Vec<BodyShape>, BlockError> {
        let bodies = self.body_parts();
        let mut cracks = vec![0.0; bodies.len()];
        if self.has_concave() {
            self.add_cracks(&bodies, tol, &mut cracks);
        }
        bodies
            .iter()
            .zip(cracks)
            .map(|((body, parts), crack_area)| {
                let blocks: Vec<&ConvexBlock> =
                    parts.iter().map(|&k| &self.blocks[k as usize]).collect();
                let volume: f64 = blocks.iter().map(|b| b.volume()).sum();
                let (hull_excess, non_convex) = if blocks.len() > 1 {
                    hull_excess(&blocks, volume, tol)?
                } else {
                    (0.0, false)
                };
                Ok(BodyShape {
                    body: *body,
                    parts: parts.len() as u32,
                    volume,
                    hull_excess,
                    non_convex,
                    crack_area,
                })
            })
            .collect()
    }

    /// Adds to `cracks` (per body of `bodies`) the unglued face-face contact area of each
    /// pair of its parts, where beyond the tolerance.
    fn add_cracks(&self, bodies: &[(u32, Vec<u32>)], tol: &Tolerance, cracks: &mut [f64]) {
        let index_of = |body: u32| bodies.partition_point(|(b, _)| *b < body);
        let internal = self.internal_faces();
        self.face_face_contacts(
            tol,
            |i, j| self.body_of(i) == self.body_of(j),
            |[i, j], [fa, fb], g| {
                let body = self.body_of(i);
                let (a, b) = (&self.blocks[i as usize], &self.blocks[j as usize]);
                if self.is_rock_joint(a, fa) && self.is_rock_joint(b, fb) {
                    cracks[index_of(body)] += g.area();
                    return;
                }
                let pair = [i.min(j), i.max(j)];
                let from = internal.partition_point(|f| f.parts < pair);
                let glued: f64 = internal[from..]
                    .iter()
                    .take_while(|f| f.parts == pair)
                    .map(|f| f.area)
                    .sum();
                let points = g.points();
                let perimeter: f64 = (0..points.len())
                    .map(|k| points[k].distance(points[(k + 1) % points.len()]))
                    .sum();
                let length = tol.for_box(&union_box(&[a, b])).length;
                let unglued = g.area() - glued;
                if unglued > length * perimeter {
                    cracks[index_of(body)] += unglued;
                }
            },
        );
    }
}

impl BlockSystem {
    /// Whether face `face` of `block` lies on a joint of the rock (a plane, set, disc or
    /// polygon of the spec), not on an excavation's cut or a rock bridge.
    fn is_rock_joint(&self, block: &ConvexBlock, face: u32) -> bool {
        match block.face_origins()[face as usize] {
            FaceOrigin::Joint { set, .. } => self
                .sets
                .get(set as usize)
                .is_some_and(|r| r.kind != SetKind::Excavation),
            _ => false,
        }
    }
}

/// The bounding box of blocks.
fn union_box(blocks: &[&ConvexBlock]) -> Aabb {
    let mut b = blocks[0].aabb();
    for block in &blocks[1..] {
        let other = block.aabb();
        b.min = b.min.min(other.min);
        b.max = b.max.max(other.max);
    }
    b
}

/// The excess of the hull of `blocks`' vertices over their union's `volume`, and whether it
/// is beyond the length threshold times the hull's surface area.
fn hull_excess(
    blocks: &[&ConvexBlock],
    volume: f64,
    tol: &Tolerance,
) -> Result<(f64, bool), BlockError> {
    let points: Vec<[f64; 3]> = blocks
        .iter()
        .flat_map(|b| b.vertices().iter().map(|v| v.to_array()))
        .collect();
    let (hull_volume, area) = hull_volume_and_area(&points, tol)?;
    let excess = hull_volume - volume;
    let length = tol.for_box(&union_box(blocks)).length;
    Ok((excess, excess > length * area))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> ConvexBlock {
        ConvexBlock::cuboid(lo, hi).unwrap()
    }

    /// The shapes of a system of one body of the given parts.
    fn one_body(parts: Vec<ConvexBlock>) -> BodyShape {
        let tol = Tolerance::default();
        let n = parts.len();
        let system = BlockSystem::new(parts)
            .with_bodies(vec![0; n], &tol)
            .unwrap();
        let shapes = system.body_shapes(&tol).unwrap();
        assert_eq!(shapes.len(), 1);
        shapes[0]
    }

    #[test]
    fn concave_shapes_of_an_l_block_in_two_cuts_have_its_hull_excess() {
        // The L of profile (0,0) (3,0) (3,1) (1,1) (1,3) (0,3) in x-z, 10 long in y: area 5;
        // its hull cuts the corner (1,3) (3,1) off the 3 x 3 square: area 9 - 2 = 7. Excess
        // (7 - 5) x 10 = 20.
        let cuts = [
            vec![
                cuboid([0.0, 0.0, 0.0], [3.0, 10.0, 1.0]),
                cuboid([0.0, 0.0, 1.0], [1.0, 10.0, 3.0]),
            ],
            vec![
                cuboid([0.0, 0.0, 0.0], [1.0, 10.0, 3.0]),
                cuboid([1.0, 0.0, 0.0], [3.0, 10.0, 1.0]),
            ],
            vec![
                cuboid([0.0, 0.0, 0.0], [1.0, 10.0, 1.0]),
                cuboid([1.0, 0.0, 0.0], [3.0, 10.0, 1.0]),
                cuboid([0.0, 0.0, 1.0], [1.0, 4.0, 3.0]),
                cuboid([0.0, 4.0, 1.0], [1.0, 10.0, 3.0]),
            ],
        ];
        for parts in cuts {
            let n = parts.len() as u32;
            let s = one_body(parts);
            assert_eq!(s.parts, n);
            assert!((s.volume - 50.0).abs() < 1e-9);
            assert!((s.hull_excess - 20.0).abs() < 1e-9, "{}", s.hull_excess);
            assert!(s.non_convex && !s.cracked() && s.concave());
        }
    }

    #[test]
    fn concave_shapes_of_a_block_cut_into_convex_parts_are_convex() {
        // A 1 x 1 x 2 box cut at z = 1, and a unit cube cut by the oblique plane x + z = 1
        // (a wedge and the rest): the union is the box, its own hull.
        let y = [[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
        let wedge = ConvexBlock::from_planes(
            &[
                y[0],
                y[1],
                [-1.0, 0.0, 0.0],
                [0.0, 0.0, -1.0],
                [1.0, 0.0, 1.0],
            ],
            &[0.0, 1.0, 0.0, 0.0, 1.0],
        )
        .unwrap();
        let rest = ConvexBlock::from_planes(
            &[
                y[0],
                y[1],
                [1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                [-1.0, 0.0, -1.0],
            ],
            &[0.0, 1.0, 1.0, 1.0, -1.0],
        )
        .unwrap();
        assert!((wedge.volume() - 0.5).abs() < 1e-12 && (rest.volume() - 0.5).abs() < 1e-12);
        for parts in [
            vec![
                cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
                cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            ],
            vec![wedge, rest],
        ] {
            let s = one_body(parts);
            assert!(s.hull_excess.abs() < 1e-12, "{}", s.hull_excess);
            assert!(!s.non_convex && !s.cracked() && !s.concave());
        }
    }

    #[test]
    fn concave_shapes_of_a_notch_and_of_a_step_at_the_threshold() {
        // A U-block: a 3 x 1 x 1 floor and two 1 x 1 x 1 posts at its ends; its hull is the
        // 3 x 1 x 2 box: excess 6 - 5 = 1.
        let s = one_body(vec![
            cuboid([0.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
            cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            cuboid([2.0, 0.0, 1.0], [3.0, 1.0, 2.0]),
        ]);
        assert!((s.hull_excess - 1.0).abs() < 1e-12 && s.non_convex);
        // Two unit cubes, the upper one moved by d along x: in the x-z profile the hull adds
        // two triangles of legs d and 1, d / 2 each: excess d. The length threshold of the
        // pair (1e-9 x its diagonal, about 2.4) times the hull's area (about 10) is about
        // 2.4e-8: d = 1e-3 is a step, d = 1e-12 is rounding.
        for (d, step) in [(1e-3, true), (1e-12, false)] {
            let s = one_body(vec![
                cuboid([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
                cuboid([d, 0.0, 1.0], [1.0 + d, 1.0, 2.0]),
            ]);
            if step {
                assert!((s.hull_excess - d).abs() < 1e-12, "{}", s.hull_excess);
            }
            assert_eq!(s.non_convex, step, "d = {d}: excess {}", s.hull_excess);
            assert!(!s.cracked());
        }
    }

    #[test]
    fn concave_shapes_find_a_crack_where_two_parts_touch_without_glue() {
        // A 2 x 1 x 2 box: a 2 x 1 x 1 floor (0), and on it two unit cubes (1 at x < 1, 2 at
        // x > 1). Glued 0-1 and 1-2 but not 0-2: the face x in [1, 2] at z = 1 is a crack of
        // area 1 (a joint from x = 1 to the side x = 2, the bridge from 0 to 1). The union is
        // the box: convex by volume.
        let tol = Tolerance::default();
        let parts = vec![
            cuboid([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
            cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
            cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]),
            cuboid([5.0, 0.0, 0.0], [6.0, 1.0, 1.0]),
        ];
        let mut system = BlockSystem::new(parts)
            .with_bodies(vec![0, 0, 0, 1], &tol)
            .unwrap();
        let whole = system.body_shapes(&tol).unwrap();
        assert!(!whole[0].cracked() && !whole[0].non_convex && !whole[1].concave());
        // The glue between 0 and 2 taken away.
        let glue = system.glue.as_mut().unwrap();
        assert_eq!(glue.internal.len(), 3);
        glue.internal.retain(|f| f.parts != [0, 2]);
        let shapes = system.body_shapes(&tol).unwrap();
        assert!((shapes[0].crack_area - 1.0).abs() < 1e-9, "{:?}", shapes[0]);
        assert!(shapes[0].cracked() && !shapes[0].non_convex && shapes[0].concave());
        assert!(!shapes[1].concave());
    }

    #[test]
    fn concave_shapes_find_a_crack_on_glued_joint_faces() {
        // The box of the test above, generated as by a polygonal joint with a bridge on the
        // plane z = 1: the floor's top face and the right cube's bottom face are joint faces
        // (the crack, x in [1, 2]: area 1), the left cube's bottom face a bridge face. All
        // three are glued (with_bodies glues every face-face contact of a body), yet the
        // joint is a real face inside the body; not so for an excavation's cut.
        let tol = Tolerance::default();
        let on_plane = |block: ConvexBlock, up: bool, origin: FaceOrigin| {
            let mut origins = block.face_origins().to_vec();
            let z = if up { 1.0 } else { -1.0 };
            let face = block.planes().iter().position(|p| p.normal.z == z).unwrap();
            origins[face] = origin;
            block.with_face_origins(origins).unwrap()
        };
        let joint = FaceOrigin::Joint { set: 0, joint: 0 };
        let bridge = FaceOrigin::Bridge { set: 0, joint: 0 };
        let parts = vec![
            on_plane(cuboid([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]), true, joint),
            on_plane(cuboid([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]), false, bridge),
            on_plane(cuboid([1.0, 0.0, 1.0], [2.0, 1.0, 2.0]), false, joint),
        ];
        let record = |kind| crate::generation::SetRecord {
            name: "J".to_string(),
            kind,
        };
        for (kind, crack) in [(SetKind::Polygon, 1.0), (SetKind::Excavation, 0.0)] {
            let system =
                BlockSystem::with_provenance(parts.clone(), vec![], vec![], vec![record(kind)])
                    .with_bodies(vec![0, 0, 0], &tol)
                    .unwrap();
            assert_eq!(system.internal_faces().len(), 3);
            let s = system.body_shapes(&tol).unwrap()[0];
            assert!((s.crack_area - crack).abs() < 1e-9, "{kind:?}: {s:?}");
            assert!(!s.non_convex);
        }
    }

    #[test]
    fn concave_shapes_of_a_generated_bridged_joint_are_one_cracked_convex_body() {
        // A 10 m cube and a horizontal 4 x 4 m square joint with bridges at z = 5, inside
        // its section: generation cuts the cube through and glues the pieces into one body
        // (docs/generation.md, "Rock bridges"). The union is the cube (convex); the crack is
        // the joint's square, 16 m2.
        let spec = crate::io::spec::parse_toml(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
             [[joints]]\ntype = \"polygon\"\nbridge = true\n\
             vertices = [[3, 3, 5], [7, 3, 5], [7, 7, 5], [3, 7, 5]]\n",
        )
        .unwrap();
        let system = crate::generation::generate(&spec).unwrap().system;
        assert!(system.len() > 2);
        let tol = Tolerance::default();
        let shapes = system.body_shapes(&tol).unwrap();
        assert_eq!(shapes.len(), 1);
        let s = shapes[0];
        assert!((s.volume - 1000.0).abs() < 1e-9);
        assert!(s.hull_excess.abs() < 1e-9 && !s.non_convex);
        assert!((s.crack_area - 16.0).abs() < 1e-9, "{s:?}");
    }
}
