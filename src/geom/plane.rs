//! Infinite plane `n · p = d`: unbounded, so it lives outside the grid and is always tested.

use crate::math::{gamma, Ray, RayPacket, Vec3};

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

/// [`intersect`] for the `live` lanes of a packet at once, each within `(t_min, bound)`: the same
/// IEEE operations in the same order as the scalar test (glam's dot products,
/// `(x·x' + y·y') + z·z'`), lane-wise and without branches, so every lane's `t` has the scalar
/// hit's bits. A lane's hit is passed to `record(lane, t)`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
pub fn intersect_lanes<const N: usize>(
    normal: Vec3,
    offset: f32,
    packet: &RayPacket<N>,
    live: &[bool; N],
    t_min: &[f32; N],
    bound: &[f32; N],
    mut record: impl FnMut(usize, f32),
) {
    let [ox, oy, oz] = &packet.origin;
    let [dx, dy, dz] = &packet.dir;
    let mut found = [f32::NAN; N];
    for i in 0..N {
        let denom = normal.x * dx[i] + normal.y * dy[i] + normal.z * dz[i];
        let t = (offset - (normal.x * ox[i] + normal.y * oy[i] + normal.z * oz[i])) / denom;
        // A parallel ray (`denom == 0`) misses, whatever its `t` (±∞ or NaN) says.
        let hit = live[i] & (denom != 0.0) & (t > t_min[i]) & (t < bound[i]);
        found[i] = if hit { t } else { f32::NAN };
    }
    for i in 0..N {
        if !found[i].is_nan() {
            record(i, found[i]);
        }
    }
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
