//! The render settings as scripts see them: the global variable `settings`, whose properties
//! (sample counts, depth, image size, seed, adaptive supersampling) read and write the shared
//! mirror, each write checked against the scene format's rule for its field ([`fields`]).

use rhai::{Dynamic, Engine, INT};

use super::convert::{error, finite, integer, ScriptResult};
use super::limits;
use super::scene::obeys;
use crate::scene::fields;
use crate::script::state::SharedState;

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
pub struct SettingsHandle(pub(super) SharedState);

/// Registers the `settings` type and its properties.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<SettingsHandle>("settings");
    engine.register_fn("to_string", |_: &mut SettingsHandle| "settings".to_string());

    macro_rules! count_property {
        ($name:literal, $field:ident, $rule:expr) => {
            engine.register_get($name, |h: &mut SettingsHandle| h.0.lock().settings.$field as INT);
            engine.register_set($name, |h: &mut SettingsHandle, v: Dynamic| -> ScriptResult<()> {
                let what = concat!("settings.", $name);
                let n = integer(&v, what)?;
                obeys($rule(n), what)?;
                let mut s = h.0.lock();
                let old = std::mem::replace(&mut s.settings.$field, n as _);
                if let Err(e) = limits::radiance(&s, what) {
                    s.settings.$field = old;
                    return Err(e);
                }
                s.settings_dirty = true;
                Ok(())
            });
        };
    }
    count_property!("samples", samples, fields::sample_count);
    count_property!("lens_samples", lens_samples, fields::sample_count);
    count_property!("time_samples", time_samples, fields::sample_count);
    count_property!("glossy_samples", glossy_samples, fields::sample_count);
    count_property!("max_depth", max_depth, fields::max_depth);
    count_property!("max_secondary_rays", max_secondary_rays, fields::max_secondary_rays);
    count_property!("width", width, fields::image_size);
    count_property!("height", height, fields::image_size);
    // Any u64 is a seed in a scene file; a script's integers stop at INT::MAX.
    count_property!("seed", seed, |n: INT| match n >= 0 {
        true => Ok(()),
        false => Err(format!("must be in 0..={}, got {n}", INT::MAX)),
    });

    engine.register_get("adaptive", |h: &mut SettingsHandle| match h.0.lock().settings.adaptive {
        Some((threshold, _)) => Dynamic::from_float(threshold),
        None => Dynamic::UNIT,
    });
    engine.register_set("adaptive", |h: &mut SettingsHandle, v: Dynamic| -> ScriptResult<()> {
        let mut s = h.0.lock();
        let old = s.settings.adaptive;
        s.settings.adaptive = match v.is_unit() {
            true => None,
            false => {
                let threshold = finite(&v, "settings.adaptive")?;
                obeys(
                    fields::non_negative(threshold as f32),
                    "settings.adaptive (a threshold, or () for off)",
                )?;
                let depth = s.settings.adaptive.map_or(3, |(_, d)| d);
                Some((threshold, depth))
            }
        };
        if let Err(e) = limits::radiance(&s, "settings.adaptive") {
            s.settings.adaptive = old;
            return Err(e);
        }
        s.settings_dirty = true;
        Ok(())
    });
    engine.register_get("adaptive_depth", |h: &mut SettingsHandle| match h.0.lock().settings.adaptive {
        Some((_, depth)) => Dynamic::from_int(depth as INT),
        None => Dynamic::UNIT,
    });
    engine.register_set("adaptive_depth", |h: &mut SettingsHandle, v: Dynamic| -> ScriptResult<()> {
        let depth = integer(&v, "settings.adaptive_depth")?;
        obeys(fields::adaptive_depth(depth), "settings.adaptive_depth")?;
        let mut s = h.0.lock();
        let Some((threshold, _)) = s.settings.adaptive else {
            return error(
                "settings.adaptive_depth: adaptive supersampling is off; set settings.adaptive first",
            );
        };
        s.settings.adaptive = Some((threshold, depth as u32));
        s.settings_dirty = true;
        Ok(())
    });
}
