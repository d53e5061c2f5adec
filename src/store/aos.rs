//! Array-of-structures store: the structure-of-arrays store's twin, one struct per primitive
//! (a triangle's three vertices together, an object's shape and material together), for
//! measuring what the layout alone is worth.

use std::sync::Arc;

use super::mesh::{self, MeshEntry};
use super::packet::{self, PacketHits};
use super::{
    Hit, MaterialId, PlacedObject, PrimitiveStore, SurfacePoint, Tally, TraversalCost, TriangleLayout,
};
use super::{ObjectId, Stored};
use crate::geom::mesh::MeshData;
use crate::geom::triangle::{self, TriangleHit, WatertightRay};
use crate::geom::{sphere, Placed};
use crate::math::{Affine3A, Ray, RayPacket, Vec3};

/// One triangle: its three vertices side by side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AosTriangle {
    /// First vertex.
    pub v0: Vec3,
    /// Second vertex.
    pub v1: Vec3,
    /// Third vertex.
    pub v2: Vec3,
}

/// Triangles as one array of [`AosTriangle`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AosTriangles(Vec<AosTriangle>);

impl TriangleLayout for AosTriangles {
    fn from_mesh(mesh: &MeshData) -> Self {
        Self::from_vertices(mesh.indices.iter().map(|f| f.map(|k| mesh.positions[k as usize])))
    }

    fn from_vertices(tris: impl IntoIterator<Item = [Vec3; 3]>) -> Self {
        Self(tris.into_iter().map(|[v0, v1, v2]| AosTriangle { v0, v1, v2 }).collect())
    }

    #[inline]
    fn len(&self) -> u32 {
        self.0.len() as u32
    }

    #[inline]
    fn vertices(&self, i: u32) -> [Vec3; 3] {
        let t = &self.0[i as usize];
        [t.v0, t.v1, t.v2]
    }

    #[inline]
    fn intersect(&self, i: u32, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        let t = &self.0[i as usize];
        triangle::intersect(t.v0, t.v1, t.v2, ray, t_min, t_max)
    }

    fn memory_bytes(&self) -> usize {
        self.0.len() * std::mem::size_of::<AosTriangle>()
    }
}

/// The shape of one bounded object, with its data inline.
#[derive(Debug, Clone, Copy, PartialEq)]
enum AosShape {
    Sphere { centre: Vec3, radius: f32 },
    Triangles { first: u32, count: u32 },
    Cuboid { to_object: Affine3A, min: Vec3, max: Vec3 },
    Instance { to_object: Affine3A, mesh: u32 },
}

/// One bounded object.
#[derive(Debug, Clone, Copy, PartialEq)]
struct AosObject {
    shape: AosShape,
    material: MaterialId,
}

/// One plane.
#[derive(Debug, Clone, Copy, PartialEq)]
struct AosPlane {
    normal: Vec3,
    offset: f32,
    material: MaterialId,
}

/// Array-of-structures primitive store.
#[derive(Debug, Clone, Default)]
pub struct AosStore {
    objects: Vec<AosObject>,
    triangles: AosTriangles,
    planes: Vec<AosPlane>,
    meshes: Vec<Arc<MeshEntry<AosTriangles>>>,
}

impl AosStore {
    /// Bounded object `id`'s mesh and world-to-object map, when it is a mesh instance.
    pub(crate) fn instance(&self, id: u32) -> Option<(&MeshEntry<AosTriangles>, Affine3A)> {
        match self.objects[id as usize].shape {
            AosShape::Instance { to_object, mesh } => Some((&*self.meshes[mesh as usize], to_object)),
            _ => None,
        }
    }
}

impl AosStore {
    /// [`PrimitiveStore::intersect_bounded`] of any bounded object, out of line (spheres, the
    /// commonest, take the inlined [`super::sphere_hit`] first).
    fn intersect_any<T: Tally>(
        &self,
        id: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        cost: &mut T,
    ) -> Option<Hit> {
        match &self.objects[id as usize].shape {
            AosShape::Sphere { centre, radius } => {
                super::sphere_hit(*centre, *radius, id, ray, t_min, t_max, cost)
            }
            AosShape::Triangles { first, count } => {
                cost.tests(*count);
                super::triangle_range_hit(
                    &self.triangles,
                    ObjectId::bounded(id),
                    *first,
                    *count,
                    ray,
                    t_min,
                    t_max,
                )
            }
            AosShape::Cuboid { to_object, min, max } => {
                cost.tests(1);
                super::cuboid_hit(to_object, *min, *max, ObjectId::bounded(id), ray, t_min, t_max)
            }
            AosShape::Instance { to_object, mesh } => mesh::instance_hit(
                &self.meshes[*mesh as usize],
                to_object,
                ObjectId::bounded(id),
                ray,
                t_min,
                t_max,
                cost,
            ),
        }
    }
}

impl PrimitiveStore for AosStore {
    type Triangles = AosTriangles;

    fn build(
        bounded: &[PlacedObject],
        unbounded: &[PlacedObject],
        meshes: &[Arc<MeshEntry<AosTriangles>>],
    ) -> Self {
        let mut tris = Vec::new();
        let mut objects = Vec::with_capacity(bounded.len());
        for obj in bounded {
            let shape = match &obj.geometry {
                Placed::Sphere { centre, radius } => AosShape::Sphere { centre: *centre, radius: *radius },
                Placed::Triangles(list) => {
                    let first = tris.len() as u32;
                    tris.extend_from_slice(list);
                    AosShape::Triangles { first, count: list.len() as u32 }
                }
                Placed::Cuboid { to_object, min, max, .. } => {
                    AosShape::Cuboid { to_object: *to_object, min: *min, max: *max }
                }
                Placed::Instance { mesh, to_object, .. } => {
                    debug_assert!((mesh.0 as usize) < meshes.len(), "instance of an unknown mesh");
                    AosShape::Instance { to_object: *to_object, mesh: mesh.0 }
                }
                Placed::Plane { .. } => {
                    debug_assert!(false, "planes are unbounded and belong in the unbounded list");
                    continue;
                }
            };
            objects.push(AosObject { shape, material: obj.material });
        }
        let planes = unbounded
            .iter()
            .filter_map(|obj| match obj.geometry {
                Placed::Plane { normal, offset } => Some(AosPlane { normal, offset, material: obj.material }),
                _ => None,
            })
            .collect();
        Self { objects, triangles: AosTriangles::from_vertices(tris), planes, meshes: meshes.to_vec() }
    }

    #[inline]
    fn bounded_count(&self) -> u32 {
        self.objects.len() as u32
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
        // Spheres, the commonest object, are tested in the caller's loop (as the SoA store does).
        match &self.objects[id as usize].shape {
            AosShape::Sphere { centre, radius } => {
                super::sphere_hit(*centre, *radius, id, ray, t_min, t_max, cost)
            }
            _ => self.intersect_any(id, ray, t_min, t_max, cost),
        }
    }

    #[inline]
    fn occludes_bounded<T: Tally>(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32, cost: &mut T) -> bool {
        match &self.objects[id as usize].shape {
            AosShape::Instance { to_object, mesh } => {
                let local = mesh::object_ray(to_object, ray);
                mesh::occluded(&self.meshes[*mesh as usize], &local, t_min, t_max, cost)
            }
            // The commonest blocker.
            AosShape::Sphere { centre, radius } => {
                super::sphere_hit(*centre, *radius, id, ray, t_min, t_max, cost).is_some()
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
        match &self.objects[id as usize].shape {
            AosShape::Instance { to_object, mesh } => {
                let mesh = &self.meshes[*mesh as usize];
                packet::instance_hits(mesh, to_object, ObjectId::bounded(id), packet, live, hits, cost)
            }
            AosShape::Triangles { first, count } => packet::triangle_range_hits(
                &self.triangles,
                ObjectId::bounded(id),
                *first,
                *count,
                packet,
                live,
                hits,
                cost,
            ),
            AosShape::Sphere { centre, radius } => {
                packet::sphere_hits(*centre, *radius, ObjectId::bounded(id), packet, live, hits, cost)
            }
            AosShape::Cuboid { to_object, min, max } => {
                packet::cuboid_hits(to_object, *min, *max, ObjectId::bounded(id), packet, live, hits, cost)
            }
        }
    }

    #[inline(always)]
    fn may_meet(&self, id: u32, footprint: &crate::math::Aabb) -> bool {
        match &self.objects[id as usize].shape {
            AosShape::Sphere { centre, radius } => sphere::bounds_meet(*centre, *radius, footprint),
            _ => true,
        }
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
        match &self.objects[id as usize].shape {
            AosShape::Instance { to_object, mesh } => {
                let local = packet.mapped(to_object, live);
                packet::mesh_occluded(&self.meshes[*mesh as usize], &local, live, occluded, cost)
            }
            AosShape::Triangles { first, count } => {
                packet::triangle_range_occluded(&self.triangles, *first, *count, packet, live, occluded, cost)
            }
            AosShape::Sphere { centre, radius } => {
                packet::sphere_occluded(*centre, *radius, packet, live, occluded, cost)
            }
            AosShape::Cuboid { to_object, min, max } => {
                packet::cuboid_occluded(to_object, *min, *max, packet, live, occluded, cost)
            }
        }
    }

    #[inline]
    fn unbounded_count(&self) -> u32 {
        self.planes.len() as u32
    }

    #[inline]
    fn unbounded_plane(&self, i: u32) -> (Vec3, f32) {
        let p = &self.planes[i as usize];
        (p.normal, p.offset)
    }

    #[inline]
    fn material(&self, hit: &Hit) -> MaterialId {
        let obj = match hit.stored() {
            Stored::Plane(i) => return self.planes[i].material,
            Stored::Bounded(o) => &self.objects[o],
        };
        match &obj.shape {
            AosShape::Instance { mesh, .. } => {
                self.meshes[*mesh as usize].face_material(obj.material, hit.prim)
            }
            _ => obj.material,
        }
    }

    // Always inlined: a packet lane reads the surface's fields back at once, some with loads
    // wider than the stores that wrote them, which the CPU cannot forward across a call.
    #[inline(always)]
    fn surface(&self, hit: &Hit, ray: &Ray) -> SurfacePoint {
        let obj = match hit.stored() {
            Stored::Plane(i) => {
                let p = &self.planes[i];
                return super::plane_surface(p.normal, p.offset, hit, ray, p.material);
            }
            Stored::Bounded(o) => &self.objects[o],
        };
        match &obj.shape {
            AosShape::Sphere { centre, radius } => {
                super::sphere_surface(*centre, *radius, hit, ray, obj.material)
            }
            AosShape::Triangles { first, .. } => {
                super::triangle_surface(self.triangles.vertices(first + hit.prim), hit, obj.material)
            }
            AosShape::Cuboid { to_object, min, max } => {
                super::cuboid_surface(to_object, *min, *max, hit, ray, obj.material)
            }
            AosShape::Instance { to_object, mesh } => {
                super::instance_surface(&self.meshes[*mesh as usize], to_object, hit, obj.material)
            }
        }
    }

    fn uv(&self, hit: &Hit, point: Vec3, origin: glam::DVec3) -> crate::geom::uv::SurfaceUv {
        use crate::geom::uv;
        let obj = match hit.stored() {
            Stored::Plane(i) => return uv::planar(self.planes[i].normal, point, origin),
            Stored::Bounded(o) => &self.objects[o],
        };
        match &obj.shape {
            AosShape::Sphere { centre, .. } => uv::sphere(*centre, point),
            AosShape::Triangles { first, .. } => {
                super::triangle_uv(self.triangles.vertices(first + hit.prim), point, origin)
            }
            AosShape::Cuboid { to_object, min, max } => super::cuboid_uv(to_object, *min, *max, hit, point),
            AosShape::Instance { mesh, to_object } => {
                super::instance_uv(&self.meshes[*mesh as usize], to_object, hit)
            }
        }
    }

    fn memory_bytes(&self) -> usize {
        self.objects.len() * std::mem::size_of::<AosObject>()
            + self.triangles.memory_bytes()
            + self.planes.len() * std::mem::size_of::<AosPlane>()
    }

    fn meshes(&self) -> &[Arc<MeshEntry<AosTriangles>>] {
        &self.meshes
    }
}
