//! Fuzz target `scene`: arbitrary bytes as a RON scene file: loader, validator, spawn and one World
//! update.
//! The body lives in `tests/fuzz_entries/mod.rs`, which `tests/fuzz_regressions.rs` runs on
//! every input a target ever crashed on.
#![no_main]

#[path = "../../tests/fuzz_entries/mod.rs"]
#[allow(dead_code)] // each target uses one entry
mod fuzz_entries;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _accepted_or_refused = fuzz_entries::scene(data);
});
