//! Tracing: the immutable snapshot a frame is rendered from, Phong shading with shadows,
//! reflection and refraction, the parallel tile renderer and its statistics.
//!
//! Nothing here touches the ECS: [`render`] is a pure function of a [`TraceScene`] and
//! [`RenderSettings`], which is what makes it testable without a World and deterministic.

pub mod integrator;
pub mod light;
pub mod material;
pub mod render;
pub mod scene;
pub mod stats;

pub use integrator::{closest_hit, closest_hit_brute};
pub use light::Light;
pub use material::Material;
pub use render::{render, RenderSettings};
pub use scene::{Effects, SceneTables, TraceScene};
pub use stats::{GridStats, RayCounts, RenderStats, StageTimes};
