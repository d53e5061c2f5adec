//! Question: what do ray packets over structure-of-arrays buy over single rays, and what does
//! the layout alone buy (structure-of-arrays against array-of-structures on the identical
//! single-ray code path: the tracer is generic over the store)?
//!
//! Scenes: ANCHORS.md's "many" (100,000 spheres of radius 0.02–0.06 in an 8×8×8 box over a
//! ground plane), and its "mesh" scenes with the full Stanford bunny (69,451 triangles) and
//! dragon (871,414) from `../shared/models/` (skipped with a note when absent). Rays: one
//! camera ray per pixel of a 640×480 image, and one shadow ray per hit towards the point light
//! (ANCHORS' 0.31 M + ~0.30 M), traced on both cores: as SoA packets at the best SIMD level
//! this CPU has (camera rays in 4×4 pixel blocks, shadow rays 16 consecutive hits towards the
//! light); as single rays through the SoA store with the single-ray SIMD kernels (one ray
//! against a mesh cell's triangles, 8 at a time, at the best level); and as single rays through
//! the SoA and AoS stores with scalar kernels (one primitive at a time). Groups
//! `layout_primary` and `layout_shadow`, ids `packets/SCENE`, `soa_simd/SCENE`, `soa/SCENE` and
//! `aos/SCENE`; then a table of medians with the ratios against AoS scalar single rays.
//!
//! Run: `cargo bench --bench layout`.

#[path = "../tests/common/mod.rs"]
mod common;
mod harness;

use criterion::{BenchmarkId, Criterion, Throughput};
use glam::{DAffine3, DVec3};
use harness::rays::{
    median, mrays, ray_set, trace_primary_at, trace_primary_packets, trace_shadow_at, trace_shadow_packets,
    RaySet,
};
use penumbra::camera::Camera;
use penumbra::geom::Shape;
use penumbra::math::Vec3;
use penumbra::simd::SimdLevel;
use penumbra::store::{AosStore, MaterialId, PlacedObject, PrimitiveStore, SoaStore};
use penumbra::trace::{Light, Material, SceneTables, TraceScene};
use rand::RngExt;

const W: u32 = 640;
const H: u32 = 480;
const MANY_LIGHT: Vec3 = Vec3::new(6.0, 14.0, -10.0);

/// ANCHORS.md's "many": 100k random spheres over a ground plane.
fn many<S: PrimitiveStore>() -> TraceScene<S> {
    let mut rng = common::rng(100_000);
    let mut objects: Vec<PlacedObject> = (0..100_000)
        .map(|_| {
            let centre = common::point_in(&mut rng, Vec3::new(-4.0, 0.1, -4.0), Vec3::new(4.0, 8.1, 4.0));
            let radius = rng.random_range(0.02f32..0.06);
            PlacedObject {
                geometry: Shape::Sphere { centre: centre.as_dvec3(), radius }
                    .place(&DAffine3::IDENTITY, DVec3::ZERO),
                material: MaterialId(0),
            }
        })
        .collect();
    objects.push(PlacedObject {
        geometry: Shape::Plane { point: DVec3::ZERO, normal: Vec3::Y }
            .place(&DAffine3::IDENTITY, DVec3::ZERO),
        material: MaterialId(0),
    });
    let tables = SceneTables {
        materials: vec![Material::default()],
        lights: vec![Light::Point { position: MANY_LIGHT, radiance: Vec3::ONE, falloff: Default::default() }],
        camera: Camera::look_at(
            Vec3::new(0.0, 4.0, -11.0),
            Vec3::new(0.0, 4.0, 0.0),
            Vec3::Y,
            45f32.to_radians(),
        ),
        background: Vec3::ZERO,
        ambient: Vec3::ZERO,
    };
    TraceScene::build(&objects, tables, penumbra::accel::DEFAULT_LAMBDA)
}

/// A scene in both layouts, with its rays.
struct Case {
    name: &'static str,
    soa: TraceScene<SoaStore>,
    aos: TraceScene<AosStore>,
    rays: RaySet,
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let soa = many::<SoaStore>();
    let rays = ray_set(&soa, W, H, MANY_LIGHT);
    out.push(Case { name: "spheres_100k", soa, aos: many::<AosStore>(), rays });
    for (name, file) in [("bunny", "bunny.obj"), ("dragon", "dragon.obj")] {
        let Some(path) = common::shared_model(file) else {
            eprintln!("layout: ../shared/models/{file} not found; skipping the {name}");
            continue;
        };
        let mesh = common::mesh_asset(&path, penumbra::accel::MESH_LAMBDA);
        let soa: TraceScene<SoaStore> = common::mesh_scene(mesh.clone(), penumbra::accel::DEFAULT_LAMBDA);
        let aos: TraceScene<AosStore> = common::mesh_scene(mesh, penumbra::accel::DEFAULT_LAMBDA);
        let rays = ray_set(&soa, W, H, common::MESH_LIGHT);
        out.push(Case { name, soa, aos, rays });
    }
    out
}

fn groups(c: &mut Criterion, cases: &[Case]) {
    type Kernel<S, R> = fn(&TraceScene<S>, &[R], SimdLevel) -> usize;
    let level = SimdLevel::Auto.resolve();
    fn group<R>(
        c: &mut Criterion,
        name: &str,
        cases: &[Case],
        rays: impl Fn(&Case) -> &[R],
        packets: impl Fn(&Case, &[R]) -> usize,
        soa: Kernel<SoaStore, R>,
        aos: Kernel<AosStore, R>,
    ) {
        let mut group = c.benchmark_group(name);
        for case in cases {
            let r = rays(case);
            group.throughput(Throughput::Elements(r.len() as u64));
            group.bench_function(BenchmarkId::new("packets", case.name), |b| b.iter(|| packets(case, r)));
            group.bench_function(BenchmarkId::new("soa_simd", case.name), |b| {
                b.iter(|| soa(&case.soa, r, SimdLevel::Auto))
            });
            group.bench_function(BenchmarkId::new("soa", case.name), |b| {
                b.iter(|| soa(&case.soa, r, SimdLevel::Scalar))
            });
            group.bench_function(BenchmarkId::new("aos", case.name), |b| {
                b.iter(|| aos(&case.aos, r, SimdLevel::Scalar))
            });
        }
        group.finish();
    }
    let primary_packets = |k: &Case, r: &[penumbra::math::Ray]| trace_primary_packets(&k.soa, r, W, level);
    let shadow_packets = |k: &Case, r: &[(penumbra::math::Ray, f32)]| {
        trace_shadow_packets(&k.soa, r, &k.rays.shadow_block, level)
    };
    group(
        c,
        "layout_primary",
        cases,
        |k| &k.rays.primary,
        primary_packets,
        trace_primary_at,
        trace_primary_at,
    );
    group(c, "layout_shadow", cases, |k| &k.rays.shadow, shadow_packets, trace_shadow_at, trace_shadow_at);
}

fn table(cases: &[Case]) {
    let level = SimdLevel::Auto.resolve();
    println!(
        "\nlayout: camera and point-light shadow rays, {W}x{H}, both cores, medians of 7 (Mrays/s); \
         pkt: SoA packets of 4x4 pixels; simd: SoA single rays, a mesh cell's triangles 8 at a time; \
         SoA, AoS: single rays, one primitive at a time; all at {level}; ratios against AoS"
    );
    println!(
        "{:<13} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7}   {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7}",
        "scene",
        "cam pkt",
        "cam sim",
        "cam SoA",
        "cam AoS",
        "pkt/A",
        "simd/A",
        "SoA/A",
        "shd pkt",
        "shd sim",
        "shd SoA",
        "shd AoS",
        "pkt/A",
        "simd/A",
        "SoA/A"
    );
    for case in cases {
        let (p, s) = (&case.rays.primary, &case.rays.shadow);
        // Interleave the variants so drift on a shared machine hits them alike.
        let pp = median(7, || trace_primary_packets(&case.soa, p, W, level));
        let pv = median(7, || trace_primary_at(&case.soa, p, SimdLevel::Auto));
        let ps = median(7, || trace_primary_at(&case.soa, p, SimdLevel::Scalar));
        let pa = median(7, || trace_primary_at(&case.aos, p, SimdLevel::Scalar));
        let sp = median(7, || trace_shadow_packets(&case.soa, s, &case.rays.shadow_block, level));
        let sv = median(7, || trace_shadow_at(&case.soa, s, SimdLevel::Auto));
        let ss = median(7, || trace_shadow_at(&case.soa, s, SimdLevel::Scalar));
        let sa = median(7, || trace_shadow_at(&case.aos, s, SimdLevel::Scalar));
        let ratio = |a: std::time::Duration, b: std::time::Duration| a.as_secs_f64() / b.as_secs_f64();
        println!(
            "{:<13} {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.3} {:>7.3} {:>7.3}   {:>7.2} {:>7.2} {:>7.2} {:>7.2} {:>7.3} {:>7.3} {:>7.3}",
            case.name,
            mrays(p.len(), pp),
            mrays(p.len(), pv),
            mrays(p.len(), ps),
            mrays(p.len(), pa),
            ratio(pa, pp),
            ratio(pa, pv),
            ratio(pa, ps),
            mrays(s.len(), sp),
            mrays(s.len(), sv),
            mrays(s.len(), ss),
            mrays(s.len(), sa),
            ratio(sa, sp),
            ratio(sa, sv),
            ratio(sa, ss),
        );
    }
}

fn main() {
    let cases = cases();
    harness::run(10, |c| groups(c, &cases), || table(&cases));
}
