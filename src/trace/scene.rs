//! The immutable per-frame snapshot the tracer reads: flat arrays, no ECS.

use std::sync::Arc;

use super::effects::Effects;
use super::light::Light;
use super::material::Material;
use super::motion::SceneMotion;
use crate::accel::{GridBuilder, UniformGrid};
use crate::camera::Camera;
use glam::DVec3;

use crate::geom::uv::SurfaceUv;
use crate::math::{Ray, Vec2, Vec3};
use crate::store::{
    Hit, MaterialId, MeshAsset, MeshEntry, ObjectKind, PlacedObject, PrimitiveStore, SoaStore, SurfacePoint,
};
use crate::texture::Texture;

/// True when a hit is on a moving object.
#[inline]
pub fn is_moving(hit: &Hit) -> bool {
    matches!(hit.object.kind(), ObjectKind::Moving(_))
}

/// Step in (u, v) of a bump map's finite differences.
const BUMP_STEP: f32 = 1.0 / 1024.0;

/// The unit normal of the surface `su` displaced along `n` by `depth × height`, the height being
/// the mean of `texture`'s channels and `depth` relative to the size of one unit of (u, v)
/// there (pbrt's bump mapping, by finite differences); on `n`'s side. `n` where the surface
/// has no derivatives.
fn bumped(texture: &Texture, depth: f32, su: &SurfaceUv, n: Vec3) -> Vec3 {
    if su.dpdu == Vec3::ZERO || su.dpdv == Vec3::ZERO {
        return n;
    }
    let scale = depth * 0.5 * (su.dpdu.length() + su.dpdv.length());
    let height = |uv: Vec2| texture.eval(uv).element_sum() / 3.0 * scale;
    let h = height(su.uv);
    let dhdu = (height(su.uv + Vec2::new(BUMP_STEP, 0.0)) - h) / BUMP_STEP;
    let dhdv = (height(su.uv + Vec2::new(0.0, BUMP_STEP)) - h) / BUMP_STEP;
    let tilted = (su.dpdu + dhdu * n).cross(su.dpdv + dhdv * n).normalize_or_zero();
    match tilted.dot(n) {
        d if d > 0.0 => tilted,
        d if d < 0.0 => -tilted,
        _ => n,
    }
}

/// The non-geometric part of a snapshot: materials, lights, camera and the constant terms.
#[derive(Debug, Clone)]
pub struct SceneTables {
    /// Material table indexed by [`MaterialId`].
    pub materials: Vec<Material>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Camera.
    pub camera: Camera,
    /// Colour of rays that escape.
    pub background: Vec3,
    /// Ambient light (times kd).
    pub ambient: Vec3,
}

/// Everything one frame is traced from. `S` is the primitive layout.
#[derive(Debug, Clone)]
pub struct TraceScene<S: PrimitiveStore = SoaStore> {
    /// Flattened geometry.
    pub store: S,
    /// Grid over the store's bounded objects (shared between frames until something moves).
    pub grid: Arc<UniformGrid>,
    /// Material table indexed by [`MaterialId`].
    pub materials: Vec<Material>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Camera.
    pub camera: Camera,
    /// Colour of rays that escape.
    pub background: Vec3,
    /// Ambient light (times kd).
    pub ambient: Vec3,
    /// Effects present in this scene.
    pub effects: Effects,
    /// Scene names of the objects, bounded ones in grid-id order then unbounded ones (empty
    /// when the snapshot was not built from a World); the legend of the object-id AOV. Moving
    /// objects follow, named in [`SceneMotion::names`].
    pub object_names: Vec<String>,
    /// What moves while the shutter is open (motion blur); `None` when nothing does, and then
    /// no ray is given a time and nothing is paid for motion.
    pub motion: Option<Arc<SceneMotion>>,
    /// Texture table indexed by [`crate::texture::TextureId`] (shared between frames).
    pub textures: Arc<[Texture]>,
    /// Where the camera is in the world: the snapshot's coordinates are relative to it. Planar
    /// texture coordinates add it back, so textures stay put when the camera moves.
    pub origin: DVec3,
}

impl<S: PrimitiveStore> TraceScene<S> {
    /// Assembles a snapshot around an already built grid over `bounded` (in grid-id order),
    /// with the mesh assets its instances refer to already laid out for `S`.
    pub fn with_grid(
        grid: Arc<UniformGrid>,
        bounded: &[PlacedObject],
        unbounded: &[PlacedObject],
        meshes: &[Arc<MeshEntry<S::Triangles>>],
        tables: SceneTables,
    ) -> Self {
        let SceneTables { materials, lights, camera, background, ambient } = tables;
        let effects = Effects::of(&materials, &lights, &camera);
        Self {
            store: S::build(bounded, unbounded, meshes),
            grid,
            materials,
            lights,
            camera,
            background,
            ambient,
            effects,
            object_names: Vec::new(),
            motion: None,
            textures: Arc::from(Vec::new()),
            origin: DVec3::ZERO,
        }
    }

    /// The snapshot with its texture table (`Effects::textures` says whether a material uses
    /// one) and the world position of its origin, the camera.
    pub fn with_textures(mut self, textures: Arc<[Texture]>, origin: DVec3) -> Self {
        debug_assert!(
            self.materials.iter().flat_map(|m| m.maps.textures()).all(|t| (t.0 as usize) < textures.len()),
            "a material names a texture the table lacks"
        );
        self.textures = textures;
        self.origin = origin;
        self
    }

    /// Texture coordinates at `hit` ([`crate::geom::uv`]), whose surface point is `point`, for a
    /// ray at time `s`.
    #[inline]
    pub fn uv(&self, hit: &Hit, point: Vec3, s: f32) -> SurfaceUv {
        match &self.motion {
            Some(m) if is_moving(hit) => m.uv(self.store.meshes(), hit, point, s, self.origin),
            _ => self.store.uv(hit, point, self.origin),
        }
    }

    /// Material `m` as it is at `hit` (surface point `point`, time `s`): its colours times its
    /// textures there. Untextured materials come back unchanged, and cost one test.
    #[inline]
    pub fn material_at(&self, m: &Material, hit: &Hit, point: Vec3, s: f32) -> Material {
        self.shade_at(m, hit, point, Vec3::ZERO, s).0
    }

    /// [`TraceScene::material_at`], and the unit shading normal `ns` (facing the viewer) tilted by
    /// the material's bump map there (`ns` itself without one, or where the surface has no
    /// texture derivatives).
    #[inline(always)]
    pub fn shade_at(&self, m: &Material, hit: &Hit, point: Vec3, ns: Vec3, s: f32) -> (Material, Vec3) {
        // The untextured case, every hit of most scenes, stays in the caller whatever the
        // inliner's budget there; the texture lookups are a call of their own.
        if m.maps.is_empty() {
            return (*m, ns);
        }
        self.textured(m, hit, point, ns, s)
    }

    /// [`TraceScene::shade_at`] of a material with texture maps.
    #[inline(never)]
    fn textured(&self, m: &Material, hit: &Hit, point: Vec3, ns: Vec3, s: f32) -> (Material, Vec3) {
        let mut m = *m;
        let su = self.uv(hit, point, s);
        if let Some(t) = m.maps.kd {
            m.kd *= self.textures[t.0 as usize].eval(su.uv);
        }
        if let Some(t) = m.maps.ks {
            m.ks *= self.textures[t.0 as usize].eval(su.uv).element_sum() / 3.0;
        }
        let ns = match m.maps.bump {
            Some(bump) if ns != Vec3::ZERO => {
                bumped(&self.textures[bump.texture.0 as usize], bump.depth, &su, ns)
            }
            _ => ns,
        };
        (m, ns)
    }

    /// The snapshot with `motion` (none when it is empty): moving objects and the camera's
    /// motion, seen by rays at their times. Sets [`Effects::motion`].
    pub fn with_motion(mut self, motion: SceneMotion) -> Self {
        self.effects.motion = !motion.is_empty();
        self.motion = (!motion.is_empty()).then(|| Arc::new(motion));
        self
    }

    /// The camera at time `s` of the shutter interval: the snapshot's camera unless it moves.
    #[inline]
    pub fn camera_at(&self, s: f32) -> Camera {
        match self.motion.as_ref().and_then(|m| m.camera.as_ref()) {
            Some(camera) => camera.at(s),
            None => self.camera,
        }
    }

    /// Position, normals and material at a hit by `ray` at time `s` (which only moving
    /// objects read).
    #[inline]
    pub fn surface(&self, hit: &Hit, ray: &Ray, s: f32) -> SurfacePoint {
        match &self.motion {
            Some(m) if is_moving(hit) => m.surface(self.store.meshes(), hit, ray, s),
            _ => self.store.surface(hit, ray),
        }
    }

    /// Material of the object hit.
    #[inline]
    pub fn hit_material(&self, hit: &Hit) -> MaterialId {
        match &self.motion {
            Some(m) if is_moving(hit) => m.material(self.store.meshes(), hit),
            _ => self.store.material(hit),
        }
    }

    /// Builds a snapshot, its grid included, straight from placed objects (no ECS): planes go to
    /// the unbounded list, everything else into the grid in the given order.
    pub fn build(objects: &[PlacedObject], tables: SceneTables, lambda: f32) -> Self {
        Self::build_with_meshes(objects, &[], tables, lambda)
    }

    /// [`TraceScene::build`] for scenes with mesh instances, whose ids index `meshes`.
    pub fn build_with_meshes(
        objects: &[PlacedObject],
        meshes: &[Arc<MeshAsset>],
        tables: SceneTables,
        lambda: f32,
    ) -> Self {
        let layouts: Vec<Arc<MeshEntry<S::Triangles>>> =
            meshes.iter().map(|m| Arc::new(MeshEntry::new(m.clone()))).collect();
        let (bounded, unbounded): (Vec<PlacedObject>, Vec<PlacedObject>) =
            objects.iter().cloned().partition(|o| o.geometry.bounds().is_some());
        let bounds: Vec<_> = bounded.iter().filter_map(|o| o.geometry.bounds()).collect();
        let grid =
            GridBuilder::new(lambda).build(&bounds, |id, cell| bounded[id as usize].geometry.overlaps(cell));
        Self::with_grid(Arc::new(grid), &bounded, &unbounded, &layouts, tables)
    }

    /// The material of a material id.
    #[inline]
    pub fn material(&self, id: MaterialId) -> &Material {
        &self.materials[id.0 as usize]
    }
}
