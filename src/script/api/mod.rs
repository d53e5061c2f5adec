//! The API scripts see, registered into a sandboxed engine: vectors and animation helpers
//! (`math`, `path`), and the scene (camera, entities, settings, the clock).

pub mod convert;
pub mod math;
pub mod path;
