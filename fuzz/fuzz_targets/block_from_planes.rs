//! Fuzz target `block_from_planes`: the body is [`penedge::fuzzing::block_from_planes`], shared with the regression
//! tests (`crates/penedge/tests/fuzz_regressions.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| penedge::fuzzing::block_from_planes(data));
