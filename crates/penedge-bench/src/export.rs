//! Writes the pairs of the geometry benchmark to a JSON file, for engines timed in another
//! process (`benches/python/coal_patch.py`).
//!
//! Format (`"format": "penedge-bench pairs 1"`):
//!
//! ```text
//! { "format", "seed", "hot": first pairs of the hot window, "penetration",
//!   "sets": [ { "situation", "family", "relative_gap",
//!     "pairs": [ { "expected": contact type name,
//!                  "gap": penedge's absolute gap (parry's prediction),
//!                  "a": { "vertices": [[x, y, z], ...] (body frame), "faces": [[i, ...], ...]
//!                         (counter-clockwise seen from outside), "rotation": [x, y, z, w]
//!                         (unit quaternion), "translation": [x, y, z] },
//!                  "b": { ... },
//!                  "penedge": { "type", "normal", "distance", "area", "points": count } } ] } ] }
//! ```
//!
//! A point `p` of a block's body frame is at `rotation * p + translation` in the world, the
//! same poses as parry's. Numbers are written with Rust's shortest round-trip formatting, so
//! they read back bit for bit.

use crate::geometry::{expected_name, result_name};
use crate::pairs::PairSet;
use crate::placement::PENETRATION;
use crate::Options;
use parry3d_f64::math::Pose;
use penedge::{ConvexBlock, Detector};
use std::fmt::Write as _;
use std::io::Write as _;

/// Writes every pair of `sets` (made with their reference blocks kept) to `path`.
pub fn write_pairs(path: &str, sets: &[PairSet], o: &Options) -> std::io::Result<()> {
    let mut s = String::new();
    write!(
        s,
        "{{\"format\":\"penedge-bench pairs 1\",\"seed\":{},\"hot\":{},\"penetration\":{:?},\"sets\":[",
        o.seed, o.hot, PENETRATION
    )
    .expect("writing to a String");
    for (k, set) in sets.iter().enumerate() {
        assert_eq!(set.refs.len(), set.len(), "reference blocks were not kept");
        if k > 0 {
            s.push(',');
        }
        write_set(&mut s, set);
    }
    s.push_str("]}\n");
    let mut file = std::io::BufWriter::new(std::fs::File::create(path)?);
    file.write_all(s.as_bytes())?;
    file.flush()
}

fn write_set(s: &mut String, set: &PairSet) {
    let mut detector = Detector::new(set.tolerance);
    write!(
        s,
        "{{\"situation\":\"{}\",\"family\":\"{}\",\"relative_gap\":{:?},\"pairs\":[",
        set.scenario.name,
        set.family.name(),
        set.tolerance.gap()
    )
    .expect("writing to a String");
    for i in 0..set.len() {
        if i > 0 {
            s.push(',');
        }
        let (a, b) = &set.blocks[i];
        let (ref_a, ref_b) = &set.refs[i];
        let p = &set.parry[i];
        write!(
            s,
            "\n{{\"expected\":\"{}\",\"gap\":{:?},\"a\":",
            expected_name(set.expected[i]),
            p.prediction
        )
        .expect("writing to a String");
        write_block(s, ref_a, &p.pose_a);
        s.push_str(",\"b\":");
        write_block(s, ref_b, &p.pose_b);
        let (result, geometry) = detector.detect_with_geometry(a, b);
        write!(s, ",\"penedge\":{{\"type\":\"{}\"", result_name(&result))
            .expect("writing to a String");
        if let Some(g) = geometry {
            let n = g.normal();
            write!(
                s,
                ",\"normal\":[{:?},{:?},{:?}],\"distance\":{:?},\"area\":{:?},\"points\":{}",
                n.x,
                n.y,
                n.z,
                g.distance(),
                g.area(),
                g.points().len()
            )
            .expect("writing to a String");
        }
        s.push_str("}}");
    }
    s.push_str("]}");
}

fn write_block(s: &mut String, block: &ConvexBlock, pose: &Pose) {
    s.push_str("{\"vertices\":[");
    for (k, v) in block.vertices().iter().enumerate() {
        let sep = if k > 0 { "," } else { "" };
        write!(s, "{sep}[{:?},{:?},{:?}]", v.x, v.y, v.z).expect("writing to a String");
    }
    s.push_str("],\"faces\":[");
    for (k, face) in block.faces().enumerate() {
        let sep = if k > 0 { "," } else { "" };
        write!(s, "{sep}{face:?}").expect("writing to a String");
    }
    let (r, t) = (pose.rotation, pose.translation);
    write!(
        s,
        "],\"rotation\":[{:?},{:?},{:?},{:?}],\"translation\":[{:?},{:?},{:?}]}}",
        r.x, r.y, r.z, r.w, t.x, t.y, t.z
    )
    .expect("writing to a String");
}
