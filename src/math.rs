//! Math shared by every layer: glam re-exports, rays, axis-aligned boxes and ray offsets.

pub use glam::{Affine3A, DVec3, Mat3, Mat3A, Quat, Vec2, Vec3, Vec3A};

/// A ray `origin + t * dir`; `dir` is unit length for every ray the tracer makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: Vec3,
    /// Direction (unit length in world space).
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// An axis-aligned bounding box; empty when `min > max` on some axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Default for Aabb {
    /// The empty box, [`Aabb::EMPTY`].
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box, identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// The box spanning two corners.
    #[inline]
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The smallest box holding every point.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grow(p))
    }

    /// This box grown to hold `p`.
    #[inline]
    pub fn grow(self, p: Vec3) -> Self {
        Self::new(self.min.min(p), self.max.max(p))
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(self, other: Aabb) -> Self {
        Self::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// True when the box holds no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Size along each axis (zero or negative when empty).
    #[inline]
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// True when the closed boxes share at least one point. Branch-free (all six comparisons,
    /// one mask), so packet walks can screen a cell's objects with it without a branch each.
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (self.min.cmple(other.max) & other.min.cmple(self.max)).bitmask() == 0b111
    }

    /// The box holding this box after an affine map (all eight corners transformed).
    pub fn transformed(&self, m: &Affine3A) -> Aabb {
        let corners = (0..8).map(|i| {
            let pick = |bit: u32, lo: f32, hi: f32| if i & bit == 0 { lo } else { hi };
            m.transform_point3(Vec3::new(
                pick(1, self.min.x, self.max.x),
                pick(2, self.min.y, self.max.y),
                pick(4, self.min.z, self.max.z),
            ))
        });
        Aabb::from_points(corners)
    }

    /// Parametric range `[t0, t1]` where the ray is inside the closed box, clipped to `[t_min, t_max]`.
    ///
    /// `inv_dir` is `1 / ray.dir` per axis. An axis where the direction is zero (either sign)
    /// imposes no limit when the origin lies within that slab, walls included, and misses otherwise.
    #[inline]
    pub fn clip_ray(&self, ray: &Ray, inv_dir: Vec3, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        // Plain arrays, not `Vec3` indexing: the loop unrolls into straight-line code.
        let (o, d, inv) = (ray.origin.to_array(), ray.dir.to_array(), inv_dir.to_array());
        let (lo, hi) = (self.min.to_array(), self.max.to_array());
        let (mut t0, mut t1) = (t_min, t_max);
        let mut outside = false;
        for axis in 0..3 {
            if d[axis] == 0.0 {
                outside |= o[axis] < lo[axis] || o[axis] > hi[axis];
                continue;
            }
            let a = (lo[axis] - o[axis]) * inv[axis];
            let b = (hi[axis] - o[axis]) * inv[axis];
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        (!outside && t0 <= t1).then_some((t0, t1))
    }

    /// [`Self::clip_ray`] of the `live` lanes of `packet`, each clipped to `[t_min, t_max]`
    /// of its lane, lane by lane without a branch: per lane whether it meets the box, and
    /// where it does, the same range as [`Self::clip_ray`] (elsewhere the ranges are
    /// meaningless). Inline it into a [`crate::simd::SimdLevel::run`] closure to get the
    /// level's vectors.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn clip_lanes<const N: usize>(
        &self,
        packet: &RayPacket<N>,
        live: &[bool; N],
        t_max: &[f32; N],
    ) -> ([bool; N], [f32; N], [f32; N]) {
        let (mut meets, mut t0, mut t1) = (*live, packet.t_min, *t_max);
        for axis in 0..3 {
            let (lo, hi) = (self.min[axis], self.max[axis]);
            for i in 0..N {
                let o = packet.origin[axis][i];
                let inv = packet.inv_dir[axis][i];
                // A lane that does not move along this axis: inside the slab or a miss.
                let flat = packet.dir[axis][i] == 0.0;
                // `&` and `|`, not `&&` and `||`: no branch per lane, so the lanes stay in vectors.
                meets[i] &= !(flat & ((o < lo) | (o > hi)));
                let a = (lo - o) * inv;
                let b = (hi - o) * inv;
                t0[i] = if flat { t0[i] } else { t0[i].max(a.min(b)) };
                t1[i] = if flat { t1[i] } else { t1[i].min(a.max(b)) };
            }
        }
        for i in 0..N {
            meets[i] &= t0[i] <= t1[i];
        }
        (meets, t0, t1)
    }
}

/// Unit roundoff of f32: half the spacing of floats at 1.
pub const UNIT_ROUNDOFF: f32 = f32::EPSILON * 0.5;

/// Higham's `γ(n) = n·u / (1 − n·u)`: a bound on the relative error of `n` chained f32
/// operations (pbrt-v4's `gamma`). Error bounds on hit points are built from it.
#[inline]
pub const fn gamma(n: u32) -> f32 {
    let nu = n as f32 * UNIT_ROUNDOFF;
    nu / (1.0 - nu)
}

/// How far a shadow ray stops short of its light, as a fraction of its length: geometry that the
/// light lies on (a lamp's own shade, a ceiling an area light is set into) does not shadow it.
pub const SHADOW_EPSILON: f32 = 1.0 / 8192.0;

/// The origin of a ray leaving the surface point `p` on the side of unit normal `n` that `dir`
/// points into (pbrt-v4's `OffsetRayOrigin`).
///
/// `error` is a conservative bound on the distance between `p` and the true surface along `n`
/// (each shape computes its own, see [`crate::store::SurfacePoint::error`]). The point moves
/// that far along `n`, plus two units of roundoff of each coordinate in the same direction, so
/// that rounding the sum (half a unit at most) cannot bring it back: every coordinate that moves
/// ends at least `error·|n_i|` out, as pbrt's one-float nudge ensures, without a branch per
/// coordinate. The offset depends on the arithmetic that produced `p`, not on how far `p` lies
/// from the world origin.
#[inline(always)]
pub fn offset_origin(p: Vec3, error: f32, n: Vec3, dir: Vec3) -> Vec3 {
    // Lane-wise in `Vec3A` (one SIMD instruction per step, the same IEEE operation per
    // coordinate as three scalar ones).
    let (p, n) = (Vec3A::from(p), Vec3A::from(n));
    let offset = if dir.dot(n.into()) < 0.0 { n * -error } else { n * error };
    let spare = ((p.abs() + offset.abs()) * (2.0 * UNIT_ROUNDOFF)).copysign(offset);
    (p + offset + Vec3A::select(offset.cmpeq(Vec3A::ZERO), Vec3A::ZERO, spare)).into()
}

/// The entry-wise absolute value of a matrix, for bounding the rounding of a transform.
#[inline]
pub fn abs_matrix(m: Mat3A) -> Mat3A {
    Mat3A::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs())
}

/// A bound on the rounding error of `m.transform_point3(p)` for an exact `p`, per axis (the
/// pbrt-v4 bound: `γ(3)·(|M|·|p| + |t|)`).
#[inline]
pub fn transform_error(m: &Affine3A, p: Vec3) -> Vec3 {
    let abs: Vec3 = (abs_matrix(m.matrix3) * Vec3A::from(p.abs())).into();
    (abs + Vec3::from(m.translation.abs())) * gamma(3)
}

/// Mirror reflection of incoming direction `d` about unit normal `n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refraction of unit `d` through unit normal `n` (facing against `d`) with `eta = n_i / n_t`;
/// `None` on total internal reflection.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize())
}

/// The unit vector along `v` and `v`'s length, computed on `v` divided by its largest
/// component so that `v · v` can neither overflow nor underflow (the length itself may round
/// to +∞ when `v` is near `f32::MAX`); `None` for a zero or non-finite `v`. The fallback for
/// where `normalize` and `length` would give NaN or zero.
pub fn unit_and_length(v: Vec3) -> Option<(Vec3, f32)> {
    let m = v.abs().max_element();
    if !(m > 0.0 && v.is_finite()) {
        return None;
    }
    let u = v / m;
    let len = u.length();
    Some((u / len, m * len))
}

/// `N` rays in structure-of-arrays form, with each lane's parametric range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayPacket<const N: usize> {
    /// Origins, one array per axis.
    pub origin: [[f32; N]; 3],
    /// Directions (any non-zero length), one array per axis.
    pub dir: [[f32; N]; 3],
    /// Reciprocal directions, one array per axis.
    pub inv_dir: [[f32; N]; 3],
    /// Lower end of each lane's range (exclusive).
    pub t_min: [f32; N],
    /// Upper end of each lane's range (exclusive).
    pub t_max: [f32; N],
    /// Lanes that carry a ray.
    pub active: [bool; N],
}

impl<const N: usize> Default for RayPacket<N> {
    fn default() -> Self {
        Self {
            origin: [[0.0; N]; 3],
            dir: [[0.0; N]; 3],
            inv_dir: [[0.0; N]; 3],
            t_min: [0.0; N],
            t_max: [0.0; N],
            active: [false; N],
        }
    }
}

impl<const N: usize> RayPacket<N> {
    /// Puts `ray` with range `(t_min, t_max)` in lane `i` and marks it active.
    #[inline]
    pub fn set(&mut self, i: usize, ray: &Ray, t_min: f32, t_max: f32) {
        let inv = ray.dir.recip();
        for axis in 0..3 {
            self.origin[axis][i] = ray.origin[axis];
            self.dir[axis][i] = ray.dir[axis];
            self.inv_dir[axis][i] = inv[axis];
        }
        self.t_min[i] = t_min;
        self.t_max[i] = t_max;
        self.active[i] = true;
    }

    /// Puts `ray` in lane `i` as [`Self::set`] does, but leaves its reciprocal direction for
    /// [`Self::reciprocals`] to work out together with the other lanes'.
    #[inline]
    pub fn put(&mut self, i: usize, ray: &Ray, t_min: f32, t_max: f32) {
        for axis in 0..3 {
            self.origin[axis][i] = ray.origin[axis];
            self.dir[axis][i] = ray.dir[axis];
        }
        self.t_min[i] = t_min;
        self.t_max[i] = t_max;
        self.active[i] = true;
    }

    /// The reciprocal direction of every active lane, worked out lane by lane so that the
    /// lanes' divisions share instructions: the same bits as [`Self::set`] gives (inactive
    /// lanes get 0). Inline it into a [`crate::simd::SimdLevel::run`] closure to get the
    /// level's vectors.
    #[inline(always)]
    pub fn reciprocals(&mut self) {
        for axis in 0..3 {
            for i in 0..N {
                let inv = 1.0 / self.dir[axis][i];
                self.inv_dir[axis][i] = if self.active[i] { inv } else { 0.0 };
            }
        }
    }

    /// The ray in lane `i`.
    #[inline]
    pub fn ray(&self, i: usize) -> Ray {
        Ray::new(
            Vec3::new(self.origin[0][i], self.origin[1][i], self.origin[2][i]),
            Vec3::new(self.dir[0][i], self.dir[1][i], self.dir[2][i]),
        )
    }

    /// The packet mapped into an instance's object space lane by lane, exactly as
    /// [`crate::store::mesh::object_ray`] maps a single ray (the same products and sums in the
    /// same order as glam's `transform_point3` and `transform_vector3`, and the reciprocal
    /// [`Self::set`] takes; ranges and lanes unchanged, dead lanes zero), the lanes sharing
    /// vector instructions.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn mapped(&self, to_object: &Affine3A, live: &[bool; N]) -> Self {
        let mut out = Self { t_min: self.t_min, t_max: self.t_max, active: *live, ..Self::default() };
        let m = &to_object.matrix3;
        let axes = [m.x_axis, m.y_axis, m.z_axis].map(|a| a.to_array());
        let shift = to_object.translation.to_array();
        let (o, d) = (&self.origin, &self.dir);
        for r in 0..3 {
            for i in 0..N {
                let origin = axes[0][r] * o[0][i] + axes[1][r] * o[1][i] + axes[2][r] * o[2][i] + shift[r];
                let dir = axes[0][r] * d[0][i] + axes[1][r] * d[1][i] + axes[2][r] * d[2][i];
                let inv = 1.0 / dir;
                out.origin[r][i] = if live[i] { origin } else { 0.0 };
                out.dir[r][i] = if live[i] { dir } else { 0.0 };
                out.inv_dir[r][i] = if live[i] { inv } else { 0.0 };
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_ray_handles_axis_parallel_rays_inside_and_outside_slabs() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        let inv = ray.dir.recip();
        assert_eq!(b.clip_ray(&ray, inv, 0.0, f32::INFINITY), Some((1.0, 2.0)));
        let outside = Ray::new(Vec3::new(2.0, 0.5, -1.0), Vec3::Z);
        assert_eq!(b.clip_ray(&outside, outside.dir.recip(), 0.0, f32::INFINITY), None);
        // Ray lying exactly in the slab's boundary plane x = 0: 0 * inf = NaN must not poison it.
        let on_wall = Ray::new(Vec3::new(0.0, 0.5, -1.0), Vec3::Z);
        assert_eq!(b.clip_ray(&on_wall, on_wall.dir.recip(), 0.0, f32::INFINITY), Some((1.0, 2.0)));
    }

    #[test]
    fn an_offset_origin_is_at_least_the_error_out_on_every_moving_axis() {
        // Points where rounding the sum would pull a plain `p + n·error` back, all signs.
        for p in [Vec3::new(1.0, -3.0, 7.5e5), Vec3::new(-1e-30, 2.5, -0.0), Vec3::new(4e7, -4e7, 1.0)] {
            for n in [Vec3::new(0.6, 0.0, -0.8), Vec3::new(-0.36, 0.48, 0.8), Vec3::Y] {
                let error = 1e-9;
                for dir in [n, -n] {
                    let po = offset_origin(p, error, n, dir);
                    let side = if dir.dot(n) < 0.0 { -n } else { n };
                    for i in 0..3 {
                        let moved = (po[i] as f64 - p[i] as f64) * side[i].signum() as f64;
                        if side[i] == 0.0 {
                            assert_eq!(po[i], p[i], "{p} {n}: axis {i} moved");
                        } else {
                            assert!(
                                moved >= (error * side[i].abs()) as f64 && moved > 0.0,
                                "{p} {n} axis {i}: {moved}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn refract_obeys_snell_and_reports_total_internal_reflection() {
        let n = Vec3::Y;
        let theta_i = 30f32.to_radians();
        let d = Vec3::new(theta_i.sin(), -theta_i.cos(), 0.0);
        let t = refract(d, n, 1.0 / 1.5).unwrap();
        let sin_t = t.x;
        assert!((theta_i.sin() - 1.5 * sin_t).abs() < 1e-6);
        // From glass to air past the critical angle asin(1/1.5) = 41.8 degrees.
        let steep = 45f32.to_radians();
        let d = Vec3::new(steep.sin(), -steep.cos(), 0.0);
        assert!(refract(d, n, 1.5).is_none());
    }

    #[test]
    fn unit_and_length_survives_huge_and_tiny_vectors() {
        for (v, len) in [
            (Vec3::new(3e30, 4e30, 0.0), 5e30),
            (Vec3::new(0.0, -3e-30, 4e-30), 5e-30),
            (Vec3::new(3.0, 4.0, 0.0), 5.0),
            (Vec3::new(1e-45, 0.0, 0.0), 1e-45),
        ] {
            let (u, l) = unit_and_length(v).unwrap();
            assert!((u.length() - 1.0).abs() < 1e-6 && (u - v / len).length() < 1e-6, "{v} -> {u}");
            assert!((l / len - 1.0).abs() < 1e-6, "{v}: {l}");
        }
        let (u, l) = unit_and_length(Vec3::splat(f32::MAX)).unwrap();
        assert!(u.is_finite() && (u.length() - 1.0).abs() < 1e-6 && l == f32::INFINITY);
        assert_eq!(unit_and_length(Vec3::ZERO), None);
        assert_eq!(unit_and_length(Vec3::new(f32::NAN, 1.0, 0.0)), None);
        assert_eq!(unit_and_length(Vec3::new(f32::INFINITY, 1.0, 0.0)), None);
    }
}
