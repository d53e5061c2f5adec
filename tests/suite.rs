//! The integration tests, one binary: each file beside this one is a module of it. One binary
//! links the library once instead of once per file, which is most of `cargo test`'s build time
//! (Cargo.toml sets `autotests = false`; a new test file is added to the list below).
//!
//! Run one file's tests with `cargo test --release --test suite FILE::`, for example
//! `cargo test --release --test suite hard_rays::`.

mod common;
mod fuzz_entries;

mod analytic;
mod aov;
mod batch;
mod camera_relative;
mod cli;
mod combined_validation;
mod deploy;
mod determinism;
mod docs;
mod effects;
mod errors;
mod finite_film;
mod fuzz_regressions;
mod grid;
mod hard_rays;
mod invariants;
mod lanes;
mod materials;
mod memory;
mod mesh;
mod motion;
mod noise;
mod output;
mod packets;
mod properties;
mod provenance;
mod ray_budget;
mod report;
mod scene_validation;
mod script;
mod script_cli;
mod script_textures;
mod simd_cli;
mod world;
