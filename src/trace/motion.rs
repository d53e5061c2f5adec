//! Motion blur's part of a snapshot: the objects and the camera that move while the shutter is
//! open, and the visibility queries that see them at a ray's time.
//!
//! Time is a sample dimension: every camera sample carries a time `s` in `[0, 1]`, the fraction
//! of the shutter interval (0 at shutter open, 1 at close), and every ray of its path sees the
//! scene at that time. An object whose transform differs between shutter open and close is a
//! [`MovingObject`]: its object-space shape and its two poses. A ray at time `s` sees it placed
//! by the pose interpolated at `s` (translation and scale linearly, rotation by quaternion
//! slerp), through the same [`Shape::place`] and the same intersection routines as a static
//! object, so its hits keep the rounding-error bounds of the static path.
//!
//! Moving objects sit in their own small top-level grid, each by the bounds of its swept motion
//! ([`MovingObject::swept_bounds`]), walked beside the static grid; the static grid, the stores
//! and the mesh grids (object space) are untouched. Nothing here exists in a snapshot where
//! nothing moved ([`crate::trace::TraceScene::motion`] is `None`), so such frames pay nothing.

use std::sync::Arc;

use glam::{DAffine3, DVec3};

use crate::accel::{walk, GridBuilder, Tally, UniformGrid};
use crate::camera::Camera;
use crate::geom::{self, Placed, Shape};
use crate::math::{Aabb, Quat, Ray, Vec3};
use crate::store::{
    cuboid_hit, cuboid_surface, cuboid_uv, instance_surface, instance_uv, mesh, plane_surface,
    sphere_surface, triangle_surface, triangle_uv, Hit, MaterialId, MeshEntry, ObjectId, ObjectKind,
    SurfacePoint, TriangleLayout,
};

/// Segments the swept bounds of a rotating or rescaling object are sampled in.
const SWEEP_STEPS: u32 = 16;

/// A placement: scale, then rotate, then translate. Translations are `f64` and relative to the
/// snapshot's origin (the camera position at shutter open).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Translation.
    pub translation: DVec3,
    /// Rotation.
    pub rotation: Quat,
    /// Per-axis scale.
    pub scale: Vec3,
}

impl Pose {
    /// The pose a fraction `s` of the way from `self` to `to`: translation and scale linearly,
    /// rotation by slerp (the shorter way). Exactly `self` at `s <= 0` and `to` at `s >= 1`.
    pub fn lerp(&self, to: &Pose, s: f32) -> Pose {
        if s <= 0.0 {
            return *self;
        }
        if s >= 1.0 {
            return *to;
        }
        Pose {
            translation: self.translation.lerp(to.translation, f64::from(s)),
            rotation: self.rotation.slerp(to.rotation, s),
            scale: self.scale.lerp(to.scale, s),
        }
    }

    /// The object-to-frame map, in `f64`.
    pub fn to_affine(&self) -> DAffine3 {
        DAffine3::from_scale_rotation_translation(
            self.scale.as_dvec3(),
            self.rotation.as_dquat(),
            self.translation,
        )
    }
}

/// An object that moves while the shutter is open.
#[derive(Debug, Clone, PartialEq)]
pub struct MovingObject {
    /// Object-space geometry.
    pub shape: Shape,
    /// Pose at shutter open.
    pub open: Pose,
    /// Pose at shutter close.
    pub close: Pose,
    /// Material.
    pub material: MaterialId,
}

impl MovingObject {
    /// The pose at time `s` (fraction of the shutter interval).
    #[inline]
    pub fn pose_at(&self, s: f32) -> Pose {
        self.open.lerp(&self.close, s)
    }

    /// The geometry at time `s`, placed as a static object with that pose would be.
    #[inline]
    pub fn placed_at(&self, s: f32) -> Placed {
        self.shape.place(&self.pose_at(s).to_affine(), DVec3::ZERO)
    }

    /// Bounds of everything the object covers while the shutter is open; `None` for a plane.
    ///
    /// Under translation alone every point moves along a straight line, so the box around the
    /// open and close bounds holds the sweep. With rotation or scaling the motion is sampled at
    /// `SWEEP_STEPS` + 1 times and the box widened by how far a point may stray from the
    /// chord between two samples: its speed relative to the translation is at most
    /// `L = (θ · max scale + max scale change) · r` (θ the rotation angle, `r` the object-space
    /// distance of its farthest corner), and a path with speed `L` stays within `L · h` of the
    /// chord of a segment `h` long.
    pub fn swept_bounds(&self) -> Option<Aabb> {
        let (lo, hi) = self.shape.bounds()?;
        let turns = self.open.rotation != self.close.rotation;
        let rescales = self.open.scale != self.close.scale;
        let steps = if turns || rescales { SWEEP_STEPS } else { 1 };
        let mut swept = Aabb::EMPTY;
        for k in 0..=steps {
            let placed = self.placed_at(k as f32 / steps as f32);
            swept = swept.union(placed.bounds()?);
        }
        if steps > 1 {
            let r = lo.abs().max(hi.abs()).length() as f32;
            let angle = self.open.rotation.angle_between(self.close.rotation);
            let scale = self.open.scale.abs().max(self.close.scale.abs()).max_element();
            let rescale = (self.close.scale - self.open.scale).abs().max_element();
            let speed = (angle * scale + rescale) * r;
            // One part in a million more, for the rounding of the sampled placements.
            let size = swept.extent().max_element().max(swept.min.abs().max(swept.max.abs()).max_element());
            let pad = Vec3::splat(speed / steps as f32 + size * 1e-6);
            swept = Aabb::new(swept.min - pad, swept.max + pad);
        }
        Some(swept)
    }
}

/// A camera pose at one end of the shutter interval, in the snapshot's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPose {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub look_at: Vec3,
    /// Rough up direction.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Lens radius.
    pub aperture: f32,
    /// Distance of the plane in focus along the view direction.
    pub focus_distance: f32,
}

/// A camera that moves (or zooms, or pulls focus) while the shutter is open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraMotion {
    /// Pose at shutter open.
    pub open: CameraPose,
    /// Pose at shutter close.
    pub close: CameraPose,
}

impl CameraMotion {
    /// The camera at time `s`: every field interpolated linearly. Where the interpolated pose
    /// is degenerate (the eye on the point looked at, or looking along `up`), the nearer end's
    /// camera is used.
    pub fn at(&self, s: f32) -> Camera {
        let (a, b) = (&self.open, &self.close);
        let mix = |x: f32, y: f32| x + (y - x) * s;
        let camera = |p: &CameraPose| {
            Camera::look_at(p.position, p.look_at, p.up, p.fov_y).with_lens(p.aperture, p.focus_distance)
        };
        let pose = CameraPose {
            position: a.position.lerp(b.position, s),
            look_at: a.look_at.lerp(b.look_at, s),
            up: a.up.lerp(b.up, s),
            fov_y: mix(a.fov_y, b.fov_y),
            aperture: mix(a.aperture, b.aperture),
            focus_distance: mix(a.focus_distance, b.focus_distance),
        };
        let c = camera(&pose);
        if c.forward.is_finite() && c.right.is_finite() && c.up.is_finite() {
            c
        } else if s < 0.5 {
            camera(a)
        } else {
            camera(b)
        }
    }
}

/// What moves in a frame: objects (bounded ones first, then planes) in a grid of their swept
/// bounds, and the camera.
#[derive(Debug, Clone)]
pub struct SceneMotion {
    objects: Vec<MovingObject>,
    /// Objects `0..bounded` have bounds and are in `grid`; the rest are planes.
    bounded: u32,
    grid: UniformGrid,
    /// The camera's motion, if it moves.
    pub camera: Option<CameraMotion>,
    /// Scene names of the objects, in object order (empty when not built from a World).
    pub names: Vec<String>,
}

impl SceneMotion {
    /// The motion of `objects` (any order: bounded ones are put first, keeping their order)
    /// and of the camera, with a grid of density `lambda` over the swept bounds.
    pub fn new(objects: Vec<(MovingObject, String)>, camera: Option<CameraMotion>, lambda: f32) -> Self {
        let (bounded, planes): (Vec<_>, Vec<_>) =
            objects.into_iter().partition(|(o, _)| o.shape.bounds().is_some());
        let bounds: Vec<Aabb> = bounded.iter().filter_map(|(o, _)| o.swept_bounds()).collect();
        let grid = GridBuilder::new(lambda).build(&bounds, |id, cell| bounds[id as usize].overlaps(cell));
        let count = bounded.len() as u32;
        let (objects, names) = bounded.into_iter().chain(planes).unzip();
        Self { objects, bounded: count, grid, camera, names }
    }

    /// True when nothing moves.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty() && self.camera.is_none()
    }

    /// The moving objects, bounded ones first.
    pub fn objects(&self) -> &[MovingObject] {
        &self.objects
    }

    /// The moving object of a hit on one.
    #[inline]
    fn object(&self, hit: &Hit) -> &MovingObject {
        match hit.object.kind() {
            ObjectKind::Moving(i) => &self.objects[i as usize],
            _ => unreachable!("the hit is on a moving object"),
        }
    }

    /// Material of a hit on a moving object.
    pub fn material<L: TriangleLayout>(&self, meshes: &[Arc<MeshEntry<L>>], hit: &Hit) -> MaterialId {
        let o = self.object(hit);
        match &o.shape {
            Shape::Mesh { mesh, .. } => meshes[mesh.0 as usize].face_material(o.material, hit.prim),
            _ => o.material,
        }
    }

    /// Nearest hit with a moving object at time `s` in `(t_min, t_max)`: the planes, then the
    /// grid of swept bounds front to back.
    pub fn nearest<L: TriangleLayout, T: Tally>(
        &self,
        meshes: &[Arc<MeshEntry<L>>],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        s: f32,
        tally: &mut T,
    ) -> Option<Hit> {
        let planes = self.bounded..self.objects.len() as u32;
        let best = self.nearest_among(planes, meshes, ray, t_min, t_max, s, tally);
        let bound = best.map_or(t_max, |h| h.t);
        let found = walk::nearest(&self.grid, ray, t_min, bound, tally, |i, bound, tally| {
            self.intersect(meshes, i, ray, t_min, bound, s, tally).map(|h| (h.t, h))
        });
        found.or(best)
    }

    /// [`Self::nearest`] by testing every moving object: the reference the grid is checked
    /// against in this module's tests.
    #[cfg(test)]
    fn nearest_brute<L: TriangleLayout>(
        &self,
        meshes: &[Arc<MeshEntry<L>>],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        s: f32,
    ) -> Option<Hit> {
        let all = 0..self.objects.len() as u32;
        self.nearest_among(all, meshes, ray, t_min, t_max, s, &mut crate::store::NoTally)
    }

    /// Nearest hit among moving objects `ids` at time `s`, each tested in turn below the
    /// nearest so far (the first of equally near ones).
    #[allow(clippy::too_many_arguments)]
    fn nearest_among<L: TriangleLayout, T: Tally>(
        &self,
        ids: std::ops::Range<u32>,
        meshes: &[Arc<MeshEntry<L>>],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        s: f32,
        tally: &mut T,
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for i in ids {
            tally.tests(1);
            let bound = best.map_or(t_max, |h| h.t);
            if let Some(h) = self.intersect(meshes, i, ray, t_min, bound, s, tally) {
                best = Some(h);
            }
        }
        best
    }

    /// The moving objects' part of a shadow ray's transmittance at time `s` over `(0, t_max)`:
    /// each object's `kt` once per crossing, objects in ascending index (0 as soon as one
    /// blocks; with `opaque`, any crossing blocks). `kt` maps a material to its transmittance.
    #[allow(clippy::too_many_arguments)]
    pub fn transmittance<L: TriangleLayout, T: Tally>(
        &self,
        meshes: &[Arc<MeshEntry<L>>],
        ray: &Ray,
        t_max: f32,
        s: f32,
        opaque: bool,
        kt: impl Fn(MaterialId) -> Vec3,
        tally: &mut T,
    ) -> Vec3 {
        let share = |i: u32, tally: &mut T| {
            let mut share = Vec3::ONE;
            let mut t_lo = 0.0;
            while let Some(h) = self.intersect(meshes, i, ray, t_lo, t_max, s, tally) {
                share *= if opaque { Vec3::ZERO } else { kt(self.objects[i as usize].material) };
                if share == Vec3::ZERO {
                    return Vec3::ZERO;
                }
                t_lo = h.t;
            }
            share
        };
        // The objects a ray crosses, found by walking the grid, each counted once.
        let mut crossed: Vec<u32> = (self.bounded..self.objects.len() as u32).collect();
        let mut seen = Vec::new();
        walk::any(&self.grid, ray, 0.0, t_max, tally, |i, _| {
            if !seen.contains(&i) {
                seen.push(i);
            }
            false
        });
        crossed.extend(seen);
        crossed.sort_unstable();
        let mut pass = Vec3::ONE;
        for i in crossed {
            pass *= share(i, tally);
            if pass == Vec3::ZERO {
                return Vec3::ZERO;
            }
        }
        pass
    }

    /// Hit of moving object `i` at time `s` in `(t_min, t_max)`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn intersect<L: TriangleLayout, T: Tally>(
        &self,
        meshes: &[Arc<MeshEntry<L>>],
        i: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        s: f32,
        tally: &mut T,
    ) -> Option<Hit> {
        let object = ObjectId::moving(i);
        match self.objects[i as usize].placed_at(s) {
            Placed::Sphere { centre, radius } => {
                tally.tests(1);
                geom::sphere::intersect(centre, radius, ray, t_min, t_max).map(|t| Hit::new(t, object, 0))
            }
            Placed::Plane { normal, offset } => {
                geom::plane::intersect(normal, offset, ray, t_min, t_max).map(|t| Hit::new(t, object, 0))
            }
            Placed::Triangles(tris) => {
                tally.tests(tris.len() as u32);
                let wray = geom::triangle::WatertightRay::new(ray);
                let mut best = None;
                let mut bound = t_max;
                for (k, [a, b, c]) in tris.iter().enumerate() {
                    if let Some(h) = geom::triangle::intersect(*a, *b, *c, &wray, t_min, bound) {
                        bound = h.t;
                        best = Some(Hit::triangle(object, k as u32, &h));
                    }
                }
                best
            }
            Placed::Cuboid { to_object, min, max, .. } => {
                tally.tests(1);
                cuboid_hit(&to_object, min, max, object, ray, t_min, t_max)
            }
            Placed::Instance { mesh: id, to_object, .. } => {
                let entry = &meshes[id.0 as usize];
                mesh::instance_hit(entry, &to_object, object, ray, t_min, t_max, tally)
            }
        }
    }

    /// Texture coordinates at a hit on a moving object by a ray at time `s`, whose surface
    /// point is `point` ([`crate::store::PrimitiveStore::uv`]).
    pub fn uv<L: TriangleLayout>(
        &self,
        meshes: &[Arc<MeshEntry<L>>],
        hit: &Hit,
        point: Vec3,
        s: f32,
        origin: DVec3,
    ) -> crate::geom::uv::SurfaceUv {
        use crate::geom::uv;
        match self.object(hit).placed_at(s) {
            Placed::Sphere { centre, .. } => uv::sphere(centre, point),
            Placed::Plane { normal, .. } => uv::planar(normal, point, origin),
            Placed::Triangles(tris) => triangle_uv(tris[hit.prim as usize], point, origin),
            Placed::Cuboid { to_object, min, max, .. } => cuboid_uv(&to_object, min, max, hit, point),
            Placed::Instance { mesh: id, to_object, .. } => {
                instance_uv(&meshes[id.0 as usize], &to_object, hit)
            }
        }
    }

    /// Position, normals and material at a hit on a moving object by a ray at time `s`.
    pub fn surface<L: TriangleLayout>(
        &self,
        meshes: &[Arc<MeshEntry<L>>],
        hit: &Hit,
        ray: &Ray,
        s: f32,
    ) -> SurfacePoint {
        let o = self.object(hit);
        let material = o.material;
        match o.placed_at(s) {
            Placed::Sphere { centre, radius } => sphere_surface(centre, radius, hit, ray, material),
            Placed::Plane { normal, offset } => plane_surface(normal, offset, hit, ray, material),
            Placed::Triangles(tris) => triangle_surface(tris[hit.prim as usize], hit, material),
            Placed::Cuboid { to_object, min, max, .. } => {
                cuboid_surface(&to_object, min, max, hit, ray, material)
            }
            Placed::Instance { mesh: id, to_object, .. } => {
                instance_surface(&meshes[id.0 as usize], &to_object, hit, material)
            }
        }
    }
}

#[cfg(test)]
mod tests;
