//! Primitive stores: the flattened geometry of a snapshot, behind one trait so the tracer can
//! be monomorphized over different memory layouts and benchmarked on identical code paths.
//!
//! Objects are numbered by the caller: bounded objects `0..bounded_count()` in the order the
//! grid indexes them, unbounded ones (planes) tested on every ray. Mesh instances are bounded
//! objects that point at a shared [`MeshEntry`]: the bottom level of the two-level grid. A hit
//! names its object with an [`ObjectId`] (bounded, plane, or moving), decoded in one place.
//!
//! Two layouts implement the trait on one code path: [`SoaStore`] (one array per coordinate)
//! and [`AosStore`] (one struct per primitive). The tracer is generic over the store, so the
//! `--layout` benchmark compares memory layout and nothing else.

pub mod aos;
pub mod mesh;
mod object_id;
pub mod packet;
pub mod soa;

use std::sync::Arc;

pub use aos::{AosStore, AosTriangles};
pub use mesh::{MeshAsset, MeshEntry};
pub use object_id::{ObjectId, ObjectKind};
pub use packet::PacketHits;
pub use soa::{SoaStore, SoaTriangles};

pub use crate::accel::{NoTally, Tally};

use crate::accel::packet::Footprint;
use crate::geom::mesh::MeshData;
use crate::geom::triangle::{TriangleHit, WatertightRay};
use crate::geom::uv::SurfaceUv;
use crate::geom::Placed;
use crate::math::{offset_origin, Ray, RayPacket, Vec2, Vec3};

/// Index of a material in the snapshot's material table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct MaterialId(pub u32);

/// A ray/object intersection, before shading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Ray parameter.
    pub t: f32,
    /// The object: bounded, a plane, or moving.
    pub object: ObjectId,
    /// Detail within the object: the triangle index of a triangle set or mesh, the face code
    /// of a box.
    pub prim: u32,
    /// Barycentric weight of the triangle's second vertex (0 for other shapes).
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex (0 for other shapes).
    pub v: f32,
}

impl Hit {
    /// A hit with no barycentrics (spheres, boxes, planes).
    #[inline]
    pub fn new(t: f32, object: ObjectId, prim: u32) -> Self {
        Self { t, object, prim, u: 0.0, v: 0.0 }
    }

    /// A triangle hit.
    #[inline]
    pub fn triangle(object: ObjectId, prim: u32, h: &TriangleHit) -> Self {
        Self { t: h.t, object, prim, u: h.u, v: h.v }
    }

    /// Where a store finds this hit's object: its planes or its bounded objects. A moving
    /// object's hit is shaded from the snapshot's motion ([`crate::trace::SceneMotion`]),
    /// never looked up in a store.
    #[inline]
    pub(crate) fn stored(&self) -> Stored {
        match self.object.kind() {
            ObjectKind::Plane(i) => Stored::Plane(i as usize),
            ObjectKind::Bounded(o) => Stored::Bounded(o as usize),
            ObjectKind::Moving(_) => unreachable!("a moving object's hit is not a store's"),
        }
    }
}

/// A stored object's index, by table: [`Hit::stored`].
pub(crate) enum Stored {
    /// Index into the planes.
    Plane(usize),
    /// Index into the bounded objects.
    Bounded(usize),
}

/// What one ray's traversal cost: grid cells visited and primitives tested, both levels. The
/// [`Tally`] that counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraversalCost {
    /// Cells visited (top level and mesh grids).
    pub cells: u32,
    /// Primitive intersection tests (objects and triangles).
    pub tests: u32,
}

impl TraversalCost {
    /// A packet's cost shared among its `rays` lanes (rounded up): what each ray cost.
    pub fn per_ray(&self, rays: u32) -> Self {
        let rays = rays.max(1);
        Self { cells: self.cells.div_ceil(rays), tests: self.tests.div_ceil(rays) }
    }
}

impl Tally for TraversalCost {
    #[inline(always)]
    fn cell(&mut self) {
        self.cells += 1;
    }

    #[inline(always)]
    fn tests(&mut self, n: u32) {
        self.tests += n;
    }
}

/// What shading needs of a hit point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// World position.
    pub point: Vec3,
    /// Unit geometric normal (outward for closed shapes; front side for flat ones).
    pub normal: Vec3,
    /// Unit shading normal: the interpolated vertex normal of a smooth mesh, else `normal`.
    pub shading: Vec3,
    /// Where rays leaving the front side start from, relative to `point`: on a smooth mesh the
    /// point lifted towards the curved surface its vertex normals describe (Hanika 2021,
    /// "Hacking the shadow terminator"), so that shadow rays do not fall back onto the flat
    /// facet; zero elsewhere.
    pub lift: Vec3,
    /// A conservative bound on the distance between `point` and the surface along `normal`, as
    /// the shape's own intersection test will see a ray starting there (each shape derives it
    /// from the rounding of its arithmetic, pbrt-v4 style): rays leaving the surface start just
    /// beyond it ([`SurfacePoint::spawn`]).
    pub error: f32,
    /// On a box's edge or corner, the sum of the world normals of the adjacent faces the point
    /// lies on (within rounding); zero elsewhere. Rays leave along `normal + edge`, so that they
    /// start off every face they touch ([`crate::geom::cuboid::surface_point`]).
    pub edge: Vec3,
    /// Material of the object hit.
    pub material: MaterialId,
}

impl SurfacePoint {
    /// The origin of a ray leaving this point towards `dir`: just beyond the error bound along
    /// the geometric normal (and, on a box's edge or corner, along the adjacent faces' normals),
    /// on the side `dir` points into ([`crate::math::offset_origin`]). Rays leaving the front of
    /// a smooth mesh start from the lifted point. Always inlined, as are
    /// [`crate::trace::ShadingPoint::new`] and [`offset_origin`], into the packet lane that has
    /// just built the surface point: its fields are read in registers, not back from memory.
    #[inline(always)]
    pub fn spawn(&self, dir: Vec3) -> Vec3 {
        if self.lift != Vec3::ZERO && dir.dot(self.normal) > 0.0 {
            // Adding the lift rounds the coordinates by half an ulp each.
            let lifted = self.point + self.lift;
            let error = self.error + crate::math::gamma(1) * lifted.abs().dot(self.normal.abs());
            return offset_origin(lifted, error, self.normal, dir);
        }
        if self.edge != Vec3::ZERO {
            // The side is the face's; the offset leaves the adjacent faces on that side too.
            let along = self.normal + self.edge;
            let side = if dir.dot(self.normal) < 0.0 { -along } else { along };
            return offset_origin(self.point, self.error, along, side);
        }
        offset_origin(self.point, self.error, self.normal, dir)
    }
}

/// One object handed to a store: placed geometry and its material.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedObject {
    /// World-space geometry.
    pub geometry: Placed,
    /// Material id.
    pub material: MaterialId,
}

/// A layout of triangles: the bottom level's hot data.
pub trait TriangleLayout: Send + Sync + Sized + std::fmt::Debug + 'static {
    /// Lays out a mesh's triangles in index order.
    fn from_mesh(mesh: &MeshData) -> Self;
    /// Lays out triangles given by their vertices.
    fn from_vertices(tris: impl IntoIterator<Item = [Vec3; 3]>) -> Self;
    /// Number of triangles.
    fn len(&self) -> u32;
    /// True when there are none.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The vertices of triangle `i`.
    fn vertices(&self, i: u32) -> [Vec3; 3];
    /// Watertight test of triangle `i` within `(t_min, t_max)`.
    fn intersect(&self, i: u32, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<TriangleHit>;
    /// Bytes held.
    fn memory_bytes(&self) -> usize;
    /// Which of triangles `ids` (at most 64, one cell's) have bounds that meet a packet walk's
    /// `footprint` on its two cross axes (bit `k` for `ids[k]`), without a branch per triangle;
    /// the same comparisons as the bounds' overlap with the footprint, less the dominant axis's,
    /// which every triangle of the slice's cells passes. A layout may read only the two axes.
    #[inline(always)]
    fn screen(&self, ids: &[u32], footprint: &Footprint) -> u64 {
        let [u, v] = footprint.cross;
        screen_by(ids, footprint, |id| {
            let [a, b, c] = self.vertices(id).map(|p| p.to_array());
            ([a[u], b[u], c[u]], [a[v], b[v], c[v]])
        })
    }
}

/// [`TriangleLayout::screen`] with each triangle's three coordinates on the two cross axes
/// given by `coordinates(id)`: the mask, one bit per id, without a branch per triangle.
#[inline(always)]
pub fn screen_by(
    ids: &[u32],
    footprint: &Footprint,
    coordinates: impl Fn(u32) -> ([f32; 3], [f32; 3]),
) -> u64 {
    let [u, v] = footprint.cross;
    let (lo, hi) = (footprint.bounds.min.to_array(), footprint.bounds.max.to_array());
    let mut mask = 0u64;
    for (k, &id) in ids.iter().enumerate() {
        let (cu, cv) = coordinates(id);
        mask |= u64::from(spans_meet(cu, lo[u], hi[u]) & spans_meet(cv, lo[v], hi[v])) << k;
    }
    mask
}

/// Whether the span of three coordinates meets `[lo, hi]`: their smallest is at most `hi` and
/// their largest at least `lo` (what a box overlap compares on one axis).
#[inline(always)]
fn spans_meet([a, b, c]: [f32; 3], lo: f32, hi: f32) -> bool {
    // Compare-selects, not `f32::min` (NaN handling a mesh's finite vertices never need).
    let min = |x: f32, y: f32| if x < y { x } else { y };
    let max = |x: f32, y: f32| if x > y { x } else { y };
    let (min, max) = (min(min(a, b), c), max(max(a, b), c));
    (min <= hi) & (lo <= max)
}

/// A layout of flattened primitives that the tracer can intersect.
///
/// Every method takes directions of any non-zero length, with `t` in units of that length (mesh
/// instances hand their object-space rays to the mesh grid without renormalising them).
pub trait PrimitiveStore: Send + Sync + Sized + std::fmt::Debug + 'static {
    /// The layout of mesh triangles in this store.
    type Triangles: TriangleLayout;
    /// Builds the store: `bounded` in grid-id order, `unbounded` (planes) in any order;
    /// mesh instances index `meshes` by their [`crate::geom::MeshId`].
    fn build(
        bounded: &[PlacedObject],
        unbounded: &[PlacedObject],
        meshes: &[Arc<MeshEntry<Self::Triangles>>],
    ) -> Self;
    /// Number of bounded objects.
    fn bounded_count(&self) -> u32;
    /// Nearest hit with bounded object `id` in `(t_min, t_max)`, adding its cost to `cost`
    /// (pass [`NoTally`] when nobody asks).
    fn intersect_bounded<T: Tally>(
        &self,
        id: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        cost: &mut T,
    ) -> Option<Hit>;
    /// True when bounded object `id` is hit anywhere in `(t_min, t_max)`, adding its cost.
    fn occludes_bounded<T: Tally>(&self, id: u32, ray: &Ray, t_min: f32, t_max: f32, cost: &mut T) -> bool {
        self.intersect_bounded(id, ray, t_min, t_max, cost).is_some()
    }
    /// False only where bounded object `id` certainly meets nothing in the closed box
    /// `footprint` (a sphere whose bounds miss it): packet walks screen a cell's objects against
    /// the slice's footprint with this. By default every object may meet it.
    #[inline(always)]
    fn may_meet(&self, id: u32, footprint: &crate::math::Aabb) -> bool {
        let _ = (id, footprint);
        true
    }
    /// The packet form of [`PrimitiveStore::intersect_bounded`]: each `live` lane's nearest hit
    /// with bounded object `id` within `(t_min, hits.t)` goes into `hits`. Lane for lane the
    /// same hits as the single-ray method (this default calls it per lane).
    #[inline(always)]
    fn intersect_bounded_packet<const N: usize>(
        &self,
        id: u32,
        packet: &RayPacket<N>,
        live: &[bool; N],
        hits: &mut PacketHits<N>,
        cost: &mut TraversalCost,
    ) {
        packet::lane_by_lane(self, id, packet, live, hits, cost)
    }
    /// The packet form of [`PrimitiveStore::occludes_bounded`]: sets `occluded[i]` for each
    /// `live` lane that bounded object `id` blocks within `(t_min, t_max)`. Lane for lane the
    /// same answer as the single-ray method (this default calls it per lane).
    #[inline(always)]
    fn occludes_bounded_packet<const N: usize>(
        &self,
        id: u32,
        packet: &RayPacket<N>,
        live: &[bool; N],
        occluded: &mut [bool; N],
        cost: &mut TraversalCost,
    ) {
        packet::occluded_lane_by_lane(self, id, packet, live, occluded, cost)
    }
    /// Number of unbounded objects.
    fn unbounded_count(&self) -> u32;
    /// Unbounded object `i`, a plane `normal · p = offset`: `(normal, offset)`.
    fn unbounded_plane(&self, i: u32) -> (Vec3, f32);
    /// Hit with unbounded object `i` in `(t_min, t_max)`.
    #[inline(always)]
    fn intersect_unbounded(&self, i: u32, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let (normal, offset) = self.unbounded_plane(i);
        crate::geom::plane::intersect(normal, offset, ray, t_min, t_max)
            .map(|t| Hit::new(t, ObjectId::plane(i), 0))
    }
    /// The packet form of [`PrimitiveStore::intersect_unbounded`]: each `live` lane's hit with
    /// unbounded object `i` within `(t_min, bound)` goes to `record(lane, hit)`, lane-wise
    /// ([`crate::geom::plane::intersect_lanes`]); lane for lane the single-ray method's hits.
    #[inline(always)]
    fn intersect_unbounded_packet<const N: usize>(
        &self,
        i: u32,
        packet: &RayPacket<N>,
        live: &[bool; N],
        t_min: &[f32; N],
        bound: &[f32; N],
        mut record: impl FnMut(usize, Hit),
    ) {
        let (normal, offset) = self.unbounded_plane(i);
        crate::geom::plane::intersect_lanes(normal, offset, packet, live, t_min, bound, |lane, t| {
            record(lane, Hit::new(t, ObjectId::plane(i), 0))
        });
    }
    /// Material of the object hit.
    fn material(&self, hit: &Hit) -> MaterialId;
    /// Position, normals and material at a hit.
    fn surface(&self, hit: &Hit, ray: &Ray) -> SurfacePoint;
    /// Texture coordinates and their position derivatives at a hit whose surface point is
    /// `point`, the camera being at `origin` in the world ([`crate::geom::uv`]). Asked only
    /// where a texture is looked up.
    fn uv(&self, hit: &Hit, point: Vec3, origin: glam::DVec3) -> SurfaceUv;
    /// Bytes held by the store's own arrays (shared mesh layouts excluded).
    fn memory_bytes(&self) -> usize;
    /// The mesh table the store was built with.
    fn meshes(&self) -> &[Arc<MeshEntry<Self::Triangles>>];
}

/// Hit with the sphere that is bounded object `id`, counting one test: both stores' sphere
/// path, inlined into the single-ray walks' loops.
#[inline(always)]
pub(crate) fn sphere_hit<T: Tally>(
    centre: Vec3,
    radius: f32,
    id: u32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    cost: &mut T,
) -> Option<Hit> {
    cost.tests(1);
    crate::geom::sphere::intersect(centre, radius, ray, t_min, t_max)
        .map(|t| Hit::new(t, ObjectId::bounded(id), 0))
}

/// Nearest hit among triangles `first..first + count` of a layout (a scene triangle or polygon).
#[inline]
pub(crate) fn triangle_range_hit<L: TriangleLayout>(
    tris: &L,
    object: ObjectId,
    first: u32,
    count: u32,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let wray = WatertightRay::new(ray);
    let mut best = None;
    let mut t_best = t_max;
    for i in first..first + count {
        if let Some(h) = tris.intersect(i, &wray, t_min, t_best) {
            t_best = h.t;
            best = Some(Hit::triangle(object, i - first, &h));
        }
    }
    best
}

/// A box hit with its face encoded in `prim`: axis in the low bits, sign in bit 2.
#[inline]
pub(crate) fn cuboid_hit(
    to_object: &crate::math::Affine3A,
    min: Vec3,
    max: Vec3,
    object: ObjectId,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    crate::geom::cuboid::intersect(to_object, min, max, ray, t_min, t_max)
        .map(|h| cuboid_face_hit(object, &h))
}

/// A box hit as a [`Hit`]: the face (axis and sign of its normal) encoded in `prim`.
#[inline]
pub(crate) fn cuboid_face_hit(object: ObjectId, h: &crate::geom::cuboid::CuboidHit) -> Hit {
    let n = h.local_normal;
    let axis = if n.x != 0.0 {
        0
    } else if n.y != 0.0 {
        1
    } else {
        2
    };
    let negative = (n[axis] < 0.0) as u32;
    Hit::new(h.t, object, axis as u32 | negative << 2)
}

/// The object-space outward normal of the box face encoded by [`cuboid_hit`].
#[inline]
fn cuboid_local_normal(face: u32) -> Vec3 {
    let mut local = Vec3::ZERO;
    local[(face & 3) as usize] = if face & 4 != 0 { -1.0 } else { 1.0 };
    local
}

/// The surface at a hit on the box face encoded by [`cuboid_hit`].
#[inline]
pub(crate) fn cuboid_surface(
    to_object: &crate::math::Affine3A,
    min: Vec3,
    max: Vec3,
    hit: &Hit,
    ray: &Ray,
    material: MaterialId,
) -> SurfacePoint {
    let local = cuboid_local_normal(hit.prim);
    let normal = crate::geom::cuboid::world_normal(to_object, local);
    let (point, error, edge) = crate::geom::cuboid::surface_point(to_object, min, max, local, ray, hit.t);
    SurfacePoint { point, normal, shading: normal, lift: Vec3::ZERO, error, edge, material }
}

/// The surface at a hit on a sphere.
#[inline]
pub(crate) fn sphere_surface(
    centre: Vec3,
    radius: f32,
    hit: &Hit,
    ray: &Ray,
    material: MaterialId,
) -> SurfacePoint {
    let (point, normal, error) = crate::geom::sphere::surface_point(centre, radius, ray, hit.t);
    SurfacePoint { point, normal, shading: normal, lift: Vec3::ZERO, error, edge: Vec3::ZERO, material }
}

/// The surface at a hit on a world-space triangle.
#[inline]
pub(crate) fn triangle_surface([a, b, c]: [Vec3; 3], hit: &Hit, material: MaterialId) -> SurfacePoint {
    let normal = crate::geom::triangle::normal(a, b, c);
    let (point, error) = crate::geom::triangle::surface_point(a, b, c, hit.u, hit.v, normal);
    SurfacePoint { point, normal, shading: normal, lift: Vec3::ZERO, error, edge: Vec3::ZERO, material }
}

/// The surface at a hit on a plane.
#[inline]
pub(crate) fn plane_surface(
    normal: Vec3,
    offset: f32,
    hit: &Hit,
    ray: &Ray,
    material: MaterialId,
) -> SurfacePoint {
    let (point, error) = crate::geom::plane::surface_point(normal, offset, ray, hit.t);
    SurfacePoint { point, normal, shading: normal, lift: Vec3::ZERO, error, edge: Vec3::ZERO, material }
}

/// Texture coordinates at a hit on a mesh instance placed by `to_object`: the file's `vt`
/// interpolated, or zero (and no derivatives) for a mesh without them.
#[inline]
pub(crate) fn instance_uv<L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    to_object: &crate::math::Affine3A,
    hit: &Hit,
) -> SurfaceUv {
    let data = &mesh.asset.data;
    match data.indices.get(hit.prim as usize) {
        Some(face) if !data.uvs.is_empty() => crate::geom::uv::triangle(
            face.map(|i| data.positions[i as usize]),
            face.map(|i| data.uvs[i as usize]),
            hit.u,
            hit.v,
            &to_object.matrix3.inverse(),
        ),
        _ => SurfaceUv { uv: Vec2::ZERO, dpdu: Vec3::ZERO, dpdv: Vec3::ZERO },
    }
}

/// Texture coordinates at a hit on a box face ([`cuboid_hit`]'s face code in `hit.prim`).
#[inline]
pub(crate) fn cuboid_uv(
    to_object: &crate::math::Affine3A,
    min: Vec3,
    max: Vec3,
    hit: &Hit,
    point: Vec3,
) -> SurfaceUv {
    crate::geom::uv::cuboid(to_object, min, max, hit.prim, point)
}

/// Planar texture coordinates on a world-space triangle.
#[inline]
pub(crate) fn triangle_uv([a, b, c]: [Vec3; 3], point: Vec3, origin: glam::DVec3) -> SurfaceUv {
    crate::geom::uv::planar(crate::geom::triangle::normal(a, b, c), point, origin)
}

/// The surface at a hit on a mesh instance drawn with `material` (the first of its block when
/// the mesh has its file's materials).
#[inline(always)]
pub(crate) fn instance_surface<L: TriangleLayout>(
    mesh: &MeshEntry<L>,
    to_object: &crate::math::Affine3A,
    hit: &Hit,
    material: MaterialId,
) -> SurfacePoint {
    let s = mesh::instance_surface(mesh, to_object, hit);
    // A mesh with its file's materials: the triangle's own material in the instance's block.
    let material = mesh.face_material(material, hit.prim);
    SurfacePoint {
        point: s.point,
        normal: s.geometric,
        shading: s.shading,
        lift: s.lift,
        error: s.error,
        edge: Vec3::ZERO,
        material,
    }
}
