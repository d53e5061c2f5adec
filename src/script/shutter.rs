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

use bevy_ecs::prelude::{Entity, Resource, World};

use super::lent::{resolved_rig, FocusOn, ScriptMaterial};
use crate::world::components::{Light, LightTerms, MaterialRef, Motion, Transform, Visible};
use crate::world::resources::{CameraRig, Materials, SceneSettings, ShutterCamera, Textures};

/// The World's pose at shutter close: every named object's transform and the camera rig (its
/// focus resolved), from [`super::ScriptedWorld::evaluate_at`].
#[derive(Debug, Clone, PartialEq)]
pub struct ClosePose {
    /// Each object's transform at shutter close.
    pub transforms: Vec<(Entity, Transform)>,
    /// The camera at shutter close.
    pub rig: CameraRig,
}

impl ClosePose {
    /// The pose `world` is in now, for the objects among `entities`.
    pub fn of(world: &World, entities: &[Entity]) -> Self {
        let transforms = entities.iter().filter_map(|&e| Some((e, *world.get::<Transform>(e)?))).collect();
        Self { transforms, rig: resolved_rig(world) }
    }
}

/// The pose at shutter close for the next frame, taken by [`apply_shutter_pose`]; `None`: the
/// frame has no shutter (nothing moves).
#[derive(Resource, Default)]
pub struct ShutterPose(pub Option<ClosePose>);

/// The World's input system after the script's writes: sets or clears each object's
/// [`Motion`] and the [`ShutterCamera`] from the pose at shutter close ([`ShutterPose`],
/// consumed) against the World's pose, which is the pose at shutter open.
pub fn apply_shutter_pose(world: &mut World) {
    let Some(close) = world.get_resource_mut::<ShutterPose>().and_then(|mut p| p.0.take()) else {
        clear_motion(world);
        return;
    };
    for (entity, at_close) in close.transforms {
        let Some(at_open) = world.get::<Transform>(entity).copied() else { continue };
        let mut entity = world.entity_mut(entity);
        match at_open != at_close {
            true => {
                if entity.get::<Motion>().map(|m| m.close) != Some(at_close) {
                    entity.insert(Motion { close: at_close });
                }
            }
            false => {
                if entity.contains::<Motion>() {
                    entity.remove::<Motion>();
                }
            }
        }
    }
    // A camera the script never moved compares equal bit for bit.
    let camera = (close.rig != resolved_rig(world)).then_some(close.rig);
    let mut shutter_camera = world.resource_mut::<ShutterCamera>();
    if shutter_camera.0 != camera {
        shutter_camera.0 = camera;
    }
}

/// Everything a script can write, as it was before a call that is to be undone.
pub struct Saved {
    entities: Vec<SavedEntity>,
    rig: CameraRig,
    focus_on: Option<FocusOn>,
    settings: SceneSettings,
    materials: Materials,
    textures: Option<Textures>,
}

type SavedEntity = (
    Entity,
    Option<Transform>,
    Option<Visible>,
    Option<MaterialRef>,
    Option<ScriptMaterial>,
    Option<Light>,
    Option<LightTerms>,
);

impl Saved {
    /// What a script can write in `world`, for the named `entities`.
    pub fn of(world: &World, entities: &[Entity]) -> Self {
        let entities = entities
            .iter()
            .map(|&e| {
                (
                    e,
                    world.get::<Transform>(e).copied(),
                    world.get::<Visible>(e).copied(),
                    world.get::<MaterialRef>(e).copied(),
                    world.get::<ScriptMaterial>(e).copied(),
                    world.get::<Light>(e).copied(),
                    world.get::<LightTerms>(e).copied(),
                )
            })
            .collect();
        Self {
            entities,
            rig: *world.resource::<CameraRig>(),
            focus_on: world.get_resource::<FocusOn>().copied(),
            settings: *world.resource::<SceneSettings>(),
            materials: world.resource::<Materials>().clone(),
            textures: world.get_resource::<Textures>().cloned(),
        }
    }

    /// Puts it all back, leaving the change ticks as they are (the writes undone were made
    /// quietly, see [`super::lent::LentWorld::lend`]).
    pub fn restore(self, world: &mut World) {
        use bevy_ecs::prelude::DetectChangesMut;
        macro_rules! put {
            ($entity:expr, $value:expr, $t:ty) => {
                if let (Some(value), Some(mut c)) = ($value, world.get_mut::<$t>($entity)) {
                    *c.bypass_change_detection() = value;
                }
            };
        }
        for (e, transform, visible, material, script_material, light, terms) in self.entities {
            put!(e, transform, Transform);
            put!(e, visible, Visible);
            put!(e, material, MaterialRef);
            put!(e, script_material, ScriptMaterial);
            put!(e, light, Light);
            put!(e, terms, LightTerms);
        }
        *world.resource_mut::<CameraRig>().bypass_change_detection() = self.rig;
        if let (Some(focus), Some(mut r)) = (self.focus_on, world.get_resource_mut::<FocusOn>()) {
            *r.bypass_change_detection() = focus;
        }
        *world.resource_mut::<SceneSettings>().bypass_change_detection() = self.settings;
        *world.resource_mut::<Materials>().bypass_change_detection() = self.materials;
        if let (Some(textures), Some(mut r)) = (self.textures, world.get_resource_mut::<Textures>()) {
            *r.bypass_change_detection() = textures;
        }
    }
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
