//! Question: what does each distribution effect cost? The showcase scene (`scenes/showcase.ron`)
//! with every effect off, each effect on alone, and all together: time per frame and rays per
//! pixel by kind. "Off" means: aperture 0, one sample per pixel, glossiness 0, area lights
//! replaced by point lights at their centres with the same power.
//!
//! Run: `cargo bench --bench effects` (criterion groups, then the table);
//! `cargo bench --bench effects -- zzz` prints only the table.

mod harness;

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use penumbra::scene::{self, LightDesc, SceneDesc};
use penumbra::trace::{render, RenderSettings, RenderStats, TraceScene};
use penumbra::world::SceneWorld;

/// Image size of every variant (the showcase's own size is larger).
const SIZE: (u32, u32) = (160, 120);

fn showcase() -> SceneDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/showcase.ron");
    let mut d = scene::load_scene(&path).expect("scenes/showcase.ron is valid");
    (d.camera.width, d.camera.height) = SIZE;
    d.settings.adaptive = None;
    d
}

/// The showcase with every effect switched off.
fn plain(full: &SceneDesc) -> SceneDesc {
    let mut d = full.clone();
    d.camera.aperture = 0.0;
    d.settings.aa.samples = 1;
    d.materials.iter_mut().for_each(|m| m.glossiness = 0.0);
    for light in &mut d.lights {
        let point = match *light {
            LightDesc::Rect { corner, edge_u, edge_v, colour, intensity, .. } => {
                Some((corner + 0.5 * (edge_u + edge_v).as_dvec3(), colour, intensity))
            }
            LightDesc::Disk { centre, colour, intensity, .. } => Some((centre, colour, intensity)),
            _ => None,
        };
        if let Some((position, colour, intensity)) = point {
            *light = LightDesc::Point { position, colour, intensity, falloff: Default::default() };
        }
    }
    d
}

/// (name, scene) for every variant.
fn variants() -> Vec<(&'static str, SceneDesc)> {
    let full = showcase();
    let base = plain(&full);
    let mut aa = base.clone();
    aa.settings.aa = full.settings.aa;
    let mut soft = base.clone();
    soft.lights = full.lights.clone();
    let mut glossy = base.clone();
    glossy.materials = full.materials.clone();
    let mut dof = base.clone();
    dof.camera = full.camera.clone();
    vec![
        ("none", base),
        ("aa", aa),
        ("soft_shadows", soft),
        ("glossy_blurry", glossy),
        ("dof", dof),
        ("all", full),
    ]
}

fn snapshot(d: &SceneDesc) -> (std::sync::Arc<TraceScene>, RenderSettings) {
    let mut world: SceneWorld = scene::spawn_world(d);
    let snapshot = world.update();
    (snapshot, world.render_settings())
}

fn bench_effects(c: &mut Criterion) {
    let mut group = c.benchmark_group("effects");
    for (name, d) in variants() {
        let (scene, settings) = snapshot(&d);
        group.bench_with_input(BenchmarkId::new(name, SIZE.0 * SIZE.1), &(scene, settings), |b, (s, r)| {
            b.iter(|| black_box(render(s, r)))
        });
    }
    group.finish();
}

fn median_render(scene: &TraceScene, settings: &RenderSettings, runs: usize) -> (f64, RenderStats) {
    let mut times = Vec::new();
    let mut stats = RenderStats::default();
    for _ in 0..runs {
        let t = Instant::now();
        stats = render(scene, settings).1;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times[runs / 2], stats)
}

fn print_table() {
    let pixels = f64::from(SIZE.0 * SIZE.1);
    println!(
        "\neffects on the showcase at {}x{}, {} threads (medians of 3)",
        SIZE.0,
        SIZE.1,
        rayon::current_num_threads()
    );
    println!(
        "{:>14} {:>9} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>8}",
        "variant",
        "ms",
        "cam/px",
        "lens/px",
        "shd/px",
        "area/px",
        "refl/px",
        "glos/px",
        "refr/px",
        "blur/px",
        "x none"
    );
    let mut none_ms = 0.0;
    for (name, d) in variants() {
        let (scene, settings) = snapshot(&d);
        let (secs, s) = median_render(&scene, &settings, 3);
        let ms = secs * 1e3;
        if name == "none" {
            none_ms = ms;
        }
        let r = s.rays;
        let per = |v: u64| v as f64 / pixels;
        println!(
            "{name:>14} {ms:>9.1} {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.1}x",
            per(r.camera),
            per(r.lens),
            per(r.shadow),
            per(r.area_shadow),
            per(r.reflection),
            per(r.glossy),
            per(r.refraction),
            per(r.blurry),
            ms / none_ms
        );
    }
}

fn main() {
    harness::run(10, bench_effects, print_table);
}
