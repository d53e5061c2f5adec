//! Triangles in the structure-of-arrays layout: each vertex as three coordinate arrays, the
//! watertight test's input.

use super::columns::Xyz;
use crate::accel::packet::Footprint;
use crate::geom::mesh::MeshData;
use crate::geom::triangle::{self, TriangleHit, WatertightRay};
use crate::math::Vec3;
use crate::store::{screen_by, TriangleLayout};

/// Triangles as nine coordinate arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SoaTriangles {
    v0: Xyz,
    v1: Xyz,
    v2: Xyz,
}

impl TriangleLayout for SoaTriangles {
    fn from_mesh(mesh: &MeshData) -> Self {
        Self::from_vertices(mesh.indices.iter().map(|f| f.map(|k| mesh.positions[k as usize])))
    }

    fn from_vertices(tris: impl IntoIterator<Item = [Vec3; 3]>) -> Self {
        let mut s = Self::default();
        for [a, b, c] in tris {
            s.v0.push(a);
            s.v1.push(b);
            s.v2.push(c);
        }
        s
    }

    #[inline]
    fn len(&self) -> u32 {
        self.v0.x.len() as u32
    }

    #[inline(always)]
    fn vertices(&self, i: u32) -> [Vec3; 3] {
        let i = i as usize;
        [self.v0.get(i), self.v1.get(i), self.v2.get(i)]
    }

    #[inline]
    fn intersect(&self, i: u32, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        let i = i as usize;
        triangle::intersect(self.v0.get(i), self.v1.get(i), self.v2.get(i), ray, t_min, t_max)
    }

    fn memory_bytes(&self) -> usize {
        self.v0.bytes() + self.v1.bytes() + self.v2.bytes()
    }

    /// Reads only the two cross axes' columns: six coordinates per triangle, not nine.
    #[inline(always)]
    fn screen(&self, ids: &[u32], footprint: &Footprint) -> u64 {
        let [u, v] = footprint.cross;
        let us = [self.v0.axis(u), self.v1.axis(u), self.v2.axis(u)];
        let vs = [self.v0.axis(v), self.v1.axis(v), self.v2.axis(v)];
        screen_by(ids, footprint, |id| (us.map(|c| c[id as usize]), vs.map(|c| c[id as usize])))
    }
}
