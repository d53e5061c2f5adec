//! Sphere: centre and radius.

use crate::math::{gamma, unit_and_length, Aabb, Ray, Vec3};

/// The bounds of a sphere.
#[inline]
pub fn bounds(centre: Vec3, radius: f32) -> Aabb {
    Aabb::new(centre - Vec3::splat(radius), centre + Vec3::splat(radius))
}

/// False only where the sphere certainly misses the closed box `b`: its bounds, widened by
/// their own rounding (a few ulps of the largest coordinate), miss it. Branch-free, for packets
/// screening a cell's objects against a slice's footprint.
#[inline(always)]
pub fn bounds_meet(centre: Vec3, radius: f32, b: &Aabb) -> bool {
    let reach = radius + 4.0 * f32::EPSILON * (centre.abs().max_element() + radius);
    b.overlaps(&bounds(centre, reach))
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
#[inline(always)]
pub fn intersect(centre: Vec3, radius: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let d = ray.dir;
    let f = ray.origin - centre;
    let a = d.dot(d);
    let b = -f.dot(d);
    // The closest approach is at `b / a`; a unit direction (the tracer's) skips the division,
    // which changes `b` by at most 3 ulps, inside the error bound below.
    let s = if unit(a) { b } else { b / a };
    let l = f + s * d;
    let r2 = radius * radius;
    let ll = l.dot(l);
    let disc = r2 - ll;
    // `l` is off by at most γ(12)·(|f_i| + m·|d_i|) ≤ 2·γ(12)·|f| per component
    // (`m = (|f|·|d|)/a`, Cauchy–Schwarz), so `|l|²` by at most 4·γ(12)·|l|·|f| + … ≤
    // 2·γ(12)·(|l|² + |f|²), and `r²` by half an ulp: a cheap bound (with `|f|² = |l|² + s·b`,
    // a sum of two positive terms, so no dot product is spent on it); only rays inside it get the
    // tight one.
    if disc.abs() <= ll * COARSE_LL + s * b * COARSE_SB + r2 * COARSE_R2 {
        return near_tangent(centre, radius, ray, t_min, t_max, (f, a, b, ll));
    }
    if disc < 0.0 {
        return None;
    }
    roots(a, b, disc, f.dot(f), r2, t_min, t_max)
}

/// The cheap bound `2·γ(13)·(2·|l|² + s·b) + γ(3)·(|l|² + r²)`, its terms gathered.
const COARSE_LL: f32 = 4.0 * gamma(13) + gamma(3);
const COARSE_SB: f32 = 2.0 * gamma(13);
const COARSE_R2: f32 = gamma(3);

/// True when `a = dir·dir` is 1 to within its rounding: a unit direction.
#[inline]
fn unit(a: f32) -> bool {
    (a - 1.0).abs() <= 4.0 * f32::EPSILON
}

/// The nearer root of the two in `(t_min, t_max)` that clears `t_min` by its error bound.
#[inline(always)]
fn roots(a: f32, b: f32, disc: f32, ff: f32, r2: f32, t_min: f32, t_max: f32) -> Option<f32> {
    let q = b + (a * disc).sqrt().copysign(b);
    let t0 = (ff - r2) / q;
    let t1 = if unit(a) { q } else { q / a };
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    // Either root is off by the error of `c = |f|² − r²` over `|q|` plus a few ulps of itself:
    // `t − t_min > γ(8)·((|f|² + r²)/|q| + |t|)`, multiplied through by `|q|`.
    let c_error = gamma(8) * (ff + r2);
    let qa = q.abs();
    let inside = |t: f32| t > t_min && t < t_max && (t - t_min - gamma(8) * t.abs()) * qa > c_error;
    if inside(near) {
        Some(near)
    } else if inside(far) {
        Some(far)
    } else {
        None
    }
}

/// A ray the cheap bound could not decide: the tight bound on the rounding error of
/// `r² − |l|²` (`2·|l|·|δl| + |δl|² + γ(3)·(|l|² + r²)` with `|δl_i| ≤ γ(12)·(|f_i| + m·|d_i|)`),
/// and, within it, the whole test again in f64.
#[cold]
#[inline(never)]
fn near_tangent(
    centre: Vec3,
    radius: f32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    (f, a, b, ll): (Vec3, f32, f32, f32),
) -> Option<f32> {
    let d = ray.dir;
    let ff = f.dot(f);
    let r2 = radius * radius;
    let m = f.abs().dot(d.abs()) / a;
    let dl = (f.abs() + d.abs() * m) * gamma(12);
    let dl2 = dl.dot(dl);
    let error = 2.0 * (ll * dl2).sqrt() + dl2 + gamma(3) * (ll + r2);
    let disc = r2 - ll;
    if disc.abs() <= error {
        return intersect_f64(centre, radius, ray, t_min, t_max);
    }
    if disc < 0.0 {
        return None;
    }
    roots(a, b, disc, ff, r2, t_min, t_max)
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
/// the normal falls back as [`normal`] explains and the bound is the whole radius. Always
/// inlined: the tuple returned through memory was read back with loads wider than its stores.
#[inline(always)]
pub fn surface_point(centre: Vec3, radius: f32, ray: &Ray, t: f32) -> (Vec3, Vec3, f32) {
    let p = ray.at(t);
    let v = p - centre;
    let n = match v.normalize_or_zero() {
        n if n != Vec3::ZERO => n,
        // |p − c|² underflowed or overflowed: scale first.
        _ => match unit_and_length(v) {
            Some((n, _)) => n,
            None => return (p, normal(centre, radius, p, ray), radius + gamma(2) * p.abs().max_element()),
        },
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

/// [`intersect`] for the `live` lanes of a packet, each within `(t_min, bound)`: a lane it hits
/// gets `record(lane, t)` and its bound moves to `t`. Bit for bit [`intersect`] on every lane:
/// the same operations in the same order, lane-wise; a lane near the tangent (the cold path)
/// is handed to [`intersect`] itself.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
pub fn intersect_lanes<const N: usize>(
    centre: Vec3,
    radius: f32,
    packet: &crate::math::RayPacket<N>,
    live: &[bool; N],
    bound: &mut [f32; N],
    mut record: impl FnMut(usize, f32),
) {
    let r2 = radius * radius;
    let mut found = [f32::NAN; N];
    let mut cold = [false; N];
    for i in 0..N {
        let (dx, dy, dz) = (packet.dir[0][i], packet.dir[1][i], packet.dir[2][i]);
        let (fx, fy, fz) =
            (packet.origin[0][i] - centre.x, packet.origin[1][i] - centre.y, packet.origin[2][i] - centre.z);
        let a = dx * dx + dy * dy + dz * dz;
        let b = -(fx * dx + fy * dy + fz * dz);
        let unit_a = (a - 1.0).abs() <= 4.0 * f32::EPSILON;
        let s = if unit_a { b } else { b / a };
        let (lx, ly, lz) = (fx + s * dx, fy + s * dy, fz + s * dz);
        let ll = lx * lx + ly * ly + lz * lz;
        let disc = r2 - ll;
        cold[i] = live[i] & (disc.abs() <= ll * COARSE_LL + s * b * COARSE_SB + r2 * COARSE_R2);
        // `roots`, lane-wise.
        let ff = fx * fx + fy * fy + fz * fz;
        let q = b + (a * disc).sqrt().copysign(b);
        let t0 = (ff - r2) / q;
        let t1 = if unit_a { q } else { q / a };
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let c_error = gamma(8) * (ff + r2);
        let qa = q.abs();
        let (lo, hi) = (packet.t_min[i], bound[i]);
        let inside = |t: f32| t > lo && t < hi && (t - lo - gamma(8) * t.abs()) * qa > c_error;
        let t = if inside(near) {
            near
        } else if inside(far) {
            far
        } else {
            f32::NAN
        };
        // `disc < 0.0` misses; a NaN goes on to the roots, as in `intersect`, and misses there.
        found[i] = if live[i] & !cold[i] & (disc >= 0.0 || disc.is_nan()) { t } else { f32::NAN };
    }
    for i in 0..N {
        if cold[i] {
            if let Some(t) = intersect(centre, radius, &packet.ray(i), packet.t_min[i], bound[i]) {
                bound[i] = t;
                record(i, t);
            }
        } else if !found[i].is_nan() {
            bound[i] = found[i];
            record(i, found[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_meet_every_box_the_sphere_touches_and_screen_out_boxes_it_misses() {
        // Boxes touching the sphere exactly (on a face, at the pole) and far from the origin,
        // where the bounds' own rounding matters; then boxes clearly apart.
        let cases = [(Vec3::ZERO, 1.0), (Vec3::new(1e5, -3e4, 7.0), 0.01), (Vec3::splat(-2.5), 1e-4)];
        for (c, r) in cases {
            for axis in 0..3 {
                for sign in [-1.0f32, 1.0] {
                    let mut pole = c;
                    pole[axis] += sign * r;
                    let touching = Aabb::new(pole, pole);
                    assert!(bounds_meet(c, r, &touching), "{c} {r}: pole box on axis {axis}");
                    let mut away = pole;
                    away[axis] += sign * (r + c.abs().max_element() * 1e-3 + 1e-3);
                    let apart = Aabb::new(away, away + Vec3::splat(sign.max(0.0)));
                    assert!(!bounds_meet(c, r, &apart), "{c} {r}: box beyond the pole on axis {axis}");
                }
            }
        }
        // Conservative against the exact test on a lattice of boxes around a sphere.
        let (c, r) = (Vec3::new(0.3, -0.2, 0.1), 0.7);
        for i in 0..400 {
            let lo = Vec3::new((i % 7) as f32, (i / 7 % 7) as f32, (i / 49) as f32) * 0.3 - 1.2;
            let b = Aabb::new(lo, lo + Vec3::splat(0.25));
            if overlaps_box(c, r, &b) {
                assert!(bounds_meet(c, r, &b), "box {b:?}");
            }
        }
    }

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
