//! Amanatides–Woo 3D DDA: the cells a ray crosses, in order, each with its parametric range.
//!
//! The seed report's formulas: the start voxel is `⌊(o - min) / size⌋`, the step per axis is
//! the sign of `d`, and `tMax` is the parameter of the next wall on each axis (∞ for a zero
//! component, which covers `-0.0` too). Instead of accumulating `tDelta = size / |d|`, each
//! crossing is recomputed from the grid's own wall coordinate ([`UniformGrid::plane`]), so a
//! ray's crossings agree exactly with the cell boxes used at build time and never drift. As in
//! pbrt's `DDAMajorantIterator`, the walk is an iterator, so callers decide when to stop.

use super::grid::UniformGrid;
use crate::math::{Ray, Vec3};

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
    grid: &'g UniformGrid,
    /// The grid's walls per axis.
    walls: [&'g [f32]; 3],
    /// The grid's skip distances, or empty for a walk that visits every cell.
    skip: &'g [u8],
    dir: [f32; 3],
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
    #[inline(always)]
    pub fn new(grid: &'g UniformGrid, ray: &Ray, t_min: f32, t_max: f32) -> Self {
        let inv_dir = ray.dir.recip();
        let mut walk = GridWalk {
            grid,
            walls: [&grid.walls[0], &grid.walls[1], &grid.walls[2]],
            skip: &[],
            dir: ray.dir.to_array(),
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
        let (origin, dir, inv_dir) = (walk.origin, walk.dir, walk.inv_dir);
        for axis in 0..3 {
            let d = dir[axis];
            let c = entry[axis];
            walk.cell[axis] = c as i32;
            walk.index += c as i32 * walk.stride[axis];
            // `d == 0.0` is true for -0.0 too: such a ray never crosses a wall on this axis.
            if d > 0.0 {
                walk.step[axis] = 1;
                walk.out[axis] = grid.dims[axis] as i32;
                walk.t_next[axis] = (grid.plane(axis, c + 1) - origin[axis]) * inv_dir[axis];
            } else if d < 0.0 {
                walk.step[axis] = -1;
                walk.out[axis] = -1;
                walk.t_next[axis] = (grid.plane(axis, c) - origin[axis]) * inv_dir[axis];
            }
        }
        walk.t_enter = t0;
        walk.t_end = t1;
        walk.done = false;
        walk
    }

    /// [`GridWalk::new`], jumping across runs of empty cells with the grid's skip distances:
    /// only spans of cells that may hold objects (and some empty ones) are returned, in order.
    /// What a caller finds is the same as with [`GridWalk::new`]; it just visits fewer cells.
    #[inline(always)]
    pub fn skipping(grid: &'g UniformGrid, ray: &Ray, t_min: f32, t_max: f32) -> Self {
        let mut walk = Self::new(grid, ray, t_min, t_max);
        walk.skip = &grid.skip;
        walk
    }

    /// Moves the walk past the cube of cells around the current one that its skip distance `d`
    /// says are empty. Returns false when the walk ends inside it.
    #[cold]
    #[allow(clippy::needless_range_loop)] // per-axis state lives in several arrays
    fn jump(&mut self, d: u8) -> bool {
        let r = i32::from(d) - 1;
        let dims = self.grid.dims.map(|n| n as i32);
        let (mut t_jump, mut exit) = (f32::INFINITY, 0);
        for axis in 0..3 {
            let wall = match self.step[axis] {
                1 => (self.cell[axis] + r + 1).min(dims[axis]),
                -1 => (self.cell[axis] - r).max(0),
                _ => continue,
            };
            let t = (self.walls[axis][wall as usize] - self.origin[axis]) * self.inv_dir[axis];
            if t < t_jump {
                (t_jump, exit) = (t, axis);
            }
        }
        let beyond = self.cell[exit] + self.step[exit] * (r + 1);
        if t_jump >= self.t_end || beyond < 0 || beyond >= dims[exit] {
            return false;
        }
        let t_jump = t_jump.max(self.t_enter);
        let at = Vec3::from_array(self.origin) + Vec3::from_array(self.dir) * t_jump;
        let found = self.grid.cell_coords(at);
        let mut index = 0;
        for axis in 0..3 {
            // Never step back, and never sideways on an axis the ray does not move along.
            let c = match self.step[axis] {
                _ if axis == exit => beyond,
                1 => (found[axis] as i32).max(self.cell[axis]),
                -1 => (found[axis] as i32).min(self.cell[axis]),
                _ => self.cell[axis],
            };
            self.cell[axis] = c;
            index += c * self.stride[axis];
            let wall = match self.step[axis] {
                1 => c + 1,
                -1 => c,
                _ => continue,
            };
            self.t_next[axis] = (self.walls[axis][wall as usize] - self.origin[axis]) * self.inv_dir[axis];
        }
        self.index = index;
        self.t_enter = t_jump;
        true
    }
}

/// The axis of the nearest of the next walls `t`; ties go to the lowest axis (the next span is
/// then empty). `if t0 <= t1 && t0 <= t2 { 0 } else if t1 <= t2 { 1 } else { 2 }`, NaN
/// included, without a branch: which axis comes next is as irregular as a coin toss.
#[inline(always)]
fn nearest_wall(t: [f32; 3]) -> usize {
    let first = (t[0] <= t[1]) & (t[0] <= t[2]);
    let second = t[1] <= t[2];
    usize::from(!first) * (1 + usize::from(!second))
}

/// Smallest skip distance worth a jump: a jump costs about as much as three DDA steps.
const MIN_JUMP: u8 = 3;

impl Iterator for GridWalk<'_> {
    type Item = CellSpan;

    #[inline(always)]
    fn next(&mut self) -> Option<CellSpan> {
        if self.done {
            return None;
        }
        if let Some(&d) = self.skip.get(self.index as usize) {
            if d >= MIN_JUMP && !self.jump(d) {
                self.done = true;
                return None;
            }
        }
        let cell = self.index as u32;
        // Axis of the nearest wall; ties go to the lowest axis (the next span is then empty).
        // The crossings are read one by one: copying the array whole read the last step's
        // 4-byte store with a wider load, which the CPU cannot forward (a stall on every step).
        let t = [self.t_next[0], self.t_next[1], self.t_next[2]];
        let axis = nearest_wall(t);
        // Chosen by a select, not `t[axis]`: indexing spills the three to the stack and reads
        // one back (measured 1.02x slower on showcase, bunny and effects_glossy).
        let t_axis = match axis {
            0 => t[0],
            1 => t[1],
            _ => t[2],
        };
        let next = self.cell[axis] + self.step[axis];
        let leaves = t_axis >= self.t_end || next == self.out[axis];
        // The last span ends exactly at the clip range; rounding never lets time run backwards.
        let t_exit = if leaves { self.t_end } else { t_axis.max(self.t_enter) };
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
    use crate::math::Aabb;

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

    /// The branch-free choice equals the comparison chain it replaced on every ordering, ties,
    /// infinities and NaN (a subnormal direction on a wall gives `0 · ∞`).
    #[test]
    fn the_nearest_wall_is_the_comparison_chains_choice() {
        let chain = |t: [f32; 3]| {
            if t[0] <= t[1] && t[0] <= t[2] {
                0
            } else if t[1] <= t[2] {
                1
            } else {
                2
            }
        };
        let values = [f32::NEG_INFINITY, -1.0, -0.0, 0.0, 1.0, 2.0, f32::INFINITY, f32::NAN];
        let mut seen = [0; 3];
        for a in values {
            for b in values {
                for c in values {
                    let t = [a, b, c];
                    assert_eq!(nearest_wall(t), chain(t), "{t:?}");
                    seen[chain(t)] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&n| n > 50), "{seen:?}");
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

    /// A 24³ grid over scattered small boxes: mostly empty cells with skip distances up to ~10.
    fn sparse_grid() -> UniformGrid {
        let boxes: Vec<Aabb> = (0..40u32)
            .map(|i| {
                let c = Vec3::new((i * 37 % 97) as f32, (i * 61 % 89) as f32, (i * 17 % 83) as f32) * 0.1;
                Aabb::new(c, c + Vec3::splat(0.05))
            })
            .collect();
        GridBuilder::new(300.0).build(&boxes, |_, _| true)
    }

    #[test]
    fn skip_distances_are_the_chebyshev_distance_to_the_nearest_non_empty_cell() {
        let g = sparse_grid();
        let [dx, dy, dz] = g.dims;
        let full: Vec<[i64; 3]> = (0..g.cell_count() as u32)
            .filter(|&c| !g.cell_prims(c).is_empty())
            .map(|c| [(c % dx) as i64, (c / dx % dy) as i64, (c / (dx * dy)) as i64])
            .collect();
        assert!(g.skip.iter().any(|&d| d >= 4), "the fixture should have wide empty regions");
        for z in 0..dz {
            for y in 0..dy {
                for x in 0..dx {
                    let want = full
                        .iter()
                        .map(|n| {
                            (n[0] - x as i64).abs().max((n[1] - y as i64).abs()).max((n[2] - z as i64).abs())
                        })
                        .min()
                        .unwrap_or(255)
                        .min(255) as u8;
                    assert_eq!(g.skip[g.cell_index(x, y, z) as usize], want, "cell {x},{y},{z}");
                }
            }
        }
    }

    #[test]
    fn a_skipping_walk_visits_every_non_empty_cell_of_the_full_walk_in_order() {
        let g = sparse_grid();
        let mut state = 12345u32;
        let mut rand = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let (mut jumped, mut total) = (0, 0);
        for _ in 0..3000 {
            let origin = Vec3::new(rand() * 14.0 - 2.0, rand() * 14.0 - 2.0, rand() * 14.0 - 2.0);
            let mut dir = Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5);
            // Some rays axis-parallel or with zero components.
            if rand() < 0.2 {
                dir.y = 0.0;
            }
            if rand() < 0.1 {
                dir.z = -0.0;
            }
            let Some(dir) = dir.try_normalize() else { continue };
            let ray = Ray::new(origin, dir);
            let full: Vec<CellSpan> = GridWalk::new(&g, &ray, 0.0, f32::INFINITY)
                .filter(|s| !g.cell_prims(s.cell).is_empty())
                .collect();
            let skipping: Vec<CellSpan> = GridWalk::skipping(&g, &ray, 0.0, f32::INFINITY).collect();
            let kept: Vec<u32> =
                skipping.iter().map(|s| s.cell).filter(|&c| !g.cell_prims(c).is_empty()).collect();
            assert_eq!(kept, full.iter().map(|s| s.cell).collect::<Vec<_>>(), "ray {ray:?}");
            assert!(skipping.windows(2).all(|w| w[0].t_exit <= w[1].t_enter), "time runs forward");
            let n = GridWalk::new(&g, &ray, 0.0, f32::INFINITY).count();
            total += n;
            jumped += n - skipping.len();
        }
        assert!(jumped * 2 > total, "skipping should avoid most cells here: {jumped} of {total}");
    }
}
