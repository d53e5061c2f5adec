//! The Whitted integrator: nearest hits through the grid, shadow transmittance, and Phong
//! shading with recursive reflection and refraction.

use super::scene::TraceScene;
use super::stats::RayCounts;
use crate::accel::GridWalk;
use crate::math::{offset_distance, reflect, refract, Ray, Vec3};
use crate::store::{Hit, PrimitiveStore};

/// Nearest hit in `(t_min, t_max)`: planes first, then the grid's cells front to back.
///
/// A hit found in a cell is final once it lies within that cell's t-range: no later cell can
/// hold a nearer one. A hit beyond the range (an object reaching into later cells) is kept as
/// the bound for the rest of the walk, so it is never tested again at a larger t.
#[inline]
pub fn closest_hit<S: PrimitiveStore>(
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
    for span in GridWalk::new(&scene.grid, ray, t_min, nearest.t) {
        if span.t_enter > nearest.t {
            break;
        }
        for &id in scene.grid.cell_prims(span.cell) {
            nearest.offer(store.intersect_bounded(id, ray, t_min, nearest.t));
        }
        if nearest.t <= span.t_exit {
            break;
        }
    }
    nearest.hit
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
        nearest.offer(store.intersect_bounded(id, ray, t_min, nearest.t));
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

/// Fraction of light that passes along `ray` over `(0, t_max)`: 0 behind an opaque object,
/// the product of `kt` over every surface crossed otherwise.
///
/// Each object is handled whole the first time the walk meets it: all its crossings in
/// `(0, t_max)` are counted then, and a per-ray list of visited ids skips it in later cells.
/// Counting a crossing in "the cell whose t-range holds it" is not enough: a crossing exactly on
/// a wall, or rounded across one, can land in a span whose cell does not store the object.
pub fn transmittance<S: PrimitiveStore>(scene: &TraceScene<S>, ray: &Ray, t_max: f32) -> f32 {
    let store = &scene.store;
    let opaque_only = !scene.effects.transmission;
    let mut pass = 1.0f32;
    let mut cross = |h: &Hit| -> bool {
        let kt = scene.material(store.material(h)).kt;
        pass *= kt;
        opaque_only || pass == 0.0
    };
    for i in 0..store.unbounded_count() {
        if let Some(h) = store.intersect_unbounded(i, ray, 0.0, t_max) {
            if cross(&h) {
                return 0.0;
            }
        }
    }
    let walk = GridWalk::new(&scene.grid, ray, 0.0, t_max);
    if opaque_only {
        // Any crossing anywhere in (0, t_max) blocks the light: no bookkeeping needed.
        for span in walk {
            for &id in scene.grid.cell_prims(span.cell) {
                if store.intersect_bounded(id, ray, 0.0, t_max).is_some() {
                    return 0.0;
                }
            }
        }
        return pass;
    }
    let mut visited: Vec<u32> = Vec::new();
    for span in walk {
        for &id in scene.grid.cell_prims(span.cell) {
            if visited.contains(&id) {
                continue;
            }
            visited.push(id);
            // All of this object's crossings, nearest first.
            let mut t_lo = 0.0;
            while let Some(h) = store.intersect_bounded(id, ray, t_lo, t_max) {
                if cross(&h) {
                    return 0.0;
                }
                t_lo = h.t;
            }
        }
    }
    pass
}

/// Per-ray context: recursion limits and the counters of one worker.
pub struct PathContext<'a> {
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Minimum path weight worth tracing.
    pub min_contribution: f32,
    /// Ray counters to add to.
    pub rays: &'a mut RayCounts,
}

/// Radiance arriving along `ray`, which already carries path weight `weight` at `depth`.
pub fn radiance<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    depth: u32,
    weight: f32,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let Some(hit) = closest_hit(scene, ray, 0.0, f32::INFINITY) else {
        return scene.background;
    };
    let sp = scene.store.surface(&hit, ray);
    let m = *scene.material(sp.material);
    // Shade the side the ray arrives on.
    let entering = sp.normal.dot(ray.dir) < 0.0;
    let n = if entering { sp.normal } else { -sp.normal };
    let eps = offset_distance(sp.point, scene.offset_floor);
    let above = sp.point + n * eps;
    let view = -ray.dir;

    // Ambient and direct light.
    let mut colour = scene.ambient * m.kd;
    for light in &scene.lights {
        let (to_light, dist, radiance) = light.towards(sp.point);
        let n_dot_l = n.dot(to_light);
        if n_dot_l <= 0.0 {
            continue;
        }
        ctx.rays.shadow += 1;
        let shadow = Ray::new(above, to_light);
        let pass = transmittance(scene, &shadow, dist - eps);
        if pass == 0.0 {
            continue;
        }
        let diffuse = m.kd * n_dot_l;
        let r_dot_v = reflect(-to_light, n).dot(view).max(0.0);
        let specular = if m.ks > 0.0 { m.ks * r_dot_v.powf(m.shininess) } else { 0.0 };
        colour += radiance * pass * (diffuse + Vec3::splat(specular));
    }

    if depth >= ctx.max_depth {
        return colour;
    }
    // Mirror reflection.
    if m.kr > 0.0 && weight * m.kr >= ctx.min_contribution {
        ctx.rays.reflection += 1;
        let r = Ray::new(above, reflect(ray.dir, n));
        colour += m.kr * radiance(scene, &r, depth + 1, weight * m.kr, ctx);
    }
    // Refraction (Snell), or total internal reflection.
    if m.kt > 0.0 && weight * m.kt >= ctx.min_contribution {
        ctx.rays.refraction += 1;
        let eta = if entering { 1.0 / m.ior } else { m.ior };
        let next = match refract(ray.dir, n, eta) {
            Some(dir) => Ray::new(sp.point - n * eps, dir),
            None => Ray::new(above, reflect(ray.dir, n)),
        };
        colour += m.kt * radiance(scene, &next, depth + 1, weight * m.kt, ctx);
    }
    colour
}
