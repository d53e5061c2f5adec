//! Structure-of-arrays store: one array per coordinate, as Embree's `RTCRay4` lays out rays.
//!
//! Bounded objects are a kind tag plus an index into that kind's arrays (a polygon is a range
//! of fan triangles, a mesh instance an index into the instance arrays). Triangles keep their
//! three vertices per axis (`v0_x`, ...), the watertight test's input; boxes and instances keep
//! the world-to-object map as four column arrays per axis.

use std::sync::Arc;

use super::mesh::{self, MeshEntry};
use super::packet::{self, PacketHits};
use super::{
    Hit, MaterialId, PlacedObject, PrimitiveStore, SurfacePoint, Tally, TraversalCost, TriangleLayout,
};
use super::{ObjectId, Stored};
use crate::geom::{sphere, Placed};
use crate::math::{Affine3A, Ray, RayPacket, Vec3};

mod columns;
mod triangles;

use columns::{Affines, Xyz};
pub use triangles::SoaTriangles;

/// Kind of a bounded object, selecting which arrays its index refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Kind {
    Sphere,
    Triangles,
    Cuboid,
    Instance,
}

/// Structure-of-arrays primitive store.
#[derive(Debug, Clone, Default)]
pub struct SoaStore {
    // Bounded objects.
    kind: Vec<Kind>,
    first: Vec<u32>,
    /// How many bounded objects, from id 0, are spheres: object `id` below it is sphere `id`
    /// (its `kind` is `Sphere` and its `first` is `id`), known without reading either array.
    /// Most sphere scenes are spheres throughout, and a sphere test that reads neither saves
    /// two dependent loads (cache misses in a large scene) before the sphere's own.
    leading_spheres: u32,
    count: Vec<u32>,
    material: Vec<MaterialId>,
    // Spheres.
    centre: Xyz,
    radius: Vec<f32>,
    // Scene triangles (polygons are fans).
    triangles: SoaTriangles,
    // Boxes: world-to-object maps and object-space corners.
    box_to_object: Affines,
    box_min: Xyz,
    box_max: Xyz,
    // Mesh instances: world-to-object maps and mesh ids.
    instance_to_object: Affines,
    instance_mesh: Vec<u32>,
    // Planes.
    plane_normal: Xyz,
    plane_offset: Vec<f32>,
    plane_material: Vec<MaterialId>,
    // Shared mesh layouts.
    meshes: Vec<Arc<MeshEntry<SoaTriangles>>>,
}

impl SoaStore {
    /// Bounded object `id`'s mesh and world-to-object map, when it is a mesh instance.
    pub(crate) fn instance(&self, id: u32) -> Option<(&MeshEntry<SoaTriangles>, Affine3A)> {
        let o = id as usize;
        (self.kind[o] == Kind::Instance).then(|| {
            let i = self.first[o] as usize;
            (&*self.meshes[self.instance_mesh[i] as usize], self.instance_to_object.get(i))
        })
    }

    /// [`PrimitiveStore::intersect_bounded`] of bounded object `id`, a sphere.
    #[inline(always)]
    fn sphere_hit<T: Tally>(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32, cost: &mut T) -> Option<Hit> {
        let i = self.sphere_index(id);
        super::sphere_hit(self.centre.get(i), self.radius[i], id, ray, t_min, t_max, cost)
    }

    /// The sphere arrays' index of bounded object `id`, a sphere.
    #[inline(always)]
    fn sphere_index(&self, id: u32) -> usize {
        match id < self.leading_spheres {
            true => id as usize,
            false => self.first[id as usize] as usize,
        }
    }

    /// Bounded object `id`'s kind and index into that kind's arrays, read from neither array
    /// for a leading sphere.
    #[inline(always)]
    fn kind_and_first(&self, id: u32) -> (Kind, u32) {
        match id < self.leading_spheres {
            true => (Kind::Sphere, id),
            false => (self.kind[id as usize], self.first[id as usize]),
        }
    }

    /// Whether bounded object `id` is a sphere.
    #[inline(always)]
    fn is_sphere(&self, id: u32) -> bool {
        id < self.leading_spheres || self.kind[id as usize] == Kind::Sphere
    }

    /// [`PrimitiveStore::intersect_bounded`] of any bounded object, out of line (spheres, the
    /// commonest, take the inlined [`SoaStore::sphere_hit`] first).
    fn intersect_any<T: Tally>(
        &self,
        id: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        cost: &mut T,
    ) -> Option<Hit> {
        let o = id as usize;
        let first = self.first[o] as usize;
        match self.kind[o] {
            Kind::Sphere => self.sphere_hit(id, ray, t_min, t_max, cost),
            Kind::Triangles => {
                let count = self.count[o];
                cost.tests(count);
                super::triangle_range_hit(
                    &self.triangles,
                    ObjectId::bounded(id),
                    first as u32,
                    count,
                    ray,
                    t_min,
                    t_max,
                )
            }
            Kind::Cuboid => {
                cost.tests(1);
                let to_object = self.box_to_object.get(first);
                super::cuboid_hit(
                    &to_object,
                    self.box_min.get(first),
                    self.box_max.get(first),
                    ObjectId::bounded(id),
                    ray,
                    t_min,
                    t_max,
                )
            }
            Kind::Instance => {
                let mesh = &self.meshes[self.instance_mesh[first] as usize];
                mesh::instance_hit(
                    mesh,
                    &self.instance_to_object.get(first),
                    ObjectId::bounded(id),
                    ray,
                    t_min,
                    t_max,
                    cost,
                )
            }
        }
    }
}

impl PrimitiveStore for SoaStore {
    type Triangles = SoaTriangles;

    fn build(
        bounded: &[PlacedObject],
        unbounded: &[PlacedObject],
        meshes: &[Arc<MeshEntry<SoaTriangles>>],
    ) -> Self {
        let mut s = SoaStore { meshes: meshes.to_vec(), ..Default::default() };
        let mut tris = Vec::new();
        for obj in bounded {
            let (kind, first, count) = match &obj.geometry {
                Placed::Sphere { centre, radius } => {
                    s.centre.push(*centre);
                    s.radius.push(*radius);
                    (Kind::Sphere, s.radius.len() - 1, 1)
                }
                Placed::Triangles(list) => {
                    let first = tris.len();
                    tris.extend_from_slice(list);
                    (Kind::Triangles, first, list.len())
                }
                Placed::Cuboid { to_object, min, max, .. } => {
                    s.box_to_object.push(to_object);
                    s.box_min.push(*min);
                    s.box_max.push(*max);
                    (Kind::Cuboid, s.box_min.x.len() - 1, 1)
                }
                Placed::Instance { mesh, to_object, .. } => {
                    debug_assert!((mesh.0 as usize) < meshes.len(), "instance of an unknown mesh");
                    s.instance_to_object.push(to_object);
                    s.instance_mesh.push(mesh.0);
                    (Kind::Instance, s.instance_mesh.len() - 1, 1)
                }
                Placed::Plane { .. } => {
                    debug_assert!(false, "planes are unbounded and belong in the unbounded list");
                    continue;
                }
            };
            s.kind.push(kind);
            s.first.push(first as u32);
            s.count.push(count as u32);
            s.material.push(obj.material);
        }
        s.triangles = SoaTriangles::from_vertices(tris);
        s.leading_spheres = s.kind.iter().take_while(|&&k| k == Kind::Sphere).count() as u32;
        debug_assert!((0..s.leading_spheres).all(|id| s.first[id as usize] == id));
        for obj in unbounded {
            if let Placed::Plane { normal, offset } = obj.geometry {
                s.plane_normal.push(normal);
                s.plane_offset.push(offset);
                s.plane_material.push(obj.material);
            }
        }
        s
    }

    #[inline]
    fn bounded_count(&self) -> u32 {
        self.kind.len() as u32
    }

    #[inline]
    fn intersect_bounded<T: Tally>(
        &self,
        id: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        cost: &mut T,
    ) -> Option<Hit> {
        // Spheres, the commonest object, are tested in the caller's loop.
        match self.is_sphere(id) {
            true => self.sphere_hit(id, ray, t_min, t_max, cost),
            false => self.intersect_any(id, ray, t_min, t_max, cost),
        }
    }

    #[inline]
    fn occludes_bounded<T: Tally>(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32, cost: &mut T) -> bool {
        let (kind, first) = self.kind_and_first(id);
        match kind {
            Kind::Instance => {
                let i = first as usize;
                let mesh = &self.meshes[self.instance_mesh[i] as usize];
                let local = mesh::object_ray(&self.instance_to_object.get(i), ray);
                mesh::occluded(mesh, &local, t_min, t_max, cost)
            }
            // The commonest blocker.
            Kind::Sphere => {
                let i = first as usize;
                super::sphere_hit(self.centre.get(i), self.radius[i], id, ray, t_min, t_max, cost).is_some()
            }
            _ => self.intersect_any(id, ray, t_min, t_max, cost).is_some(),
        }
    }

    #[inline(always)]
    fn intersect_bounded_packet<const N: usize>(
        &self,
        id: u32,
        packet: &RayPacket<N>,
        live: &[bool; N],
        hits: &mut PacketHits<N>,
        cost: &mut TraversalCost,
    ) {
        let (kind, first) = self.kind_and_first(id);
        match kind {
            Kind::Instance => {
                let i = first as usize;
                let mesh = &self.meshes[self.instance_mesh[i] as usize];
                let to_object = self.instance_to_object.get(i);
                packet::instance_hits(mesh, &to_object, ObjectId::bounded(id), packet, live, hits, cost)
            }
            Kind::Triangles => packet::triangle_range_hits(
                &self.triangles,
                ObjectId::bounded(id),
                first,
                self.count[id as usize],
                packet,
                live,
                hits,
                cost,
            ),
            Kind::Sphere => {
                let i = first as usize;
                packet::sphere_hits(
                    self.centre.get(i),
                    self.radius[i],
                    ObjectId::bounded(id),
                    packet,
                    live,
                    hits,
                    cost,
                )
            }
            Kind::Cuboid => {
                let i = first as usize;
                let (min, max) = (self.box_min.get(i), self.box_max.get(i));
                packet::cuboid_hits(
                    &self.box_to_object.get(i),
                    min,
                    max,
                    ObjectId::bounded(id),
                    packet,
                    live,
                    hits,
                    cost,
                )
            }
        }
    }

    #[inline(always)]
    fn may_meet(&self, id: u32, footprint: &crate::math::Aabb) -> bool {
        if !self.is_sphere(id) {
            return true;
        }
        let i = self.sphere_index(id);
        sphere::bounds_meet(self.centre.get(i), self.radius[i], footprint)
    }

    #[inline(always)]
    fn occludes_bounded_packet<const N: usize>(
        &self,
        id: u32,
        packet: &RayPacket<N>,
        live: &[bool; N],
        occluded: &mut [bool; N],
        cost: &mut TraversalCost,
    ) {
        let (kind, first) = self.kind_and_first(id);
        match kind {
            Kind::Instance => {
                let i = first as usize;
                let mesh = &self.meshes[self.instance_mesh[i] as usize];
                let local = packet.mapped(&self.instance_to_object.get(i), live);
                packet::mesh_occluded(mesh, &local, live, occluded, cost)
            }
            Kind::Triangles => packet::triangle_range_occluded(
                &self.triangles,
                first,
                self.count[id as usize],
                packet,
                live,
                occluded,
                cost,
            ),
            Kind::Sphere => {
                let i = first as usize;
                packet::sphere_occluded(self.centre.get(i), self.radius[i], packet, live, occluded, cost)
            }
            Kind::Cuboid => {
                let i = first as usize;
                let (min, max) = (self.box_min.get(i), self.box_max.get(i));
                packet::cuboid_occluded(&self.box_to_object.get(i), min, max, packet, live, occluded, cost)
            }
        }
    }

    #[inline]
    fn unbounded_count(&self) -> u32 {
        self.plane_offset.len() as u32
    }

    #[inline]
    fn unbounded_plane(&self, i: u32) -> (Vec3, f32) {
        (self.plane_normal.get(i as usize), self.plane_offset[i as usize])
    }

    #[inline]
    fn material(&self, hit: &Hit) -> MaterialId {
        let o = match hit.stored() {
            Stored::Plane(i) => return self.plane_material[i],
            Stored::Bounded(o) => o,
        };
        match self.kind[o] {
            Kind::Instance => {
                let mesh = &self.meshes[self.instance_mesh[self.first[o] as usize] as usize];
                mesh.face_material(self.material[o], hit.prim)
            }
            _ => self.material[o],
        }
    }

    // Always inlined: a packet lane reads the surface's fields back at once, some with loads
    // wider than the stores that wrote them, which the CPU cannot forward across a call.
    #[inline(always)]
    fn surface(&self, hit: &Hit, ray: &Ray) -> SurfacePoint {
        let o = match hit.stored() {
            Stored::Plane(i) => {
                let material = self.plane_material[i];
                return super::plane_surface(
                    self.plane_normal.get(i),
                    self.plane_offset[i],
                    hit,
                    ray,
                    material,
                );
            }
            Stored::Bounded(o) => o,
        };
        let first = self.first[o] as usize;
        let material = self.material[o];
        match self.kind[o] {
            Kind::Sphere => {
                super::sphere_surface(self.centre.get(first), self.radius[first], hit, ray, material)
            }
            Kind::Triangles => {
                super::triangle_surface(self.triangles.vertices(first as u32 + hit.prim), hit, material)
            }
            Kind::Cuboid => super::cuboid_surface(
                &self.box_to_object.get(first),
                self.box_min.get(first),
                self.box_max.get(first),
                hit,
                ray,
                material,
            ),
            Kind::Instance => {
                let mesh = &self.meshes[self.instance_mesh[first] as usize];
                super::instance_surface(mesh, &self.instance_to_object.get(first), hit, material)
            }
        }
    }

    fn uv(&self, hit: &Hit, point: Vec3, origin: glam::DVec3) -> crate::geom::uv::SurfaceUv {
        use crate::geom::uv;
        let o = match hit.stored() {
            Stored::Plane(i) => return uv::planar(self.plane_normal.get(i), point, origin),
            Stored::Bounded(o) => o,
        };
        let first = self.first[o] as usize;
        match self.kind[o] {
            Kind::Sphere => uv::sphere(self.centre.get(first), point),
            Kind::Triangles => {
                super::triangle_uv(self.triangles.vertices(first as u32 + hit.prim), point, origin)
            }
            Kind::Cuboid => super::cuboid_uv(
                &self.box_to_object.get(first),
                self.box_min.get(first),
                self.box_max.get(first),
                hit,
                point,
            ),
            Kind::Instance => super::instance_uv(
                &self.meshes[self.instance_mesh[first] as usize],
                &self.instance_to_object.get(first),
                hit,
            ),
        }
    }

    fn memory_bytes(&self) -> usize {
        let xyz = [&self.centre, &self.box_min, &self.box_max, &self.plane_normal];
        let f = std::mem::size_of::<f32>();
        xyz.iter().map(|a| a.bytes()).sum::<usize>()
            + self.triangles.memory_bytes()
            + self.box_to_object.bytes()
            + self.instance_to_object.bytes()
            + self.kind.len() * (1 + 4 + 4 + 4)
            + (self.radius.len()
                + self.plane_offset.len()
                + self.plane_material.len()
                + self.instance_mesh.len())
                * f
    }

    fn meshes(&self) -> &[Arc<MeshEntry<SoaTriangles>>] {
        &self.meshes
    }
}
