//! Tracing: the immutable snapshot a frame is rendered from, Phong shading with shadows,
//! reflection and refraction, the parallel tile renderer and its statistics.
//!
//! Dependencies point one way: [`render`](mod@render) dispatches to the tile renderers (`tiles`,
//! `camera_samples`, `packet_tile`, `corners` for adaptive supersampling, `progressive` for
//! noise-driven rounds), which trace paths with the [`integrator`]; it shades with [`phong`]
//! and asks [`visibility`] what a ray hits and what a shadow ray lets through; the path's
//! state (limits, ray budget, effect samples) is `path`; [`settings`] is what every layer
//! reads. Sample dimensions come from one table, [`crate::sample::dims`].
//!
//! Nothing here touches the ECS: [`render()`] is a pure function of a [`TraceScene`] and
//! [`RenderSettings`], which is what makes it testable without a World and deterministic.

pub mod aov;
mod camera_samples;
mod corners;
pub mod effects;
pub mod finite;
pub mod integrator;
pub mod light;
mod local;
pub mod material;
pub mod motion;
pub mod packet;
mod packet_tile;
pub(crate) mod path;
pub mod phong;
mod progressive;
pub mod render;
pub mod scene;
pub mod settings;
pub mod stats;
mod surface;
mod tiles;
pub mod visibility;

pub use effects::Effects;
pub use finite::DroppedSamples;
pub use integrator::{facing_normals, trace_ray, ShadingPoint};
pub use light::Light;
pub use material::Material;
pub use motion::{CameraMotion, CameraPose, MovingObject, Pose, SceneMotion};
pub use render::{render, render_observed, render_with_aovs};
pub use scene::{SceneTables, TraceScene};
pub use settings::{AntiAliasing, RenderSettings, Sampling, DEFAULT_MAX_SECONDARY_RAYS};
pub use stats::{
    AdaptiveCounts, BudgetStats, GridStats, MotionStats, NoiseStats, NoiseStop, RayCounts, RenderStats,
    StageTimes,
};
pub use tiles::{tile_count, TILE};
pub use visibility::{closest_hit, closest_hit_tallied, transmittance, transmittance_tallied};
