//! Structure-of-arrays store: one array per coordinate, as Embree's `RTCRay4` lays out rays.
//!
//! Bounded objects are a kind tag plus a range into that kind's arrays (a polygon is a range
//! of fan triangles). Triangles keep `v0` and the precomputed edges `e1`, `e2`; boxes keep the
//! world-to-object map as four column arrays per axis.

use super::{Hit, MaterialId, PlacedObject, PrimitiveStore, SurfacePoint, UNBOUNDED_FLAG};
use crate::geom::{cuboid, plane, sphere, triangle, Placed};
use crate::math::{Affine3A, Ray, Vec3};

/// Kind of a bounded object, selecting which arrays its range indexes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Kind {
    Sphere,
    Triangles,
    Cuboid,
}

/// Three coordinate arrays.
#[derive(Debug, Clone, Default, PartialEq)]
struct Xyz {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
}

impl Xyz {
    #[inline]
    fn push(&mut self, v: Vec3) {
        self.x.push(v.x);
        self.y.push(v.y);
        self.z.push(v.z);
    }

    #[inline]
    fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    fn bytes(&self) -> usize {
        3 * self.x.len() * std::mem::size_of::<f32>()
    }
}

/// Structure-of-arrays primitive store.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SoaStore {
    // Bounded objects.
    kind: Vec<Kind>,
    first: Vec<u32>,
    count: Vec<u32>,
    material: Vec<MaterialId>,
    // Spheres.
    centre: Xyz,
    radius: Vec<f32>,
    // Triangles.
    v0: Xyz,
    e1: Xyz,
    e2: Xyz,
    // Boxes: world-to-object map columns, and object-space corners.
    to_object_x: Xyz,
    to_object_y: Xyz,
    to_object_z: Xyz,
    to_object_w: Xyz,
    box_min: Xyz,
    box_max: Xyz,
    // Planes.
    plane_normal: Xyz,
    plane_offset: Vec<f32>,
    plane_material: Vec<MaterialId>,
}

impl SoaStore {
    fn to_object(&self, i: usize) -> Affine3A {
        Affine3A::from_cols(
            self.to_object_x.get(i).into(),
            self.to_object_y.get(i).into(),
            self.to_object_z.get(i).into(),
            self.to_object_w.get(i).into(),
        )
    }
}

impl PrimitiveStore for SoaStore {
    fn build(bounded: &[PlacedObject], unbounded: &[PlacedObject]) -> Self {
        let mut s = SoaStore::default();
        for obj in bounded {
            let (kind, first, count) = match &obj.geometry {
                Placed::Sphere { centre, radius } => {
                    s.centre.push(*centre);
                    s.radius.push(*radius);
                    (Kind::Sphere, s.radius.len() - 1, 1)
                }
                Placed::Triangles(tris) => {
                    let first = s.v0.x.len();
                    for [v0, e1, e2] in tris {
                        s.v0.push(*v0);
                        s.e1.push(*e1);
                        s.e2.push(*e2);
                    }
                    (Kind::Triangles, first, tris.len())
                }
                Placed::Cuboid { to_object, min, max, .. } => {
                    s.to_object_x.push(to_object.matrix3.x_axis.into());
                    s.to_object_y.push(to_object.matrix3.y_axis.into());
                    s.to_object_z.push(to_object.matrix3.z_axis.into());
                    s.to_object_w.push(to_object.translation.into());
                    s.box_min.push(*min);
                    s.box_max.push(*max);
                    (Kind::Cuboid, s.box_min.x.len() - 1, 1)
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
    fn intersect_bounded(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let o = id as usize;
        let first = self.first[o] as usize;
        match self.kind[o] {
            Kind::Sphere => sphere::intersect(self.centre.get(first), self.radius[first], ray, t_min, t_max)
                .map(|t| Hit { t, object: id, prim: 0 }),
            Kind::Triangles => {
                let mut best: Option<Hit> = None;
                let mut t_best = t_max;
                for i in first..first + self.count[o] as usize {
                    if let Some(h) = triangle::intersect(
                        self.v0.get(i),
                        self.e1.get(i),
                        self.e2.get(i),
                        ray,
                        t_min,
                        t_best,
                    ) {
                        t_best = h.t;
                        best = Some(Hit { t: h.t, object: id, prim: (i - first) as u32 });
                    }
                }
                best
            }
            Kind::Cuboid => cuboid::intersect(
                &self.to_object(first),
                self.box_min.get(first),
                self.box_max.get(first),
                ray,
                t_min,
                t_max,
            )
            .map(|h| {
                // Face code: axis in the low bits, sign in bit 2.
                let axis = if h.local_normal.x != 0.0 {
                    0
                } else if h.local_normal.y != 0.0 {
                    1
                } else {
                    2
                };
                let negative = (h.local_normal[axis] < 0.0) as u32;
                Hit { t: h.t, object: id, prim: axis as u32 | negative << 2 }
            }),
        }
    }

    #[inline]
    fn unbounded_count(&self) -> u32 {
        self.plane_offset.len() as u32
    }

    #[inline]
    fn intersect_unbounded(&self, i: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let p = i as usize;
        plane::intersect(self.plane_normal.get(p), self.plane_offset[p], ray, t_min, t_max).map(|t| Hit {
            t,
            object: i | UNBOUNDED_FLAG,
            prim: 0,
        })
    }

    #[inline]
    fn material(&self, hit: &Hit) -> MaterialId {
        if hit.object & UNBOUNDED_FLAG != 0 {
            self.plane_material[(hit.object & !UNBOUNDED_FLAG) as usize]
        } else {
            self.material[hit.object as usize]
        }
    }

    fn surface(&self, hit: &Hit, ray: &Ray) -> SurfacePoint {
        let point = ray.at(hit.t);
        if hit.object & UNBOUNDED_FLAG != 0 {
            let i = (hit.object & !UNBOUNDED_FLAG) as usize;
            return SurfacePoint {
                point,
                normal: self.plane_normal.get(i),
                material: self.plane_material[i],
            };
        }
        let o = hit.object as usize;
        let first = self.first[o] as usize;
        let normal = match self.kind[o] {
            Kind::Sphere => sphere::normal(self.centre.get(first), self.radius[first], point),
            Kind::Triangles => {
                let i = first + hit.prim as usize;
                triangle::normal(self.e1.get(i), self.e2.get(i))
            }
            Kind::Cuboid => {
                let mut local = Vec3::ZERO;
                local[(hit.prim & 3) as usize] = if hit.prim & 4 != 0 { -1.0 } else { 1.0 };
                cuboid::world_normal(&self.to_object(first), local)
            }
        };
        SurfacePoint { point, normal, material: self.material[o] }
    }

    fn memory_bytes(&self) -> usize {
        let xyz = [
            &self.centre,
            &self.v0,
            &self.e1,
            &self.e2,
            &self.to_object_x,
            &self.to_object_y,
            &self.to_object_z,
            &self.to_object_w,
            &self.box_min,
            &self.box_max,
            &self.plane_normal,
        ];
        let f = std::mem::size_of::<f32>();
        xyz.iter().map(|a| a.bytes()).sum::<usize>()
            + self.kind.len() * (1 + 4 + 4 + 4)
            + (self.radius.len() + self.plane_offset.len() + self.plane_material.len()) * f
    }
}
