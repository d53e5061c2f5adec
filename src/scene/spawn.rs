//! Spawning a validated [`SceneDesc`] into a bevy_ecs World: resources for the tables and
//! settings, one entity per object and per light. Positions stay `f64`; the derived geometry
//! is placed relative to the camera (see [`crate::world`]).

use bevy_ecs::prelude::World;

use super::format::{LightDesc, MaterialDesc, SamplingDesc, SceneDesc, ShapeDesc};
use super::mesh::MeshLibrary;
use crate::accel::DEFAULT_LAMBDA;
use crate::geom;
use crate::math::Vec3;
use crate::sample::adaptive::AdaptiveSettings;
use crate::sample::warp::orthonormal_basis;
use crate::store::{MaterialId, PrimitiveStore};
use crate::trace::{self, AntiAliasing, Sampling};
use crate::world::components::{Light, MaterialRef, Name, Shape, Transform, Visible, WorldAabb, WorldShape};
use crate::world::resources::{CameraRig, Focus, FrameOrigin, Materials, MeshTable, SceneSettings};
use crate::world::SceneWorld;

/// A World holding the scene: the caller has validated `desc` (see `super::load`).
pub fn spawn_world<S: PrimitiveStore + 'static>(desc: &SceneDesc) -> SceneWorld<S> {
    let mut world = World::new();
    let materials = Materials {
        table: desc.materials.iter().map(MaterialDesc::material).collect(),
        names: desc.materials.iter().map(|m| m.name.clone()).collect(),
    };
    let c = &desc.camera;
    let focus = match (c.focus_distance, c.focus_on) {
        (Some(d), _) => Focus::Distance(d),
        (None, Some(p)) => Focus::Point(p),
        (None, None) => Focus::LookAt,
    };
    world.insert_resource(CameraRig {
        position: c.position,
        look_at: c.look_at,
        up: c.up,
        fov_y: c.fov_deg.to_radians(),
        aperture: c.aperture,
        focus,
    });
    let s = &desc.settings;
    world.insert_resource(SceneSettings {
        width: c.width,
        height: c.height,
        max_depth: s.max_depth,
        min_contribution: s.min_contribution,
        background: s.background,
        ambient: s.ambient,
        seed: s.seed,
        frame: 0,
        lambda: DEFAULT_LAMBDA,
        aa: AntiAliasing {
            sampling: Sampling { samples: s.aa.samples, pattern: s.aa.pattern },
            filter: s.aa.filter,
        },
        adaptive: s
            .adaptive
            .as_ref()
            .map(|a| AdaptiveSettings { threshold: a.threshold, max_depth: a.max_depth }),
        noise: s.noise.as_ref().map(|n| crate::sample::NoiseSettings {
            target_error: n.target_error,
            min_samples: n.min_samples,
            max_samples: n.max_samples,
            time_limit: n.time_limit.map(f64::from),
        }),
        lens: sampling(&c.lens),
        glossy: sampling(&s.glossy),
        max_secondary_rays: s.max_secondary_rays,
        // Validated on load: `0 <= open <= close <= 1`.
        shutter: c.shutter.and_then(|(open, close)| crate::camera::Shutter::new(open, close).ok()),
        time: sampling(&c.time),
    });

    for (i, object) in desc.objects.iter().enumerate() {
        let Some(shape) = shape_in(&object.shape, &desc.meshes) else {
            // Only a description that `load_scene` did not load can name an unloaded mesh.
            debug_assert!(false, "objects[{i}] names a mesh that was not loaded");
            continue;
        };
        let t = &object.transform;
        let transform = Transform::from_scene(t.translate, t.rotate_deg, t.scale);
        let placed = shape.place(&transform.to_affine(), c.position);
        let aabb = placed.bounds().unwrap_or(crate::math::Aabb::EMPTY);
        // Validation guarantees the material exists; an unknown name falls back to id 0.
        let material = materials.id(&object.material).unwrap_or(MaterialId(0));
        let name = object.name.clone().unwrap_or_else(|| format!("{}_{i}", object.shape.kind()));
        world.spawn((
            Name::new(name),
            Shape(shape),
            transform,
            MaterialRef(material),
            WorldShape(placed),
            WorldAabb(aabb),
            Visible(true),
        ));
    }
    for (i, light) in desc.lights.iter().enumerate() {
        world.spawn((Name::new(format!("light_{i}")), light_of(light), Visible(true)));
    }
    world.insert_resource(FrameOrigin(c.position));
    world.insert_resource(materials);
    world.insert_resource(MeshTable(desc.meshes.assets()));
    SceneWorld::new(world)
}

/// Engine geometry of a shape description, mesh ids taken from `meshes`; `None` for a mesh
/// the library has not loaded.
pub fn shape_in(desc: &ShapeDesc, meshes: &MeshLibrary) -> Option<geom::Shape> {
    match desc {
        ShapeDesc::Mesh { file, smooth } => {
            let (id, asset) = meshes.get(file, *smooth)?;
            Some(geom::Shape::Mesh { mesh: id, bounds: asset.data.bounds })
        }
        other => Some(shape_of(other)),
    }
}

/// Engine geometry of a shape description other than a mesh (which needs the mesh library:
/// see [`shape_in`]); a mesh gives an empty polygon.
fn shape_of(desc: &ShapeDesc) -> geom::Shape {
    match desc {
        ShapeDesc::Mesh { .. } => geom::Shape::Polygon { vertices: Vec::new() },
        // Positions stay f64: `geom::Shape::place` rounds them once, relative to the camera.
        ShapeDesc::Sphere { centre, radius } => geom::Shape::Sphere { centre: *centre, radius: *radius },
        ShapeDesc::Plane { point, normal } => geom::Shape::Plane { point: *point, normal: *normal },
        ShapeDesc::Triangle { vertices } => geom::Shape::Triangle { vertices: *vertices },
        ShapeDesc::Polygon { vertices } => geom::Shape::Polygon { vertices: vertices.clone() },
        ShapeDesc::Cuboid { min, max } => geom::Shape::Cuboid { min: *min, max: *max },
    }
}

fn sampling(desc: &SamplingDesc) -> Sampling {
    Sampling { samples: desc.samples, pattern: desc.pattern }
}

/// The World's light of a light description: radiance is colour × intensity, directions unit
/// length, and the position (point), corner (rectangle) or centre (disk) the light's `f64`
/// anchor.
pub fn light_of(desc: &LightDesc) -> Light {
    match *desc {
        LightDesc::Rect { corner, edge_u, edge_v, colour, intensity, samples, pattern } => {
            let source = trace::Light::Rect {
                corner: Vec3::ZERO,
                edge_u,
                edge_v,
                radiance: colour * intensity,
                samples,
                pattern,
            };
            Light::at(corner, source)
        }
        LightDesc::Disk { centre, normal, radius, colour, intensity, samples, pattern } => {
            let (axis_u, axis_v) = orthonormal_basis(normal.normalize());
            let source = trace::Light::Disk {
                centre: Vec3::ZERO,
                axis_u,
                axis_v,
                radius,
                radiance: colour * intensity,
                samples,
                pattern,
            };
            Light::at(centre, source)
        }
        LightDesc::Point { position, colour, intensity } => {
            Light::at(position, trace::Light::Point { position: Vec3::ZERO, radiance: colour * intensity })
        }
        LightDesc::Directional { direction, colour, intensity } => {
            let source =
                trace::Light::Directional { direction: direction.normalize(), radiance: colour * intensity };
            Light::at(glam::DVec3::ZERO, source)
        }
    }
}
