//! Fuzz target `cut_block`: the body is [`penedge::fuzzing::cut_block`], shared with the regression
//! tests (`crates/penedge/tests/fuzz_regressions.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| penedge::fuzzing::cut_block(data));
