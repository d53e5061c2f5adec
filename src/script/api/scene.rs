//! The scene as scripts see it: the global variables `camera` and `settings`, entities by
//! name (`entity("ball")`) and the clock (`frame_number()`, `time()`, `fps()`).
//!
//! Each is a handle onto the shared mirror ([`SharedState`]); property reads and writes go
//! straight to it, so `let ball = entity("ball"); ball.position = p;` moves the ball,
//! `camera.fov = 30` narrows the view and `let key = entity("light_0"); key.intensity = 0.5;`
//! dims the first light. Every write is checked against the scene format's own rules and
//! fails with the rule it broke, e.g. ``entity `ball`: kd must be in [0, 1] in every channel,
//! got g = 1.2``. The property names are listed in [`super::properties`].

use glam::{DVec3, Vec3};
use rhai::{Array, Dynamic, Engine, ImmutableString, Module, FLOAT, INT};

use super::convert::{error, finite, vector, ScriptResult};
use super::limits;
use super::properties::unknown_name;
use crate::scene::fields::{self, Rule};
use crate::scene::format::{CameraDesc, Sampling};
use crate::script::state::{
    EntityKind, EntityState, FocusState, LightTerms, MaterialParams, ScriptState, SharedState,
};

pub use super::settings::{SettingsHandle, SETTINGS_PROPERTIES};

/// Camera properties a sweep parameter may name.
pub const CAMERA_PROPERTIES: &[&str] = &["position", "look_at", "up", "fov", "aperture", "focus_distance"];

/// Handle on the camera.
#[derive(Clone)]
pub struct CameraHandle(SharedState);

/// Handle on one named entity.
#[derive(Clone)]
pub struct EntityHandle {
    state: SharedState,
    index: usize,
}

/// Registers the scene API over `state`.
pub fn register(engine: &mut Engine, state: &SharedState) {
    // Global variables, visible inside functions too (script functions see no outer
    // variables, but they do see the engine's global module).
    let mut globals = Module::new();
    globals.set_var("camera", CameraHandle(state.clone()));
    globals.set_var("settings", SettingsHandle(state.clone()));
    engine.register_global_module(globals.into());
    register_clock(engine, state);
    register_camera(engine);
    register_entities(engine, state);
    super::settings::register(engine);
}

fn register_clock(engine: &mut Engine, state: &SharedState) {
    let s = state.clone();
    engine.register_fn("frame_number", move || s.lock().clock.frame as INT);
    let s = state.clone();
    engine.register_fn("time", move || s.lock().clock.time as FLOAT);
    let s = state.clone();
    engine.register_fn("fps", move || s.lock().clock.fps as FLOAT);
}

/// A vector finite in 32-bit floats (the tracer's precision), or an error naming `what`.
fn finite_vec(v: DVec3, what: &str) -> ScriptResult<DVec3> {
    match v.as_vec3().is_finite() {
        true => Ok(v),
        false => error(format!("{what} must be finite in every component (as a 32-bit float), got {v}")),
    }
}

/// A point or scale: finite and within ±`MAX_COORDINATE`, the scene format's rule.
fn coordinate_vec(v: DVec3, what: &str) -> ScriptResult<DVec3> {
    let v = finite_vec(v, what)?;
    obeys(fields::position(v), what).map(|()| v)
}

/// The scene format's rule for a field ([`fields`]), applied to a script write: the error is
/// `what` (the property written) followed by the rule's words, as a scene file's error has
/// them after the field.
pub(super) fn obeys(rule: Rule, what: &str) -> ScriptResult<()> {
    match rule {
        Ok(()) => Ok(()),
        Err(rule) => error(format!("{what} {rule}")),
    }
}

fn register_camera(engine: &mut Engine) {
    engine.register_type_with_name::<CameraHandle>("camera");
    engine.register_fn("to_string", |_: &mut CameraHandle| "camera".to_string());

    macro_rules! vec_property {
        ($name:literal, $field:ident) => {
            engine.register_get($name, |c: &mut CameraHandle| c.0.lock().camera.$field);
            engine.register_set($name, |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
                let what = concat!("camera.", $name);
                let v = coordinate_vec(vector(&v, what)?, what)?;
                let mut s = c.0.lock();
                let old = std::mem::replace(&mut s.camera.$field, v);
                if let Err(e) = limits::lens(&s) {
                    s.camera.$field = old;
                    return Err(e);
                }
                s.camera_dirty = true;
                Ok(())
            });
        };
    }
    vec_property!("position", position);
    vec_property!("look_at", look_at);
    vec_property!("up", up);

    engine.register_get("fov", |c: &mut CameraHandle| c.0.lock().camera.fov_deg);
    engine.register_set("fov", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let fov = finite(&v, "camera.fov")?;
        obeys(fields::fov_deg(fov as f32), "camera.fov:")?;
        let mut s = c.0.lock();
        s.camera.fov_deg = fov;
        s.camera_dirty = true;
        Ok(())
    });
    engine.register_get("aperture", |c: &mut CameraHandle| c.0.lock().camera.aperture);
    engine.register_set("aperture", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let aperture = finite(&v, "camera.aperture")?;
        obeys(fields::non_negative(aperture as f32), "camera.aperture:")?;
        let mut s = c.0.lock();
        let old = std::mem::replace(&mut s.camera.aperture, aperture);
        if let Err(e) = limits::lens(&s).and_then(|()| limits::radiance(&s, "camera.aperture")) {
            s.camera.aperture = old;
            return Err(e);
        }
        s.camera_dirty = true;
        Ok(())
    });
    engine.register_get("focus_distance", |c: &mut CameraHandle| c.0.lock().focus_distance());
    engine.register_set("focus_distance", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let distance = finite(&v, "camera.focus_distance")?;
        obeys(fields::positive(distance as f32), "camera.focus_distance:")?;
        let mut s = c.0.lock();
        let old = std::mem::replace(&mut s.camera.focus, FocusState::Distance(distance));
        if let Err(e) = limits::lens(&s) {
            s.camera.focus = old;
            return Err(e);
        }
        s.camera_dirty = true;
        Ok(())
    });
    engine.register_fn("focus_on", |c: &mut CameraHandle, name: ImmutableString| -> ScriptResult<()> {
        let mut s = c.0.lock();
        let index = find(&s, &name)?;
        s.camera.focus = FocusState::Entity(index);
        s.camera_dirty = true;
        Ok(())
    });
}

/// The camera as the scene format describes it, for the rules that span the scene
/// ([`super::limits`]).
pub fn camera_desc(state: &ScriptState) -> CameraDesc {
    let c = &state.camera;
    CameraDesc {
        position: c.position,
        look_at: c.look_at,
        up: c.up.as_vec3(),
        fov_deg: c.fov_deg as f32,
        width: state.settings.width,
        height: state.settings.height,
        aperture: c.aperture as f32,
        focus_distance: match c.focus {
            FocusState::Distance(d) => Some(d as f32),
            _ => None,
        },
        focus_on: None,
        lens: Sampling { samples: state.settings.lens_samples, ..Default::default() },
        shutter: None,
        time: Sampling { samples: state.settings.time_samples, ..Default::default() },
    }
}

/// The index of the entity called `name`, or an error that suggests the closest name and
/// lists the names there are.
fn find(state: &ScriptState, name: &str) -> ScriptResult<usize> {
    match state.index_of(name) {
        Some(index) => Ok(index),
        None => error(unknown_name("entity", name, state.entities.iter().map(|e| e.name.as_str()))),
    }
}

fn register_entities(engine: &mut Engine, state: &SharedState) {
    engine.register_type_with_name::<EntityHandle>("entity");
    let s = state.clone();
    engine.register_fn("entity", move |name: ImmutableString| -> ScriptResult<EntityHandle> {
        let index = find(&s.lock(), &name)?;
        Ok(EntityHandle { state: s.clone(), index })
    });
    let s = state.clone();
    engine.register_fn("has_entity", move |name: ImmutableString| s.lock().index_of(&name).is_some());
    let s = state.clone();
    engine.register_fn("entity_names", move || -> Array {
        s.lock().entities.iter().map(|e| Dynamic::from(e.name.clone())).collect()
    });
    engine.register_fn("to_string", |e: &mut EntityHandle| format!("entity(\"{}\")", e.name()));
    engine.register_get("name", |e: &mut EntityHandle| e.name());
    engine.register_get("centre", |e: &mut EntityHandle| e.state.lock().entities[e.index].centre());

    engine.register_get("position", |e: &mut EntityHandle| e.state.lock().entities[e.index].position);
    engine.register_set("position", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        e.write(|entry| {
            if let EntityKind::Light { positioned: false } = entry.kind {
                return error(format!("entity `{}` is a directional light: it has no position", entry.name));
            }
            let what = format!("entity `{}`: position", entry.name);
            let position = coordinate_vec(vector(&v, &what)?, &what)?;
            placed(entry, &what, |entry| entry.position = position)
        })
    });
    engine.register_get("rotation", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|entry| object(entry, "rotation").map(|_| entry.rotation_deg))
    });
    engine.register_set("rotation", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        e.write(|entry| {
            object(entry, "rotation")?;
            let what = format!("entity `{}`: rotation", entry.name);
            let rotation = finite_vec(vector(&v, &what)?, &what)?;
            placed(entry, &what, |entry| entry.rotation_deg = rotation)?;
            entry.rotation_written = true;
            Ok(())
        })
    });
    engine.register_get("scale", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|entry| object(entry, "scale").map(|_| entry.scale))
    });
    engine.register_set("scale", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        e.write(|entry| {
            let uniform = object(entry, "scale")?;
            let what = format!("entity `{}`: scale", entry.name);
            let v = match v.clone().try_cast::<DVec3>() {
                Some(v) => coordinate_vec(v, &what)?,
                None => coordinate_vec(DVec3::splat(finite(&v, &what)?), &what)?,
            };
            if v.cmpeq(DVec3::ZERO).any() {
                return error(format!("{what} must be non-zero on every axis, got {v}"));
            }
            let m = v.abs();
            if uniform && m.max_element() - m.min_element() > 1e-5 * m.max_element() {
                return error(format!("{what} must be uniform for a sphere (|x| = |y| = |z|), got {v}"));
            }
            placed(entry, &what, |entry| entry.scale = v)
        })
    });
    engine.register_get("visible", |e: &mut EntityHandle| e.state.lock().entities[e.index].visible);
    engine.register_set("visible", |e: &mut EntityHandle, v: bool| -> ScriptResult<()> {
        e.write(|entry| {
            entry.visible = v;
            entry.visible_dirty = true;
            Ok(())
        })
    });

    engine.register_get("kd", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|entry| material(entry).map(|m| m.kd))
    });
    engine.register_set("kd", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let v = vector(&v, &format!("entity `{}`: kd", e.name()))?;
        e.write_material("kd", |m| m.kd = v, fields::unit_channels(v.as_vec3()))
    });
    macro_rules! scalar_material {
        ($name:literal, $field:ident, $rule:path) => {
            engine.register_get($name, |e: &mut EntityHandle| -> ScriptResult<FLOAT> {
                e.read(|entry| material(entry).map(|m| m.$field))
            });
            engine.register_set($name, |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
                let v = finite(&v, $name)?;
                e.write_material($name, |m| m.$field = v, $rule(v as f32))
            });
        };
    }
    scalar_material!("ks", ks, fields::unit_interval);
    scalar_material!("shininess", shininess, fields::shininess);
    scalar_material!("kr", kr, fields::unit_interval);
    // `kt` is the strength of the transmittance; a scene's tint stays (its largest channel is
    // the strength, so the file's rule sees the same value).
    engine.register_get("kt", |e: &mut EntityHandle| -> ScriptResult<FLOAT> {
        e.read(|entry| material(entry).map(|m| m.kt))
    });
    engine.register_set("kt", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        let v = finite(&v, "kt")?;
        e.write_material("kt", |m| m.kt = v, fields::kt(Vec3::splat(v as f32)))
    });
    scalar_material!("ior", ior, fields::positive);
    scalar_material!("glossiness", glossiness, fields::unit_interval);

    engine.register_get("colour", |e: &mut EntityHandle| -> ScriptResult<DVec3> {
        e.read(|entry| light(entry, "colour").map(|l| l.colour))
    });
    engine.register_set("colour", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        e.relight("colour", |terms, what| Ok(LightTerms { colour: vector(&v, what)?, ..terms }))
    });
    engine.register_get("intensity", |e: &mut EntityHandle| -> ScriptResult<FLOAT> {
        e.read(|entry| light(entry, "intensity").map(|l| l.intensity))
    });
    engine.register_set("intensity", |e: &mut EntityHandle, v: Dynamic| -> ScriptResult<()> {
        e.relight("intensity", |terms, what| Ok(LightTerms { intensity: finite(&v, what)?, ..terms }))
    });
}

/// A light's colour and intensity, or an error for objects.
fn light(entry: &EntityState, property: &str) -> ScriptResult<LightTerms> {
    match entry.light {
        Some(terms) => Ok(terms),
        None => error(format!(
            "entity `{}` is an object: it has no {property} (lights have colour and intensity; an \
             object's colour is its material's kd)",
            entry.name
        )),
    }
}

/// Checks a light's colour and intensity against the scene format's rules for lights; the
/// error names `field`.
fn check_light_field(name: &str, field: &str, terms: LightTerms) -> ScriptResult<()> {
    let what = format!("entity `{name}`: {field}");
    obeys(fields::non_negative_channels(terms.colour.as_vec3()), &what)?;
    obeys(fields::non_negative(terms.intensity as f32), &what)
}

/// Changes an object's placement with `set`, keeping it only if the object stays within the
/// world-space limit (see [`limits::extent`]).
fn placed(entry: &mut EntityState, what: &str, set: impl FnOnce(&mut EntityState)) -> ScriptResult<()> {
    let (position, rotation, scale) = (entry.position, entry.rotation_deg, entry.scale);
    set(entry);
    if let Err(e) = limits::extent(entry, what) {
        (entry.position, entry.rotation_deg, entry.scale) = (position, rotation, scale);
        return Err(e);
    }
    entry.transform_dirty = true;
    Ok(())
}

/// Objects only: errors for lights; says whether the object takes only uniform scales.
fn object(entry: &EntityState, property: &str) -> ScriptResult<bool> {
    match entry.kind {
        EntityKind::Object { uniform_scale, .. } => Ok(uniform_scale),
        EntityKind::Light { .. } => {
            error(format!("entity `{}` is a light: it has no {property}", entry.name))
        }
    }
}

/// The object's material parameters, or an error for lights.
fn material(entry: &EntityState) -> ScriptResult<&MaterialParams> {
    match &entry.material {
        Some(m) => Ok(&m.params),
        None if entry.faces_own_materials => error(format!(
            "entity `{}` takes its faces' materials from its file (`materials: FromFile`): set them in the scene (a scene material named like a library material replaces it)",
            entry.name
        )),
        None => error(format!("entity `{}` is a light: it has no material", entry.name)),
    }
}

impl EntityHandle {
    fn name(&self) -> String {
        self.state.lock().entities[self.index].name.clone()
    }

    fn read<T>(&self, f: impl FnOnce(&EntityState) -> ScriptResult<T>) -> ScriptResult<T> {
        f(&self.state.lock().entities[self.index])
    }

    fn write(&self, f: impl FnOnce(&mut EntityState) -> ScriptResult<()>) -> ScriptResult<()> {
        f(&mut self.state.lock().entities[self.index])
    }

    /// Sets a light's colour or intensity (`field`) to what `next` makes of the current terms,
    /// after checking the light's own rules and the scene's radiance rule.
    fn relight(
        &self,
        field: &str,
        next: impl FnOnce(LightTerms, &str) -> ScriptResult<LightTerms>,
    ) -> ScriptResult<()> {
        let mut state = self.state.lock();
        let entry = &mut state.entities[self.index];
        let what = format!("entity `{}`: {field}", entry.name);
        let old = light(entry, field)?;
        let terms = next(old, &what)?;
        check_light_field(&entry.name, field, terms)?;
        entry.light = Some(terms);
        if let Err(e) = limits::radiance(&state, &what) {
            state.entities[self.index].light = Some(old);
            return Err(e);
        }
        state.entities[self.index].light_dirty = true;
        Ok(())
    }

    /// Sets one material field after checking it against the scene format's rule for it
    /// (`rule`, the field's rule applied to the new value). `kr + kt` spans two fields and is
    /// checked once the call has made all its writes.
    fn write_material(
        &self,
        field: &str,
        set: impl FnOnce(&mut MaterialParams),
        rule: Rule,
    ) -> ScriptResult<()> {
        self.write(|entry| {
            material(entry)?;
            obeys(rule, &format!("entity `{}`: {field}", entry.name))?;
            if let Some(m) = entry.material.as_mut() {
                set(&mut m.params);
                entry.material_dirty = true;
            }
            Ok(())
        })
    }
}
