//! Question: how many camera rays does adaptive supersampling save at equal error?
//!
//! The showcase scene (`scenes/showcase.ron`) at a small size: a 256-spp jittered reference,
//! then fixed anti-aliasing at 1, 4, 16 and 64 spp and adaptive corner subdivision at several
//! (threshold, depth) settings. For each adaptive run the table gives its RMSE against the
//! reference, its camera rays and time, and the camera rays and time fixed AA needs for the
//! same RMSE (interpolated log-log between the fixed runs), with the ratios.
//!
//! Run: `cargo bench --bench adaptive` (criterion timing of one fixed and one adaptive
//! setting, then the table); `cargo bench --bench adaptive -- zzz` prints only the table.

mod harness;

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use penumbra::film::{rmse, Film};
use penumbra::sample::adaptive::AdaptiveSettings;
use penumbra::sample::{Filter, Pattern};
use penumbra::scene;
use penumbra::trace::{render, RenderSettings, RenderStats, TraceScene};
use penumbra::world::SceneWorld;

const SIZE: (u32, u32) = (64, 48);
const REFERENCE_SPP: u32 = 256;
const FIXED_SPP: &[u32] = &[1, 4, 16, 64];
const ADAPTIVE: &[(f32, u32)] = &[(0.2, 2), (0.1, 2), (0.05, 3), (0.02, 3), (0.01, 4)];

fn showcase() -> (std::sync::Arc<TraceScene>, RenderSettings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/showcase.ron");
    let mut d = scene::load_scene(&path).expect("scenes/showcase.ron is valid");
    (d.camera.width, d.camera.height) = SIZE;
    let mut world: SceneWorld = scene::spawn_world(&d);
    let snapshot = world.update();
    let mut settings = world.render_settings();
    settings.adaptive = None;
    // One lens point per camera sample, so "spp" counts camera rays for both methods (lens
    // points are stratified across a pixel's samples; adaptive takes one per lattice point).
    settings.lens.samples = 1;
    // Adaptive refines the pixel's own square: compare against the box filter over that square.
    settings.aa.filter = Filter::Box;
    (snapshot, settings)
}

fn fixed(settings: &RenderSettings, spp: u32) -> RenderSettings {
    let mut s = *settings;
    s.aa.samples = spp;
    s.aa.pattern = Pattern::Jittered;
    s.adaptive = None;
    s
}

fn adaptive(settings: &RenderSettings, threshold: f32, max_depth: u32) -> RenderSettings {
    let mut s = *settings;
    s.adaptive = Some(AdaptiveSettings { threshold, max_depth });
    s
}

fn bench_adaptive(c: &mut Criterion) {
    let (scene, settings) = showcase();
    let mut group = c.benchmark_group("adaptive_vs_fixed");
    group.bench_function(BenchmarkId::new("fixed", 16), |b| {
        b.iter(|| black_box(render(&scene, &fixed(&settings, 16))))
    });
    group.bench_function(BenchmarkId::new("adaptive", "0.05:3"), |b| {
        b.iter(|| black_box(render(&scene, &adaptive(&settings, 0.05, 3))))
    });
    group.finish();
}

fn timed(scene: &TraceScene, settings: &RenderSettings) -> (Film, RenderStats, f64) {
    let t = Instant::now();
    let (film, stats) = render(scene, settings);
    (film, stats, t.elapsed().as_secs_f64())
}

fn print_table() {
    let (scene, settings) = showcase();
    let (reference, ..) = timed(&scene, &fixed(&settings, REFERENCE_SPP));
    println!(
        "\nadaptive vs fixed AA on the showcase at {}x{} (reference: {REFERENCE_SPP} spp jittered)",
        SIZE.0, SIZE.1
    );
    println!("{:>16} {:>10} {:>12} {:>12} {:>9}", "setting", "RMSE", "camera rays", "all rays", "ms");
    let mut curve = Vec::new();
    for &spp in FIXED_SPP {
        let (film, stats, secs) = timed(&scene, &fixed(&settings, spp));
        let e = rmse(&film, &reference).unwrap_or(f64::NAN);
        let primary = stats.rays.primary();
        println!(
            "{:>16} {e:>10.5} {primary:>12} {:>12} {:>9.1}",
            format!("fixed {spp} spp"),
            stats.rays.total(),
            secs * 1e3
        );
        curve.push((e, primary as f64, secs * 1e3));
    }
    println!(
        "{:>16} {:>10} {:>12} {:>12} {:>9} {:>12} {:>8} {:>9} {:>8}",
        "setting", "RMSE", "camera rays", "all rays", "ms", "fixed rays", "saving", "fixed ms", "time"
    );
    for &(t, d) in ADAPTIVE {
        let (film, stats, secs) = timed(&scene, &adaptive(&settings, t, d));
        let e = rmse(&film, &reference).unwrap_or(f64::NAN);
        let primary = stats.rays.primary() as f64;
        let ms = secs * 1e3;
        let (rays, saving, fixed_ms, time) = match fixed_at(&curve, e) {
            Some((r, m)) => (
                format!("{r:.0}"),
                format!("{:.2}x", r / primary),
                format!("{m:.1}"),
                format!("{:.2}x", m / ms),
            ),
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        println!(
            "{:>16} {e:>10.5} {primary:>12} {:>12} {ms:>9.1} {rays:>12} {saving:>8} {fixed_ms:>9} {time:>8}",
            format!("adaptive {t}:{d}"),
            stats.rays.total(),
        );
    }
}

/// Camera rays and milliseconds fixed AA needs for RMSE `e`, interpolating log-log between the
/// two fixed runs that bracket it.
fn fixed_at(curve: &[(f64, f64, f64)], e: f64) -> Option<(f64, f64)> {
    curve.windows(2).find_map(|w| {
        let ((e0, r0, m0), (e1, r1, m1)) = (w[0], w[1]);
        (e <= e0 && e >= e1).then(|| {
            let s = (e.ln() - e0.ln()) / (e1.ln() - e0.ln());
            let lerp = |a: f64, b: f64| (a.ln() + s * (b.ln() - a.ln())).exp();
            (lerp(r0, r1), lerp(m0, m1))
        })
    })
}

fn main() {
    harness::run(10, bench_adaptive, print_table);
}
