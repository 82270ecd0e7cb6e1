//! Slopes and topographic surfaces: the rock left below a profile or a surface has the
//! exact volume under it (worked out here by integrating the piecewise linear surface, not
//! by the code), its blocks do not penetrate, the same ground given as a profile or as
//! triangulated surfaces of different triangulations gives the same blocks and contacts, and
//! bad surfaces are errors naming what is wrong.

use penedge::generation::{
    generate, Discontinuity, Domain, Excavation, ExcavationShape, JointSet, Orientation, Spec,
    Surface,
};
use penedge::io::spec::{parse_toml, parse_toml_in};
use penedge::io::surface::{parse_surface, Kind};
use penedge::{BlockSystem, ContactType, Tolerance};
use std::path::Path;

fn jointed(min: [f64; 3], max: [f64; 3]) -> Spec {
    let set = |dip, dir, spacing| {
        let mut s = JointSet::new(Orientation::dip(dip, dir), spacing);
        s.origin = [0.3, 0.7, 0.45];
        Discontinuity::set(s)
    };
    Spec::new(Domain::cuboid(min, max).unwrap())
        .with(set(0.0, 0.0, 4.0))
        .with(set(90.0, 90.0, 5.0))
        .with(set(60.0, 250.0, 6.0))
}

fn volume(s: &BlockSystem) -> f64 {
    s.blocks().iter().map(|b| b.volume()).sum()
}

/// The elevation of a polyline `(u, v)` (increasing `u`) at `x`, extended horizontally
/// past its ends.
fn ground(line: &[[f64; 2]], x: f64) -> f64 {
    match line.windows(2).find(|w| w[0][0] <= x && x <= w[1][0]) {
        Some(w) => w[0][1] + (w[1][1] - w[0][1]) * (x - w[0][0]) / (w[1][0] - w[0][0]),
        None if x < line[0][0] => line[0][1],
        None => line[line.len() - 1][1],
    }
}

/// The area under a polyline from `a` to `b`: trapezoids between its vertices.
fn area_under(line: &[[f64; 2]], a: f64, b: f64) -> f64 {
    let mut xs = vec![a];
    xs.extend(line.iter().map(|p| p[0]).filter(|&x| x > a && x < b));
    xs.push(b);
    xs.windows(2)
        .map(|w| (w[1] - w[0]) * (ground(line, w[0]) + ground(line, w[1])) / 2.0)
        .sum()
}

/// A benched profile: crest at 12 m, faces down to a bench at 7 m, to the toe at 3 m.
const BENCHES: [[f64; 2]; 6] = [
    [2.0, 12.0],
    [6.0, 12.0],
    [9.0, 7.0],
    [12.0, 7.0],
    [15.0, 3.0],
    [18.0, 3.0],
];

fn assert_close(got: f64, exact: f64, what: &str) {
    assert!(
        (got - exact).abs() < 1e-9 * exact,
        "{what}: {got} against {exact} (difference {:e})",
        got - exact
    );
}

#[test]
fn a_benched_slope_leaves_the_area_under_its_profile_times_the_length() {
    // Strike North (u East), the profile's origin on the domain's West edge at z = 0.
    let slope = Excavation::new(ExcavationShape::Slope {
        origin: [0.0, 0.0, 0.0],
        trend: 0.0,
        vertices: BENCHES.to_vec(),
    });
    let spec = jointed([0.0; 3], [20.0, 10.0, 15.0]).excavate(slope);
    let out = generate(&spec).unwrap();
    let exact = area_under(&BENCHES, 0.0, 20.0) * 10.0;
    assert_close(volume(&out.system), exact, "rock left");
    assert_close(
        out.report.excavated_volume,
        20.0 * 10.0 * 15.0 - exact,
        "volume removed",
    );
    let found = out.system.detect_bodies(&Tolerance::default());
    assert!(found.penetrating.is_empty(), "{:?}", found.penetrating);
    // No block above the profile.
    for b in out.system.blocks() {
        let c = b.centroid();
        assert!(
            c.z < ground(&BENCHES, c.x),
            "a part's centroid {c} is above the ground"
        );
    }

    // The same ground with the strike looking South: u is West, so u = -x.
    let slope = Excavation::new(ExcavationShape::Slope {
        origin: [0.0, 0.0, 0.0],
        trend: 180.0,
        vertices: BENCHES.iter().map(|p| [-p[0], p[1]]).collect(),
    });
    let other = generate(&jointed([0.0; 3], [20.0, 10.0, 15.0]).excavate(slope)).unwrap();
    assert_close(volume(&other.system), exact, "rock left, mirrored");
}

#[test]
fn a_slope_along_an_oblique_strike_in_a_domain_turned_with_it_leaves_the_same_rock() {
    // The box of the first test turned about z so that its x axis is the profile's u for a
    // strike trending N30E: u = (cos 30, -sin 30, 0), the strike d = (sin 30, cos 30, 0).
    let t = 30f64.to_radians();
    let (u, d) = ([t.cos(), -t.sin(), 0.0], [t.sin(), t.cos(), 0.0]);
    let neg = |v: [f64; 3]| v.map(|x| -x);
    let normals = [neg(u), u, neg(d), d, [0.0, 0.0, -1.0], [0.0, 0.0, 1.0]];
    let domain = Domain::from_halfspaces(&normals, &[0.0, 20.0, 0.0, 10.0, 0.0, 15.0]).unwrap();
    let mut s = JointSet::new(Orientation::dip(0.0, 0.0), 4.0);
    s.origin = [0.0, 0.0, 0.45];
    let slope = Excavation::new(ExcavationShape::Slope {
        origin: [0.0, 0.0, 0.0],
        trend: 30.0,
        vertices: BENCHES.to_vec(),
    });
    let spec = Spec::new(domain)
        .with(Discontinuity::set(s))
        .with(Discontinuity::plane(
            [5.0, 5.0, 0.0],
            Orientation::dip(90.0, 75.0),
        ))
        .excavate(slope);
    let out = generate(&spec).unwrap();
    let exact = area_under(&BENCHES, 0.0, 20.0) * 10.0;
    assert_close(volume(&out.system), exact, "rock left, oblique strike");
}

#[test]
fn a_pyramid_hill_from_obj_and_stl_files_leaves_its_exact_volume() {
    // A square pyramid on a 10 x 10 base at z = 2, apex (5, 5, 7): rock 100 x 2 + 100 x 5 / 3.
    let dir = std::env::temp_dir().join(format!("penedge-pyramid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let corners = [
        [0.0, 0.0, 2.0],
        [10.0, 0.0, 2.0],
        [10.0, 10.0, 2.0],
        [0.0, 10.0, 2.0],
    ];
    let apex = [5.0f64, 5.0, 7.0];
    let mut obj = String::new();
    for p in corners.iter().chain([&apex]) {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    obj += "f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";
    std::fs::write(dir.join("pyramid.obj"), obj).unwrap();
    // The same triangles as binary STL, wound the other way (the winding is ignored).
    let mut stl = vec![0u8; 80];
    stl.extend(4u32.to_le_bytes());
    for k in 0..4 {
        stl.extend([0u8; 12]);
        for p in [corners[(k + 1) % 4], corners[k], apex] {
            p.iter().for_each(|c| stl.extend((*c as f32).to_le_bytes()));
        }
        stl.extend([0u8; 2]);
    }
    std::fs::write(dir.join("pyramid.stl"), stl).unwrap();
    let exact = 200.0 + 500.0 / 3.0;
    for file in ["pyramid.obj", "pyramid.stl"] {
        let text = format!(
            "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
             [[joints]]\ntype = \"set\"\ndip = 20\ndip_direction = 30\nspacing = 2.2\n\n\
             [[excavations]]\ntype = \"topography\"\nfile = \"{file}\"\n"
        );
        let out = generate(&parse_toml_in(&text, &dir).unwrap()).unwrap();
        assert_close(volume(&out.system), exact, file);
        let found = out.system.detect_bodies(&Tolerance::default());
        assert!(
            found.penetrating.is_empty(),
            "{file}: {:?}",
            found.penetrating
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Elevations of a hill on a grid: not a plane, so each cell's two triangles differ.
fn hill(x: f64, y: f64) -> f64 {
    4.0 + 0.25 * x + 3.0 * (-((x - 8.0).powi(2) + (y - 5.0).powi(2)) / 20.0).exp()
}

#[test]
fn a_topographic_grid_leaves_the_volume_under_its_triangles() {
    let xs: Vec<f64> = (0..=5).map(|i| i as f64 * 4.0).collect(); // 0..20
    let ys: Vec<f64> = [0.0, 2.5, 6.0, 10.0].to_vec();
    let z: Vec<f64> = ys
        .iter()
        .flat_map(|&y| xs.iter().map(move |&x| hill(x, y)))
        .collect();
    let surface = Surface::from_grid(&xs, &ys, &z, "hill");
    // Exact: each cell is cut along its diagonal from (x_i, y_j) to (x_i+1, y_j+1); a
    // triangle's prism down to z = 0 has the triangle's area times its mean elevation.
    let mut exact = 0.0;
    for j in 0..ys.len() - 1 {
        for i in 0..xs.len() - 1 {
            let half = (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) / 2.0;
            let (a, b) = (hill(xs[i], ys[j]), hill(xs[i + 1], ys[j]));
            let (c, d) = (hill(xs[i + 1], ys[j + 1]), hill(xs[i], ys[j + 1]));
            exact += half * (a + b + c) / 3.0 + half * (a + c + d) / 3.0;
        }
    }
    let top = Excavation::new(ExcavationShape::Topography { surface });
    let out = generate(&jointed([0.0; 3], [20.0, 10.0, 15.0]).excavate(top)).unwrap();
    assert_close(volume(&out.system), exact, "rock under the grid");
    let found = out.system.detect_bodies(&Tolerance::default());
    assert!(found.penetrating.is_empty(), "{:?}", found.penetrating);
    assert!(out.system.has_concave());
}

/// The bodies (volume, centroid) and contact regions (the bodies' centroids, type, area,
/// normal) of a system, rounded and sorted: what does not depend on how the bodies are
/// decomposed into parts, nor on their ids.
type Summary = (Vec<[i64; 4]>, Vec<String>);

fn summary(s: &BlockSystem) -> Summary {
    let r = |x: f64| (x * 1e6).round() as i64;
    let props = s.body_mass_properties();
    let mut bodies: Vec<[i64; 4]> = props
        .iter()
        .map(|(_, m)| {
            [
                r(m.volume),
                r(m.centroid.x),
                r(m.centroid.y),
                r(m.centroid.z),
            ]
        })
        .collect();
    bodies.sort();
    let centroid = |id: u32| {
        let m = &props.iter().find(|p| p.0 == id).unwrap().1;
        [r(m.centroid.x), r(m.centroid.y), r(m.centroid.z)]
    };
    let found = s.detect_bodies(&Tolerance::default());
    assert!(found.penetrating.is_empty(), "{:?}", found.penetrating);
    let mut contacts: Vec<String> = found
        .contacts
        .iter()
        .map(|c| {
            let (a, b) = (centroid(c.bodies[0]), centroid(c.bodies[1]));
            // Order the pair by centroid, the normal with it.
            let sign = if a <= b { 1.0 } else { -1.0 };
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            // Vertex-vertex, vertex-edge and edge-edge superposition contacts have a cone of
            // valid normals (docs/benchmarks.md); which one is picked can depend on the
            // parts, so only the normals of the other types are compared.
            let unique = !matches!(
                c.kind,
                ContactType::VertexVertex
                    | ContactType::VertexEdge
                    | ContactType::EdgeEdgeSuperposition
            );
            let n = if unique {
                c.normal.map(|x| r(sign * x))
            } else {
                [0; 3]
            };
            format!("{a:?} {b:?} {:?} {} {n:?}", c.kind, r(c.area))
        })
        .collect();
    contacts.sort();
    (bodies, contacts)
}

#[test]
fn the_same_ground_as_a_profile_or_as_two_triangulations_gives_the_same_blocks() {
    // A crest and a face, strike North: the ground over x, whatever y.
    let line = [[0.0, 9.0], [7.0, 9.0], [11.0, 4.0], [16.0, 4.0]];
    let spec = || jointed([0.0; 3], [16.0, 8.0, 12.0]);
    let profile = Excavation::new(ExcavationShape::Slope {
        origin: [0.0, 0.0, 0.0],
        trend: 0.0,
        vertices: line.to_vec(),
    });
    // The same ground as triangles: each strip between two profile vertices is a
    // rectangle, cut along one diagonal or the other.
    let mesh = |flip: bool| {
        let mut triangles = Vec::new();
        for w in line.windows(2) {
            let a = [w[0][0], 0.0, w[0][1]];
            let b = [w[1][0], 0.0, w[1][1]];
            let c = [w[1][0], 8.0, w[1][1]];
            let d = [w[0][0], 8.0, w[0][1]];
            if flip {
                triangles.extend([[a, b, d], [b, c, d]]);
            } else {
                triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
        let surface = Surface::new(triangles, "mesh");
        Excavation::new(ExcavationShape::Topography { surface })
    };
    let by_profile = generate(&spec().excavate(profile)).unwrap().system;
    let by_mesh = generate(&spec().excavate(mesh(false))).unwrap().system;
    let by_flipped = generate(&spec().excavate(mesh(true))).unwrap().system;
    let reference = summary(&by_profile);
    assert!(reference.0.len() > 10 && reference.1.len() > 20);
    for other in [&by_mesh, &by_flipped] {
        let got = summary(other);
        let only = |a: &Summary, b: &Summary| {
            let bodies: Vec<_> = a.0.iter().filter(|x| !b.0.contains(x)).collect();
            let contacts: Vec<_> = a.1.iter().filter(|x| !b.1.contains(x)).collect();
            format!("{bodies:?} {contacts:?}")
        };
        assert!(
            got == reference,
            "only by profile: {}\nonly by mesh: {}",
            only(&reference, &got),
            only(&got, &reference)
        );
    }
    // The part decompositions differ: the mesh's strips cut the parts along y too.
    assert_ne!(by_profile.len(), by_flipped.len());
}

#[test]
fn slopes_and_surfaces_are_read_from_a_spec_and_bad_ones_are_named() {
    let dir = std::env::temp_dir().join(format!("penedge-slopes-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("data")).unwrap();
    let head = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n\n\
                [[excavations]]\n";
    let run = |entry: &str| {
        let spec = parse_toml_in(&format!("{head}{entry}"), &dir)?;
        generate(&spec).map(|g| g.system).map_err(|e| match e {
            penedge::generation::GenerationError::Spec(s) => s,
            other => panic!("{other}"),
        })
    };
    // A plane ramp z = 2 + 0.5 x as a grid file, relative to the spec's folder.
    let mut xyz = String::from("x y z\n");
    for y in [0.0, 10.0] {
        for x in [0.0, 5.0, 10.0] {
            xyz += &format!("{x} {y} {}\n", 2.0 + 0.5 * x);
        }
    }
    std::fs::write(dir.join("data/ramp.xyz"), &xyz).unwrap();
    let s = run("type = \"topography\"\nfile = \"data/ramp.xyz\"\n").unwrap();
    assert_close(volume(&s), 100.0 * (2.0 + 2.5), "rock under the ramp");

    // The ramp in map coordinates (eastings, northings, elevations 100 m up), brought back.
    let mut map = String::from("x y z\n");
    for y in [0.0, 10.0] {
        for x in [0.0, 5.0, 10.0] {
            map += &format!(
                "{} {} {}\n",
                512_300.0 + x,
                5_100_200.0 + y,
                102.0 + 0.5 * x
            );
        }
    }
    std::fs::write(dir.join("data/map.xyz"), map).unwrap();
    let s = run("type = \"topography\"\nfile = \"data/map.xyz\"\n\
                 offset = [-512300, -5100200, -100]\n")
    .unwrap();
    assert_close(volume(&s), 450.0, "rock under the ramp, in map coordinates");
    let e = run("type = \"topography\"\nfile = \"data/map.xyz\"\n").unwrap_err();
    assert!(e.to_string().contains("does not cover the rock"), "{e}");
    // The same ramp as an ESRI ASCII grid: nodes at the cells' centres.
    let asc = "ncols 3\nnrows 2\nxllcenter 0\nyllcenter 0\ndx 5\ndy 10\n\
               NODATA_value -9999\n2 4.5 7\n2 4.5 7\n";
    std::fs::write(dir.join("data/ramp.asc"), asc).unwrap();
    let s = run("type = \"topography\"\nfile = \"data/ramp.asc\"\n").unwrap();
    assert_close(volume(&s), 450.0, "rock under the ramp, ESRI grid");
    std::fs::write(
        dir.join("data/holed.asc"),
        asc.replace("2 4.5 7\n2", "2 -9999 7\n2"),
    )
    .unwrap();
    let e = run("type = \"topography\"\nfile = \"data/holed.asc\"\n").unwrap_err();
    assert!(
        e.to_string().contains("(x = 5, y = 10) has no elevation"),
        "{e}"
    );
    // A hole: one node missing.
    let holed: String = xyz
        .lines()
        .filter(|l| *l != "5 10 4.5")
        .map(|l| l.to_string() + "\n")
        .collect();
    std::fs::write(dir.join("data/holed.csv"), holed).unwrap();
    let e = run("type = \"topography\"\nfile = \"data/holed.csv\"\n").unwrap_err();
    assert_eq!(e.field, "excavations[0].file");
    assert!(
        e.to_string().contains("no elevation at x = 5, y = 10"),
        "{e}"
    );
    // A header claiming 10^8 x 10^8 values before three: refused from the header, naming
    // the entry (it aborted the process, allocating 80 PB before reading a value).
    std::fs::write(
        dir.join("data/huge.asc"),
        "ncols 100000000\nnrows 100000000\nxllcorner -6\nyllcorner -6\ncellsize 11\n5 5 5\n",
    )
    .unwrap();
    let e = run("type = \"topography\"\nfile = \"data/huge.asc\"\n").unwrap_err();
    assert_eq!(e.field, "excavations[0].file");
    assert!(
        e.to_string().contains(
            "a grid of 100000000 x 100000000 nodes (ncols x nrows) would make \
             19999999600000002 triangles, more than the limit of 2000000"
        ),
        "{e}"
    );
    // A file of the wrong kind; a missing file; an unknown extension.
    std::fs::write(dir.join("data/ramp.stl"), &xyz).unwrap();
    let e = run("type = \"topography\"\nfile = \"data/ramp.stl\"\n").unwrap_err();
    assert!(e.to_string().contains("not an STL file"), "{e}");
    let e = run("type = \"topography\"\nfile = \"data/none.obj\"\n").unwrap_err();
    assert!(e.to_string().contains("none.obj"), "{e}");
    let e = run("type = \"topography\"\nfile = \"data/ramp.las\"\n").unwrap_err();
    assert!(
        e.to_string().contains("unknown kind of surface file"),
        "{e}"
    );
    // A mesh smaller than the rock, and one above it.
    let obj = "v 0 0 5\nv 10 0 5\nv 10 8 5\nv 0 8 5\nf 1 2 3 4\n";
    std::fs::write(dir.join("data/short.obj"), obj).unwrap();
    let e = run("type = \"topography\"\nfile = \"data/short.obj\"\n").unwrap_err();
    assert!(
        e.to_string()
            .contains("does not cover the rock: 20 of the 100"),
        "{e}"
    );
    std::fs::write(
        dir.join("data/high.obj"),
        obj.replace(" 8 ", " 10 ").replace(" 5\n", " 12\n"),
    )
    .unwrap();
    let e = run("type = \"topography\"\nfile = \"data/high.obj\"\n").unwrap_err();
    assert!(e.to_string().contains("entirely above the rock"), "{e}");

    // A profile that goes back, one below the rock, a field that is not a slope's.
    let slope = "type = \"slope\"\norigin = [0, 0, 0]\ntrend = 0\n";
    let e = run(&format!(
        "{slope}vertices = [[0, 5], [4, 5], [3, 2], [10, 2]]\n"
    ))
    .unwrap_err();
    assert_eq!(e.field, "excavations[0].vertices");
    assert!(e.to_string().contains("must go one way along u"), "{e}");
    let e = run(&format!("{slope}vertices = [[0, -1], [10, -2]]\n")).unwrap_err();
    assert!(e.to_string().contains("entirely below the rock"), "{e}");
    let e = run(&format!(
        "{slope}vertices = [[0, 5], [10, 2]]\nradius = 3\n"
    ))
    .unwrap_err();
    assert_eq!(e.field, "excavations[0].radius");
    let s = run(&format!("{slope}vertices = [[0, 5], [10, 2]]\n")).unwrap();
    assert_close(volume(&s), 35.0 * 10.0, "rock under the plane slope");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_slope_examples_run() {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for name in ["slope_profile.toml", "slope_topography.toml"] {
        let path = examples.join(name);
        let spec = penedge::io::spec::read_spec(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let out = generate(&spec).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(out.system.len() > 10, "{name}");
        assert!(out.report.excavated_volume > 0.0, "{name}");
    }
    // parse_toml reads surface files relative to the current folder: a plain name there.
    assert!(parse_toml("[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n").is_ok());
}

#[test]
fn the_surface_fuzz_target_takes_its_seeds() {
    let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/read_surface");
    let mut count = 0;
    for entry in std::fs::read_dir(seeds).unwrap() {
        let data = std::fs::read(entry.unwrap().path()).unwrap();
        // Each seed is a good surface: it parses and excavates the cube.
        penedge::fuzzing::read_surface(&data);
        let kind = [Kind::Grid, Kind::Asc, Kind::Obj, Kind::Stl][data[0] as usize % 4];
        let surface = parse_surface(kind, &data[1..], "seed").unwrap();
        let rock = BlockSystem::new(vec![
            penedge::ConvexBlock::cuboid([0.0; 3], [10.0; 3]).unwrap()
        ]);
        let ground = Excavation::new(ExcavationShape::Topography { surface });
        rock.excavate(&ground, &Tolerance::default()).unwrap();
        count += 1;
    }
    assert_eq!(count, 5);
}
