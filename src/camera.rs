//! The pinhole camera: eye, orthonormal frame and vertical field of view.

use crate::math::{Ray, Vec3};

/// A pinhole camera. Image x grows right, y grows down; the view looks along `forward`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit right vector.
    pub right: Vec3,
    /// Unit up vector, orthogonal to `forward` and `right`.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
}

impl Camera {
    /// A camera at `position` looking at `look_at`, with `up` as the rough up direction.
    /// The caller guarantees `look_at ≠ position` and `up` not parallel to the view (validated on load).
    pub fn look_at(position: Vec3, look_at: Vec3, up: Vec3, fov_y: f32) -> Self {
        let forward = (look_at - position).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        Self { position, forward, right, up, fov_y }
    }

    /// The primary ray through continuous image coordinates `(px, py)` of a `width × height`
    /// image (pixel `(i, j)` covers `[i, i+1) × [j, j+1)`; its centre is `(i + 0.5, j + 0.5)`).
    #[inline]
    pub fn ray(&self, px: f32, py: f32, width: u32, height: u32) -> Ray {
        let half_h = (0.5 * self.fov_y).tan();
        let half_w = half_h * width as f32 / height as f32;
        let sx = (2.0 * px / width as f32 - 1.0) * half_w;
        let sy = (1.0 - 2.0 * py / height as f32) * half_h;
        Ray::new(self.position, (self.forward + sx * self.right + sy * self.up).normalize())
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
}
