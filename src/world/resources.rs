//! Resources of the scene World: tables shared by all entities (materials, camera, settings)
//! and what the systems produce (the grid index, the snapshot, counters and timings).

use std::sync::Arc;

use bevy_ecs::prelude::{Entity, Resource};

use crate::accel::{UniformGrid, DEFAULT_LAMBDA};
use crate::math::Vec3;
use crate::store::{MaterialId, PrimitiveStore};
use crate::trace::{Material, TraceScene};

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

/// The camera as authored (angles in radians).
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct CameraRig {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub look_at: Vec3,
    /// Rough up direction.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
}

/// Frame-wide render settings.
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct SceneSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Minimum path weight worth tracing.
    pub min_contribution: f32,
    /// Colour of escaping rays.
    pub background: Vec3,
    /// Ambient light.
    pub ambient: Vec3,
    /// Seed of all randomness.
    pub seed: u64,
    /// Frame number.
    pub frame: u32,
    /// Grid density: cells ≈ λ · objects.
    pub lambda: f32,
}

impl Default for SceneSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            max_depth: 5,
            min_contribution: 1e-3,
            background: Vec3::ZERO,
            ambient: Vec3::splat(0.1),
            seed: 0,
            frame: 0,
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
