//! `build_snapshot`: flattens the World into an immutable [`TraceScene`], in coordinates whose
//! origin is the camera ([`FrameOrigin`]): the camera sits at `Vec3::ZERO`, geometry and lights
//! are placed relative to it in `f64` and rounded once to `f32`.

use std::sync::Arc;
use std::time::Instant;

use bevy_ecs::prelude::{Entity, Has, Query, Res, ResMut};
use glam::DVec3;

use crate::store::{MeshEntry, PlacedObject, PrimitiveStore};
use crate::trace::{CameraMotion, CameraPose, MovingObject, Pose, SceneMotion, SceneTables, TraceScene};
use crate::world::components::{
    Light, MaterialRef, Motion, Name, Shape, Transform, Visible, WorldAabb, WorldShape,
};
use crate::world::resources::{
    CameraRig, FrameOrigin, GridIndex, Materials, MeshLayouts, MeshTable, SceneSettings, ShutterCamera,
    Snapshot, StageClock, Textures,
};
use crate::world::systems::grid::is_visible;

/// What the snapshot reads of each object.
type ObjectParts = (
    Entity,
    &'static WorldShape,
    &'static WorldAabb,
    &'static MaterialRef,
    Option<&'static Name>,
    Option<&'static Visible>,
    Has<Motion>,
);

/// What the snapshot reads of each object that moves while the shutter is open.
type MovingParts = (
    Entity,
    &'static Shape,
    &'static Transform,
    &'static Motion,
    &'static MaterialRef,
    Option<&'static Name>,
    Option<&'static Visible>,
);

/// Builds this frame's snapshot: bounded objects in grid order, visible planes and lights in
/// entity order, and the material table, camera and settings; everything relative to the
/// camera position, the origin `update_bounds` derived the geometry for.
#[allow(clippy::too_many_arguments)]
pub fn build_snapshot<S: PrimitiveStore + 'static>(
    objects: Query<ObjectParts>,
    moving: Query<MovingParts>,
    shutter_camera: Res<ShutterCamera>,
    lights: Query<(Entity, &Light, Option<&Visible>)>,
    index: Res<GridIndex>,
    materials: Res<Materials>,
    textures: Option<Res<Textures>>,
    rig: Res<CameraRig>,
    origin: Res<FrameOrigin>,
    settings: Res<SceneSettings>,
    meshes: Res<MeshTable>,
    mut layouts: ResMut<MeshLayouts<S>>,
    mut snapshot: ResMut<Snapshot<S>>,
    mut clock: ResMut<StageClock>,
) {
    let started = Instant::now();
    debug_assert_eq!(origin.0, rig.position, "update_bounds moves the origin to the camera");
    // Lay out mesh assets added since the last frame (normally all of them, once).
    let have = layouts.0.len();
    layouts.0.extend(meshes.0[have..].iter().map(|m| Arc::new(MeshEntry::new(m.clone()))));
    let placed = |shape: &WorldShape, material: &MaterialRef| PlacedObject {
        geometry: shape.0.clone(),
        material: material.0,
    };
    // The grid index lists exactly the bounded entities, so `get` cannot fail for them.
    let bounded: Vec<PlacedObject> = index
        .entities
        .iter()
        .filter_map(|&e| objects.get(e).ok())
        .map(|(_, shape, _, material, ..)| placed(shape, material))
        .collect();
    debug_assert_eq!(bounded.len(), index.entities.len(), "grid index out of date");

    let mut planes: Vec<_> = objects
        .iter()
        .filter(|(_, _, aabb, _, _, visible, moves)| !aabb.is_bounded() && is_visible(*visible) && !moves)
        .collect();
    planes.sort_unstable_by_key(|(e, ..)| *e);
    let unbounded: Vec<PlacedObject> =
        planes.iter().map(|(_, shape, _, material, ..)| placed(shape, material)).collect();
    let name = |name: Option<&Name>| name.map_or_else(String::new, |n| n.as_str().to_owned());
    let object_names: Vec<String> = index
        .entities
        .iter()
        .filter_map(|&e| objects.get(e).ok())
        .map(|(.., n, _, _)| name(n))
        .chain(planes.iter().map(|(.., n, _, _)| name(*n)))
        .collect();

    let mut lights: Vec<_> = lights.iter().filter(|(.., visible)| is_visible(*visible)).collect();
    lights.sort_unstable_by_key(|(e, ..)| *e);

    let tables = SceneTables {
        materials: materials.table.clone(),
        lights: lights.iter().map(|(_, l, _)| l.relative_to(origin.0)).collect(),
        camera: rig.camera(),
        background: settings.background,
        ambient: settings.ambient,
    };
    let mut scene = TraceScene::with_grid(index.grid.clone(), &bounded, &unbounded, &layouts.0, tables);
    scene.object_names = object_names;
    if let Some(textures) = textures {
        scene = scene.with_textures(textures.table.clone(), origin.0);
    }
    let motion = scene_motion(&moving, &rig, shutter_camera.0.as_ref(), origin.0, settings.lambda);
    if let Some(motion) = motion {
        scene.object_names.extend(motion.names.iter().cloned());
        scene = scene.with_motion(motion);
    }
    snapshot.0 = Some(Arc::new(scene));
    clock.snapshot = started.elapsed().as_secs_f64();
}

/// What moves while the shutter is open, relative to `origin` (the camera at shutter open):
/// the visible objects with a [`Motion`] in entity order, and the camera when its pose at
/// close differs. `None` when nothing moves.
fn scene_motion(
    moving: &Query<MovingParts>,
    rig: &CameraRig,
    close_rig: Option<&CameraRig>,
    origin: DVec3,
    lambda: f32,
) -> Option<SceneMotion> {
    let mut movers: Vec<_> = moving.iter().filter(|(.., visible)| is_visible(*visible)).collect();
    movers.sort_unstable_by_key(|(e, ..)| *e);
    let pose =
        |t: &Transform| Pose { translation: t.translation - origin, rotation: t.rotation, scale: t.scale };
    let objects: Vec<(MovingObject, String)> = movers
        .iter()
        .map(|(_, shape, open, motion, material, name, _)| {
            let object = MovingObject {
                shape: shape.0.clone(),
                open: pose(open),
                close: pose(&motion.close),
                material: material.0,
            };
            (object, name.map_or_else(String::new, |n| n.as_str().to_owned()))
        })
        .collect();
    let camera = close_rig
        .filter(|close| *close != rig)
        .map(|close| CameraMotion { open: camera_pose(rig, origin), close: camera_pose(close, origin) });
    (!objects.is_empty() || camera.is_some()).then(|| SceneMotion::new(objects, camera, lambda))
}

/// A camera rig's pose relative to `origin`, its focus resolved against that pose.
fn camera_pose(rig: &CameraRig, origin: DVec3) -> CameraPose {
    let camera = rig.camera();
    CameraPose {
        position: (rig.position - origin).as_vec3(),
        look_at: (rig.look_at - origin).as_vec3(),
        up: rig.up,
        fov_y: rig.fov_y,
        aperture: rig.aperture,
        focus_distance: camera.focus_distance,
    }
}
