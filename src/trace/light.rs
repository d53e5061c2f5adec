//! Light sources in engine form: radiance already scaled by intensity.

use crate::math::Vec3;

/// A light source.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Point light without distance falloff.
    Point {
        /// Position.
        position: Vec3,
        /// Colour × intensity.
        radiance: Vec3,
    },
    /// Light from infinitely far away.
    Directional {
        /// Unit direction the light travels in.
        direction: Vec3,
        /// Colour × intensity.
        radiance: Vec3,
    },
}

impl Light {
    /// Unit direction from `p` towards the light, the distance to it (∞ for directional) and
    /// the radiance arriving.
    #[inline]
    pub fn towards(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Point { position, radiance } => {
                let to = position - p;
                let dist = to.length();
                (to / dist, dist, radiance)
            }
            Light::Directional { direction, radiance } => (-direction, f32::INFINITY, radiance),
        }
    }
}
