//! Primitive stores: the flattened geometry of a snapshot, behind one trait so the tracer can
//! be monomorphized over different memory layouts and benchmarked on identical code paths.
//!
//! Objects are numbered by the caller: bounded objects `0..bounded_count()` in the order the
//! grid indexes them, unbounded ones (planes) tested on every ray.

pub mod soa;

pub use soa::SoaStore;

use crate::geom::Placed;
use crate::math::{Ray, Vec3};

/// Index of a material in the snapshot's material table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct MaterialId(pub u32);

/// Flag bit marking an unbounded object in [`Hit::object`].
pub const UNBOUNDED_FLAG: u32 = 1 << 31;

/// A ray/object intersection, before shading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Ray parameter.
    pub t: f32,
    /// Object: a bounded object id, or a plane index with [`UNBOUNDED_FLAG`] set.
    pub object: u32,
    /// Detail within the object: the triangle index of a triangle set, the face axis of a box.
    pub prim: u32,
}

/// What shading needs of a hit point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// World position.
    pub point: Vec3,
    /// Unit geometric normal (outward for closed shapes; front side for flat ones).
    pub normal: Vec3,
    /// Material of the object hit.
    pub material: MaterialId,
}

/// One object handed to a store: placed geometry and its material.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedObject {
    /// World-space geometry.
    pub geometry: Placed,
    /// Material id.
    pub material: MaterialId,
}

/// A layout of flattened primitives that the tracer can intersect.
pub trait PrimitiveStore: Send + Sync + Sized + std::fmt::Debug {
    /// Builds the store: `bounded` in grid-id order, `unbounded` (planes) in any order.
    fn build(bounded: &[PlacedObject], unbounded: &[PlacedObject]) -> Self;
    /// Number of bounded objects.
    fn bounded_count(&self) -> u32;
    /// Nearest hit with bounded object `id` in `(t_min, t_max)`.
    fn intersect_bounded(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit>;
    /// Number of unbounded objects.
    fn unbounded_count(&self) -> u32;
    /// Hit with unbounded object `i` in `(t_min, t_max)`.
    fn intersect_unbounded(&self, i: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit>;
    /// Material of the object hit.
    fn material(&self, hit: &Hit) -> MaterialId;
    /// Position, normal and material at a hit.
    fn surface(&self, hit: &Hit, ray: &Ray) -> SurfacePoint;
    /// Bytes held by the store's arrays.
    fn memory_bytes(&self) -> usize;
}
