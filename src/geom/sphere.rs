//! Sphere: centre and radius.

use crate::math::{Aabb, Ray, Vec3};

/// The bounds of a sphere.
#[inline]
pub fn bounds(centre: Vec3, radius: f32) -> Aabb {
    Aabb::new(centre - Vec3::splat(radius), centre + Vec3::splat(radius))
}

/// Nearest hit of a unit-direction ray with a sphere within `(t_min, t_max)`.
///
/// Uses the geometric discriminant `r² - |f - (f·d)d|²` (Ray Tracing Gems, ch. 7), which keeps its
/// precision for grazing rays and for spheres far from the ray origin, and the stable root pair
/// `q = b + sign(b)·√Δ`, `t = c/q, q`.
#[inline]
pub fn intersect(centre: Vec3, radius: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let f = ray.origin - centre;
    let b = -f.dot(ray.dir);
    let closest = f + b * ray.dir;
    let r2 = radius * radius;
    let disc = r2 - closest.length_squared();
    if disc < 0.0 {
        return None;
    }
    let c = f.length_squared() - r2;
    let q = b + disc.sqrt().copysign(b);
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q) };
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    if near > t_min && near < t_max {
        Some(near)
    } else if far > t_min && far < t_max {
        Some(far)
    } else {
        None
    }
}

/// Outward unit normal at a point on the sphere.
#[inline]
pub fn normal(centre: Vec3, radius: f32, p: Vec3) -> Vec3 {
    ((p - centre) / radius).normalize()
}

/// True when the sphere overlaps the box (exact: distance from centre to box ≤ radius).
#[inline]
pub fn overlaps_box(centre: Vec3, radius: f32, cell: &Aabb) -> bool {
    let nearest = centre.clamp(cell.min, cell.max);
    (nearest - centre).length_squared() <= radius * radius
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on_hit_is_distance_minus_radius_and_inside_hit_is_exit() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        assert_eq!(intersect(Vec3::ZERO, 1.0, &ray, 0.0, f32::INFINITY), Some(4.0));
        let inside = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(intersect(Vec3::ZERO, 1.0, &inside, 0.0, f32::INFINITY), Some(1.0));
        assert_eq!(intersect(Vec3::ZERO, 1.0, &ray, 0.0, 3.9), None);
    }

    #[test]
    fn far_away_sphere_keeps_precision() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0e5), Vec3::Z);
        let t = intersect(Vec3::ZERO, 1.0, &ray, 0.0, f32::INFINITY).unwrap();
        assert!((t - (1.0e5 - 1.0)).abs() <= 1.0e5 * 1e-6, "t = {t}");
    }
}
