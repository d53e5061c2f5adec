//! The uniform grid's data layout: compressed rows (`cell_start`, `prim_ids`).

use crate::math::{Aabb, Vec3};

/// A uniform voxel grid over a box, storing per cell the ids of the objects that overlap it.
///
/// Cell `c`'s ids are `prim_ids[cell_start[c] .. cell_start[c + 1]]`, sorted ascending.
/// Cells are numbered `x + dims.x * (y + dims.y * z)`.
#[derive(Debug, Clone, PartialEq)]
pub struct UniformGrid {
    /// The box the cells tile (empty for a grid with no objects).
    pub bounds: Aabb,
    /// Number of cells per axis, each ≥ 1.
    pub dims: [u32; 3],
    /// Size of one cell per axis.
    pub cell_size: Vec3,
    /// `1 / cell_size` per axis.
    pub inv_cell_size: Vec3,
    /// Row offsets into `prim_ids`, one per cell plus a final end offset.
    pub cell_start: Vec<u32>,
    /// Object ids of all cells, concatenated.
    pub prim_ids: Vec<u32>,
}

impl UniformGrid {
    /// A grid holding nothing: every walk over it is empty.
    pub fn empty() -> Self {
        Self {
            bounds: Aabb::EMPTY,
            dims: [1, 1, 1],
            cell_size: Vec3::ONE,
            inv_cell_size: Vec3::ONE,
            cell_start: vec![0, 0],
            prim_ids: Vec::new(),
        }
    }

    /// Total number of cells.
    #[inline]
    pub fn cell_count(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }

    /// Linear index of cell `(x, y, z)`.
    #[inline]
    pub fn cell_index(&self, x: u32, y: u32, z: u32) -> u32 {
        x + self.dims[0] * (y + self.dims[1] * z)
    }

    /// The ids stored in a cell.
    #[inline]
    pub fn cell_prims(&self, cell: u32) -> &[u32] {
        let c = cell as usize;
        &self.prim_ids[self.cell_start[c] as usize..self.cell_start[c + 1] as usize]
    }

    /// The box of cell `(x, y, z)`.
    pub fn cell_bounds(&self, x: u32, y: u32, z: u32) -> Aabb {
        let lo = Vec3::new(self.plane(0, x), self.plane(1, y), self.plane(2, z));
        let hi = Vec3::new(self.plane(0, x + 1), self.plane(1, y + 1), self.plane(2, z + 1));
        Aabb::new(lo, hi)
    }

    /// Coordinate of the `i`-th cell wall on `axis` (`0..=dims[axis]`); the last wall is exactly
    /// the grid's bound, whatever the rounding. The DDA steps through these same walls.
    #[inline]
    pub fn plane(&self, axis: usize, i: u32) -> f32 {
        if i >= self.dims[axis] {
            self.bounds.max[axis]
        } else {
            self.bounds.min[axis] + i as f32 * self.cell_size[axis]
        }
    }

    /// The range of cells (inclusive) covered by a box, clamped to the grid.
    pub fn cell_range(&self, b: &Aabb) -> ([u32; 3], [u32; 3]) {
        let lo = self.cell_coords(b.min);
        let hi = self.cell_coords(b.max);
        (lo, hi)
    }

    /// The cell holding point `p`, clamped into the grid.
    #[inline]
    pub fn cell_coords(&self, p: Vec3) -> [u32; 3] {
        let rel = (p - self.bounds.min) * self.inv_cell_size;
        let clamp = |v: f32, d: u32| (v.floor().max(0.0) as u32).min(d - 1);
        [clamp(rel.x, self.dims[0]), clamp(rel.y, self.dims[1]), clamp(rel.z, self.dims[2])]
    }

    /// Bytes held by the grid's arrays.
    pub fn memory_bytes(&self) -> usize {
        (self.cell_start.len() + self.prim_ids.len()) * std::mem::size_of::<u32>()
    }

    /// Total number of stored references (an object counts once per overlapped cell).
    pub fn reference_count(&self) -> usize {
        self.prim_ids.len()
    }
}
