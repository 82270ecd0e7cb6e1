//! The exact dev cases (`tests/data/dev-cases.json`, or `$PENEDGE_SHARED/cases/`), read as
//! JSON, and their blocks, optionally with every vertex moved.

use penedge::geometry::DVec3;
use penedge::ConvexBlock;
use serde_json::Value;
use std::path::PathBuf;

fn path() -> PathBuf {
    if let Ok(dir) = std::env::var("PENEDGE_SHARED") {
        return PathBuf::from(dir).join("cases/dev-cases.json");
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/dev-cases.json")
}

/// Every case, as JSON.
pub fn cases() -> Vec<Value> {
    let path = path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn numbers<T>(v: &Value, each: impl Fn(&Value) -> T) -> Vec<T> {
    v.as_array().unwrap().iter().map(each).collect()
}

/// The vertices of a case's block (`case["a"]` or `case["b"]`).
pub fn vertices(v: &Value) -> Vec<DVec3> {
    numbers(&v["vertices"], |p| {
        let c = numbers(p, |x| x.as_f64().unwrap());
        DVec3::new(c[0], c[1], c[2])
    })
}

/// The block with every vertex mapped by `f`.
pub fn block_moved(v: &Value, f: impl Fn(DVec3) -> DVec3) -> ConvexBlock {
    let faces = numbers(&v["faces"], |f| {
        numbers(f, |i| i.as_u64().unwrap() as usize)
    });
    let moved: Vec<[f64; 3]> = vertices(v).into_iter().map(|p| f(p).to_array()).collect();
    ConvexBlock::new(&moved, &faces).unwrap_or_else(|e| panic!("bad block: {e}"))
}

/// The block as given.
pub fn block(v: &Value) -> ConvexBlock {
    block_moved(v, |p| p)
}
