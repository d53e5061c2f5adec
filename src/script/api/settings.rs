//! The render settings as scripts see them: the global variable `settings`, whose properties
//! (sample counts, depth, image size, seed, adaptive supersampling) read and write the
//! World's [`SceneSettings`], each write checked against the scene format's rule for its field ([`fields`]).

use rhai::{Dynamic, Engine, INT};

use super::convert::{error, finite, integer, ScriptResult};
use super::limits;
use super::scene::obeys;
use crate::sample::adaptive::AdaptiveSettings;
use crate::scene::fields;
use crate::script::lent::LentWorld;
use crate::trace::RenderSettings;
use crate::world::resources::SceneSettings;

/// Settings properties a sweep parameter may name.
pub const SETTINGS_PROPERTIES: &[&str] = &[
    "samples",
    "lens_samples",
    "time_samples",
    "glossy_samples",
    "max_depth",
    "max_secondary_rays",
    "width",
    "height",
    "seed",
    "adaptive",
    "adaptive_depth",
];

/// Handle on the render settings.
#[derive(Clone)]
pub struct SettingsHandle(pub(super) LentWorld);

impl SettingsHandle {
    fn read<T>(&self, f: impl FnOnce(&RenderSettings) -> T) -> ScriptResult<T> {
        let mut lent = self.0.get()?;
        Ok(f(&lent.scene()?.world.resource::<SceneSettings>().render))
    }

    /// Changes the render settings with `change`, keeping the change only if the scene's
    /// radiance and camera-samples rules still hold; `what` names the write in their errors.
    fn write(&self, what: &str, change: impl FnOnce(&mut RenderSettings)) -> ScriptResult<()> {
        let mut lent = self.0.get()?;
        let mut scene = lent.scene()?;
        let mut settings = *scene.world.resource::<SceneSettings>();
        change(&mut settings.render);
        scene.set_resource(settings, |world| limits::radiance(world, what))
    }
}

/// Registers the `settings` type and its properties.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<SettingsHandle>("settings");
    engine.register_fn("to_string", |_: &mut SettingsHandle| "settings".to_string());

    macro_rules! count_property {
        ($name:literal, $($field:ident).+, $rule:expr) => {
            engine.register_get($name, |h: &mut SettingsHandle| h.read(|s| s.$($field).+ as INT));
            engine.register_set($name, |h: &mut SettingsHandle, v: Dynamic| -> ScriptResult<()> {
                let what = concat!("settings.", $name);
                let n = integer(&v, what)?;
                obeys($rule(n), what)?;
                h.write(what, |s| s.$($field).+ = n as _)
            });
        };
    }
    count_property!("samples", aa.samples, fields::sample_count);
    count_property!("lens_samples", lens.samples, fields::sample_count);
    count_property!("time_samples", time.samples, fields::sample_count);
    count_property!("glossy_samples", glossy.samples, fields::sample_count);
    count_property!("max_depth", max_depth, fields::max_depth);
    count_property!("max_secondary_rays", max_secondary_rays, fields::max_secondary_rays);
    count_property!("width", width, fields::image_size);
    count_property!("height", height, fields::image_size);
    // Any u64 is a seed in a scene file; a script's integers stop at INT::MAX.
    count_property!("seed", seed, |n: INT| match n >= 0 {
        true => Ok(()),
        false => Err(format!("must be in 0..={}, got {n}", INT::MAX)),
    });

    engine.register_get("adaptive", |h: &mut SettingsHandle| {
        h.read(|s| match s.adaptive {
            Some(a) => Dynamic::from_float(f64::from(a.threshold)),
            None => Dynamic::UNIT,
        })
    });
    engine.register_set("adaptive", |h: &mut SettingsHandle, v: Dynamic| -> ScriptResult<()> {
        let threshold = match v.is_unit() {
            true => None,
            false => {
                let threshold = finite(&v, "settings.adaptive")? as f32;
                obeys(fields::non_negative(threshold), "settings.adaptive (a threshold, or () for off)")?;
                Some(threshold)
            }
        };
        h.write("settings.adaptive", |s| {
            s.adaptive = threshold.map(|threshold| AdaptiveSettings {
                threshold,
                max_depth: s.adaptive.map_or(AdaptiveSettings::default().max_depth, |a| a.max_depth),
            })
        })
    });
    engine.register_get("adaptive_depth", |h: &mut SettingsHandle| {
        h.read(|s| match s.adaptive {
            Some(a) => Dynamic::from_int(a.max_depth as INT),
            None => Dynamic::UNIT,
        })
    });
    engine.register_set("adaptive_depth", |h: &mut SettingsHandle, v: Dynamic| -> ScriptResult<()> {
        let depth = integer(&v, "settings.adaptive_depth")?;
        obeys(fields::adaptive_depth(depth), "settings.adaptive_depth")?;
        let Some(adaptive) = h.read(|s| s.adaptive)? else {
            return error(
                "settings.adaptive_depth: adaptive supersampling is off; set settings.adaptive first",
            );
        };
        h.write("settings.adaptive_depth", |s| {
            s.adaptive = Some(AdaptiveSettings { max_depth: depth as u32, ..adaptive })
        })
    });
}
