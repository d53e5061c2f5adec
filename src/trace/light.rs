//! Light sources in engine form: radiance already scaled by intensity.
//!
//! Point and directional lights are sampled once per shading point. Area lights (a
//! parallelogram or a disk) take `samples` points per pixel with their own pattern, shared
//! among the pixel's camera samples; shading averages the Phong terms and the visibility over
//! those points (each a point light with the light's radiance). Area lights are not visible
//! to camera rays.

use super::finite::clamp_radiance;
use crate::math::{unit_and_length, Vec2, Vec3};
use crate::sample::pattern::{disk_point, square_point};
use crate::sample::Pattern;

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
    /// A parallelogram `corner + s·edge_u + t·edge_v`, s, t ∈ [0, 1], emitting to both sides.
    Rect {
        /// One corner.
        corner: Vec3,
        /// First edge from the corner.
        edge_u: Vec3,
        /// Second edge from the corner.
        edge_v: Vec3,
        /// Colour × intensity of the whole light.
        radiance: Vec3,
        /// Shadow rays per shading point.
        samples: u32,
        /// Placement of the samples.
        pattern: Pattern,
    },
    /// A disk of `radius` around `centre`, spanned by the unit axes `axis_u`, `axis_v`.
    Disk {
        /// Centre.
        centre: Vec3,
        /// Unit vector in the disk's plane.
        axis_u: Vec3,
        /// Unit vector in the disk's plane, orthogonal to `axis_u`.
        axis_v: Vec3,
        /// Radius.
        radius: f32,
        /// Colour × intensity of the whole light.
        radiance: Vec3,
        /// Shadow rays per shading point.
        samples: u32,
        /// Placement of the samples.
        pattern: Pattern,
    },
}

impl Light {
    /// The point a light is placed by: a point light's position, a rectangle's corner, a
    /// disk's centre; zero for directional lights.
    pub fn anchor(&self) -> Vec3 {
        match *self {
            Light::Point { position, .. } => position,
            Light::Rect { corner, .. } => corner,
            Light::Disk { centre, .. } => centre,
            Light::Directional { .. } => Vec3::ZERO,
        }
    }

    /// The light moved by `by` (directional lights do not move).
    pub fn translated(&self, by: Vec3) -> Self {
        let mut moved = *self;
        match &mut moved {
            Light::Point { position: p, .. }
            | Light::Rect { corner: p, .. }
            | Light::Disk { centre: p, .. } => *p += by,
            Light::Directional { .. } => {}
        }
        moved
    }

    /// Unit direction from `p` towards a point light or directional light, the distance to it
    /// (∞ for directional) and the radiance arriving. For area lights, the direction to the
    /// centre and the whole radiance (used only where one representative sample is wanted).
    #[inline]
    pub fn towards(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Point { position, radiance } => towards_point(p, position, radiance),
            Light::Directional { direction, radiance } => {
                (-direction, f32::INFINITY, clamp_radiance(radiance))
            }
            Light::Rect { corner, edge_u, edge_v, radiance, .. } => {
                towards_point(p, corner + 0.5 * (edge_u + edge_v), radiance)
            }
            Light::Disk { centre, radiance, .. } => towards_point(p, centre, radiance),
        }
    }

    /// True for lights with an area (sampled with several shadow rays).
    #[inline]
    pub fn is_area(&self) -> bool {
        matches!(self, Light::Rect { .. } | Light::Disk { .. })
    }

    /// Samples per shading point (1 for point and directional lights).
    #[inline]
    pub fn samples(&self) -> u32 {
        match *self {
            Light::Rect { samples, .. } | Light::Disk { samples, .. } => samples.max(1),
            _ => 1,
        }
    }

    /// Stratum `i` (of the light's `samples`) of an area light as (direction from `p`,
    /// distance, the light's whole radiance), with `u` the random pair placing the point in the
    /// stratum. The caller averages over the samples it takes. Point and directional lights
    /// ignore `i` and `u`.
    #[inline]
    pub fn sample(&self, p: Vec3, i: u32, u: Vec2) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Rect { corner, edge_u, edge_v, radiance, samples, pattern } => {
                let st = square_point(pattern, samples, i, u);
                towards_point(p, corner + st.x * edge_u + st.y * edge_v, radiance)
            }
            Light::Disk { centre, axis_u, axis_v, radius, radiance, samples, pattern } => {
                let d = disk_point(pattern, samples, i, u) * radius;
                towards_point(p, centre + d.x * axis_u + d.y * axis_v, radiance)
            }
            _ => self.towards(p),
        }
    }
}

/// Below this distance to a light, `to / |to|` loses precision: [`unit_and_length`] takes over.
const TINY_DISTANCE: f32 = 1e-18;

/// Direction and distance from `p` to a point of a light, and the radiance arriving (at most
/// `f32::MAX` per channel). Safe at any distance: far points (where `|to|²` overflows) and
/// near ones (where it underflows) are handled on a scaled vector, and a light exactly at `p`
/// gives a zero direction, which every caller skips as facing away.
#[inline]
fn towards_point(p: Vec3, position: Vec3, radiance: Vec3) -> (Vec3, f32, Vec3) {
    let to = position - p;
    let dist = to.length();
    let radiance = clamp_radiance(radiance);
    if dist.is_finite() && dist >= TINY_DISTANCE {
        return (to / dist, dist, radiance);
    }
    match unit_and_length(to) {
        Some((dir, dist)) => (dir, dist, radiance),
        None => (Vec3::ZERO, 0.0, radiance),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn towards_a_point_is_finite_near_far_and_at_the_light() {
        let one = Vec3::ONE;
        let (d, dist, _) = towards_point(Vec3::new(-1e30, 0.0, 0.0), Vec3::new(1e30, 0.0, 0.0), one);
        assert_eq!((d, dist), (Vec3::X, 2e30));
        let (d, dist, _) = towards_point(Vec3::ZERO, Vec3::new(0.0, 3e-25, 4e-25), one);
        assert!((d - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6 && (dist - 5e-25).abs() < 1e-30);
        let (d, dist, _) = towards_point(Vec3::splat(1e7), Vec3::splat(1e7), one);
        assert_eq!((d, dist), (Vec3::ZERO, 0.0));
        // An ordinary distance keeps the plain bits.
        let to = Vec3::new(1.0, 2.0, -2.5);
        assert_eq!(towards_point(Vec3::ZERO, to, one).0, to / to.length());
    }

    #[test]
    fn radiance_beyond_the_largest_float_arrives_as_the_largest_float() {
        let light = Light::Point { position: Vec3::Y, radiance: Vec3::new(f32::INFINITY, 3e38, 0.0) };
        assert_eq!(light.towards(Vec3::ZERO).2, Vec3::new(f32::MAX, 3e38, 0.0));
        let sun = Light::Directional { direction: -Vec3::Y, radiance: Vec3::splat(f32::INFINITY) };
        assert_eq!(sun.towards(Vec3::ZERO), (Vec3::Y, f32::INFINITY, Vec3::splat(f32::MAX)));
    }
}
