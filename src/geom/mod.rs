//! Shapes: one file each, with bounds and ray intersection as plain functions over plain values,
//! so every primitive store (structure-of-arrays or array-of-structures) shares the same maths.
//!
//! Intersections return the ray parameter of the nearest hit strictly inside `(t_min, t_max)`,
//! for directions of any non-zero length, in units of that length (`origin + t·dir`).
//!
//! Two precisions meet here. A [`Shape`] is authored geometry: its positions (a sphere's
//! centre, a plane's point, vertices, a box's corners) are `f64`, like the transforms that
//! place it, so that a scene far from the origin keeps its detail. [`Shape::place`] computes
//! the world geometry in `f64`, subtracts the frame's origin (the camera position) and rounds
//! once to `f32`: a [`Placed`] shape is camera-relative, and that is what the grid, the stores
//! and the tracer read. Mesh assets stay `f32` in their own object space.

pub mod cuboid;
pub mod mesh;
pub mod plane;
pub mod polygon;
pub mod sphere;
pub mod triangle;
pub mod uv;

use glam::{DAffine3, DVec3};

use crate::math::{Aabb, Affine3A, Vec3};

/// Geometry of an object in object space, in engine units; positions in `f64`.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Sphere with centre and radius.
    Sphere {
        /// Centre.
        centre: DVec3,
        /// Radius (> 0).
        radius: f32,
    },
    /// Infinite plane through `point` with (non-zero) `normal`.
    Plane {
        /// A point on the plane.
        point: DVec3,
        /// Normal, any non-zero length.
        normal: Vec3,
    },
    /// One triangle.
    Triangle {
        /// Corners, counter-clockwise from the front.
        vertices: [DVec3; 3],
    },
    /// Convex planar polygon, corners in order.
    Polygon {
        /// Corners.
        vertices: Vec<DVec3>,
    },
    /// Axis-aligned box in object space.
    Cuboid {
        /// Minimum corner.
        min: DVec3,
        /// Maximum corner.
        max: DVec3,
    },
    /// An instance of a triangle mesh asset (shared by every instance of it).
    Mesh {
        /// The asset.
        mesh: MeshId,
        /// Object-space bounds of the asset.
        bounds: Aabb,
    },
}

/// Index of a mesh asset in the scene's mesh table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct MeshId(pub u32);

/// Geometry placed in the world, relative to the frame's origin (see [`Shape::place`]): what
/// the grid indexes and the snapshot flattens.
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
    /// World-space triangles as vertex triples (a polygon becomes a fan).
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
    /// A mesh instance: the asset and the maps between its object space and the world.
    Instance {
        /// The asset.
        mesh: MeshId,
        /// World-to-object map (rays enter the asset's grid through it).
        to_object: Affine3A,
        /// Object-to-world map.
        to_world: Affine3A,
        /// World bounds: the asset's bounds transformed.
        bounds: Aabb,
    },
}

/// A box whose centre is further than this many times its size from its object-space origin
/// is placed by its centre (see [`Shape::place`]).
pub const FAR_BOX: f64 = 16.0;

impl Shape {
    /// The shape placed by an object-to-world map, relative to `origin`: world positions are
    /// computed in `f64`, `origin` is subtracted, and the result is rounded once to `f32`, so
    /// detail near `origin` survives however far it lies from the world's origin. Spheres use
    /// the map's x scale (scenes are validated to scale spheres uniformly). Boxes and mesh
    /// instances get their maps with `origin` taken off the translation, inverted in `f64`; a
    /// box whose centre lies more than [`FAR_BOX`] times its size from its object-space origin
    /// is placed by its centre (the map carries the centre, the corners become `±half`
    /// extent), so its intersections run near it.
    ///
    /// # Examples
    /// ```
    /// # use glam::{DAffine3, DVec3};
    /// # use penumbra::geom::{Placed, Shape};
    /// let far = DVec3::new(1e6 + 0.01, 0.0, 0.0);
    /// let ball = Shape::Sphere { centre: far, radius: 1.0 };
    /// // In f32 at 1e6 the 0.01 would be lost (the step there is 1/16); relative to a nearby
    /// // origin it is kept.
    /// let Placed::Sphere { centre, .. } = ball.place(&DAffine3::IDENTITY, DVec3::new(1e6, 0.0, 0.0))
    /// else { unreachable!() };
    /// assert!((centre.x - 0.01).abs() < 1e-9 && centre.y == 0.0);
    /// ```
    pub fn place(&self, to_world: &DAffine3, origin: DVec3) -> Placed {
        // The map into the frame: the world placement with the origin taken off its translation,
        // in f64 (exact when the two are within a factor of two, as near the camera).
        let to_frame = DAffine3 { translation: to_world.translation - origin, ..*to_world };
        let relative = |p: DVec3| to_frame.transform_point3(p).as_vec3();
        match self {
            Shape::Sphere { centre, radius } => {
                let scale = to_world.matrix3.x_axis.length();
                Placed::Sphere { centre: relative(*centre), radius: (f64::from(*radius) * scale) as f32 }
            }
            Shape::Plane { point, normal } => {
                let normal_map = to_world.matrix3.inverse().transpose();
                let n = (normal_map * normal.as_dvec3()).normalize().as_vec3();
                // The offset of the rounded normal, so the plane holds the placed point.
                let offset = n.as_dvec3().dot(to_frame.transform_point3(*point));
                Placed::Plane { normal: n, offset: offset as f32 }
            }
            Shape::Triangle { vertices } => Placed::Triangles(polygon::fan(&vertices.map(relative))),
            Shape::Polygon { vertices } => {
                let placed: Vec<Vec3> = vertices.iter().map(|&v| relative(v)).collect();
                Placed::Triangles(polygon::fan(&placed))
            }
            Shape::Cuboid { min, max } => {
                // A box authored far from its own origin is placed by its centre, so that its
                // intersections run near it; one authored around its origin keeps its corners.
                let centre = 0.5 * (*min + *max);
                let far = centre.abs().max_element() > FAR_BOX * (*max - *min).max_element();
                let (to_frame, pivot) = match far {
                    true => (to_frame * DAffine3::from_translation(centre), centre),
                    false => (to_frame, DVec3::ZERO),
                };
                Placed::Cuboid {
                    to_object: to_frame.inverse().as_affine3a(),
                    to_world: to_frame.as_affine3a(),
                    min: (*min - pivot).as_vec3(),
                    max: (*max - pivot).as_vec3(),
                }
            }
            Shape::Mesh { mesh, bounds } => {
                let to_world = to_frame.as_affine3a();
                Placed::Instance {
                    mesh: *mesh,
                    to_object: to_frame.inverse().as_affine3a(),
                    to_world,
                    bounds: transform_bounds(&to_world, bounds),
                }
            }
        }
    }

    /// Object-space bounds as `(min, max)` in `f64`; `None` for a plane.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let span = |points: &mut dyn Iterator<Item = DVec3>| {
            points.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)))
        };
        match self {
            Shape::Sphere { centre, radius } => {
                let r = DVec3::splat(f64::from(*radius));
                Some((*centre - r, *centre + r))
            }
            Shape::Plane { .. } => None,
            Shape::Triangle { vertices } => Some(span(&mut vertices.iter().copied())),
            Shape::Polygon { vertices } => Some(span(&mut vertices.iter().copied())),
            Shape::Cuboid { min, max } => Some((*min, *max)),
            Shape::Mesh { bounds, .. } => Some((bounds.min.as_dvec3(), bounds.max.as_dvec3())),
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
                tris.iter().fold(Aabb::EMPTY, |b, [v0, v1, v2]| b.union(triangle::bounds(*v0, *v1, *v2))),
            ),
            Placed::Cuboid { to_world, min, max, .. } => Some(cuboid::bounds(to_world, *min, *max)),
            Placed::Instance { bounds, .. } => Some(*bounds),
        }
    }

    /// True when the geometry may touch the cell: exact for spheres and triangles, bounds for
    /// boxes and mesh instances (whose triangles their own grid sorts). Conservative: never
    /// false for a cell the geometry touches.
    pub fn overlaps(&self, cell: &Aabb) -> bool {
        match self {
            Placed::Sphere { centre, radius } => sphere::overlaps_box(*centre, *radius, cell),
            Placed::Plane { .. } => true,
            Placed::Triangles(tris) => {
                tris.iter().any(|[v0, v1, v2]| triangle::overlaps_box(*v0, *v1, *v2, cell))
            }
            Placed::Cuboid { .. } | Placed::Instance { .. } => {
                self.bounds().is_some_and(|b| b.overlaps(cell))
            }
        }
    }
}

/// The world bounds of an object-space box under `to_world`, grown by a relative hair so that
/// rounding in the transform never leaves a point of the instance outside them.
pub fn transform_bounds(to_world: &Affine3A, b: &Aabb) -> Aabb {
    if b.is_empty() {
        return Aabb::EMPTY;
    }
    let w = b.transformed(to_world);
    let size = w.extent().max_element().max(w.min.abs().max_element()).max(w.max.abs().max_element());
    let pad = Vec3::splat(size * 1e-6);
    Aabb::new(w.min - pad, w.max + pad)
}
