//! Rhai scripting: a sandboxed engine that drives the World's camera, objects, materials,
//! texture transforms and settings frame by frame, for animations ([`animate`]) and
//! parameter sweeps.
//!
//! ```
//! use penumbra::scene::{default_scene, spawn_world};
//! use penumbra::script::{Clock, Limits, Script, ScriptedWorld};
//! let script = Script::from_source(
//!     "orbit.rhai",
//!     "fn frame(t) { camera.position = vec3(6 * sin(t), 2, -6 * cos(t)); }",
//!     Limits::default(),
//! )?;
//! let mut world: ScriptedWorld = ScriptedWorld::new(spawn_world(&default_scene()), &script);
//! world.setup()?;
//! world.frame(Clock::at(12, 24.0))?; // t = 0.5 s
//! let snapshot = world.update();
//! let rig = world.world().world().resource::<penumbra::world::resources::CameraRig>();
//! assert!((rig.position.x - 6.0 * 0.5f64.sin()).abs() < 1e-12); // scripts write f64 positions
//! // Snapshots are camera-relative: the traced camera sits at the origin.
//! assert_eq!(snapshot.camera.position, penumbra::math::Vec3::ZERO);
//! # Ok::<(), penumbra::script::ScriptError>(())
//! ```

pub mod animate;
pub mod api;
pub mod engine;
pub mod error;
pub mod lent;
pub mod runtime;
pub mod shutter;
pub mod sweep;

pub use animate::{Animation, FrameRange};
pub use engine::Limits;
pub use error::{ErrorKind, Limit, ScriptError};
pub use lent::Clock;
pub use runtime::{Script, ScriptRuntime, ScriptedWorld};
