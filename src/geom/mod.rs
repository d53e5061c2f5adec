//! Shapes: one file each, with bounds and ray intersection as plain functions over plain values,
//! so every primitive store (structure-of-arrays or array-of-structures) shares the same maths.
//!
//! Intersections return the ray parameter of the nearest hit strictly inside `(t_min, t_max)`.
//! Rays are unit length in world space.

pub mod cuboid;
pub mod mesh;
pub mod plane;
pub mod polygon;
pub mod sphere;
pub mod triangle;

use crate::math::{Aabb, Affine3A, Vec3};

/// Geometry of an object in object space, in engine units.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Sphere with centre and radius.
    Sphere {
        /// Centre.
        centre: Vec3,
        /// Radius (> 0).
        radius: f32,
    },
    /// Infinite plane through `point` with (non-zero) `normal`.
    Plane {
        /// A point on the plane.
        point: Vec3,
        /// Normal, any non-zero length.
        normal: Vec3,
    },
    /// One triangle.
    Triangle {
        /// Corners, counter-clockwise from the front.
        vertices: [Vec3; 3],
    },
    /// Convex planar polygon, corners in order.
    Polygon {
        /// Corners.
        vertices: Vec<Vec3>,
    },
    /// Axis-aligned box in object space.
    Cuboid {
        /// Minimum corner.
        min: Vec3,
        /// Maximum corner.
        max: Vec3,
    },
}

/// Geometry placed in the world: what the grid indexes and the snapshot flattens.
#[derive(Debug, Clone, PartialEq)]
pub enum Placed {
    /// World-space sphere.
    Sphere {
        /// Centre.
        centre: Vec3,
        /// Radius.
        radius: f32,
    },
    /// World-space plane `normal · p = offset`, unit normal.
    Plane {
        /// Unit normal.
        normal: Vec3,
        /// Plane offset along the normal.
        offset: f32,
    },
    /// World-space triangles as `[v0, e1, e2]` (a polygon becomes a fan).
    Triangles(Vec<[Vec3; 3]>),
    /// A box: object-space corners and the maps between object and world space.
    Cuboid {
        /// World-to-object map.
        to_object: Affine3A,
        /// Object-to-world map.
        to_world: Affine3A,
        /// Object-space minimum corner.
        min: Vec3,
        /// Object-space maximum corner.
        max: Vec3,
    },
}

impl Shape {
    /// The shape placed by an object-to-world map. Spheres use the map's x scale (scenes are
    /// validated to scale spheres uniformly).
    pub fn place(&self, to_world: &Affine3A) -> Placed {
        match self {
            Shape::Sphere { centre, radius } => {
                let scale = to_world.matrix3.x_axis.length();
                Placed::Sphere { centre: to_world.transform_point3(*centre), radius: radius * scale }
            }
            Shape::Plane { point, normal } => {
                let normal_map = to_world.matrix3.inverse().transpose();
                let n: Vec3 = normal_map.mul_vec3a((*normal).into()).normalize().into();
                let p = to_world.transform_point3(*point);
                Placed::Plane { normal: n, offset: n.dot(p) }
            }
            Shape::Triangle { vertices } => {
                Placed::Triangles(polygon::fan(&vertices.map(|v| to_world.transform_point3(v))))
            }
            Shape::Polygon { vertices } => {
                let world: Vec<Vec3> = vertices.iter().map(|&v| to_world.transform_point3(v)).collect();
                Placed::Triangles(polygon::fan(&world))
            }
            Shape::Cuboid { min, max } => {
                Placed::Cuboid { to_object: to_world.inverse(), to_world: *to_world, min: *min, max: *max }
            }
        }
    }
}

impl Placed {
    /// World bounds; `None` for unbounded geometry (planes).
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Placed::Sphere { centre, radius } => Some(sphere::bounds(*centre, *radius)),
            Placed::Plane { .. } => None,
            Placed::Triangles(tris) => Some(
                tris.iter().fold(Aabb::EMPTY, |b, [v0, e1, e2]| b.union(triangle::bounds(*v0, *e1, *e2))),
            ),
            Placed::Cuboid { to_world, min, max, .. } => Some(cuboid::bounds(to_world, *min, *max)),
        }
    }

    /// True when the geometry may touch the cell: exact for spheres and triangles, bounds for
    /// boxes. Conservative: never false for a cell the geometry touches.
    pub fn overlaps(&self, cell: &Aabb) -> bool {
        match self {
            Placed::Sphere { centre, radius } => sphere::overlaps_box(*centre, *radius, cell),
            Placed::Plane { .. } => true,
            Placed::Triangles(tris) => {
                tris.iter().any(|[v0, e1, e2]| triangle::overlaps_box(*v0, *e1, *e2, cell))
            }
            Placed::Cuboid { .. } => self.bounds().is_some_and(|b| b.overlaps(cell)),
        }
    }
}
