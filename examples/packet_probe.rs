//! One thread's packet throughput on a mesh scene, for profiling: the camera rays of
//! ANCHORS.md's mesh scene (640×480, one per pixel) traced as 4 × 4 pixel packets, or the
//! point-light shadow rays of their hits traced as one packet per block (as the renderer and
//! `benches/layout.rs` group them), at the best SIMD level, on this thread only; the best of
//! `REPS` passes in Mrays/s, and the traversal cost per ray (cells and lane tests) of the
//! packets and, for shadow rays, of the same rays traced alone. Each packet is traced in a
//! function of its own (`camera_packet`, `shadow_packet`) for profilers to select, for example
//! `valgrind --tool=callgrind --toggle-collect='*camera_packet*'`.
//!
//! Run: `cargo run --release --example packet_probe -- bunny camera 5` (model `bunny` or
//! `dragon` from `../shared/models/`, rays `camera` or `shadow`, passes; add `aos` to trace
//! through the array-of-structures store instead, or a SIMD level such as `avx2` to trace at
//! that level instead of the best).

#[path = "../tests/common/mod.rs"]
mod common;
#[path = "../benches/harness/rays.rs"]
mod rays;

use penumbra::math::RayPacket;
use penumbra::simd::SimdLevel;
use penumbra::store::{AosStore, PacketHits, PrimitiveStore, SoaStore, TraversalCost};
use penumbra::trace::packet::{closest_hits, occluded, Origins, LANES};
use penumbra::trace::TraceScene;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let model = args.first().map_or("bunny", String::as_str);
    let shadow = args.get(1).is_some_and(|k| k == "shadow");
    let reps: usize = args.get(2).and_then(|r| r.parse().ok()).unwrap_or(5);
    // An argument naming a level (`avx2`, `baseline`, ...) overrides the best one.
    let level = args.iter().find_map(|a| a.parse::<SimdLevel>().ok()).unwrap_or(SimdLevel::Auto).resolve();
    if args.iter().any(|a| a == "aos") {
        probe::<AosStore>(model, shadow, reps, level)
    } else {
        probe::<SoaStore>(model, shadow, reps, level)
    }
}

fn probe<S: PrimitiveStore>(model: &str, shadow: bool, reps: usize, level: SimdLevel) {
    let Some(path) = common::shared_model(&format!("{model}.obj")) else {
        eprintln!("packet_probe: ../shared/models/{model}.obj not found");
        return;
    };
    let mesh = common::mesh_asset(&path, penumbra::accel::MESH_LAMBDA);
    let scene: TraceScene<S> = common::mesh_scene(mesh, penumbra::accel::DEFAULT_LAMBDA);
    let (w, h) = (640u32, 480u32);
    let set = rays::ray_set(&scene, w, h, common::MESH_LIGHT);
    // The packets, filled once: camera rays by 4 × 4 pixel block, shadow rays by the block of
    // their camera ray's pixel.
    let packets: Vec<RayPacket<LANES>> = if shadow {
        let mut packets = Vec::new();
        let mut start = 0;
        for i in 1..=set.shadow.len() {
            if i == set.shadow.len() || set.shadow_block[i] != set.shadow_block[start] {
                let mut p = RayPacket::default();
                for (lane, (ray, t_max)) in set.shadow[start..i].iter().enumerate() {
                    p.set(lane, ray, 0.0, *t_max);
                }
                packets.push(p);
                start = i;
            }
        }
        packets
    } else {
        let mut packets = Vec::new();
        for by in (0..h).step_by(4) {
            for bx in (0..w).step_by(4) {
                let mut p = RayPacket::default();
                for lane in 0..LANES as u32 {
                    let pixel = (by + lane / 4) * w + bx + lane % 4;
                    p.set(lane as usize, &set.primary[pixel as usize], 0.0, f32::INFINITY);
                }
                packets.push(p);
            }
        }
        packets
    };
    let rays = if shadow { set.shadow.len() } else { set.primary.len() };
    let mut best = f64::INFINITY;
    let mut cost = TraversalCost::default();
    let mut found = 0;
    for rep in 0..reps.max(1) {
        let mut c = TraversalCost::default();
        let mut n = 0;
        let started = std::time::Instant::now();
        for p in &packets {
            n += if shadow {
                shadow_packet(&scene, p, level, &mut c).iter().filter(|&&b| b).count()
            } else {
                camera_packet(&scene, p, level, &mut c).hit.iter().filter(|h| h.is_some()).count()
            };
        }
        best = best.min(started.elapsed().as_secs_f64());
        if rep == 0 {
            (cost, found) = (c, n);
        }
    }
    let per_ray = |n: u32| f64::from(n) / rays as f64;
    println!(
        "{model} {}: {rays} rays, {found} {}, packets of {LANES} at {level}, one thread: {:.2} Mrays/s; \
         per ray {:.2} cells, {:.1} lane tests",
        if shadow { "shadow" } else { "camera" },
        if shadow { "blocked" } else { "hit" },
        rays as f64 / best / 1e6,
        per_ray(cost.cells),
        per_ray(cost.tests),
    );
    if shadow {
        let mut alone = TraversalCost::default();
        for (ray, t_max) in &set.shadow {
            penumbra::trace::visibility::transmittance_tallied(&scene, ray, *t_max, &mut alone);
        }
        println!(
            "the same rays alone: per ray {:.2} cells, {:.1} tests",
            per_ray(alone.cells),
            per_ray(alone.tests)
        );
    }
}

/// One camera packet's nearest hits.
#[inline(never)]
fn camera_packet<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    p: &RayPacket<LANES>,
    level: SimdLevel,
    cost: &mut TraversalCost,
) -> PacketHits<LANES> {
    level.run(
        #[inline(always)]
        || closest_hits(scene, p, cost),
    )
}

/// One shadow packet's blocked lanes.
#[inline(never)]
fn shadow_packet<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    p: &RayPacket<LANES>,
    level: SimdLevel,
    cost: &mut TraversalCost,
) -> [bool; LANES] {
    level.run(
        #[inline(always)]
        || occluded(scene, p, Origins::Apart, cost),
    )
}
