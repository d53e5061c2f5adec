//! Tracing: the immutable snapshot a frame is rendered from, Phong shading with shadows,
//! reflection and refraction, the parallel tile renderer and its statistics.
//!
//! Nothing here touches the ECS: [`render`] is a pure function of a [`TraceScene`] and
//! [`RenderSettings`], which is what makes it testable without a World and deterministic.

pub mod aov;
pub mod effects;
pub mod finite;
pub mod integrator;
pub mod light;
pub mod material;
pub mod motion;
pub mod packet;
pub mod phong;
mod progressive;
pub mod render;
pub mod scene;
pub mod stats;

pub use effects::Effects;
pub use finite::DroppedSamples;
pub use integrator::{
    closest_hit, closest_hit_brute, closest_hit_tallied, facing_normals, transmittance,
    transmittance_tallied, ShadingPoint,
};
pub use light::Light;
pub use material::Material;
pub use motion::{CameraMotion, CameraPose, MovingObject, Pose, SceneMotion};
pub use render::{
    render, render_observed, render_with_aovs, tile_count, AntiAliasing, RenderSettings, Sampling,
};
pub use scene::{SceneTables, TraceScene};
pub use stats::{
    AdaptiveCounts, BudgetStats, GridStats, MotionStats, NoiseStats, NoiseStop, RayCounts, RenderStats,
    StageTimes,
};
