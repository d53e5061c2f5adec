//! Penumbra: a data-oriented CPU ray tracer.
//!
//! A frame flows `scene` (RON → [`scene::SceneDesc`]) → `world` (bevy_ecs entities, change
//! detection) → [`trace::TraceScene`] (an immutable structure-of-arrays snapshot with a
//! uniform grid) → [`trace::render()`] (rayon tiles, 3D DDA, Phong) → `film` (an sRGB PNG or an
//! EXR, written atomically).
//!
//! Load a scene file, render it and write a PNG:
//!
//! ```
//! use penumbra::prelude::*;
//!
//! let file = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/spheres.ron");
//! let scene = load_scene(file.as_ref()).expect("a valid scene");
//! let mut world: SceneWorld = spawn_world(&scene);
//! let snapshot = world.update();
//! let settings = RenderSettings { width: 64, height: 48, ..world.render_settings() };
//! let (film, stats) = render(&snapshot, &settings);
//! assert_eq!(stats.rays.camera, 64 * 48);
//!
//! let out = tempfile::tempdir().unwrap();
//! write_png(&film, &out.path().join("spheres.png")).expect("a writable folder");
//! ```
//!
//! Or build the scene in code, checked by the rules a scene file is ([`scene::SceneBuilder`]):
//! spheres, a mesh, a light and a camera.
//!
//! ```
//! use penumbra::prelude::*;
//! use penumbra::math::{DVec3, Vec3};
//! use penumbra::scene::{CameraDesc, MaterialDesc, TransformDesc};
//!
//! let camera = CameraDesc::new(DVec3::new(0.0, 1.5, -5.0), DVec3::new(0.0, 0.5, 0.0), 40.0, 48, 32);
//! let scene = SceneBuilder::new(camera)
//!     .files_relative_to(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes"))
//!     .material(MaterialDesc { kr: 0.5, ..MaterialDesc::new("mirror", [0.2, 0.2, 0.2]) })
//!     .material(MaterialDesc::new("clay", [0.8, 0.5, 0.3]))
//!     .material(MaterialDesc::new("floor", [0.6, 0.6, 0.6]))
//!     .sphere(DVec3::new(-1.2, 0.5, 0.0), 0.5, "mirror")
//!     .sphere(DVec3::new(1.2, 0.4, 0.5), 0.4, "clay")
//!     .mesh("bunny_res3.obj", "clay", TransformDesc { translate: DVec3::new(0.0, -0.27, 0.8), scale: Vec3::splat(8.0), ..Default::default() })
//!     .plane(DVec3::ZERO, Vec3::Y, "floor")
//!     .point_light(DVec3::new(-3.0, 5.0, -4.0), 1.0)
//!     .build()
//!     .expect("a valid scene");
//!
//! let mut world: SceneWorld = spawn_world(&scene);
//! let snapshot = world.update();
//! let settings = RenderSettings { width: 48, height: 32, ..Default::default() };
//! let (film, _) = render(&snapshot, &settings);
//! // Something was hit and lit: the image is not black.
//! assert!(film.pixels.iter().any(|p| p.max_element() > 0.05));
//! ```
//!
//! The library's core (scene files, World, tracer, film) builds with no features. Features add
//! layers: `scripting` (Rhai scripts, frame sequences, batch manifests), `reports` (accuracy
//! against time, plots, the HTML page) and `cli` (the `penumbra` command); `cli` is the default.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
pub mod accel;
#[cfg(feature = "scripting")]
pub mod batch;
pub mod camera;
pub mod film;
pub mod geom;
pub mod math;
#[cfg(feature = "reports")]
pub mod report;
pub mod sample;
pub mod scene;
#[cfg(feature = "scripting")]
pub mod script;
pub mod simd;
pub mod store;
pub mod testing;
pub mod texture;
pub mod trace;
pub mod world;

/// The types most programs need: load or build a scene, step its World, render a frame, write it.
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
    pub use crate::scene::{default_scene, load_scene, parse_scene, spawn_world, SceneBuilder, SceneDesc};
    pub use crate::trace::{render, RenderSettings, RenderStats, TraceScene};
    pub use crate::world::SceneWorld;
}
