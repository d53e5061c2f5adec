//! The two walks every grid level shares: nearest hit and any hit, front to back over a
//! [`UniformGrid`] with the skip distances ([`GridWalk::skipping`]). The top-level grid (ids are
//! objects) and the mesh grids (ids are triangles, in object space) both walk through here; the
//! caller says what testing an id means.

use super::dda::GridWalk;
use super::grid::UniformGrid;
use super::tally::Tally;
use crate::math::Ray;

/// Nearest hit in `(t_min, t_max)` among the ids stored in the cells `ray` crosses.
///
/// `test(id, bound, tally)` tests one id within `(t_min, bound)` and returns the hit's ray
/// parameter with whatever the caller keeps of it; a hit it returns must lie below `bound`, and
/// becomes the new bound. The walk adds one cell to `tally` per cell visited; `test` adds its
/// own tests.
///
/// A hit found in a cell is final once it lies within that cell's t-range: no later cell can
/// hold a nearer one. A hit beyond the range (an id reaching into later cells) is kept as the
/// bound for the rest of the walk, so it is never tested again at a larger t.
#[inline(always)]
pub fn nearest<H, T: Tally>(
    grid: &UniformGrid,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
    mut test: impl FnMut(u32, f32, &mut T) -> Option<(f32, H)>,
) -> Option<H> {
    nearest_by_cell(grid, ray, t_min, t_max, tally, |ids, mut bound, tally| {
        let mut best = None;
        for &id in ids {
            if let Some((t, hit)) = test(id, bound, tally) {
                bound = t;
                best = Some((t, hit));
            }
        }
        best
    })
}

/// [`nearest`], with `test(ids, bound, tally)` given a whole cell's ids at once: it returns the
/// nearest hit among them below `bound` (the first of equally near ones, as testing them one by
/// one in order finds), so a kernel can test many primitives against the ray together.
#[inline(always)]
pub fn nearest_by_cell<H, T: Tally>(
    grid: &UniformGrid,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
    mut test: impl FnMut(&[u32], f32, &mut T) -> Option<(f32, H)>,
) -> Option<H> {
    let mut best = None;
    let mut bound = t_max;
    for span in GridWalk::skipping(grid, ray, t_min, t_max) {
        if span.t_enter > bound {
            break;
        }
        tally.cell();
        if grid.known_empty(span.cell) {
            continue;
        }
        if let Some((t, hit)) = test(grid.cell_prims(span.cell), bound, tally) {
            bound = t;
            best = Some(hit);
        }
        if bound <= span.t_exit {
            break;
        }
    }
    best
}

/// True when `test(id, tally)` holds for some id stored in a cell `ray` crosses between `t_min`
/// and `t_max`; stops at the first. The walk adds one cell to `tally` per cell visited; `test`
/// adds its own tests. An id stored in several cells is offered once per cell.
#[inline(always)]
pub fn any<T: Tally>(
    grid: &UniformGrid,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
    mut test: impl FnMut(u32, &mut T) -> bool,
) -> bool {
    any_by_cell(grid, ray, t_min, t_max, tally, |ids, tally| ids.iter().any(|&id| test(id, tally)))
}

/// [`any`], with `test(ids, tally)` given a whole cell's ids at once.
#[inline(always)]
pub fn any_by_cell<T: Tally>(
    grid: &UniformGrid,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    tally: &mut T,
    mut test: impl FnMut(&[u32], &mut T) -> bool,
) -> bool {
    for span in GridWalk::skipping(grid, ray, t_min, t_max) {
        tally.cell();
        if !grid.known_empty(span.cell) && test(grid.cell_prims(span.cell), tally) {
            return true;
        }
    }
    false
}
