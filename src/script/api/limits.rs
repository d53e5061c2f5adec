//! The scene format's combined rules ([`crate::scene::limits`]) applied to script writes, on
//! the script's whole view of the scene, so that a write that breaks one fails at its own line:
//! moving or scaling an object beyond ±1e18 in world space, a lens or focus point beyond it,
//! and light, sample counts or depth that would let a pixel's radiance sum overflow.

use glam::DVec3;

use super::convert::{error, ScriptResult};
use super::scene::camera_desc;
use crate::scene::error::number as num;
use crate::scene::format::{AdaptiveSettings, AntiAliasing, LightDesc, Sampling, SceneFile, SettingsDesc};
use crate::scene::limits::{
    camera_samples_violation, extent_excess, extent_rule, lens_violation, radiance_violation, Extent,
    Placement,
};
use crate::scene::locate::Segment;
use crate::script::state::{EntityKind, EntityState, ScriptState};

/// The lens rule on the camera as the script has it.
pub fn lens(state: &ScriptState) -> ScriptResult<()> {
    match lens_violation(&camera_desc(state)) {
        Some(v) => error(format!("camera.{}: {}", v.path, v.rule)),
        None => Ok(()),
    }
}

/// The extent rule on an object as the script has it (lights have none); `what` names the
/// write, e.g. ``entity `ball`: scale``.
pub fn extent(entry: &EntityState, what: &str) -> ScriptResult<()> {
    let EntityKind::Object { pivot, uniform_scale, bounds } = entry.kind else {
        return Ok(());
    };
    let extent = match bounds {
        None => Extent::Plane(pivot),
        Some((min, max)) if uniform_scale => {
            Extent::Ball { centre: 0.5 * (min + max), radius: 0.5 * (max.x - min.x) }
        }
        Some((min, max)) => Extent::corners(min, max),
    };
    let placement =
        Placement { translate: entry.position, rotate_deg: entry.rotation_deg, scale: entry.scale };
    match extent_excess(&extent, &placement) {
        Some((_, axis, value)) => error(format!(
            "{what}: {}, but this puts the object at {axis} = {} (position {}, scale {})",
            extent_rule(),
            num(value),
            entry.position,
            entry.scale
        )),
        None => Ok(()),
    }
}

/// The camera-samples and radiance rules on the scene as the script has it; `what` names the write, e.g.
/// `settings.samples` or ``entity `key`: intensity``.
pub fn radiance(state: &ScriptState, what: &str) -> ScriptResult<()> {
    let lights: Vec<(&str, LightDesc)> = state
        .entities
        .iter()
        .filter_map(|e| {
            let terms = e.light?;
            let colour = terms.colour.as_vec3();
            Some((
                e.name.as_str(),
                LightDesc::Point {
                    position: DVec3::ZERO,
                    colour,
                    intensity: terms.intensity as f32,
                    falloff: Default::default(),
                },
            ))
        })
        .collect();
    let s = &state.settings;
    let mut camera = camera_desc(state);
    camera.lens = Sampling { samples: s.lens_samples, ..Default::default() };
    let scene = SceneFile {
        camera,
        settings: SettingsDesc {
            max_depth: s.max_depth,
            background: s.background,
            ambient: s.ambient,
            aa: AntiAliasing { samples: s.samples, ..Default::default() },
            adaptive: s
                .adaptive
                .map(|(threshold, max_depth)| AdaptiveSettings { threshold: threshold as f32, max_depth }),
            glossy: Sampling { samples: s.glossy_samples, ..Default::default() },
            ..Default::default()
        },
        materials: Vec::new(),
        textures: Vec::new(),
        lights: lights.iter().map(|(_, l)| l.clone()).collect(),
        objects: Vec::new(),
    };
    if let Some(v) = camera_samples_violation(&scene) {
        return error(format!("{what}: {}", script_names(&v.rule)));
    }
    let Some(v) = radiance_violation(&scene) else { return Ok(()) };
    let rule = script_names(&v.rule);
    let field = v.path.to_string();
    let who = match v.path.segments() {
        [_, Segment::Index(i), Segment::Field(f)] => {
            format!("entity `{}`: {f}", lights.get(*i).map_or("?", |(name, _)| name))
        }
        _ => field,
    };
    match who == what {
        true => error(format!("{what}: {rule}")),
        false => error(format!("{what}: {who}: {rule}")),
    }
}

/// A rule's scene-format field names as scripts spell them.
fn script_names(rule: &str) -> String {
    rule.replace("settings.aa.samples", "settings.samples")
        .replace("camera.lens.samples", "settings.lens_samples")
        .replace("camera.time.samples", "settings.time_samples")
        .replace("settings.glossy.samples", "settings.glossy_samples")
}
