//! Every input that made a fuzz target fail (`fuzz/`, docs/fuzzing.md), kept and run through
//! the target's own body ([`penedge::fuzzing`]): `tests/fuzz_regressions/<target>/<name>`.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// A target's body: decode the bytes, run, panic on a broken guarantee.
type Body = fn(&[u8]);

const TARGETS: [(&str, Body); 7] = [
    ("block_from_mesh", penedge::fuzzing::block_from_mesh),
    ("block_from_planes", penedge::fuzzing::block_from_planes),
    ("detect_pair", penedge::fuzzing::detect_pair),
    ("cut_block", penedge::fuzzing::cut_block),
    ("read_json", penedge::fuzzing::read_json),
    ("read_spec", penedge::fuzzing::read_spec),
    ("read_surface", penedge::fuzzing::read_surface),
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions")
}

fn inputs(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries.map(|e| e.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    };
    files.retain(|p| p.is_file());
    files.sort();
    files
}

/// Runs every input of `dir` through the targets; returns the failures (file: message).
fn run(dir: &Path) -> (usize, Vec<String>) {
    let (mut count, mut failures) = (0, Vec::new());
    for (target, body) in TARGETS {
        for path in inputs(&dir.join(target)) {
            count += 1;
            let data = std::fs::read(&path).unwrap();
            if let Err(e) = catch_unwind(AssertUnwindSafe(|| body(&data))) {
                let message = e
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                failures.push(format!("{}: {message}", path.display()));
            }
        }
    }
    (count, failures)
}

#[test]
fn every_saved_crash_input_passes() {
    let (count, failures) = run(&root());
    assert!(
        count > 0,
        "no regression inputs found under {}",
        root().display()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_targets_take_trivial_inputs() {
    for (_, body) in TARGETS {
        body(&[]);
        body(&[0xff; 64]);
    }
}
