//! Amanatides–Woo 3D DDA: the cells a ray crosses, in order, each with its parametric range.
//!
//! The seed report's formulas: the start voxel is `⌊(o - min) / size⌋`, the step per axis is
//! the sign of `d`, and `tMax` is the parameter of the next wall on each axis (∞ for a zero
//! component, which covers `-0.0` too). Instead of accumulating `tDelta = size / |d|`, each
//! crossing is recomputed from the grid's own wall coordinate ([`UniformGrid::plane`]), so a
//! ray's crossings agree exactly with the cell boxes used at build time and never drift. As in
//! pbrt's `DDAMajorantIterator`, the walk is an iterator, so callers decide when to stop.

use super::grid::UniformGrid;
use crate::math::Ray;

/// One cell on a ray's path, with the ray's parametric range `[t_enter, t_exit]` inside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellSpan {
    /// Linear cell index.
    pub cell: u32,
    /// Ray parameter where the ray enters the cell (or the walk's start).
    pub t_enter: f32,
    /// Ray parameter where the ray leaves the cell (or the walk's end).
    pub t_exit: f32,
}

/// Iterator over the cells a ray crosses between `t_min` and `t_max`, front to back.
///
/// The state is kept in plain per-axis arrays (no `Vec3` indexing in the loop) and the cell as
/// a linear index moved by per-axis strides.
#[derive(Debug, Clone)]
pub struct GridWalk<'g> {
    /// The grid's walls per axis.
    walls: [&'g [f32]; 3],
    /// Cell coordinate per axis.
    cell: [i32; 3],
    /// −1, 0 or +1 per axis.
    step: [i32; 3],
    /// Coordinate at which the walk leaves the grid per axis (−1 or `dims`).
    out: [i32; 3],
    /// Change of the linear index per step on each axis.
    stride: [i32; 3],
    /// Linear index of the current cell.
    index: i32,
    /// Ray parameter of the next wall crossing per axis (∞ where the ray never crosses one).
    t_next: [f32; 3],
    origin: [f32; 3],
    inv_dir: [f32; 3],
    t_enter: f32,
    t_end: f32,
    done: bool,
}

impl<'g> GridWalk<'g> {
    /// Starts a walk of `ray` restricted to `[t_min, t_max]` and to the grid's bounds.
    #[inline]
    pub fn new(grid: &'g UniformGrid, ray: &Ray, t_min: f32, t_max: f32) -> Self {
        let inv_dir = ray.dir.recip();
        let mut walk = GridWalk {
            walls: [&grid.walls[0], &grid.walls[1], &grid.walls[2]],
            cell: [0; 3],
            step: [0; 3],
            out: [0; 3],
            stride: [1, grid.dims[0] as i32, (grid.dims[0] * grid.dims[1]) as i32],
            index: 0,
            t_next: [f32::INFINITY; 3],
            origin: ray.origin.to_array(),
            inv_dir: inv_dir.to_array(),
            t_enter: 0.0,
            t_end: 0.0,
            done: true,
        };
        let Some((t0, t1)) = grid.bounds.clip_ray(ray, inv_dir, t_min, t_max) else {
            return walk;
        };
        let entry = grid.cell_coords(ray.at(t0));
        for axis in 0..3 {
            let d = ray.dir[axis];
            let c = entry[axis];
            walk.cell[axis] = c as i32;
            walk.index += c as i32 * walk.stride[axis];
            // `d == 0.0` is true for -0.0 too: such a ray never crosses a wall on this axis.
            if d > 0.0 {
                walk.step[axis] = 1;
                walk.out[axis] = grid.dims[axis] as i32;
                walk.t_next[axis] = (grid.plane(axis, c + 1) - ray.origin[axis]) * inv_dir[axis];
            } else if d < 0.0 {
                walk.step[axis] = -1;
                walk.out[axis] = -1;
                walk.t_next[axis] = (grid.plane(axis, c) - ray.origin[axis]) * inv_dir[axis];
            }
        }
        walk.t_enter = t0;
        walk.t_end = t1;
        walk.done = false;
        walk
    }
}

impl Iterator for GridWalk<'_> {
    type Item = CellSpan;

    #[inline]
    fn next(&mut self) -> Option<CellSpan> {
        if self.done {
            return None;
        }
        let cell = self.index as u32;
        // Axis of the nearest wall; ties go to the lowest axis (the next span is then empty).
        let t = self.t_next;
        let axis = if t[0] <= t[1] && t[0] <= t[2] {
            0
        } else if t[1] <= t[2] {
            1
        } else {
            2
        };
        let next = self.cell[axis] + self.step[axis];
        let leaves = t[axis] >= self.t_end || next == self.out[axis];
        // The last span ends exactly at the clip range; rounding never lets time run backwards.
        let t_exit = if leaves { self.t_end } else { t[axis].max(self.t_enter) };
        let span = CellSpan { cell, t_enter: self.t_enter, t_exit };
        if leaves {
            self.done = true;
        } else {
            self.cell[axis] = next;
            self.index += self.step[axis] * self.stride[axis];
            self.t_enter = t_exit;
            // Recompute the crossing from the wall itself (no accumulated drift): crossings
            // agree exactly with the cell boxes the grid was built with.
            let wall = if self.step[axis] > 0 { next as u32 + 1 } else { next as u32 };
            self.t_next[axis] = (self.walls[axis][wall as usize] - self.origin[axis]) * self.inv_dir[axis];
        }
        Some(span)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::GridBuilder;
    use crate::math::{Aabb, Vec3};

    /// A 4×4×4 grid over [0, 4]³ (exactly: λ·N = 64 cells over 64 unit cubes... built from bounds).
    fn unit_grid() -> UniformGrid {
        let mut g = GridBuilder::new(64.0).build(&[Aabb::new(Vec3::ZERO, Vec3::splat(4.0))], |_, _| true);
        // Pin the exact geometry so expected crossings are integers.
        g.bounds = Aabb::new(Vec3::ZERO, Vec3::splat(4.0));
        g.dims = [4, 4, 4];
        g.cell_size = Vec3::ONE;
        g.inv_cell_size = Vec3::ONE;
        g.update_walls();
        g
    }

    fn cells(walk: GridWalk<'_>) -> Vec<(u32, f32, f32)> {
        walk.map(|s| (s.cell, s.t_enter, s.t_exit)).collect()
    }

    #[test]
    fn axis_parallel_ray_from_outside_visits_a_row_with_unit_spans() {
        let g = unit_grid();
        let ray = Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X);
        assert_eq!(
            cells(GridWalk::new(&g, &ray, 0.0, f32::INFINITY)),
            vec![(0, 1.0, 2.0), (1, 2.0, 3.0), (2, 3.0, 4.0), (3, 4.0, 5.0)]
        );
    }

    #[test]
    fn negative_zero_components_and_negative_directions_walk_backwards() {
        let g = unit_grid();
        let ray = Ray::new(Vec3::new(3.5, 0.5, 0.5), Vec3::new(-1.0, -0.0, -0.0));
        let got = cells(GridWalk::new(&g, &ray, 0.0, f32::INFINITY));
        assert_eq!(got, vec![(3, 0.0, 0.5), (2, 0.5, 1.5), (1, 1.5, 2.5), (0, 2.5, 3.5)]);
    }

    #[test]
    fn ray_starting_on_a_wall_and_ray_along_a_wall_stay_in_the_grid() {
        let g = unit_grid();
        let on_wall = Ray::new(Vec3::new(2.0, 0.5, 0.5), Vec3::X);
        assert_eq!(
            cells(GridWalk::new(&g, &on_wall, 0.0, f32::INFINITY)),
            vec![(2, 0.0, 1.0), (3, 1.0, 2.0)]
        );
        // Exactly in the plane y = 1 (a wall): it must still see one row of cells, in order.
        let along = Ray::new(Vec3::new(0.5, 1.0, 0.5), Vec3::Z);
        let got = cells(GridWalk::new(&g, &along, 0.0, f32::INFINITY));
        assert_eq!(got.len(), 4);
        assert!(got.windows(2).all(|w| w[0].2 == w[1].1));
    }

    #[test]
    fn diagonal_ray_spans_are_contiguous_and_cover_the_clip_range() {
        let g = unit_grid();
        let ray = Ray::new(Vec3::new(-0.3, -0.2, -0.1), Vec3::new(1.0, 0.7, 0.4).normalize());
        let spans: Vec<CellSpan> = GridWalk::new(&g, &ray, 0.0, f32::INFINITY).collect();
        let (t0, t1) = g.bounds.clip_ray(&ray, ray.dir.recip(), 0.0, f32::INFINITY).unwrap();
        assert_eq!(spans.first().unwrap().t_enter, t0);
        assert_eq!(spans.last().unwrap().t_exit, t1);
        for w in spans.windows(2) {
            assert_eq!(w[0].t_exit, w[1].t_enter);
        }
        for s in &spans {
            // The midpoint of each span lies in the reported cell.
            let p = ray.at(0.5 * (s.t_enter + s.t_exit));
            let [x, y, z] = g.cell_coords(p);
            if s.t_exit > s.t_enter {
                assert_eq!(g.cell_index(x, y, z), s.cell);
            }
        }
    }

    #[test]
    fn ray_missing_the_grid_yields_nothing() {
        let g = unit_grid();
        let ray = Ray::new(Vec3::new(-1.0, 5.0, 0.5), Vec3::X);
        assert_eq!(GridWalk::new(&g, &ray, 0.0, f32::INFINITY).count(), 0);
    }
}
