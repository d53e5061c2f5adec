//! Penumbra: a data-oriented CPU ray tracer.
//!
//! A frame flows `scene` (RON → `SceneDesc`) → `world` (bevy_ecs entities, change detection)
//! → `trace::TraceScene` (an immutable structure-of-arrays snapshot with a uniform grid)
//! → `trace::render` (rayon tiles, 3D DDA, Phong) → `film` (sRGB PNG written atomically).
#![forbid(unsafe_code)]
#![warn(missing_docs)]
pub mod accel;
pub mod batch;
pub mod camera;
pub mod film;
pub mod geom;
pub mod math;
pub mod report;
pub mod sample;
pub mod scene;
pub mod script;
pub mod simd;
pub mod store;
pub mod texture;
pub mod trace;
pub mod world;

/// The types most programs need: load a scene, step its World, render a frame, write it.
///
/// ```
/// use penumbra::prelude::*;
/// let mut world: SceneWorld = spawn_world(&default_scene());
/// let snapshot = world.update();
/// let settings = RenderSettings { width: 32, height: 24, ..world.render_settings() };
/// let (film, stats) = render(&snapshot, &settings);
/// assert_eq!(stats.rays.camera, 32 * 24);
/// # let _ = film;
/// ```
pub mod prelude {
    pub use crate::film::{write_png, Film};
    pub use crate::math::{Ray, Vec3};
    pub use crate::scene::{default_scene, load_scene, parse_scene, spawn_world, SceneDesc};
    pub use crate::trace::{render, RenderSettings, RenderStats, TraceScene};
    pub use crate::world::SceneWorld;
}
