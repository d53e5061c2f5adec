//! Placeholder replaced by the math API (vec3, lerp, easing).
pub fn register(_engine: &mut rhai::Engine) {}
