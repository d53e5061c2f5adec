//! Reference implementations for tests and benches: brute force over every object (and every
//! triangle of every mesh), not for rendering. Stable but slow.
//!
//! The tracer's answers are checked against these: [`closest_hit_brute`] finds what
//! [`crate::trace::closest_hit`] finds, testing every plane and every bounded object in turn
//! with no grid at either level. Both store layouts implement [`BruteForce`].
//!
//! ```
//! use penumbra::prelude::*;
//! use penumbra::testing::closest_hit_brute;
//! use penumbra::trace::closest_hit;
//!
//! let mut world: SceneWorld = spawn_world(&default_scene());
//! let scene = world.update();
//! let ray = Ray::new(Vec3::new(0.0, 1.0, -5.0), Vec3::new(0.0, -0.1, 1.0));
//! let brute = closest_hit_brute(&scene, &ray, 0.0, f32::INFINITY);
//! assert!(brute.is_some());
//! assert_eq!(closest_hit(&scene, &ray, 0.0, f32::INFINITY), brute);
//! ```

use crate::math::{Affine3A, Ray};
use crate::store::mesh::{self, MeshEntry};
use crate::store::{AosStore, Hit, NoTally, ObjectId, PrimitiveStore, SoaStore};
use crate::trace::TraceScene;

/// A store that can be searched by brute force: the reference its grids are checked against.
pub trait BruteForce: PrimitiveStore {
    /// Nearest hit with bounded object `id` in `(t_min, t_max)`, testing every triangle of a
    /// mesh (no mesh grid); other shapes as [`PrimitiveStore::intersect_bounded`] tests them.
    fn intersect_bounded_brute(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit>;
}

impl BruteForce for SoaStore {
    fn intersect_bounded_brute(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        bounded_brute(self, self.instance(id), id, ray, t_min, t_max)
    }
}

impl BruteForce for AosStore {
    fn intersect_bounded_brute(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        bounded_brute(self, self.instance(id), id, ray, t_min, t_max)
    }
}

/// Bounded object `id` of `store`, which is `instance` (its mesh and world-to-object map) when
/// it is a mesh instance: every triangle of the mesh, else the store's own test.
fn bounded_brute<S: PrimitiveStore>(
    store: &S,
    instance: Option<(&MeshEntry<S::Triangles>, Affine3A)>,
    id: u32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    match instance {
        Some((entry, to_object)) => {
            let local = mesh::object_ray(&to_object, ray);
            mesh::intersect_brute(entry, &local, t_min, t_max)
                .map(|(k, h)| Hit::triangle(ObjectId::bounded(id), k, &h))
        }
        None => store.intersect_bounded(id, ray, t_min, t_max, &mut NoTally),
    }
}

/// Nearest hit in `(t_min, t_max)` by testing every object: planes first, then every bounded
/// object in id order ([`BruteForce::intersect_bounded_brute`]). The reference the grid is
/// checked against; moving objects are not tested.
pub fn closest_hit_brute<S: BruteForce>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let store = &scene.store;
    let mut hit = None;
    let mut bound = t_max;
    for i in 0..store.unbounded_count() {
        if let Some(h) = store.intersect_unbounded(i, ray, t_min, bound) {
            bound = h.t;
            hit = Some(h);
        }
    }
    for id in 0..store.bounded_count() {
        if let Some(h) = store.intersect_bounded_brute(id, ray, t_min, bound) {
            bound = h.t;
            hit = Some(h);
        }
    }
    hit
}
