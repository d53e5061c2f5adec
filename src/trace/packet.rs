//! Ray packets in structure-of-arrays form, traced through the grids by coherent grid traversal.
//!
//! A [`RayPacket`] holds `N` rays as per-axis lane arrays. [`closest_hits`] finds every lane's
//! nearest hit: planes lane by lane, then the top-level grid walked by the whole packet at once
//! ([`coherent_walk`]: Wald, Ize, Kensler, Knoll and Parker, "Ray Tracing Animated Scenes using
//! Coherent Grid Traversal", SIGGRAPH 2006). The packet crosses the grid slice by slice along
//! its rays' common dominant axis; in each slice it visits the rectangle of cells that bounds
//! all its live rays there, and tests each object found against all its live lanes. A mesh
//! instance maps the packet into object space and walks its mesh grid the same way, testing
//! each triangle against all lanes with one SIMD kernel ([`triangle_lanes`](crate::geom::triangle::triangle_lanes)).
//!
//! **Same answers as single rays.** Every lane's hit comes from the same primitive tests, with
//! the same IEEE operations in the same order, as the single-ray path's
//! ([`super::visibility::closest_hit`]): the kernels are the scalar ones written lane-wise, and
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
use crate::accel::packet::{coherent_walk, extent, Footprint, PacketSink, Walk};
use crate::math::{Aabb, RayPacket, Vec3};
use crate::store::{PacketHits, PrimitiveStore, TraversalCost};

/// Rays per packet: 4 × 4 neighbouring pixels (measured against other widths by
/// `benches/layout.rs`).
pub const LANES: usize = 16;

/// Fewest rays worth tracing as a packet: narrower ones go alone. A frustum walk costs about
/// what a few rays' own walks cost, and one or two rays crossing a slice diagonally already
/// overflow its per-lane cell budget (measured: `showcase`, whose area light gives each camera
/// sample one shadow ray, ran 1.35× slower with one-ray packets).
pub const MIN_LANES: usize = 4;

/// Every lane's nearest hit in the scene: planes lane by lane, then the top-level grid by
/// coherent traversal (or lane by lane where the packet is not coherent). Equal, lane for lane,
/// to [`super::visibility::closest_hit`]. `cost` gets the packet's cells and tests.
#[inline(always)]
pub fn closest_hits<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    cost: &mut TraversalCost,
) -> PacketHits<N> {
    struct Objects<'a, const N: usize, S: PrimitiveStore> {
        store: &'a S,
        packet: &'a RayPacket<N>,
        // Borrowed, not moved in and out: the hits are some 450 bytes at 16 lanes.
        hits: &'a mut PacketHits<N>,
        cost: TraversalCost,
    }
    impl<const N: usize, S: PrimitiveStore> PacketSink<N> for Objects<'_, N, S> {
        #[inline(always)]
        fn bound(&self) -> &[f32; N] {
            &self.hits.t
        }
        #[inline(always)]
        fn candidates(&self, ids: &[u32], footprint: &Footprint) -> u64 {
            screen(self.store, ids, &footprint.bounds)
        }
        #[inline(always)]
        fn visit(&mut self, id: u32, live: &[bool; N]) {
            self.store.intersect_bounded_packet(id, self.packet, live, self.hits, &mut self.cost);
        }
    }
    let store = &scene.store;
    let mut hits = PacketHits::new(packet);
    let lanes = packet.active.iter().filter(|&&a| a).count() as u32;
    for p in 0..store.unbounded_count() {
        cost.tests += lanes;
        let bound = hits.t;
        store.intersect_unbounded_packet(p, packet, &packet.active, &packet.t_min, &bound, |i, h| {
            hits.offer(i, Some(h))
        });
    }
    let mut sink = Objects { store, packet, hits: &mut hits, cost: TraversalCost::default() };
    let mut cells = 0;
    let walked = coherent_walk(&scene.grid, packet, &packet.active, &mut sink, &mut cells);
    let tested = sink.cost;
    cost.cells += cells + tested.cells;
    cost.tests += tested.tests;
    if let Walk::GaveUp(unfinished) = walked {
        for i in 0..N {
            if unfinished[i] {
                let ray = packet.ray(i);
                let bound = hits.t[i];
                let found = super::visibility::grid_hit(scene, &ray, packet.t_min[i], bound, cost);
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
/// [`super::visibility::transmittance`] being 0. Shadow packets start at `t_min = 0`.
#[inline(always)]
pub fn occluded<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    origins: Origins,
    cost: &mut TraversalCost,
) -> [bool; N] {
    debug_assert!(!scene.effects.transmission, "`occluded` is for opaque scenes; see `transmittances`");
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
        fn candidates(&self, ids: &[u32], footprint: &Footprint) -> u64 {
            screen(self.store, ids, &footprint.bounds)
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
    let (mut pass, open) = planes_part(scene, packet, cost);
    if scattered(scene, packet, origins, &open) {
        alone(scene, packet, &open, &mut pass, cost);
        return std::array::from_fn(|i| packet.active[i] && pass[i] == Vec3::ZERO);
    }
    let occluded = std::array::from_fn(|i| packet.active[i] && !open[i]);
    let bound = std::array::from_fn(|i| if occluded[i] { f32::NEG_INFINITY } else { packet.t_max[i] });
    let mut sink = Blockers { store, packet, bound, occluded, cost: TraversalCost::default() };
    let mut cells = 0;
    let walked = coherent_walk(&scene.grid, packet, &open, &mut sink, &mut cells);
    let Blockers { mut occluded, cost: tested, .. } = sink;
    cost.cells += cells + tested.cells;
    cost.tests += tested.tests;
    if let Walk::GaveUp(unfinished) = walked {
        let rest = std::array::from_fn(|i| unfinished[i] && !occluded[i]);
        alone(scene, packet, &rest, &mut pass, cost);
        for i in 0..N {
            occluded[i] |= rest[i] && pass[i] == Vec3::ZERO;
        }
    }
    occluded
}

/// Every active lane's shadow transmittance over `(0, t_max)`: equal, lane for lane, to
/// [`super::visibility::transmittance`]. Opaque scenes trace the packet with [`occluded`] (1 or
/// 0); scenes with transmission with [`transmittances`]. Shadow packets start at `t_min = 0`.
#[inline(always)]
pub fn shadow_passes<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    origins: Origins,
    cost: &mut TraversalCost,
) -> [Vec3; N] {
    if scene.effects.transmission {
        transmittances(scene, packet, origins, cost)
    } else {
        occluded(scene, packet, origins, cost).map(|blocked| if blocked { Vec3::ZERO } else { Vec3::ONE })
    }
}

/// Where a shadow packet's rays start. The area-light shadow rays of one shading point share
/// their origin; the shadow rays from a packet's camera hits towards a light start apart, and
/// where those origins are scattered over more than two cells of the grid (hits at different
/// depths) the rays walk alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origins {
    /// Every active lane starts at the same point: never scattered, so not measured.
    Shared,
    /// The lanes start at different points.
    Apart,
}

/// Every active lane's shadow transmittance in a scene with transmission: planes lane by lane,
/// then the top-level grid by coherent traversal. Each object met is handled whole for every
/// walking lane, as a single ray handles it (`object_transmittance`: all
/// its crossings, nearest first, each found by the packet kernels), and a lane drops out once an
/// object blocks it. A lane's shares are multiplied in ascending object id
/// (`ordered_product`), the order the single-ray walk uses too, so the
/// product has the same bits although the packet meets the objects in another order. Lanes of
/// a packet that cannot walk together are traced alone from the start.
#[inline(always)]
pub fn transmittances<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    origins: Origins,
    cost: &mut TraversalCost,
) -> [Vec3; N] {
    use super::visibility::ordered_product;
    /// One object met by the walk: each lane's share, and which lanes have one.
    struct Met<const N: usize> {
        id: u32,
        share: [Vec3; N],
        done: [bool; N],
    }
    struct Shares<'a, const N: usize, S: PrimitiveStore> {
        scene: &'a TraceScene<S>,
        packet: &'a RayPacket<N>,
        /// The packet, each lane's `t_min` moved past the crossings found so far of the object
        /// being visited.
        from: RayPacket<N>,
        bound: [f32; N],
        met: Vec<Met<N>>,
        cost: TraversalCost,
    }
    impl<const N: usize, S: PrimitiveStore> PacketSink<N> for Shares<'_, N, S> {
        #[inline(always)]
        fn bound(&self) -> &[f32; N] {
            &self.bound
        }
        #[inline(always)]
        fn candidates(&self, ids: &[u32], footprint: &Footprint) -> u64 {
            screen(&self.scene.store, ids, &footprint.bounds)
        }
        #[inline(always)]
        fn visit(&mut self, id: u32, live: &[bool; N]) {
            let k = match self.met.iter().position(|m| m.id == id) {
                Some(k) => k,
                None => {
                    self.met.push(Met { id, share: [Vec3::ONE; N], done: [false; N] });
                    self.met.len() - 1
                }
            };
            let met = &mut self.met[k];
            // The lanes still open that have no share of this object yet: all its crossings,
            // nearest first, one packet-kernel call per crossing.
            let mut todo = [false; N];
            for i in 0..N {
                todo[i] = live[i] & (self.bound[i] > f32::NEG_INFINITY) & !met.done[i];
                met.done[i] |= todo[i];
            }
            let store = &self.scene.store;
            let from = &mut self.from;
            from.t_min = self.packet.t_min;
            while todo.iter().any(|&t| t) {
                let mut hits = PacketHits::new(from);
                store.intersect_bounded_packet(id, from, &todo, &mut hits, &mut self.cost);
                for i in 0..N {
                    if !todo[i] {
                        continue;
                    }
                    let Some(h) = hits.hit[i] else {
                        todo[i] = false;
                        continue;
                    };
                    met.share[i] *= self.scene.material(store.material(&h)).kt;
                    if met.share[i] == Vec3::ZERO {
                        // Blocked: the lane's walk is over.
                        self.bound[i] = f32::NEG_INFINITY;
                        todo[i] = false;
                    } else {
                        from.t_min[i] = h.t;
                    }
                }
            }
        }
    }
    let (mut pass, open) = planes_part(scene, packet, cost);
    if scattered(scene, packet, origins, &open) {
        alone(scene, packet, &open, &mut pass, cost);
        return pass;
    }
    let bound = std::array::from_fn(|i| if open[i] { packet.t_max[i] } else { f32::NEG_INFINITY });
    let mut sink =
        Shares { scene, packet, from: *packet, bound, met: Vec::new(), cost: TraversalCost::default() };
    let mut cells = 0;
    let walked = coherent_walk(&scene.grid, packet, &open, &mut sink, &mut cells);
    let Shares { bound, mut met, cost: tested, .. } = sink;
    cost.cells += cells + tested.cells;
    cost.tests += tested.tests;
    if let Walk::GaveUp(_) = walked {
        // The shares found so far cover only part of each lane's way: start again, alone.
        alone(scene, packet, &open, &mut pass, cost);
        return pass;
    }
    // Each lane's shares straight from the objects, in id order: no vector per packet.
    met.sort_unstable_by_key(|m| m.id);
    for i in 0..N {
        if !open[i] {
            continue;
        }
        if bound[i] == f32::NEG_INFINITY {
            pass[i] = Vec3::ZERO;
            continue;
        }
        pass[i] = ordered_product(pass[i], met.iter().filter(|m| m.done[i]).map(|m| (m.id, m.share[i])));
    }
    pass
}

/// The planes' part of each active lane's shadow transmittance
/// ([`super::visibility::planes_transmittance`]), and the lanes it leaves open.
#[inline(always)]
fn planes_part<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    cost: &mut TraversalCost,
) -> ([Vec3; N], [bool; N]) {
    // Lane-wise, plane by plane: each lane multiplies its planes' `kt` in the single ray's order
    // and stops (blocked) where it would return 0.
    let store = &scene.store;
    let mut pass = packet.active.map(|a| if a { Vec3::ONE } else { Vec3::ZERO });
    let mut open = packet.active;
    for p in 0..store.unbounded_count() {
        let live = open;
        cost.tests += live.iter().filter(|&&l| l).count() as u32;
        store.intersect_unbounded_packet(p, packet, &live, &[0.0; N], &packet.t_max, |i, h| {
            pass[i] *= scene.material(store.material(&h)).kt;
            if !scene.effects.transmission || pass[i] == Vec3::ZERO {
                pass[i] = Vec3::ZERO;
                open[i] = false;
            }
        });
    }
    (pass, open)
}

/// The objects of a top-level cell (`ids`, at most 64) that may meet a slice's `footprint`
/// ([`PrimitiveStore::may_meet`]), as a [`PacketSink::candidates`] mask: a cell of small
/// spheres holds many that a packet's few rays pass by.
#[inline(always)]
fn screen<S: PrimitiveStore>(store: &S, ids: &[u32], footprint: &Aabb) -> u64 {
    let mut mask = 0u64;
    for (k, &id) in ids.iter().enumerate() {
        mask |= u64::from(store.may_meet(id, footprint)) << k;
    }
    mask
}

/// True when the `open` lanes' origins are scattered over more than two cells (shadow rays from
/// hits at different depths): their frustum would sweep many cells per ray, so they walk alone
/// from the start. [`Origins::Shared`] never is.
#[inline(always)]
fn scattered<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    origins: Origins,
    open: &[bool; N],
) -> bool {
    debug_assert!(
        origins == Origins::Apart || origin_spread(packet, &packet.active) == 0.0,
        "a packet said to share its origin does not"
    );
    origins == Origins::Apart && origin_spread(packet, open) > 2.0 * scene.grid.cell_size.max_element()
}

/// Each of the `lanes`' whole shadow transmittance, traced alone, into `pass`.
#[inline(always)]
fn alone<const N: usize, S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &RayPacket<N>,
    lanes: &[bool; N],
    pass: &mut [Vec3; N],
    cost: &mut TraversalCost,
) {
    for i in 0..N {
        if lanes[i] {
            pass[i] = super::visibility::transmittance_tallied(scene, &packet.ray(i), packet.t_max[i], cost);
        }
    }
}

/// The largest extent of the box around the `live` lanes' origins.
#[inline(always)]
fn origin_spread<const N: usize>(packet: &RayPacket<N>, live: &[bool; N]) -> f32 {
    let mut spread = 0.0f32;
    for axis in 0..3 {
        let o = &packet.origin[axis];
        let lo: [f32; N] = std::array::from_fn(|i| if live[i] { o[i] } else { f32::INFINITY });
        let hi: [f32; N] = std::array::from_fn(|i| if live[i] { o[i] } else { f32::NEG_INFINITY });
        let (lo, hi) = extent(lo, hi);
        spread = spread.max(hi - lo);
    }
    spread
}
