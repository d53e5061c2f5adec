//! Ray packets in structure-of-arrays form, traced through the grids by coherent grid traversal.
//!
//! A [`RayPacket`] holds `N` rays as per-axis lane arrays. [`closest_hits`] finds every lane's
//! nearest hit: planes lane by lane, then the top-level grid walked by the whole packet at once
//! ([`coherent_walk`]: Wald, Ize, Kensler, Knoll and Parker, "Ray Tracing Animated Scenes using
//! Coherent Grid Traversal", SIGGRAPH 2006). The packet crosses the grid slice by slice along
//! its rays' common dominant axis; in each slice it visits the rectangle of cells that bounds
//! all its live rays there, and tests each object found against all its live lanes. A mesh
//! instance maps the packet into object space and walks its mesh grid the same way, testing
//! each triangle against all lanes with one SIMD kernel ([`triangle_lanes`]).
//!
//! **Same answers as single rays.** Every lane's hit comes from the same primitive tests, with
//! the same IEEE operations in the same order, as the single-ray path's
//! ([`super::integrator::closest_hit`]): the kernels are the scalar ones written lane-wise, and
//! a lane the vector kernel cannot decide (an edge function exactly zero) is handed to the
//! scalar kernel. The walk only decides *which* primitives are tested: every primitive a lane
//! could hit lies in a cell of the rectangle of the slice where it is hit (the rectangles are
//! widened by a margin that covers the rounding of the lanes' coordinates), and a lane stops
//! only once its nearest hit lies before the far wall of the slice just searched, as a single
//! ray stops at the end of its cell. A packet whose rays disagree on the sign of the dominant
//! axis falls back to walking its lanes one by one, with the same results.

// Lane loops index several parallel lane arrays by the same lane number.
#![allow(clippy::needless_range_loop)]

use super::scene::TraceScene;
use crate::accel::packet::{coherent_walk, PacketSink};
use crate::math::RayPacket;
use crate::store::{PacketHits, PrimitiveStore, TraversalCost};

/// Rays per packet: 4 × 4 neighbouring pixels (measured against other widths by
/// `benches/layout.rs`).
pub const LANES: usize = 16;

/// Every lane's nearest hit in the scene: planes lane by lane, then the top-level grid by
/// coherent traversal (or lane by lane where the packet is not coherent). Equal, lane for lane,
/// to [`super::integrator::closest_hit`]. `cost` gets the packet's cells and tests.
#[inline(always)]
pub fn closest_hits<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    cost: &mut TraversalCost,
) -> PacketHits<N> {
    struct Objects<'a, const N: usize, S: PrimitiveStore> {
        store: &'a S,
        packet: &'a RayPacket<N>,
        hits: PacketHits<N>,
        cost: TraversalCost,
    }
    impl<const N: usize, S: PrimitiveStore> PacketSink<N> for Objects<'_, N, S> {
        #[inline(always)]
        fn bound(&self) -> &[f32; N] {
            &self.hits.t
        }
        #[inline(always)]
        fn visit(&mut self, id: u32, live: &[bool; N]) {
            self.store.intersect_bounded_packet(id, self.packet, live, &mut self.hits, &mut self.cost);
        }
    }
    let store = &scene.store;
    let mut hits = PacketHits::new(packet);
    for p in 0..store.unbounded_count() {
        for i in 0..N {
            if packet.active[i] {
                cost.tests += 1;
                let ray = packet.ray(i);
                hits.offer(i, store.intersect_unbounded(p, &ray, packet.t_min[i], hits.t[i]));
            }
        }
    }
    let mut sink = Objects { store, packet, hits, cost: TraversalCost::default() };
    let mut cells = 0;
    let walked = coherent_walk(&scene.grid, packet, &packet.active, &mut sink, &mut cells);
    let Objects { mut hits, cost: tested, .. } = sink;
    cost.cells += cells + tested.cells;
    cost.tests += tested.tests;
    if walked.is_none() {
        for i in 0..N {
            if packet.active[i] {
                let ray = packet.ray(i);
                let bound = hits.t[i];
                let found = super::integrator::grid_hit(scene, &ray, packet.t_min[i], bound, cost);
                hits.offer(i, found);
            }
        }
    }
    hits
}

/// Which live lanes of a shadow packet are blocked within `(t_min, t_max)`, in a scene without
/// transmission (where a shadow ray's transmittance is 1 or 0): planes lane by lane, then the
/// top-level grid by coherent traversal, a lane dropping out at its first blocker (or lane by
/// lane where the packet is not coherent). Equal, lane for lane, to
/// [`super::integrator::transmittance`] being 0. Shadow packets start at `t_min = 0`.
#[inline(always)]
pub fn occluded<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    cost: &mut TraversalCost,
) -> [bool; N] {
    debug_assert!(!scene.effects.transmission, "shadow packets are for opaque scenes");
    struct Blockers<'a, const N: usize, S: PrimitiveStore> {
        store: &'a S,
        packet: &'a RayPacket<N>,
        bound: [f32; N],
        occluded: [bool; N],
        cost: TraversalCost,
    }
    impl<const N: usize, S: PrimitiveStore> PacketSink<N> for Blockers<'_, N, S> {
        #[inline(always)]
        fn bound(&self) -> &[f32; N] {
            &self.bound
        }
        #[inline(always)]
        fn visit(&mut self, id: u32, live: &[bool; N]) {
            let mut open = [false; N];
            for i in 0..N {
                open[i] = live[i] & !self.occluded[i];
            }
            self.store.occludes_bounded_packet(id, self.packet, &open, &mut self.occluded, &mut self.cost);
            // A blocked lane's walk is over.
            for i in 0..N {
                if self.occluded[i] {
                    self.bound[i] = f32::NEG_INFINITY;
                }
            }
        }
    }
    let store = &scene.store;
    let mut occluded = [false; N];
    for p in 0..store.unbounded_count() {
        for i in 0..N {
            if packet.active[i] && !occluded[i] {
                cost.tests += 1;
                occluded[i] = store.intersect_unbounded(p, &packet.ray(i), 0.0, packet.t_max[i]).is_some();
            }
        }
    }
    let mut open = [false; N];
    for i in 0..N {
        open[i] = packet.active[i] & !occluded[i];
    }
    // Origins scattered over more than two cells make a frustum that sweeps many cells per ray
    // (shadow rays from hits at different depths): such lanes walk alone from the start.
    if origin_spread(packet, &open) > 2.0 * scene.grid.cell_size.max_element() {
        for i in 0..N {
            if open[i] {
                let pass =
                    super::integrator::transmittance_tallied(scene, &packet.ray(i), packet.t_max[i], cost);
                occluded[i] = pass == 0.0;
            }
        }
        return occluded;
    }
    let bound = std::array::from_fn(|i| if occluded[i] { f32::NEG_INFINITY } else { packet.t_max[i] });
    let mut sink = Blockers { store, packet, bound, occluded, cost: TraversalCost::default() };
    let mut cells = 0;
    let walked = coherent_walk(&scene.grid, packet, &open, &mut sink, &mut cells);
    let Blockers { mut occluded, cost: tested, .. } = sink;
    cost.cells += cells + tested.cells;
    cost.tests += tested.tests;
    if walked.is_none() {
        for i in 0..N {
            if open[i] && !occluded[i] {
                let pass =
                    super::integrator::transmittance_tallied(scene, &packet.ray(i), packet.t_max[i], cost);
                occluded[i] = pass == 0.0;
            }
        }
    }
    occluded
}

/// The largest extent of the box around the `live` lanes' origins.
#[inline(always)]
fn origin_spread<const N: usize>(packet: &RayPacket<N>, live: &[bool; N]) -> f32 {
    let mut spread = 0.0f32;
    for axis in 0..3 {
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for i in 0..N {
            if live[i] {
                lo = lo.min(packet.origin[axis][i]);
                hi = hi.max(packet.origin[axis][i]);
            }
        }
        spread = spread.max(hi - lo);
    }
    spread
}
