//! Sphere: centre and radius.

use crate::math::{unit_and_length, Aabb, Ray, Vec3};

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

/// Outward unit normal at a point `p` where `ray` hit the sphere.
///
/// Always finite: where rounding put `p` on the centre (a sphere far smaller than the float
/// spacing of its coordinates, or a hit point from a ray that started very far away), the
/// normal is the ray's direction when the ray started inside the sphere and its reverse
/// otherwise, so the hit is shaded as facing the ray on the side it arrived from.
#[inline]
pub fn normal(centre: Vec3, radius: f32, p: Vec3, ray: &Ray) -> Vec3 {
    let n = ((p - centre) / radius).normalize();
    if n.is_finite() {
        return n;
    }
    if let Some((n, _)) = unit_and_length(p - centre) {
        return n;
    }
    let inside = (ray.origin - centre).length_squared() < radius * radius;
    if inside {
        ray.dir
    } else {
        -ray.dir
    }
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
    fn normals_are_finite_when_the_hit_point_rounds_onto_the_centre() {
        // A camera at the centre of a sphere of radius 5e-7 at 1e7: the hit point rounds back
        // onto the centre.
        let centre = Vec3::splat(1e7);
        let inside = Ray::new(centre, Vec3::Z);
        let t = intersect(centre, 5e-7, &inside, 0.0, f32::INFINITY).unwrap();
        let p = inside.at(t);
        assert_eq!(p, centre);
        assert_eq!(normal(centre, 5e-7, p, &inside), Vec3::Z);
        let outside = Ray::new(Vec3::new(1e7, 1e7, 0.0), Vec3::Z);
        assert_eq!(normal(centre, 5e-7, centre, &outside), -Vec3::Z);
        // Near the origin the offset is representable: the plain normal.
        let near = Ray::new(Vec3::ZERO, Vec3::X);
        let t = intersect(Vec3::ZERO, 5e-7, &near, 0.0, f32::INFINITY).unwrap();
        assert!((normal(Vec3::ZERO, 5e-7, near.at(t), &near) - Vec3::X).length() < 1e-6);
        // An offset too small to square still has a direction.
        assert_eq!(normal(Vec3::ZERO, 1e-30, Vec3::new(0.0, -1e-40, 0.0), &near), -Vec3::Y);
    }

    #[test]
    fn far_away_sphere_keeps_precision() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0e5), Vec3::Z);
        let t = intersect(Vec3::ZERO, 1.0, &ray, 0.0, f32::INFINITY).unwrap();
        assert!((t - (1.0e5 - 1.0)).abs() <= 1.0e5 * 1e-6, "t = {t}");
    }
}
