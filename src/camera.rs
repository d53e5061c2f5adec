//! The camera: a pinhole, or a thin lens with an aperture and a focal plane (depth of field).

use crate::math::{unit_and_length, Ray, RayPacket, Vec2, Vec3};

/// When the shutter is open, as fractions of the frame interval from the frame's time: motion
/// blur integrates the scene over `[open, close]`. Validated to `0 ≤ open ≤ close ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shutter {
    /// Opening, as a fraction of the frame interval.
    pub open: f32,
    /// Closing, as a fraction of the frame interval (≥ `open`).
    pub close: f32,
}

impl Shutter {
    /// The shutter `(open, close)`, or the rule it breaks unless `0 ≤ open ≤ close ≤ 1`: the
    /// rule every source of a shutter (scene file, command line) is checked against.
    pub fn new(open: f32, close: f32) -> Result<Self, String> {
        match (0.0..=1.0).contains(&open) && (0.0..=1.0).contains(&close) && open <= close {
            true => Ok(Self { open, close }),
            false => Err(format!(
                "must be (open, close) with 0 <= open <= close <= 1 (fractions of the frame interval), got ({open}, {close})"
            )),
        }
    }
}

/// A pinhole or thin-lens camera. Image x grows right, y grows down; the view looks along
/// `forward`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position (the lens centre).
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit right vector.
    pub right: Vec3,
    /// Unit up vector, orthogonal to `forward` and `right`.
    pub up: Vec3,
    /// Vertical field of view in radians ([`Camera::fov_y`]).
    fov_y: f32,
    /// `tan(fov_y / 2)`: half the image plane's height at distance 1, computed once here
    /// rather than once per camera ray.
    half_height: f32,
    /// Lens radius; 0 is a pinhole (everything sharp).
    pub aperture: f32,
    /// Distance along `forward` of the plane in focus.
    pub focus_distance: f32,
}

impl Camera {
    /// A pinhole camera at `position` looking at `look_at`, with `up` as the rough up direction.
    /// The caller guarantees `look_at ≠ position` and `up` not parallel to the view (validated on load).
    pub fn look_at(position: Vec3, look_at: Vec3, up: Vec3, fov_y: f32) -> Self {
        let forward = (look_at - position).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        let focus_distance = (look_at - position).length();
        let half_height = (0.5 * fov_y).tan();
        Self { position, forward, right, up, fov_y, half_height, aperture: 0.0, focus_distance }
    }

    /// Vertical field of view in radians.
    #[inline]
    pub fn fov_y(&self) -> f32 {
        self.fov_y
    }

    /// The same camera with a thin lens of radius `aperture` focused at `focus_distance`.
    pub fn with_lens(self, aperture: f32, focus_distance: f32) -> Self {
        Self { aperture, focus_distance, ..self }
    }

    /// True when the camera has a finite aperture (rays need lens samples).
    #[inline]
    pub fn has_lens(&self) -> bool {
        self.aperture > 0.0
    }

    /// Unnormalised direction through continuous image coordinates `(px, py)` of a
    /// `width × height` image, with `forward` component 1 (pixel `(i, j)` covers
    /// `[i, i+1) × [j, j+1)`; its centre is `(i + 0.5, j + 0.5)`).
    #[inline]
    fn direction(&self, px: f32, py: f32, width: u32, height: u32) -> Vec3 {
        let half_h = self.half_height;
        let half_w = half_h * width as f32 / height as f32;
        let sx = (2.0 * px / width as f32 - 1.0) * half_w;
        let sy = (1.0 - 2.0 * py / height as f32) * half_h;
        self.forward + sx * self.right + sy * self.up
    }

    /// The pinhole ray through image coordinates `(px, py)`.
    #[inline]
    pub fn ray(&self, px: f32, py: f32, width: u32, height: u32) -> Ray {
        Ray::new(self.position, self.direction(px, py, width, height).normalize())
    }

    /// The pinhole rays through the image points `point` of the `active` lanes, as a packet
    /// with range `(0, ∞)`: lane by lane the bits of [`Self::ray`] and of
    /// [`RayPacket::set`]'s reciprocals, worked out together so that the lanes' divisions and
    /// square roots share instructions (inactive lanes are left as
    /// [`RayPacket::default`] has them). Inline it into a [`crate::simd::SimdLevel::run`]
    /// closure to get the level's vectors.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn pinhole_lanes<const N: usize>(
        &self,
        point: &[Vec2; N],
        active: &[bool; N],
        width: u32,
        height: u32,
    ) -> RayPacket<N> {
        // `direction`, then `normalize` (`v * (1 / |v|)`), in the same order.
        let half_h = self.half_height;
        let half_w = half_h * width as f32 / height as f32;
        let (w, h) = (width as f32, height as f32);
        let mut d = [[0.0f32; N]; 3];
        for i in 0..N {
            let sx = (2.0 * point[i].x / w - 1.0) * half_w;
            let sy = (1.0 - 2.0 * point[i].y / h) * half_h;
            for axis in 0..3 {
                d[axis][i] = self.forward[axis] + sx * self.right[axis] + sy * self.up[axis];
            }
        }
        let mut packet = RayPacket::<N>::default();
        for i in 0..N {
            let scale = 1.0 / (d[0][i] * d[0][i] + d[1][i] * d[1][i] + d[2][i] * d[2][i]).sqrt();
            for axis in 0..3 {
                packet.origin[axis][i] = if active[i] { self.position[axis] } else { 0.0 };
                packet.dir[axis][i] = if active[i] { d[axis][i] * scale } else { 0.0 };
            }
            packet.t_max[i] = if active[i] { f32::INFINITY } else { 0.0 };
        }
        packet.active = *active;
        packet.reciprocals();
        packet
    }

    /// The thin-lens ray through image coordinates `(px, py)` leaving the lens at `lens`, a
    /// point of the unit disk: it starts on the aperture and passes through the point where the
    /// pinhole ray meets the plane in focus, so that plane is sharp for any aperture.
    ///
    /// Safe for any finite aperture: where the lens point is so far from the focus point that
    /// the squared distance overflows (or so near that it underflows), the direction is taken
    /// from the scaled vector; a lens point on the focus point looks along `forward`.
    #[inline]
    pub fn lens_ray(&self, px: f32, py: f32, width: u32, height: u32, lens: Vec2) -> Ray {
        let d = self.direction(px, py, width, height);
        let focus = self.position + d * self.focus_distance;
        let origin = self.position + self.aperture * (lens.x * self.right + lens.y * self.up);
        let to = focus - origin;
        let len2 = to.length_squared();
        let dir = if len2.is_finite() && len2 >= f32::MIN_POSITIVE {
            to.normalize()
        } else {
            unit_and_length(to).map_or(self.forward, |(unit, _)| unit)
        };
        Ray::new(origin, dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_forward_and_edge_rays_span_the_field_of_view() {
        let cam = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 90f32.to_radians());
        let centre = cam.ray(50.0, 50.0, 100, 100);
        assert!((centre.dir - Vec3::Z).length() < 1e-6);
        let top = cam.ray(50.0, 0.0, 100, 100);
        assert!((top.dir.angle_between(Vec3::Z) - 45f32.to_radians()).abs() < 1e-5);
        assert!(top.dir.y > 0.0);
        let right = cam.ray(100.0, 50.0, 100, 100);
        assert!(right.dir.x < 0.0, "right-handed, y up, looking down +z: right is -x");
    }

    #[test]
    fn lens_rays_meet_the_pinhole_ray_on_the_focal_plane() {
        let cam = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 0.0, 10.0), Vec3::Y, 0.7)
            .with_lens(0.4, 6.0);
        let pin = cam.ray(13.0, 7.0, 40, 30);
        let depth = 6.0 / pin.dir.dot(cam.forward);
        let target = pin.at(depth);
        for lens in [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(-0.3, 0.8), Vec2::new(0.0, -1.0)] {
            let r = cam.lens_ray(13.0, 7.0, 40, 30, lens);
            let t = (target - r.origin).dot(r.dir);
            assert!((r.at(t) - target).length() < 1e-4, "lens point {lens} misses the focus point");
            assert!(((r.origin - cam.position).length() - 0.4 * lens.length()).abs() < 1e-5);
        }
        let centre = cam.lens_ray(13.0, 7.0, 40, 30, Vec2::ZERO);
        assert!((centre.dir - pin.dir).length() < 1e-6, "the lens centre is the pinhole");
    }

    #[test]
    fn huge_apertures_give_unit_directions_towards_the_focus_point() {
        let base = Camera::look_at(Vec3::new(0.0, 1.0, -5.0), Vec3::new(0.0, 0.5, 0.0), Vec3::Y, 1.0);
        for aperture in [1e9f32, 1e17, 1e18, 1e30, f32::MAX] {
            let cam = base.with_lens(aperture, 5.0);
            let pin = cam.ray(20.0, 15.0, 32, 24);
            let target = pin.at(5.0 / pin.dir.dot(cam.forward));
            for lens in [Vec2::new(1.0, 0.0), Vec2::new(-0.3, 0.8), Vec2::new(0.0, -1e-3)] {
                let r = cam.lens_ray(20.0, 15.0, 32, 24, lens);
                assert!(r.origin.is_finite() && r.dir.is_finite(), "aperture {aperture}, lens {lens}: {r:?}");
                assert!((r.dir.length() - 1.0).abs() < 1e-5, "aperture {aperture}: {}", r.dir);
                // Towards the focus point: the direction from the origin to it, to f32 precision.
                let (towards, _) = unit_and_length(target - r.origin).unwrap();
                assert!((r.dir - towards).length() < 1e-5, "aperture {aperture}, lens {lens}");
            }
        }
    }
}
