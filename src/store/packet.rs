//! Packets against the stores: each lane's nearest hit, and the mesh level of coherent
//! traversal (a packet mapped into an instance's object space walks the mesh grid and tests
//! each triangle against all its lanes with one kernel).

// Lane loops index several parallel lane arrays by the same lane number.
#![allow(clippy::needless_range_loop)]

use super::{Hit, MeshEntry, ObjectId, TraversalCost, TriangleLayout};
use crate::accel::packet::{coherent_walk, Footprint, PacketSink, Walk};
use crate::geom::triangle::{triangle_lanes, TriangleHit, WatertightPacket};
use crate::math::RayPacket;

/// Each lane's nearest hit so far; `t` bounds the search (a lane's `t_max` until it hits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PacketHits<const N: usize> {
    /// Ray parameter of the nearest hit, or the lane's `t_max`.
    pub t: [f32; N],
    /// The hit.
    pub hit: [Option<Hit>; N],
}

impl<const N: usize> PacketHits<N> {
    /// No hits yet: every lane searches up to its `t_max`.
    #[inline]
    pub fn new(packet: &RayPacket<N>) -> Self {
        Self { t: packet.t_max, hit: [None; N] }
    }

    /// Keeps `candidate` for lane `i`, which the caller found within `(t_min, t[i])`.
    #[inline]
    pub fn offer(&mut self, i: usize, candidate: Option<Hit>) {
        if let Some(h) = candidate {
            self.t[i] = h.t;
            self.hit[i] = Some(h);
        }
    }
}

/// The nearest triangle hits of a packet in a mesh (in object space), by coherent traversal of
/// the mesh grid; lanes that cannot walk together finish alone. `record(lane, index, hit)` gets
/// every improvement; `bound` is each lane's search bound.
#[inline(always)]
pub fn mesh_hits<const N: usize, L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    packet: &RayPacket<N>,
    live: &[bool; N],
    bound: &mut [f32; N],
    cost: &mut TraversalCost,
    mut record: impl FnMut(usize, u32, TriangleHit),
) {
    let Walk::GaveUp(unfinished) = mesh_walk(mesh, packet, live, bound, cost, &mut record) else { return };
    for i in 0..N {
        if unfinished[i] {
            if let Some((k, h)) =
                super::mesh::intersect(mesh, &packet.ray(i), packet.t_min[i], bound[i], cost)
            {
                bound[i] = h.t;
                record(i, k, h);
            }
        }
    }
}

/// The coherent walk of the `live` lanes through the mesh grid, for [`mesh_hits`] and
/// [`mesh_occluded`]: each triangle met is tested against every walking lane, `bound` tightens
/// and `record` hears of each improvement.
#[inline(always)]
fn mesh_walk<const N: usize, L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    packet: &RayPacket<N>,
    live: &[bool; N],
    bound: &mut [f32; N],
    cost: &mut TraversalCost,
    record: impl FnMut(usize, u32, TriangleHit),
) -> Walk<N> {
    struct Tris<'a, const N: usize, L: TriangleLayout, R: FnMut(usize, u32, TriangleHit)> {
        triangles: &'a L,
        w: WatertightPacket<N>,
        t_min: [f32; N],
        bound: &'a mut [f32; N],
        tests: u32,
        record: R,
    }
    impl<const N: usize, L: TriangleLayout, R: FnMut(usize, u32, TriangleHit)> PacketSink<N>
        for Tris<'_, N, L, R>
    {
        #[inline(always)]
        fn bound(&self) -> &[f32; N] {
            self.bound
        }
        /// The triangles whose bounds meet the footprint, screened without a branch per
        /// triangle (about half of a cell's pass, so a branch would often be mispredicted).
        #[inline(always)]
        fn candidates(&self, ids: &[u32], footprint: &Footprint) -> u64 {
            self.triangles.screen(ids, footprint)
        }
        #[inline(always)]
        fn visit(&mut self, id: u32, live: &[bool; N]) {
            self.tests += lanes(live);
            let record = &mut self.record;
            triangle_lanes(self.triangles.vertices(id), &self.w, live, &self.t_min, self.bound, |i, h| {
                record(i, id, h)
            });
        }
    }
    let grid = &mesh.asset.grid;
    let mut sink = Tris {
        triangles: &mesh.triangles,
        w: WatertightPacket::new(packet, live),
        t_min: packet.t_min,
        bound,
        tests: 0,
        record,
    };
    let mut cells = 0;
    let walked = coherent_walk(grid, packet, live, &mut sink, &mut cells);
    cost.cells += cells;
    cost.tests += sink.tests;
    walked
}

/// Each `live` lane's nearest hit with bounded object `id`, one lane at a time through the
/// store's single-ray test (the default of [`super::PrimitiveStore::intersect_bounded_packet`],
/// and the way kinds without a packet kernel are tested).
#[inline(always)]
pub fn lane_by_lane<const N: usize, S: super::PrimitiveStore>(
    store: &S,
    id: u32,
    packet: &RayPacket<N>,
    live: &[bool; N],
    hits: &mut PacketHits<N>,
    cost: &mut TraversalCost,
) {
    for i in 0..N {
        if live[i] {
            let found = store.intersect_bounded(id, &packet.ray(i), packet.t_min[i], hits.t[i], cost);
            hits.offer(i, found);
        }
    }
}

/// Each `live` lane's nearest hit with mesh instance `object` (its mesh `mesh`, its map
/// `to_object`): the packet mapped into object space walks the mesh grid together.
#[inline(always)]
pub fn instance_hits<const N: usize, L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    to_object: &crate::math::Affine3A,
    object: ObjectId,
    packet: &RayPacket<N>,
    live: &[bool; N],
    hits: &mut PacketHits<N>,
    cost: &mut TraversalCost,
) {
    let local = packet.mapped(to_object, live);
    let found = &mut hits.hit;
    mesh_hits(mesh, &local, live, &mut hits.t, cost, |i, k, h| found[i] = Some(Hit::triangle(object, k, &h)));
}

/// Each `live` lane's nearest hit with the triangles `first..first + count` of a layout (a scene
/// triangle or polygon, object `object`), every triangle tested against all lanes at once.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn triangle_range_hits<const N: usize, L: TriangleLayout>(
    triangles: &L,
    object: ObjectId,
    first: u32,
    count: u32,
    packet: &RayPacket<N>,
    live: &[bool; N],
    hits: &mut PacketHits<N>,
    cost: &mut TraversalCost,
) {
    cost.tests += count * lanes(live);
    let w = WatertightPacket::new(packet, live);
    let found = &mut hits.hit;
    for k in first..first + count {
        triangle_lanes(triangles.vertices(k), &w, live, &packet.t_min, &mut hits.t, |i, h| {
            found[i] = Some(Hit::triangle(object, k - first, &h))
        });
    }
}

/// Marks the `live` lanes that mesh `mesh` blocks anywhere in `(t_min, t_max)` (in object
/// space) in `occluded`: the packet walks the mesh grid together, each lane dropping out after
/// the slice of its first hit; where the packet gives up, the lanes it has not found blocked
/// and had not finished take the single-ray any-hit walk ([`super::mesh::occluded`]).
#[inline(always)]
pub fn mesh_occluded<const N: usize, L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    packet: &RayPacket<N>,
    live: &[bool; N],
    occluded: &mut [bool; N],
    cost: &mut TraversalCost,
) {
    let mut bound = packet.t_max;
    let mut found = [false; N];
    let walked = mesh_walk(mesh, packet, live, &mut bound, cost, |i, _, _| found[i] = true);
    // The walk searches with nearest-hit bounds; for any-hit, a hit anywhere in range is enough,
    // so a lane with one is done whether or not its walk was, and the others finish alone.
    if let Walk::GaveUp(unfinished) = walked {
        for i in 0..N {
            if unfinished[i] && !found[i] {
                found[i] =
                    super::mesh::occluded(mesh, &packet.ray(i), packet.t_min[i], packet.t_max[i], cost);
            }
        }
    }
    for i in 0..N {
        occluded[i] |= found[i];
    }
}

/// Marks the `live` lanes that the triangles `first..first + count` block in `occluded`.
#[inline(always)]
pub fn triangle_range_occluded<const N: usize, L: TriangleLayout>(
    triangles: &L,
    first: u32,
    count: u32,
    packet: &RayPacket<N>,
    live: &[bool; N],
    occluded: &mut [bool; N],
    cost: &mut TraversalCost,
) {
    cost.tests += count * lanes(live);
    let w = WatertightPacket::new(packet, live);
    let mut bound = packet.t_max;
    for k in first..first + count {
        triangle_lanes(triangles.vertices(k), &w, live, &packet.t_min, &mut bound, |i, _| occluded[i] = true);
    }
}

/// Marks in `occluded` the `live` lanes that bounded object `id` blocks, one lane at a time
/// through the store's single-ray test (the default of
/// [`super::PrimitiveStore::occludes_bounded_packet`]).
#[inline(always)]
pub fn occluded_lane_by_lane<const N: usize, S: super::PrimitiveStore>(
    store: &S,
    id: u32,
    packet: &RayPacket<N>,
    live: &[bool; N],
    occluded: &mut [bool; N],
    cost: &mut TraversalCost,
) {
    for i in 0..N {
        if live[i] && !occluded[i] {
            occluded[i] = store.occludes_bounded(id, &packet.ray(i), packet.t_min[i], packet.t_max[i], cost);
        }
    }
}

/// Each `live` lane's nearest hit with sphere `object`, all lanes in one kernel.
#[inline(always)]
pub fn sphere_hits<const N: usize>(
    centre: crate::math::Vec3,
    radius: f32,
    object: ObjectId,
    packet: &RayPacket<N>,
    live: &[bool; N],
    hits: &mut PacketHits<N>,
    cost: &mut TraversalCost,
) {
    cost.tests += lanes(live);
    let found = &mut hits.hit;
    crate::geom::sphere::intersect_lanes(centre, radius, packet, live, &mut hits.t, |i, t| {
        found[i] = Some(Hit::new(t, object, 0))
    });
}

/// Marks the `live` lanes that a sphere blocks in `occluded`, all lanes in one kernel.
#[inline(always)]
pub fn sphere_occluded<const N: usize>(
    centre: crate::math::Vec3,
    radius: f32,
    packet: &RayPacket<N>,
    live: &[bool; N],
    occluded: &mut [bool; N],
    cost: &mut TraversalCost,
) {
    cost.tests += lanes(live);
    let mut bound = packet.t_max;
    crate::geom::sphere::intersect_lanes(centre, radius, packet, live, &mut bound, |i, _| occluded[i] = true);
}

/// Each `live` lane's nearest hit with box `object` (its world-to-object map and corners), all
/// lanes in one kernel.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn cuboid_hits<const N: usize>(
    to_object: &crate::math::Affine3A,
    min: crate::math::Vec3,
    max: crate::math::Vec3,
    object: ObjectId,
    packet: &RayPacket<N>,
    live: &[bool; N],
    hits: &mut PacketHits<N>,
    cost: &mut TraversalCost,
) {
    cost.tests += lanes(live);
    let found = &mut hits.hit;
    crate::geom::cuboid::intersect_lanes(to_object, min, max, packet, live, &mut hits.t, |i, h| {
        found[i] = Some(super::cuboid_face_hit(object, &h))
    });
}

/// Marks the `live` lanes that a box blocks in `occluded`, all lanes in one kernel.
#[inline(always)]
pub fn cuboid_occluded<const N: usize>(
    to_object: &crate::math::Affine3A,
    min: crate::math::Vec3,
    max: crate::math::Vec3,
    packet: &RayPacket<N>,
    live: &[bool; N],
    occluded: &mut [bool; N],
    cost: &mut TraversalCost,
) {
    cost.tests += lanes(live);
    let mut bound = packet.t_max;
    crate::geom::cuboid::intersect_lanes(to_object, min, max, packet, live, &mut bound, |i, _| {
        occluded[i] = true
    });
}

/// Number of `live` lanes: one primitive test each.
#[inline(always)]
fn lanes<const N: usize>(live: &[bool; N]) -> u32 {
    live.iter().filter(|&&l| l).count() as u32
}
