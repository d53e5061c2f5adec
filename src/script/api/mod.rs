//! The API scripts see, registered into a sandboxed engine: vectors and animation helpers
//! (`math`, `path`), the scene (`scene`: the camera and the clock; `entity`: objects and lights by name; `settings`; `texture`:
//! the textures' transforms), sweep helpers (`sweep`) and the property names of each type (`properties`), for error messages;
//! `limits` checks writes against the scene's combined rules.

pub mod convert;
pub mod entity;
pub mod limits;
pub mod math;
pub mod path;
pub mod properties;
pub mod scene;
pub mod settings;
pub mod sweep;
pub mod texture;

use rhai::Engine;

use super::lent::LentWorld;

/// Registers the whole API, the scene part over the World `lent` holds during calls.
pub fn register(engine: &mut Engine, lent: &LentWorld) {
    math::register(engine);
    path::register(engine);
    sweep::register(engine);
    scene::register(engine, lent);
    entity::register(engine, lent);
    texture::register(engine, lent);
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
