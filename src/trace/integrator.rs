//! The Whitted integrator with distribution effects: radiance along a ray, from direct light
//! ([`super::phong`]) and recursive mirror or glossy reflection and sharp or blurry
//! refraction. What a ray hits and what a shadow ray lets through are asked of
//! [`super::visibility`]; the path's limits and samples are carried in a `PathContext`.

use super::material::Material;
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
            return seen;
        }
    }
    let Some(hit) = found else {
        return scene.background;
    };
    let shading = ShadingPoint::new(scene.surface(&hit, ray, ctx.time), ray.dir);
    let lit = Lit::new(scene, &hit, ray, &shading, ctx.time);
    let direct = direct_light(scene, &lit.m, &lit.surface, -ray.dir, ctx);
    bounce(scene, ray, &hit, &lit, direct, depth, weight, ctx)
}

/// A hit ready to be shaded: its shading point, its material with textures applied, and the
/// surface lights see (the shading normal bumped where the material has a bump map and the
/// bump does not tilt it away from the viewer).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lit<'a> {
    /// The hit seen from the side its ray arrived on.
    pub shading: &'a ShadingPoint,
    /// The material at the hit.
    pub m: Material,
    /// What direct light is computed on.
    pub surface: Surface,
}

impl<'a> Lit<'a> {
    /// The hit `hit` of `ray`, seen as `shading`, at time `time`.
    #[inline]
    pub fn new<S: PrimitiveStore>(
        scene: &TraceScene<S>,
        hit: &Hit,
        ray: &Ray,
        shading: &'a ShadingPoint,
        time: f32,
    ) -> Self {
        let ShadingPoint { sp, ns, above, .. } = *shading;
        let material = scene.material(sp.material);
        let (m, bumped) = scene.shade_at(material, hit, sp.point, ns, time);
        // A bump may not tilt the normal away from the viewer. Untextured (`bumped` is `ns`),
        // `ns` is taken as it is: read back from `shade_at`'s result, its y and z came in one
        // load across the two stores that wrote them, a stall the CPU cannot forward.
        let ns = if !material.maps.is_empty() && bumped.dot(ray.dir) < 0.0 { bumped } else { ns };
        Self { shading, m, surface: Surface { point: sp.point, normal: ns, above, eps: sp.error } }
    }

    /// The shares of reflected and transmitted light for `ray`.
    #[inline]
    fn split(&self, ray: &Ray) -> (f32, Vec3) {
        split(&self.m, self.surface.normal, self.shading.entering, ray)
    }

    /// Whether [`bounce`] traces a reflected or refracted ray from this hit of `ray` at `depth`
    /// on a path of weight `weight`: where it does not, the hit's colour is [`Lit::local`].
    #[inline]
    pub fn bounces(&self, ray: &Ray, depth: u32, weight: f32, max_depth: u32, min_contribution: f32) -> bool {
        let on = (&self.m, self.surface.normal, self.shading.entering);
        bounces(on, ray, depth, weight, max_depth, min_contribution)
    }

    /// The colour of this hit of `ray` from its own light alone: ambient, `direct` and emission,
    /// less what its material absorbed on the way in (Beer–Lambert: light reaching a surface
    /// from inside its material lost some on the way).
    #[inline]
    pub fn local<S: PrimitiveStore>(
        &self,
        scene: &TraceScene<S>,
        ray: &Ray,
        hit: &Hit,
        direct: Vec3,
    ) -> Vec3 {
        self.absorbed(ray, hit, self.own(scene, direct))
    }

    /// Ambient, `direct` and emission.
    #[inline]
    fn own<S: PrimitiveStore>(&self, scene: &TraceScene<S>, direct: Vec3) -> Vec3 {
        own_light(scene.ambient, self.m.kd, direct, self.m.emission)
    }

    /// `colour` less what the material absorbed on the way in, where the ray travelled inside it.
    #[inline]
    fn absorbed(&self, ray: &Ray, hit: &Hit, colour: Vec3) -> Vec3 {
        match self.shading.entering || self.m.absorption == Vec3::ZERO {
            true => colour,
            // `libm`'s `expf`, not the system's: the same bits on every CPU.
            false => {
                colour
                    * Vec3::from_array(
                        (-self.m.absorption * (hit.t * ray.dir.length())).to_array().map(libm::expf),
                    )
            }
        }
    }
}

/// A hit's own light ([`Lit::own`]): `ambient` on its diffuse colour `kd`, its `direct` light and
/// the `emission` of its material, added in that order.
#[inline]
pub(crate) fn own_light(ambient: Vec3, kd: Vec3, direct: Vec3, emission: Vec3) -> Vec3 {
    let mut colour = ambient * kd + direct;
    if emission != Vec3::ZERO {
        colour += emission;
    }
    colour
}

/// The shares of reflected and transmitted light for `ray` meeting material `m` whose normal
/// (facing the ray) is `normal`, arriving on the front side where `entering`.
#[inline]
fn split(m: &Material, normal: Vec3, entering: bool, ray: &Ray) -> (f32, Vec3) {
    if m.fresnel {
        m.fresnel_split((-ray.dir.dot(normal) / ray.dir.length()).clamp(0.0, 1.0), entering)
    } else {
        (m.kr, m.kt)
    }
}

/// [`Lit::bounces`] for a hit on material `m` (textures already applied) with shading normal
/// `normal`, arriving on the front side where `entering`.
#[inline]
pub(crate) fn bounces(
    (m, normal, entering): (&Material, Vec3, bool),
    ray: &Ray,
    depth: u32,
    weight: f32,
    max_depth: u32,
    min_contribution: f32,
) -> bool {
    if depth >= max_depth {
        return false;
    }
    let (kr, kt) = split(m, normal, entering, ray);
    let kt_max = kt.max_element();
    (kr > 0.0 && weight * kr >= min_contribution) || (kt_max > 0.0 && weight * kt_max >= min_contribution)
}

/// The radiance leaving hit `hit` of `ray` towards the ray's origin: [`Lit::local`] (with direct
/// light `direct`) plus the mirror or glossy reflection and the refraction traced from it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn bounce<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    hit: &Hit,
    lit: &Lit,
    direct: Vec3,
    depth: u32,
    weight: f32,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let (m, surface) = (&lit.m, &lit.surface);
    let ShadingPoint { sp, entering, n, .. } = *lit.shading;
    let ns = surface.normal;
    let mut colour = lit.own(scene, direct);
    if depth >= ctx.max_depth {
        return lit.absorbed(ray, hit, colour);
    }
    let (kr, kt) = lit.split(ray);
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
    lit.absorbed(ray, hit, colour)
}

/// The nearest visible light along `ray` in `(0, t_max)` and the radiance seen there.
#[inline]
pub(crate) fn visible_light<S: PrimitiveStore>(scene: &TraceScene<S>, ray: &Ray, t_max: f32) -> Option<Vec3> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prelude::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Where `Lit::bounces` says a hit sends no further ray, `bounce` traces none and
        /// returns `Lit::local` bit for bit (the packet path shades such lanes without a path
        /// context); where it says one is sent, `bounce` traces one.
        #[test]
        fn a_hit_that_does_not_bounce_is_its_local_colour(
            kr in prop_oneof![Just(0.0f32), 0.0f32..1.0],
            kt in prop_oneof![Just(0.0f32), 0.0f32..1.0],
            fresnel: bool,
            absorbing: bool,
            glossiness in prop_oneof![Just(0.0f32), 0.0f32..0.5],
            max_depth in 0u32..3,
            depth in 0u32..3,
            weight in 0.01f32..1.0,
            min_contribution in prop_oneof![Just(0.0f32), 0.0f32..0.5],
            pixel in (0u32..64, 0u32..48),
        ) {
            let mut world: SceneWorld = spawn_world(&default_scene());
            let scene = world.update();
            let settings = RenderSettings { max_depth, min_contribution, ..world.render_settings() };
            let camera = &scene.camera;
            let target = Vec3::new(pixel.0 as f32 / 32.0 - 1.0, 0.75 - pixel.1 as f32 / 32.0, 0.0);
            let ray = Ray::new(camera.position, (camera.forward + camera.right * target.x + camera.up * target.y).normalize());
            let mut cost = TraversalCost::default();
            let Some(hit) = closest_hit_at(&scene, &ray, 0.0, f32::INFINITY, 0.0, &mut cost) else {
                return Ok(());
            };
            let shading = ShadingPoint::new(scene.surface(&hit, &ray, 0.0), ray.dir);
            let mut lit = Lit::new(&scene, &hit, &ray, &shading, 0.0);
            lit.m.kr = kr;
            lit.m.kt = Vec3::splat(kt);
            lit.m.fresnel = fresnel;
            lit.m.glossiness = glossiness;
            lit.m.absorption = if absorbing { Vec3::new(0.5, 1.0, 2.0) } else { Vec3::ZERO };
            let direct = Vec3::new(0.25, 0.5, 0.125);
            let mut rays = RayCounts::default();
            let key = SampleKey { seed: settings.seed, frame: settings.frame, ..SampleKey::default() };
            let mut ctx = PathContext::new(&settings, CameraSample::single(key), &mut rays);
            let colour = bounce(&scene, &ray, &hit, &lit, direct, depth, weight, &mut ctx);
            let spent = ctx.budget.spent();
            ctx.finish();
            let secondary = rays.reflection + rays.refraction + rays.glossy + rays.blurry;
            if lit.bounces(&ray, depth, weight, max_depth, min_contribution) {
                prop_assert!(secondary > 0 && spent > 0, "a bounce traced no ray");
            } else {
                prop_assert_eq!(secondary, 0);
                prop_assert_eq!(colour.to_array().map(f32::to_bits), lit.local(&scene, &ray, &hit, direct).to_array().map(f32::to_bits));
            }
        }
    }
}
