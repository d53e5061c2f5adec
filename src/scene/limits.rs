//! The rules on what fields produce together, checked once each field has passed its own rule
//! in [`super::validate`] (and the meshes are loaded):
//!
//! - **World-space extent.** Every object's bounds, after its transform (radius × scale,
//!   vertices, box corners and mesh bounds scaled, rotated and translated), and every area
//!   light's corners lie within ±[`MAX_COORDINATE`]: each coordinate is fine alone, but a
//!   sphere of radius 1e17 scaled by 1e3 is not.
//! - **Lens.** Every lens point (`position` ± `aperture`) and the focus point (`position` +
//!   `focus_distance` along the view) lie within ±[`MAX_COORDINATE`], so the lens maths
//!   stays finite.
//! - **Camera samples.** A pixel's camera samples, `settings.aa.samples` ×
//!   `camera.lens.samples` (with an aperture) × `camera.time.samples`, are at most
//!   [`MAX_CAMERA_SAMPLES`], so every sample has a 32-bit index. Time samples count whether or
//!   not anything moves: what moves comes from a script, after this check.
//! - **Radiance.** The radiance a pixel can sum, [`RadianceBudget::values`] ×
//!   [`RadianceBudget::per_value`], is at most [`MAX_RADIANCE_SUM`] in every channel.
//!
//! [`check`] applies them to a scene, in document order (camera, settings and lights,
//! objects); the script API applies the same functions to each write, and the command line to
//! the scene with its overrides applied.

use glam::DVec3;

use super::desc::SceneDesc;
use super::error::SceneError;
use super::locate::{position_of, FieldPath, Segment};
use super::rules::MAX_COORDINATE;
use super::validate::Violation;

mod camera;
mod extent;
mod radiance;

pub use camera::{camera_samples_violation, lens_rule, lens_violation};
pub use extent::{extent_excess, extent_rule, light_extent_violation, object_violation, Extent, Placement};
pub use radiance::{radiance_violation, RadianceBudget};

/// What the camera-samples and radiance rules read of a scene: its render settings (sample
/// counts, depth), the lens radius, and the terms a pixel's radiance sums — background,
/// ambient and each light's colour and intensity, in the scene's order. A scene file gives
/// them ([`PixelTerms::of`]), and so does a script's World, so both apply the same rules.
#[derive(Debug, Clone, PartialEq)]
pub struct PixelTerms {
    /// Sample counts, adaptive and noise-driven sampling, depth.
    pub render: crate::trace::RenderSettings,
    /// Lens radius (lens samples count only with one).
    pub aperture: f32,
    /// Colour of escaping rays.
    pub background: glam::Vec3,
    /// Ambient light.
    pub ambient: glam::Vec3,
    /// Each light's colour and intensity.
    pub lights: Vec<(glam::Vec3, f32)>,
}

impl PixelTerms {
    /// The terms of a scene file.
    pub fn of(scene: &super::format::SceneFile) -> Self {
        Self {
            render: scene.render_settings(),
            aperture: scene.camera.aperture,
            background: scene.settings.background,
            ambient: scene.settings.ambient,
            lights: scene.lights.iter().map(|l| l.terms()).collect(),
        }
    }
}

/// Largest radiance a pixel may sum, in any channel, before dividing by its sample count.
/// Film sums are 32-bit floats (largest ≈ 3.4e38); 1e29 leaves room for the Phong bracket
/// (≤ 2: `kd` ≤ 1 plus `ks` ≤ 1 times a highlight that [`super::rules::MAX_SHININESS`]
/// keeps ≤ 1.01), for an exposure of up to 2^30 in tone mapping, and for 10⁸ lights.
pub const MAX_RADIANCE_SUM: f64 = 1e29;

/// Largest number of camera samples a pixel may take: AA positions × lens points × times
/// (4096², what AA and lens samples at their largest already make).
pub const MAX_CAMERA_SAMPLES: u64 = 1 << 24;

/// Checks the combined rules on a validated scene whose meshes are loaded; the first
/// violation in document order.
///
/// # Examples
/// ```
/// use penumbra::scene::{default_scene, limits::check};
/// let mut scene = default_scene();
/// assert!(check(&scene).is_ok());
/// scene.camera.aperture = 1e30;
/// assert_eq!(check(&scene).unwrap_err().path.to_string(), "camera.aperture");
/// ```
pub fn check(scene: &SceneDesc) -> Result<(), Violation> {
    let root = FieldPath::root();
    if let Some(v) = lens_violation(&scene.camera) {
        return Err(under(&root.clone().field("camera"), v));
    }
    let terms = PixelTerms::of(scene);
    if let Some(v) = camera_samples_violation(&terms) {
        return Err(v);
    }
    if let Some(v) = radiance_violation(&terms) {
        return Err(v);
    }
    for (i, light) in scene.lights.iter().enumerate() {
        if let Some(v) = light_extent_violation(light) {
            return Err(under(&root.clone().field("lights").index(i), v));
        }
    }
    for (i, object) in scene.objects.iter().enumerate() {
        if let Some(v) = object_violation(object, &scene.assets.meshes) {
            return Err(under(&root.clone().field("objects").index(i), v));
        }
    }
    Ok(())
}

/// [`check`] as a [`SceneError`] located in `text` (the scene's source, named `origin`).
pub fn check_located(scene: &SceneDesc, text: &str, origin: &str) -> Result<(), SceneError> {
    check(scene).map_err(|v| located(v, text, origin))
}

/// A violation as a [`SceneError`]: at its field in `text`, or at the nearest enclosing field
/// the text has (a field the command line set may be absent from the file).
pub fn located(v: Violation, text: &str, origin: &str) -> SceneError {
    let segments = v.path.segments();
    let (line, col) = (0..=segments.len())
        .rev()
        .find_map(|n| position_of(text, &path_of(&segments[..n])))
        .unwrap_or((1, 1));
    SceneError::Invalid { path: origin.to_owned(), line, col, field: v.path.to_string(), rule: v.rule }
}

/// [`check`] on a scene the command line has changed: `flags` pairs a field it set (e.g.
/// `settings.aa.samples`) with the flag that set it (`--samples aa=4096`), and every flag whose
/// field the rule names is added to the message. `text` is the scene's source, named `origin`.
pub fn check_overrides(
    desc: &SceneDesc,
    text: &str,
    origin: &str,
    flags: &[(String, String)],
) -> Result<(), SceneError> {
    let Err(mut v) = check(desc) else { return Ok(()) };
    let named: Vec<String> = flags
        .iter()
        .filter(|(field, _)| {
            v.rule.contains(field.as_str()) || v.path.to_string().starts_with(field.as_str())
        })
        .map(|(field, flag)| format!("{field} from `{flag}`"))
        .collect();
    if !named.is_empty() {
        v.rule = format!("{} (the command line set {})", v.rule, named.join(", "));
    }
    Err(located(v, text, origin))
}

fn path_of(segments: &[Segment]) -> FieldPath {
    segments.iter().fold(FieldPath::root(), |p, s| match s {
        Segment::Field(name) => p.field(name),
        Segment::Index(i) => p.index(*i),
    })
}

/// `v` with its path put under `path`.
fn under(path: &FieldPath, v: Violation) -> Violation {
    let mut segments = path.segments().to_vec();
    segments.extend_from_slice(v.path.segments());
    Violation { path: path_of(&segments), rule: v.rule }
}

fn violation(path: &str, rule: String) -> Violation {
    Violation { path: FieldPath::parse(path).unwrap_or_default(), rule }
}

/// Whether `value`, as the engine's 32-bit float, lies within ±[`MAX_COORDINATE`].
fn within(value: f64) -> bool {
    (value as f32).abs() <= MAX_COORDINATE
}

/// The first axis and value of `p` beyond ±[`MAX_COORDINATE`].
fn beyond(p: DVec3) -> Option<(&'static str, f64)> {
    ["x", "y", "z"].into_iter().zip(p.to_array()).find(|&(_, c)| !within(c))
}

#[cfg(test)]
mod tests;
