//! Resources of the scene World: tables shared by all entities (materials, camera, settings)
//! and what the systems produce (the grid index, the snapshot, counters and timings).

use std::sync::Arc;

use bevy_ecs::prelude::{Entity, Resource};
use glam::DVec3;

use crate::accel::{UniformGrid, DEFAULT_LAMBDA};
use crate::math::Vec3;
use crate::store::{MaterialId, MeshAsset, MeshEntry, PrimitiveStore};
use crate::trace::{Material, RenderSettings, TraceScene};

/// Material table; [`MaterialId`] indexes it. Names are kept for scripts and messages.
#[derive(Resource, Debug, Clone, Default)]
pub struct Materials {
    /// Materials in id order.
    pub table: Vec<Material>,
    /// Name of each material, same order.
    pub names: Vec<String>,
}

impl Materials {
    /// Id of the material called `name`.
    pub fn id(&self, name: &str) -> Option<MaterialId> {
        self.names.iter().position(|n| n == name).map(|i| MaterialId(i as u32))
    }
}

/// Texture table; [`crate::texture::TextureId`] indexes it. Names are kept for scripts.
#[derive(Resource, Debug, Clone)]
pub struct Textures {
    /// Textures in id order (shared with every snapshot until a script changes one).
    pub table: Arc<[crate::texture::Texture]>,
    /// Name of each texture, same order.
    pub names: Vec<String>,
}

impl Default for Textures {
    fn default() -> Self {
        Self { table: Arc::from(Vec::new()), names: Vec::new() }
    }
}

impl Textures {
    /// Id of the texture called `name`.
    pub fn id(&self, name: &str) -> Option<crate::texture::TextureId> {
        self.names.iter().position(|n| n == name).map(|i| crate::texture::TextureId(i as u32))
    }
}

/// The camera as authored (positions in `f64`, angles in radians). Its position is the
/// origin of every snapshot ([`FrameOrigin`]).
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct CameraRig {
    /// Eye position.
    pub position: DVec3,
    /// Point looked at.
    pub look_at: DVec3,
    /// Rough up direction.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Lens radius (0: pinhole).
    pub aperture: f32,
    /// What is in focus.
    pub focus: Focus,
}

/// What a thin-lens camera keeps sharp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Focus {
    /// The plane through the look-at point.
    LookAt,
    /// The plane at this distance along the view direction.
    Distance(f32),
    /// The plane through this point (its depth along the view direction); follows the camera.
    Point(DVec3),
}

impl CameraRig {
    /// The camera this rig describes in the snapshot's coordinates, whose origin is the eye:
    /// it sits at `Vec3::ZERO` and looks towards `look_at - position` (computed in `f64`),
    /// its focus resolved against the current pose.
    pub fn camera(&self) -> crate::camera::Camera {
        let towards = (self.look_at - self.position).as_vec3();
        let camera = crate::camera::Camera::look_at(Vec3::ZERO, towards, self.up, self.fov_y);
        camera.with_lens(self.aperture, self.focus_distance_along(camera.forward))
    }

    /// The distance from the eye to the plane in focus, along the view direction: the one
    /// resolution of [`Focus`] that the renderer and scripts (`camera.focus_distance`) share.
    pub fn focus_distance(&self) -> f32 {
        // The camera's forward axis, as `Camera::look_at` computes it from the eye at zero.
        self.focus_distance_along((self.look_at - self.position).as_vec3().normalize())
    }

    fn focus_distance_along(&self, forward: Vec3) -> f32 {
        match self.focus {
            Focus::LookAt => (self.look_at - self.position).as_vec3().length(),
            Focus::Distance(d) => d,
            // A file's point lies in front of the camera (validation); a point a script or
            // the moving camera left behind it gives the nearest plane in front instead.
            Focus::Point(p) => ((p - self.position).dot(forward.as_dvec3()) as f32).max(f32::MIN_POSITIVE),
        }
    }
}

/// The camera at shutter close, where it differs from [`CameraRig`] (the camera at shutter
/// open): motion blur then moves the camera across the shutter interval.
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq)]
pub struct ShutterCamera(pub Option<CameraRig>);

/// The world point the current `WorldShape`s, `WorldAabb`s and grid are relative to: the
/// camera position of the frame they were derived for. Snapshots are camera-relative, so that
/// `f32` keeps its precision where the camera looks however far that is from the world's
/// origin. `update_bounds` moves it to the camera each frame; when it moves, every entity's
/// world geometry is derived again and the grid is rebuilt.
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameOrigin(pub DVec3);

/// Frame-wide settings: how the tracer renders (its own [`RenderSettings`], not a copy of
/// them) and the scene-wide terms the snapshot and the grid take.
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct SceneSettings {
    /// How every frame is rendered (image size, depth, seed, frame number, the effects'
    /// sample counts); its `simd` is the caller's choice at render time.
    pub render: RenderSettings,
    /// Colour of escaping rays.
    pub background: Vec3,
    /// Ambient light.
    pub ambient: Vec3,
    /// Grid density: cells ≈ λ · objects.
    pub lambda: f32,
}

impl Default for SceneSettings {
    fn default() -> Self {
        Self {
            render: RenderSettings::default(),
            background: Vec3::ZERO,
            ambient: Vec3::splat(0.1),
            lambda: DEFAULT_LAMBDA,
        }
    }
}

/// The grid over bounded entities, and the entity behind each grid object id.
#[derive(Resource, Debug, Clone)]
pub struct GridIndex {
    /// The grid (shared with every snapshot taken while nothing moves).
    pub grid: Arc<UniformGrid>,
    /// `entities[id]` is the entity of grid object `id`.
    pub entities: Vec<Entity>,
}

impl Default for GridIndex {
    fn default() -> Self {
        Self { grid: Arc::new(UniformGrid::empty()), entities: Vec::new() }
    }
}

/// How many times `rebuild_grid` has run.
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GridRebuilds(pub u64);

/// Seconds spent by the last run of each frame stage.
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq)]
pub struct StageClock {
    /// `update_bounds`.
    pub bounds: f64,
    /// `rebuild_grid` (zero on frames that reuse the grid).
    pub grid_build: f64,
    /// `build_snapshot`.
    pub snapshot: f64,
}

/// The latest snapshot, produced by `build_snapshot`.
#[derive(Resource, Debug, Clone)]
pub struct Snapshot<S: PrimitiveStore + 'static>(pub Option<Arc<TraceScene<S>>>);

impl<S: PrimitiveStore + 'static> Default for Snapshot<S> {
    fn default() -> Self {
        Self(None)
    }
}

/// The scene's mesh assets, indexed by [`crate::geom::MeshId`]: loaded and gridded once, shared
/// by every instance and every frame.
#[derive(Resource, Debug, Clone, Default)]
pub struct MeshTable(pub Vec<Arc<MeshAsset>>);

/// The mesh assets laid out for store `S`, made once from [`MeshTable`] by `build_snapshot`.
#[derive(Resource, Debug)]
pub struct MeshLayouts<S: PrimitiveStore + 'static>(pub Vec<Arc<MeshEntry<S::Triangles>>>);

impl<S: PrimitiveStore + 'static> Default for MeshLayouts<S> {
    fn default() -> Self {
        Self(Vec::new())
    }
}
