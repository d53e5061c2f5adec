//! The Whitted integrator with distribution effects: radiance along a ray, from direct light
//! ([`super::phong`]) and recursive mirror or glossy reflection and sharp or blurry
//! refraction. What a ray hits and what a shadow ray lets through are asked of
//! [`super::visibility`]; the path's limits and samples are carried in a `PathContext`.

use super::path::{CameraSample, PathContext};
use super::phong::{direct_light, Surface};
use super::scene::TraceScene;
use super::settings::RenderSettings;
use super::stats::RayCounts;
pub use super::surface::{facing_normals, ShadingPoint};
use super::visibility::closest_hit_at;
use crate::math::{reflect, refract, Ray, Vec3};
use crate::sample::rng::SampleKey;
use crate::sample::warp::cone;
use crate::store::{Hit, PrimitiveStore, TraversalCost};

/// Largest cone half-angle, reached at glossiness 1: 45°.
pub const MAX_GLOSSY_ANGLE: f32 = std::f32::consts::FRAC_PI_4;

/// Radiance arriving along a single `ray` (a unit direction) from a scene rendered with
/// `settings`: the path of a pixel's only camera sample, with the settings' depth, glossy
/// samples and ray budget, and the first sample key of frame `settings.frame`. For probing a
/// scene ray by ray; [`super::render()`] renders whole images.
///
/// ```
/// use penumbra::prelude::*;
/// use penumbra::trace::trace_ray;
/// let mut world: SceneWorld = spawn_world(&default_scene());
/// let snapshot = world.update();
/// let camera = &snapshot.camera;
/// let ray = Ray::new(camera.position, camera.forward);
/// let radiance = trace_ray(&snapshot, &world.render_settings(), &ray);
/// assert!(radiance.is_finite());
/// ```
pub fn trace_ray<S: PrimitiveStore>(scene: &TraceScene<S>, settings: &RenderSettings, ray: &Ray) -> Vec3 {
    let mut rays = RayCounts::default();
    let key = SampleKey { seed: settings.seed, frame: settings.frame, ..SampleKey::default() };
    let mut ctx = PathContext::new(settings, CameraSample::single(key), &mut rays);
    let radiance = radiance(scene, ray, 0, 1.0, &mut ctx);
    ctx.finish();
    radiance
}

/// Radiance arriving along `ray`, which already carries path weight `weight` at `depth`.
pub(crate) fn radiance<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    depth: u32,
    weight: f32,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let mut cost = TraversalCost::default();
    let found = closest_hit_at(scene, ray, 0.0, f32::INFINITY, ctx.time, &mut cost);
    radiance_at(scene, ray, found, cost, depth, weight, ctx)
}

/// [`radiance`] for a ray whose nearest hit (`found`, at traversal cost `cost`) is already
/// known: a camera ray traced in a packet.
pub(crate) fn radiance_at<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    found: Option<Hit>,
    cost: TraversalCost,
    depth: u32,
    weight: f32,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    ctx.rays.traversal.record(cost);
    if scene.effects.visible_lights {
        if let Some(seen) = visible_light(scene, ray, found.map_or(f32::INFINITY, |h| h.t)) {
            // A light in front of the hit: what a packet prepared for the hit is not needed.
            ctx.surface_hint = None;
            ctx.shadow_hint = None;
            return seen;
        }
    }
    let Some(hit) = found else {
        return scene.background;
    };
    let ShadingPoint { sp, entering, n, ns, above } = match ctx.surface_hint.take() {
        Some(shading) => shading,
        None => ShadingPoint::new(scene.surface(&hit, ray, ctx.time), ray.dir),
    };
    let (m, ns) = match scene.shade_at(scene.material(sp.material), &hit, sp.point, ns, ctx.time) {
        // A bump may not tilt the normal away from the viewer.
        (m, bumped) if bumped.dot(ray.dir) < 0.0 => (m, bumped),
        (m, _) => (m, ns),
    };
    let surface = Surface { point: sp.point, normal: ns, above, eps: sp.error };
    let mut colour = scene.ambient * m.kd + direct_light(scene, &m, &surface, -ray.dir, ctx);
    if m.emission != Vec3::ZERO {
        colour += m.emission;
    }

    // Beer–Lambert: light reaching a surface from inside its material lost some on the way.
    let absorbed = |colour: Vec3| match entering || m.absorption == Vec3::ZERO {
        true => colour,
        false => colour * (-m.absorption * (hit.t * ray.dir.length())).exp(),
    };
    if depth >= ctx.max_depth {
        return absorbed(colour);
    }
    let (kr, kt) = if m.fresnel {
        m.fresnel_split((-ray.dir.dot(ns) / ray.dir.length()).clamp(0.0, 1.0), entering)
    } else {
        (m.kr, m.kt)
    };
    // The refraction's rays are set aside while the reflection's tree is traced.
    let kt_max = kt.max_element();
    let refracts = kt_max > 0.0 && weight * kt_max >= ctx.min_contribution;
    let pending = match (refracts, m.glossiness > 0.0) {
        (false, _) => 0,
        (true, false) => 1,
        (true, true) => ctx.cone_rays(depth),
    };
    // Mirror or glossy reflection.
    if kr > 0.0 && weight * kr >= ctx.min_contribution {
        ctx.budget.reserve(pending);
        let mirror = match reflect(ray.dir, ns) {
            r if r.dot(n) > 0.0 => r,
            _ => reflect(ray.dir, n),
        };
        if m.glossiness > 0.0 {
            colour += kr
                * scatter(
                    scene,
                    surface.above,
                    mirror,
                    n,
                    m.glossiness,
                    depth,
                    weight * kr,
                    Scatter::Glossy,
                    ctx,
                );
        } else if ctx.budget.grant() {
            ctx.rays.reflection += 1;
            colour += kr * radiance(scene, &Ray::new(surface.above, mirror), depth + 1, weight * kr, ctx);
        }
        ctx.budget.release(pending);
    }
    // Refraction (Snell), or total internal reflection; blurry around that direction.
    if refracts {
        let eta = if entering { 1.0 / m.ior } else { m.ior };
        let bent = refract(ray.dir, ns, eta).filter(|d| d.dot(n) < 0.0);
        let (origin, dir, side) = match bent.or_else(|| refract(ray.dir, n, eta)) {
            Some(dir) => (sp.spawn(-n), dir, -n),
            None => (surface.above, reflect(ray.dir, n), n),
        };
        if m.glossiness > 0.0 {
            colour += kt
                * scatter(
                    scene,
                    origin,
                    dir,
                    side,
                    m.glossiness,
                    depth,
                    weight * kt_max,
                    Scatter::Blurry,
                    ctx,
                );
        } else if ctx.budget.grant() {
            ctx.rays.refraction += 1;
            colour += kt * radiance(scene, &Ray::new(origin, dir), depth + 1, weight * kt_max, ctx);
        }
    }
    absorbed(colour)
}

/// The nearest visible light along `ray` in `(0, t_max)` and the radiance seen there.
#[inline]
fn visible_light<S: PrimitiveStore>(scene: &TraceScene<S>, ray: &Ray, t_max: f32) -> Option<Vec3> {
    let mut nearest = (t_max, None);
    for light in scene.lights.iter().filter(|l| l.is_visible()) {
        if let Some((t, radiance)) = light.hit(ray, nearest.0) {
            nearest = (t, Some(radiance));
        }
    }
    nearest.1
}

/// Which kind of ray a [`scatter`] traces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scatter {
    Glossy,
    Blurry,
}

/// Mean radiance over rays in the cone of half-angle `glossiness × 45°` around `axis`, kept on
/// the `side` of the surface the axis leaves towards (a direction that dips under the surface
/// is mirrored back). The pixel's `glossy.samples` rays at the first bounce, shared among its
/// camera samples; one ray deeper down. Rays the budget refuses are left out of the mean (no
/// ray traced: black, as past `max_depth`).
#[allow(clippy::too_many_arguments)]
fn scatter<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    origin: Vec3,
    axis: Vec3,
    side: Vec3,
    glossiness: f32,
    depth: u32,
    weight: f32,
    kind: Scatter,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let pattern = ctx.glossy.pattern;
    let half_angle = glossiness * MAX_GLOSSY_ANGLE;
    // The per-pixel budget at the first bounce; a single ray (its own stratum of 1) deeper down.
    let n = if depth == 0 { ctx.glossy.samples } else { 1 };
    let samples = ctx.effect_samples(n, pattern);
    debug_assert_eq!(samples.taken(), ctx.cone_rays(depth), "the rays set aside for a cone");
    // The cone's later rays are set aside while each earlier ray's tree is traced.
    ctx.budget.reserve(samples.taken());
    let mut traced = 0u32;
    let mut sum = Vec3::ZERO;
    for st in samples {
        ctx.budget.release(1);
        if !ctx.budget.grant() {
            continue;
        }
        traced += 1;
        let mut dir = cone(axis, half_angle, st);
        let below = dir.dot(side);
        if below <= 0.0 {
            dir = (dir - 2.0 * below * side).normalize();
        }
        match kind {
            Scatter::Glossy => ctx.rays.glossy += 1,
            Scatter::Blurry => ctx.rays.blurry += 1,
        }
        sum += radiance(scene, &Ray::new(origin, dir), depth + 1, weight, ctx);
    }
    if traced == 0 {
        return Vec3::ZERO;
    }
    sum / traced as f32
}
