//! Penumbra: a data-oriented CPU ray tracer.
//!
//! A frame flows `scene` (RON → `SceneDesc`) → `world` (bevy_ecs entities, change detection)
//! → `trace::TraceScene` (an immutable structure-of-arrays snapshot with a uniform grid)
//! → `trace::render` (rayon tiles, 3D DDA, Phong) → `film` (sRGB PNG written atomically).
#![forbid(unsafe_code)]
#![warn(missing_docs)]
pub mod accel;
pub mod camera;
pub mod film;
pub mod geom;
pub mod math;
pub mod scene;
pub mod store;
pub mod trace;
pub mod world;
