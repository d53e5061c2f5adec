//! The World lent to a script for the length of a call: the API reads the World's own
//! components and resources and writes them in place, through the same rules as the scene
//! file ([`crate::scene::fields`]). There is no copy of the scene on the script's side.
//!
//! [`super::ScriptedWorld`] moves its World into a [`LentWorld`] before each call into the
//! script and takes it back after ([`LentWorld::lend`]); API functions reach it through
//! [`LentWorld::get`] and [`Lent::scene`]. A write changes a component only when the value
//! differs (so an entity the script did not touch, or set to the value it already had,
//! triggers no change detection and no grid rebuild), and reads give back what the World
//! holds: positions in `f64`, the rest in the tracer's `f32`, rotations as the angles of the
//! stored quaternion.
//!
//! What scripts can write that the tracer does not keep apart lives in components of its own:
//! a light's colour and intensity ([`LightTerms`], whose product is the radiance) and an
//! object's own material ([`ScriptMaterial`]: the copy a script's first material write makes,
//! so that other objects sharing the scene material keep theirs).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use bevy_ecs::component::Mutable;
use bevy_ecs::prelude::{Component, DetectChangesMut, Entity, Resource, World};
use glam::{DVec3, EulerRot, Quat, Vec3};

use super::api::convert::{error, ScriptResult};
use crate::geom;
use crate::store::MaterialId;
use crate::trace::{self, Material};
use crate::world::components::{Light, LightTerms, MaterialRef, Name, Shape, Transform};
use crate::world::resources::{CameraRig, Focus, MeshTable};

/// The frame being made: its number, time in seconds and the frame rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    /// Frame number.
    pub frame: u32,
    /// Seconds since frame 0: `frame / fps`.
    pub time: f64,
    /// Frames per second.
    pub fps: f64,
}

impl Default for Clock {
    fn default() -> Self {
        Self { frame: 0, time: 0.0, fps: 24.0 }
    }
}

impl Clock {
    /// Frame `frame` at `fps` frames per second.
    pub fn at(frame: u32, fps: f64) -> Self {
        Self { frame, time: frame as f64 / fps, fps }
    }

    /// Frame `frame` at `fps`, a fraction `offset` of the frame interval later (a shutter's
    /// opening or closing): time `(frame + offset) / fps`. `offset` 0 is [`Clock::at`].
    pub fn at_offset(frame: u32, offset: f32, fps: f64) -> Self {
        match offset {
            0.0 => Self::at(frame, fps),
            _ => Self { frame, time: (f64::from(frame) + f64::from(offset)) / fps, fps },
        }
    }
}

/// An object's own material, once a script has changed its material, and the colour of its
/// transmittance (scripts set `kt`'s strength; the scene's tint stays, even through `kt = 0`).
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct ScriptMaterial {
    /// The entity's own entry in the material table, made on the first write that changes it.
    pub own: Option<MaterialId>,
    /// `kt`'s channels over the largest (white for grey glass and for opaque materials).
    pub kt_tint: Vec3,
}

impl ScriptMaterial {
    /// A shared scene material, not yet changed.
    pub fn shared(material: &Material) -> Self {
        let k = material.kt.max_element();
        let grey = material.kt.x == material.kt.y && material.kt.y == material.kt.z;
        Self { own: None, kt_tint: if k > 0.0 && !grey { material.kt / k } else { Vec3::ONE } }
    }
}

/// The entity whose centre the camera keeps in focus wherever it moves (`camera.focus_on`);
/// [`follow_focus`] puts its centre into the rig's focus before each frame.
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq)]
pub struct FocusOn(pub Option<Entity>);

/// The World's input system for [`FocusOn`].
pub fn follow_focus(world: &mut World) {
    let Some(entity) = world.get_resource::<FocusOn>().and_then(|f| f.0) else { return };
    let Some(centre) = centre(world, entity) else { return };
    let mut rig = world.resource_mut::<CameraRig>();
    let focus = Focus::Point(centre);
    if rig.focus != focus {
        rig.focus = focus;
    }
}

/// The rig with its focus resolved: a [`FocusOn`] entity's current centre as the focus point.
pub fn resolved_rig(world: &World) -> CameraRig {
    let mut rig = *world.resource::<CameraRig>();
    if let Some(centre) = world.get_resource::<FocusOn>().and_then(|f| f.0).and_then(|e| centre(world, e)) {
        rig.focus = Focus::Point(centre);
    }
    rig
}

/// What a name refers to, as far as scripts care.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EntityKind {
    /// A renderable object; `pivot` is its object-space centre (the centre of its bounds, or
    /// a plane's point), which the transform carries to the world.
    Object {
        /// Object-space centre.
        pivot: DVec3,
        /// Spheres accept only uniform scales.
        uniform_scale: bool,
        /// Object-space bounds (`None` for a plane), for the world-space extent rule.
        bounds: Option<(DVec3, DVec3)>,
        /// A mesh whose faces take their materials from its file (`materials: FromFile`).
        faces_own_materials: bool,
    },
    /// A light source; directional lights have no position.
    Light {
        /// Point, spot and area lights can be moved; directional lights cannot.
        positioned: bool,
    },
}

/// What `entity` is, from its components; `None` for an entity that is neither.
pub fn kind(world: &World, entity: Entity) -> Option<EntityKind> {
    let e = world.get_entity(entity).ok()?;
    if let (Some(shape), Some(_)) = (e.get::<Shape>(), e.get::<Transform>()) {
        let bounds = shape.0.bounds();
        let pivot = match &shape.0 {
            geom::Shape::Plane { point, .. } => *point,
            _ => bounds.map_or(DVec3::ZERO, |(min, max)| 0.5 * (min + max)),
        };
        let faces_own_materials = match &shape.0 {
            geom::Shape::Mesh { mesh, .. } => world
                .get_resource::<MeshTable>()
                .and_then(|t| t.0.get(mesh.0 as usize))
                .is_some_and(|a| !a.data.face_material.is_empty()),
            _ => false,
        };
        let uniform_scale = matches!(shape.0, geom::Shape::Sphere { .. });
        return Some(EntityKind::Object { pivot, uniform_scale, bounds, faces_own_materials });
    }
    e.get::<Light>().map(|light| EntityKind::Light { positioned: light.position().is_some() })
}

/// World-space centre: an object's pivot under its transform, or a light's position.
pub fn centre(world: &World, entity: Entity) -> Option<DVec3> {
    match kind(world, entity)? {
        EntityKind::Object { pivot, .. } => {
            let t = world.get::<Transform>(entity)?;
            Some(t.translation + t.rotation.as_dquat() * (t.scale.as_dvec3() * pivot))
        }
        EntityKind::Light { .. } => world.get::<Light>(entity).and_then(light_position),
    }
}

/// The light's position as scripts see it: a point light's position, an area light's centre
/// (`None` for directional lights).
pub fn light_position(light: &Light) -> Option<DVec3> {
    let anchor = light.position()?;
    match light.source {
        trace::Light::Rect { edge_u, edge_v, .. } => Some(anchor + 0.5 * (edge_u + edge_v).as_dvec3()),
        _ => Some(anchor),
    }
}

/// The light moved so that its position (as [`light_position`] defines it) is `to`.
pub fn moved_light(light: &Light, to: DVec3) -> Light {
    match light.source {
        trace::Light::Directional { .. } => *light,
        trace::Light::Rect { edge_u, edge_v, .. } => {
            Light::at(to - 0.5 * (edge_u + edge_v).as_dvec3(), light.source)
        }
        _ => Light::at(to, light.source),
    }
}

/// The rotation of the scene convention: about X, then Y, then Z, by angles in degrees.
pub fn rotation_from_degrees(deg: DVec3) -> Quat {
    Transform::from_scene(DVec3::ZERO, deg.as_vec3(), Vec3::ONE).rotation
}

/// Angles in degrees (about X, then Y, then Z) of a rotation; the inverse of
/// [`rotation_from_degrees`] up to rounding.
pub fn degrees_from_rotation(q: Quat) -> DVec3 {
    let (z, y, x) = q.to_euler(EulerRot::ZYX);
    DVec3::new(x as f64, y as f64, z as f64) * (180.0 / std::f64::consts::PI)
}

/// What a call wrote that spans several fields, checked once the call has made all its writes:
/// the camera's pose (`look_at` ≠ `position`, `up` not along the view) and `kr + kt`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Written {
    /// The camera's pose was written.
    pub camera: bool,
    /// Objects whose material was written, in order, each once.
    pub materials: Vec<Entity>,
}

/// The script's handle on its World: empty between calls, the World itself during one.
#[derive(Clone, Default)]
pub struct LentWorld(Arc<Mutex<Lent>>);

/// The inside of a [`LentWorld`].
#[derive(Default)]
pub struct Lent {
    world: Option<World>,
    quiet: bool,
    written: Written,
    /// The frame being made.
    pub clock: Clock,
    /// Named objects and lights, in spawn order (`entity_names()`).
    pub names: Vec<(String, Entity)>,
    /// The same, by name: what `entity(name)` finds (names are unique in a scene).
    by_name: HashMap<String, Entity>,
}

impl LentWorld {
    /// A handle for the named objects and lights `names` (in spawn order).
    pub fn new(names: Vec<(String, Entity)>) -> Self {
        let by_name = names.iter().cloned().collect();
        Self(Arc::new(Mutex::new(Lent { names, by_name, ..Lent::default() })))
    }

    /// Locks the handle. API functions never panic while holding it, so a poisoned lock still
    /// holds consistent data.
    pub fn lock(&self) -> MutexGuard<'_, Lent> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Locks the handle for an API function that may fail: a lock already held (an API
    /// function reaching the World again while it holds it, a bug) is an error rather than a
    /// deadlock.
    pub fn get(&self) -> ScriptResult<MutexGuard<'_, Lent>> {
        match self.0.try_lock() {
            Ok(lent) => Ok(lent),
            Err(std::sync::TryLockError::Poisoned(p)) => Ok(p.into_inner()),
            Err(std::sync::TryLockError::WouldBlock) => {
                error("internal error: the scene is already being read or written by this call")
            }
        }
    }

    /// Lends `world` to the script for the length of `call` and takes it back; returns what
    /// `call` returned and what it wrote. `quiet`: the writes are to be undone (a pose at
    /// shutter close), so they leave the World's change ticks alone.
    pub fn lend<T>(&self, world: &mut World, quiet: bool, call: impl FnOnce() -> T) -> (T, Written) {
        {
            let mut lent = self.lock();
            lent.world = Some(std::mem::take(world));
            lent.quiet = quiet;
            lent.written = Written::default();
        }
        let result = call();
        let mut lent = self.lock();
        if let Some(lent_world) = lent.world.take() {
            *world = lent_world;
        }
        (result, std::mem::take(&mut lent.written))
    }
}

impl Lent {
    /// The World as the API sees it, or an error outside a call (a handle kept and used after
    /// the call that made it ended cannot happen in a script, but fails cleanly if it did).
    pub fn scene(&mut self) -> ScriptResult<Scene<'_>> {
        match self.world.as_mut() {
            Some(world) => Ok(Scene { world, quiet: self.quiet, written: &mut self.written }),
            None => error("the scene can be read and written only while the script runs"),
        }
    }

    /// The entity called `name`.
    pub fn entity(&self, name: &str) -> Option<Entity> {
        self.by_name.get(name).copied()
    }
}

/// The lent World, and what a call has written.
pub struct Scene<'a> {
    /// The World.
    pub world: &'a mut World,
    quiet: bool,
    /// What the call wrote that spans fields.
    pub written: &'a mut Written,
}

impl Scene<'_> {
    /// Sets `entity`'s component to `value` if it has one and the value differs; `check`
    /// then sees the World with the new value and, on an error, the old value is put back
    /// (the change is marked only when kept).
    pub fn set<C>(
        &mut self,
        entity: Entity,
        value: C,
        check: impl FnOnce(&World) -> ScriptResult<()>,
    ) -> ScriptResult<()>
    where
        C: Component<Mutability = Mutable> + PartialEq,
    {
        let Some(mut c) = self.world.get_mut::<C>(entity) else { return Ok(()) };
        if *c == value {
            return Ok(());
        }
        let old = std::mem::replace(c.bypass_change_detection(), value);
        if let Err(e) = check(self.world) {
            if let Some(mut c) = self.world.get_mut::<C>(entity) {
                *c.bypass_change_detection() = old;
            }
            return Err(e);
        }
        if let (false, Some(mut c)) = (self.quiet, self.world.get_mut::<C>(entity)) {
            c.set_changed();
        }
        Ok(())
    }

    /// Sets the resource `R` to `value` if it differs, checked as [`Self::set`] checks.
    pub fn set_resource<R>(
        &mut self,
        value: R,
        check: impl FnOnce(&World) -> ScriptResult<()>,
    ) -> ScriptResult<()>
    where
        R: Resource<Mutability = Mutable> + PartialEq,
    {
        let Some(mut r) = self.world.get_resource_mut::<R>() else { return Ok(()) };
        if *r == value {
            return Ok(());
        }
        let old = std::mem::replace(r.bypass_change_detection(), value);
        if let Err(e) = check(self.world) {
            *self.world.resource_mut::<R>().bypass_change_detection() = old;
            return Err(e);
        }
        if !self.quiet {
            self.world.resource_mut::<R>().set_changed();
        }
        Ok(())
    }

    /// Runs `change` on the resource `R` and marks it changed (unless quiet); for tables a
    /// script changes one entry of.
    pub fn change_resource<R: Resource<Mutability = Mutable>>(&mut self, change: impl FnOnce(&mut R)) {
        if let Some(mut r) = self.world.get_resource_mut::<R>() {
            change(r.bypass_change_detection());
            if !self.quiet {
                r.set_changed();
            }
        }
    }

    /// The name of `entity` as the scene gives it.
    pub fn name(&self, entity: Entity) -> &str {
        self.world.get::<Name>(entity).map_or("?", |n| n.as_str())
    }

    /// Gives `entity` a material of its own equal to `wanted`, or changes the one it has;
    /// nothing while `wanted` equals the shared material it draws with.
    pub fn set_material(&mut self, entity: Entity, wanted: Material) {
        let (Some(reference), Some(script)) = (
            self.world.get::<MaterialRef>(entity).copied(),
            self.world.get::<ScriptMaterial>(entity).copied(),
        ) else {
            return;
        };
        let materials = self.world.resource::<crate::world::resources::Materials>();
        if materials.table.get(reference.0 .0 as usize) == Some(&wanted) {
            return;
        }
        let id = match script.own {
            Some(id) => id,
            None => MaterialId(materials.table.len() as u32),
        };
        let name = format!("{}#script", self.name(entity));
        self.change_resource(|m: &mut crate::world::resources::Materials| match script.own {
            Some(id) => m.table[id.0 as usize] = wanted,
            None => {
                m.table.push(wanted);
                m.names.push(name);
            }
        });
        let _ = self.set(entity, MaterialRef(id), |_| Ok(()));
        let _ = self.set(entity, ScriptMaterial { own: Some(id), ..script }, |_| Ok(()));
        if !self.written.materials.contains(&entity) {
            self.written.materials.push(entity);
        }
    }
}

/// Adds what a script needs to a World holding a spawned scene, and lists its named objects
/// and lights in spawn order: objects with one material get a [`ScriptMaterial`], lights
/// spawned without their [`LightTerms`] read as colour = radiance and intensity = 1.
pub fn prepare(world: &mut World) -> Vec<(String, Entity)> {
    let mut named: Vec<(Entity, String)> =
        world.query::<(Entity, &Name)>().iter(world).map(|(e, n)| (e, n.as_str().to_owned())).collect();
    named.sort_unstable_by_key(|(e, _)| *e);
    let mut names = Vec::with_capacity(named.len());
    for (entity, name) in named {
        match kind(world, entity) {
            Some(EntityKind::Object { faces_own_materials, .. }) => {
                let material = world
                    .get::<MaterialRef>(entity)
                    .filter(|_| !faces_own_materials)
                    .and_then(|m| {
                        world.resource::<crate::world::resources::Materials>().table.get(m.0 .0 as usize)
                    })
                    .map(ScriptMaterial::shared);
                if let Some(material) = material {
                    world.entity_mut(entity).insert(material);
                }
            }
            Some(EntityKind::Light { .. }) => {
                if world.get::<LightTerms>(entity).is_none() {
                    let colour = world.get::<Light>(entity).map_or(Vec3::ZERO, |l| l.source.radiance());
                    world.entity_mut(entity).insert(LightTerms { colour, intensity: 1.0 });
                }
            }
            None => continue,
        }
        names.push((name, entity));
    }
    world.init_resource::<FocusOn>();
    names
}

#[cfg(test)]
mod tests;
