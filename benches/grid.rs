//! Question: how much does the uniform grid buy over testing every object, how does time per
//! ray grow with N, and which density λ minimises build + trace time?
//!
//! Group `grid_vs_brute`: seeded random sphere clouds at each N of [`SIZES`], a camera looking
//! into the cloud, 256×256 primary rays plus one shadow ray per hit towards a point light,
//! traced on one thread. Brute force at large N would take seconds per iteration, so it traces
//! a fixed deterministic subset of the pixels (every [`brute_stride`]-th pixel in scan order)
//! and both variants report `Throughput::Elements(rays actually traced)`: criterion's
//! elements/s are then comparable per ray. After the groups, a table of medians (N, grid ns/ray,
//! brute ns/ray, speed-up, grid build ms) and the λ curve are printed from a quick repeated
//! timing of the same functions.
//!
//! Group `grid_lambda`: 10,000 spheres and 10,000 random triangles, λ over [`LAMBDAS`]: grid
//! build plus the full 256×256 trace, the cost `DEFAULT_LAMBDA` is chosen on.
//!
//! Run: `cargo bench --bench grid -- --warm-up-time 1 --measurement-time 3`.

#[path = "../tests/common/mod.rs"]
mod common;
mod harness;

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput};
use penumbra::camera::Camera;
use penumbra::math::{Ray, Vec3, SHADOW_EPSILON};
use penumbra::store::{PlacedObject, PrimitiveStore};
use penumbra::testing::closest_hit_brute;
use penumbra::trace::{closest_hit, Light, Material, SceneTables, TraceScene};

use harness::rays::median;

/// Scene sizes of `grid_vs_brute`.
const SIZES: &[usize] = &[100, 1_000, 10_000, 100_000];
/// Densities of `grid_lambda`.
const LAMBDAS: &[f32] = &[0.5, 1.0, 2.0, 4.0, 8.0, 16.0];
/// Image side in pixels.
const SIDE: u32 = 256;
/// Edge of the cube the objects are scattered in.
const EXTENT: f32 = 20.0;
/// Grid density of `grid_vs_brute` (the crate default).
const LAMBDA: f32 = penumbra::accel::DEFAULT_LAMBDA;

/// Brute force traces every `brute_stride(n)`-th pixel: all of them at N = 100, fewer as N
/// grows, so one iteration stays well under a second.
fn brute_stride(n: usize) -> u32 {
    match n {
        0..=100 => 1,
        101..=1_000 => 4,
        1_001..=10_000 => 16,
        _ => 256,
    }
}

const LIGHT: Vec3 = Vec3::new(15.0, 25.0, 30.0);

fn tables() -> SceneTables {
    SceneTables {
        materials: vec![Material::default()],
        lights: vec![Light::Point { position: LIGHT, radiance: Vec3::ONE, falloff: Default::default() }],
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 1.6 * EXTENT), Vec3::ZERO, Vec3::Y, 45f32.to_radians()),
        background: Vec3::ZERO,
        ambient: Vec3::ZERO,
    }
}

type Intersect = fn(&TraceScene, &Ray, f32, f32) -> Option<penumbra::store::Hit>;

/// Traces every `stride`-th pixel: a primary ray, and for a hit one shadow ray towards the
/// light (first hit in `(0, dist)`). Returns the number of rays traced and a checksum.
fn trace(scene: &TraceScene, stride: u32, hit: Intersect) -> (u64, u32) {
    let (mut rays, mut lit) = (0u64, 0u32);
    let mut pixel = 0;
    while pixel < SIDE * SIDE {
        let (x, y) = (pixel % SIDE, pixel / SIDE);
        pixel += stride;
        let ray = scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, SIDE, SIDE);
        rays += 1;
        let Some(h) = hit(scene, black_box(&ray), 0.0, f32::INFINITY) else {
            continue;
        };
        let sp = scene.store.surface(&h, &ray);
        let n = if sp.normal.dot(ray.dir) < 0.0 { sp.normal } else { -sp.normal };
        let to = LIGHT - sp.point;
        let dist = to.length();
        let shadow = Ray::new(sp.spawn(n), to / dist);
        rays += 1;
        lit += hit(scene, black_box(&shadow), 0.0, dist * (1.0 - SHADOW_EPSILON)).is_none() as u32;
    }
    (rays, black_box(lit))
}

fn grid_hit(scene: &TraceScene, ray: &Ray, t_min: f32, t_max: f32) -> Option<penumbra::store::Hit> {
    closest_hit(scene, ray, t_min, t_max)
}

fn brute_hit(scene: &TraceScene, ray: &Ray, t_min: f32, t_max: f32) -> Option<penumbra::store::Hit> {
    closest_hit_brute(scene, ray, t_min, t_max)
}

fn spheres(n: usize) -> Vec<PlacedObject> {
    common::random_spheres(n as u64, n, EXTENT)
}

fn grid_vs_brute(c: &mut Criterion) {
    let mut group = c.benchmark_group("grid_vs_brute");
    for &n in SIZES {
        let scene = TraceScene::build(&spheres(n), tables(), LAMBDA);
        for (name, stride, f) in [("grid", 1, grid_hit as Intersect), ("brute", brute_stride(n), brute_hit)] {
            let (rays, _) = trace(&scene, stride, f);
            group.throughput(Throughput::Elements(rays));
            group.bench_with_input(BenchmarkId::new(name, n), &scene, |b, s| b.iter(|| trace(s, stride, f)));
        }
    }
    group.finish();
}

fn lambda_scenes() -> [(&'static str, Vec<PlacedObject>); 2] {
    [("spheres", spheres(10_000)), ("triangles", common::random_triangles(7, 10_000, EXTENT))]
}

fn grid_lambda(c: &mut Criterion) {
    let mut group = c.benchmark_group("grid_lambda");
    for (kind, objects) in lambda_scenes() {
        for &lambda in LAMBDAS {
            group.bench_with_input(BenchmarkId::new(kind, lambda), &objects, |b, objs| {
                b.iter(|| {
                    let scene = TraceScene::build(objs, tables(), black_box(lambda));
                    trace(&scene, 1, grid_hit)
                })
            });
        }
    }
    group.finish();
}

fn print_tables() {
    println!("\ngrid_vs_brute (single thread, medians of 5; brute traces every k-th pixel)");
    println!(
        "{:>8} {:>5} {:>14} {:>15} {:>9} {:>14} {:>10}",
        "N", "k", "grid ns/ray", "brute ns/ray", "speed-up", "grid build ms", "grid refs"
    );
    for &n in SIZES {
        let objects = spheres(n);
        let build = median(5, || TraceScene::<penumbra::store::SoaStore>::build(&objects, tables(), LAMBDA));
        let scene = TraceScene::build(&objects, tables(), LAMBDA);
        let stride = brute_stride(n);
        let (grid_rays, _) = trace(&scene, 1, grid_hit);
        let (brute_rays, _) = trace(&scene, stride, brute_hit);
        let grid_ns = median(5, || trace(&scene, 1, grid_hit)).as_nanos() as f64 / grid_rays as f64;
        let brute_ns = median(5, || trace(&scene, stride, brute_hit)).as_nanos() as f64 / brute_rays as f64;
        println!(
            "{n:>8} {stride:>5} {grid_ns:>14.1} {brute_ns:>15.1} {:>8.1}x {:>14.2} {:>10}",
            brute_ns / grid_ns,
            build.as_secs_f64() * 1e3,
            scene.grid.reference_count()
        );
    }
    println!("\ngrid_lambda (N = 10,000; build + 256x256 trace, medians of 5)");
    println!(
        "{:>10} {:>7} {:>10} {:>10} {:>10} {:>12} {:>10}",
        "scene", "lambda", "build ms", "trace ms", "total ms", "ns/ray", "refs/obj"
    );
    for (kind, objects) in lambda_scenes() {
        for &lambda in LAMBDAS {
            let build =
                median(5, || TraceScene::<penumbra::store::SoaStore>::build(&objects, tables(), lambda));
            let scene = TraceScene::build(&objects, tables(), lambda);
            let (rays, _) = trace(&scene, 1, grid_hit);
            let traced = median(5, || trace(&scene, 1, grid_hit));
            println!(
                "{kind:>10} {lambda:>7} {:>10.2} {:>10.2} {:>10.2} {:>12.1} {:>10.2}",
                build.as_secs_f64() * 1e3,
                traced.as_secs_f64() * 1e3,
                (build + traced).as_secs_f64() * 1e3,
                traced.as_nanos() as f64 / rays as f64,
                scene.grid.reference_count() as f64 / objects.len() as f64
            );
        }
    }
}

fn main() {
    harness::run(
        10,
        |c| {
            grid_vs_brute(c);
            grid_lambda(c)
        },
        print_tables,
    );
}
