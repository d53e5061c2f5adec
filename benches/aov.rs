//! Question: what does each AOV cost? The showcase scene (`scenes/showcase.ron`) at 160×120
//! rendered with no AOV, each AOV alone and all of them: time and buffer memory.
//!
//! Run: `cargo bench --bench aov` (criterion groups, then the table);
//! `cargo bench --bench aov -- zzz` prints only the table.

mod harness;

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use penumbra::film::AovSet;
use penumbra::scene;
use penumbra::trace::{render_with_aovs, RenderSettings, TraceScene};
use penumbra::world::SceneWorld;

const SIZE: (u32, u32) = (160, 120);

fn showcase() -> (std::sync::Arc<TraceScene>, RenderSettings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/showcase.ron");
    let mut d = scene::load_scene(&path).expect("scenes/showcase.ron is valid");
    (d.camera.width, d.camera.height) = SIZE;
    let mut world: SceneWorld = scene::spawn_world(&d);
    let snapshot = world.update();
    (snapshot, world.render_settings())
}

fn variants() -> Vec<(&'static str, AovSet)> {
    let one = |f: fn(&mut AovSet)| {
        let mut s = AovSet::default();
        f(&mut s);
        s
    };
    vec![
        ("none", AovSet::default()),
        ("depth", one(|s| s.depth = true)),
        ("normal", one(|s| s.normal = true)),
        ("albedo", one(|s| s.albedo = true)),
        ("object", one(|s| s.object = true)),
        ("cost", one(|s| s.cost = true)),
        ("all", AovSet { depth: true, normal: true, albedo: true, object: true, cost: true }),
    ]
}

fn bench_aov(c: &mut Criterion) {
    let (scene, settings) = showcase();
    let mut group = c.benchmark_group("aov");
    for (name, set) in variants() {
        group.bench_function(BenchmarkId::new(name, SIZE.0 * SIZE.1), |b| {
            b.iter(|| black_box(render_with_aovs(&scene, &settings, set)))
        });
    }
    group.finish();
}

fn print_table() {
    let (scene, settings) = showcase();
    println!(
        "\nAOV cost on the showcase at {}x{}, {} threads (medians of 5)",
        SIZE.0,
        SIZE.1,
        rayon::current_num_threads()
    );
    println!("{:>8} {:>9} {:>9} {:>11} {:>10}", "aov", "ms", "vs none", "aov bytes", "aov rays");
    let mut base = 0.0;
    for (name, set) in variants() {
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..5 {
            let t = Instant::now();
            last = Some(render_with_aovs(&scene, &settings, set).2);
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        times.sort_by(f64::total_cmp);
        let ms = times[2];
        if name == "none" {
            base = ms;
        }
        let stats = last.unwrap_or_default();
        println!("{name:>8} {ms:>9.1} {:>8.3}x {:>11} {:>10}", ms / base, stats.aov_bytes, stats.rays.aov);
    }
}

fn main() {
    harness::run(10, bench_aov, print_table);
}
