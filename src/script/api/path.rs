//! Placeholder replaced by Catmull–Rom paths.
pub fn register(_engine: &mut rhai::Engine) {}
