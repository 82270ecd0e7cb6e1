//! The `tunnel` subcommand: detection around a tunnel with concave blocks and rock bridges
//! (issue 20, "Speed").
//!
//! `cargo run --release -p penedge-bench -- tunnel [--runs R] [--threads T] [--spacing S]
//! [--persistence P] [--radius M] [--profile]`
//!
//! The model: the 100 m cube of `examples/three_joint_sets.toml` (three joint sets, spacing
//! `S`, default 2.13 m: about 10^5 blocks) with a circular tunnel (radius `M`, default 8 m, 32
//! segments) driven North through its middle, as `examples/tunnel_circular.toml` does: the
//! blocks the tunnel's wall crosses become concave blocks of convex parts. The third set
//! (J3) is a **finite-joint set of persistence `P`** (default 0.7): as 3DEC does, its planes
//! cut the blocks through, and the part of each plane that is not joint is a rock bridge
//! holding the blocks on either side together, one body. On each J3 plane the joints are
//! strips across the dip direction: along the strike, a stretch of `P L` of joint, then
//! `(1 - P) L` of bridge (`L` = 4 spacings), the pattern shifted along the strike by a
//! pseudo-random offset per plane. Two blocks whose J3 faces touch face to face with the
//! centroid of the first one's face on a bridge are glued (parts of one body), as are the
//! parts the tunnel made; bodies are the connected groups.
//!
//! Times (wall clock and process CPU time, medians of `R` rounds, `T` threads, default 2),
//! in the same run:
//! 1. `detect_bodies` on the system with its bodies;
//! 2. `detect_bodies` on the same convex parts, each its own block (the reference of the
//!    issue's 1.5x bound);
//! 3. `detect_with_geometry` and `detect` on the parts, for reference;
//! 4. `with_bodies`, once.
//!
//! `--profile` runs only the first, `R` times, after the set-up (for `perf record`).
//!
//! Rounds are interleaved (each times the four in turn) so that a change of load on a shared
//! machine weighs on all of them alike.

use crate::system::{pool, timed};
use penedge::block::FaceOrigin;
use penedge::generation::generate;
use penedge::system::{BlockSystem, BodyShape};
use penedge::{ContactType, ConvexBlock, Feature, Tolerance};

struct Options {
    runs: usize,
    threads: usize,
    spacing: f64,
    persistence: f64,
    radius: f64,
    /// Only `detect_bodies` on the bodies, `runs` times (for a profiler).
    profile: bool,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        runs: 3,
        threads: 2,
        spacing: 2.13,
        persistence: 0.7,
        radius: 8.0,
        profile: false,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        let mut real = |name: &str| -> Result<f64, String> {
            value()?.parse().map_err(|e| format!("{name}: {e}"))
        };
        match flag.as_str() {
            "--runs" => o.runs = crate::number(value()?)?,
            "--threads" => o.threads = crate::number(value()?)?,
            "--spacing" => o.spacing = real("--spacing")?,
            "--persistence" => o.persistence = real("--persistence")?,
            "--radius" => o.radius = real("--radius")?,
            "--profile" => o.profile = true,
            other => return Err(format!("unknown option {other}")),
        }
    }
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if o.runs == 0 || o.threads == 0 {
        return Err("--runs and --threads must be positive".to_string());
    }
    if !(positive(o.spacing) && positive(o.radius) && o.radius < 40.0) {
        return Err("--spacing must be positive, --radius in (0, 40) m".to_string());
    }
    if !(0.0..=1.0).contains(&o.persistence) {
        return Err(format!(
            "--persistence must be in [0, 1], got {}",
            o.persistence
        ));
    }
    Ok(o)
}

/// The generation spec: three joint sets and the tunnel.
fn spec_text(o: &Options) -> String {
    let set = |name: &str, dip: f64, direction: f64| {
        format!(
            "[[joints]]\ntype = \"set\"\nname = \"{name}\"\ndip = {dip}\ndip_direction = \
             {direction}\nspacing = {}\norigin = [0.3, 0.7, 0.11]\n\n",
            o.spacing
        )
    };
    format!(
        "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [100, 100, 100]\n\n{}{}{}\
         [[excavations]]\ntype = \"tunnel\"\nname = \"drive\"\nprofile = \"circle\"\n\
         radius = {}\nsegments = 32\nstart = [50, -1, 50]\ntrend = 0\nplunge = 0\n\
         length = 102\n",
        set("J1", 30.0, 45.0),
        set("J2", 70.0, 160.0),
        set("J3", 80.0, 280.0),
        o.radius
    )
}

/// A number in [0, 1) from an integer (SplitMix64's finaliser).
fn scatter(k: u64) -> f64 {
    let mut z = k.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// The centroid of face `f` of `block` (the mean of its vertices).
fn face_centre(block: &ConvexBlock, f: usize) -> penedge::geometry::DVec3 {
    let face = block.face(f);
    let sum: penedge::geometry::DVec3 = face.iter().map(|&v| block.vertices()[v as usize]).sum();
    sum / face.len() as f64
}

/// Body ids: the generated bodies (the tunnel's concave blocks) joined across the rock
/// bridges of set `bridged` (module docs).
fn bridged_bodies(system: &BlockSystem, tol: &Tolerance, bridged: u32, o: &Options) -> Vec<u32> {
    let n = system.len();
    let mut root: Vec<u32> = (0..n as u32).collect();
    fn find(root: &mut [u32], mut k: u32) -> u32 {
        while root[k as usize] != k {
            root[k as usize] = root[root[k as usize] as usize];
            k = root[k as usize];
        }
        k
    }
    // The generated bodies (parts ascending): each part joined to the first.
    for (_, parts) in system.body_parts() {
        for &k in &parts[1..] {
            root[k as usize] = parts[0];
        }
    }
    let period = 4.0 * o.spacing;
    for c in system.detect(tol).contacts {
        let (Feature::Face(fa), Feature::Face(_)) = (c.contact.feature_a, c.contact.feature_b)
        else {
            continue;
        };
        if c.contact.kind != ContactType::FaceFace {
            continue;
        }
        let a = &system.blocks()[c.pair[0] as usize];
        let FaceOrigin::Joint { set, joint } = a.face_origins()[fa as usize] else {
            continue;
        };
        if set != bridged {
            continue;
        }
        let plane = &system.joints()[joint as usize].plane;
        // Along the strike: horizontal, in the plane.
        let strike = plane.normal.cross(penedge::geometry::DVec3::Z).normalize();
        let t = strike.dot(face_centre(a, fa as usize)) / period + scatter(joint as u64);
        if t - t.floor() >= o.persistence {
            let (x, y) = (find(&mut root, c.pair[0]), find(&mut root, c.pair[1]));
            root[x.max(y) as usize] = x.min(y);
        }
    }
    (0..n as u32).map(|k| find(&mut root, k)).collect()
}

/// `tunnel`: prints the table.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    pool(o.threads)?.install(|| table(&o))
}

fn table(o: &Options) -> Result<(), String> {
    let tol = Tolerance::default();
    let spec = penedge::io::spec::parse_toml(&spec_text(o)).map_err(|e| e.to_string())?;
    let (generation, generated) = timed(1, || generate(&spec));
    let generated = generated.map_err(|e| e.to_string())?.system;
    let n = generated.len();
    let tunnel_concave = generated
        .body_parts()
        .iter()
        .filter(|(_, p)| p.len() > 1)
        .count();
    let parts = generated
        .clone()
        .with_bodies((0..n as u32).collect(), &tol)
        .map_err(|e| e.to_string())?;
    let ids = bridged_bodies(&generated, &tol, 2, o);
    let (setup, bodies) = timed(1, || parts.clone().with_bodies(ids.clone(), &tol));
    let bodies = bodies.map_err(|e| e.to_string())?;
    let groups = bodies.body_parts();
    let multi: Vec<&Vec<u32>> = groups
        .iter()
        .filter(|(_, p)| p.len() > 1)
        .map(|(_, p)| p)
        .collect();
    if o.profile {
        for _ in 0..o.runs {
            std::hint::black_box(bodies.detect_bodies(&tol));
        }
        return Ok(());
    }
    let in_multi: usize = multi.iter().map(|p| p.len()).sum();
    let (shapes_s, shapes) = timed(1, || bodies.body_shapes(&tol));
    let shapes = shapes.map_err(|e| e.to_string())?;
    let count = |f: &dyn Fn(&BodyShape) -> bool| {
        let kind = shapes.iter().filter(|s| f(s));
        (
            kind.clone().count(),
            kind.map(|s| s.parts as usize).sum::<usize>(),
        )
    };
    let kinds = [
        ("non-convex by volume", count(&|s| s.non_convex)),
        ("cracked", count(&|s| s.cracked())),
        ("non-convex or cracked (concave)", count(&|s| s.concave())),
        (
            "non-convex and cracked",
            count(&|s| s.non_convex && s.cracked()),
        ),
    ];
    println!("## Concave blocks around a tunnel, with rock bridges\n");
    println!(
        "{} threads; {}. Load average at the start: {}.\n",
        o.threads,
        crate::report::machine(),
        crate::report::load()
    );
    println!(
        "Model: 100 m cube, joint sets J1 30/045, J2 70/160, J3 80/280 at {} m spacing, J3 of \
         persistence {} (bridges glue its blocks); circular tunnel of radius {} m (32 \
         segments) along y through the centre. Generated in {generation:.2} s.\n",
        o.spacing, o.persistence, o.radius
    );
    println!(
        "{n} convex parts; {} bodies, {} of them of several parts ({:.1} % of the bodies, \
         {in_multi} parts: {:.1} % of the parts); {tunnel_concave} made by the tunnel; {} \
         internal faces.\n",
        groups.len(),
        multi.len(),
        100.0 * multi.len() as f64 / groups.len() as f64,
        100.0 * in_multi as f64 / n as f64,
        bodies.internal_faces().len()
    );
    println!(
        "Concavity (`BlockSystem::body_shapes`, {shapes_s:.2} s):\n\n| bodies | count | % of \
         the bodies | their parts | % of the parts |\n|---|---:|---:|---:|---:|"
    );
    for (name, (bodies_of_kind, parts_of_kind)) in kinds {
        println!(
            "| {name} | {bodies_of_kind} | {:.1} | {parts_of_kind} | {:.1} |",
            100.0 * bodies_of_kind as f64 / groups.len() as f64,
            100.0 * parts_of_kind as f64 / n as f64
        );
    }
    println!();
    // Interleaved rounds (each round times the four in turn), so that a change of the load
    // of a shared machine weighs on all of them alike; medians over the rounds, of the wall
    // time and of the process's CPU time (all threads: under load, the wall time also counts
    // the time the threads wait for a core).
    let mut wall: [Vec<f64>; 4] = Default::default();
    let mut cpu: [Vec<f64>; 4] = Default::default();
    let mut measure = |k: usize, f: &mut dyn FnMut()| {
        let at = crate::mechanics::process_cpu_s();
        wall[k].push(timed(1, f).0);
        cpu[k].push(crate::mechanics::process_cpu_s() - at);
    };
    let (mut found, mut separate) = (None, None);
    for _ in 0..o.runs {
        measure(0, &mut || found = Some(bodies.detect_bodies(&tol)));
        measure(1, &mut || separate = Some(parts.detect_bodies(&tol)));
        measure(2, &mut || drop(parts.detect_with_geometry(&tol)));
        measure(3, &mut || drop(parts.detect(&tol)));
    }
    let median = |s: [Vec<f64>; 4]| s.map(|mut v| crate::timing::median(&mut v));
    let (wall, cpu) = (median(wall), median(cpu));
    let (found, separate) = (found.expect("runs > 0"), separate.expect("runs > 0"));
    let several = found.contacts.iter().filter(|c| c.region > 0).count();
    println!(
        "Regions: {} with the bodies ({several} of them a second or later region of a pair; \
         {} pairs of bodies penetrating), {} with the parts as separate blocks.\n",
        found.contacts.len(),
        found.penetrating.len(),
        separate.contacts.len()
    );
    println!("| what | wall s | ratio | CPU s (all threads) | ratio |\n|---|---:|---:|---:|---:|");
    let names = [
        "`detect_bodies`, the bodies",
        "`detect_bodies`, the parts as separate blocks",
        "`detect_with_geometry`, the parts",
        "`detect`, the parts",
    ];
    for (k, name) in names.iter().enumerate() {
        println!(
            "| {name} | {:.3} | {:.2} | {:.3} | {:.2} |",
            wall[k],
            wall[k] / wall[1],
            cpu[k],
            cpu[k] / cpu[1]
        );
    }
    println!(
        "| `with_bodies` (once) | {setup:.3} | {:.2} | | |\n",
        setup / wall[1]
    );
    println!(
        "Medians of {} interleaved rounds (each round times the four detections in turn).\n",
        o.runs
    );
    println!("Load average at the end: {}.", crate::report::load());
    Ok(())
}
