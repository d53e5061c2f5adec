//! Coherent grid traversal: a packet of rays walks a uniform grid as one frustum.
//!
//! Wald, Ize, Kensler, Knoll and Parker, "Ray Tracing Animated Scenes using Coherent Grid
//! Traversal" (SIGGRAPH 2006). The packet crosses the grid slice by slice along its rays'
//! common dominant axis; in each slice it visits the rectangle of cells that bounds all its
//! live rays there, and hands each object found to a [`PacketSink`], which tests it against all
//! live lanes at once. Every object a lane could hit lies in a cell of the rectangle of the
//! slice where it is hit (rectangles are widened by a margin that covers the rounding of the
//! lanes' coordinates), and a lane stops only once its nearest hit lies before the far wall of
//! the slice just searched, as a single ray stops at the end of its cell: the objects a lane is
//! tested against include every one its single-ray walk would have found nearest. A packet
//! too spread out to walk together gives up ([`Walk::GaveUp`]) and names the lanes whose walk
//! is not over: the caller finishes those alone, from what the packet found.
//!
//! Each slice also hands the sink its *footprint*: the box of the walking lanes' points in the
//! slice, widened by the same margin plus the rounding of the kernels' differences from the
//! origins. A sink may decline the objects whose bounds miss it (mesh triangles do: a mesh
//! cell holds about twenty triangles of which the packet's few lanes meet only some). It
//! screens a whole cell's ids at once ([`PacketSink::candidates`]), without a branch per id;
//! a declined object stays out of the mailbox, so it is offered again in any later slice.
//! Along the dominant axis the footprint spans the slice, which every object listed in its
//! cells meets, so a sink need compare only the two cross axes ([`Footprint::cross`]; the
//! structure-of-arrays triangles then read six of their nine coordinate columns).

// Lane loops index several parallel lane arrays by the same lane number.
#![allow(clippy::needless_range_loop)]

use super::grid::UniformGrid;
use crate::math::{Aabb, RayPacket, Vec3};

/// Where a slice's walking lanes can be: the box of their points in the slice, widened by the
/// rounding margin plus the rounding of the kernels' differences from the origins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// The box, in the grid's axes.
    pub bounds: Aabb,
    /// The walk's two cross axes. Along the third, the dominant axis, the box spans the slice's
    /// walls (widened), which every object listed in the slice's cells meets (a cell lists only
    /// objects that meet it): a sink may compare the cross axes only.
    pub cross: [usize; 2],
}

/// What a packet's walk does with the objects it meets.
pub trait PacketSink<const N: usize> {
    /// Each lane's current search bound (its nearest hit so far).
    fn bound(&self) -> &[f32; N];
    /// Which of `ids` (at most 64, one cell's) the walk should offer to [`PacketSink::visit`]:
    /// bit `k` for `ids[k]`. `footprint` holds every point of the live lanes within the slice
    /// being searched (widened by the rounding margin), so an object whose bounds miss it cannot
    /// be hit there; one declined is screened again in every later slice whose cells hold it.
    /// By default every id is a candidate.
    #[inline(always)]
    fn candidates(&self, ids: &[u32], footprint: &Footprint) -> u64 {
        let _ = footprint;
        u64::MAX >> (64 - ids.len())
    }
    /// Tests object `id` against the `live` lanes.
    fn visit(&mut self, id: u32, live: &[bool; N]);
}

/// Most ids [`PacketSink::candidates`] screens at once.
const SCREEN: usize = 64;

/// Widening of a slice's rectangle, as a fraction of a cell: covers the rounding of the lanes'
/// coordinates wherever it is smaller than this.
const MARGIN_CELLS: f32 = 1.0 / 1024.0;

/// Relative rounding of a lane's coordinate `o + t·d` (a few ulps of its magnitude).
const MARGIN_RELATIVE: f32 = 8.0 * f32::EPSILON;

/// Most cells a slice's rectangle may hold per walking lane before the packet gives up and its
/// lanes walk alone (a single ray crosses one to three cells per slice).
const CELLS_PER_LANE: i64 = 3;

/// Size of the direct-mapped mailbox that keeps a walk from testing an object twice.
const MAILBOX: usize = 64;

/// The rectangle of cells (inclusive ranges on the two cross axes) that holds every walking
/// lane's points between two walls of the dominant axis, widened by the rounding margin, and
/// the box of those points itself (in the grid's axes x, y, z, widened too); `None` when no
/// lane has points there.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Rect {
    u: [i64; 2],
    v: [i64; 2],
    footprint: Footprint,
}

/// The smaller of two floats by one compare (no NaN handling: the walk's values are finite or
/// infinite, never NaN, and either zero of a tie will do for a conservative bound).
#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// The larger of two floats by one compare (see [`min`]).
#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// The smallest of `lo` and the largest of `hi`, by halving reductions: the lanes pair up, so
/// the compiler keeps them in vector registers (a running minimum is one long dependent chain).
/// Exact (see [`min`]).
#[inline(always)]
pub(crate) fn extent<const N: usize>(mut lo: [f32; N], mut hi: [f32; N]) -> (f32, f32) {
    let mut width = N;
    while width > 1 {
        let half = width / 2;
        for i in 0..half {
            lo[i] = min(lo[i], lo[i + half]);
            hi[i] = max(hi[i], hi[i + half]);
        }
        if width % 2 == 1 {
            lo[0] = min(lo[0], lo[width - 1]);
            hi[0] = max(hi[0], hi[width - 1]);
        }
        width = half;
    }
    (lo[0], hi[0])
}

/// A packet's lanes in the frame of one walk: the dominant axis `k` and the cross axes `u`, `v`.
struct Frame<const N: usize> {
    axes: [usize; 3],
    o: [[f32; N]; 3],
    d: [[f32; N]; 3],
    inv_k: [f32; N],
    t_min: [f32; N],
    /// Extra widening of footprints for the rounding of the lanes' own coordinates and of the
    /// kernels' differences from the origins: [`MARGIN_RELATIVE`] of the largest origin
    /// coordinate.
    slack: f32,
    /// The grid's lower corner, cell size, reciprocal cell size and last cell index, in the
    /// frame's axes (`k`, `u`, `v`): read by constant index, not by a grid axis known only at
    /// run time (a `Vec3` index is a `match`).
    min: [f32; 3],
    cell: [f32; 3],
    inv_cell: [f32; 3],
    last: [i64; 3],
}

impl<const N: usize> Frame<N> {
    /// The rounding margin of coordinates in `[lo, hi]` on frame axis `f` (0 for `k`, 1 and 2
    /// for `u` and `v`).
    #[inline(always)]
    fn margin(&self, f: usize, lo: f32, hi: f32) -> f32 {
        MARGIN_CELLS * self.cell[f] + MARGIN_RELATIVE * lo.abs().max(hi.abs())
    }

    /// The cell of coordinate `c` on frame axis `f`, clamped into the grid.
    #[inline(always)]
    fn cell_of(&self, f: usize, c: f32) -> i64 {
        let x = (c - self.min[f]) * self.inv_cell[f];
        // NaN (only from infinite inputs) clamps to the first cell, as `max` drops it; then
        // truncation is the floor of the non-negative value.
        (x.max(0.0) as i64).min(self.last[f])
    }

    /// The rectangle of the `walking` lanes' points between walls `wa` and `wb` of the dominant
    /// axis (in travel order), each lane cut to `(t_min, bound)`.
    #[inline(always)]
    fn rect(&self, wa: f32, wb: f32, walking: &[bool; N], bound: &[f32; N]) -> Option<Rect> {
        let mut lo = [[f32::INFINITY; N]; 2];
        let mut hi = [[f32::NEG_INFINITY; N]; 2];
        for i in 0..N {
            let a = max((wa - self.o[0][i]) * self.inv_k[i], self.t_min[i]);
            let b = min((wb - self.o[0][i]) * self.inv_k[i], bound[i]);
            let valid = walking[i] & (a <= b);
            for c in 0..2 {
                let (pa, pb) =
                    (self.o[c + 1][i] + a * self.d[c + 1][i], self.o[c + 1][i] + b * self.d[c + 1][i]);
                lo[c][i] = if valid { min(pa, pb) } else { f32::INFINITY };
                hi[c][i] = if valid { max(pa, pb) } else { f32::NEG_INFINITY };
            }
        }
        // Two calls, not a `map` over the axes: the compiler kept that closure out of line,
        // passing the lane arrays through memory.
        let (u_lo, u_hi) = extent(lo[0], hi[0]);
        let (v_lo, v_hi) = extent(lo[1], hi[1]);
        let ext = [[u_lo, u_hi], [v_lo, v_hi]];
        if ext[0][0] > ext[0][1] {
            return None;
        }
        let mut out = [[0i64; 2]; 2];
        let (mut lo, mut hi) = ([0.0f32; 3], [0.0f32; 3]);
        for c in 0..2 {
            let axis = self.axes[c + 1];
            let [l, h] = ext[c];
            let margin = self.margin(c + 1, l, h);
            out[c] = [self.cell_of(c + 1, l - margin), self.cell_of(c + 1, h + margin)];
            (lo[axis], hi[axis]) = (l - margin - self.slack, h + margin + self.slack);
        }
        let k = self.axes[0];
        let (wl, wh) = (min(wa, wb), max(wa, wb));
        let margin = self.margin(0, wl, wh) + self.slack;
        (lo[k], hi[k]) = (wl - margin, wh + margin);
        let footprint = Footprint {
            bounds: Aabb::new(Vec3::from(lo), Vec3::from(hi)),
            cross: [self.axes[1], self.axes[2]],
        };
        Some(Rect { u: out[0], v: out[1], footprint })
    }
}

/// How a [`coherent_walk`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[must_use]
pub enum Walk<const N: usize> {
    /// Every lane's walk is over: the sink has each lane's result.
    Finished,
    /// The packet gave up part way. The lanes marked still need their own walks, up to their
    /// search bounds (a lane's walk ends, as a single ray's does, once its nearest hit so far
    /// lies before the far wall of the last slice searched, or once it has left the grid: what
    /// the sink has for such a lane is its result); the others are done.
    GaveUp([bool; N]),
}

/// Walks `grid` with the `live` lanes of `packet` as one frustum, slice by slice along the
/// dominant axis, handing every object in each slice's rectangle of cells to `sink` once.
///
/// Runs of empty slices are crossed in one step where the grid has skip distances: when every
/// cell of a slice's rectangle is at least `m` cells from any object, the next `m − 1` slices
/// are empty wherever their own rectangle stays within `m − 1` cells of it.
///
/// Gives up ([`Walk::GaveUp`]) when the packet is not coherent enough to walk together: when
/// the live lanes disagree on the sign of the dominant axis (or move along it not at all), or
/// when a slice's rectangle holds more than `CELLS_PER_LANE` cells per walking lane (rays
/// spreading apart, or crossing the grid at a shallow angle to the slices). What the sink has
/// found so far stands, and the lanes whose walk had already ended are done; the caller
/// finishes the others one by one. `cells` counts the cells visited.
#[inline(always)]
pub fn coherent_walk<const N: usize, K: PacketSink<N>>(
    grid: &UniformGrid,
    packet: &RayPacket<N>,
    live: &[bool; N],
    sink: &mut K,
    cells: &mut u32,
) -> Walk<N> {
    // Each lane's range inside the grid, exactly as a single ray's walk clips it.
    let (inside, t_in, t_out) = grid.bounds.clip_lanes(packet, live, sink.bound());
    // No lane meets the grid: nothing to walk.
    let Some(first) = inside.iter().position(|&inside| inside) else { return Walk::Finished };
    // The dominant axis of the first lane; every lane must move along it the same way, with a
    // finite reciprocal.
    let d0 = [packet.dir[0][first], packet.dir[1][first], packet.dir[2][first]];
    let k = if d0[0].abs() >= d0[1].abs() && d0[0].abs() >= d0[2].abs() {
        0
    } else if d0[1].abs() >= d0[2].abs() {
        1
    } else {
        2
    };
    let forward = d0[k] > 0.0;
    // Lane by lane without a branch (so the lanes stay in vectors), then one decision.
    let mut against = false;
    for i in 0..N {
        let d = packet.dir[k][i];
        let along = if forward { d > 0.0 } else { d < 0.0 };
        against |= inside[i] & !(along & packet.inv_dir[k][i].is_finite());
    }
    if against {
        return Walk::GaveUp(inside);
    }
    let axes = [k, (k + 1) % 3, (k + 2) % 3];
    // The largest origin coordinate of the lanes inside, lane by lane and then by halving (a
    // running maximum over the lanes was one long dependent chain, kept in memory): the same
    // value, a maximum of values that are never NaN not depending on its order.
    let o = &packet.origin;
    let far = std::array::from_fn(|i| {
        let m = max(max(o[0][i].abs(), o[1][i].abs()), o[2][i].abs());
        if inside[i] {
            m
        } else {
            0.0
        }
    });
    let (_, reach) = extent([0.0; N], far);
    let frame = Frame {
        axes,
        o: axes.map(|a| packet.origin[a]),
        d: axes.map(|a| packet.dir[a]),
        inv_k: packet.inv_dir[k],
        t_min: packet.t_min,
        slack: MARGIN_RELATIVE * reach,
        min: axes.map(|a| grid.bounds.min[a]),
        cell: axes.map(|a| grid.cell_size[a]),
        inv_cell: axes.map(|a| grid.inv_cell_size[a]),
        last: axes.map(|a| i64::from(grid.dims[a]) - 1),
    };
    // The slices the lanes cross, from their entry and exit points along the dominant axis.
    let (mut lo, mut hi) = ([f32::INFINITY; N], [f32::NEG_INFINITY; N]);
    for i in 0..N {
        let [a, b] = [t_in[i], t_out[i]].map(|t| packet.origin[k][i] + t * packet.dir[k][i]);
        (lo[i], hi[i]) = if inside[i] { (min(a, b), max(a, b)) } else { (f32::INFINITY, f32::NEG_INFINITY) };
    }
    let (near, far) = extent(lo, hi);
    let margin_k = frame.margin(0, near, far);
    let (s_lo, s_hi) = (frame.cell_of(0, near - margin_k), frame.cell_of(0, far + margin_k));
    let (mut s, last, step) = if forward { (s_lo, s_hi, 1) } else { (s_hi, s_lo, -1) };
    let dims = grid.dims.map(i64::from);
    let stride = [1i64, dims[0], dims[0] * dims[1]];
    let [sk, su, sv] = axes.map(|a| stride[a]);
    let walls = &grid.walls[k];
    // The walls bounding slice `s` in travel order, and the ray parameter at the far one.
    let bounds = |s: i64| {
        let (lo, hi) = (walls[s as usize], walls[s as usize + 1]);
        if forward {
            (lo, hi)
        } else {
            (hi, lo)
        }
    };
    let mut walking = inside;
    let mut mail = [u32::MAX; MAILBOX];
    loop {
        let (w_near, w_far) = bounds(s);
        let mut jump = 0;
        if let Some(r) = frame.rect(w_near, w_far, &walking, sink.bound()) {
            let lanes = walking.iter().filter(|&&w| w).count() as i64;
            if (r.u[1] - r.u[0] + 1) * (r.v[1] - r.v[0] + 1) > CELLS_PER_LANE * lanes {
                return Walk::GaveUp(walking);
            }
            let mut clearance = u8::MAX;
            for cv in r.v[0]..=r.v[1] {
                for cu in r.u[0]..=r.u[1] {
                    let cell = (s * sk + cu * su + cv * sv) as u32;
                    let skip = grid.skip.get(cell as usize).copied().unwrap_or(0);
                    clearance = clearance.min(skip);
                    if skip > 0 {
                        continue;
                    }
                    let prims = grid.cell_prims(cell);
                    if prims.is_empty() {
                        continue;
                    }
                    *cells += 1;
                    for ids in prims.chunks(SCREEN) {
                        let mut todo = sink.candidates(ids, &r.footprint);
                        while todo != 0 {
                            let id = ids[todo.trailing_zeros() as usize];
                            todo &= todo - 1;
                            let slot = &mut mail[id as usize % MAILBOX];
                            if *slot != id {
                                sink.visit(id, &walking);
                                *slot = id;
                            }
                        }
                    }
                }
            }
            // Every cell within `clearance − 1` of the rectangle is empty: jump the slices
            // ahead whose rectangle stays inside that box.
            let reach = i64::from(clearance) - 1;
            let ahead = reach.min((last - s) * step);
            if ahead >= 1 {
                let (w_from, _) = bounds(s + step);
                let (_, w_to) = bounds(s + step * ahead);
                let inside_box = |q: Rect| {
                    q.u[0] >= r.u[0] - reach
                        && q.u[1] <= r.u[1] + reach
                        && q.v[0] >= r.v[0] - reach
                        && q.v[1] <= r.v[1] + reach
                };
                if frame.rect(w_from, w_to, &walking, sink.bound()).is_none_or(inside_box) {
                    jump = ahead;
                }
            }
        }
        // A lane is done once its nearest hit lies before the far wall of the last slice
        // searched, or once it has left the grid; the walk once every lane is.
        let (_, w_done) = bounds(s + step * jump);
        let mut more = false;
        for i in 0..N {
            let t_far = (w_done - packet.origin[k][i]) * packet.inv_dir[k][i];
            walking[i] &= !(sink.bound()[i] <= t_far || t_far >= t_out[i]);
            more |= walking[i];
        }
        s += step * jump;
        if !more || s == last {
            break;
        }
        s += step;
    }
    Walk::Finished
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::GridBuilder;
    use crate::math::Ray;

    /// Ends lanes 0 and 1 at `t = 1` (a hit) the first time a visit reaches them.
    struct EndTwo {
        bound: [f32; 16],
    }

    impl PacketSink<16> for EndTwo {
        fn bound(&self) -> &[f32; 16] {
            &self.bound
        }
        fn visit(&mut self, _id: u32, live: &[bool; 16]) {
            for i in 0..2 {
                if live[i] && self.bound[i] == f32::INFINITY {
                    self.bound[i] = 1.0;
                }
            }
        }
    }

    /// A 10 × 10 × 10 lattice of overlapping boxes: every cell of the grid holds some.
    fn lattice() -> UniformGrid {
        let bounds: Vec<Aabb> = (0..1000)
            .map(|n| {
                let c = Vec3::new((n % 10) as f32, (n / 10 % 10) as f32, (n / 100) as f32);
                Aabb::new(c - 0.1, c + 1.1)
            })
            .collect();
        let grid = GridBuilder::new(1.0).build(&bounds, |_, _| true);
        assert!(grid.dims.iter().all(|&d| (8..=12).contains(&d)), "{:?}", grid.dims);
        grid
    }

    #[test]
    fn a_walk_that_gives_up_hands_back_only_the_lanes_still_walking() {
        let grid = lattice();
        let mut packet = RayPacket::<16>::default();
        let from = Vec3::new(5.5, 5.5, -1.0);
        // Lanes 0 and 1 end in the first slice (the sink gives them a hit at t = 1, z = 0);
        // lanes 2 and 3 spread apart by two cells per slice, which overflows the second
        // slice's cell budget once they walk alone; lane 4 misses the grid.
        packet.set(0, &Ray::new(from, Vec3::Z), 0.0, f32::INFINITY);
        packet.set(1, &Ray::new(from + Vec3::X * 0.01, Vec3::Z), 0.0, f32::INFINITY);
        packet.set(2, &Ray::new(from, Vec3::new(2.0, 0.0, 1.0)), 0.0, f32::INFINITY);
        packet.set(3, &Ray::new(from, Vec3::new(-2.0, 0.0, 1.0)), 0.0, f32::INFINITY);
        packet.set(4, &Ray::new(Vec3::new(50.0, 50.0, -1.0), Vec3::Z), 0.0, f32::INFINITY);
        let live: [bool; 16] = std::array::from_fn(|i| i < 5);
        let mut sink = EndTwo { bound: [f32::INFINITY; 16] };
        let walked = coherent_walk(&grid, &packet, &live, &mut sink, &mut 0);
        let want: [bool; 16] = std::array::from_fn(|i| i == 2 || i == 3);
        assert_eq!(walked, Walk::GaveUp(want));
        assert_eq!(sink.bound[..2], [1.0, 1.0], "lanes 0 and 1 were visited and ended");

        // Without the spreading lanes the same walk finishes.
        let narrow: [bool; 16] = std::array::from_fn(|i| i < 2 || i == 4);
        let mut sink = EndTwo { bound: [f32::INFINITY; 16] };
        assert_eq!(coherent_walk(&grid, &packet, &narrow, &mut sink, &mut 0), Walk::Finished);

        // Lanes that disagree on the direction along the dominant axis give up at once: every
        // lane inside the grid is handed back, and the one that misses it is not.
        packet.set(1, &Ray::new(from + Vec3::Z * 20.0, -Vec3::Z), 0.0, f32::INFINITY);
        let mut sink = EndTwo { bound: [f32::INFINITY; 16] };
        let want: [bool; 16] = std::array::from_fn(|i| i < 2);
        assert_eq!(coherent_walk(&grid, &packet, &narrow, &mut sink, &mut 0), Walk::GaveUp(want));
    }
}
