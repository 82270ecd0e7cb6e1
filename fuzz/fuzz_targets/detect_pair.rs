//! Fuzz target `detect_pair`: the body is [`penedge::fuzzing::detect_pair`], shared with the regression
//! tests (`crates/penedge/tests/fuzz_regressions.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| penedge::fuzzing::detect_pair(data));
