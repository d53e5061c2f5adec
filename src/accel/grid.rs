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
    /// Wall coordinates per axis (`dims[axis] + 1` each; the last is exactly the bound): the
    /// DDA reads crossings from here (see [`UniformGrid::plane`]).
    pub walls: [Vec<f32>; 3],
    /// Per cell, the Chebyshev distance in cells to the nearest non-empty cell (0 for a
    /// non-empty cell, capped at 255; empty when not computed): every cell closer than that is
    /// empty, so a walk may jump across them ("proximity clouds", Cohen and Sheffer 1994).
    pub skip: Vec<u8>,
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
            walls: [vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, 1.0]],
            skip: Vec::new(),
        }
    }

    /// Computes [`UniformGrid::skip`] from the rows: an exact Chebyshev distance transform by
    /// two raster passes over the 26-neighbourhood (forward, then backward).
    pub fn update_skip(&mut self) {
        let [dx, dy, dz] = self.dims.map(|d| d as i64);
        let mut d: Vec<u8> = (0..self.cell_count())
            .map(|c| if self.cell_start[c] == self.cell_start[c + 1] { 255 } else { 0 })
            .collect();
        let at = |x: i64, y: i64, z: i64| (x + dx * (y + dy * z)) as usize;
        // The 13 neighbours that come before a cell in raster order.
        let mut before = Vec::with_capacity(13);
        for oz in -1i64..=1 {
            for oy in -1i64..=1 {
                for ox in -1i64..=1 {
                    if (oz, oy, ox) < (0, 0, 0) {
                        before.push((ox, oy, oz));
                    }
                }
            }
        }
        let mut pass = |forward: bool| {
            let sign = if forward { 1 } else { -1 };
            for k in 0..dz * dy * dx {
                let k = if forward { k } else { dz * dy * dx - 1 - k };
                let (x, y, z) = (k % dx, k / dx % dy, k / (dx * dy));
                let here = at(x, y, z);
                let mut best = d[here];
                for &(ox, oy, oz) in &before {
                    let (nx, ny, nz) = (x + sign * ox, y + sign * oy, z + sign * oz);
                    if nx >= 0 && ny >= 0 && nz >= 0 && nx < dx && ny < dy && nz < dz {
                        best = best.min(d[at(nx, ny, nz)].saturating_add(1));
                    }
                }
                d[here] = best;
            }
        };
        pass(true);
        pass(false);
        self.skip = d;
    }

    /// Recomputes [`UniformGrid::walls`] from `bounds`, `dims` and `cell_size` (call after
    /// changing them): wall `i` is `min + i · size`, the last one exactly `max`.
    pub fn update_walls(&mut self) {
        for axis in 0..3 {
            let (min, max) = (self.bounds.min.to_array()[axis], self.bounds.max.to_array()[axis]);
            let size = self.cell_size.to_array()[axis];
            let d = self.dims[axis];
            self.walls[axis] = (0..=d).map(|i| if i == d { max } else { min + i as f32 * size }).collect();
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

    /// Whether cell `cell` holds no ids, read from the one-byte skip distances where the grid
    /// has them (a smaller array, so more of it stays in cache than of `cell_start`).
    #[inline(always)]
    pub fn known_empty(&self, cell: u32) -> bool {
        self.skip.get(cell as usize).is_some_and(|&d| d > 0)
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
        let walls = &self.walls[axis];
        walls[(i as usize).min(walls.len() - 1)]
    }

    /// The range of cells (inclusive) whose closed boxes touch the closed box `b`, clamped to
    /// the grid. Decided against the same walls as [`UniformGrid::cell_bounds`]: a box whose
    /// face lies exactly on a wall gets the cells on both sides.
    pub fn cell_range(&self, b: &Aabb) -> ([u32; 3], [u32; 3]) {
        let mut lo = self.cell_coords(b.min);
        let hi = self.cell_coords(b.max);
        for (axis, l) in lo.iter_mut().enumerate() {
            // `cell_coords` is half-open; the cell below also touches a box starting on its wall.
            if *l > 0 && b.min[axis] <= self.plane(axis, *l) {
                *l -= 1;
            }
        }
        (lo, hi)
    }

    /// The cell holding point `p`, clamped into the grid: on each axis the `i` with
    /// `plane(i) <= p < plane(i + 1)`, decided against the walls themselves so that it agrees
    /// with [`UniformGrid::cell_bounds`] and the DDA's crossings whatever the rounding of
    /// `(p - min) / size`.
    #[inline(always)]
    pub fn cell_coords(&self, p: Vec3) -> [u32; 3] {
        let rel = ((p - self.bounds.min) * self.inv_cell_size).to_array();
        let p = p.to_array();
        let mut out = [0u32; 3];
        for axis in 0..3 {
            let d = self.dims[axis];
            // Truncation is the floor of a non-negative value, and `max` sends negatives and
            // NaN to 0 first: no rounding call.
            let mut c = (rel[axis].max(0.0) as u32).min(d - 1);
            if c > 0 && p[axis] < self.plane(axis, c) {
                c -= 1;
            } else if c + 1 < d && p[axis] >= self.plane(axis, c + 1) {
                c += 1;
            }
            out[axis] = c;
        }
        out
    }

    /// Bytes held by the grid's arrays.
    pub fn memory_bytes(&self) -> usize {
        (self.cell_start.len() + self.prim_ids.len() + self.walls.iter().map(Vec::len).sum::<usize>()) * 4
            + self.skip.len()
    }

    /// Total number of stored references (an object counts once per overlapped cell).
    pub fn reference_count(&self) -> usize {
        self.prim_ids.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::GridBuilder;

    fn grid() -> UniformGrid {
        // Awkward bounds so `(p - min) * inv_cell_size` rounds differently from the walls.
        let b = [Aabb::new(Vec3::splat(-6.1), Vec3::splat(6.1))];
        GridBuilder::new(343.0).build(&b, |_, _| true)
    }

    #[test]
    fn cell_coords_agree_with_the_walls_for_points_exactly_on_them() {
        let g = grid();
        for axis in 0..3 {
            for i in 0..g.dims[axis] {
                let mut p = Vec3::splat(0.1);
                p[axis] = g.plane(axis, i);
                assert_eq!(g.cell_coords(p)[axis], i, "wall {i} on axis {axis}");
                let below =
                    f32::from_bits(if p[axis] > 0.0 { p[axis].to_bits() - 1 } else { p[axis].to_bits() + 1 });
                p[axis] = below;
                if i > 0 {
                    assert_eq!(g.cell_coords(p)[axis], i - 1, "just below wall {i} on axis {axis}");
                }
            }
        }
    }

    #[test]
    fn a_box_with_a_face_on_a_wall_touches_the_cells_on_both_sides() {
        // Regression: `cell_range` used the rounded `cell_coords`, so a box whose min face lay
        // exactly on a wall was stored only above it, and a ray leaving the box through that
        // face (crossing at exactly the span boundary) found it in no cell.
        let g = grid();
        for axis in 0..3 {
            for i in 1..g.dims[axis] - 1 {
                let mut min = Vec3::splat(0.1);
                min[axis] = g.plane(axis, i);
                let mut max = min + Vec3::splat(0.2);
                max[axis] = g.plane(axis, i + 1);
                let (lo, hi) = g.cell_range(&Aabb::new(min, max));
                assert_eq!((lo[axis], hi[axis]), (i - 1, i + 1), "wall {i} on axis {axis}");
            }
        }
    }
}
