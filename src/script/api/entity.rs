//! Objects and lights by name: `entity("ball")` is a handle on the World's entity of that
//! name, whose properties read and write its components — `position`, `rotation`, `scale`
//! and `visible` its [`Transform`] and [`Visible`], `kd` … `glossiness` its material, a
//! light's `colour` and `intensity` its [`LightTerms`] (and so its radiance). Also
//! `has_entity(name)`, `entity_names()` and the read-only `name` and `centre`.

use bevy_ecs::prelude::{Entity, World};
use glam::{DVec3, Vec3};
use rhai::{Array, Dynamic, Engine, ImmutableString, FLOAT};

use super::convert::{error, finite, vector, ScriptResult};
use super::limits;
use super::properties::unknown_name;
use super::scene::{coordinate_vec, finite_vec, obeys};
use crate::scene::fields::{self, Rule};
use crate::script::lent::{
    centre, degrees_from_rotation, kind, light_position, moved_light, rotation_from_degrees, EntityKind,
    Lent, LentWorld, Scene, ScriptMaterial,
};
use crate::trace::Material;
use crate::world::components::{Light, LightTerms, MaterialRef, Transform, Visible};
use crate::world::resources::Materials;

/// Handle on one named entity.
#[derive(Clone)]
pub struct EntityHandle {
    lent: LentWorld,
    entity: Entity,
    name: ImmutableString,
}

/// The entity called `name`, or an error that suggests the closest name and lists the names
/// there are.
pub(super) fn find(lent: &Lent, name: &str) -> ScriptResult<Entity> {
    match lent.entity(name) {
        Some(entity) => Ok(entity),
        None => error(unknown_name("entity", name, lent.names.iter().map(|(n, _)| n.as_str()))),
    }
}

/// Registers `entity(name)`, `has_entity(name)`, `entity_names()` and the entity properties.
pub fn register(engine: &mut Engine, lent: &LentWorld) {
    engine.register_type_with_name::<EntityHandle>("entity");
    let l = lent.clone();
    engine.register_fn("entity", move |name: ImmutableString| -> ScriptResult<EntityHandle> {
        let entity = find(&*l.get()?, &name)?;
        Ok(EntityHandle { lent: l.clone(), entity, name })
    });
    let l = lent.clone();
    engine.register_fn("has_entity", move |name: ImmutableString| l.lock().entity(&name).is_some());
    let l = lent.clone();
    engine.register_fn("entity_names", move || -> Array {
        l.lock().names.iter().map(|(n, _)| Dynamic::from(n.clone())).collect()
    });
    engine.register_fn("to_string", |e: &mut EntityHandle| format!("entity(\"{}\")", e.name));
    engine.register_get("name", |e: &mut EntityHandle| e.name.to_string());
    engine.register_get("centre", |e: &mut EntityHandle| {
        e.read(|world, entity| Ok(centre(world, entity).unwrap_or(DVec3::ZERO)))
    });

    register_placement(engine);
    register_material(engine);

    engine.register_get("colour", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|world, entity| e.terms(world, entity, "colour").map(|t| t.colour.as_dvec3()))
    });
    engine.register_set("colour", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let what = format!("entity `{}`: colour", e.name);
        let colour = vector(&v, &what)?;
        obeys(fields::non_negative_channels(colour.as_vec3()), &what)?;
        e.relight("colour", |terms| LightTerms { colour: colour.as_vec3(), ..terms })
    });
    engine.register_get("intensity", |e: &mut EntityHandle| -> ScriptResult<FLOAT> {
        e.read(|world, entity| e.terms(world, entity, "intensity").map(|t| f64::from(t.intensity)))
    });
    engine.register_set("intensity", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let what = format!("entity `{}`: intensity", e.name);
        let intensity = finite(&v, &what)? as f32;
        obeys(fields::non_negative(intensity), &what)?;
        e.relight("intensity", |terms| LightTerms { intensity, ..terms })
    });
}

fn register_placement(engine: &mut Engine) {
    engine.register_get("position", |e: &mut EntityHandle| {
        e.read(|world, entity| {
            Ok(match world.get::<Light>(entity) {
                Some(light) => light_position(light).unwrap_or(DVec3::ZERO),
                None => world.get::<Transform>(entity).map_or(DVec3::ZERO, |t| t.translation),
            })
        })
    });
    engine.register_set("position", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let what = format!("entity `{}`: position", e.name);
        let mut lent = e.lent.get()?;
        let mut scene = lent.scene()?;
        match kind(scene.world, e.entity) {
            Some(EntityKind::Light { positioned: false }) => {
                error(format!("entity `{}` is a directional light: it has no position", e.name))
            }
            Some(EntityKind::Light { positioned: true }) => {
                let position = coordinate_vec(vector(&v, &what)?, &what)?;
                let Some(light) = scene.world.get::<Light>(e.entity) else { return Ok(()) };
                scene.set(e.entity, moved_light(light, position), |_| Ok(()))
            }
            _ => {
                let position = coordinate_vec(vector(&v, &what)?, &what)?;
                e.place(&mut scene, &what, |t| t.translation = position)
            }
        }
    });
    engine.register_get("rotation", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|world, entity| {
            e.transform(world, entity, "rotation").map(|t| degrees_from_rotation(t.rotation))
        })
    });
    engine.register_set("rotation", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let what = format!("entity `{}`: rotation", e.name);
        let rotation = finite_vec(vector(&v, &what)?, &what)?;
        let mut lent = e.lent.get()?;
        let mut scene = lent.scene()?;
        e.transform(scene.world, e.entity, "rotation")?;
        e.place(&mut scene, &what, |t| t.rotation = rotation_from_degrees(rotation))
    });
    engine.register_get("scale", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|world, entity| e.transform(world, entity, "scale").map(|t| t.scale.as_dvec3()))
    });
    engine.register_set("scale", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let what = format!("entity `{}`: scale", e.name);
        let mut lent = e.lent.get()?;
        let mut scene = lent.scene()?;
        e.transform(scene.world, e.entity, "scale")?;
        let uniform =
            matches!(kind(scene.world, e.entity), Some(EntityKind::Object { uniform_scale: true, .. }));
        let v = match v.clone().try_cast::<DVec3>() {
            Some(v) => coordinate_vec(v, &what)?,
            None => coordinate_vec(DVec3::splat(finite(&v, &what)?), &what)?,
        };
        // Non-zero as the tracer keeps it, in f32.
        if v.as_vec3().cmpeq(Vec3::ZERO).any() {
            return error(format!("{what} must be non-zero on every axis, got {v}"));
        }
        let m = v.abs();
        if uniform && m.max_element() - m.min_element() > 1e-5 * m.max_element() {
            return error(format!("{what} must be uniform for a sphere (|x| = |y| = |z|), got {v}"));
        }
        e.place(&mut scene, &what, |t| t.scale = v.as_vec3())
    });
    engine.register_get("visible", |e: &mut EntityHandle| {
        e.read(|world, entity| Ok(world.get::<Visible>(entity).is_none_or(|v| v.0)))
    });
    engine.register_set("visible", |e: &mut EntityHandle, v: bool| -> ScriptResult<()> {
        e.lent.get()?.scene()?.set(e.entity, Visible(v), |_| Ok(()))
    });
}

fn register_material(engine: &mut Engine) {
    engine.register_get("kd", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|world, entity| e.material(world, entity).map(|(m, _)| m.kd.as_dvec3()))
    });
    engine.register_set("kd", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let v = vector(&v, &format!("entity `{}`: kd", e.name))?.as_vec3();
        e.write_material("kd", fields::unit_channels(v), |m, _| m.kd = v)
    });
    macro_rules! scalar_material {
        ($name:literal, $field:ident, $rule:path) => {
            engine.register_get($name, |e: &mut EntityHandle| -> ScriptResult<FLOAT> {
                e.read(|world, entity| e.material(world, entity).map(|(m, _)| f64::from(m.$field)))
            });
            engine.register_set($name, |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
                let v = finite(&v, $name)? as f32;
                e.write_material($name, $rule(v), |m, _| m.$field = v)
            });
        };
    }
    scalar_material!("ks", ks, fields::unit_interval);
    scalar_material!("shininess", shininess, fields::shininess);
    scalar_material!("kr", kr, fields::unit_interval);
    // `kt` is the strength of the transmittance; the scene's tint stays (its largest channel
    // is the strength, so the file's rule sees the same value).
    engine.register_get("kt", |e: &mut EntityHandle| -> ScriptResult<FLOAT> {
        e.read(|world, entity| e.material(world, entity).map(|(m, _)| f64::from(m.kt.max_element())))
    });
    engine.register_set("kt", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let v = finite(&v, "kt")? as f32;
        e.write_material("kt", fields::kt(Vec3::splat(v)), |m, tint| m.kt = tint * v)
    });
    scalar_material!("ior", ior, fields::positive);
    scalar_material!("glossiness", glossiness, fields::unit_interval);
}

impl EntityHandle {
    fn read<T>(&self, f: impl FnOnce(&World, Entity) -> ScriptResult<T>) -> ScriptResult<T> {
        let mut lent = self.lent.get()?;
        let scene = lent.scene()?;
        f(scene.world, self.entity)
    }

    /// An object's transform, or an error naming `property` for lights.
    fn transform<'w>(&self, world: &'w World, entity: Entity, property: &str) -> ScriptResult<&'w Transform> {
        match world.get::<Transform>(entity) {
            Some(t) => Ok(t),
            None => error(format!("entity `{}` is a light: it has no {property}", self.name)),
        }
    }

    /// Changes an object's transform with `change`, keeping the change only if the object
    /// stays within the world-space limit (see [`limits::extent`]).
    fn place(&self, scene: &mut Scene, what: &str, change: impl FnOnce(&mut Transform)) -> ScriptResult<()> {
        let Some(mut t) = scene.world.get::<Transform>(self.entity).copied() else { return Ok(()) };
        change(&mut t);
        scene.set(self.entity, t, |world| limits::extent(world, self.entity, what))
    }

    /// The object's material and its transmittance's tint, or an error for lights and for
    /// meshes whose faces take their file's materials.
    fn material(&self, world: &World, entity: Entity) -> ScriptResult<(Material, Vec3)> {
        let own = world.get::<ScriptMaterial>(entity);
        let material = world
            .get::<MaterialRef>(entity)
            .and_then(|m| world.resource::<Materials>().table.get(m.0 .0 as usize));
        match (own, material) {
            (Some(own), Some(material)) => Ok((*material, own.kt_tint)),
            _ => match kind(world, entity) {
                Some(EntityKind::Object { faces_own_materials: true, .. }) => error(format!(
                    "entity `{}` takes its faces' materials from its file (`materials: FromFile`): set them in the scene (a scene material named like a library material replaces it)",
                    self.name
                )),
                _ => error(format!("entity `{}` is a light: it has no material", self.name)),
            },
        }
    }

    /// Sets one material field with `set` (given the material and its `kt` tint) after
    /// checking it against the scene format's rule for it (`rule`, the field's rule applied to
    /// the new value). `kr + kt` spans two fields and is checked once the call has made all
    /// its writes.
    fn write_material(
        &self,
        field: &str,
        rule: Rule,
        set: impl FnOnce(&mut Material, Vec3),
    ) -> ScriptResult<()> {
        let mut lent = self.lent.get()?;
        let mut scene = lent.scene()?;
        let (mut material, tint) = self.material(scene.world, self.entity)?;
        obeys(rule, &format!("entity `{}`: {field}", self.name))?;
        set(&mut material, tint);
        scene.set_material(self.entity, material);
        Ok(())
    }

    /// A light's colour and intensity, or an error naming `property` for objects.
    fn terms(&self, world: &World, entity: Entity, property: &str) -> ScriptResult<LightTerms> {
        match world.get::<LightTerms>(entity) {
            Some(terms) => Ok(*terms),
            None => error(format!(
                "entity `{}` is an object: it has no {property} (lights have colour and intensity; an \
                 object's colour is its material's kd)",
                self.name
            )),
        }
    }

    /// Sets a light's colour or intensity (`field`) to what `next` makes of the current terms,
    /// and its radiance to their product, if the scene's radiance rule still holds.
    fn relight(&self, field: &str, next: impl FnOnce(LightTerms) -> LightTerms) -> ScriptResult<()> {
        let what = format!("entity `{}`: {field}", self.name);
        let mut lent = self.lent.get()?;
        let mut scene = lent.scene()?;
        let terms = next(self.terms(scene.world, self.entity, field)?);
        scene.set(self.entity, terms, |world| limits::radiance(world, &what))?;
        let Some(light) = scene.world.get::<Light>(self.entity) else { return Ok(()) };
        let relit = Light { source: light.source.with_radiance(terms.colour * terms.intensity), ..*light };
        scene.set(self.entity, relit, |_| Ok(()))
    }
}
