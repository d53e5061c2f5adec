//! Fixed ray sets for the mesh benches: one camera ray per pixel centre, and one shadow ray
//! from each camera ray's hit towards a point light; traced in parallel (both cores, as the
//! anchors' "2T" figures are).

#![allow(dead_code)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use penumbra::math::{Ray, Vec3, SHADOW_EPSILON};
use penumbra::simd::{with_single_ray_level, SimdLevel};
use penumbra::store::PrimitiveStore;
use penumbra::trace::{closest_hit, transmittance, TraceScene};
use rayon::prelude::*;

/// Camera rays and the shadow rays of their hits (with their lengths).
pub struct RaySet {
    /// One per pixel, in pixel order.
    pub primary: Vec<Ray>,
    /// One per primary hit: towards the light, with the distance to stop at; grouped by 4 × 4
    /// pixel block (blocks in raster order, pixels in raster order within them), as the
    /// renderer groups a packet of camera hits.
    pub shadow: Vec<(Ray, f32)>,
    /// The 4 × 4 block of each shadow ray's pixel.
    pub shadow_block: Vec<u32>,
}

/// The rays of a `w × h` image of `scene` lit from `light`.
pub fn ray_set<S: PrimitiveStore>(scene: &TraceScene<S>, w: u32, h: u32, light: Vec3) -> RaySet {
    let primary: Vec<Ray> =
        (0..w * h).map(|p| scene.camera.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5, w, h)).collect();
    let blocks_x = w.div_ceil(4);
    let mut order: Vec<u32> = (0..w * h).collect();
    order.sort_by_key(|&p| ((p / w / 4) * blocks_x + p % w / 4, p));
    let (shadow, shadow_block) = order
        .iter()
        .filter_map(|&p| {
            let ray = &primary[p as usize];
            let hit = closest_hit(scene, ray, 0.0, f32::INFINITY)?;
            let sp = scene.store.surface(&hit, ray);
            let n = if sp.normal.dot(ray.dir) < 0.0 { sp.normal } else { -sp.normal };
            let to = light - sp.point;
            let dist = to.length();
            let block = (p / w / 4) * blocks_x + p % w / 4;
            Some(((Ray::new(sp.spawn(n), to / dist), dist * (1.0 - SHADOW_EPSILON)), block))
        })
        .unzip();
    RaySet { primary, shadow, shadow_block }
}

/// Closest hits of every ray; returns the number of hits.
pub fn trace_primary<S: PrimitiveStore>(scene: &TraceScene<S>, rays: &[Ray]) -> usize {
    trace_primary_at(scene, rays, SimdLevel::Auto)
}

/// [`trace_primary`] with the single-ray kernels at `level` (`Scalar`: one primitive at a time).
pub fn trace_primary_at<S: PrimitiveStore>(scene: &TraceScene<S>, rays: &[Ray], level: SimdLevel) -> usize {
    rays.par_chunks(256)
        .map(|c| {
            with_single_ray_level(level, || {
                c.iter().filter(|r| closest_hit(scene, black_box(r), 0.0, f32::INFINITY).is_some()).count()
            })
        })
        .sum()
}

/// Closest hits of an image's camera rays (`w × h`, row-major) traced as packets of 4 × 4
/// neighbouring pixels at SIMD `level`, bands of 16 rows in parallel; returns the number of hits.
pub fn trace_primary_packets<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    rays: &[Ray],
    w: u32,
    level: penumbra::simd::SimdLevel,
) -> usize {
    use penumbra::math::RayPacket;
    use penumbra::trace::packet::{closest_hits, LANES};
    let h = rays.len() as u32 / w;
    (0..h.div_ceil(16))
        .into_par_iter()
        .map(|band| {
            let mut found = 0;
            for by in (band * 16..(band * 16 + 16).min(h)).step_by(4) {
                for bx in (0..w).step_by(4) {
                    let mut p = RayPacket::<LANES>::default();
                    for lane in 0..LANES {
                        let (x, y) = (bx + lane as u32 % 4, by + lane as u32 / 4);
                        if x < w && y < h {
                            p.set(lane, black_box(&rays[(y * w + x) as usize]), 0.0, f32::INFINITY);
                        }
                    }
                    let hits = level.run(
                        #[inline(always)]
                        || closest_hits(scene, &p, &mut Default::default()),
                    );
                    found += hits.hit.iter().filter(|h| h.is_some()).count();
                }
            }
            found
        })
        .sum()
}

/// Shadow tests of an image's point-light shadow rays (one per camera hit, as [`ray_set`]
/// makes them), each 4 × 4 pixel block's rays traced as one packet towards the common light at
/// SIMD `level`, as the renderer traces them; returns the number of occluded rays.
pub fn trace_shadow_packets<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    rays: &[(Ray, f32)],
    blocks: &[u32],
    level: penumbra::simd::SimdLevel,
) -> usize {
    use penumbra::math::RayPacket;
    use penumbra::trace::packet::{occluded, LANES};
    let groups: Vec<&[(Ray, f32)]> = {
        let mut groups = Vec::new();
        let mut start = 0;
        for i in 1..=rays.len() {
            if i == rays.len() || blocks[i] != blocks[start] {
                groups.push(&rays[start..i]);
                start = i;
            }
        }
        groups
    };
    groups
        .par_chunks(16)
        .map(|chunk| {
            let mut blocked = 0;
            for group in chunk {
                debug_assert!(group.len() <= LANES);
                let mut p = RayPacket::<LANES>::default();
                for (lane, (ray, t_max)) in group.iter().enumerate() {
                    p.set(lane, black_box(ray), 0.0, *t_max);
                }
                let hit = level.run(
                    #[inline(always)]
                    || occluded(scene, &p, penumbra::trace::packet::Origins::Apart, &mut Default::default()),
                );
                blocked += hit.iter().filter(|&&b| b).count();
            }
            blocked
        })
        .sum()
}

/// Shadow tests of every ray; returns the number of occluded rays.
pub fn trace_shadow<S: PrimitiveStore>(scene: &TraceScene<S>, rays: &[(Ray, f32)]) -> usize {
    trace_shadow_at(scene, rays, SimdLevel::Auto)
}

/// [`trace_shadow`] with the single-ray kernels at `level` (`Scalar`: one primitive at a time).
pub fn trace_shadow_at<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    rays: &[(Ray, f32)],
    level: SimdLevel,
) -> usize {
    rays.par_chunks(256)
        .map(|c| {
            with_single_ray_level(level, || {
                c.iter()
                    .filter(|(r, t)| transmittance(scene, black_box(r), *t) == penumbra::math::Vec3::ZERO)
                    .count()
            })
        })
        .sum()
}

/// Median of `reps` timings of `f`.
pub fn median<T>(reps: usize, mut f: impl FnMut() -> T) -> Duration {
    let mut times: Vec<Duration> = (0..reps)
        .map(|_| {
            let started = Instant::now();
            black_box(f());
            started.elapsed()
        })
        .collect();
    times.sort();
    times[reps / 2]
}

/// Million rays per second.
pub fn mrays(rays: usize, t: Duration) -> f64 {
    rays as f64 / t.as_secs_f64() / 1e6
}
