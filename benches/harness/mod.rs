//! What every bench's `main` does: run its criterion groups with short, shared settings, then
//! print its table (skipped under `cargo test --benches`, `--list`, or with
//! `PENUMBRA_BENCH_NO_TABLE` set).

pub mod rays;

use std::time::Duration;

use criterion::Criterion;

/// Runs `groups` with `samples` samples each, then `table`.
pub fn run(samples: usize, groups: impl FnOnce(&mut Criterion), table: impl FnOnce()) {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .sample_size(samples)
        .configure_from_args();
    groups(&mut c);
    c.final_summary();
    let quick = std::env::args().any(|a| a == "--test" || a == "--list");
    if !quick && std::env::var_os("PENUMBRA_BENCH_NO_TABLE").is_none() {
        table();
    }
}
