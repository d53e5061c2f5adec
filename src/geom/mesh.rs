//! Indexed triangle meshes in object space, as loaded from a file.

use crate::math::{Aabb, Vec3};

/// An indexed triangle mesh in object space, as loaded from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit per-vertex shading normals, same indexing as `positions`; empty for flat facets.
    pub normals: Vec<Vec3>,
    /// Triangles as indices into `positions` (counter-clockwise seen from the front).
    pub indices: Vec<[u32; 3]>,
    /// Bounds of the positions used by faces.
    pub bounds: Aabb,
}

impl MeshData {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Bytes held by the arrays.
    pub fn memory_bytes(&self) -> usize {
        (self.positions.len() + self.normals.len()) * 12 + self.indices.len() * 12
    }

    /// Recomputes `bounds`.
    pub fn update_bounds(&mut self) {
        self.bounds = Aabb::from_points(self.indices.iter().flatten().map(|&i| self.positions[i as usize]));
    }
}
