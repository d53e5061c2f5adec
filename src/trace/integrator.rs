//! The Whitted integrator with distribution effects: nearest hits through the grid, shadow
//! transmittance, and recursive mirror or glossy reflection and sharp or blurry refraction.

use super::phong::{direct_light, Surface};
use super::render::{RenderSettings, Sampling};
use super::scene::TraceScene;
use super::stats::RayCounts;
use crate::accel::walk;
use crate::math::{reflect, refract, Ray, Vec2, Vec3};
use crate::sample::pattern::square_point;
use crate::sample::rng::{Dimension, Permutation, SampleKey, SampleStream};
use crate::sample::warp::cone;
use crate::store::{Hit, NoTally, PrimitiveStore, SurfacePoint, Tally, TraversalCost};

/// Nearest hit in `(t_min, t_max)`: planes first, then the grid's cells front to back.
///
/// The direction may have any non-zero length; `t` is in units of it. Counts nothing; see
/// [`closest_hit_tallied`] for the traversal statistics.
#[inline]
pub fn closest_hit<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    closest_hit_tallied(scene, ray, t_min, t_max, &mut NoTally)
}

/// [`closest_hit`], adding the cells visited and primitives tested to `tally` (a
/// [`crate::store::TraversalCost`] counts them).
#[inline]
pub fn closest_hit_tallied<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
) -> Option<Hit> {
    closest_hit_at(scene, ray, t_min, t_max, 0.0, tally)
}

/// [`closest_hit_tallied`] for a ray at time `s` of the shutter interval (0 at open, 1 at
/// close): moving objects are seen where they are then ([`super::motion`]); the static scene
/// is the same at every time.
#[inline]
pub fn closest_hit_at<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    s: f32,
    tally: &mut T,
) -> Option<Hit> {
    let mut nearest = Nearest::new(t_max);
    let store = &scene.store;
    for i in 0..store.unbounded_count() {
        tally.tests(1);
        nearest.offer(store.intersect_unbounded(i, ray, t_min, nearest.t));
    }
    nearest.offer(grid_hit(scene, ray, t_min, nearest.t, tally));
    if let Some(motion) = &scene.motion {
        nearest.offer(motion.nearest(store.meshes(), ray, t_min, nearest.t, s, tally));
    }
    nearest.hit
}

/// Nearest hit with a bounded object in `(t_min, t_max)`, walking the top-level grid with the
/// walk the mesh grids share ([`walk::nearest`]): the second half of [`closest_hit_tallied`],
/// after the planes.
#[inline]
pub(crate) fn grid_hit<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
) -> Option<Hit> {
    let store = &scene.store;
    walk::nearest(&scene.grid, ray, t_min, t_max, tally, |id, bound, tally| {
        store.intersect_bounded(id, ray, t_min, bound, tally).map(|h| (h.t, h))
    })
}

/// Nearest hit by testing every object: the reference the grid is checked against.
pub fn closest_hit_brute<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let mut nearest = Nearest::new(t_max);
    let store = &scene.store;
    for i in 0..store.unbounded_count() {
        nearest.offer(store.intersect_unbounded(i, ray, t_min, nearest.t));
    }
    for id in 0..store.bounded_count() {
        nearest.offer(store.intersect_bounded_brute(id, ray, t_min, nearest.t));
    }
    nearest.hit
}

/// The nearest hit so far and the ray parameter that bounds further searches.
struct Nearest {
    hit: Option<Hit>,
    t: f32,
}

impl Nearest {
    #[inline]
    fn new(t_max: f32) -> Self {
        Self { hit: None, t: t_max }
    }

    /// Keeps `candidate`, which the caller found within `(t_min, self.t)`, so it is nearer.
    #[inline]
    fn offer(&mut self, candidate: Option<Hit>) {
        if let Some(h) = candidate {
            self.t = h.t;
            self.hit = Some(h);
        }
    }
}

/// Fraction of light that passes along `ray` over `(0, t_max)` (`t` in units of the direction's
/// length, which may be any), per colour channel: 0 behind an opaque object, the product of
/// `kt` over every surface
/// crossed otherwise (planes first, then each object's crossings nearest first, the objects in
/// ascending id: [`ordered_product`]). Counts nothing; see
/// [`transmittance_tallied`] for the traversal statistics.
///
/// Each object is handled whole the first time the walk meets it: all its crossings in
/// `(0, t_max)` are counted then, and a per-ray list of visited ids skips it in later cells.
/// Counting a crossing in "the cell whose t-range holds it" is not enough: a crossing exactly on
/// a wall, or rounded across one, can land in a span whose cell does not store the object.
pub fn transmittance<S: PrimitiveStore>(scene: &TraceScene<S>, ray: &Ray, t_max: f32) -> Vec3 {
    transmittance_tallied(scene, ray, t_max, &mut NoTally)
}

/// [`transmittance`], adding the cells visited and primitives tested to `tally` (a
/// [`TraversalCost`] counts them). Both branches walk the top-level grid with the any-hit walk
/// the mesh grids share ([`walk::any`]); with transmission, "hit" means the light is used up.
pub fn transmittance_tallied<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    transmittance_at(scene, ray, t_max, 0.0, tally)
}

/// [`transmittance_tallied`] for a shadow ray at time `s` of the shutter interval: the static
/// scene's part, times the moving objects' part ([`super::motion::SceneMotion::transmittance`],
/// objects in ascending index) where something moves.
pub fn transmittance_at<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    s: f32,
    tally: &mut T,
) -> Vec3 {
    let pass = static_transmittance(scene, ray, t_max, tally);
    match &scene.motion {
        Some(motion) if pass != Vec3::ZERO => {
            let kt = |m| scene.material(m).kt;
            let opaque = !scene.effects.transmission;
            pass * motion.transmittance(scene.store.meshes(), ray, t_max, s, opaque, kt, tally)
        }
        _ => pass,
    }
}

/// The static scene's part of [`transmittance_at`].
fn static_transmittance<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    let store = &scene.store;
    let pass = planes_transmittance(scene, ray, t_max, tally);
    if pass == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let grid = &scene.grid;
    if !scene.effects.transmission {
        // Any crossing anywhere in (0, t_max) blocks the light: no bookkeeping needed.
        let blocked = walk::any(grid, ray, 0.0, t_max, tally, |id, tally| {
            store.occludes_bounded(id, ray, 0.0, t_max, tally)
        });
        return if blocked { Vec3::ZERO } else { pass };
    }
    let mut shares: Vec<(u32, Vec3)> = Vec::new();
    let blocked = walk::any(grid, ray, 0.0, t_max, tally, |id, tally| {
        if shares.iter().any(|&(seen, _)| seen == id) {
            return false;
        }
        let share = object_transmittance(scene, id, ray, t_max, tally);
        shares.push((id, share));
        share == Vec3::ZERO
    });
    if blocked {
        Vec3::ZERO
    } else {
        ordered_product(pass, &mut shares)
    }
}

/// The planes' part of a shadow ray's transmittance: `kt` of every plane crossed in
/// `(0, t_max)`, multiplied in plane order (0 as soon as one blocks; in a scene without
/// transmission, any crossing blocks).
#[inline]
pub(crate) fn planes_transmittance<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    let store = &scene.store;
    let mut pass = Vec3::ONE;
    for i in 0..store.unbounded_count() {
        tally.tests(1);
        if let Some(h) = store.intersect_unbounded(i, ray, 0.0, t_max) {
            pass *= scene.material(store.material(&h)).kt;
            if !scene.effects.transmission || pass == Vec3::ZERO {
                return Vec3::ZERO;
            }
        }
    }
    pass
}

/// Bounded object `id`'s share of a shadow ray's transmittance: its `kt` once per crossing in
/// `(0, t_max)`, multiplied nearest first; 0 once it blocks.
#[inline]
pub(crate) fn object_transmittance<S: PrimitiveStore, T: Tally>(
    scene: &TraceScene<S>,
    id: u32,
    ray: &Ray,
    t_max: f32,
    tally: &mut T,
) -> Vec3 {
    let store = &scene.store;
    let mut share = Vec3::ONE;
    let mut t_lo = 0.0;
    while let Some(h) = store.intersect_bounded(id, ray, t_lo, t_max, tally) {
        share *= scene.material(store.material(&h)).kt;
        if share == Vec3::ZERO {
            return Vec3::ZERO;
        }
        t_lo = h.t;
    }
    share
}

/// A shadow ray's transmittance from its planes' part and its objects' shares: the shares are
/// multiplied in ascending object id, an order that does not depend on how the objects were
/// found, so a single ray's walk and a packet's (which meets objects in another order) give the
/// same bits. Sorts `shares` (ids are distinct).
#[inline]
pub(crate) fn ordered_product(pass: Vec3, shares: &mut [(u32, Vec3)]) -> Vec3 {
    shares.sort_unstable_by_key(|&(id, _)| id);
    shares.iter().fold(pass, |pass, &(_, share)| pass * share)
}

/// Default of [`RenderSettings::max_secondary_rays`]: the secondary rays one camera sample may
/// trace. The shipped scenes use at most a few hundred (see `docs/scene-format.md`).
pub const DEFAULT_MAX_SECONDARY_RAYS: u32 = 1024;

/// The secondary rays (reflection, refraction, glossy, blurry) one camera sample may still
/// trace: a per-sample counter carried down the recursion, so the rays it refuses depend only
/// on the sample, never on threads or tile order.
///
/// Rays are granted depth-first in the order the integrator asks for them (reflection before
/// refraction, a cone's rays in turn), but a node first sets aside one ray for each sibling
/// still to come (the refraction while the reflection's tree is traced, the rest of a cone), so
/// a tree that outgrows the budget loses its deepest rays, not its shallow siblings. A tree
/// that fits is never cut: every ray set aside is asked for later, so `spent + reserved`
/// never exceeds the rays the whole tree asks for. Shadow rays are not counted: each shading
/// point sends a bounded number (one per point light, `samples` per area light), and the
/// budget bounds the shading points to one plus the secondary rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayBudget {
    limit: u32,
    spent: u32,
    reserved: u32,
    refused: u32,
}

impl RayBudget {
    /// A budget of `limit` secondary rays, none spent.
    pub fn new(limit: u32) -> Self {
        Self { limit, spent: 0, reserved: 0, refused: 0 }
    }

    /// Sets aside `n` rays that siblings will ask for later.
    #[inline]
    fn reserve(&mut self, n: u32) {
        self.reserved = self.reserved.saturating_add(n);
    }

    /// Gives back `n` rays set aside by [`Self::reserve`] (their sibling is about to ask).
    #[inline]
    fn release(&mut self, n: u32) {
        debug_assert!(self.reserved >= n, "released more rays than were set aside");
        self.reserved = self.reserved.saturating_sub(n);
    }

    /// Grants one ray if the budget, less what is set aside, has one left; counts a refusal
    /// otherwise.
    #[inline]
    fn grant(&mut self) -> bool {
        if self.spent.saturating_add(self.reserved) < self.limit {
            self.spent += 1;
            true
        } else {
            self.refused = self.refused.saturating_add(1);
            false
        }
    }

    /// Rays granted so far.
    pub fn spent(&self) -> u32 {
        self.spent
    }

    /// Rays refused so far (0 unless the tree was cut).
    pub fn refused(&self) -> u32 {
        self.refused
    }
}

/// Per-path context: recursion limits, sampling budgets, the randomness of the camera sample
/// being traced, and the counters of one worker.
pub struct PathContext<'a> {
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Minimum path weight worth tracing.
    pub min_contribution: f32,
    /// Glossy/blurry rays per pixel at the first bounce (one per path deeper down).
    pub glossy: Sampling,
    /// Randomness of this camera sample: every random choice along the path takes dimensions
    /// from it in traversal order, so the path is a pure function of its key.
    pub stream: SampleStream,
    /// Which camera sample of which pixel this path belongs to.
    pub camera: CameraSample,
    /// Secondary rays this camera sample may still trace.
    pub budget: RayBudget,
    /// Ray counters to add to.
    pub rays: &'a mut RayCounts,
    /// The SIMD level shadow packets are traced at, or `None` for single rays (`--simd scalar`).
    pub packets: Option<crate::simd::SimdLevel>,
    /// Transmittance of the shadow ray towards each of the first [`HINTED_LIGHTS`] lights from
    /// the next shading point, already traced in a packet with its neighbours' (camera hits and
    /// point or directional lights); taken by the first [`super::phong::direct_light`].
    pub shadow_hint: Option<ShadowHint>,
    /// The next shading point, already found by a packet tracer that needed it (for the
    /// shadow rays of [`PathContext::shadow_hint`]); taken by the first [`radiance_at`], which
    /// would compute the same.
    pub surface_hint: Option<ShadingPoint>,
    /// Time of this camera sample in the shutter interval (0 at open, 1 at close): every ray
    /// of the path sees moving objects where they are then. 0 where nothing moves.
    pub time: f32,
}

/// Lights whose shadow rays from camera hits are traced in packets.
pub const HINTED_LIGHTS: usize = 4;

/// Per light (by index), the transmittance of a shading point's shadow ray, where known.
pub type ShadowHint = [Option<Vec3>; HINTED_LIGHTS];

/// First dimension of a path's stream; the ones below belong to the pixel's own patterns
/// (sub-pixel position, lens).
pub const FIRST_PATH_DIM: u32 = 2;

/// A camera sample: its own key, and its place among its pixel's samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CameraSample {
    /// Key of this sample's path stream.
    pub key: SampleKey,
    /// Key shared by all of the pixel's samples: effect patterns are stratified through it.
    pub pixel: SampleKey,
    /// Index of this sample among the pixel's `spp`.
    pub slot: u32,
    /// Camera samples of the pixel: an effect's per-pixel sample count is shared among them.
    pub spp: u32,
}

impl CameraSample {
    /// A sample that is its pixel's only one (adaptive lattice points, single rays).
    pub fn single(key: SampleKey) -> Self {
        Self { key, pixel: key, slot: 0, spp: 1 }
    }
}

impl<'a> PathContext<'a> {
    /// The context of the path of `camera` under `settings`.
    pub fn new(settings: &RenderSettings, camera: CameraSample, rays: &'a mut RayCounts) -> Self {
        Self {
            max_depth: settings.max_depth,
            min_contribution: settings.min_contribution,
            glossy: settings.glossy,
            stream: SampleStream::starting_at(camera.key, FIRST_PATH_DIM),
            camera: CameraSample { spp: camera.spp.max(1), ..camera },
            budget: RayBudget::new(settings.max_secondary_rays),
            rays,
            packets: settings.simd.packets().then(|| settings.simd.resolve()),
            shadow_hint: None,
            surface_hint: None,
            time: 0.0,
        }
    }

    /// This context for a path at time `s` of a scene with motion: single rays only (packets
    /// share no time), every ray at `s`.
    pub fn at_time(mut self, s: f32) -> Self {
        self.packets = None;
        self.time = s;
        self
    }

    /// Ends the path: adds what the budget did to the ray counters.
    pub fn finish(self) {
        self.rays.budget.record(self.budget.spent(), self.budget.refused());
    }

    /// Rays a glossy or blurry cone traces at `depth`: this camera sample's share of
    /// `glossy.samples` at the first bounce, one deeper down (what [`scatter`] asks for).
    #[inline]
    fn cone_rays(&self, depth: u32) -> u32 {
        if depth == 0 {
            self.glossy.samples.max(1).div_ceil(self.camera.spp)
        } else {
            1
        }
    }

    /// This camera sample's share of an effect that takes `n` samples per pixel:
    /// `ceil(n / spp)` pairs of (stratum of `n`, uniform pair). Across the pixel's camera samples
    /// the strata are a permutation of `0..n`, so the pixel's samples stay stratified.
    pub fn effect_samples(&mut self, n: u32) -> EffectSamples {
        let n = n.max(1);
        let dim = self.stream.take_dim();
        let c = &self.camera;
        let share = n.div_ceil(c.spp);
        let first = c.slot.wrapping_mul(share);
        let points = Dimension::new(&c.pixel, dim);
        EffectSamples {
            points,
            n,
            next: first,
            end: first.wrapping_add(share),
            order: Permutation::new(n, points.hash(u32::MAX)),
        }
    }
}

/// One camera sample's share of an effect's per-pixel samples; see
/// [`PathContext::effect_samples`].
#[derive(Debug, Clone)]
pub struct EffectSamples {
    /// The pixel's points in this effect's dimension.
    points: Dimension,
    n: u32,
    next: u32,
    end: u32,
    /// The order strata are visited in.
    order: Permutation,
}

impl EffectSamples {
    /// Samples this camera sample takes.
    pub fn taken(&self) -> u32 {
        self.end.wrapping_sub(self.next)
    }

    /// Samples of the whole pixel (the pattern's size).
    pub fn pattern_size(&self) -> u32 {
        self.n
    }
}

impl Iterator for EffectSamples {
    type Item = (u32, Vec2);

    #[inline]
    fn next(&mut self) -> Option<(u32, Vec2)> {
        if self.next == self.end {
            return None;
        }
        let g = self.next;
        self.next = self.next.wrapping_add(1);
        Some((self.order.at(g % self.n), self.points.uniform2(g)))
    }
}

/// Largest cone half-angle, reached at glossiness 1: 45°.
pub const MAX_GLOSSY_ANGLE: f32 = std::f32::consts::FRAC_PI_4;

/// Radiance arriving along `ray`, which already carries path weight `weight` at `depth`.
pub fn radiance<S: PrimitiveStore>(
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
pub fn radiance_at<S: PrimitiveStore>(
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

/// The normals a hit is shaded with, turned towards the incoming direction `dir`: whether the
/// ray arrives on the front (geometric) side, the geometric normal on the arrival side, and the
/// shading normal on that side (the geometric one where the interpolated normal would face
/// away from the viewer, which can happen at grazing angles on a smooth mesh).
#[inline]
pub fn facing_normals(sp: &crate::store::SurfacePoint, dir: Vec3) -> (bool, Vec3, Vec3) {
    let entering = sp.normal.dot(dir) < 0.0;
    let n = if entering { sp.normal } else { -sp.normal };
    let ns = match if entering { sp.shading } else { -sp.shading } {
        s if s.dot(dir) < 0.0 => s,
        _ => n,
    };
    (entering, n, ns)
}

/// A hit as shading sees it from the side its ray arrives on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingPoint {
    /// The surface at the hit.
    pub sp: SurfacePoint,
    /// Whether the ray arrives on the front (geometric) side.
    pub entering: bool,
    /// The unit geometric normal on the arrival side: it decides offsets and sides.
    pub n: Vec3,
    /// The unit shading normal on the arrival side, unless it would face away from the viewer
    /// (possible at grazing angles on a smooth mesh), where `n` takes over.
    pub ns: Vec3,
    /// Where rays leaving on the arrival side start: just beyond the hit point's error bound
    /// along `n` (the front of a smooth mesh from its lifted point: no shadow terminator).
    pub above: Vec3,
}

impl ShadingPoint {
    /// The surface `sp` seen by a ray travelling along `dir`.
    #[inline]
    pub fn new(sp: SurfacePoint, dir: Vec3) -> Self {
        let (entering, n, ns) = facing_normals(&sp, dir);
        Self { sp, entering, n, ns, above: sp.spawn(n) }
    }
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
    let samples = if depth == 0 { ctx.effect_samples(ctx.glossy.samples) } else { ctx.effect_samples(1) };
    let n = samples.pattern_size();
    debug_assert_eq!(samples.taken(), ctx.cone_rays(depth), "the rays set aside for a cone");
    // The cone's later rays are set aside while each earlier ray's tree is traced.
    ctx.budget.reserve(samples.taken());
    let mut traced = 0u32;
    let mut sum = Vec3::ZERO;
    for (stratum, u) in samples {
        ctx.budget.release(1);
        if !ctx.budget.grant() {
            continue;
        }
        traced += 1;
        let mut dir = cone(axis, half_angle, square_point(pattern, n, stratum, u));
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

    #[test]
    fn a_budget_grants_up_to_its_limit_less_the_rays_set_aside() {
        let mut budget = RayBudget::new(3);
        budget.reserve(1);
        assert!(budget.grant());
        assert!(budget.grant());
        assert!(!budget.grant(), "the last ray is set aside for a sibling");
        budget.release(1);
        assert!(budget.grant(), "the sibling gets it");
        assert!(!budget.grant());
        assert_eq!((budget.spent(), budget.refused()), (3, 2));
    }

    #[test]
    fn a_budget_that_holds_the_tree_refuses_nothing() {
        // Four rays asked for, two of them set aside first: exactly four fit.
        let mut budget = RayBudget::new(4);
        budget.reserve(2);
        assert!(budget.grant() && budget.grant());
        budget.release(2);
        assert!(budget.grant() && budget.grant());
        assert_eq!((budget.spent(), budget.refused()), (4, 0));
    }
}
