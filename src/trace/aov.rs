//! First-hit AOVs: one geometric probe ray per pixel through its centre from the lens centre,
//! with no shading, giving noise-free depth, normal, albedo and object id even when the image
//! itself is anti-aliased or blurred by depth of field.

use rayon::prelude::*;

use super::scene::TraceScene;
use super::settings::RenderSettings;
use super::stats::RayCounts;
use super::visibility::closest_hit;
use crate::film::{AovSet, Aovs};
use crate::math::Vec3;
use crate::store::{ObjectId, ObjectKind, PrimitiveStore};

/// The first-hit AOVs in `wanted` (cost is filled by the renderer), counting one `aov` ray per
/// pixel when any first-hit AOV is wanted.
pub fn first_hit_aovs<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    wanted: AovSet,
    rays: &mut RayCounts,
) -> Aovs {
    let (w, h) = (settings.width, settings.height);
    let mut aovs = Aovs::new(AovSet { cost: false, ..wanted }, w, h);
    aovs.object_names = scene.object_names.clone();
    if !(wanted.depth || wanted.normal || wanted.albedo || wanted.object) {
        return aovs;
    }
    let rows: Vec<Vec<Probe>> =
        (0..h).into_par_iter().map(|y| (0..w).map(|x| probe(scene, settings, x, y)).collect()).collect();
    rays.aov += u64::from(w) * u64::from(h);
    for (i, p) in rows.iter().flatten().enumerate() {
        if let Some(d) = aovs.depth.as_mut() {
            d[i] = p.depth;
        }
        if let Some(n) = aovs.normal.as_mut() {
            n[i] = p.normal;
        }
        if let Some(a) = aovs.albedo.as_mut() {
            a[i] = p.albedo;
        }
        if let Some(o) = aovs.object.as_mut() {
            o[i] = p.object;
        }
    }
    aovs
}

/// What the probe through one pixel centre sees.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Probe {
    depth: f32,
    normal: Vec3,
    albedo: Vec3,
    object: u32,
}

fn probe<S: PrimitiveStore>(scene: &TraceScene<S>, settings: &RenderSettings, x: u32, y: u32) -> Probe {
    let ray = scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, settings.width, settings.height);
    let Some(hit) = closest_hit(scene, &ray, 0.0, f32::INFINITY) else {
        return Probe { depth: f32::INFINITY, normal: Vec3::ZERO, albedo: Vec3::ZERO, object: 0 };
    };
    let sp = scene.surface(&hit, &ray, 0.0);
    let normal = if sp.normal.dot(ray.dir) < 0.0 { sp.shading } else { -sp.shading };
    Probe {
        depth: hit.t * ray.dir.dot(scene.camera.forward),
        normal,
        albedo: scene.material_at(scene.material(sp.material), &hit, sp.point, 0.0).kd,
        object: object_index(scene, hit.object) + 1,
    }
}

/// Index of a hit's object in [`TraceScene::object_names`] order: bounded objects first (grid
/// ids), then unbounded ones, then moving ones.
pub fn object_index<S: PrimitiveStore>(scene: &TraceScene<S>, object: ObjectId) -> u32 {
    match object.kind() {
        ObjectKind::Bounded(o) => o,
        ObjectKind::Plane(i) => scene.store.bounded_count() + i,
        ObjectKind::Moving(i) => scene.store.bounded_count() + scene.store.unbounded_count() + i,
    }
}
