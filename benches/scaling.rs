//! Question: how do build time and time per ray grow with the triangle count, what does the
//! two-level grid buy over brute force on a real mesh, and which mesh-grid density λ is best?
//!
//! Meshes: closed icospheres of 1,280, 20,480, 81,920 and 1,310,720 triangles, and the full
//! bunny (69,451) and dragon (871,414) from `../shared/models/` (skipped when absent), each in
//! ANCHORS.md's mesh scene (fitted to extent 2.4 on a ground plane, one point light). Rays: one
//! camera ray per pixel at 640×480 plus one shadow ray per hit, both cores.
//!
//! Groups: `scaling_trace/mesh/N` (primary + shadow rays), `scaling_build/mesh/N` (the mesh's
//! own grid). Tables: per N the build ms and ns per ray with the growth exponent between
//! neighbouring sizes (`log(t2/t1) / log(N2/N1)`: 0 = constant, 1 = linear); the bunny's grid
//! against brute force over every triangle (on every 61st pixel); and the λ curve
//! (`mesh_lambda`: build + trace for λ in 0.5…16, the trace both as single rays and as the
//! renderer's packets, and the grid's bytes per triangle) that `MESH_LAMBDA` is chosen on.
//!
//! Run: `cargo bench --bench scaling`.

#[path = "../tests/common/mod.rs"]
mod common;
mod harness;

use std::hint::black_box;
use std::sync::Arc;

use criterion::{BenchmarkId, Criterion, Throughput};
use harness::rays::{
    median, ray_set, trace_primary, trace_primary_packets, trace_shadow, trace_shadow_packets, RaySet,
};
use penumbra::accel::{DEFAULT_LAMBDA, MESH_LAMBDA};
use penumbra::geom::mesh::{icosphere, MeshData};
use penumbra::math::Vec3;
use penumbra::simd::SimdLevel;
use penumbra::store::{MeshAsset, PrimitiveStore};
use penumbra::testing::closest_hit_brute;
use penumbra::trace::{closest_hit, TraceScene};

const W: u32 = 640;
const H: u32 = 480;
const LAMBDAS: &[f32] = &[0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// The meshes, smallest first: name, data.
fn meshes() -> Vec<(String, MeshData)> {
    let mut out: Vec<(String, MeshData)> =
        [3, 5, 6, 8].iter().map(|&s| (format!("icosphere_{s}"), icosphere(Vec3::ZERO, 1.0, s))).collect();
    for file in ["bunny.obj", "dragon.obj"] {
        match common::shared_model(file) {
            Some(path) => out.push((
                file.trim_end_matches(".obj").to_owned(),
                penumbra::scene::obj::load_obj(&path, true).expect("model loads"),
            )),
            None => eprintln!("scaling: ../shared/models/{file} not found; skipping it"),
        }
    }
    out.sort_by_key(|(_, m)| m.triangle_count());
    out
}

struct Case {
    name: String,
    n: usize,
    data: MeshData,
    scene: TraceScene,
    rays: RaySet,
}

fn cases() -> Vec<Case> {
    meshes()
        .into_iter()
        .map(|(name, data)| {
            let asset = Arc::new(MeshAsset::new(name.clone(), data.clone(), MESH_LAMBDA));
            let scene: TraceScene = common::mesh_scene(asset, DEFAULT_LAMBDA);
            let rays = ray_set(&scene, W, H, common::MESH_LIGHT);
            Case { n: data.triangle_count(), name, data, scene, rays }
        })
        .collect()
}

fn trace(case: &Case, scene: &TraceScene) -> usize {
    trace_primary(scene, &case.rays.primary) + trace_shadow(scene, &case.rays.shadow)
}

/// [`trace`]'s rays as the renderer traces a pinhole frame: camera rays in packets of 4 × 4
/// pixels, each block's shadow rays as one packet, at the best SIMD level.
fn trace_packets(case: &Case, scene: &TraceScene) -> usize {
    let level = SimdLevel::Auto.resolve();
    trace_primary_packets(scene, &case.rays.primary, W, level)
        + trace_shadow_packets(scene, &case.rays.shadow, &case.rays.shadow_block, level)
}

fn groups(c: &mut Criterion, cases: &[Case]) {
    let mut group = c.benchmark_group("scaling_trace");
    for case in cases {
        group.throughput(Throughput::Elements((case.rays.primary.len() + case.rays.shadow.len()) as u64));
        group.bench_function(BenchmarkId::new(&case.name, case.n), |b| b.iter(|| trace(case, &case.scene)));
    }
    group.finish();
    let mut group = c.benchmark_group("scaling_build");
    group.sample_size(10);
    for case in cases {
        group.throughput(Throughput::Elements(case.n as u64));
        group.bench_function(BenchmarkId::new(&case.name, case.n), |b| {
            b.iter(|| MeshAsset::new("bench", black_box(case.data.clone()), MESH_LAMBDA))
        });
    }
    group.finish();
}

fn tables(cases: &[Case]) {
    println!(
        "\nscaling: {W}x{H} primary + shadow rays on both cores; build = the mesh's own grid (medians of 5)"
    );
    println!(
        "{:<13} {:>10} {:>10} {:>8} {:>10} {:>8} {:>10} {:>10}",
        "mesh", "triangles", "build ms", "growth", "ns/ray", "growth", "B/tri grid", "Mrays/s"
    );
    let mut prev: Option<(usize, f64, f64)> = None;
    for case in cases {
        let build = median(5, || MeshAsset::new("bench", case.data.clone(), MESH_LAMBDA)).as_secs_f64();
        let rays = case.rays.primary.len() + case.rays.shadow.len();
        let t = median(5, || trace(case, &case.scene)).as_secs_f64();
        let ns = t * 1e9 / rays as f64;
        let growth = |a: f64, b: f64, n0: usize| (b / a).ln() / (case.n as f64 / n0 as f64).ln();
        let (gb, gt) = prev.map_or((String::from("-"), String::from("-")), |(n0, b0, t0)| {
            (format!("{:.2}", growth(b0, build, n0)), format!("{:.2}", growth(t0, ns, n0)))
        });
        let grid = &case.scene.store.meshes()[0].asset.grid;
        println!(
            "{:<13} {:>10} {:>10.1} {:>8} {:>10.1} {:>8} {:>10.1} {:>10.2}",
            case.name,
            case.n,
            build * 1e3,
            gb,
            ns,
            gt,
            grid.memory_bytes() as f64 / case.n as f64,
            rays as f64 / t / 1e6
        );
        prev = Some((case.n, build, ns));
    }

    if let Some(bunny) = cases.iter().find(|c| c.name == "bunny") {
        // Brute force tests all 69k triangles per ray: trace a fixed subset of the pixels.
        let subset: Vec<_> = bunny.rays.primary.iter().step_by(61).copied().collect();
        let time = |f: &dyn Fn(&penumbra::math::Ray) -> bool| {
            median(3, || subset.iter().filter(|r| f(r)).count()).as_secs_f64() / subset.len() as f64
        };
        let grid = time(&|r| closest_hit(&bunny.scene, r, 0.0, f32::INFINITY).is_some());
        let brute = time(&|r| closest_hit_brute(&bunny.scene, r, 0.0, f32::INFINITY).is_some());
        println!(
            "\nbunny, {} camera rays on one thread: grid {:.0} ns/ray, brute force {:.0} ns/ray: grid is {:.0}x faster",
            subset.len(),
            grid * 1e9,
            brute * 1e9,
            brute / grid
        );
    }

    println!(
        "\nmesh_lambda: build + trace (ms) per mesh-grid density λ, medians of 3; trace as single rays \
         (the secondary rays' path) and as packets (a pinhole frame's camera and point-light shadow \
         rays), and the grid's bytes per triangle"
    );
    print!("{:<13} {:<7}", "mesh", "trace");
    for l in LAMBDAS {
        print!(" {:>13}", format!("λ={l}"));
    }
    println!();
    for case in cases.iter().filter(|c| c.n >= 20_000) {
        let mut rows = [String::new(), String::new(), String::new()];
        for &lambda in LAMBDAS {
            let asset = Arc::new(MeshAsset::new("bench", case.data.clone(), lambda));
            let (build, bytes) = (asset.build_seconds, asset.grid.memory_bytes() as f64 / case.n as f64);
            let scene: TraceScene = common::mesh_scene(asset, DEFAULT_LAMBDA);
            // Interleaved, so drift on a shared machine hits both paths alike.
            let (mut single, mut packets) = (Vec::new(), Vec::new());
            for _ in 0..3 {
                single.push(median(1, || trace(case, &scene)).as_secs_f64());
                packets.push(median(1, || trace_packets(case, &scene)).as_secs_f64());
            }
            let mid = |mut v: Vec<f64>| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            };
            rows[0] += &format!(" {:>13}", format!("{:.0}+{:.0}", build * 1e3, mid(single) * 1e3));
            rows[1] += &format!(" {:>13}", format!("{:.0}+{:.0}", build * 1e3, mid(packets) * 1e3));
            rows[2] += &format!(" {:>13.1}", bytes);
        }
        for (what, row) in ["single", "packets", "B/tri"].iter().zip(rows) {
            println!("{:<13} {:<7}{row}", case.name, what);
        }
    }
}

fn main() {
    let cases = cases();
    harness::run(10, |c| groups(c, &cases), || tables(&cases));
}
