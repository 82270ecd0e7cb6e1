//! References computed independently of the module: a brute-force separating-axis test
//! (every face normal from the face's own vertices, every pair of edges, no merging), the
//! intersection built as a block of its own from both blocks' half-spaces, and finite
//! differences of its volume.

use super::*;
use crate::classify::PairResult;
use crate::contact::Detector;
use crate::system::test_rng::{polytope, Rng};
use glam::DQuat;

/// `max_A u·x - min_B u·y` for a unit `u`: how far B must move along `u` to clear A's
/// extent (the support of `A - B`).
fn support(a: &ConvexBlock, b: &ConvexBlock, u: DVec3) -> f64 {
    let hi_a = a
        .vertices()
        .iter()
        .map(|&x| u.dot(x))
        .fold(f64::MIN, f64::max);
    let lo_b = b
        .vertices()
        .iter()
        .map(|&y| u.dot(y))
        .fold(f64::MAX, f64::min);
    hi_a - lo_b
}

/// The separating-axis minimum by brute force: the smallest support over every face
/// normal (Newell's normal of the face's vertices) and every cross product of an edge of A
/// with an edge of B, both signs. Positive when the interiors overlap.
fn brute_sat(a: &ConvexBlock, b: &ConvexBlock) -> (f64, DVec3) {
    let mut axes = Vec::new();
    for block in [a, b] {
        for face in block.faces() {
            let p: Vec<DVec3> = face.iter().map(|&k| block.vertices()[k as usize]).collect();
            let mut n = DVec3::ZERO;
            for i in 0..p.len() {
                n += p[i].cross(p[(i + 1) % p.len()]);
            }
            axes.push(n.normalize());
        }
    }
    let edge = |x: &ConvexBlock, e: &crate::block::Edge| {
        x.vertices()[e.vertices[1] as usize] - x.vertices()[e.vertices[0] as usize]
    };
    for ea in a.edges() {
        for eb in b.edges() {
            let c = edge(a, ea).cross(edge(b, eb));
            if c.length() > 1e-9 * edge(a, ea).length() * edge(b, eb).length() {
                axes.push(c.normalize());
            }
        }
    }
    axes.iter()
        .flat_map(|&u| [u, -u])
        .map(|u| (support(a, b, u), u))
        .fold(
            (f64::INFINITY, DVec3::ZERO),
            |m, x| if x.0 < m.0 { x } else { m },
        )
}

fn moved(b: &ConvexBlock, t: DVec3) -> ConvexBlock {
    b.transformed(DQuat::IDENTITY, t, 1.0)
}

/// `A ∩ B` as a block of its own, from both blocks' half-spaces.
fn intersection(a: &ConvexBlock, b: &ConvexBlock) -> Option<ConvexBlock> {
    let planes = a.planes().iter().chain(b.planes());
    let normals: Vec<[f64; 3]> = planes.clone().map(|p| p.normal.to_array()).collect();
    let offsets: Vec<f64> = planes.map(|p| p.normal.dot(p.point)).collect();
    ConvexBlock::from_planes(&normals, &offsets).ok()
}

/// Area of the projection of a convex block on a plane normal to the unit `n`: half the
/// sum of `|n · area vector|` over its faces (each point of the shadow is covered by one
/// face in front and one behind).
fn projected_area(block: &ConvexBlock, n: DVec3) -> f64 {
    let v = block.vertices();
    let mut total = 0.0;
    for face in block.faces() {
        let p: Vec<DVec3> = face.iter().map(|&k| v[k as usize]).collect();
        let mut a = DVec3::ZERO;
        for i in 1..p.len() - 1 {
            a += (p[i] - p[0]).cross(p[i + 1] - p[0]) * 0.5;
        }
        total += n.dot(a).abs();
    }
    0.5 * total
}

/// A random pair: two random polytopes (each holds the unit ball), B's centre at a
/// distance that makes about half of the pairs overlap, B rotated and scaled.
fn random_pair(rng: &mut Rng) -> (ConvexBlock, ConvexBlock) {
    let na = 5 + (rng.unit() * 10.0) as usize;
    let nb = 5 + (rng.unit() * 10.0) as usize;
    let a = polytope(rng, na, [0.0; 3], None);
    let b = polytope(rng, nb, [0.0; 3], None);
    let dir = DVec3::new(rng.signed(), rng.signed(), rng.signed()).normalize();
    let axis = DVec3::new(rng.signed(), rng.signed(), rng.signed()).normalize();
    let scale = 0.5 + rng.unit();
    let dist = (1.0 + scale) * (0.9 + rng.unit());
    let b = b.transformed(
        DQuat::from_axis_angle(axis, 3.0 * rng.signed()),
        dir * dist,
        scale,
    );
    (a, b)
}

#[test]
fn random_pairs_agree_with_brute_force_separating_axes() {
    let tol = Tolerance::default();
    let mut rng = Rng(11);
    let mut det = Detector::new(tol);
    let (mut overlapping, mut apart, mut penetrating) = (0, 0, 0);
    for case in 0..400 {
        let (a, b) = random_pair(&mut rng);
        let size = a.size().max(b.size());
        let eps = 1e-9 * size;
        let (sat, axis) = brute_sat(&a, &b);
        let found = overlap(&a, &b, &tol);
        if det.detect(&a, &b) == PairResult::Penetrating {
            penetrating += 1;
            assert!(
                found.is_some(),
                "case {case}: penetrating without an overlap"
            );
        }
        if sat < -eps {
            apart += 1;
            assert!(found.is_none(), "case {case}: apart by {sat}");
            continue;
        }
        if sat < eps {
            continue; // touching within rounding: either answer
        }
        overlapping += 1;
        let o = found.unwrap_or_else(|| panic!("case {case}: no overlap, SAT depth {sat}"));
        assert!((o.normal.length() - 1.0).abs() < 1e-12);
        // The separating-axis minimum, as the brute force finds it.
        let min = o.min_translation.length();
        assert!((min - sat).abs() < eps, "case {case}: {min} vs {sat}");
        // The depth along the normal: at least the minimum, at most the minimum's bound
        // along the normal; moving B by it leaves the blocks touching, by less overlapping.
        assert!(o.depth >= sat - eps, "case {case}: {} < {sat}", o.depth);
        let cos = o.normal.dot(axis);
        if cos > 0.1 {
            assert!(o.depth <= sat / cos + eps, "case {case}");
        }
        let touching = brute_sat(&a, &moved(&b, o.normal * o.depth)).0;
        assert!(
            touching.abs() < eps,
            "case {case}: {touching} after the depth"
        );
        let short = brute_sat(&a, &moved(&b, o.normal * (0.99 * o.depth))).0;
        assert!(short > 0.0, "case {case}: apart before the depth");
        // The region lies on the common plane, through the centroid, normal to the normal.
        for p in o.points() {
            assert!(o.normal.dot(*p - o.centroid).abs() < eps, "case {case}");
        }
    }
    assert!(
        overlapping > 100 && apart > 100 && penetrating > 50,
        "{overlapping} {apart} {penetrating}"
    );
}

#[test]
fn volume_centroid_and_area_match_the_intersection_block() {
    let tol = Tolerance::default();
    let mut rng = Rng(5);
    let mut checked = 0;
    for case in 0..300 {
        let (a, b) = random_pair(&mut rng);
        let (Some(o), Some(i)) = (overlap(&a, &b, &tol), intersection(&a, &b)) else {
            continue;
        };
        if i.volume() < 1e-3 {
            continue; // a sliver: the half-space construction merges its corners
        }
        checked += 1;
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-300);
        assert!(
            rel(o.volume, i.volume()) < 1e-9,
            "case {case}: {} {}",
            o.volume,
            i.volume()
        );
        assert!(o.centroid.distance(i.centroid()) < 1e-9, "case {case}");
        let shadow = projected_area(&i, o.normal);
        assert!(
            rel(o.area, shadow) < 1e-9,
            "case {case}: {} {shadow}",
            o.area
        );
        // Every vertex of the intersection projects into the region's polygon.
        let ContactPoints::Polygon(poly) = &o.region else {
            panic!("case {case}: a thick overlap projects to a polygon");
        };
        let pv = poly.vertices();
        for &x in i.vertices() {
            let x = x - o.normal * o.normal.dot(x - o.centroid);
            for k in 0..pv.len() {
                let (p, q) = (pv[k], pv[(k + 1) % pv.len()]);
                let left = (q - p).cross(x - p).dot(o.normal);
                assert!(
                    left > -1e-9 * (q - p).length(),
                    "case {case}: outside the region"
                );
            }
        }
    }
    assert!(checked > 50, "{checked}");
}

/// The normal is the direction in which moving B shrinks the overlap fastest: minus the
/// gradient of the intersection's volume with respect to B's translation, here by central
/// differences of the intersection block's volume.
#[test]
fn the_normal_is_minus_the_gradient_of_the_overlap_volume() {
    let tol = Tolerance::default();
    let mut rng = Rng(3);
    let mut checked = 0;
    for case in 0..200 {
        let (a, b) = random_pair(&mut rng);
        let Some(o) = overlap(&a, &b, &tol) else {
            continue;
        };
        if o.volume < 1e-2 {
            continue;
        }
        let h = 1e-5;
        let volume = |t: DVec3| intersection(&a, &moved(&b, t)).map(|i| i.volume());
        let mut gradient = DVec3::ZERO;
        let mut ok = true;
        for (k, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            match (volume(e * h), volume(-e * h)) {
                (Some(p), Some(m)) => gradient[k] = (p - m) / (2.0 * h),
                _ => ok = false,
            }
        }
        if !ok {
            continue;
        }
        checked += 1;
        let angle = o.normal.angle_between(-gradient);
        assert!(
            angle < 1e-5,
            "case {case}: {angle} rad off the volume gradient"
        );
    }
    assert!(checked > 30, "{checked}");
}

#[test]
fn swapping_negates_the_normal_and_keeps_the_rest() {
    let tol = Tolerance::default();
    let mut rng = Rng(17);
    let mut checked = 0;
    for case in 0..200 {
        let (a, b) = random_pair(&mut rng);
        let (Some(ab), Some(ba)) = (overlap(&a, &b, &tol), overlap(&b, &a, &tol)) else {
            continue;
        };
        checked += 1;
        let eps = 1e-12 * a.size().max(b.size());
        assert!((ab.normal + ba.normal).length() < 1e-12, "case {case}");
        assert!((ab.depth - ba.depth).abs() < eps, "case {case}");
        assert!((ab.min_translation + ba.min_translation).length() < eps);
        assert!((ab.volume - ba.volume).abs() < 10.0 * eps, "case {case}");
        assert!(
            ab.centroid.distance(ba.centroid) < eps * 10.0,
            "case {case}"
        );
    }
    assert!(checked > 50, "{checked}");
}

#[test]
fn translating_both_blocks_moves_the_region_and_keeps_the_rest() {
    let tol = Tolerance::default();
    let mut rng = Rng(23);
    let shift = DVec3::new(1234.5, -678.25, 90.125);
    let mut checked = 0;
    for case in 0..200 {
        let (a, b) = random_pair(&mut rng);
        let Some(o) = overlap(&a, &b, &tol) else {
            continue;
        };
        let m = overlap(&moved(&a, shift), &moved(&b, shift), &tol).unwrap();
        checked += 1;
        // Coordinates of 1e3 carry a rounding of 1e-13 each.
        let eps = 1e-9;
        assert!(
            (o.normal - m.normal).length() < eps * 1e2 / o.depth.max(1e-2),
            "case {case}"
        );
        assert!((o.depth - m.depth).abs() < eps, "case {case}");
        assert!((o.volume - m.volume).abs() < eps, "case {case}");
        assert!(
            (o.centroid + shift).distance(m.centroid) < 1e-6,
            "case {case}"
        );
        assert!((o.area - m.area).abs() < 1e-6, "case {case}");
    }
    assert!(checked > 50, "{checked}");
}

/// Two cubes overlapping along an edge: A's ridge along y inside B's, by `ex` along x and
/// `ez` along z. The separating-axis minimum is along x or z, whichever is shallower, and
/// turns by 90° where they are equal. B rotating about an axis along y half a unit off its
/// ridge moves the ridge along (1, 0, -1) and takes the pair through that point. The normal
/// turns with the overlap's shape, by steps that shrink with the rotation's steps: no jump.
#[test]
fn the_normal_turns_continuously_where_the_minimum_translation_flips() {
    let tol = Tolerance::default();
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    let (ex, ez) = (0.011, 0.009);
    let b0 = ConvexBlock::cuboid([1.0 - ex, 0.0, 1.0 - ez], [2.0 - ex, 1.0, 2.0 - ez]).unwrap();
    let pivot = DVec3::new(1.0 - ex, 0.0, 1.0 - ez) - DVec3::new(0.5, 0.0, 0.5);
    let at = |angle: f64| {
        let q = DQuat::from_rotation_y(angle);
        let o = overlap(&a, &b0.transformed(q, pivot - q * pivot, 1.0), &tol).unwrap();
        (o.normal, o.min_translation.normalize())
    };
    // The largest turn between neighbouring angles, for the normal and the minimum.
    let sweep = |steps: usize| {
        let (from, to) = (-0.015, 0.015);
        let mut last = at(from);
        let (mut normal, mut minimum) = (0.0f64, 0.0f64);
        for k in 1..=steps {
            let now = at(from + (to - from) * k as f64 / steps as f64);
            normal = normal.max(now.0.angle_between(last.0));
            minimum = minimum.max(now.1.angle_between(last.1));
            last = now;
        }
        (normal, minimum)
    };
    let (coarse, coarse_min) = sweep(100);
    let (fine, fine_min) = sweep(1000);
    // The minimum flips by about 90° at any resolution; the normal's steps shrink tenfold.
    assert!(
        coarse_min > 1.0 && fine_min > 1.0,
        "{coarse_min} {fine_min}"
    );
    assert!(coarse < 0.1 && fine < 0.15 * coarse, "{coarse} {fine}");
    // Unrotated: the area vector of A's two faces in B, ez x + ex z per unit length.
    let (n, _) = at(0.0);
    let expected = DVec3::new(ez, 0.0, ex).normalize();
    assert!(n.angle_between(expected) < 1e-9, "{n}");
}

/// Face on face with a small tilt: the normal is the normal of the face that covers the
/// other one (the overlap's surface on that block is that face alone), whichever block it
/// belongs to and whatever the tilt: no switch between the two faces.
#[test]
fn a_tilted_face_on_face_overlap_takes_the_covering_face() {
    let tol = Tolerance::default();
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    // B smaller than A's top face and within it, then larger and covering it.
    for (min, max, b_covers) in [
        ([0.2, 0.1, 0.99], [0.7, 0.6, 1.99], false),
        ([-0.5, -0.5, 0.99], [1.5, 1.5, 1.99], true),
    ] {
        let b0 = ConvexBlock::cuboid(min, max).unwrap();
        let pivot = DVec3::new(0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1]), 0.99);
        for angle in [-4e-3, -1e-3, -1e-5, 0.0, 1e-5, 1e-3, 4e-3] {
            let q = DQuat::from_rotation_x(angle);
            let b = b0.transformed(q, pivot - q * pivot, 1.0);
            let o = overlap(&a, &b, &tol).unwrap();
            let expected = if b_covers { q * DVec3::Z } else { DVec3::Z };
            assert!(
                (o.normal - expected).length() < 1e-12,
                "{angle}: {}",
                o.normal
            );
            // The deepest corner, 0.01 plus the tilt over half the covered face's width.
            assert!(
                (0.01 - 1e-12..=0.01 + angle.abs() + 1e-12).contains(&o.depth),
                "{angle}"
            );
        }
    }
}

#[test]
fn apart_or_touching_blocks_have_no_overlap() {
    let tol = Tolerance::default();
    let a = ConvexBlock::cuboid([0.0; 3], [1.0; 3]).unwrap();
    for min in [
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 1.0],
        [1.5, 0.0, 0.0],
        [0.5, 0.5, 1.0],
    ] {
        let b = ConvexBlock::cuboid(min, min.map(|c| c + 1.0)).unwrap();
        assert_eq!(overlap(&a, &b, &tol), None, "{min:?}");
    }
}
