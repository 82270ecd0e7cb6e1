//! Fuzz target `read_surface`: the body is [`penedge::fuzzing::read_surface`], shared with the
//! regression tests (`crates/penedge/tests/fuzz_regressions.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| penedge::fuzzing::read_surface(data));
