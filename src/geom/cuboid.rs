//! Box: axis-aligned in object space, placed by an affine map (so a rotated box stays exact).
//!
//! Stored as the world-to-object map and the object-space corners; the slab test runs in
//! object space, where an affine map preserves the ray parameter.

use crate::math::{transform_error, Aabb, Affine3A, Ray, Vec3, UNIT_ROUNDOFF};

/// Which face a box hit landed on, for the normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CuboidHit {
    /// Ray parameter.
    pub t: f32,
    /// Object-space outward normal of the face that was hit (an axis, signed).
    pub local_normal: Vec3,
}

/// Nearest hit within `(t_min, t_max)` of a world ray with the box `[min, max]` in object space,
/// for a direction of any non-zero length (`t` in units of its length; an affine map keeps `t`).
///
/// The box is closed: touching it is hitting it. A ray lying in a face's plane, along an edge
/// or through a corner hits where it first meets the closed box, exactly as
/// [`crate::math::Aabb::clip_ray`] clips rays to the grid, and the same on all six faces: an
/// axis along which the ray does not move (a zero or subnormal component) constrains nothing
/// when the origin lies in that slab, walls included, and misses otherwise; every other axis
/// has a finite reciprocal, so no `0 × ∞` can make a NaN. The face reported is the one whose
/// slab decided `t` (the first axis in x, y, z order on an edge or corner).
#[inline(always)]
pub fn intersect(
    world_to_object: &Affine3A,
    min: Vec3,
    max: Vec3,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<CuboidHit> {
    let o = world_to_object.transform_point3(ray.origin);
    let d = world_to_object.transform_vector3(ray.dir);
    // A component too small to have a finite reciprocal (zero or subnormal: less than 1.2e-38
    // per unit of t) does not move the ray along that axis: it misses unless it lies in the
    // slab, and constrains nothing there. Every other axis has a finite reciprocal.
    let still = d.abs().cmplt(Vec3::splat(f32::MIN_POSITIVE));
    if (still & (o.cmplt(min) | o.cmpgt(max))).any() || still.all() {
        return None;
    }
    let inv = Vec3::select(still, Vec3::ONE, d.recip());
    let (a, b) = ((min - o) * inv, (max - o) * inv);
    let near = Vec3::select(still, Vec3::NEG_INFINITY, a.min(b));
    let far = Vec3::select(still, Vec3::INFINITY, a.max(b));
    let (t_near, t_far) = (near.max_element(), far.min_element());
    if t_near > t_far {
        return None;
    }
    // The first axis in x, y, z order that decided each end.
    let first = |v: Vec3, t: f32| {
        if v.x == t {
            0
        } else if v.y == t {
            1
        } else {
            2
        }
    };
    let (near_axis, far_axis) = (first(near, t_near), first(far, t_far));
    // The entering face when it is ahead, else the exit face (origin inside the box).
    let (t, axis, sign) = if t_near > t_min && t_near < t_max {
        // Entering through a face means moving against its outward normal.
        (t_near, near_axis, -d[near_axis].signum())
    } else if t_far > t_min && t_far < t_max {
        (t_far, far_axis, d[far_axis].signum())
    } else {
        return None;
    };
    let mut local_normal = Vec3::ZERO;
    local_normal[axis] = sign;
    Some(CuboidHit { t, local_normal })
}

/// [`intersect`] for the `live` lanes of a packet at once, each within `(t_min, bound)`: the same
/// IEEE operations in the same order as the scalar test, lane-wise and without branches (the
/// world-to-object map as glam applies it, `((x·p_x + y·p_y) + z·p_z) + w`; the slab test's
/// selects as glam's `min`/`max`), so every lane's hit has the scalar hit's bits. A lane's hit
/// lowers its `bound` and is passed to `record(lane, hit)`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
pub fn intersect_lanes<const N: usize>(
    world_to_object: &Affine3A,
    min: Vec3,
    max: Vec3,
    packet: &crate::math::RayPacket<N>,
    live: &[bool; N],
    bound: &mut [f32; N],
    mut record: impl FnMut(usize, CuboidHit),
) {
    let m = world_to_object.matrix3;
    let cols = [Vec3::from(m.x_axis), Vec3::from(m.y_axis), Vec3::from(m.z_axis)];
    let w = Vec3::from(world_to_object.translation);
    let (lo, hi) = (min.to_array(), max.to_array());
    let sel_max = |a: f32, b: f32| if a > b { a } else { b };
    let sel_min = |a: f32, b: f32| if a < b { a } else { b };
    let mut found = [f32::NAN; N];
    let mut face = [0u8; N];
    for i in 0..N {
        let p = [packet.origin[0][i], packet.origin[1][i], packet.origin[2][i]];
        let v = [packet.dir[0][i], packet.dir[1][i], packet.dir[2][i]];
        let mut near = [0.0f32; 3];
        let mut far = [0.0f32; 3];
        let mut d = [0.0f32; 3];
        let (mut outside, mut all_still) = (false, true);
        for r in 0..3 {
            let o = ((cols[0][r] * p[0] + cols[1][r] * p[1]) + cols[2][r] * p[2]) + w[r];
            d[r] = (cols[0][r] * v[0] + cols[1][r] * v[1]) + cols[2][r] * v[2];
            let still = d[r].abs() < f32::MIN_POSITIVE;
            outside |= still & ((o < lo[r]) | (o > hi[r]));
            all_still &= still;
            let inv = if still { 1.0 } else { 1.0 / d[r] };
            let (a, b) = ((lo[r] - o) * inv, (hi[r] - o) * inv);
            near[r] = if still { f32::NEG_INFINITY } else { sel_min(a, b) };
            far[r] = if still { f32::INFINITY } else { sel_max(a, b) };
        }
        let t_near = sel_max(near[0], sel_max(near[1], near[2]));
        let t_far = sel_min(far[0], sel_min(far[1], far[2]));
        let first = |v: [f32; 3], t: f32| {
            if v[0] == t {
                0
            } else if v[1] == t {
                1
            } else {
                2
            }
        };
        let (t_min, t_max) = (packet.t_min[i], bound[i]);
        let enter = (t_near > t_min) & (t_near < t_max);
        let leave = (t_far > t_min) & (t_far < t_max);
        let axis = if enter { first(near, t_near) } else { first(far, t_far) };
        let d_axis = if axis == 0 {
            d[0]
        } else if axis == 1 {
            d[1]
        } else {
            d[2]
        };
        // Entering through a face means moving against its outward normal.
        let negative = if enter { d_axis > 0.0 } else { d_axis < 0.0 };
        let apart = t_near > t_far;
        let hit = live[i] & !outside & !all_still & !apart & (enter | leave);
        found[i] = if !hit {
            f32::NAN
        } else if enter {
            t_near
        } else {
            t_far
        };
        face[i] = axis | (u8::from(negative) << 2);
    }
    for i in 0..N {
        if !found[i].is_nan() {
            bound[i] = found[i];
            let axis = (face[i] & 3) as usize;
            let mut local_normal = Vec3::ZERO;
            local_normal[axis] = if face[i] & 4 != 0 { -1.0 } else { 1.0 };
            record(i, CuboidHit { t: found[i], local_normal });
        }
    }
}

/// World-space unit normal from an object-space one (inverse transpose of the object-to-world map).
#[inline]
pub fn world_normal(world_to_object: &Affine3A, local_normal: Vec3) -> Vec3 {
    world_to_object.matrix3.transpose().mul_vec3a(local_normal.into()).normalize().into()
}

/// The world hit point of `ray` at `t` on the face `local_normal` of the box, a conservative
/// bound on its distance from that face along the world normal, and the sum of the world
/// normals of the adjacent faces the point lies on (zero away from edges and corners).
///
/// The object-space point is put exactly on the face plane (`min` or `max` on the face's
/// axis), then mapped to the world. What the box test will see of a ray leaving from there is
/// that point mapped back through `world_to_object`, so the bound is measured rather than
/// derived: the mapped-back point's distance from the face, plus the rounding of that map
/// (twice: once for this measurement, once for the next ray's own), divided by how much one
/// world unit along the normal moves the object-space coordinate.
///
/// On an edge or a corner, offsetting along the face's own normal is not enough: rounding the
/// offset point moves it sideways by a few units of roundoff of its coordinates, which can put
/// it just outside an adjacent face, where a ray sent into the box would enter it again a
/// hair's breadth away. An adjacent face counts when the point, mapped back, lies within that
/// sideways rounding of it (or beyond it); its normal joins the offset
/// ([`crate::store::SurfacePoint::spawn`]) and the bound grows to cover its distance too.
pub fn surface_point(
    world_to_object: &Affine3A,
    min: Vec3,
    max: Vec3,
    local_normal: Vec3,
    ray: &Ray,
    t: f32,
) -> (Vec3, f32, Vec3) {
    let axis = if local_normal.x != 0.0 {
        0
    } else if local_normal.y != 0.0 {
        1
    } else {
        2
    };
    let face = if local_normal[axis] < 0.0 { min[axis] } else { max[axis] };
    let mut local =
        world_to_object.transform_point3(ray.origin) + world_to_object.transform_vector3(ray.dir) * t;
    local[axis] = face;
    let point = world_to_object.inverse().transform_point3(local);
    let back = world_to_object.transform_point3(point);
    let rounding = 2.0 * transform_error(world_to_object, point);
    let residual = (back[axis] - face).abs() + rounding[axis];
    let row = world_to_object.matrix3.row(axis).length();
    let mut error = residual / row;
    // How far sideways the offset point's rounding can move it (two units of roundoff of each
    // coordinate from `offset_origin`'s spare, half a unit from the sum), with room to spare.
    let sideways = 8.0 * UNIT_ROUNDOFF * point.abs().max_element();
    let mut edge = Vec3::ZERO;
    for k in [(axis + 1) % 3, (axis + 2) % 3] {
        let row = world_to_object.matrix3.row(k).length();
        for (bound, side) in [(min[k], -1.0), (max[k], 1.0)] {
            // How far beyond the face plane (negative: inside) the box test may see the point.
            let beyond = ((back[k] - bound) * side + rounding[k]) / row;
            if beyond > -sideways {
                let mut normal = Vec3::ZERO;
                normal[k] = side;
                edge += world_normal(world_to_object, normal);
                error = error.max(beyond.max(0.0) + sideways);
            }
        }
    }
    (point, error, edge)
}

/// World bounds of the placed box.
pub fn bounds(object_to_world: &Affine3A, min: Vec3, max: Vec3) -> Aabb {
    Aabb::new(min, max).transformed(object_to_world)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Quat;

    #[test]
    fn unit_box_front_face_and_inside_exit() {
        let id = Affine3A::IDENTITY;
        let ray = Ray::new(Vec3::new(0.5, 0.5, -2.0), Vec3::Z);
        let hit = intersect(&id, Vec3::ZERO, Vec3::ONE, &ray, 0.0, f32::INFINITY).unwrap();
        assert_eq!(hit.t, 2.0);
        assert_eq!(hit.local_normal, -Vec3::Z);
        let inside = Ray::new(Vec3::splat(0.5), Vec3::X);
        let hit = intersect(&id, Vec3::ZERO, Vec3::ONE, &inside, 0.0, f32::INFINITY).unwrap();
        assert_eq!((hit.t, hit.local_normal), (0.5, Vec3::X));
    }

    #[test]
    fn rotated_box_hits_its_corner_edge_at_the_diagonal_distance() {
        // A unit cube centred at the origin, turned 45 degrees about y: its edge faces -z at
        // distance sqrt(2)/2 from the centre.
        let to_world =
            Affine3A::from_rotation_translation(Quat::from_rotation_y(45f32.to_radians()), Vec3::ZERO);
        let to_object = to_world.inverse();
        let ray = Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::Z);
        let hit =
            intersect(&to_object, Vec3::splat(-0.5), Vec3::splat(0.5), &ray, 0.0, f32::INFINITY).unwrap();
        assert!((hit.t - (3.0 - 0.5 * 2f32.sqrt())).abs() < 1e-5);
    }
}
