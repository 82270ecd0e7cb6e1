//! The `tunnel` subcommand: detection around a tunnel with concave blocks and rock bridges
//! (issue 20, "Speed").
//!
//! `cargo run --release -p penedge-bench -- tunnel [--runs R] [--threads T] [--spacing S]
//! [--persistence P] [--radius M] [--segments N] [--profile]`
//!
//! The model: the 100 m cube of `examples/three_joint_sets.toml` (sets J1 30/045 and J2
//! 70/160 at spacing `S`, default 2.13 m) with a circular tunnel (radius `M`, default 8 m,
//! `N` segments, default 64: sides of 0.79 m, shorter than the spacing) driven North through
//! its middle, as `examples/tunnel_circular.toml` does: the blocks the tunnel's wall crosses
//! become concave blocks of convex parts. The third set (J3, 80/280 at `S`) is a **finite
//! set of persistence `P`** (default 0.7), made of polygonal joints with rock bridges
//! (`bridge = true`): on each J3 plane, strips along the dip, `P L` wide along the strike
//! with `(1 - P) L` of rock bridge between two (`L` = 4 spacings), shifted along the strike
//! by a pseudo-random fraction of `L` per plane, so that joints cover `P` of each plane.
//! Generation cuts the blocks a strip ends inside through and glues the pieces the bridge
//! holds into one body: a block with a crack.
//!
//! Times (wall clock and process CPU time, medians of `R` rounds, `T` threads, default 2),
//! in the same run:
//! 1. `detect_bodies` on the system with its bodies;
//! 2. `detect_bodies` on the same convex parts, each its own block (the reference of the
//!    issue's 1.5x bound);
//! 3. `detect_with_geometry` and `detect` on the parts, for reference;
//! 4. `with_bodies` (gluing the parts into the generated bodies again), once.
//!
//! `--profile` runs only the first, `R` times, after the set-up (for `perf record`).
//!
//! Rounds are interleaved (each times the four in turn) so that a change of load on a shared
//! machine weighs on all of them alike.

use crate::system::{pool, timed};
use penedge::block::FaceOrigin;
use penedge::generation::{generate_with, Attitude, Limits, SetKind};
use penedge::geometry::DVec3;
use penedge::system::BodyShape;
use penedge::Tolerance;

struct Options {
    runs: usize,
    threads: usize,
    spacing: f64,
    persistence: f64,
    radius: f64,
    /// Sides of the tunnel's polygon.
    segments: usize,
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
        segments: 64,
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
            "--segments" => o.segments = crate::number(value()?)?,
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

/// The generation spec: joint sets J1 and J2, the strips of J3 (finite polygons with rock
/// bridges, [`j3_strips`]) and the tunnel.
fn spec_text(o: &Options) -> String {
    let set = |name: &str, dip: f64, direction: f64| {
        format!(
            "[[joints]]\ntype = \"set\"\nname = \"{name}\"\ndip = {dip}\ndip_direction = \
             {direction}\nspacing = {}\norigin = [0.3, 0.7, 0.11]\n\n",
            o.spacing
        )
    };
    let mut text = format!(
        "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [100, 100, 100]\n\n{}{}",
        set("J1", 30.0, 45.0),
        set("J2", 70.0, 160.0),
    );
    for (k, strip) in j3_strips(o).iter().enumerate() {
        let v: Vec<String> = strip
            .iter()
            .map(|p| format!("[{}, {}, {}]", p.x, p.y, p.z))
            .collect();
        text += &format!(
            "[[joints]]\ntype = \"polygon\"\nname = \"J3 strip {k}\"\nbridge = true\n\
             vertices = [{}]\n\n",
            v.join(", ")
        );
    }
    text + &format!(
        "[[excavations]]\ntype = \"tunnel\"\nname = \"drive\"\nprofile = \"circle\"\n\
         radius = {}\nsegments = {}\nstart = [50, -1, 50]\ntrend = 0\nplunge = 0\n\
         length = 102\n",
        o.radius, o.segments
    )
}

/// The joints of J3 (80/280, spacing `S`), a finite set of persistence `P`: on each of its
/// planes that crosses the 100 m cube (offsets `n · (0.3, 0.7, 0.11) + k S`), strips across
/// the cube along the dip, each `P L` wide along the strike with `(1 - P) L` of rock bridge
/// between two (`L` = 4 spacings), the pattern shifted along the strike by a pseudo-random
/// fraction of `L` per plane. On each plane the joints cover `P` of the plane (exactly, over
/// whole periods). Strips that meet the plane's section of the cube over less than 1 cm are
/// left out. Each strip: the rectangle's four corners, reaching 1 m beyond the section.
fn j3_strips(o: &Options) -> Vec<[DVec3; 4]> {
    let normal = Attitude::new(80.0, 280.0).normal();
    let strike = normal.cross(DVec3::Z).normalize();
    let down = normal.cross(strike);
    let period = 4.0 * o.spacing;
    let corners: Vec<DVec3> = (0..8)
        .map(|k| DVec3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64) * 100.0)
        .collect();
    let (lo, hi) = range(corners.iter().map(|c| normal.dot(*c)));
    let base = normal.dot(DVec3::new(0.3, 0.7, 0.11));
    let first = ((lo - base) / o.spacing).ceil() as i64;
    let mut strips = Vec::new();
    for k in first.. {
        let offset = base + k as f64 * o.spacing;
        if offset >= hi {
            break;
        }
        // The section of the cube: where its edges cross the plane.
        let mut section = Vec::new();
        for (i, a) in corners.iter().enumerate() {
            for b in &corners[i + 1..] {
                let (da, db) = (normal.dot(*a) - offset, normal.dot(*b) - offset);
                if (*a - *b).length() == 100.0 && da * db < 0.0 {
                    section.push(*a + (*b - *a) * (da / (da - db)));
                }
            }
        }
        if section.len() < 3 {
            continue;
        }
        let (t0, t1) = range(section.iter().map(|p| strike.dot(*p)));
        let (u0, u1) = range(section.iter().map(|p| down.dot(*p)));
        let shift = scatter(k as u64) * period;
        let m0 = ((t0 + shift) / period).floor() as i64 - 1;
        for m in m0.. {
            let (a, b) = (
                m as f64 * period - shift,
                (m as f64 + o.persistence) * period - shift,
            );
            if a >= t1 {
                break;
            }
            if b.min(t1) - a.max(t0) < 0.01 {
                continue;
            }
            let (a, b) = (a.max(t0 - 1.0), b.min(t1 + 1.0));
            let at = |t: f64, u: f64| normal * offset + strike * t + down * u;
            strips.push([
                at(a, u0 - 1.0),
                at(b, u0 - 1.0),
                at(b, u1 + 1.0),
                at(a, u1 + 1.0),
            ]);
        }
    }
    strips
}

/// The least and greatest of some numbers.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// A number in [0, 1) from an integer (SplitMix64's finaliser).
fn scatter(k: u64) -> f64 {
    let mut z = k.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// `tunnel`: prints the table.
pub fn run(args: &[String]) -> Result<(), String> {
    let o = parse(args)?;
    pool(o.threads)?.install(|| table(&o))
}

fn table(o: &Options) -> Result<(), String> {
    let tol = Tolerance::default();
    let strips = j3_strips(o).len();
    let spec = penedge::io::spec::parse_toml(&spec_text(o)).map_err(|e| e.to_string())?;
    // The estimate counts each strip as most of a plane (its extent is the cube's) and
    // would refuse the spec; the bench knows it makes about 10^5 blocks.
    let limits = Limits::blocks(5_000_000);
    let (generation, generated) = timed(1, || {
        generate_with(&spec, &limits, &mut |_| std::ops::ControlFlow::Continue(()))
    });
    let generated = generated.map_err(|e| e.to_string())?;
    let bridged_cuts = generated.report.bridged_cuts;
    let bodies = generated.system;
    let n = bodies.len();
    let ids = bodies.body_ids();
    let parts = bodies
        .clone()
        .with_bodies((0..n as u32).collect(), &tol)
        .map_err(|e| e.to_string())?;
    // Gluing the parts into the generated bodies again, timed for the table (generation
    // does it once, after the cuts).
    let (setup, glued) = timed(1, || parts.clone().with_bodies(ids.clone(), &tol));
    drop(glued.map_err(|e| e.to_string())?);
    let excavated = |k: &u32| {
        let block = &bodies.blocks()[*k as usize];
        block.face_origins().iter().any(|o| match o {
            FaceOrigin::Joint { set, .. } => {
                bodies.sets()[*set as usize].kind == SetKind::Excavation
            }
            _ => false,
        })
    };
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
    let tunnel_concave = multi.iter().filter(|p| p.iter().any(excavated)).count();
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
        "Model: 100 m cube, joint sets J1 30/045 and J2 70/160 at {} m spacing; J3 80/280 at \
         the same spacing, a finite set of persistence {}: {} polygonal strips along the dip \
         with rock bridges between them (`bridge = true`: {bridged_cuts} blocks cut through); \
         circular tunnel of radius {} m ({} segments) along y through the centre. Generated \
         in {generation:.2} s.\n",
        o.spacing, o.persistence, strips, o.radius, o.segments
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
