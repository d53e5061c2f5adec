//! The scene format's combined rules ([`crate::scene::limits`]) applied to script writes, on
//! the World as the write leaves it, so that a write that breaks one fails at its own line:
//! moving or scaling an object beyond ±1e18 in world space, a lens or focus point beyond it,
//! and light, sample counts or depth that would let a pixel's radiance sum overflow.

use bevy_ecs::prelude::{Entity, World};

use super::convert::{error, ScriptResult};
use crate::scene::error::number as num;
use crate::scene::limits::{
    camera_samples_violation, extent_excess, extent_rule, lens_rule, radiance_violation, Extent, PixelTerms,
    Placement,
};
use crate::scene::locate::Segment;
use crate::script::lent::{kind, EntityKind};
use crate::world::components::{LightTerms, Name, Transform};
use crate::world::resources::{CameraRig, Focus, SceneSettings};

/// The lens rule on the World's camera.
pub fn lens(world: &World) -> ScriptResult<()> {
    let rig = world.resource::<CameraRig>();
    let distance = match rig.focus {
        Focus::Distance(d) => Some(d),
        _ => None,
    };
    match lens_rule(rig.position, rig.look_at, rig.aperture, distance) {
        Some(v) => error(format!("camera.{}: {}", v.path, v.rule)),
        None => Ok(()),
    }
}

/// The extent rule on an object as the World places it (lights have none); `what` names the
/// write, e.g. ``entity `ball`: scale``.
pub fn extent(world: &World, entity: Entity, what: &str) -> ScriptResult<()> {
    let Some(EntityKind::Object { pivot, uniform_scale, bounds, .. }) = kind(world, entity) else {
        return Ok(());
    };
    let Some(t) = world.get::<Transform>(entity) else { return Ok(()) };
    let extent = match bounds {
        None => Extent::Plane(pivot),
        Some((min, max)) if uniform_scale => {
            Extent::Ball { centre: 0.5 * (min + max), radius: 0.5 * (max.x - min.x) }
        }
        Some((min, max)) => Extent::corners(min, max),
    };
    match extent_excess(&extent, &Placement::of_transform(t)) {
        Some((_, axis, value)) => error(format!(
            "{what}: {}, but this puts the object at {axis} = {} (position {}, scale {})",
            extent_rule(),
            num(value),
            t.translation,
            t.scale.as_dvec3()
        )),
        None => Ok(()),
    }
}

/// The camera-samples and radiance rules on the World's settings, camera and lights, as the
/// scene file has them ([`PixelTerms`]); `what` names the write, e.g. `settings.samples` or
/// ``entity `key`: intensity``.
pub fn radiance(world: &World, what: &str) -> ScriptResult<()> {
    let mut lights: Vec<(Entity, &str, LightTerms)> = world
        .iter_entities()
        .filter_map(|e| Some((e.id(), e.get::<Name>().map_or("?", |n| n.as_str()), *e.get::<LightTerms>()?)))
        .collect();
    lights.sort_unstable_by_key(|(e, _, _)| *e);
    let settings = world.resource::<SceneSettings>();
    let terms = PixelTerms {
        render: settings.render,
        aperture: world.resource::<CameraRig>().aperture,
        background: settings.background,
        ambient: settings.ambient,
        lights: lights.iter().map(|(_, _, t)| (t.colour, t.intensity)).collect(),
    };
    if let Some(v) = camera_samples_violation(&terms) {
        return error(format!("{what}: {}", script_names(&v.rule)));
    }
    let Some(v) = radiance_violation(&terms) else { return Ok(()) };
    let rule = script_names(&v.rule);
    let field = v.path.to_string();
    let who = match v.path.segments() {
        [_, Segment::Index(i), Segment::Field(f)] => {
            format!("entity `{}`: {f}", lights.get(*i).map_or("?", |(_, name, _)| name))
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
