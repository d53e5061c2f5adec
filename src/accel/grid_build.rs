//! Parallel grid construction: resolution by density, then count → prefix sum → fill.

use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

use super::grid::UniformGrid;
use crate::math::{Aabb, Vec3};

/// Default grid density λ (cells per object), chosen by `benches/grid.rs` (`grid_lambda`):
/// build + trace of 10k objects is best at λ = 1 for spheres and λ = 4 for triangles; λ = 2 is
/// within ~5% of the best on both.
pub const DEFAULT_LAMBDA: f32 = 2.0;

/// Grid density λ of mesh assets' own grids (cells per triangle), chosen by
/// `benches/scaling.rs` (`mesh_lambda`): see `docs/meshes.md` for the curve.
pub const MESH_LAMBDA: f32 = 2.0;

/// Cap on cells per axis and in total, so a pathological scene cannot exhaust memory.
const MAX_DIM: u32 = 1024;
const MAX_CELLS: usize = 1 << 24;

/// Builds a [`UniformGrid`] over objects given by their bounds and an exact overlap test.
#[derive(Debug, Clone, Copy)]
pub struct GridBuilder {
    /// Density: the grid gets about `lambda * N` cells for `N` objects.
    pub lambda: f32,
}

impl Default for GridBuilder {
    fn default() -> Self {
        Self { lambda: DEFAULT_LAMBDA }
    }
}

impl GridBuilder {
    /// A builder with the given density λ.
    pub fn new(lambda: f32) -> Self {
        Self { lambda }
    }

    /// Builds the grid over `bounds[id]` for every object id.
    ///
    /// `overlaps(id, cell)` refines the bounds test: an object is stored only in cells it
    /// really overlaps. It must be conservative (never false for a cell the object touches).
    pub fn build<F>(&self, bounds: &[Aabb], overlaps: F) -> UniformGrid
    where
        F: Fn(u32, &Aabb) -> bool + Sync,
    {
        let scene = bounds.iter().fold(Aabb::EMPTY, |acc, b| acc.union(*b));
        if bounds.is_empty() || scene.is_empty() || !scene.min.is_finite() || !scene.max.is_finite() {
            return UniformGrid::empty();
        }
        let grid_bounds = pad(scene);
        let dims = resolution(&grid_bounds, bounds.len(), self.lambda);
        let cell_size = grid_bounds.extent() / Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
        let mut grid = UniformGrid {
            bounds: grid_bounds,
            dims,
            cell_size,
            inv_cell_size: cell_size.recip(),
            cell_start: Vec::new(),
            prim_ids: Vec::new(),
            walls: Default::default(),
            skip: Vec::new(),
        };
        grid.update_walls();

        if bounds.len() < PARALLEL_MIN {
            let mut grid = build_serial(grid, bounds, &overlaps);
            grid.update_skip();
            return grid;
        }
        // Step 1: each object's overlapped cells, in parallel (the exact tests are the cost).
        let cells_of: Vec<Vec<u32>> = bounds
            .par_iter()
            .enumerate()
            .map(|(id, b)| overlapped_cells(&grid, id as u32, b, &overlaps))
            .collect();

        // Step 2: count references per cell.
        let counts: Vec<AtomicU32> = (0..grid.cell_count()).map(|_| AtomicU32::new(0)).collect();
        cells_of.par_iter().flatten().for_each(|&c| {
            counts[c as usize].fetch_add(1, Ordering::Relaxed);
        });

        // Step 3: exclusive prefix sum gives each cell's row start.
        let mut cell_start = Vec::with_capacity(counts.len() + 1);
        let mut total = 0u32;
        for c in &counts {
            cell_start.push(total);
            total += c.load(Ordering::Relaxed);
        }
        cell_start.push(total);

        // Step 4: fill rows through per-cell cursors, then sort each row so the layout (and so
        // every tie between equal hits) is independent of thread scheduling.
        let cursor: Vec<AtomicU32> =
            cell_start[..cell_start.len() - 1].iter().map(|&s| AtomicU32::new(s)).collect();
        let slots: Vec<AtomicU32> = (0..total).map(|_| AtomicU32::new(0)).collect();
        cells_of.par_iter().enumerate().for_each(|(id, cells)| {
            for &c in cells {
                let at = cursor[c as usize].fetch_add(1, Ordering::Relaxed);
                slots[at as usize].store(id as u32, Ordering::Relaxed);
            }
        });
        let mut prim_ids: Vec<u32> = slots.into_iter().map(AtomicU32::into_inner).collect();
        let mut rows: Vec<&mut [u32]> = Vec::with_capacity(cell_start.len());
        let mut rest = prim_ids.as_mut_slice();
        for w in cell_start.windows(2) {
            let (row, tail) = rest.split_at_mut((w[1] - w[0]) as usize);
            rows.push(row);
            rest = tail;
        }
        rows.par_iter_mut().for_each(|row| row.sort_unstable());

        grid.cell_start = cell_start;
        grid.prim_ids = prim_ids;
        grid.update_skip();
        grid
    }
}

/// Below this many objects the build runs on the calling thread: handing four small steps to
/// the thread pool costs more than they do (a top level of 100 instances took 0.22 ms in
/// parallel, 0.02 ms serially; `benches/rebuild.rs`).
const PARALLEL_MIN: usize = 2048;

/// The same count → prefix sum → fill on one thread, for small object counts.
fn build_serial<F>(mut grid: UniformGrid, bounds: &[Aabb], overlaps: &F) -> UniformGrid
where
    F: Fn(u32, &Aabb) -> bool,
{
    let cells_of: Vec<Vec<u32>> =
        bounds.iter().enumerate().map(|(id, b)| overlapped_cells(&grid, id as u32, b, overlaps)).collect();
    let mut cell_start = vec![0u32; grid.cell_count() + 1];
    for &c in cells_of.iter().flatten() {
        cell_start[c as usize + 1] += 1;
    }
    for i in 1..cell_start.len() {
        cell_start[i] += cell_start[i - 1];
    }
    // Objects are visited in id order, so every row comes out sorted.
    let mut cursor = cell_start.clone();
    let mut prim_ids = vec![0u32; cell_start[cell_start.len() - 1] as usize];
    for (id, cells) in cells_of.iter().enumerate() {
        for &c in cells {
            prim_ids[cursor[c as usize] as usize] = id as u32;
            cursor[c as usize] += 1;
        }
    }
    grid.cell_start = cell_start;
    grid.prim_ids = prim_ids;
    grid
}

/// Grows a box by a small relative margin (and gives flat boxes thickness) so that objects on
/// its faces fall strictly inside cells.
fn pad(b: Aabb) -> Aabb {
    let extent = b.extent();
    let size = extent.max_element().max(b.min.abs().max_element()).max(b.max.abs().max_element());
    let margin = Vec3::splat((size * 1e-5).max(f32::MIN_POSITIVE)) + extent * 1e-4;
    Aabb::new(b.min - margin, b.max + margin)
}

/// Cells per axis: cubic-ish cells with about `lambda * n` cells in total.
///
/// An axis too thin to hold one cube of the target size gets a single cell, and the budget is
/// spread over the remaining axes (a flat scene gets a 2D grid of about `lambda * n` cells,
/// not the per-axis cap squared).
fn resolution(b: &Aabb, n: usize, lambda: f32) -> [u32; 3] {
    let e = b.extent();
    let target = (lambda as f64 * n as f64).clamp(1.0, MAX_CELLS as f64);
    let mut active = [true; 3];
    let mut dims = [1u32; 3];
    loop {
        let live: Vec<usize> = (0..3).filter(|&a| active[a]).collect();
        if live.is_empty() {
            break;
        }
        let volume: f64 = live.iter().map(|&a| e[a] as f64).product();
        let per_unit = (target / volume).powf(1.0 / live.len() as f64);
        // Drop the axes that cannot hold one cell, then share the budget again.
        let thin: Vec<usize> = live.iter().copied().filter(|&a| e[a] as f64 * per_unit < 1.0).collect();
        if thin.is_empty() {
            for a in live {
                dims[a] = ((e[a] as f64 * per_unit).round() as u32).clamp(1, MAX_DIM);
            }
            break;
        }
        for a in thin {
            active[a] = false;
        }
    }
    while dims.iter().map(|&d| d as usize).product::<usize>() > MAX_CELLS {
        let axis = (0..3).max_by_key(|&i| dims[i]).unwrap_or(0);
        dims[axis] = (dims[axis] / 2).max(1);
    }
    dims
}

fn overlapped_cells<F>(grid: &UniformGrid, id: u32, b: &Aabb, overlaps: &F) -> Vec<u32>
where
    F: Fn(u32, &Aabb) -> bool,
{
    let (lo, hi) = grid.cell_range(b);
    let single = lo == hi;
    let mut cells = Vec::new();
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                // A box inside one cell overlaps it by construction: skip the exact test.
                if single || overlaps(id, &grid.cell_bounds(x, y, z)) {
                    cells.push(grid.cell_index(x, y, z));
                }
            }
        }
    }
    cells
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_object_is_in_every_cell_its_bounds_overlap_and_rows_are_sorted() {
        let bounds: Vec<Aabb> = (0..50)
            .map(|i| {
                let c = Vec3::new((i * 7 % 10) as f32, (i * 3 % 10) as f32, (i % 10) as f32);
                Aabb::new(c, c + Vec3::splat(0.7 + (i % 3) as f32))
            })
            .collect();
        let grid = GridBuilder::new(2.0).build(&bounds, |_, _| true);
        assert_eq!(*grid.cell_start.last().unwrap() as usize, grid.prim_ids.len());
        for z in 0..grid.dims[2] {
            for y in 0..grid.dims[1] {
                for x in 0..grid.dims[0] {
                    let cell = grid.cell_bounds(x, y, z);
                    let row = grid.cell_prims(grid.cell_index(x, y, z));
                    assert!(row.windows(2).all(|w| w[0] < w[1]));
                    for (id, b) in bounds.iter().enumerate() {
                        // Strict overlap must be stored; touching faces may go either way.
                        let strict = b.min.cmplt(cell.max).all() && cell.min.cmplt(b.max).all();
                        if strict {
                            assert!(row.contains(&(id as u32)), "object {id} missing from cell {x},{y},{z}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn density_sets_cell_count_near_lambda_n() {
        let bounds: Vec<Aabb> = (0..1000)
            .map(|i| {
                let c = Vec3::new((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32);
                Aabb::new(c, c + Vec3::splat(0.1))
            })
            .collect();
        let grid = GridBuilder::new(4.0).build(&bounds, |_, _| true);
        let cells = grid.cell_count() as f32;
        assert!((2000.0..8000.0).contains(&cells), "cells = {cells}");
    }

    #[test]
    fn flat_scene_gets_a_flat_grid_of_about_lambda_n_cells() {
        // Regression: a scene in one plane has a padded thickness of ~1e-5 of its size, so the
        // cube root of λN / volume was huge and the two wide axes hit the 1024 cap (1M cells
        // for 60 objects). Thin axes now get one cell and the budget goes to the others.
        let bounds: Vec<Aabb> = (0..60)
            .map(|i| {
                let c = Vec3::new((i % 8) as f32, (i / 8) as f32, 0.5);
                Aabb::new(c, c + Vec3::new(0.5, 0.5, 0.0))
            })
            .collect();
        let grid = GridBuilder::new(4.0).build(&bounds, |_, _| true);
        assert_eq!(grid.dims[2], 1);
        let cells = grid.cell_count() as f32;
        assert!((120.0..480.0).contains(&cells), "dims = {:?}", grid.dims);
        // A thin slab (much thinner than a cube cell) is also one layer deep.
        let slab = [Aabb::new(Vec3::ZERO, Vec3::new(100.0, 100.0, 0.01))];
        assert_eq!(resolution(&pad(slab[0]), 1000, 4.0)[2], 1);
    }

    #[test]
    fn serial_and_parallel_builds_agree() {
        let bounds: Vec<Aabb> = (0..PARALLEL_MIN as u32 + 10)
            .map(|i| {
                let c = Vec3::new((i * 37 % 101) as f32, (i * 11 % 53) as f32, (i % 29) as f32) * 0.3;
                Aabb::new(c, c + Vec3::splat(0.2 + (i % 5) as f32 * 0.3))
            })
            .collect();
        let overlaps = |id: u32, cell: &Aabb| !(id + cell.min.x as u32).is_multiple_of(7);
        let parallel = GridBuilder::new(2.0).build(&bounds, overlaps);
        let empty = UniformGrid {
            cell_start: Vec::new(),
            prim_ids: Vec::new(),
            skip: Vec::new(),
            ..parallel.clone()
        };
        let mut serial = build_serial(empty, &bounds, &overlaps);
        serial.update_skip();
        assert_eq!(serial, parallel);
    }

    #[test]
    fn no_objects_gives_the_empty_grid() {
        assert_eq!(GridBuilder::default().build(&[], |_, _| true), UniformGrid::empty());
    }
}
