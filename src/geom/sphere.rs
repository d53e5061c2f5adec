//! Sphere: centre and radius.

use crate::math::{gamma, unit_and_length, Aabb, Ray, Vec3};

/// The bounds of a sphere.
#[inline]
pub fn bounds(centre: Vec3, radius: f32) -> Aabb {
    Aabb::new(centre - Vec3::splat(radius), centre + Vec3::splat(radius))
}

/// Nearest hit of a ray with a sphere within `(t_min, t_max)`, for a direction of any non-zero
/// length; `t` is in units of the direction's length (the hit is `origin + t·dir`).
///
/// Follows Haines, Günther and Akenine-Möller, "Precision Improvements for Ray/Sphere
/// Intersection" (Ray Tracing Gems, 2019, ch. 7): the discriminant comes from the vector `l`
/// from the centre to the ray's point of closest approach, `Δ = a·(r² − |l|²)` with
/// `a = dir·dir`, which keeps its precision for spheres far from the origin; the roots come
/// from the stable pair `q = b + sign(b)·√Δ`, `t = c/q, q/a`.
///
/// Two guards make the answer trustworthy where f32 cannot decide it:
/// - a ray within the rounding error of the tangent (`|r² − |l|²|` below its error bound, a
///   grazing ray from 10⁵ radii away, say) is decided again in f64, where the same inputs give
///   an error ten orders of magnitude smaller;
/// - a root is taken only when it exceeds `t_min` by more than its own error bound, so a ray
///   leaving the surface (offset by its error bound, see [`surface_point`]) never finds the
///   surface it left at a tiny `t` (pbrt-v4's conservative root test).
#[inline]
pub fn intersect(centre: Vec3, radius: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let d = ray.dir;
    let f = ray.origin - centre;
    let a = d.dot(d);
    let b = -f.dot(d);
    let l = f + (b / a) * d;
    let r2 = radius * radius;
    let ll = l.dot(l);
    let disc = r2 - ll;
    let ff = f.dot(f);
    if disc.abs() <= discriminant_error(f, d, a, ll, ff, r2) {
        return intersect_f64(centre, radius, ray, t_min, t_max);
    }
    if disc < 0.0 {
        return None;
    }
    let c = ff - r2;
    let q = b + (a * disc).sqrt().copysign(b);
    let (t0, t1) = (c / q, q / a);
    // Bound on either root's rounding error: the error of `c` over `|q|`, and a few ulps of the root.
    let spread = gamma(8) * (ff + r2) / q.abs();
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    let inside = |t: f32| t - (spread + gamma(8) * t.abs()) > t_min && t < t_max;
    if inside(near) {
        Some(near)
    } else if inside(far) {
        Some(far)
    } else {
        None
    }
}

/// A bound on the rounding error of `r² − |l|²` as [`intersect`] computes it: `l`'s components
/// are off by at most `γ(9)·(|f_i| + m·|d_i|)` with `m = (|f|·|d|)/a`, so `|l|²` is off by
/// at most `2·|l|·|δl| + |δl|² + γ(3)·|l|²`, and `r²` by half an ulp. The square root is
/// taken only for rays near the tangent, where a cheap bound says it could matter.
#[inline]
fn discriminant_error(f: Vec3, d: Vec3, a: f32, ll: f32, ff: f32, r2: f32) -> f32 {
    // |δl| ≤ γ(9)·(|f| + m·|d|) ≤ 2·γ(9)·|f| (Cauchy–Schwarz), so 2·|l|·|δl| ≤ 4·γ(9)·|l|·|f|.
    let coarse = gamma(9) * 2.0 * (ll + ff) + gamma(3) * (ll + r2);
    if (r2 - ll).abs() > coarse {
        return 0.0;
    }
    let m = f.abs().dot(d.abs()) / a;
    let dl = (f.abs() + d.abs() * m) * gamma(9);
    let dl2 = dl.dot(dl);
    2.0 * (ll * dl2).sqrt() + dl2 + gamma(3) * (ll + r2)
}

/// [`intersect`] carried out in f64: for rays within f32's rounding error of the tangent.
#[cold]
fn intersect_f64(centre: Vec3, radius: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let d = ray.dir.as_dvec3();
    let f = ray.origin.as_dvec3() - centre.as_dvec3();
    let a = d.dot(d);
    let b = -f.dot(d);
    let l = f + (b / a) * d;
    let r2 = f64::from(radius) * f64::from(radius);
    let disc = r2 - l.dot(l);
    if disc < 0.0 {
        return None;
    }
    let ff = f.dot(f);
    let q = b + (a * disc).sqrt().copysign(b);
    if q == 0.0 {
        return None;
    }
    let (t0, t1) = ((ff - r2) / q, q / a);
    let spread = 16.0 * f64::EPSILON * ((ff + r2) / q.abs());
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    let inside =
        |t: f64| t - (spread + 16.0 * f64::EPSILON * t.abs()) > f64::from(t_min) && (t as f32) < t_max;
    [near, far].into_iter().find(|&t| inside(t)).map(|t| t as f32).filter(|&t| t > t_min)
}

/// The hit point of `ray` at `t` on the sphere, its outward unit normal, and a conservative
/// bound on the point's distance from the true surface along that normal.
///
/// The point is reprojected onto the sphere (the ray's `origin + t·dir` is off by the error of
/// `t` times the ray's length; the reprojected point is within `γ(5)·r` of the sphere, pbrt-v4's
/// bound), then placed in the world, which adds half an ulp of its coordinates. Where rounding
/// put the point on the centre (a sphere smaller than the float spacing of its coordinates),
/// the normal falls back as [`normal`] explains and the bound is the whole radius.
#[inline]
pub fn surface_point(centre: Vec3, radius: f32, ray: &Ray, t: f32) -> (Vec3, Vec3, f32) {
    let p = ray.at(t);
    let Some((n, _)) = unit_and_length(p - centre) else {
        return (p, normal(centre, radius, p, ray), radius + gamma(2) * p.abs().max_element());
    };
    let local = n * radius;
    let point = centre + local;
    let error = local.abs() * gamma(5) + point.abs() * gamma(2);
    (point, n, error.dot(n.abs()))
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
    let dir = ray.dir.normalize_or(Vec3::Z);
    if inside {
        dir
    } else {
        -dir
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
