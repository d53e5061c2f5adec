//! The scene as scripts see it: the global variables `camera` and `settings`, entities by
//! name (`entity("ball")`, [`super::entity`]) and the clock (`frame_number()`, `time()`, `fps()`).
//!
//! Each is a handle onto the World the script is lent ([`LentWorld`]); property reads and
//! writes go straight to its components and resources, so `let ball = entity("ball");
//! ball.position = p;` moves the ball, `camera.fov = 30` narrows the view and
//! `let key = entity("light_0"); key.intensity = 0.5;` dims the first light. Every write is
//! checked against the scene format's own rules and fails with the rule it broke, e.g.
//! ``entity `ball`: kd must be in [0, 1] in every channel, got g = 1.2``. The property names
//! are listed in [`super::properties`].

use glam::DVec3;
use rhai::{Dynamic, Engine, ImmutableString, Module, FLOAT, INT};

use super::convert::{error, finite, vector, ScriptResult};
use super::limits;
use crate::scene::fields::{self, Rule};
use crate::script::lent::{resolved_rig, FocusOn, LentWorld, Scene};
use crate::world::resources::{CameraRig, Focus};

pub use super::entity::EntityHandle;
pub use super::settings::{SettingsHandle, SETTINGS_PROPERTIES};

/// Camera properties a sweep parameter may name.
pub const CAMERA_PROPERTIES: &[&str] = &["position", "look_at", "up", "fov", "aperture", "focus_distance"];

/// Handle on the camera.
#[derive(Clone)]
pub struct CameraHandle(LentWorld);

/// Registers the camera, the settings and the clock over `lent`.
pub fn register(engine: &mut Engine, lent: &LentWorld) {
    // Global variables, visible inside functions too (script functions see no outer
    // variables, but they do see the engine's global module).
    let mut globals = Module::new();
    globals.set_var("camera", CameraHandle(lent.clone()));
    globals.set_var("settings", SettingsHandle(lent.clone()));
    engine.register_global_module(globals.into());
    register_clock(engine, lent);
    register_camera(engine);
    super::settings::register(engine);
}

fn register_clock(engine: &mut Engine, lent: &LentWorld) {
    let l = lent.clone();
    engine.register_fn("frame_number", move || l.lock().clock.frame as INT);
    let l = lent.clone();
    engine.register_fn("time", move || l.lock().clock.time as FLOAT);
    let l = lent.clone();
    engine.register_fn("fps", move || l.lock().clock.fps as FLOAT);
}

/// A vector finite in 32-bit floats (the tracer's precision), or an error naming `what`.
pub(super) fn finite_vec(v: DVec3, what: &str) -> ScriptResult<DVec3> {
    match v.as_vec3().is_finite() {
        true => Ok(v),
        false => error(format!("{what} must be finite in every component (as a 32-bit float), got {v}")),
    }
}

/// A point or scale: finite and within ±`MAX_COORDINATE`, the scene format's rule.
pub(super) fn coordinate_vec(v: DVec3, what: &str) -> ScriptResult<DVec3> {
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

    engine.register_get("position", |c: &mut CameraHandle| c.read(|rig| rig.position));
    engine.register_set("position", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let v = coordinate_vec(vector(&v, "camera.position")?, "camera.position")?;
        c.write(|rig| rig.position = v)
    });
    engine.register_get("look_at", |c: &mut CameraHandle| c.read(|rig| rig.look_at));
    engine.register_set("look_at", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let v = coordinate_vec(vector(&v, "camera.look_at")?, "camera.look_at")?;
        c.write(|rig| rig.look_at = v)
    });
    engine.register_get("up", |c: &mut CameraHandle| c.read(|rig| rig.up.as_dvec3()));
    engine.register_set("up", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let v = coordinate_vec(vector(&v, "camera.up")?, "camera.up")?;
        c.write(|rig| rig.up = v.as_vec3())
    });
    engine.register_get("fov", |c: &mut CameraHandle| c.read(|rig| f64::from(rig.fov_y.to_degrees())));
    engine.register_set("fov", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let fov = finite(&v, "camera.fov")? as f32;
        obeys(fields::fov_deg(fov), "camera.fov:")?;
        // As the scene file's `fov_deg` becomes the rig's angle.
        c.write(|rig| rig.fov_y = fov.to_radians())
    });
    engine.register_get("aperture", |c: &mut CameraHandle| c.read(|rig| f64::from(rig.aperture)));
    engine.register_set("aperture", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let aperture = finite(&v, "camera.aperture")?;
        obeys(fields::non_negative(aperture as f32), "camera.aperture:")?;
        let rig = CameraRig { aperture: aperture as f32, ..c.rig()? };
        let mut lent = c.0.get()?;
        let mut scene = lent.scene()?;
        scene.set_resource(rig, |world| {
            limits::lens(world).and_then(|()| limits::radiance(world, "camera.aperture"))
        })?;
        scene.written.camera = true;
        Ok(())
    });
    engine.register_get("focus_distance", |c: &mut CameraHandle| -> ScriptResult<FLOAT> {
        let mut lent = c.0.get()?;
        Ok(f64::from(resolved_rig(lent.scene()?.world).focus_distance()))
    });
    engine.register_set("focus_distance", |c: &mut CameraHandle, v: Dynamic| -> ScriptResult<()> {
        let distance = finite(&v, "camera.focus_distance")?;
        obeys(fields::positive(distance as f32), "camera.focus_distance:")?;
        c.write(|rig| rig.focus = Focus::Distance(distance as f32))?;
        c.0.get()?.scene()?.set_resource(FocusOn(None), |_| Ok(()))
    });
    engine.register_fn("focus_on", |c: &mut CameraHandle, name: ImmutableString| -> ScriptResult<()> {
        let mut lent = c.0.get()?;
        let entity = super::entity::find(&lent, &name)?;
        let mut scene = lent.scene()?;
        scene.set_resource(FocusOn(Some(entity)), |_| Ok(()))?;
        scene.written.camera = true;
        Ok(())
    });
}

impl CameraHandle {
    /// The rig as the World holds it.
    fn rig(&self) -> ScriptResult<CameraRig> {
        Ok(*self.0.get()?.scene()?.world.resource::<CameraRig>())
    }

    fn read<T>(&self, f: impl FnOnce(&CameraRig) -> T) -> ScriptResult<T> {
        self.rig().map(|rig| f(&rig))
    }

    /// Changes the rig with `change`, keeping the change only if the lens rule still holds.
    fn write(&self, change: impl FnOnce(&mut CameraRig)) -> ScriptResult<()> {
        let mut rig = self.rig()?;
        change(&mut rig);
        let mut lent = self.0.get()?;
        let mut scene: Scene = lent.scene()?;
        scene.set_resource(rig, limits::lens)?;
        scene.written.camera = true;
        Ok(())
    }
}
