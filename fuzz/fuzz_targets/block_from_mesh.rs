//! Fuzz target `block_from_mesh`: the body is [`penedge::fuzzing::block_from_mesh`], shared with the regression
//! tests (`crates/penedge/tests/fuzz_regressions.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| penedge::fuzzing::block_from_mesh(data));
