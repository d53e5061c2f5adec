//! The API scripts see, registered into a sandboxed engine: vectors and animation helpers
//! (`math`, `path`), the scene (`scene`: camera, entities, settings, the clock) and sweep
//! helpers (`sweep`).

pub mod convert;
pub mod math;
pub mod path;
pub mod scene;
pub mod sweep;

use rhai::Engine;

use super::state::SharedState;

/// Registers the whole API, the scene part over `state`.
pub fn register(engine: &mut Engine, state: &SharedState) {
    math::register(engine);
    path::register(engine);
    sweep::register(engine);
    scene::register(engine, state);
}
