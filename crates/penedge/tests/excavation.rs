//! Excavations in the generation spec: the examples remove exactly the volume of their
//! opening within the domain (worked out from the polygon's area, not from the code), bad
//! entries name their field, and concave blocks are left glued.

use penedge::generation::generate;
use penedge::io::spec::{parse_toml, read_spec};
use std::f64::consts::PI;
use std::path::PathBuf;

fn example(name: &str) -> penedge::generation::Generated {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    generate(&read_spec(&path).unwrap()).unwrap()
}

/// The area of a regular polygon of `n` sides inscribed in a circle of radius `r`.
fn polygon_area(n: f64, r: f64) -> f64 {
    0.5 * n * r * r * (2.0 * PI / n).sin()
}

fn left(out: &penedge::generation::Generated) -> f64 {
    out.system.blocks().iter().map(|b| b.volume()).sum()
}

#[test]
fn the_circular_tunnel_removes_its_section_times_the_domain_length() {
    let out = example("tunnel_circular.toml");
    let exact = polygon_area(16.0, 2.0) * 10.0; // right through the 10 m of the domain
    assert!((out.report.excavated_volume - exact).abs() < 1e-9 * exact);
    assert!((12.0 * 10.0 * 12.0 - left(&out) - exact).abs() < 1e-9 * exact);
    assert!(out.system.has_concave());
    assert_eq!(out.report.blocks, out.system.len());
    // The block file keeps the bodies, the excavation's entry and its faces.
    let text = penedge::io::json::to_json_string(&out.system);
    let back = penedge::io::json::from_json_str(&text).unwrap();
    assert_eq!(back.body_ids(), out.system.body_ids());
    assert_eq!(
        back.internal_faces().len(),
        out.system.internal_faces().len()
    );
    assert_eq!(back.sets().last(), out.system.sets().last());
}

#[test]
fn the_shaft_removes_its_section_times_its_depth() {
    let out = example("shaft.toml");
    let exact = polygon_area(8.0, 2.5) * 15.0;
    assert!((out.report.excavated_volume - exact).abs() < 1e-9 * exact);
    assert!((12.0 * 12.0 * 20.0 - left(&out) - exact).abs() < 1e-9 * exact);
}

#[test]
fn the_cavern_and_its_access_remove_at_most_their_volumes() {
    let out = example("cavern.toml");
    let cavern = 20.0 * 6.0 * 8.0; // wholly inside the domain
                                   // The horseshoe: a half 8-gon of radius 2 on walls 1.5 high, 4 wide; 13 m in the domain.
    let shoe = 0.5 * 8.0 * 4.0 * (PI / 8.0).sin() + 4.0 * 1.5;
    let v = out.report.excavated_volume;
    assert!(v > cavern && v < cavern + shoe * 13.0, "{v}");
    assert!((30.0 * 30.0 * 20.0 - left(&out) - v).abs() < 1e-9 * v);
}

#[test]
fn bad_excavations_name_their_field() {
    let spec = |entry: &str| {
        let text = format!(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
             [[excavations]]\n{entry}\n"
        );
        match parse_toml(&text) {
            Err(e) => e.to_string(),
            Ok(spec) => generate(&spec).unwrap_err().to_string(),
        }
    };
    let tunnel = |extra: &str| {
        spec(&format!(
            "type = \"tunnel\"\nprofile = \"circle\"\nstart = [5, -1, 5]\ntrend = 0\n{extra}"
        ))
    };
    let e = tunnel("radius = 1\nlength = 0");
    assert!(
        e.contains("excavations[0].length: must be greater than zero"),
        "{e}"
    );
    let e = tunnel("radius = 0\nlength = 5");
    assert!(
        e.contains("excavations[0].radius: must be greater than zero"),
        "{e}"
    );
    let e = tunnel("radius = nan\nlength = 5");
    assert!(
        e.contains("excavations[0].radius: must be a finite number"),
        "{e}"
    );
    let e = tunnel("radius = 1\nlength = 5\nplunge = 90");
    assert!(e.contains("excavations[0].plunge"), "{e}");
    let e = tunnel("radius = 1\nlength = 5\ndepth = 3");
    assert!(
        e.contains("excavations[0].depth: not a field of a `tunnel` entry"),
        "{e}"
    );
    let e = spec(
        "type = \"tunnel\"\nprofile = \"polygon\"\nvertices = [[0, 0], [1, 1], [1, 0], [0, 1]]\n\
         start = [5, -1, 5]\ntrend = 0\nlength = 5",
    );
    assert!(
        e.contains("excavations[0].vertices: the profile crosses itself"),
        "{e}"
    );
    let e =
        spec("type = \"shaft\"\nprofile = \"circle\"\nradius = 1\ntop = [50, 50, 10]\ndepth = 5");
    assert!(
        e.contains("excavations[0]: the excavation removes no rock"),
        "{e}"
    );
    let e = spec("type = \"pit\"");
    assert!(e.contains("excavations[0].type: unknown type `pit`"), "{e}");
}

#[test]
fn an_excavation_of_all_the_rock_is_an_error_of_every_kind() {
    // Each kind of opening, around the whole domain: refused as a ground below the rock is,
    // naming the entry (it was accepted and gave an empty system).
    let run = |joints: &str, entries: &str| {
        let text = format!(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n{joints}\n{entries}"
        );
        let spec = parse_toml(&text).unwrap();
        generate(&spec).map(|g| g.system.len())
    };
    let set = "[[joints]]\ntype = \"set\"\ndip = 0\ndip_direction = 0\nspacing = 3\n";
    let kinds = [
        "type = \"tunnel\"\nprofile = \"circle\"\nradius = 100\nstart = [5, -10, 5]\n\
         trend = 0\nlength = 100",
        "type = \"cavern\"\ncenter = [5, 5, 5]\ntrend = 30\nlength = 100\nwidth = 100\n\
         height = 100",
        "type = \"shaft\"\nprofile = \"circle\"\nradius = 100\ntop = [5, 5, 50]\ndepth = 100",
    ];
    for joints in [set, ""] {
        for kind in kinds {
            let e = run(joints, &format!("[[excavations]]\n{kind}\n"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("excavations[0]: the excavation would remove all of the rock"),
                "{kind}: {e}"
            );
        }
    }
    // Excavating in stages through the API may take all of the rock: an empty system.
    let rock = penedge::BlockSystem::new(vec![
        penedge::ConvexBlock::cuboid([0.0; 3], [10.0; 3]).unwrap()
    ]);
    let all = penedge::generation::Excavation::new(penedge::generation::ExcavationShape::Cavern {
        center: [5.0, 5.0, 5.0],
        trend: 0.0,
        length: 100.0,
        width: 100.0,
        height: 100.0,
    });
    let (left, report) = rock.excavate(&all, &penedge::Tolerance::default()).unwrap();
    assert!(left.is_empty());
    assert_eq!(report.removed_blocks, 1);
    // The second of two excavations, the first leaving some rock: named as the second.
    let half = "[[excavations]]\ntype = \"cavern\"\ncenter = [5, 5, 2]\ntrend = 0\n\
                length = 100\nwidth = 100\nheight = 4\n";
    assert!(run(set, half).unwrap() > 0);
    let e = run(set, &format!("{half}[[excavations]]\n{}\n", kinds[0]))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("excavations[1]: the excavation would remove all of the rock"),
        "{e}"
    );
}

#[test]
fn the_blocks_around_the_tunnel_touch_as_bodies_and_never_across_the_opening() {
    let out = example("tunnel_circular.toml");
    let tol = penedge::Tolerance::default();
    let found = out.system.detect_bodies(&tol);
    assert!(found.penetrating.is_empty());
    assert!(found.contacts.iter().all(|c| c.bodies[0] < c.bodies[1]));
    // No face-face contact lies inside the opening: a region's contact points are all at
    // least the tunnel's inscribed radius (2 cos(pi / 16)) from its axis (x = 6, z = 6)...
    let inner = 2.0 * (std::f64::consts::PI / 16.0).cos();
    {
        for p in &found.piece_points {
            let r = ((p[0] - 6.0).powi(2) + (p[2] - 6.0).powi(2)).sqrt();
            assert!(r > inner - 1e-9, "a contact point inside the tunnel: {p:?}");
        }
    }
    // ...and the blocks' contacts cover the joints that the tunnel did not remove: the joint
    // area left is the joints' area in the box less their sections by the tunnel.
    let found_area: f64 = found
        .contacts
        .iter()
        .filter(|c| c.kind == penedge::ContactType::FaceFace)
        .map(|c| c.area)
        .sum();
    // Joints: bedding z = 2, 6, 10 (12 x 10 each), cross joints x = 1, 6, 11 (10 x 12 each).
    // The tunnel (axis along y at x = z = 6) takes out of z = 6 and of x = 6 a strip as wide
    // as its section across the axis, times 10 m: the 16-gon (a flat side at the bottom) has
    // sides, not vertices, level with the axis and above it, so that width is 2 r cos(pi/16).
    let width = 2.0 * inner;
    let exact = 3.0 * 120.0 + 3.0 * 120.0 - 2.0 * width * 10.0;
    assert!(
        (found_area - exact).abs() < 1e-6 * exact,
        "{found_area} vs {exact}"
    );
}

/// Two excavations through the API, unnamed: their sets get distinct names ("excavation",
/// "excavation 2") and the block file reads back; a name already a joint set's, or holding
/// the contact table's separator, is refused at `excavation.name` (a block file written
/// with it would not read back).
#[test]
fn excavations_get_names_a_block_file_reads_back() {
    use penedge::generation::{Excavation, ExcavationShape};
    use penedge::{BlockSystem, ConvexBlock, Tolerance};
    let tol = Tolerance::default();
    let rock = BlockSystem::new(vec![ConvexBlock::cuboid([0.0; 3], [10.0; 3]).unwrap()]);
    let cavern = |x: f64| {
        Excavation::new(ExcavationShape::Cavern {
            center: [x, 5.0, 5.0],
            trend: 0.0,
            length: 20.0,
            width: 1.0,
            height: 2.0,
        })
    };
    let (once, _) = rock.excavate(&cavern(3.0), &tol).unwrap();
    let (twice, _) = once.excavate(&cavern(7.0), &tol).unwrap();
    let names: Vec<&str> = twice.sets().iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["excavation", "excavation 2"]);
    let text = penedge::io::json::to_json_string(&twice);
    let back = penedge::io::json::from_json_str(&text).unwrap();
    assert_eq!(back.sets(), twice.sets());
    for bad in ["excavation", "a|b", "boundary", "", "bridge of excavation"] {
        let named = Excavation {
            name: Some(bad.to_string()),
            ..cavern(7.0)
        };
        let err = once.excavate(&named, &tol).unwrap_err().to_string();
        assert!(err.contains("excavation.name"), "{err}");
    }
}

#[test]
fn an_excavation_named_as_a_joint_is_refused_naming_the_entry_as_the_spec_does() {
    // The clash read "already that of sets[0]"; the spec calls that entry joints[0].
    let text = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
                [[joints]]\ntype = \"plane\"\nname = \"J1\"\npoint = [0, 0, 3]\n\
                normal = [0, 0, 1]\n\n\
                [[excavations]]\nname = \"T1\"\ntype = \"cavern\"\ncenter = [5, 5, 5]\n\
                trend = 0\nlength = 100\nwidth = 1\nheight = 1\n\n\
                [[excavations]]\nname = \"NAME\"\ntype = \"cavern\"\ncenter = [5, 5, 8]\n\
                trend = 0\nlength = 100\nwidth = 1\nheight = 1\n";
    let error = |name: &str| {
        let spec = parse_toml(&text.replace("NAME", name)).unwrap();
        generate(&spec).unwrap_err().to_string()
    };
    let e = error("J1");
    assert!(
        e.contains("excavations[1].name: the name \"J1\" is already that of joints[0]"),
        "{e}"
    );
    let e = error("T1");
    assert!(e.contains("is already that of excavations[0]"), "{e}");
}

/// A 10 m box split into 3 blocks by vertical joints at x = 2.5 and 7.5, under a bumpy ground of `n` x `n` elevations over x, y in -1..11:
/// its air is `2 (n - 1)^2` triangular columns, and the rock below is cut into thousands
/// of convex parts.
fn bumpy_ground(n: usize) -> penedge::generation::Spec {
    use penedge::generation::{
        Discontinuity, Domain, Excavation, ExcavationShape, JointSet, Orientation, Spec, Surface,
    };
    let step = 12.0 / (n - 1) as f64;
    let xs: Vec<f64> = (0..n).map(|i| -1.0 + i as f64 * step).collect();
    let z: Vec<f64> = (0..n * n)
        .map(|k| {
            let (x, y) = (xs[k % n], xs[k / n]);
            6.0 + 0.3 * (1.3 * x).sin() * (0.9 * y).cos() + 0.1 * (3.1 * x + 2.3 * y).sin()
        })
        .collect();
    let ground = Surface::from_grid(&xs, &xs, &z, "bumpy");
    let set = JointSet {
        origin: [2.5, 0.0, 0.0],
        ..JointSet::new(Orientation::dip(90.0, 90.0), 5.0)
    };
    let mut spec =
        Spec::new(Domain::cuboid([0.0; 3], [10.0; 3]).unwrap()).with(Discontinuity::set(set));
    spec.excavations
        .push(Excavation::new(ExcavationShape::Topography {
            surface: ground,
        }));
    spec
}

#[test]
fn an_excavation_stops_when_its_parts_pass_the_block_limit() {
    use penedge::generation::{generate_with, GenerationError, Limits};
    use std::ops::ControlFlow;
    let spec = bumpy_ground(16);
    let stop = &mut |_| ControlFlow::Continue(());
    let all = generate_with(&spec, &Limits::blocks(1_000_000), stop).unwrap();
    let parts = all.system.len();
    assert!(parts > 300, "{parts}");
    // The joints make 3 blocks, well within the limit; the excavation's parts pass it.
    let err = generate_with(&spec, &Limits::blocks(100), stop).unwrap_err();
    assert!(
        matches!(
            err,
            GenerationError::Outgrew {
                limit: 100,
                excavation: Some(0),
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("excavations[0]"), "{err}");
}

#[test]
fn the_progress_callback_is_asked_during_an_excavation_and_can_stop_it() {
    use penedge::generation::{generate_with, GenerationError, Limits};
    use std::ops::ControlFlow;
    let spec = bumpy_ground(16);
    // Every report: during the excavation the blocks grow past the joints' 3, with every
    // plane applied, and the last report comes once, with the excavation done.
    let mut seen = Vec::new();
    let out = generate_with(&spec, &Limits::default(), &mut |p| {
        seen.push(p);
        ControlFlow::Continue(())
    })
    .unwrap();
    let during: Vec<_> = seen
        .iter()
        .filter(|p| p.planes_done == p.planes_total && p.excavations_done == 0)
        .collect();
    assert!(during.len() > 100, "{}", during.len());
    assert!(during.iter().any(|p| p.blocks > 300), "{during:?}");
    assert_eq!(seen.iter().filter(|p| p.is_last()).count(), 1);
    let last = seen.last().unwrap();
    assert!(
        last.is_last() && last.blocks == out.system.len(),
        "{last:?}"
    );
    // A callback that says stop once the excavation has made 50 parts stops it there.
    let mut calls = 0;
    let err = generate_with(&spec, &Limits::default(), &mut |p| {
        calls += 1;
        if p.blocks > 50 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    })
    .unwrap_err();
    assert!(
        matches!(
            err,
            GenerationError::Cancelled {
                planes_done: 2,
                planes_total: 2
            }
        ),
        "{err:?}"
    );
    assert!(calls < during.len() / 2, "{calls}");
}

#[test]
fn a_circular_tunnel_of_1024_segments_removes_its_polygon_times_its_length() {
    // 1026 faces: more half-spaces than a block from half-spaces takes (128), built from
    // its vertices and faces. A tunnel of radius 2 along y from y = -1 through the 10 m
    // box: 10 m of it within the rock.
    for segments in [127.0, 1024.0] {
        let text = format!(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
             [[joints]]\ntype = \"set\"\ndip = 90\ndip_direction = 90\nspacing = 5\n\
             origin = [2.5, 0, 0]\n\n\
             [[excavations]]\ntype = \"tunnel\"\nstart = [5.3, -1, 4.7]\ntrend = 0\n\
             plunge = 0\nlength = 12\nprofile = \"circle\"\nradius = 2\n\
             segments = {segments}\n"
        );
        let out = generate(&parse_toml(&text).unwrap()).unwrap();
        let exact = polygon_area(segments, 2.0) * 10.0;
        let err = (out.report.excavated_volume - exact).abs();
        assert!(err < 1e-9 * exact, "{segments}: {err}");
        assert!((1000.0 - left(&out) - exact).abs() < 1e-9 * exact);
        // The blocks around the tunnel stay whole: the three joint blocks, in parts.
        assert_eq!(out.system.body_parts().len(), 3);
    }
}

#[test]
fn a_smooth_slope_of_2001_vertices_removes_the_air_above_its_polyline() {
    // A valley v = 2 + 0.06 (u - 5)^2 from u = 0 to 10 at 2001 points: the air above it is
    // one convex piece of 2000 edges and its lid (a valley joins its columns), more
    // half-spaces than a block from half-spaces takes.
    let v = |u: f64| 2.0 + 0.06 * (u - 5.0) * (u - 5.0);
    let vertices: Vec<[f64; 2]> = (0..=2000)
        .map(|k| {
            let u = k as f64 / 200.0;
            [u, v(u)]
        })
        .collect();
    let list: Vec<String> = vertices
        .iter()
        .map(|p| format!("[{:?}, {:?}]", p[0], p[1]))
        .collect();
    let text = format!(
        "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
         [[joints]]\ntype = \"set\"\ndip = 90\ndip_direction = 90\nspacing = 5\n\
         origin = [2.5, 0, 0]\n\n\
         [[excavations]]\ntype = \"slope\"\norigin = [0, 0, 0]\ntrend = 0\n\
         vertices = [{}]\n",
        list.join(", ")
    );
    let out = generate(&parse_toml(&text).unwrap()).unwrap();
    // The air between the polyline and the top z = 10, 10 m along y.
    let air: f64 = vertices
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]) * (10.0 - 0.5 * (w[0][1] + w[1][1])))
        .sum::<f64>()
        * 10.0;
    let err = (out.report.excavated_volume - air).abs();
    assert!(err < 1e-9 * air, "{err}");
    assert!((1000.0 - left(&out) - air).abs() < 1e-9 * air);
    assert_eq!(out.system.body_parts().len(), 3);
}

/// A 10 m box split by the joint x = 5, an opening `cavern` that removes x from 2 to
/// `5 - thin` right through (leaving a slab `thin` thick against the joint), an `extra`
/// entry, and `slivers` as the policy.
fn thin_slab(thin: f64, slivers: &str, extra: &str) -> penedge::generation::Generated {
    let width = 3.0 - thin;
    let text = format!(
        "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
         [options]\nslivers = \"{slivers}\"\n\n\
         [[joints]]\ntype = \"plane\"\npoint = [5, 0, 0]\ndip = 90\ndip_direction = 90\n\n\
         [[excavations]]\ntype = \"cavern\"\ncenter = [{x}, 5, 5]\ntrend = 0\nlength = 20\n\
         width = {width}\nheight = 20\n{extra}",
        x = 2.0 + 0.5 * width,
    );
    generate(&parse_toml(&text).unwrap()).unwrap()
}

/// The body whose parts' centroids all lie strictly between `x0` and `x1` in x, if any.
fn body_between(out: &penedge::generation::Generated, x0: f64, x1: f64) -> Option<u32> {
    let blocks = out.system.blocks();
    out.system
        .body_parts()
        .into_iter()
        .find(|(_, parts)| {
            parts.iter().all(|&k| {
                let x = blocks[k as usize].centroid().x;
                x0 < x && x < x1
            })
        })
        .map(|(body, _)| body)
}

#[test]
fn a_sliver_left_by_an_excavation_is_listed_or_dropped_by_the_sliver_policy() {
    // The slab 2e-6 thick is far below the default minimum thickness (1e-6 of the domain's
    // size: 1.7e-5); the joints' cut alone made no sliver.
    let thin = 2e-6;
    let kept = thin_slab(thin, "keep", "");
    assert_eq!(kept.report.slivers.count, 0);
    let slivers = &kept.report.excavation_slivers;
    assert_eq!(slivers.count, 1, "{slivers:?}");
    let exact = thin * 10.0 * 10.0;
    assert!((slivers.volume - exact).abs() < 1e-6 * exact, "{slivers:?}");
    let slab = body_between(&kept, 5.0 - thin, 5.0).expect("the slab is a body");
    assert_eq!(slivers.kept_bodies, vec![slab]);
    assert_eq!(kept.system.body_parts().len(), 3);

    let dropped = thin_slab(thin, "drop", "");
    let slivers = &dropped.report.excavation_slivers;
    assert_eq!(slivers.count, 1);
    assert!(slivers.kept_bodies.is_empty());
    assert!(body_between(&dropped, 5.0 - thin, 5.0).is_none());
    // The rock left: 1000 m^3 less the opening (3 - thin wide) less the slab.
    assert_eq!(dropped.system.len(), 2);
    assert_eq!(dropped.report.blocks, 2);
    assert!((dropped.report.block_volume - 700.0).abs() < 1e-9 * 700.0);
    assert!((left(&dropped) - 700.0).abs() < 1e-9 * 700.0);
    assert_eq!(dropped.system.body_ids(), vec![0, 1]);

    // A slab thicker than the limit is not a sliver.
    let thick = thin_slab(1e-3, "drop", "");
    assert_eq!(thick.report.excavation_slivers.count, 0);
    assert_eq!(thick.system.body_parts().len(), 3);
}

#[test]
fn dropping_an_excavations_sliver_keeps_the_other_bodies_glue() {
    // A second opening takes the corner x > 7, z > 7 off the block beyond the joint: an
    // L-shaped body of convex parts glued along internal faces, beside the sliver.
    let corner = "\n[[excavations]]\ntype = \"cavern\"\ncenter = [10, 5, 10]\ntrend = 0\n\
                  length = 20\nwidth = 6\nheight = 6\n";
    let kept = thin_slab(2e-6, "keep", corner);
    let dropped = thin_slab(2e-6, "drop", corner);
    assert_eq!(kept.report.excavation_slivers.count, 1);
    assert_eq!(dropped.report.excavation_slivers.count, 1);
    let l_body = |out: &penedge::generation::Generated| {
        let body = body_between(out, 5.0, 10.0).expect("the L-shaped body");
        let parts: Vec<u32> = out
            .system
            .body_parts()
            .into_iter()
            .find(|(b, _)| *b == body)
            .unwrap()
            .1;
        let blocks: Vec<_> = parts
            .iter()
            .map(|&k| out.system.blocks()[k as usize].clone())
            .collect();
        // The internal faces of the body, by their parts' blocks rather than their ids.
        let faces: Vec<_> = out
            .system
            .internal_faces()
            .iter()
            .filter(|f| parts.contains(&f.parts[0]))
            .map(|f| {
                let at = |p: u32| parts.iter().position(|&q| q == p).unwrap();
                (f.parts.map(at), f.faces, f.area)
            })
            .collect();
        let covered: Vec<(usize, u32)> = parts
            .iter()
            .enumerate()
            .flat_map(|(i, &k)| {
                let n = out.system.blocks()[k as usize].planes().len() as u32;
                (0..n)
                    .filter(move |&f| out.system.is_internal_face(k, f))
                    .map(move |f| (i, f))
            })
            .collect();
        (blocks, faces, covered)
    };
    let (blocks_kept, faces_kept, covered_kept) = l_body(&kept);
    let (blocks_dropped, faces_dropped, covered_dropped) = l_body(&dropped);
    assert!(blocks_kept.len() >= 2, "the L is concave: several parts");
    assert_eq!(blocks_kept, blocks_dropped);
    assert_eq!(faces_kept, faces_dropped);
    assert!(!faces_dropped.is_empty());
    assert_eq!(covered_kept, covered_dropped);
    // Its volume: the half block less the 3 x 10 x 3 corner.
    let volume: f64 = blocks_dropped.iter().map(|b| b.volume()).sum();
    assert!((volume - (500.0 - 90.0)).abs() < 1e-9 * 410.0);
    assert_eq!(dropped.system.body_parts().len(), 2);
}

#[test]
fn an_excavation_that_leaves_only_slivers_to_drop_is_an_error() {
    let text = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
                [options]\nslivers = \"drop\"\n\n\
                [[excavations]]\ntype = \"cavern\"\ncenter = [5, 5, 5.0000005]\ntrend = 0\n\
                length = 20\nwidth = 20\nheight = 9.999999\n";
    let err = generate(&parse_toml(text).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("options.slivers") && err.contains("sliver"),
        "{err}"
    );
}

#[test]
fn slivers_an_excavation_leaves_under_a_bridged_joint_are_found_before_the_glue() {
    // A horizontal disc joint with rock bridges at z = 5 and an opening whose top stops
    // 1e-6 m below it: the slab between is cut into pieces that the bridge glues to the rock
    // above (one body), yet each is a rigid body of its own in a simulation, 1e-6 m thick
    // (a reviewer's case: they were in no report and not dropped).
    let spec = |policy: &str| {
        format!(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
             [options]\nslivers = \"{policy}\"\n\n\
             [[joints]]\ntype = \"disc\"\ncenter = [5, 5, 5]\nradius = 3\ndip = 0\n\
             dip_direction = 0\nbridge = true\n\n\
             [[excavations]]\ntype = \"cavern\"\ncenter = [5, 5, 2.499999]\ntrend = 0\n\
             length = 12\nwidth = 12\nheight = 5\n"
        )
    };
    let in_slab = |b: &penedge::ConvexBlock| {
        let z = b.vertices().iter().map(|v| v.z);
        z.clone().fold(f64::INFINITY, f64::min) > 4.999998 && z.fold(0.0, f64::max) < 5.000001
    };
    let kept = generate(&parse_toml(&spec("keep")).unwrap()).unwrap();
    let pieces: Vec<u32> = (0..kept.system.len() as u32)
        .filter(|&k| in_slab(&kept.system.blocks()[k as usize]))
        .collect();
    assert!(
        !pieces.is_empty(),
        "the opening leaves a slab under the disc"
    );
    let slivers = &kept.report.excavation_slivers;
    assert_eq!(slivers.count, pieces.len(), "{slivers:?}");
    // Listed by the bodies they are glued into.
    for &k in &pieces {
        assert!(slivers.kept_bodies.contains(&kept.system.body_of(k)));
    }
    let dropped = generate(&parse_toml(&spec("drop")).unwrap()).unwrap();
    assert_eq!(dropped.report.excavation_slivers.count, pieces.len());
    assert!(dropped.report.excavation_slivers.kept_bodies.is_empty());
    assert!(!dropped.system.blocks().iter().any(in_slab));
    let slab: f64 = pieces
        .iter()
        .map(|&k| kept.system.blocks()[k as usize].volume())
        .sum();
    assert!((left(&kept) - left(&dropped) - slab).abs() < 1e-9 * left(&kept));
}
