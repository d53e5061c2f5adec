//! Ray packets against single rays: on seeded random scenes (spheres, triangles, polygons,
//! boxes, planes, mesh instances), every lane of a packet traced by coherent grid traversal
//! must get exactly the hit the single-ray DDA gets (the same `t` bits, object, primitive and
//! barycentrics), at every SIMD level, for camera blocks, packets with mixed direction signs,
//! parallel rays, a shared origin inside the grid, origins inside objects and segments with
//! finite ranges. And the lane-wise triangle kernel equals the scalar one bit for bit.

// Lane loops index several parallel lane arrays by the same lane number.
#![allow(clippy::needless_range_loop)]

use crate::common;

use std::sync::Arc;

use common::{point_in, rng, unit_vector};
use glam::DVec3;
use penumbra::accel::packet::Footprint;
use penumbra::geom::mesh::{icosphere, MeshData};
use penumbra::geom::triangle::{self, TriangleHit, WatertightPacket, WatertightRay};
use penumbra::geom::{MeshId, Shape};
use penumbra::math::Aabb;
use penumbra::math::{Affine3A, Quat, Ray, RayPacket, Vec3};
use penumbra::simd::SimdLevel;
use penumbra::store::{
    AosStore, AosTriangles, Hit, MaterialId, MeshAsset, ObjectKind, PlacedObject, PrimitiveStore,
    SoaTriangles, TraversalCost, TriangleLayout,
};
use penumbra::trace::packet::{closest_hits, occluded, shadow_passes, Origins, LANES};
use penumbra::trace::{closest_hit, Material, TraceScene};
use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::RngExt;

fn asset(data: MeshData) -> Arc<MeshAsset> {
    Arc::new(MeshAsset::new("test", data, 2.0))
}

/// The random mixed cloud plus instances of two meshes (rotated, non-uniformly scaled).
fn scene<S: PrimitiveStore>(seed: u64) -> TraceScene<S> {
    scene_with(seed, &[0.0])
}

/// [`scene`] with one material per transmission coefficient in `kts`, dealt out in turn.
fn scene_with<S: PrimitiveStore>(seed: u64, kts: &[f32]) -> TraceScene<S> {
    let meshes =
        vec![asset(icosphere(Vec3::ZERO, 1.0, 2)), asset(icosphere(Vec3::new(0.5, 0.0, 0.0), 0.7, 1))];
    let mut rng = rng(seed);
    let mut objects = common::random_mixed(seed, 120);
    for i in 0..12 {
        let m = i % 2;
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::new(rng.random_range(0.3..1.5), rng.random_range(0.3..1.5), rng.random_range(0.3..1.5)),
            Quat::from_axis_angle(unit_vector(&mut rng), rng.random_range(0.0..6.3)),
            point_in(&mut rng, Vec3::splat(-5.0), Vec3::splat(5.0)),
        );
        let shape = Shape::Mesh { mesh: MeshId(m as u32), bounds: meshes[m].data.bounds };
        objects.push(PlacedObject {
            geometry: shape.place(&to_world.as_daffine3(), DVec3::ZERO),
            material: MaterialId(0),
        });
    }
    for (k, o) in objects.iter_mut().enumerate() {
        o.material = MaterialId((k % kts.len()) as u32);
    }
    // Tinted: the channels' products differ, and each must match the single ray's bits.
    let materials =
        kts.iter().map(|&kt| Material { kt: Vec3::new(kt, 0.75 * kt, kt), ..Material::default() }).collect();
    TraceScene::build_with_meshes(
        &objects,
        &meshes,
        common::tables_with(materials, Vec3::new(0.0, 0.0, 30.0)),
        3.0,
    )
}

/// The kinds of packet drawn.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// A 4×4 block of neighbouring camera pixels.
    CameraBlock,
    /// A shared origin inside the grid, directions in a narrow cone.
    SharedOrigin,
    /// Random origins and directions: mixed signs, so lanes walk alone.
    Mixed,
    /// One direction (sometimes axis-parallel with ±0.0 components), origins on a lattice.
    Parallel,
    /// Origins inside spheres of the scene.
    InsideObjects,
    /// Shadow-style segments with finite ranges and some `t_min > 0`.
    Segments,
}

fn packet<S: PrimitiveStore>(rng: &mut StdRng, scene: &TraceScene<S>, kind: Kind) -> RayPacket<LANES> {
    let mut p = RayPacket::<LANES>::default();
    let (w, h) = (64, 48);
    let (bx, by) = (rng.random_range(0..w / 4) * 4, rng.random_range(0..h / 4) * 4);
    let origin = point_in(rng, Vec3::splat(-4.0), Vec3::splat(4.0));
    let axis = unit_vector(rng);
    let dir = if rng.random::<f32>() < 0.3 {
        let mut d = Vec3::ZERO;
        d[rng.random_range(0..3)] = if rng.random::<bool>() { 1.0 } else { -1.0 };
        if rng.random::<bool>() {
            d = d.map(|c| if c == 0.0 { -0.0 } else { c });
        }
        d
    } else {
        unit_vector(rng)
    };
    for i in 0..LANES {
        if rng.random::<f32>() < 0.05 {
            continue; // an inactive lane now and then
        }
        let (ray, t_min, t_max) = match kind {
            Kind::CameraBlock => {
                let (x, y) = (bx + (i % 4) as u32, by + (i / 4) as u32);
                (scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, w, h), 0.0, f32::INFINITY)
            }
            Kind::SharedOrigin => {
                let d = (axis + 0.15 * unit_vector(rng)).normalize();
                (Ray::new(origin, d), 0.0, f32::INFINITY)
            }
            Kind::Mixed => (
                Ray::new(point_in(rng, Vec3::splat(-8.0), Vec3::splat(8.0)), unit_vector(rng)),
                0.0,
                f32::INFINITY,
            ),
            Kind::Parallel => {
                let o = origin + Vec3::new((i % 4) as f32, (i / 4) as f32, (i % 3) as f32) * 0.37 - 1.0;
                (Ray::new(o, dir), 0.0, f32::INFINITY)
            }
            Kind::InsideObjects => {
                // Inside the cloud's objects often enough: a short random walk from the origin.
                let o = origin + unit_vector(rng) * rng.random_range(0.0..0.6);
                (Ray::new(o, (axis + 0.3 * unit_vector(rng)).normalize()), 0.0, f32::INFINITY)
            }
            Kind::Segments => {
                let a = point_in(rng, Vec3::splat(-6.0), Vec3::splat(6.0));
                let b = origin + unit_vector(rng) * 0.5;
                let d = b - a;
                let t_min = if rng.random::<bool>() { 0.0 } else { rng.random_range(0.0..0.3) };
                (Ray::new(a, d.normalize()), t_min, d.length())
            }
        };
        p.set(i, &ray, t_min, t_max);
    }
    p
}

fn bits(h: Option<Hit>) -> Option<(u32, penumbra::store::ObjectId, u32, u32, u32)> {
    h.map(|h| (h.t.to_bits(), h.object, h.prim, h.u.to_bits(), h.v.to_bits()))
}

fn check<S: PrimitiveStore>(scene: &TraceScene<S>, seed: u64) -> (usize, usize) {
    let mut rng = rng(seed ^ 0x9e37);
    let kinds = [
        Kind::CameraBlock,
        Kind::SharedOrigin,
        Kind::Mixed,
        Kind::Parallel,
        Kind::InsideObjects,
        Kind::Segments,
    ];
    let (mut lanes, mut hits) = (0, 0);
    for round in 0..60 {
        for kind in kinds {
            let p = packet(&mut rng, scene, kind);
            let want: Vec<Option<Hit>> = (0..LANES)
                .map(|i| p.active[i].then(|| closest_hit(scene, &p.ray(i), p.t_min[i], p.t_max[i])).flatten())
                .collect();
            for level in [SimdLevel::Baseline, SimdLevel::Auto] {
                let got = level.run(
                    #[inline(always)]
                    || closest_hits(scene, &p, &mut TraversalCost::default()),
                );
                for i in 0..LANES {
                    assert_eq!(
                        bits(got.hit[i]),
                        bits(want[i]),
                        "seed {seed}, round {round}, {kind:?}, lane {i} ({level}): ray {:?} [{}, {}]",
                        p.ray(i),
                        p.t_min[i],
                        p.t_max[i]
                    );
                }
            }
            lanes += p.active.iter().filter(|&&a| a).count();
            hits += want.iter().filter(|h| h.is_some()).count();
        }
    }
    (lanes, hits)
}

#[test]
fn every_lane_of_a_packet_finds_the_single_rays_hit_on_random_scenes() {
    let (mut lanes, mut hits) = (0, 0);
    for seed in 0..4 {
        let (l, h) = check(&scene::<penumbra::store::SoaStore>(seed), seed);
        lanes += l;
        hits += h;
    }
    // The fixture must exercise hits and misses alike.
    assert!(hits * 5 > lanes && hits * 5 < lanes * 4, "{hits} hits of {lanes} lanes");
}

#[test]
fn packets_equal_single_rays_in_the_array_of_structures_store_too() {
    check(&scene::<AosStore>(7), 7);
}

/// A triangle and a ray aimed at it: through a vertex, an edge point, the inside or nowhere
/// in particular, on integer coordinates so that edge functions are often exactly zero.
fn triangle_case() -> impl Strategy<Value = ([Vec3; 3], Ray)> {
    let v = || (-4i32..4, -4i32..4, -4i32..4).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32));
    let dir = prop_oneof![
        (-3i32..4, -3i32..4, -3i32..4).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32)),
        (0usize..3, any::<bool>(), any::<bool>()).prop_map(|(axis, neg, negzero)| {
            let zero = if negzero { -0.0 } else { 0.0 };
            let mut d = Vec3::splat(zero);
            d[axis] = if neg { -1.0 } else { 1.0 };
            d
        }),
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
    ];
    (v(), v(), v(), dir, 0u8..4, -6i32..6, 0.0f32..1.0).prop_filter_map(
        "non-zero direction",
        |(a, b, c, d, aim, back, s)| {
            if d == Vec3::ZERO {
                return None;
            }
            let target = match aim {
                0 => a,
                1 => a + (b - a) * 0.5,
                2 => (a + b + c) / 3.0,
                _ => a + (c - a) * s,
            };
            Some(([a, b, c], Ray::new(target - d * back as f32, d)))
        },
    )
}

/// Up to eight triangles of a cell: halves of unit lattice squares in three stacked layers (so
/// neighbours share edges and vertices, and some lie behind others), repeats (equally near), and
/// now and then a random one; with a ray aimed at a vertex, an edge point or a centroid of one.
fn block_case() -> impl Strategy<Value = (Vec<[Vec3; 3]>, Ray, f32, f32)> {
    let lattice = (0i32..3, 0i32..3, 0i32..3, any::<bool>()).prop_map(|(x, y, z, upper)| {
        let p = |dx: i32, dy: i32| Vec3::new((x + dx) as f32, (y + dy) as f32, z as f32 * 0.5);
        if upper {
            [p(1, 1), p(0, 1), p(1, 0)]
        } else {
            [p(0, 0), p(1, 0), p(0, 1)]
        }
    });
    let tri = prop_oneof![4 => lattice, 1 => triangle_case().prop_map(|(t, _)| t)];
    let dir = prop_oneof![
        (-3i32..4, -3i32..4, 1i32..4).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32)),
        any::<bool>().prop_map(|negzero| if negzero { Vec3::new(-0.0, -0.0, 1.0) } else { Vec3::Z }),
        (-1.0f32..1.0, -1.0f32..1.0, 0.1f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
    ];
    (
        proptest::collection::vec(tri, 3..=8),
        0usize..8,
        0u8..3,
        dir,
        any::<bool>(),
        prop_oneof![Just(0.0f32), 0.0f32..2.0],
        prop_oneof![Just(f32::INFINITY), 1.0f32..6.0],
    )
        .prop_map(|(mut tris, k, aim, d, repeat, t_min, t_max)| {
            if repeat {
                let last = tris.len() - 1;
                tris[last] = tris[0];
            }
            let [a, b, c] = tris[k % tris.len()];
            let target = match aim {
                0 => a,
                1 => a + (b - a) * 0.5,
                _ => (a + b + c) / 3.0,
            };
            let ray = Ray::new(target - d * 2.0, if k % 2 == 0 { d } else { -d });
            (tris, ray, t_min, t_max)
        })
}

/// With transmission, a shadow packet's lanes get the single ray's transmittance bit for bit:
/// the packet meets the objects in another order than the single ray's walk, so this checks
/// that both multiply the objects' shares in the same (id) order. Some objects are opaque, the
/// rest pass 35–90 % per crossing; the planes of the cloud transmit too.
fn check_transmittances<S: PrimitiveStore>() {
    let (mut lanes, mut partial, mut several) = (0, 0, 0);
    let kts = [0.0, 0.5, 0.9, 0.35, 0.8];
    for seed in 0..4 {
        let scene = scene_with::<S>(seed, &kts);
        assert!(scene.effects.transmission, "the fixture transmits");
        let mut rng = rng(seed ^ 0x7a55);
        for round in 0..200 {
            let p = shadow_packet(&mut rng, round % 2 == 0);
            let want: Vec<Vec3> = (0..LANES)
                .map(|i| {
                    if p.active[i] {
                        penumbra::trace::transmittance(&scene, &p.ray(i), p.t_max[i])
                    } else {
                        Vec3::ZERO
                    }
                })
                .collect();
            let origins: &[Origins] =
                if round % 2 == 0 { &[Origins::Shared, Origins::Apart] } else { &[Origins::Apart] };
            for level in [SimdLevel::Scalar, SimdLevel::Baseline, SimdLevel::Auto] {
                for &from in origins {
                    let got = level.run(
                        #[inline(always)]
                        || shadow_passes(&scene, &p, from, &mut TraversalCost::default()),
                    );
                    for i in (0..LANES).filter(|&i| p.active[i]) {
                        assert_eq!(
                            got[i].to_array().map(f32::to_bits),
                            want[i].to_array().map(f32::to_bits),
                            "seed {seed}, round {round}, lane {i} ({level}, {from:?})"
                        );
                    }
                }
            }
            for i in (0..LANES).filter(|&i| p.active[i]) {
                lanes += 1;
                partial += usize::from(want[i].x > 0.0 && want[i].x < 1.0);
                // Three or more crossings of distinct coefficients: the order of the product shows.
                several += usize::from(want[i].x > 0.0 && want[i].x < 0.5 * 0.9 * 0.8);
            }
        }
    }
    assert!(partial * 5 > lanes, "{partial} of {lanes} lanes partly transmitted");
    assert!(several * 20 > lanes, "{several} of {lanes} lanes crossed several objects");
}

#[test]
fn transmissive_shadow_packets_equal_single_rays_bit_for_bit() {
    check_transmittances::<penumbra::store::SoaStore>();
    check_transmittances::<AosStore>();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// The lane-wise kernel, run on a packet of rays around the case (the case itself, its
    /// direction's sign flipped, and small perturbations), equals the scalar kernel lane for
    /// lane, at every SIMD level, with a common permutation or without.
    #[test]
    fn the_lane_kernel_equals_the_scalar_kernel_bit_for_bit((tri, ray) in triangle_case(), jitter in 0.0f32..1e-3) {
        let mut p = RayPacket::<8>::default();
        for i in 0..8 {
            let d = match i {
                0 => ray.dir,
                1 => -ray.dir,
                _ => ray.dir + Vec3::new(i as f32, -(i as f32), 0.5) * jitter,
            };
            let d = if d == Vec3::ZERO { ray.dir } else { d };
            p.set(i, &Ray::new(ray.origin, d), if i == 3 { 0.5 } else { 0.0 }, if i == 4 { 2.0 } else { f32::INFINITY });
        }
        let live = [true; 8];
        let want: Vec<Option<TriangleHit>> = (0..8)
            .map(|i| triangle::intersect(tri[0], tri[1], tri[2], &WatertightRay::new(&p.ray(i)), p.t_min[i], p.t_max[i]))
            .collect();
        for level in SimdLevel::ALL {
            if !level.available() {
                continue;
            }
            let got = level.run(#[inline(always)] || {
                let w = WatertightPacket::new(&p, &live);
                let mut bound = p.t_max;
                let mut got = [None; 8];
                triangle::triangle_lanes(tri, &w, &live, &p.t_min, &mut bound, |i, h| got[i] = Some(h));
                got
            });
            for i in 0..8 {
                let key = |h: Option<TriangleHit>| h.map(|h| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits()));
                prop_assert_eq!(key(got[i]), key(want[i]), "lane {} at {}", i, level);
            }
        }
    }
}

#[test]
fn a_camera_block_shares_one_permutation_and_mixed_signs_do_not() {
    let s = scene::<penumbra::store::SoaStore>(1);
    let mut rng = rng(3);
    let block = packet(&mut rng, &s, Kind::CameraBlock);
    let live = block.active;
    assert!(WatertightPacket::new(&block, &live).common_permutation().is_some());
    let mut mixed = RayPacket::<LANES>::default();
    mixed.set(0, &Ray::new(Vec3::ZERO, Vec3::X), 0.0, 1.0);
    mixed.set(1, &Ray::new(Vec3::ZERO, Vec3::Y), 0.0, 1.0);
    let live = mixed.active;
    assert!(WatertightPacket::new(&mixed, &live).common_permutation().is_none());
}

/// Every shipped scene, rendered small, with `simd` (the scene's own effects and samples).
fn render_shipped(path: &std::path::Path, simd: SimdLevel) -> Vec<u32> {
    render_adjusted(path, 61, simd, |_| {}).0
}

/// The scene at `path` rendered `width` pixels wide with `simd` and the settings `adjust`
/// leaves: the film's bits and the ray counts.
fn render_adjusted(
    path: &std::path::Path,
    width: u32,
    simd: SimdLevel,
    adjust: impl Fn(&mut penumbra::trace::RenderSettings),
) -> (Vec<u32>, penumbra::trace::stats::RayCounts) {
    let desc = penumbra::scene::load_scene(path).expect("shipped scene loads");
    let mut world: penumbra::world::SceneWorld = penumbra::scene::spawn_world(&desc);
    let snapshot = world.update();
    let base = world.render_settings();
    // Odd sizes leave partial blocks and tiles; the aspect is kept roughly.
    let height = (width * base.height / base.width.max(1)).max(1) | 1;
    let mut settings = penumbra::trace::RenderSettings { width, height, simd, ..base };
    adjust(&mut settings);
    let (film, stats) = penumbra::trace::render(&snapshot, &settings);
    assert_eq!(stats.simd, simd.resolve());
    (film.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect(), stats.rays)
}

/// A lens camera's samples go in per-pixel packets (up to 16 at a time) where a pixel takes
/// at least 8, and in per-point packets where an adaptive render's lattice point does: whole
/// packets, a last partial one, counts below the packet minimum, lens samples under several AA
/// positions, and adaptive renders (corners with all of a pixel's lens samples, deeper points
/// with their share) and noise-driven renders (a pixel's pending samples together) must all
/// give the single rays' bits and ray counts.
#[test]
fn lens_packets_give_the_single_rays_bits_for_any_sample_count() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/effects_dof.ron");
    use penumbra::sample::{adaptive::AdaptiveSettings, noise::NoiseSettings};
    let adaptive = Some(AdaptiveSettings { threshold: 0.02, max_depth: 2 });
    let noise = Some(NoiseSettings {
        target_error: 0.02,
        min_samples: 8,
        max_samples: 64,
        time_limit: None,
        rounds: Some(3),
    });
    let fixed =
        [(1, 3), (1, 4), (1, 16), (1, 21), (1, 33), (2, 4), (3, 7)].map(|(aa, lens)| (aa, lens, None, None));
    let refined = [(1, 16, adaptive, None), (1, 37, adaptive, None), (1, 5, adaptive, None)];
    let noisy = [(1, 16, None, noise), (1, 6, None, noise), (2, 3, None, noise)];
    for (aa, lens, adaptive, noise) in fixed.into_iter().chain(refined).chain(noisy) {
        let adjust = |s: &mut penumbra::trace::RenderSettings| {
            s.aa.samples = aa;
            s.lens.samples = lens;
            s.adaptive = adaptive;
            s.noise = noise;
        };
        let case =
            format!("AA {aa}, lens {lens}, adaptive {}, noise {}", adaptive.is_some(), noise.is_some());
        let (want, want_rays) = render_adjusted(&path, 23, SimdLevel::Scalar, adjust);
        match (adaptive, noise) {
            (None, None) => {
                assert_eq!(
                    want_rays.lens,
                    u64::from(23 * 17 * aa * lens),
                    "{case}: every sample is a lens ray"
                )
            }
            // 24 × 18 corners take all the lens samples; deeper points take their share.
            (Some(_), _) => assert!(want_rays.lens > u64::from(24 * 18 * lens), "{case}: {}", want_rays.lens),
            // At least one batch per pixel, all of them lens rays.
            (None, Some(_)) => {
                assert!(want_rays.lens >= u64::from(23 * 17 * aa * lens), "{case}: {}", want_rays.lens);
                assert_eq!(want_rays.camera, 0, "{case}");
            }
        }
        for level in [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512] {
            if level.available() {
                let (got, rays) = render_adjusted(&path, 23, level, adjust);
                let differ = want.iter().zip(&got).filter(|(a, b)| a != b).count();
                assert!(differ == 0, "{case}: {differ} channels differ between scalar and {level}");
                assert_eq!(rays.lens, want_rays.lens, "{case}");
                assert_eq!(rays.area_shadow, want_rays.area_shadow, "{case}");
                assert_eq!(rays.reflection + rays.refraction, want_rays.reflection + want_rays.refraction);
            }
        }
    }
}

/// An adaptive render's pixel corners under a pinhole camera go in packets of 4 × 4 corners
/// (bands of four corner rows; an odd width and height leave partial blocks and a partial last
/// band): on scenes lit by point and directional lights, an area light, mirrors and glass, and
/// a mesh, at several depths and thresholds, every path must give the single rays' bits and
/// ray counts, and the refinement figures must not change.
#[test]
fn adaptive_corner_packets_give_the_single_rays_bits() {
    use penumbra::sample::adaptive::AdaptiveSettings;
    let scenes = ["effects_adaptive", "effects_soft_shadows", "spheres", "bunny", "effects_aa"];
    for (name, width, max_depth, threshold) in [
        (scenes[0], 37, 3, 0.05),
        (scenes[1], 29, 2, 0.02),
        (scenes[2], 33, 1, 0.1),
        (scenes[3], 30, 2, 0.05),
        (scenes[4], 26, 4, 0.0),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.ron"));
        let adjust = |s: &mut penumbra::trace::RenderSettings| {
            s.adaptive = Some(AdaptiveSettings { threshold, max_depth });
            s.noise = None;
        };
        let render = |simd: SimdLevel| {
            let desc = penumbra::scene::load_scene(&path).expect("shipped scene loads");
            let mut world: penumbra::world::SceneWorld = penumbra::scene::spawn_world(&desc);
            let snapshot = world.update();
            let base = world.render_settings();
            assert!(!snapshot.camera.has_lens(), "{name} is a pinhole scene");
            let height = (width * base.height / base.width.max(1)).max(1) | 1;
            let mut settings = penumbra::trace::RenderSettings { width, height, simd, ..base };
            adjust(&mut settings);
            let (film, stats) = penumbra::trace::render(&snapshot, &settings);
            let bits: Vec<u32> = film.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect();
            (bits, stats.rays, stats.adaptive)
        };
        let (want, want_rays, want_adaptive) = render(SimdLevel::Scalar);
        assert!(want_adaptive.subdivisions > 0 || max_depth == 0, "{name}: nothing was refined");
        for level in [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512] {
            if level.available() {
                let (got, rays, adaptive) = render(level);
                let differ = want.iter().zip(&got).filter(|(a, b)| a != b).count();
                assert!(differ == 0, "{name}: {differ} channels differ between scalar and {level}");
                assert_eq!(
                    (rays.camera, rays.shadow, rays.area_shadow, rays.reflection, rays.refraction),
                    (
                        want_rays.camera,
                        want_rays.shadow,
                        want_rays.area_shadow,
                        want_rays.reflection,
                        want_rays.refraction
                    ),
                    "{name} at {level}"
                );
                assert_eq!(adaptive, want_adaptive, "{name} at {level}");
            }
        }
    }
}

#[test]
fn every_shipped_scene_renders_the_same_bits_on_every_path() {
    for path in common::shipped_scenes() {
        let want = render_shipped(&path, SimdLevel::Scalar);
        for level in [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512] {
            if level.available() {
                let got = render_shipped(&path, level);
                let differ = want.iter().zip(&got).filter(|(a, b)| a != b).count();
                assert!(
                    differ == 0,
                    "{}: {differ} channels differ between scalar and {level}",
                    path.display()
                );
            }
        }
    }
}

/// Shadow packets: from one point to 16 points of a square "light" (an area light's samples),
/// and from 16 scattered points to one point (a point light seen from a packet of hits).
fn shadow_packet(rng: &mut StdRng, shared_origin: bool) -> RayPacket<LANES> {
    let mut p = RayPacket::<LANES>::default();
    let common = point_in(rng, Vec3::splat(-5.0), Vec3::splat(5.0));
    let light = point_in(rng, Vec3::splat(-8.0), Vec3::splat(8.0));
    let (eu, ev) = (unit_vector(rng) * 2.0, unit_vector(rng) * 2.0);
    for i in 0..LANES {
        let (from, to) = if shared_origin {
            (common, light + eu * rng.random::<f32>() + ev * rng.random::<f32>())
        } else {
            (common + unit_vector(rng) * rng.random_range(0.0..3.0), light)
        };
        let d = to - from;
        if d.length() > 1e-3 {
            p.set(i, &Ray::new(from, d.normalize()), 0.0, d.length() * 0.999);
        }
    }
    p
}

/// Shadow packets on an opaque `scene` against single rays, lane for lane, at every level;
/// returns the lanes traced and how many were blocked.
fn check_shadows<S: PrimitiveStore>(scene: &TraceScene<S>, seed: u64) -> (usize, usize) {
    assert!(!scene.effects.transmission, "the fixture is opaque");
    let (mut lanes, mut blocked) = (0, 0);
    let mut rng = rng(seed ^ 0x5eed);
    for round in 0..200 {
        let p = shadow_packet(&mut rng, round % 2 == 0);
        let want: Vec<bool> = (0..LANES)
            .map(|i| {
                p.active[i] && penumbra::trace::transmittance(scene, &p.ray(i), p.t_max[i]) == Vec3::ZERO
            })
            .collect();
        // A packet whose lanes share their origin may say so (and is then never scattered).
        let origins: &[Origins] =
            if round % 2 == 0 { &[Origins::Shared, Origins::Apart] } else { &[Origins::Apart] };
        for (level, &from) in [SimdLevel::Baseline, SimdLevel::Auto]
            .into_iter()
            .flat_map(|l| origins.iter().map(move |o| (l, o)))
        {
            let got = level.run(
                #[inline(always)]
                || occluded(scene, &p, from, &mut TraversalCost::default()),
            );
            for i in 0..LANES {
                assert_eq!(
                    got[i] && p.active[i],
                    want[i],
                    "seed {seed}, round {round}, lane {i} ({level}, {from:?})"
                );
            }
        }
        lanes += p.active.iter().filter(|&&a| a).count();
        blocked += want.iter().filter(|&&b| b).count();
    }
    (lanes, blocked)
}

#[test]
fn shadow_packets_block_exactly_the_lanes_single_rays_find_blocked() {
    let (mut lanes, mut blocked) = (0, 0);
    for seed in 0..4 {
        let (l, b) = check_shadows(&scene::<penumbra::store::SoaStore>(seed), seed);
        lanes += l;
        blocked += b;
    }
    assert!(blocked * 5 > lanes && blocked * 5 < lanes * 4, "{blocked} blocked of {lanes}");
}

/// `n` spheres of radii in `radii` at random in [-5, 5]³.
fn random_spheres(seed: u64, n: usize, radii: std::ops::Range<f32>) -> Vec<PlacedObject> {
    let mut rng = rng(seed);
    (0..n)
        .map(|_| {
            let centre = point_in(&mut rng, Vec3::splat(-5.0), Vec3::splat(5.0)).as_dvec3();
            let radius = rng.random_range(radii.clone());
            PlacedObject {
                geometry: Shape::Sphere { centre, radius }.place(&glam::DAffine3::IDENTITY, DVec3::ZERO),
                material: MaterialId(0),
            }
        })
        .collect()
}

/// 3,000 small spheres, a dozen or more to a top-level cell (density 0.1).
fn sphere_cloud<S: PrimitiveStore>() -> TraceScene<S> {
    let objects = random_spheres(0xc10d, 3000, 0.03..0.12);
    TraceScene::build(
        &objects,
        common::tables_with(vec![Material::default()], Vec3::new(0.0, 0.0, 30.0)),
        0.1,
    )
}

/// 200 spheres first, then the random mixed cloud (spheres among triangles, polygons and
/// boxes): the structure-of-arrays store knows the leading spheres by their ids alone, the
/// later ones by their kind.
fn spheres_then_mixed<S: PrimitiveStore>() -> TraceScene<S> {
    let mut objects = random_spheres(0x1ead, 200, 0.1..0.4);
    objects.extend(common::random_mixed(11, 120));
    TraceScene::build(
        &objects,
        common::tables_with(vec![Material::default()], Vec3::new(0.0, 0.0, 30.0)),
        1.0,
    )
}

/// The array-of-structures store reads every object's kind; the structure-of-arrays store skips
/// that for its leading spheres. Both must find the same hits and blockers, ray for ray and
/// lane for lane, for spheres on either side of the boundary.
#[test]
fn leading_spheres_are_found_as_every_other_object_is() {
    let (soa, aos) = (spheres_then_mixed::<penumbra::store::SoaStore>(), spheres_then_mixed::<AosStore>());
    let mut rng = rng(0x5ca1);
    let (mut leading, mut later, mut blocked, mut shadows) = (0, 0, 0, 0);
    for round in 0..300 {
        let p = packet(&mut rng, &soa, [Kind::CameraBlock, Kind::Mixed, Kind::Segments][round % 3]);
        let got = SimdLevel::Auto.run(
            #[inline(always)]
            || closest_hits(&soa, &p, &mut TraversalCost::default()),
        );
        for i in (0..LANES).filter(|&i| p.active[i]) {
            let ray = p.ray(i);
            let want = closest_hit(&aos, &ray, p.t_min[i], p.t_max[i]);
            assert_eq!(
                bits(closest_hit(&soa, &ray, p.t_min[i], p.t_max[i])),
                bits(want),
                "round {round}, lane {i}"
            );
            assert_eq!(bits(got.hit[i]), bits(want), "round {round}, lane {i} (packet)");
            match want.map(|h| h.object.kind()) {
                Some(ObjectKind::Bounded(id)) if id < 200 => leading += 1,
                Some(ObjectKind::Bounded(_)) => later += 1,
                _ => {}
            }
        }
        let s = shadow_packet(&mut rng, round % 2 == 0);
        let got = SimdLevel::Auto.run(
            #[inline(always)]
            || occluded(&soa, &s, Origins::Apart, &mut TraversalCost::default()),
        );
        for i in (0..LANES).filter(|&i| s.active[i]) {
            let want = penumbra::trace::transmittance(&aos, &s.ray(i), s.t_max[i]) == Vec3::ZERO;
            assert_eq!(penumbra::trace::transmittance(&soa, &s.ray(i), s.t_max[i]) == Vec3::ZERO, want);
            assert_eq!(got[i], want, "round {round}, shadow lane {i}");
            (blocked, shadows) = (blocked + usize::from(want), shadows + 1);
        }
    }
    assert!(leading > 200 && later > 200, "hits on leading spheres {leading}, on later objects {later}");
    assert!(blocked * 5 > shadows && blocked * 5 < shadows * 4, "{blocked} of {shadows} blocked");
}

/// Packet walks screen a top-level cell's spheres by the slice's footprint
/// (`PrimitiveStore::may_meet`): most spheres of a crowded cell are passed by. Every lane must
/// still find the single ray's hit, and every shadow lane the single ray's blocker.
#[test]
fn packets_through_a_cloud_of_small_spheres_equal_single_rays() {
    let soa = sphere_cloud::<penumbra::store::SoaStore>();
    let cells = soa.grid.cell_count();
    let stored = soa.grid.prim_ids.len();
    assert!(stored >= 10 * cells, "the fixture should crowd the cells: {stored} ids in {cells} cells");
    let (lanes, hits) = check(&soa, 7);
    assert!(hits * 10 > lanes && hits * 10 < lanes * 9, "{hits} hits of {lanes} lanes");
    check(&sphere_cloud::<AosStore>(), 8);
    let (lanes, blocked) = check_shadows(&soa, 9);
    assert!(blocked * 10 > lanes && blocked * 10 < lanes * 9, "{blocked} blocked of {lanes}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// The lane-wise sphere kernel equals [`sphere::intersect`] bit for bit on every lane, at
    /// every SIMD level: rays through, tangent to (the cold f64 path) and missing spheres from
    /// near and far, unit and non-unit directions, origins inside, finite ranges.
    #[test]
    fn the_sphere_lane_kernel_equals_the_scalar_kernel_bit_for_bit(
        centre in common::strategies::point(50.0),
        radius in prop_oneof![1e-3f32..0.1, 0.1f32..10.0],
        from in common::strategies::point(1.0),
        distance in prop_oneof![0.0f32..3.0, 10.0f32..1e5],
        aims in proptest::collection::vec((common::strategies::point(1.5), 0.1f32..4.0, any::<bool>()), 8),
    ) {
        use penumbra::geom::sphere;
        let mut p = RayPacket::<8>::default();
        let origin = centre + from.normalize_or(Vec3::X) * radius * (1.0 + distance);
        for (i, (aim, length, tangent)) in aims.iter().enumerate() {
            let target = if *tangent {
                // A point on the sphere's silhouette as seen from the origin: grazing rays.
                let to = (centre - origin).normalize_or(Vec3::X);
                let side = to.any_orthonormal_vector();
                centre + side * radius
            } else {
                centre + *aim * radius
            };
            let dir = (target - origin).normalize_or(Vec3::Y) * if i % 2 == 0 { 1.0 } else { *length };
            let t_min = if i == 5 { 0.25 } else { 0.0 };
            let t_max = if i == 6 { 1.5 } else { f32::INFINITY };
            p.set(i, &Ray::new(origin, dir), t_min, t_max);
        }
        let live = [true; 8];
        let want: Vec<Option<u32>> = (0..8)
            .map(|i| sphere::intersect(centre, radius, &p.ray(i), p.t_min[i], p.t_max[i]).map(f32::to_bits))
            .collect();
        for level in SimdLevel::ALL {
            let got = level.run(#[inline(always)] || {
                let mut bound = p.t_max;
                let mut got = [None; 8];
                sphere::intersect_lanes(centre, radius, &p, &live, &mut bound, |i, t| got[i] = Some(t.to_bits()));
                got
            });
            prop_assert_eq!(got.to_vec(), want.clone(), "at {}", level);
        }
    }

    /// The lane-wise plane kernel equals [`plane::intersect`] bit for bit on every lane, at
    /// every SIMD level: planes at any tilt and distance, rays towards and away from them,
    /// parallel ones (some exactly, with ±0.0 components), origins on the plane, finite ranges.
    #[test]
    fn the_plane_lane_kernel_equals_the_scalar_kernel_bit_for_bit(
        normal in common::strategies::point(1.0),
        axis_aligned in any::<bool>(),
        offset in prop_oneof![-1e4f32..1e4, Just(0.0f32)],
        rays in proptest::collection::vec(
            (common::strategies::point(100.0), common::strategies::point(1.0), 0u8..4, 0.0f32..2.0, 0.5f32..50.0),
            8,
        ),
    ) {
        use penumbra::geom::plane;
        let normal = if axis_aligned { Vec3::Y } else { normal.normalize_or(Vec3::Z) };
        let mut p = RayPacket::<8>::default();
        let mut t_min = [0.0f32; 8];
        for (i, (origin, dir, kind, lo, hi)) in rays.iter().enumerate() {
            let (origin, dir) = match kind {
                // Parallel to the plane: a direction with no component along the normal.
                0 => (*origin, (*dir - normal * dir.dot(normal)).normalize_or(normal.any_orthonormal_vector())),
                // Exactly parallel to an axis-aligned plane, with a -0.0 component.
                1 if axis_aligned => (*origin, Vec3::new(dir.x, -0.0, dir.z).normalize_or(Vec3::X)),
                // Starting on the plane.
                2 => (*origin - normal * (normal.dot(*origin) - offset), dir.normalize_or(Vec3::X)),
                _ => (*origin, dir.normalize_or(Vec3::X)),
            };
            t_min[i] = if i % 3 == 0 { *lo } else { 0.0 };
            p.set(i, &Ray::new(origin, dir), t_min[i], if i % 2 == 0 { *hi } else { f32::INFINITY });
        }
        let live = [true, true, true, true, true, true, false, true];
        let want: Vec<Option<u32>> = (0..8)
            .map(|i| {
                if !live[i] { return None; }
                plane::intersect(normal, offset, &p.ray(i), t_min[i], p.t_max[i]).map(f32::to_bits)
            })
            .collect();
        for level in SimdLevel::ALL {
            let got = level.run(#[inline(always)] || {
                let mut got = [None; 8];
                plane::intersect_lanes(normal, offset, &p, &live, &t_min, &p.t_max, |i, t| got[i] = Some(t.to_bits()));
                got
            });
            prop_assert_eq!(got.to_vec(), want.clone(), "at {}", level);
        }
    }

    /// One ray against a cell's triangles at once ([`triangle::nearest_in_block`]) finds what
    /// testing them one by one in order finds (the same triangle, the first of equally near ones,
    /// and the same bits), at every SIMD level: shared edges and vertices hit exactly, repeats,
    /// ±0.0 components, finite ranges.
    #[test]
    fn one_ray_against_a_block_of_triangles_equals_testing_them_in_order((tris, ray, t_min, t_max) in block_case()) {
        let w = WatertightRay::new(&ray);
        let mut want = None;
        let mut bound = t_max;
        for (k, [a, b, c]) in tris.iter().enumerate() {
            if let Some(h) = triangle::intersect(*a, *b, *c, &w, t_min, bound) {
                bound = h.t;
                want = Some((k, h.t.to_bits(), h.u.to_bits(), h.v.to_bits()));
            }
        }
        for level in SimdLevel::ALL {
            let got = level.run(#[inline(always)] || {
                let vertices = |k: usize| tris[k];
                let block = triangle::TriangleBlock::<8>::gather(&w, tris.len(), vertices);
                triangle::nearest_in_block(&block, &w, t_min, t_max, vertices)
                    .map(|(k, h)| (k, h.t.to_bits(), h.u.to_bits(), h.v.to_bits()))
            });
            prop_assert_eq!(got, want, "at {}", level);
        }
    }

    /// The lane-wise box kernel equals [`cuboid::intersect`] bit for bit on every lane (the `t`,
    /// the face and its sign), at every SIMD level: rotated and scaled boxes, and axis-aligned
    /// ones hit by axis-parallel rays lying in a face plane, along an edge or through a corner
    /// (±0.0 components), from outside and inside, with finite ranges.
    #[test]
    fn the_box_lane_kernel_equals_the_scalar_kernel_bit_for_bit(
        turned in any::<bool>(),
        angle in 0.0f32..6.3,
        axis in common::strategies::point(1.0),
        scale in common::strategies::point(1.0),
        centre in common::strategies::point(20.0),
        half in common::strategies::point(3.0),
        aims in proptest::collection::vec(
            (common::strategies::point(1.2), common::strategies::point(1.0), 0u8..4, 0usize..3, any::<bool>()),
            8,
        ),
    ) {
        use penumbra::geom::cuboid;
        let half = half.abs() + Vec3::splat(0.01);
        let (min, max) = (-half, half);
        let to_world = if turned {
            Affine3A::from_scale_rotation_translation(
                scale.abs() + Vec3::splat(0.2),
                Quat::from_axis_angle(axis.normalize_or(Vec3::Y), angle),
                centre,
            )
        } else {
            Affine3A::from_translation(centre)
        };
        let to_object = to_world.inverse();
        let mut p = RayPacket::<8>::default();
        for (i, (aim, from, snap, k, negative_zero)) in aims.iter().enumerate() {
            // Aim at a point of the box (snapped onto a face, an edge or a corner by `snap`).
            let mut target = *aim * half;
            for r in 0..usize::from(*snap).min(3) {
                let r = (k + r) % 3;
                target[r] = if aim[r] < 0.0 { min[r] } else { max[r] };
            }
            let (origin, dir) = if !turned && i % 2 == 0 {
                // Axis-parallel along axis k, from outside or inside, lying in face planes where
                // the target was snapped.
                let mut d = Vec3::ZERO;
                d[*k] = if from[*k] < 0.0 { -1.0 } else { 1.0 };
                if *negative_zero {
                    d = d.map(|c| if c == 0.0 { -0.0 } else { c });
                }
                let mut o = target;
                o[*k] -= d[*k] * (half[*k] * 3.0 * from.x.abs());
                (to_world.transform_point3(o), d)
            } else {
                let o = to_world.transform_point3(target + *from * half * 4.0);
                (o, (to_world.transform_point3(target) - o).normalize_or(Vec3::X))
            };
            let t_min = if i == 5 { 0.25 } else { 0.0 };
            let t_max = if i == 6 { 1.5 } else { f32::INFINITY };
            p.set(i, &Ray::new(origin, dir), t_min, t_max);
        }
        let live = [true; 8];
        let face = |h: cuboid::CuboidHit| (h.t.to_bits(), h.local_normal.to_array().map(f32::to_bits));
        let want: Vec<_> = (0..8)
            .map(|i| cuboid::intersect(&to_object, min, max, &p.ray(i), p.t_min[i], p.t_max[i]).map(face))
            .collect();
        for level in SimdLevel::ALL {
            let got = level.run(#[inline(always)] || {
                let mut bound = p.t_max;
                let mut got = [None; 8];
                cuboid::intersect_lanes(&to_object, min, max, &p, &live, &mut bound, |i, h| got[i] = Some(face(h)));
                got
            });
            prop_assert_eq!(got.to_vec(), want.clone(), "at {}", level);
        }
    }
}

/// A mesh of axis-aligned boxes (twelve triangles each): faces whose bounds are flat on one
/// axis, edges along the axes, corners shared by six faces.
fn boxes_mesh() -> MeshData {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (k, (lo, hi)) in [
        (Vec3::new(-1.3, -0.7, -0.9), Vec3::new(0.2, 0.45, 0.35)),
        (Vec3::new(0.2, -0.7, -0.9), Vec3::new(1.15, 1.3, 0.05)),
        (Vec3::new(-0.6, 0.45, -0.2), Vec3::new(0.2, 0.9, 1.1)),
    ]
    .into_iter()
    .enumerate()
    {
        let base = (k * 8) as u32;
        for c in 0..8 {
            let pick = |bit: usize, a: f32, b: f32| if c & bit == 0 { a } else { b };
            positions.push(Vec3::new(pick(1, lo.x, hi.x), pick(2, lo.y, hi.y), pick(4, lo.z, hi.z)));
        }
        for [a, b, c, d] in
            [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
        {
            indices.push([base + a, base + b, base + c]);
            indices.push([base + a, base + c, base + d]);
        }
    }
    let bounds = penumbra::math::Aabb::from_points(positions.iter().copied());
    MeshData {
        positions,
        normals: Vec::new(),
        indices,
        bounds,
        uvs: Vec::new(),
        face_material: Vec::new(),
        materials: Vec::new(),
    }
}

/// Rays through mesh vertices and through the points where mesh edges cross the mesh grid's
/// walls: the places where a lane's hit lies exactly on the boundary of a triangle's bounds or
/// of a slice, so the walk's footprints must cover the rounding of the lanes' coordinates.
/// Packets of 16 lanes aimed at neighbouring such points, as parallel rays and from a shared
/// origin, get the single rays' hits and shadow answers bit for bit.
#[test]
fn packets_through_vertices_and_edge_wall_crossings_equal_single_rays() {
    let meshes = vec![asset(icosphere(Vec3::ZERO, 1.0, 3)), asset(boxes_mesh())];
    let mut rng = rng(0xfeed);
    let (mut lanes, mut hits, mut ties) = (0, 0, 0);
    for (m, mesh) in meshes.iter().enumerate() {
        let objects = vec![PlacedObject {
            geometry: Shape::Mesh { mesh: MeshId(m as u32), bounds: mesh.data.bounds }
                .place(&glam::DAffine3::IDENTITY, DVec3::ZERO),
            material: MaterialId(0),
        }];
        let scene: TraceScene = TraceScene::build_with_meshes(
            &objects,
            &meshes,
            common::tables_with(vec![Material::default()], Vec3::new(0.0, 0.0, 30.0)),
            3.0,
        );
        // Targets: the vertices, and each edge's crossings of the grid's walls.
        let grid = &mesh.grid;
        let mut targets: Vec<Vec3> = mesh.data.positions.clone();
        for f in &mesh.data.indices {
            for e in 0..3 {
                let (a, b) =
                    (mesh.data.positions[f[e] as usize], mesh.data.positions[f[(e + 1) % 3] as usize]);
                for axis in 0..3 {
                    for &w in &grid.walls[axis] {
                        let s = (w - a[axis]) / (b[axis] - a[axis]);
                        if s > 0.0 && s < 1.0 {
                            let mut p = a + (b - a) * s;
                            p[axis] = w;
                            targets.push(p);
                        }
                    }
                }
            }
        }
        for round in 0..300 {
            let anchor = targets[rng.random_range(0..targets.len())];
            let mut near = targets.clone();
            near.sort_by(|p, q| (*p - anchor).length_squared().total_cmp(&(*q - anchor).length_squared()));
            let d = unit_vector(&mut rng);
            let shared = round % 2 == 1;
            let eye = anchor - d * 6.0;
            let mut p = RayPacket::<LANES>::default();
            for (i, &q) in near.iter().take(LANES).enumerate() {
                let ray =
                    if shared { Ray::new(eye, (q - eye).normalize()) } else { Ray::new(q - d * 6.0, d) };
                p.set(i, &ray, 0.0, if round % 4 < 2 { f32::INFINITY } else { 6.0 + 1e-3 });
            }
            for level in [SimdLevel::Baseline, SimdLevel::Auto] {
                let got = level.run(
                    #[inline(always)]
                    || closest_hits(&scene, &p, &mut TraversalCost::default()),
                );
                let blocked = level.run(
                    #[inline(always)]
                    || occluded(&scene, &p, Origins::Apart, &mut TraversalCost::default()),
                );
                for i in 0..LANES {
                    let want = closest_hit(&scene, &p.ray(i), p.t_min[i], p.t_max[i]);
                    let what = format!("mesh {m}, round {round}, lane {i} ({level})");
                    match (got.hit[i], want) {
                        // Through a vertex or along an edge two triangles may hold the same
                        // nearest point; each walk keeps the first it tests. The packet's must
                        // really be hit there.
                        (Some(g), Some(w)) if g.prim != w.prim => {
                            assert_eq!(g.t.to_bits(), w.t.to_bits(), "{what}");
                            let [a, b, c] =
                                mesh.data.indices[g.prim as usize].map(|k| mesh.data.positions[k as usize]);
                            let ray = WatertightRay::new(&p.ray(i));
                            let again = triangle::intersect(a, b, c, &ray, p.t_min[i], g.t.next_up());
                            assert_eq!(again.map(|h| h.t.to_bits()), Some(g.t.to_bits()), "{what}: a tie");
                            ties += 1;
                        }
                        _ => assert_eq!(bits(got.hit[i]), bits(want), "{what}"),
                    }
                    let shadow = penumbra::trace::transmittance(&scene, &p.ray(i), p.t_max[i]) == Vec3::ZERO;
                    assert_eq!(blocked[i], shadow, "mesh {m}, round {round}, lane {i} ({level}): shadow");
                    if level == SimdLevel::Auto {
                        lanes += 1;
                        hits += usize::from(want.is_some());
                    }
                }
            }
        }
    }
    assert!(hits * 10 > lanes * 7, "the targets lie on the meshes: {hits} hits of {lanes} lanes");
    assert!(ties * 20 < hits, "ties are the exception: {ties} of {hits} hits");
}

/// A cell's screen against a walk's footprint, which compares the two cross axes only, keeps
/// exactly the triangles whose bounds overlap the footprint when (as in a walk) the footprint
/// spans the cell's triangles along the dominant axis: both layouts, every dominant axis,
/// footprints with random corners and with corners on vertex coordinates (ties).
#[test]
fn the_triangle_screen_keeps_the_triangles_whose_bounds_meet_the_footprint() {
    let mut rng = rng(41);
    let (mut kept, mut declined) = (0, 0);
    for round in 0..300 {
        let tris: Vec<[Vec3; 3]> = (0..64)
            .map(|_| [0; 3].map(|_| point_in(&mut rng, Vec3::splat(-1.0), Vec3::splat(1.0))))
            .collect();
        let soa = SoaTriangles::from_vertices(tris.clone());
        let aos = AosTriangles::from_vertices(tris.clone());
        let ids: Vec<u32> = (0..rng.random_range(1..=64)).map(|_| rng.random_range(0..64)).collect();
        let k = round % 3;
        let cross = [(k + 1) % 3, (k + 2) % 3];
        let (mut lo, mut hi) = if round % 2 == 0 {
            let a = point_in(&mut rng, Vec3::splat(-1.2), Vec3::splat(1.2));
            (a, a + point_in(&mut rng, Vec3::ZERO, Vec3::splat(0.6)))
        } else {
            // Corners on vertices' coordinates: bounds that touch the footprint exactly.
            let v = |rng: &mut StdRng| tris[rng.random_range(0..64)][rng.random_range(0..3)];
            let (a, b) = (v(&mut rng), v(&mut rng));
            (a.min(b), a.max(b))
        };
        (lo[k], hi[k]) = (-1e30, 1e30);
        let footprint = Footprint { bounds: Aabb::new(lo, hi), cross };
        let want = ids.iter().enumerate().fold(0u64, |mask, (j, &id)| {
            let [a, b, c] = tris[id as usize];
            mask | u64::from(footprint.bounds.overlaps(&triangle::bounds(a, b, c))) << j
        });
        assert_eq!(soa.screen(&ids, &footprint), want, "round {round}, structure of arrays");
        assert_eq!(aos.screen(&ids, &footprint), want, "round {round}, array of structures");
        kept += want.count_ones();
        declined += ids.len() as u32 - want.count_ones();
    }
    assert!(kept > 1000 && declined > 1000, "kept {kept}, declined {declined}");
}

/// A scene for the lanes of a camera packet shaded together: every kind of point-like light
/// (a point light with and without falloff, a spot, a directional light, and more lights than
/// a packet traces shadows for), materials with and without a highlight (whole, fractional and
/// the largest exponent), emission, a texture, a mirror, and glass that absorbs, with Fresnel.
/// `camera` is the camera's position: inside the big glass sphere every camera ray arrives
/// from inside it.
fn local_shading_scene(camera: &str) -> penumbra::scene::SceneDesc {
    let text = r#"Scene(
    camera: (position: CAMERA, look_at: (0, 0.5, 0), fov_deg: 70, width: 47, height: 35),
    settings: (max_depth: 3, background: (0.2, 0.3, 0.4), ambient: (0.1, 0.1, 0.1), seed: 5,
               aa: (samples: 2, pattern: Jittered)),
    textures: [(name: "check", kind: Checker(a: (1, 1, 1), b: (0.2, 0.2, 0.2)), scale: (0.5, 0.5))],
    materials: [
        (name: "matte", kd: (0.7, 0.6, 0.5), ks: 0),
        (name: "fractional", kd: (0.2, 0.5, 0.8), ks: 0.5, shininess: 37.5),
        (name: "tight", kd: (0.8, 0.2, 0.2), ks: 0.7, shininess: 10000),
        (name: "glow", kd: (0.1, 0.1, 0.1), ks: 0.2, shininess: 3, emission: (0.5, 0.2, 0)),
        (name: "mirror", kd: (0.1, 0.1, 0.1), ks: 0.4, shininess: 80, kr: 0.6),
        (name: "glass", kd: (0, 0, 0), ks: 0.5, shininess: 120, kt: 0.9, ior: 1.5, fresnel: true,
         absorption: (0.1, 0.2, 0.3)),
        (name: "floor", kd: (0.9, 0.9, 0.9), kd_texture: "check", ks: 0.1, shininess: 20),
    ],
    lights: [
        Point(position: (-4, 6, -3), colour: (1, 1, 1), intensity: 0.6),
        Point(position: (2, 3, -2), colour: (1, 0.8, 0.6), intensity: 5, falloff: InverseSquare),
        Spot(position: (0, 5, -4), look_at: (0, 0, 0), cone_deg: 25, soft_deg: 8, colour: (0.6, 0.8, 1),
             intensity: 0.8),
        Directional(direction: (0.3, -1, 0.2), colour: (0.5, 0.5, 0.5), intensity: 0.4),
        Point(position: (1, 0.8, 1.5), colour: (0.3, 0.3, 0.2), intensity: 0.5),
    ],
    objects: [
        (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor"),
        (shape: Sphere(centre: (-2, 0.8, 0), radius: 0.8), material: "matte"),
        (shape: Sphere(centre: (0, 0.8, 0), radius: 0.8), material: "fractional"),
        (shape: Sphere(centre: (2, 0.8, 0), radius: 0.8), material: "tight"),
        (shape: Sphere(centre: (-1, 0.4, -1.5), radius: 0.4), material: "glow"),
        (shape: Sphere(centre: (1, 0.5, -1.5), radius: 0.5), material: "mirror"),
        (shape: Box(min: (-0.4, 0, -3), max: (0.4, 0.8, -2.2)), material: "matte"),
        (shape: Sphere(centre: (-4, 1.5, -5), radius: 1.5), material: "glass"),
    ],
)"#;
    penumbra::scene::parse_scene(&text.replace("CAMERA", camera), "local.ron").expect("test scene is valid")
}

/// The lanes of a camera packet whose hit is lit by its own light alone are shaded together
/// (the lights' directions, falloffs, Phong brackets and sums in vectors; the direct light of
/// lanes that bounce too): at every SIMD level the film has the single rays' bits and the same
/// rays are counted, from outside the glass and from inside it (where every camera hit is left
/// to the single-lane path, its light absorbed on the way in).
#[test]
fn lanes_shaded_together_give_the_single_rays_bits() {
    for camera in ["(0, 3, -9)", "(-4, 1.5, -5)"] {
        let desc = local_shading_scene(camera);
        let mut world: penumbra::world::SceneWorld = penumbra::scene::spawn_world(&desc);
        let snapshot = world.update();
        let base = world.render_settings();
        let render = |simd| {
            let (film, stats) =
                penumbra::trace::render(&snapshot, &penumbra::trace::RenderSettings { simd, ..base });
            (film.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect::<Vec<_>>(), stats.rays)
        };
        let (want, rays) = render(SimdLevel::Scalar);
        assert!(rays.shadow > 4 * rays.camera && rays.reflection > 0 && rays.refraction > 0, "{rays:?}");
        for simd in
            [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512].into_iter().filter(|l| l.available())
        {
            let (got, counted) = render(simd);
            let differ = want.chunks(3).zip(got.chunks(3)).filter(|(a, b)| a != b).count();
            assert_eq!(differ, 0, "camera {camera}, {simd}: pixels differ from single rays");
            // By kind (packets walk the grid in other steps, so cells and tests differ).
            let kinds = |r: &penumbra::trace::stats::RayCounts| {
                [r.camera, r.shadow, r.area_shadow, r.reflection, r.glossy, r.refraction, r.blurry]
            };
            assert_eq!(kinds(&counted), kinds(&rays), "camera {camera}, {simd}: rays counted");
            assert_eq!(counted.budget, rays.budget, "camera {camera}, {simd}: ray budget");
        }
    }
}
