//! Box: axis-aligned in object space, placed by an affine map (so a rotated box stays exact).
//!
//! Stored as the world-to-object map and the object-space corners; the slab test runs in
//! object space, where an affine map preserves the ray parameter.

use crate::math::{Aabb, Affine3A, Ray, Vec3};

/// Which face a box hit landed on, for the normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CuboidHit {
    /// Ray parameter.
    pub t: f32,
    /// Object-space outward normal of the face that was hit (an axis, signed).
    pub local_normal: Vec3,
}

/// Nearest hit within `(t_min, t_max)` of a world ray with the box `[min, max]` in object space.
#[inline]
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
    let inv = d.recip();
    let t_lo = (min - o) * inv;
    let t_hi = (max - o) * inv;
    let near = t_lo.min(t_hi);
    let far = t_lo.max(t_hi);
    let t_near = near.x.max(near.y).max(near.z);
    let t_far = far.x.min(far.y).min(far.z);
    if t_near > t_far {
        return None;
    }
    // Entering face when the near plane is ahead, else the exit face (origin inside the box).
    let (t, axis_t, from_near) = if t_near > t_min && t_near < t_max {
        (t_near, near, true)
    } else if t_far > t_min && t_far < t_max {
        (t_far, far, false)
    } else {
        return None;
    };
    let axis = if axis_t.x == t {
        0
    } else if axis_t.y == t {
        1
    } else {
        2
    };
    // Entering through a face means moving against its outward normal.
    let sign = if from_near { -d[axis].signum() } else { d[axis].signum() };
    let mut local_normal = Vec3::ZERO;
    local_normal[axis] = sign;
    Some(CuboidHit { t, local_normal })
}

/// World-space unit normal from an object-space one (inverse transpose of the object-to-world map).
#[inline]
pub fn world_normal(world_to_object: &Affine3A, local_normal: Vec3) -> Vec3 {
    world_to_object.matrix3.transpose().mul_vec3a(local_normal.into()).normalize().into()
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
