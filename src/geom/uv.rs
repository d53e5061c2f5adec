//! Surface (u, v) coordinates: the standard parameterisation of each shape, which textures
//! are looked up by. Computed only at hits whose material has a texture.
//!
//! - **Sphere:** longitude and latitude about the world's +y axis: `u = φ / 2π` with φ the
//!   angle around +y from +x towards −z, `v = θ / π` from the south pole (v = 0 at −y,
//!   1 at +y). The sphere's own rotation is not applied (a placed sphere keeps no rotation).
//! - **Plane and polygon:** planar, in scene units: `u` and `v` are the world position's
//!   coordinates along two axes of the plane ([`plane_axes`]; a floor with normal +y has u
//!   along +x and v along −z), measured from the world origin, so a texture does not move
//!   with the camera.
//! - **Box:** each face spans [0, 1]² in the box's own space, so the texture turns and
//!   scales with the box.
//! - **Mesh:** the file's `vt` coordinates, interpolated across each triangle.

use glam::DVec3;

use crate::math::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};
use crate::sample::warp::orthonormal_basis;

/// Texture coordinates at a surface point, and how the point moves with them: the
/// derivatives of the position along u and along v (world space), which a bump map tilts the
/// normal by. Zero derivatives where the parameterisation has none (a sphere's poles).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceUv {
    /// The (u, v) coordinates.
    pub uv: Vec2,
    /// ∂p/∂u.
    pub dpdu: Vec3,
    /// ∂p/∂v.
    pub dpdv: Vec3,
}

/// The two axes a plane with unit normal `normal` is textured along (orthonormal, and
/// orthogonal to `normal`).
#[inline]
pub fn plane_axes(normal: Vec3) -> (Vec3, Vec3) {
    orthonormal_basis(normal)
}

/// Spherical coordinates of the point `p` of a sphere around `centre`.
#[inline]
pub fn sphere(centre: Vec3, p: Vec3) -> SurfaceUv {
    let r = p - centre;
    let radius = r.length();
    let d = r.normalize_or_zero();
    let phi = (-d.z).atan2(d.x);
    let u = phi * (0.5 * std::f32::consts::FRAC_1_PI);
    let u = if u < 0.0 { u + 1.0 } else { u };
    let theta = d.y.clamp(-1.0, 1.0).acos();
    let uv = Vec2::new(u, 1.0 - theta * std::f32::consts::FRAC_1_PI);
    // p = c + r·(sin θ cos φ, cos θ, −sin θ sin φ), u = φ/2π, v = 1 − θ/π.
    let s = (d.x * d.x + d.z * d.z).sqrt();
    if s <= 0.0 || !s.is_finite() {
        return SurfaceUv { uv, dpdu: Vec3::ZERO, dpdv: Vec3::ZERO };
    }
    let tau = std::f32::consts::TAU;
    let pi = std::f32::consts::PI;
    let dpdu = tau * radius * Vec3::new(d.z, 0.0, -d.x);
    let dpdv = -pi * radius * Vec3::new(d.y * d.x / s, -s, d.y * d.z / s);
    SurfaceUv { uv, dpdu, dpdv }
}

/// Planar coordinates of the camera-relative point `p` on a plane with unit `normal`, the
/// camera being at `origin` in the world: the world position along [`plane_axes`], in f64.
#[inline]
pub fn planar(normal: Vec3, p: Vec3, origin: DVec3) -> SurfaceUv {
    let (a, b) = plane_axes(normal);
    let world = p.as_dvec3() + origin;
    let uv = Vec2::new(world.dot(a.as_dvec3()) as f32, world.dot(b.as_dvec3()) as f32);
    SurfaceUv { uv, dpdu: a, dpdv: b }
}

/// Coordinates of the world point `p` on the face `face` of a box (`face & 3` the axis,
/// `face & 4` the negative side), each face spanning [0, 1]² in the box's space.
#[inline]
pub fn cuboid(to_object: &Affine3A, min: Vec3, max: Vec3, face: u32, p: Vec3) -> SurfaceUv {
    let size = max - min;
    let q = (to_object.transform_point3(p) - min) / size;
    let negative = face & 4 != 0;
    let flip = |on: bool| if on { -1.0 } else { 1.0 };
    // Seen from outside, u runs to the right and v up on every side face.
    let (uv, du, dv) = match face & 3 {
        0 => (
            Vec2::new(if negative { q.z } else { 1.0 - q.z }, q.y),
            Vec3::new(0.0, 0.0, flip(!negative) * size.z),
            Vec3::new(0.0, size.y, 0.0),
        ),
        1 => (
            Vec2::new(q.x, if negative { q.z } else { 1.0 - q.z }),
            Vec3::new(size.x, 0.0, 0.0),
            Vec3::new(0.0, 0.0, flip(!negative) * size.z),
        ),
        _ => (
            Vec2::new(if negative { 1.0 - q.x } else { q.x }, q.y),
            Vec3::new(flip(negative) * size.x, 0.0, 0.0),
            Vec3::new(0.0, size.y, 0.0),
        ),
    };
    let to_world = to_object.matrix3.inverse();
    SurfaceUv {
        uv: uv.clamp(Vec2::ZERO, Vec2::ONE),
        dpdu: (to_world * Vec3A::from(du)).into(),
        dpdv: (to_world * Vec3A::from(dv)).into(),
    }
}

/// The `vt` coordinates of a mesh triangle with object-space corners `corners` and corner
/// coordinates `uvs`, at barycentric weights `u` (second corner) and `v` (third corner); the
/// derivatives mapped to the world by `to_world` (a linear map).
#[inline]
pub fn triangle(corners: [Vec3; 3], uvs: [Vec2; 3], u: f32, v: f32, to_world: &Mat3A) -> SurfaceUv {
    let uv = uvs[0] * (1.0 - u - v) + uvs[1] * u + uvs[2] * v;
    // Solve [e1 e2] = [dpdu dpdv] · [duv1 duv2] (pbrt's triangle derivatives).
    let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
    let (d1, d2) = (uvs[1] - uvs[0], uvs[2] - uvs[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    if det == 0.0 || !det.is_finite() {
        return SurfaceUv { uv, dpdu: Vec3::ZERO, dpdv: Vec3::ZERO };
    }
    let dpdu = (e1 * d2.y - e2 * d1.y) / det;
    let dpdv = (e2 * d1.x - e1 * d2.x) / det;
    SurfaceUv {
        uv,
        dpdu: (*to_world * Vec3A::from(dpdu)).into(),
        dpdv: (*to_world * Vec3A::from(dpdv)).into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    fn close3(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-4 * (1.0 + b.abs().max_element())
    }

    /// The derivatives agree with finite differences of the position along the coordinates:
    /// moving `p` by `dpdu·δ` changes u by δ and leaves v.
    fn derivatives_follow_the_coordinates(
        at: impl Fn(Vec3) -> SurfaceUv,
        p: Vec3,
        project: impl Fn(Vec3) -> Vec3,
    ) {
        let base = at(p);
        let h = 1e-3;
        let du = at(project(p + base.dpdu * h)).uv - base.uv;
        let dv = at(project(p + base.dpdv * h)).uv - base.uv;
        assert!((du - Vec2::new(h, 0.0)).abs().max_element() < 2e-2 * h, "du {du} at {p}");
        assert!((dv - Vec2::new(0.0, h)).abs().max_element() < 2e-2 * h, "dv {dv} at {p}");
    }

    #[test]
    fn a_sphere_maps_poles_equator_and_meridians_to_known_coordinates() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let uv = |p: Vec3| sphere(c, p).uv;
        assert!(close(uv(c + Vec3::X), Vec2::new(0.0, 0.5)));
        assert!(close(uv(c - Vec3::Z), Vec2::new(0.25, 0.5)));
        assert!(close(uv(c - Vec3::X), Vec2::new(0.5, 0.5)));
        assert!(close(uv(c + Vec3::Z), Vec2::new(0.75, 0.5)));
        assert_eq!(uv(c + Vec3::Y).y, 1.0);
        assert_eq!(uv(c - Vec3::Y).y, 0.0);
        let v = uv(c + Vec3::new(1.0, 1.0, 0.0)).y;
        assert!((v - 0.75).abs() < 1e-6, "45° north is v = 0.75: {v}");
        // At the centre itself (never hit) the result is still finite.
        assert!(uv(c).is_finite());
        let radius = 2.0;
        let on = |p: Vec3| c + (p - c).normalize() * radius;
        for p in [Vec3::new(0.3, 0.5, -0.8), Vec3::new(-0.6, -0.2, 0.1), Vec3::new(0.1, 0.9, 0.4)] {
            derivatives_follow_the_coordinates(|q| sphere(c, q), on(c + p), on);
        }
    }

    #[test]
    fn planar_coordinates_are_world_positions_along_the_plane_axes_whatever_the_camera() {
        let n = Vec3::Y;
        let (a, b) = plane_axes(n);
        assert_eq!((a.dot(n), b.dot(n), a.dot(b)), (0.0, 0.0, 0.0));
        assert_eq!((a, b), (Vec3::new(1.0, 0.0, -0.0), Vec3::new(0.0, 0.0, -1.0)));
        // The same world point seen from two camera positions.
        let world = DVec3::new(3.0, 0.0, -5.0);
        for origin in [DVec3::ZERO, DVec3::new(1e6, 2.0, -7.5)] {
            let p = (world - origin).as_vec3();
            assert!(close(planar(n, p, origin).uv, Vec2::new(3.0, 5.0)), "{origin}");
        }
        let tilted = Vec3::new(0.3, 0.8, -0.2).normalize();
        derivatives_follow_the_coordinates(
            |q| planar(tilted, q, DVec3::ZERO),
            Vec3::new(0.5, 0.1, 0.2),
            |q| q,
        );
    }

    #[test]
    fn every_box_face_spans_the_unit_square_in_the_boxs_own_space() {
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            crate::math::Quat::from_rotation_y(0.7),
            Vec3::new(5.0, 0.0, 1.0),
        );
        let to_object = to_world.inverse();
        let (min, max) = (Vec3::splat(-1.0), Vec3::new(1.0, 3.0, 1.0));
        let on = |q: Vec3| to_world.transform_point3(q);
        let uv = |face: u32, q: Vec3| cuboid(&to_object, min, max, face, on(q)).uv;
        // Corners of the +x face map to corners of the unit square.
        assert!(close(uv(0, Vec3::new(1.0, -1.0, 1.0)), Vec2::new(0.0, 0.0)));
        assert!(close(uv(0, Vec3::new(1.0, 3.0, -1.0)), Vec2::new(1.0, 1.0)));
        // Middle of the top face.
        assert!(close(uv(1, Vec3::new(0.0, 3.0, 0.0)), Vec2::splat(0.5)));
        // Derivatives on every face (points inside the face, the face codes of `cuboid_hit`).
        for (face, q) in [
            (0, Vec3::new(1.0, 0.3, 0.2)),
            (4, Vec3::new(-1.0, 0.3, 0.2)),
            (1, Vec3::new(0.1, 3.0, -0.3)),
            (5, Vec3::new(0.1, -1.0, -0.3)),
            (2, Vec3::new(0.2, 1.0, 1.0)),
            (6, Vec3::new(0.2, 1.0, -1.0)),
        ] {
            derivatives_follow_the_coordinates(|p| cuboid(&to_object, min, max, face, p), on(q), |p| p);
        }
    }

    #[test]
    fn triangle_coordinates_interpolate_the_corners_and_their_derivatives_span_the_triangle() {
        let corners = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -4.0)];
        let uvs = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 2.0)];
        let id = Mat3A::IDENTITY;
        assert_eq!(triangle(corners, uvs, 0.0, 0.0, &id).uv, uvs[0]);
        assert_eq!(triangle(corners, uvs, 1.0, 0.0, &id).uv, uvs[1]);
        assert_eq!(triangle(corners, uvs, 0.0, 1.0, &id).uv, uvs[2]);
        let s = triangle(corners, uvs, 0.25, 0.5, &id);
        assert!(close(s.uv, Vec2::new(0.25, 1.0)));
        assert!(
            close3(s.dpdu, Vec3::new(2.0, 0.0, 0.0)) && close3(s.dpdv, Vec3::new(0.0, 0.0, -2.0)),
            "{s:?}"
        );
        let scaled = Mat3A::from_diagonal(Vec3::new(1.0, 1.0, 3.0));
        assert!(close3(triangle(corners, uvs, 0.25, 0.5, &scaled).dpdv, Vec3::new(0.0, 0.0, -6.0)));
        // Degenerate coordinates: no derivatives, still the interpolated uv.
        let flat = triangle(corners, [Vec2::ZERO; 3], 0.3, 0.3, &id);
        assert_eq!((flat.uv, flat.dpdu, flat.dpdv), (Vec2::ZERO, Vec3::ZERO, Vec3::ZERO));
    }
}
