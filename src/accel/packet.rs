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
//! tested against include every one its single-ray walk would have found nearest.

use super::grid::UniformGrid;
use crate::math::{RayPacket, Vec3};

/// What a packet's walk does with the objects it meets.
pub trait PacketSink<const N: usize> {
    /// Each lane's current search bound (its nearest hit so far).
    fn bound(&self) -> &[f32; N];
    /// Tests object `id` against the `live` lanes.
    fn visit(&mut self, id: u32, live: &[bool; N]);
}

/// Widening of a slice's rectangle, as a fraction of a cell: covers the rounding of the lanes'
/// coordinates wherever it is smaller than this.
const MARGIN_CELLS: f32 = 1.0 / 1024.0;

/// Relative rounding of a lane's coordinate `o + t·d` (a few ulps of its magnitude).
const MARGIN_RELATIVE: f32 = 8.0 * f32::EPSILON;

/// Size of the direct-mapped mailbox that keeps a walk from testing an object twice.
const MAILBOX: usize = 64;

/// Walks `grid` with the `live` lanes of `packet` as one frustum, slice by slice along the
/// dominant axis, handing every object in each slice's rectangle of cells to `sink` once.
///
/// Returns `None`, having visited nothing, when the live lanes disagree on the sign of the
/// dominant axis (or move along it not at all): the caller walks them one by one instead.
/// `cells` counts the cells visited.
#[inline(always)]
pub fn coherent_walk<const N: usize, K: PacketSink<N>>(
    grid: &UniformGrid,
    packet: &RayPacket<N>,
    live: &[bool; N],
    sink: &mut K,
    cells: &mut u32,
) -> Option<()> {
    // Each lane's range inside the grid, exactly as a single ray's walk clips it.
    let mut inside = [false; N];
    let mut t_in = [0.0f32; N];
    let mut t_out = [0.0f32; N];
    let mut first = None;
    for i in 0..N {
        if !live[i] {
            continue;
        }
        let ray = packet.ray(i);
        let inv = Vec3::new(packet.inv_dir[0][i], packet.inv_dir[1][i], packet.inv_dir[2][i]);
        if let Some((a, b)) = grid.bounds.clip_ray(&ray, inv, packet.t_min[i], sink.bound()[i]) {
            (inside[i], t_in[i], t_out[i]) = (true, a, b);
            first.get_or_insert(i);
        }
    }
    let first = first?;
    // The dominant axis of the first lane; every lane must move along it the same way.
    let d0 = [packet.dir[0][first], packet.dir[1][first], packet.dir[2][first]];
    let k = if d0[0].abs() >= d0[1].abs() && d0[0].abs() >= d0[2].abs() {
        0
    } else if d0[1].abs() >= d0[2].abs() {
        1
    } else {
        2
    };
    let forward = d0[k] > 0.0;
    for i in 0..N {
        if inside[i] && !(if forward { packet.dir[k][i] > 0.0 } else { packet.dir[k][i] < 0.0 }) {
            return None;
        }
    }
    let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
    let dims = grid.dims.map(|d| d as i64);
    let walls = &grid.walls;
    let size = grid.cell_size.to_array();
    let inv_size = grid.inv_cell_size.to_array();
    let lo = grid.bounds.min.to_array();
    // The cell of coordinate `c` on `axis`, clamped into the grid (conservative bounds only:
    // callers widen `c` first).
    let cell_of = |axis: usize, c: f32| -> i64 {
        let f = ((c - lo[axis]) * inv_size[axis]).floor();
        if f.is_nan() {
            return 0;
        }
        (f.max(0.0) as i64).min(dims[axis] - 1)
    };
    // The slices the lanes cross, from their entry and exit points along the dominant axis.
    let (mut near, mut far) = (f32::INFINITY, f32::NEG_INFINITY);
    for i in 0..N {
        if inside[i] {
            for t in [t_in[i], t_out[i]] {
                let c = packet.origin[k][i] + t * packet.dir[k][i];
                near = near.min(c);
                far = far.max(c);
            }
        }
    }
    let margin_k = MARGIN_CELLS * size[k] + MARGIN_RELATIVE * near.abs().max(far.abs());
    let (s_lo, s_hi) = (cell_of(k, near - margin_k), cell_of(k, far + margin_k));
    let (mut s, last, step) = if forward { (s_lo, s_hi, 1) } else { (s_hi, s_lo, -1) };
    let stride = [1i64, dims[0], dims[0] * dims[1]];
    let mut walking = inside;
    let mut mail = [u32::MAX; MAILBOX];
    loop {
        // Each walking lane's range in this slice, and the rectangle bounding its points there.
        let (w_near, w_far) = if forward {
            (walls[k][s as usize], walls[k][s as usize + 1])
        } else {
            (walls[k][s as usize + 1], walls[k][s as usize])
        };
        let mut t_far = [f32::INFINITY; N];
        let (mut u_lo, mut u_hi, mut v_lo, mut v_hi) =
            (f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY, f32::NEG_INFINITY);
        let mut magnitude = 0.0f32;
        let mut any = false;
        for i in 0..N {
            if !walking[i] {
                continue;
            }
            let (o, inv) = (packet.origin[k][i], packet.inv_dir[k][i]);
            t_far[i] = (w_far - o) * inv;
            let a = ((w_near - o) * inv).max(packet.t_min[i]);
            let b = t_far[i].min(sink.bound()[i]);
            if !(a <= b) {
                continue;
            }
            any = true;
            for t in [a, b] {
                let u = packet.origin[ku][i] + t * packet.dir[ku][i];
                let v = packet.origin[kv][i] + t * packet.dir[kv][i];
                u_lo = u_lo.min(u);
                u_hi = u_hi.max(u);
                v_lo = v_lo.min(v);
                v_hi = v_hi.max(v);
                magnitude = magnitude.max(u.abs()).max(v.abs());
            }
        }
        if any {
            let mu = MARGIN_CELLS * size[ku] + MARGIN_RELATIVE * magnitude;
            let mv = MARGIN_CELLS * size[kv] + MARGIN_RELATIVE * magnitude;
            let (cu0, cu1) = (cell_of(ku, u_lo - mu), cell_of(ku, u_hi + mu));
            let (cv0, cv1) = (cell_of(kv, v_lo - mv), cell_of(kv, v_hi + mv));
            for cv in cv0..=cv1 {
                for cu in cu0..=cu1 {
                    let cell = (s * stride[k] + cu * stride[ku] + cv * stride[kv]) as u32;
                    let prims = grid.cell_prims(cell);
                    if prims.is_empty() {
                        continue;
                    }
                    *cells += 1;
                    for &id in prims {
                        let slot = &mut mail[id as usize % MAILBOX];
                        if *slot == id {
                            continue;
                        }
                        *slot = id;
                        sink.visit(id, &walking);
                    }
                }
            }
        }
        // A lane is done once its nearest hit lies before this slice's far wall, or once it
        // has left the grid; the walk once every lane is.
        let mut more = false;
        for i in 0..N {
            if walking[i] && (sink.bound()[i] <= t_far[i] || t_far[i] >= t_out[i]) {
                walking[i] = false;
            }
            more |= walking[i];
        }
        if !more || s == last {
            break;
        }
        s += step;
    }
    Some(())
}
