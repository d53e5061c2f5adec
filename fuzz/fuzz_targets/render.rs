//! Fuzz target `render`: arbitrary bytes as a RON scene file, rendered end to end at a tiny
//! size with small sample counts; the film must be finite without a dropped sample.
//! The body lives in `tests/fuzz_entries/mod.rs`, which `tests/fuzz_regressions.rs` runs on
//! every input a target ever crashed on.
#![no_main]

#[path = "../../tests/fuzz_entries/mod.rs"]
#[allow(dead_code)] // each target uses one entry
mod fuzz_entries;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _accepted_or_refused = fuzz_entries::render(data);
});
