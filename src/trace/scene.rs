//! The immutable per-frame snapshot the tracer reads: flat arrays, no ECS.

use std::sync::Arc;

use super::effects::Effects;
use super::light::Light;
use super::material::Material;
use super::motion::{SceneMotion, MOVING_FLAG};
use crate::accel::{GridBuilder, UniformGrid};
use crate::camera::Camera;
use crate::math::{Ray, Vec3};
use crate::store::{
    Hit, MaterialId, MeshAsset, MeshEntry, PlacedObject, PrimitiveStore, SoaStore, SurfacePoint,
    UNBOUNDED_FLAG,
};

/// True when a hit is on a moving object ([`MOVING_FLAG`] set, the unbounded flag clear).
#[inline]
pub fn is_moving(hit: &Hit) -> bool {
    hit.object & (MOVING_FLAG | UNBOUNDED_FLAG) == MOVING_FLAG
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
        }
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
            Some(m) if is_moving(hit) => m.material(hit),
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
