//! Question: what does a texture cost, and does a scene without one pay anything? One scene
//! (a floor, a wall, nine spheres and a box under a point light, 1 sample per pixel) with every
//! material untextured, then with each kind of texture on every material's `kd`, and with a
//! bump map: time per frame, and the ratio to the untextured frame. (Against the code before
//! textures existed, the untextured scenes' trace times are compared by running both builds
//! side by side; see the closing note of issue 21.)
//!
//! Run: `cargo bench --bench textures` (criterion group, then the table of interleaved medians);
//! `cargo bench --bench textures -- zzz` prints only the table.

mod harness;

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use penumbra::scene::{self, SceneDesc};
use penumbra::trace::{render, RenderSettings, TraceScene};
use penumbra::world::SceneWorld;

/// Image size of every variant.
const SIZE: (u32, u32) = (240, 160);

/// The scene with `texture` (a `textures` entry named "t", or none) on every material's `kd`,
/// and `bump` as the bump map.
fn scene_with(texture: Option<&str>, bump: bool) -> SceneDesc {
    let textures = texture.map_or(String::new(), |t| format!("(name: \"t\", kind: {t}, scale: (2, 2))"));
    let kd = match (texture, bump) {
        (Some(_), false) => ", kd_texture: Some(\"t\")",
        (Some(_), true) => ", bump_texture: Some(\"t\"), bump_depth: 0.05",
        (None, _) => "",
    };
    let spheres: String = (0..9)
        .map(|i| {
            format!(
                "(shape: Sphere(centre: ({}, 0.5, {}), radius: 0.45), material: \"ball\"),",
                i % 3 - 1,
                i / 3
            )
        })
        .collect();
    let text = format!(
        "Scene(
        camera: (position: (0, 2.5, -4), look_at: (0, 0.5, 1), fov_deg: 50, width: {}, height: {}),
        settings: (max_depth: 2),
        textures: [{textures}],
        materials: [(name: \"floor\", kd: (0.8, 0.8, 0.8){kd}), (name: \"ball\", kd: (0.7, 0.3, 0.2), ks: 0.4{kd}), (name: \"wall\", kd: (0.5, 0.6, 0.7){kd})],
        lights: [Point(position: (-3, 5, -3))],
        objects: [
            (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"floor\"),
            (shape: Plane(point: (0, 0, 4), normal: (0, 0, -1)), material: \"wall\"),
            (shape: Box(min: (-0.4, 0, -0.4), max: (0.4, 0.8, 0.4)), material: \"wall\", transform: (translate: (2, 0, 0.5), rotate_deg: (0, 30, 0))),
            {spheres}
        ])",
        SIZE.0, SIZE.1
    );
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    scene::parse_scene_at(&text, "textures-bench.ron", &base).expect("bench scene is valid")
}

/// (name, scene) for every variant.
fn variants() -> Vec<(&'static str, SceneDesc)> {
    let image = "Image(file: \"room/tiles.png\")";
    vec![
        ("none", scene_with(None, false)),
        ("checker", scene_with(Some("Checker(a: (1, 1, 1), b: (0.2, 0.2, 0.2))"), false)),
        ("image", scene_with(Some(image), false)),
        ("noise", scene_with(Some("Noise(a: (1, 1, 1), b: (0.2, 0.2, 0.2), octaves: 4)"), false)),
        ("bump_image", scene_with(Some(image), true)),
    ]
}

fn snapshot(d: &SceneDesc) -> (std::sync::Arc<TraceScene>, RenderSettings) {
    let mut world: SceneWorld = scene::spawn_world(d);
    let snapshot = world.update();
    (snapshot, world.render_settings())
}

fn bench_textures(c: &mut Criterion) {
    let mut group = c.benchmark_group("textures");
    for (name, d) in variants() {
        let (scene, settings) = snapshot(&d);
        group.bench_with_input(BenchmarkId::new(name, SIZE.0 * SIZE.1), &(scene, settings), |b, (s, r)| {
            b.iter(|| black_box(render(s, r)))
        });
    }
    group.finish();
}

/// Interleaved: each round renders every variant once, so a noisy moment hits all of them.
fn print_table() {
    const ROUNDS: usize = 9;
    let snapshots: Vec<_> = variants().into_iter().map(|(name, d)| (name, snapshot(&d))).collect();
    let mut times = vec![Vec::new(); snapshots.len()];
    for _ in 0..ROUNDS {
        for (i, (_, (scene, settings))) in snapshots.iter().enumerate() {
            let t = Instant::now();
            black_box(render(scene, settings));
            times[i].push(t.elapsed().as_secs_f64());
        }
    }
    let median = |t: &mut Vec<f64>| {
        t.sort_by(f64::total_cmp);
        t[t.len() / 2]
    };
    let medians: Vec<f64> = times.iter_mut().map(median).collect();
    println!(
        "\ntextures at {}x{}, {} threads (medians of {ROUNDS} interleaved rounds)",
        SIZE.0,
        SIZE.1,
        rayon::current_num_threads()
    );
    println!("{:>12} {:>9} {:>8}", "variant", "ms", "x none");
    for ((name, _), secs) in snapshots.iter().zip(&medians) {
        println!("{name:>12} {:>9.2} {:>7.3}x", secs * 1e3, secs / medians[0]);
    }
}

fn main() {
    harness::run(10, bench_textures, print_table);
}
