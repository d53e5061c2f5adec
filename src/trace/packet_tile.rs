//! Tiles traced in packets: camera rays of a pixel block found together, and the shadow rays
//! of their hits towards point and directional lights traced together; the same bits as
//! single rays.

use super::camera_samples::{trace_camera_ray, CameraSampler};
use super::finite::SampleMean;
use super::integrator::{bounce, visible_light, Lit, ShadingPoint};
use super::local::shade_local;
use super::packet::{closest_hits, shadow_passes, Origins, LANES, MIN_LANES};
use super::path::{CameraSample, PathContext, ShadowHint, HINTED_LIGHTS};
use super::phong::{direct_light, point_lights};
use super::scene::TraceScene;
use super::settings::RenderSettings;
use super::stats::RayCounts;
use super::tiles::TileOut;
use crate::math::{Ray, RayPacket, Vec2, Vec3, SHADOW_EPSILON};
use crate::simd::SimdLevel;
use crate::store::{Hit, PrimitiveStore, TraversalCost};

/// Width and height in pixels of the block whose camera rays form one packet.
pub(super) const BLOCK: [u32; 2] = [4, 4];

/// A tile traced in packets: each block of [`BLOCK`] pixels sends its camera samples as one
/// packet per sample index, finds their first hits together ([`closest_hits`], compiled for
/// `level`), and shades each lane on its own. Every pixel accumulates its samples in the same
/// order as [`super::camera_samples::fixed_pixel`], from the same hits, so the image is the same bits.
pub(super) fn packet_tile<S: PrimitiveStore>(
    sampler: &CameraSampler<'_, S>,
    level: SimdLevel,
    [x0, y0, x1, y1]: [u32; 4],
    rays: &mut RayCounts,
    out: &mut TileOut,
) {
    const { assert!((BLOCK[0] * BLOCK[1]) as usize == LANES) };
    let tw = x1 - x0;
    out.pixels.resize(((y1 - y0) * tw) as usize, (Vec3::ZERO, 0));
    let n = sampler.n;
    // Packets are traced for pinhole cameras that do not move ([`camera_packets`]).
    let camera = &sampler.scene.camera;
    let (width, height) = (sampler.settings.width, sampler.settings.height);
    for by in (y0..y1).step_by(BLOCK[1] as usize) {
        for bx in (x0..x1).step_by(BLOCK[0] as usize) {
            let mut means = [SampleMean::default(); LANES];
            let pixel = |lane: usize| {
                let (x, y) = (bx + lane as u32 % BLOCK[0], by + lane as u32 / BLOCK[0]);
                (x < x1 && y < y1).then_some((x, y))
            };
            for sample in 0..n {
                let mut points = [Vec2::ZERO; LANES];
                let mut cameras = [None; LANES];
                for (lane, camera) in cameras.iter_mut().enumerate() {
                    if let Some((x, y)) = pixel(lane) {
                        let (point, key) = sampler.image_point(x, y, sample, rays);
                        (points[lane], *camera) = (point, Some(key));
                    }
                }
                let active = cameras.map(|c| c.is_some());
                let packet = level.run(
                    #[inline(always)]
                    || camera.pinhole_lanes(&points, &active, width, height),
                );
                let colours = shade_packet((sampler.scene, sampler.settings), level, &packet, &cameras, rays);
                for (mean, colour) in means.iter_mut().zip(colours) {
                    if let Some(colour) = colour {
                        mean.add(colour);
                    }
                }
            }
            for (lane, mean) in means.iter().enumerate() {
                if let Some((x, y)) = pixel(lane) {
                    out.pixels[((y - y0) * tw + x - x0) as usize] = (mean.mean(), mean.dropped());
                }
            }
        }
    }
}

/// A tile of a lens camera that does not move: each pixel's lens samples (up to [`LANES`] at a
/// time, in sample order) are made together, lane by lane ([`CameraSampler::lens_lanes`]:
/// strata, hashes and jitters share vector instructions), and traced as one packet where a
/// pixel takes at least [`MIN_LENS_LANES`], else one ray at a time. A pixel's samples leave the
/// aperture and pass through its footprint on the plane in focus, so its packet converges on a
/// small patch: a frustum as narrow as the aperture, walked together ([`closest_hits`]); a
/// block of pixels with one sample each would not be (each lane's lens point differs). Every
/// lane is shaded as [`shade_packet`] shades a pinhole lane (or traced as
/// [`super::camera_samples::fixed_pixel`] traces it), and each pixel adds its samples in sample
/// order, as `fixed_pixel` does: the same bits.
pub(super) fn lens_tile<S: PrimitiveStore>(
    sampler: &CameraSampler<'_, S>,
    level: SimdLevel,
    [x0, y0, x1, y1]: [u32; 4],
    rays: &mut RayCounts,
    out: &mut TileOut,
) {
    out.pixels.reserve(((y1 - y0) * (x1 - x0)) as usize);
    let n = sampler.n;
    let (scene, settings) = (sampler.scene, sampler.settings);
    for y in y0..y1 {
        for x in x0..x1 {
            let mut mean = SampleMean::default();
            if n as usize >= MIN_LENS_LANES {
                for first in (0..n).step_by(LANES) {
                    let count = (n - first).min(LANES as u32) as usize;
                    // Lens cameras that do not move ([`lens_packets`]): every time is 0.
                    let (packet, cameras) = level.run(
                        #[inline(always)]
                        || {
                            let (mut packet, cameras) = sampler.lens_lanes(x, y, first, count, rays);
                            packet.reciprocals();
                            (packet, cameras)
                        },
                    );
                    let colours = shade_packet((scene, settings), level, &packet, &cameras, rays);
                    for colour in colours.into_iter().flatten() {
                        mean.add(colour);
                    }
                }
            } else {
                // Fewer than `MIN_LENS_LANES`: made in one narrower set of lanes, traced alone.
                let (lanes, cameras) = level.run(
                    #[inline(always)]
                    || sampler.lens_lanes::<MIN_LENS_LANES>(x, y, 0, n as usize, rays),
                );
                for (lane, camera) in cameras.iter().enumerate() {
                    if let Some(camera) = *camera {
                        mean.add(trace_camera_ray(scene, settings, &lanes.ray(lane), camera, 0.0, rays));
                    }
                }
            }
            out.pixels.push((mean.mean(), mean.dropped()));
        }
    }
}

/// Fewest lens samples of one pixel (or adaptive lattice point) worth tracing as a packet;
/// fewer go as single rays ([`lens_tile`] still makes a pixel's samples together). A lens
/// packet walks and tests all [`LANES`] lanes however few are active: measured on variants of
/// `flythrough` (1 thread, one binary), packets ran 1.18× slower than single rays at 6
/// samples, and 1.06×, 1.18× and 1.31× faster at 8, 12 and 16; `effects_dof` (16) 1.48× faster.
pub(super) const MIN_LENS_LANES: usize = LANES / 2;

/// The level a lens camera's samples are traced in packets at, where they are: `None` for
/// single rays. As [`camera_packets`], but for a lens camera that does not move. The samples
/// of one pixel ([`lens_tile`]) or one adaptive lattice point go together where there are at
/// least [`MIN_LENS_LANES`] of them.
pub(super) fn lens_packets<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    want_cost: bool,
) -> Option<SimdLevel> {
    (settings.simd.packets() && !want_cost && scene.camera.has_lens() && scene.motion.is_none())
        .then(|| settings.simd.resolve())
}

/// The level camera rays are traced in packets at, where they are: `None` for single rays.
/// Packets need no per-pixel ray counts; the cost AOV (`want_cost`), which does, traces single
/// rays. So do lens cameras here: each lane's lens point differs, so a block's rays do not
/// form a frustum worth walking (measured: 20 % slower on effects_dof); a pixel's own lens
/// samples do ([`lens_tile`]). Motion
/// blur gives every lane its own time: single rays. Fixed and noise-driven renders both ask here.
pub(super) fn camera_packets<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    want_cost: bool,
) -> Option<SimdLevel> {
    (settings.simd.packets() && !want_cost && !scene.camera.has_lens() && scene.motion.is_none())
        .then(|| settings.simd.resolve())
}

/// Traces a packet of camera rays (`packet`, whose lane holds a ray where `cameras` holds its
/// camera sample): their first hits found together ([`closest_hits`], compiled for `level`),
/// the shadow rays of those hits towards point and directional lights traced together, and
/// each lane shaded on its own from its hit. Each lane's radiance, the same bits as the lane's
/// ray traced alone ([`radiance_at`](super::integrator::radiance_at)).
///
/// In a scene lit only by point, spot and directional lights, the lanes' direct light is found
/// together where their material has no textures ([`shade_local`]), and a lane whose hit
/// sends no reflected or refracted ray is finished there: its direct light from the packet's
/// shadow rays, plus ambient and emission ([`Lit::local`]).
#[inline]
pub(super) fn shade_packet<S: PrimitiveStore>(
    (scene, settings): (&TraceScene<S>, &RenderSettings),
    level: SimdLevel,
    packet: &RayPacket<LANES>,
    cameras: &[Option<CameraSample>; LANES],
    rays: &mut RayCounts,
) -> [Option<Vec3>; LANES] {
    let mut cost = TraversalCost::default();
    let hits = level.run(
        #[inline(always)]
        || closest_hits(scene, packet, &mut cost),
    );
    let lane_cost = cost.per_ray(cameras.iter().flatten().count() as u32);
    // Each hit's surface, found once: the shadow packets start from it, and so does the lane's
    // shading. Lanes are built and shaded in loops writing in place, not by `array::from_fn`:
    // that returned each lane's value through a temporary read back at once with wider loads
    // than its stores, a store the CPU could not forward.
    let mut surfaces: [Option<ShadingPoint>; LANES] = [None; LANES];
    for (lane, surface) in surfaces.iter_mut().enumerate() {
        if let Some(hit) = hits.hit[lane] {
            let ray = packet.ray(lane);
            *surface = Some(ShadingPoint::new(scene.store.surface(&hit, &ray), ray.dir));
        }
    }
    let hints = point_light_shadows(scene, &surfaces, level, rays);
    let local = shade_local((scene, settings), level, packet, cameras, &hits.hit, &surfaces, &hints, rays);
    let mut colours = [None; LANES];
    for (lane, colour) in colours.iter_mut().enumerate() {
        if let Some(camera) = cameras[lane] {
            rays.traversal.record(lane_cost);
            if local.done[lane] {
                *colour = Some(local.colour[lane]);
                continue;
            }
            *colour = Some(shade_lane(
                (scene, settings),
                packet.ray(lane),
                hits.hit[lane],
                camera,
                (&surfaces[lane], hints[lane].as_ref(), local.lit[lane].then_some(local.direct[lane])),
                rays,
            ));
        }
    }
    colours
}

/// One lane of [`shade_packet`]: the radiance along camera ray `ray` from its first hit `hit`,
/// whose shading point is `shading`, with the packet's shadow rays' transmittances `hint`, and
/// its direct light where it was found with other lanes' (`lit`: [`shade_local`]).
#[inline(always)]
fn shade_lane<S: PrimitiveStore>(
    (scene, settings): (&TraceScene<S>, &RenderSettings),
    ray: Ray,
    hit: Option<Hit>,
    camera: CameraSample,
    (shading, hint, lit_by): (&Option<ShadingPoint>, Option<&ShadowHint>, Option<Vec3>),
    rays: &mut RayCounts,
) -> Vec3 {
    if scene.effects.visible_lights {
        if let Some(seen) = visible_light(scene, &ray, hit.map_or(f32::INFINITY, |h| h.t)) {
            rays.budget.record(0, 0);
            return seen;
        }
    }
    // The shading point is read in place: a copy made here, read back at once with other
    // widths, was a store the CPU could not forward.
    let (Some(hit), Some(shading)) = (hit, shading) else {
        rays.budget.record(0, 0);
        return scene.background;
    };
    let lit = Lit::new(scene, &hit, &ray, shading, 0.0);
    let view = -ray.dir;
    // No light is sampled: direct light needs no path context ([`point_lights`]).
    let point_lit = !scene.effects.area_lights;
    let direct = point_lit
        .then(|| lit_by.unwrap_or_else(|| point_lights(scene, &lit.m, &lit.surface, view, hint, rays)));
    if let Some(direct) =
        direct.filter(|_| !lit.bounces(&ray, 0, 1.0, settings.max_depth, settings.min_contribution))
    {
        rays.budget.record(0, 0);
        return lit.local(scene, &ray, &hit, direct);
    }
    let mut ctx = PathContext::new(settings, camera, rays);
    let direct = match direct {
        Some(direct) => direct,
        None => {
            ctx.shadow_hint = hint.copied();
            direct_light(scene, &lit.m, &lit.surface, view, &mut ctx)
        }
    };
    let colour = bounce(scene, &ray, &hit, &lit, direct, 0, 1.0, &mut ctx);
    ctx.finish();
    colour
}

/// The shadow rays from a packet's camera hits towards each of the first [`HINTED_LIGHTS`]
/// point or directional lights, traced as one packet per light (a common end point, or a
/// common direction): per lane, the transmittance [`super::phong::direct_light`] would find,
/// computed from the same shading point (`surfaces`: each camera hit's, as `radiance_at` sees
/// it).
pub(super) fn point_light_shadows<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    surfaces: &[Option<ShadingPoint>; LANES],
    level: SimdLevel,
    rays: &mut RayCounts,
) -> [Option<ShadowHint>; LANES] {
    let mut hints = [None; LANES];
    let lights = scene.lights.iter().enumerate().take(HINTED_LIGHTS).filter(|(_, l)| !l.is_area());
    if scene.lights.iter().take(HINTED_LIGHTS).all(|l| l.is_area()) {
        return hints;
    }
    for (j, light) in lights {
        let mut shadow = RayPacket::<LANES>::default();
        let mut lanes = 0;
        for (lane, surface) in surfaces.iter().enumerate() {
            let Some(ShadingPoint { sp, ns, above, .. }) = *surface else { continue };
            let (to_light, dist, _) = light.towards(sp.point);
            if ns.dot(to_light) <= 0.0 {
                continue;
            }
            shadow.set(lane, &Ray::new(above, to_light), 0.0, dist * (1.0 - SHADOW_EPSILON));
            lanes += 1;
        }
        if (lanes as usize) < MIN_LANES {
            // Too few to pay for a packet: `direct_light` traces them alone.
            continue;
        }
        let mut cost = TraversalCost::default();
        let pass = level.run(
            #[inline(always)]
            || shadow_passes(scene, &shadow, Origins::Apart, &mut cost),
        );
        rays.traversal.record_many(cost.per_ray(lanes), u64::from(lanes));
        for lane in 0..LANES {
            if shadow.active[lane] {
                let hint = hints[lane].get_or_insert([None; HINTED_LIGHTS]);
                hint[j] = Some(pass[lane]);
            }
        }
    }
    hints
}
