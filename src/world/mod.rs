//! The authoring side of the engine: a bevy_ecs World of scene entities, the systems that keep
//! derived data current, and the per-frame schedule that ends in an immutable snapshot.
//!
//! Entities carry [`components::Shape`], [`components::Transform`], [`components::MaterialRef`]
//! and [`components::Name`] (objects) or [`components::Light`] and a name (lights). Each
//! [`SceneWorld::update`] runs [`schedule::FrameSystems`] in order: `update_bounds` for entities
//! whose shape or transform changed, `rebuild_grid` only when bounded geometry changed or an
//! entity was removed, and `build_snapshot`, which flattens everything into a
//! [`crate::trace::TraceScene`]. Only this module and `scene::spawn` import bevy_ecs.
//!
//! **Coordinates.** Authored positions are `f64`: transforms' translations, shapes' positions,
//! lights' anchors and the camera rig. Each frame is derived relative to the camera position
//! ([`resources::FrameOrigin`]): positions are computed in `f64`, the camera position is
//! subtracted, and only then are they rounded to the `f32` the tracer uses, so a scene a
//! million units from the origin renders like the same scene at the origin, and a camera
//! moving by less than `f32`'s step out there still moves. The snapshot's camera sits at
//! `Vec3::ZERO`. A frame where nothing moved, the camera included, reuses the grid; a frame
//! where the camera moved derives every entity's geometry again and rebuilds the top-level
//! grid (mesh grids are in object space and are never rebuilt). Every derived value is a
//! function of the frame's authored state alone, never of earlier frames.
//!
//! ```
//! # use penumbra::{scene, world::{SceneWorld, components::Transform}};
//! # use glam::DVec3;
//! let mut world: SceneWorld = scene::spawn_world(&scene::default_scene());
//! let first = world.update();
//! assert_eq!(world.grid_rebuilds(), 1);
//! world.update(); // nothing moved: the grid is reused
//! assert_eq!(world.grid_rebuilds(), 1);
//! let ball = world.entity("red_ball").unwrap();
//! world.world_mut().get_mut::<Transform>(ball).unwrap().translation += DVec3::X;
//! world.update();
//! assert_eq!(world.grid_rebuilds(), 2);
//! world.world_mut().resource_mut::<penumbra::world::resources::CameraRig>().position.x += 0.5;
//! world.update(); // the camera moved: the snapshot's origin moved with it
//! assert_eq!(world.grid_rebuilds(), 3);
//! # let _ = first;
//! ```

pub mod components;
pub mod resources;
pub mod schedule;
pub mod systems;

use std::marker::PhantomData;
use std::sync::Arc;

use bevy_ecs::prelude::{Entity, Schedule, World};

use crate::store::{PrimitiveStore, SoaStore};
use crate::trace::{RenderSettings, TraceScene};
use components::Name;
use resources::{GridRebuilds, SceneSettings, Snapshot, StageClock};

/// A scene World with its frame schedule, producing snapshots of layout `S`.
pub struct SceneWorld<S: PrimitiveStore + 'static = SoaStore> {
    world: World,
    schedule: Schedule,
    layout: PhantomData<S>,
}

impl<S: PrimitiveStore + 'static> SceneWorld<S> {
    /// Wraps a World that holds a spawned scene (see `scene::spawn_world`).
    pub fn new(mut world: World) -> Self {
        world.init_resource::<Snapshot<S>>();
        world.init_resource::<GridRebuilds>();
        world.init_resource::<StageClock>();
        world.init_resource::<resources::GridIndex>();
        world.init_resource::<resources::MeshTable>();
        world.init_resource::<resources::MeshLayouts<S>>();
        world.init_resource::<resources::FrameOrigin>();
        world.init_resource::<resources::ShutterCamera>();
        Self { world, schedule: schedule::build_schedule::<S>(), layout: PhantomData }
    }

    /// Runs one frame of the schedule and returns its snapshot.
    pub fn update(&mut self) -> Arc<TraceScene<S>> {
        self.schedule.run(&mut self.world);
        // `build_snapshot` runs unconditionally every frame, so the snapshot is present.
        self.world.resource::<Snapshot<S>>().0.clone().expect("build_snapshot runs every frame")
    }

    /// Adds a system that runs at the start of every frame, before bounds are derived
    /// ([`schedule::FrameSystems::Input`]): the place for drivers such as scripts to write
    /// into components.
    pub fn add_input_system<M>(
        &mut self,
        system: impl bevy_ecs::schedule::IntoScheduleConfigs<bevy_ecs::system::ScheduleSystem, M>,
    ) {
        self.schedule.add_systems(system.in_set(schedule::FrameSystems::Input));
    }

    /// The World, for reading components and resources.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The World, for changing the scene between frames.
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// The entity named `name` (objects and lights), if any.
    pub fn entity(&mut self, name: &str) -> Option<Entity> {
        let mut names = self.world.query::<(Entity, &Name)>();
        names.iter(&self.world).find(|(_, n)| n.as_str() == name).map(|(e, _)| e)
    }

    /// How many times the grid has been built.
    pub fn grid_rebuilds(&self) -> u64 {
        self.world.resource::<GridRebuilds>().0
    }

    /// Seconds spent in each stage during the last frame.
    pub fn stage_clock(&self) -> StageClock {
        *self.world.resource::<StageClock>()
    }

    /// The render settings the World's [`SceneSettings`] describe.
    pub fn render_settings(&self) -> RenderSettings {
        self.world.resource::<SceneSettings>().render
    }

    /// The World's settings, to change between frames (image size, depth, seed, frame number).
    pub fn settings_mut(&mut self) -> bevy_ecs::world::Mut<'_, SceneSettings> {
        self.world.resource_mut::<SceneSettings>()
    }
}
