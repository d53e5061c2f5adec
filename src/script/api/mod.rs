//! The API scripts see, registered into a sandboxed engine: vectors and animation helpers
//! (`math`, `path`), the scene (`scene`: camera, entities, settings, the clock; `texture`:
//! the textures' transforms), sweep helpers (`sweep`) and the property names of each type (`properties`), for error messages;
//! `limits` checks writes against the scene's combined rules.

pub mod convert;
pub mod limits;
pub mod math;
pub mod path;
pub mod properties;
pub mod scene;
pub mod settings;
pub mod sweep;
pub mod texture;

use rhai::Engine;

use super::state::SharedState;

/// Registers the whole API, the scene part over `state`.
pub fn register(engine: &mut Engine, state: &SharedState) {
    math::register(engine);
    path::register(engine);
    sweep::register(engine);
    scene::register(engine, state);
    texture::register(engine, state);
}

/// An engine with the scene-free API (math, paths, sweeps) and evaluation helpers for tests.
#[cfg(test)]
pub(crate) mod testing {
    use rhai::{Dynamic, Engine};

    /// A plain engine with the scene-free API registered.
    pub fn engine() -> Engine {
        let mut engine = Engine::new();
        super::math::register(&mut engine);
        super::path::register(&mut engine);
        super::sweep::register(&mut engine);
        engine
    }

    /// The value of `script`; panics with the error otherwise.
    pub fn eval<T: Clone + Send + Sync + 'static>(script: &str) -> T {
        match engine().eval::<T>(script) {
            Ok(value) => value,
            Err(e) => panic!("{script}: {e}"),
        }
    }

    /// The error text of `script`; panics if it succeeds.
    pub fn eval_err(script: &str) -> String {
        match engine().eval::<Dynamic>(script) {
            Ok(value) => panic!("{script} should fail, gave {value:?}"),
            Err(e) => e.to_string(),
        }
    }
}
