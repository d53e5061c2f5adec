//! Motion blur from a script: the World is evaluated at both ends of the shutter interval.
//!
//! With a shutter `(open, close)`, frame `n`'s World is the script's `frame(t)` at
//! `t = (n + open) / fps`, as every frame of the timeline is (so a frame is the same whether a
//! range starts at it or before it). Its pose at shutter close comes from a second call,
//! `frame((n + close) / fps)`, made from the same state as the first and then undone
//! ([`super::ScriptedWorld::evaluate_at`]): the timeline never sees it. [`apply_shutter_pose`]
//! compares the two: every object whose transform differs gets a [`Motion`] with its pose at
//! close, and a camera whose pose differs gets a [`ShutterCamera`]. Writes a script makes
//! relative to the previous frame (`x += 1`) move an object once per call; for motion blur,
//! write poses as functions of `t`. Lights, visibility, materials and texture transforms are
//! those at shutter open.

use bevy_ecs::prelude::{Resource, World};

use super::state::{rotation_from_degrees, EntityKind, EntityState, ScriptState, SharedState};
use crate::world::components::{Motion, Transform};
use crate::world::resources::{CameraRig, ShutterCamera};

/// The script's state at shutter close for the next frame, taken by [`apply_shutter_pose`];
/// `None`: the frame has no shutter (nothing moves).
#[derive(Resource, Default)]
pub struct ShutterPose(pub Option<ScriptState>);

/// The World's input system after the script's writes: sets or clears each object's
/// [`Motion`] and the [`ShutterCamera`] from the state at shutter close ([`ShutterPose`],
/// consumed) against the state at shutter open (the script's current state, just applied).
pub fn apply_shutter_pose(world: &mut World) {
    let close = world.get_resource_mut::<ShutterPose>().and_then(|mut p| p.0.take());
    let open = world.get_resource::<SharedState>().map(|s| s.lock().clone());
    let (Some(close), Some(open)) = (close, open) else {
        clear_motion(world);
        return;
    };
    for (was, now) in open.entities.iter().zip(&close.entities) {
        debug_assert_eq!(was.entity, now.entity, "the mirror's entities keep their order");
        if !matches!(now.kind, EntityKind::Object { .. }) {
            continue;
        }
        let Some(at_open) = world.get::<Transform>(now.entity).copied() else { continue };
        let moved = pose_differs(was, now);
        let mut entity = world.entity_mut(now.entity);
        match moved {
            true => {
                let rotation = match now.rotation_written {
                    true => rotation_from_degrees(now.rotation_deg),
                    false => at_open.rotation,
                };
                let close = Transform { translation: now.position, rotation, scale: now.scale.as_vec3() };
                if entity.get::<Motion>().map(|m| m.close) != Some(close) {
                    entity.insert(Motion { close });
                }
            }
            false => {
                if entity.contains::<Motion>() {
                    entity.remove::<Motion>();
                }
            }
        }
    }
    // Both rigs from the mirror, so a camera the script never moved compares equal bit for bit.
    let (rig_open, rig_close): (CameraRig, CameraRig) = (open.rig(), close.rig());
    let camera = (rig_close != rig_open).then_some(rig_close);
    let mut shutter_camera = world.resource_mut::<ShutterCamera>();
    if shutter_camera.0 != camera {
        shutter_camera.0 = camera;
    }
}

/// True when an object's authored pose differs between two states of the mirror.
fn pose_differs(open: &EntityState, close: &EntityState) -> bool {
    let rotation = |e: &EntityState| e.rotation_written.then_some(e.rotation_deg);
    open.position != close.position || open.scale != close.scale || rotation(open) != rotation(close)
}

/// Removes every [`Motion`] and the [`ShutterCamera`]: a frame without a shutter.
fn clear_motion(world: &mut World) {
    let moving: Vec<_> = world
        .query_filtered::<bevy_ecs::prelude::Entity, bevy_ecs::prelude::With<Motion>>()
        .iter(world)
        .collect();
    for e in moving {
        world.entity_mut(e).remove::<Motion>();
    }
    if let Some(mut camera) = world.get_resource_mut::<ShutterCamera>() {
        if camera.0.is_some() {
            camera.0 = None;
        }
    }
}
