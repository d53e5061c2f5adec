//! Mesh assets and the bottom level of the two-level grid.
//!
//! A [`MeshAsset`] is a mesh in object space with its own uniform grid, built once when the
//! scene is loaded and shared (through `Arc`) by every instance and every frame. A
//! [`MeshEntry`] adds the triangles in one store layout. Rays reach a mesh through an instance's
//! world-to-object map: the direction is not renormalised, so the object-space ray parameter
//! equals the world one and hits compare directly with the rest of the scene.

use std::sync::Arc;
use std::time::Instant;

use super::{MaterialId, ObjectId, TriangleLayout};
use crate::accel::{walk, GridBuilder, Tally, UniformGrid};
use crate::geom::mesh::MeshData;
use crate::geom::triangle::{self, nearest_in_block, TriangleBlock, TriangleHit, WatertightRay};
use crate::math::{gamma, transform_error, Affine3A, Ray, Vec3};
use crate::simd::SimdLevel;

/// A mesh in object space with its grid: what every instance of the mesh shares.
#[derive(Debug, Clone)]
pub struct MeshAsset {
    /// Where the mesh came from (the file name as the scene gives it).
    pub name: String,
    /// Positions, normals and faces.
    pub data: MeshData,
    /// Object-space grid over the triangles (ids are triangle indices).
    pub grid: UniformGrid,
    /// Seconds the grid build took.
    pub build_seconds: f64,
}

impl MeshAsset {
    /// Builds the asset's grid with density `lambda` (in parallel, exact triangle/cell tests).
    ///
    /// Faces are first put in Morton (Z-curve) order of their centroids, so that triangles
    /// near each other in space are near each other in memory: a cell's triangles then share
    /// cache lines in either store layout. Triangle indices in hits refer to this order.
    pub fn new(name: impl Into<String>, mut data: MeshData, lambda: f32) -> Self {
        let started = Instant::now();
        morton_order(&mut data);
        let tri = |i: usize| data.indices[i].map(|k| data.positions[k as usize]);
        let bounds: Vec<_> = (0..data.indices.len())
            .map(|i| {
                let [a, b, c] = tri(i);
                triangle::bounds(a, b, c)
            })
            .collect();
        let grid = GridBuilder::new(lambda).build(&bounds, |id, cell| {
            let [a, b, c] = tri(id as usize);
            triangle::overlaps_box(a, b, c, cell)
        });
        Self { name: name.into(), data, grid, build_seconds: started.elapsed().as_secs_f64() }
    }

    /// Bytes of the mesh data and its grid (layout copies are counted by the stores).
    pub fn memory_bytes(&self) -> usize {
        self.data.memory_bytes() + self.grid.memory_bytes()
    }

    /// Unit shading normal in object space at barycentrics `(u, v)` of triangle `i`: the
    /// interpolated vertex normals, or `geometric` for a flat mesh (or where they cancel).
    pub fn shading_normal(&self, i: u32, u: f32, v: f32, geometric: Vec3) -> Vec3 {
        if self.data.normals.is_empty() {
            return geometric;
        }
        let [a, b, c] = self.data.indices[i as usize].map(|k| self.data.normals[k as usize]);
        (a * (1.0 - u - v) + b * u + c * v).try_normalize().unwrap_or(geometric)
    }
}

/// Sorts the faces of `data` by the Morton code of their centroids (10 bits per axis over the
/// mesh bounds; ties keep file order, so the result is deterministic).
fn morton_order(data: &mut MeshData) {
    let b = data.bounds;
    if b.is_empty() {
        return;
    }
    let scale = Vec3::splat(1023.0) / (b.max - b.min).max(Vec3::splat(f32::MIN_POSITIVE));
    let spread = |v: u32| {
        // Insert two zero bits between each of the low 10 bits.
        let mut x = v & 0x3ff;
        x = (x | x << 16) & 0x0300_00ff;
        x = (x | x << 8) & 0x0300_f00f;
        x = (x | x << 4) & 0x030c_30c3;
        (x | x << 2) & 0x0924_9249
    };
    let code = |f: &[u32; 3]| {
        let c =
            f.iter().map(|&k| data.positions.get(k as usize).copied().unwrap_or(b.min)).sum::<Vec3>() / 3.0;
        let q = ((c - b.min) * scale).clamp(Vec3::ZERO, Vec3::splat(1023.0));
        spread(q.x as u32) << 2 | spread(q.y as u32) << 1 | spread(q.z as u32)
    };
    // Per-face materials move with their faces.
    let materials = std::mem::take(&mut data.face_material);
    let mut keyed: Vec<(u32, [u32; 3], u32)> = data
        .indices
        .iter()
        .enumerate()
        .map(|(i, f)| (code(f), *f, materials.get(i).copied().unwrap_or(0)))
        .collect();
    keyed.sort_by_key(|&(k, ..)| k);
    if !materials.is_empty() {
        data.face_material = keyed.iter().map(|&(.., m)| m).collect();
    }
    data.indices = keyed.into_iter().map(|(_, f, _)| f).collect();
}

/// A mesh asset with its triangles in layout `L`.
#[derive(Debug)]
pub struct MeshEntry<L: TriangleLayout> {
    /// The shared asset.
    pub asset: Arc<MeshAsset>,
    /// Its triangles, laid out for the tracer.
    pub triangles: L,
}

impl<L: TriangleLayout> MeshEntry<L> {
    /// The material of triangle `prim` of an instance drawn with `base`: `base` itself, or, for
    /// a mesh with its file's materials, `base` plus the triangle's index into them (the
    /// instance's block of the material table).
    #[inline]
    pub fn face_material(&self, base: MaterialId, prim: u32) -> MaterialId {
        match self.asset.data.face_material.get(prim as usize) {
            Some(&i) => MaterialId(base.0 + i),
            None => base,
        }
    }

    /// Lays out the asset's triangles.
    pub fn new(asset: Arc<MeshAsset>) -> Self {
        let triangles = L::from_mesh(&asset.data);
        Self { asset, triangles }
    }

    /// Bytes of the layout copy.
    pub fn memory_bytes(&self) -> usize {
        self.triangles.memory_bytes()
    }
}

/// The object-space ray of an instance: origin and direction mapped by `to_object`, the
/// direction left unnormalised so that ray parameters agree with world space.
#[inline]
pub fn object_ray(to_object: &Affine3A, ray: &Ray) -> Ray {
    Ray::new(to_object.transform_point3(ray.origin), to_object.transform_vector3(ray.dir))
}

/// Triangles one ray tests together ([`nearest_in_block`]).
const BLOCK: usize = 8;

/// Fewest triangles worth a block: fewer are tested one by one.
const MIN_BLOCK: usize = 3;

/// Nearest triangle hit in `(t_min, t_max)` with its index, walking the mesh grid front to back
/// ([`walk::nearest`]), adding the cells visited and triangles tested to `cost`. A cell's
/// triangles are tested together, `BLOCK` at a time, at this thread's
/// [`crate::simd::single_ray_level`] (one at a time at `Scalar`); every level finds the same hit.
#[inline]
pub fn intersect<L: TriangleLayout, T: Tally>(
    mesh: &MeshEntry<L>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    cost: &mut T,
) -> Option<(u32, TriangleHit)> {
    let wray = WatertightRay::new(ray);
    let grid = &mesh.asset.grid;
    let level = crate::simd::single_ray_level();
    if level == SimdLevel::Scalar {
        return walk::nearest(grid, ray, t_min, t_max, cost, |i, bound, cost| {
            cost.tests(1);
            mesh.triangles.intersect(i, &wray, t_min, bound).map(|h| (h.t, (i, h)))
        });
    }
    level.run(
        #[inline(always)]
        || {
            walk::nearest_by_cell(grid, ray, t_min, t_max, cost, |ids, bound, cost| {
                cost.tests(ids.len() as u32);
                nearest_in_cell(&mesh.triangles, ids, &wray, t_min, bound).map(|(i, h)| (h.t, (i, h)))
            })
        },
    )
}

/// The nearest hit below `bound` among a cell's triangles `ids`, the first of equally near ones
/// (as testing them in order finds): blocks of [`BLOCK`] through [`nearest_in_block`], a short
/// tail one by one.
#[inline(always)]
fn nearest_in_cell<L: TriangleLayout>(
    triangles: &L,
    ids: &[u32],
    wray: &WatertightRay,
    t_min: f32,
    mut bound: f32,
) -> Option<(u32, TriangleHit)> {
    let mut best = None;
    for chunk in ids.chunks(BLOCK) {
        if chunk.len() < MIN_BLOCK {
            for &i in chunk {
                if let Some(h) = triangles.intersect(i, wray, t_min, bound) {
                    bound = h.t;
                    best = Some((i, h));
                }
            }
            continue;
        }
        let vertices = |k: usize| triangles.vertices(chunk[k]);
        let block = TriangleBlock::<BLOCK>::gather(wray, chunk.len(), vertices);
        if let Some((k, h)) = nearest_in_block(&block, wray, t_min, bound, vertices) {
            bound = h.t;
            best = Some((chunk[k], h));
        }
    }
    best
}

/// True when some triangle is hit in `(t_min, t_max)` (stops at the first cell with one),
/// walking the mesh grid ([`walk::any`]) and adding the cells visited and triangles tested to
/// `cost`; a cell's triangles are tested together at this thread's
/// [`crate::simd::single_ray_level`].
#[inline]
pub fn occluded<L: TriangleLayout, T: Tally>(
    mesh: &MeshEntry<L>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    cost: &mut T,
) -> bool {
    let wray = WatertightRay::new(ray);
    let grid = &mesh.asset.grid;
    let level = crate::simd::single_ray_level();
    if level == SimdLevel::Scalar {
        return walk::any(grid, ray, t_min, t_max, cost, |i, cost| {
            cost.tests(1);
            mesh.triangles.intersect(i, &wray, t_min, t_max).is_some()
        });
    }
    level.run(
        #[inline(always)]
        || {
            walk::any_by_cell(grid, ray, t_min, t_max, cost, |ids, cost| {
                cost.tests(ids.len() as u32);
                nearest_in_cell(&mesh.triangles, ids, &wray, t_min, t_max).is_some()
            })
        },
    )
}

/// Nearest triangle hit by testing every triangle: the reference for the mesh grid
/// ([`crate::testing::BruteForce`]).
pub(crate) fn intersect_brute<L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<(u32, TriangleHit)> {
    let wray = WatertightRay::new(ray);
    let mut best = None;
    let mut t_best = t_max;
    for i in 0..mesh.triangles.len() {
        if let Some(h) = mesh.triangles.intersect(i, &wray, t_min, t_best) {
            t_best = h.t;
            best = Some((i, h));
        }
    }
    best
}

/// Nearest hit of a ray with mesh instance `object`: the ray enters the mesh through
/// `to_object` (shared by both store layouts).
#[inline]
pub fn instance_hit<L: TriangleLayout, T: Tally>(
    mesh: &MeshEntry<L>,
    to_object: &Affine3A,
    object: ObjectId,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    cost: &mut T,
) -> Option<super::Hit> {
    intersect(mesh, &object_ray(to_object, ray), t_min, t_max, cost)
        .map(|(i, h)| super::Hit::triangle(object, i, &h))
}

/// A hit on a mesh instance in world space: the point, the bound on its distance from the
/// triangle along the geometric normal, the geometric and shading normals, and the lift of the
/// point for rays leaving its front (see [`super::SurfacePoint`]). Normals map by the transpose
/// of the world-to-object map's linear part.
///
/// The point is interpolated from the object-space vertices and mapped to the world. A ray
/// leaving it meets the triangle again only through `to_object`, so the bound is measured in
/// object space: the mapped-back point's distance from the triangle's plane, plus the rounding
/// of that measurement and of the next ray's own map, converted to world units along the normal.
///
/// Always inlined: its result, returned through memory, was read back at once with loads wider
/// than the stores that wrote it, which the CPU cannot forward.
#[inline(always)]
pub fn instance_surface<L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    to_object: &Affine3A,
    hit: &super::Hit,
) -> InstanceSurface {
    let [a, b, c] = mesh.triangles.vertices(hit.prim);
    let (e1, e2) = (b - a, c - a);
    let local = e1.cross(e2);
    let normal_map = to_object.matrix3.transpose();
    let geometric = normal_map.mul_vec3(local).try_normalize().unwrap_or(Vec3::Y);
    let w = [1.0 - hit.u - hit.v, hit.u, hit.v];
    let p = a * w[0] + b * hit.u + c * hit.v;
    let point = to_object.inverse().transform_point3(p);
    let error = match local.try_normalize() {
        Some(n) => {
            let back = to_object.transform_point3(point);
            let rel = back - a;
            // The computed normal's direction is off by about γ(8)·|e1|·|e2| / |e1 × e2| radians.
            let tilt = gamma(8) * (e1.length_squared() * e2.length_squared() / local.length_squared()).sqrt();
            // The triangle test's own rounding, for a ray starting there (object units).
            let test = triangle::TEST_ERROR * triangle::reach(a, b, c, p);
            let residual = rel.dot(n).abs() + rel.length() * (gamma(4) + tilt) + test;
            let mapping = 2.0 * transform_error(to_object, point).dot(n.abs());
            (residual + mapping) / normal_map.mul_vec3(n).length()
        }
        // A degenerate triangle is never hit; keep the bound finite.
        None => gamma(8) * point.abs().max_element(),
    };
    let data = &mesh.asset.data;
    if data.normals.is_empty() {
        return InstanceSurface { point, error, geometric, shading: geometric, lift: Vec3::ZERO };
    }
    let mut local_shading = mesh.asset.shading_normal(hit.prim, hit.u, hit.v, local);
    // A face wound against its neighbours (scanned meshes have some) keeps its own side.
    if local_shading.dot(local) < 0.0 {
        local_shading = -local_shading;
    }
    let shading = normal_map.mul_vec3(local_shading).try_normalize().unwrap_or(geometric);
    // Lift: project the hit point onto each vertex's tangent plane and blend with the
    // barycentrics; keep it only where it lies above the facet (convex parts).
    // Written out rather than zipped over arrays: the zipped iterators were built on the stack
    // and read back at once with loads wider than their stores, which the CPU cannot forward
    // (7 % of this function's time on the dragon). Summed from zero, as `sum` did, for the same
    // bits.
    let [na, nb, nc] = data.indices[hit.prim as usize].map(|k| data.normals[k as usize]);
    let project = |v: Vec3, n: Vec3| p - (p - v).dot(n) * n;
    let lifted = Vec3::ZERO + project(a, na) * w[0] + project(b, nb) * w[1] + project(c, nc) * w[2];
    let offset = lifted - p;
    let lift = if offset.dot(local) > 0.0 {
        let world = to_object.matrix3.inverse().mul_vec3(offset);
        if world.is_finite() {
            world
        } else {
            Vec3::ZERO
        }
    } else {
        Vec3::ZERO
    };
    InstanceSurface { point, error, geometric, shading, lift }
}

/// What [`instance_surface`] finds at a hit on a mesh instance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstanceSurface {
    /// World position.
    pub point: Vec3,
    /// Bound on the point's distance from the triangle along `geometric`, in world units.
    pub error: f32,
    /// Unit geometric normal.
    pub geometric: Vec3,
    /// Unit shading normal.
    pub shading: Vec3,
    /// Lift of the point for rays leaving the front.
    pub lift: Vec3,
}
