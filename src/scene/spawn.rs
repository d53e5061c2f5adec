//! Spawning a validated [`SceneDesc`] into a bevy_ecs World: resources for the tables and
//! settings, one entity per object and per light. Positions stay `f64`; the derived geometry
//! is placed relative to the camera (see [`crate::world`]).

use bevy_ecs::prelude::World;

use super::desc::SceneDesc;
use super::format::{LightDesc, ShapeDesc};
use super::mesh::MeshLibrary;
use crate::accel::DEFAULT_LAMBDA;
use crate::geom;
use crate::math::Vec3;
use crate::sample::warp::orthonormal_basis;
use crate::store::{MaterialId, PrimitiveStore};
use crate::trace;
use crate::world::components::{
    Light, LightTerms, MaterialRef, Name, Shape, Transform, Visible, WorldAabb, WorldShape,
};
use crate::world::resources::{CameraRig, Focus, FrameOrigin, Materials, MeshTable, SceneSettings, Textures};
use crate::world::SceneWorld;

/// A World holding the scene: the caller has validated `desc` (see `super::load`).
pub fn spawn_world<S: PrimitiveStore + 'static>(desc: &SceneDesc) -> SceneWorld<S> {
    let mut world = World::new();
    let mut materials = Materials {
        table: desc.materials.iter().map(|m| m.material(&desc.textures)).collect(),
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
        render: desc.file.render_settings(),
        background: s.background,
        ambient: s.ambient,
        lambda: DEFAULT_LAMBDA,
    });

    let mut blocks = super::mesh_materials::MaterialBlocks::default();
    for (i, object) in desc.objects.iter().enumerate() {
        let Some(shape) = shape_in(&object.shape, &desc.assets.meshes) else {
            // Only a description that `load_scene` did not load can name an unloaded mesh.
            debug_assert!(false, "objects[{i}] names a mesh that was not loaded");
            continue;
        };
        let t = &object.transform;
        let transform = Transform::from_scene(t.translate, t.rotate_deg, t.scale);
        let placed = shape.place(&transform.to_affine(), c.position);
        let aabb = placed.bounds().unwrap_or(crate::math::Aabb::EMPTY);
        // Validation guarantees the material exists; an unknown name falls back to id 0.
        let material = match (&shape, object.shape.mesh_key()) {
            // Faces drawn with the file's materials: the object's block of the table.
            (geom::Shape::Mesh { mesh, .. }, Some((file, _, true))) => blocks.block(
                *mesh,
                file,
                &desc.assets.meshes.assets()[mesh.0 as usize].data.materials,
                &object.material,
                &desc.file,
                &desc.assets.library_textures,
                &mut materials.table,
                &mut materials.names,
            ),
            _ => materials.id(&object.material).unwrap_or(MaterialId(0)),
        };
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
        let (colour, intensity) = light.terms();
        let terms = LightTerms { colour, intensity };
        world.spawn((Name::new(format!("light_{i}")), light_of(light), terms, Visible(true)));
    }
    world.insert_resource(FrameOrigin(c.position));
    world.insert_resource(materials);
    world.insert_resource(Textures {
        table: desc.assets.texture_table.clone(),
        names: desc.textures.iter().map(|t| t.name.clone()).collect(),
    });
    world.insert_resource(MeshTable(desc.assets.meshes.assets()));
    SceneWorld::new(world)
}

/// Engine geometry of a shape description, mesh ids taken from `meshes`; `None` for a mesh
/// the library has not loaded.
pub fn shape_in(desc: &ShapeDesc, meshes: &MeshLibrary) -> Option<geom::Shape> {
    match desc {
        ShapeDesc::Mesh { .. } => {
            let (id, asset) = meshes.get_key(desc.mesh_key()?)?;
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

/// The World's light of a light description: radiance is colour × intensity, directions unit
/// length, and the position (point), corner (rectangle) or centre (disk) the light's `f64`
/// anchor.
pub fn light_of(desc: &LightDesc) -> Light {
    match *desc {
        LightDesc::Rect { corner, edge_u, edge_v, colour, intensity, samples, pattern, falloff, visible } => {
            let source = trace::Light::Rect {
                corner: Vec3::ZERO,
                edge_u,
                edge_v,
                radiance: colour * intensity,
                samples,
                pattern,
                falloff,
                visible,
            };
            Light::at(corner, source)
        }
        LightDesc::Disk { centre, normal, radius, colour, intensity, samples, pattern, falloff, visible } => {
            let (axis_u, axis_v) = orthonormal_basis(normal.normalize());
            let source = trace::Light::Disk {
                centre: Vec3::ZERO,
                axis_u,
                axis_v,
                radius,
                radiance: colour * intensity,
                samples,
                pattern,
                falloff,
                visible,
            };
            Light::at(centre, source)
        }
        LightDesc::Point { position, colour, intensity, falloff } => Light::at(
            position,
            trace::Light::Point { position: Vec3::ZERO, radiance: colour * intensity, falloff },
        ),
        LightDesc::Spot { position, look_at, cone_deg, soft_deg, colour, intensity, falloff } => {
            let soft = soft_deg.unwrap_or(DEFAULT_SPOT_SOFT_DEG.min(cone_deg));
            let source = trace::Light::Spot {
                position: Vec3::ZERO,
                direction: (look_at - position).normalize().as_vec3(),
                cos_inner: (cone_deg - soft).to_radians().cos(),
                cos_outer: cone_deg.to_radians().cos(),
                radiance: colour * intensity,
                falloff,
            };
            Light::at(position, source)
        }
        LightDesc::Directional { direction, colour, intensity } => {
            let source =
                trace::Light::Directional { direction: direction.normalize(), radiance: colour * intensity };
            Light::at(glam::DVec3::ZERO, source)
        }
    }
}

/// Width of a spot light's soft edge when the scene gives none (at most the cone's half-angle).
pub const DEFAULT_SPOT_SOFT_DEG: f32 = 5.0;
