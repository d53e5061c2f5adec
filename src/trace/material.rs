//! Phong material parameters, in engine form.

use crate::math::Vec3;

/// A Phong material with mirror reflection and transmission.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Diffuse reflectance (RGB).
    pub kd: Vec3,
    /// Specular reflectance.
    pub ks: f32,
    /// Phong exponent.
    pub shininess: f32,
    /// Mirror reflectance.
    pub kr: f32,
    /// Transmittance.
    pub kt: f32,
    /// Index of refraction.
    pub ior: f32,
    /// Blur of reflection and refraction in [0, 1] (used by distribution effects).
    pub glossiness: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self { kd: Vec3::splat(0.5), ks: 0.0, shininess: 32.0, kr: 0.0, kt: 0.0, ior: 1.5, glossiness: 0.0 }
    }
}
