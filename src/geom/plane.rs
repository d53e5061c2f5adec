//! Infinite plane `n · p = d`: unbounded, so it lives outside the grid and is always tested.

use crate::math::{gamma, Ray, Vec3};

/// Hit of a ray with the plane `normal · p = offset` within `(t_min, t_max)`, for a direction of
/// any non-zero length (`t` in units of its length); rays parallel to the plane miss.
#[inline]
pub fn intersect(normal: Vec3, offset: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let denom = normal.dot(ray.dir);
    if denom == 0.0 {
        return None;
    }
    let t = (offset - normal.dot(ray.origin)) / denom;
    (t > t_min && t < t_max).then_some(t)
}

/// The hit point of `ray` at `t`, projected back onto the plane, and a conservative bound on its
/// distance from the plane along the unit normal, which covers the plane test's own rounding
/// for a ray starting there (`γ(10)·(|n|·|p| + |offset|)`).
#[inline]
pub fn surface_point(normal: Vec3, offset: f32, ray: &Ray, t: f32) -> (Vec3, f32) {
    let p = ray.at(t);
    let point = p - normal * (normal.dot(p) - offset);
    (point, gamma(10) * (normal.abs().dot(point.abs()) + offset.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_at_height_over_cosine_and_parallel_rays_miss() {
        let ray = Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, -1.0, 0.0).normalize());
        let t = intersect(Vec3::Y, 0.0, &ray, 0.0, f32::INFINITY).unwrap();
        assert!((t - 2.0 * 2f32.sqrt()).abs() < 1e-5);
        let parallel = Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::X);
        assert_eq!(intersect(Vec3::Y, 0.0, &parallel, 0.0, f32::INFINITY), None);
    }
}
