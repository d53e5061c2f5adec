//! The rules a [`SceneFile`] must satisfy beyond what serde checks: ranges, geometry and
//! references between materials and objects.
//!
//! [`validate`] stops at the first [`Violation`] in document order (camera, settings,
//! materials, lights, objects; fields in schema order) and names it by [`FieldPath`], which
//! [`super::load`] turns into a line and column. Every rule text says what is wrong and what
//! is allowed, e.g. `must be in [0, 1], got 1.2`. Geometric tolerances are relative to the
//! shape's own size, so a scene means the same at any scale.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use super::error::shown;
use super::fields::{self, dvec, vec, AXES};
use super::format::{AdaptiveSettings, CameraDesc, LightDesc, MaterialDesc, ObjectDesc, SceneFile};
use super::format::{NoiseSettings, Sampling, SettingsDesc, ShapeDesc, ToneMapping, TransformDesc};
use super::locate::FieldPath;
pub use super::rules::*;

pub use super::fields::Violation;
use super::fields::{check, fail, Check, Child};

/// Checks every rule of the scene format, returning the first violation in document order.
///
/// # Examples
/// ```
/// use penumbra::scene::{default_scene, validate::validate};
/// let mut scene = default_scene();
/// assert!(validate(&scene).is_ok());
/// scene.materials[1].ks = 1.2;
/// let violation = validate(&scene).unwrap_err();
/// assert_eq!(violation.path.to_string(), "materials[1].ks");
/// assert_eq!(violation.rule, "must be in [0, 1], got 1.2");
/// ```
pub fn validate(scene: &SceneFile) -> Check {
    let root = FieldPath::root();
    camera(&root.clone().field("camera"), &scene.camera)?;
    settings(&root.clone().field("settings"), &scene.settings)?;
    let mut names: HashMap<&str, usize> = HashMap::new();
    for (i, material_desc) in scene.materials.iter().enumerate() {
        let path = root.clone().field("materials").index(i);
        material(&path, material_desc)?;
        if let Some(first) = names.insert(&material_desc.name, i) {
            let rule = format!(
                "duplicate material name `{}`, already used by materials[{first}]",
                shown(&material_desc.name)
            );
            return fail(&path, "name", rule);
        }
    }
    for (i, material_desc) in scene.materials.iter().enumerate() {
        let path = root.clone().field("materials").index(i);
        super::texture::check_references(&path, material_desc, &scene.textures)?;
    }
    super::texture::check_textures(&root, &scene.textures)?;
    for (i, light_desc) in scene.lights.iter().enumerate() {
        light(&root.clone().field("lights").index(i), light_desc)?;
    }
    let mut object_names: HashMap<&str, usize> = HashMap::new();
    for (i, object) in scene.objects.iter().enumerate() {
        let path = root.clone().field("objects").index(i);
        if let Some(name) = &object.name {
            if name.trim().is_empty() {
                return fail(&path, "name", "must not be empty".into());
            }
            if let Some(first) = object_names.insert(name, i) {
                return fail(
                    &path,
                    "name",
                    format!("duplicate object name `{}`, already used by objects[{first}]", shown(name)),
                );
            }
        }
        self::object(&path, object, &scene.materials)?;
    }
    Ok(())
}

/// The first rule a camera breaks, with a path relative to the camera (e.g. `fov_deg`).
pub fn camera_violation(camera: &CameraDesc) -> Option<Violation> {
    self::camera(&FieldPath::root(), camera).err()
}

/// The first rule a material breaks, with a path relative to the material (e.g. `kd`).
pub fn material_violation(material: &MaterialDesc) -> Option<Violation> {
    self::material(&FieldPath::root(), material).err()
}

fn camera(path: &FieldPath, camera: &CameraDesc) -> Check {
    check(path, "position", fields::position(camera.position))?;
    check(path, "look_at", fields::position(camera.look_at))?;
    if let Err((field, rule)) = fields::view(camera.position, camera.look_at, camera.up) {
        return fail(path, field, rule);
    }
    check(path, "fov_deg", fields::fov_deg(camera.fov_deg))?;
    check(path, "width", fields::image_size(camera.width.into()))?;
    check(path, "height", fields::image_size(camera.height.into()))?;
    check(path, "aperture", fields::non_negative(camera.aperture))?;
    if let Some(distance) = camera.focus_distance {
        check(path, "focus_distance", fields::positive(distance))?;
    }
    if let Some(point) = camera.focus_on {
        check(path, "focus_on", fields::position(point))?;
        if camera.focus_distance.is_some() {
            let rule = "must not be given together with `focus_distance`; give one of them".into();
            return fail(path, "focus_on", rule);
        }
        let depth = (point - camera.position).dot((camera.look_at - camera.position).normalize());
        if depth as f32 <= 0.0 {
            let rule = format!(
                "must be in front of the camera (depth along `look_at - position` > 0), got {} at depth {}",
                dvec(point),
                depth as f32
            );
            return fail(path, "focus_on", rule);
        }
    }
    if let Some((open, close)) = camera.shutter {
        if let Err(rule) = crate::camera::Shutter::new(open, close) {
            return fail(path, "shutter", rule);
        }
    }
    sampling(&path.clone().field("lens"), &camera.lens)?;
    sampling(&path.clone().field("time"), &camera.time)
}

fn settings(path: &FieldPath, settings: &SettingsDesc) -> Check {
    check(path, "max_depth", fields::max_depth(settings.max_depth.into()))?;
    check(path, "min_contribution", fields::unit_interval(settings.min_contribution))?;
    check(path, "background", fields::non_negative_channels(settings.background))?;
    check(path, "ambient", fields::non_negative_channels(settings.ambient))?;
    check(&path.clone().field("aa"), "samples", fields::sample_count(settings.aa.samples.into()))?;
    if let Some(adaptive_desc) = &settings.adaptive {
        adaptive(&path.clone().field("adaptive"), adaptive_desc)?;
    }
    if let Some(noise_desc) = &settings.noise {
        if settings.adaptive.is_some() {
            let rule = "must not be given together with `adaptive`; choose one adaptive mode".into();
            return fail(path, "noise", rule);
        }
        noise(&path.clone().field("noise"), noise_desc)?;
    }
    sampling(&path.clone().field("glossy"), &settings.glossy)?;
    check(path, "max_secondary_rays", fields::max_secondary_rays(settings.max_secondary_rays.into()))?;
    tonemap(&path.clone().field("tonemap"), &settings.tonemap)
}

fn tonemap(path: &FieldPath, t: &ToneMapping) -> Check {
    finite(path, "exposure", t.exposure)?;
    if t.exposure.abs() > MAX_EXPOSURE {
        return fail(
            path,
            "exposure",
            format!("must be in [-{MAX_EXPOSURE}, {MAX_EXPOSURE}] stops, got {}", t.exposure),
        );
    }
    check(path, "white", fields::positive(t.white))
}

fn adaptive(path: &FieldPath, adaptive: &AdaptiveSettings) -> Check {
    check(path, "threshold", fields::non_negative(adaptive.threshold))?;
    check(path, "max_depth", fields::adaptive_depth(adaptive.max_depth.into()))
}

fn noise(path: &FieldPath, noise: &NoiseSettings) -> Check {
    finite(path, "target_error", noise.target_error)?;
    if !(0.0..=1.0).contains(&noise.target_error) {
        let rule =
            format!("must be in [0, 1] (display units; 0.01 is about 2.5/255), got {}", noise.target_error);
        return fail(path, "target_error", rule);
    }
    if !(1..=MAX_NOISE_SAMPLES).contains(&noise.min_samples) {
        let rule = format!("must be in 1..={MAX_NOISE_SAMPLES}, got {}", noise.min_samples);
        return fail(path, "min_samples", rule);
    }
    if !(noise.min_samples..=MAX_NOISE_SAMPLES).contains(&noise.max_samples) {
        let rule = format!(
            "must be in min_samples..={MAX_NOISE_SAMPLES} ({}..={MAX_NOISE_SAMPLES}), got {}",
            noise.min_samples, noise.max_samples
        );
        return fail(path, "max_samples", rule);
    }
    if let Some(limit) = noise.time_limit {
        finite(path, "time_limit", limit)?;
        if limit <= 0.0 {
            return fail(path, "time_limit", format!("must be > 0 seconds, got {limit}"));
        }
    }
    if noise.rounds == Some(0) {
        return fail(path, "rounds", "must be at least 1 (round 0 always runs), got 0".to_owned());
    }
    Ok(())
}

fn sampling(path: &FieldPath, sampling: &Sampling) -> Check {
    check(path, "samples", fields::sample_count(sampling.samples.into()))
}

fn material(path: &FieldPath, material: &MaterialDesc) -> Check {
    if material.name.trim().is_empty() {
        return fail(path, "name", "must not be empty".into());
    }
    check(path, "kd", fields::unit_channels(material.kd))?;
    check(path, "ks", fields::unit_interval(material.ks))?;
    check(path, "shininess", fields::shininess(material.shininess))?;
    check(path, "kr", fields::unit_interval(material.kr))?;
    check(path, "kt", fields::kt(material.kt))?;
    check(path, "kt", fields::kr_plus_kt(material.kr, material.kt))?;
    check(path, "ior", fields::positive(material.ior))?;
    check(path, "glossiness", fields::unit_interval(material.glossiness))?;
    check(path, "emission", fields::non_negative_channels(material.emission))?;
    check(path, "absorption", fields::non_negative_channels(material.absorption))?;
    finite(path, "bump_depth", material.bump_depth)
}

fn light(path: &FieldPath, light: &LightDesc) -> Check {
    let (colour, intensity, samples) = match light {
        LightDesc::Point { position, colour, intensity, .. } => {
            check(path, "position", fields::position(*position))?;
            (colour, intensity, None)
        }
        LightDesc::Spot { position, look_at, cone_deg, soft_deg, colour, intensity, .. } => {
            check(path, "position", fields::position(*position))?;
            check(path, "look_at", fields::position(*look_at))?;
            if look_at == position {
                return fail(path, "look_at", "must differ from `position`".into());
            }
            finite(path, "cone_deg", *cone_deg)?;
            if !(*cone_deg > 0.0 && *cone_deg <= 90.0) {
                return fail(path, "cone_deg", format!("must be in (0, 90] degrees, got {cone_deg}"));
            }
            if let Some(soft) = soft_deg {
                finite(path, "soft_deg", *soft)?;
                if !(0.0..=*cone_deg).contains(soft) {
                    let rule = format!("must be in [0, cone_deg] = [0, {cone_deg}] degrees, got {soft}");
                    return fail(path, "soft_deg", rule);
                }
            }
            (colour, intensity, None)
        }
        LightDesc::Directional { direction, colour, intensity } => {
            check(path, "direction", fields::non_zero_vec(*direction))?;
            (colour, intensity, None)
        }
        LightDesc::Rect { corner, edge_u, edge_v, colour, intensity, samples, .. } => {
            check(path, "corner", fields::position(*corner))?;
            check(path, "edge_u", fields::non_zero_vec(*edge_u))?;
            check(path, "edge_v", fields::non_zero_vec(*edge_v))?;
            let (u, v) = (edge_u.as_dvec3(), edge_v.as_dvec3());
            if u.cross(v).length() < DEGENERATE_TOLERANCE * u.length() * v.length() {
                let rule =
                    format!("must not be parallel to `edge_u` = {}, got {}", vec(*edge_u), vec(*edge_v));
                return fail(path, "edge_v", rule);
            }
            (colour, intensity, Some(samples))
        }
        LightDesc::Disk { centre, normal, radius, colour, intensity, samples, .. } => {
            check(path, "centre", fields::position(*centre))?;
            check(path, "normal", fields::non_zero_vec(*normal))?;
            check(path, "radius", fields::coordinate(*radius))?;
            if *radius <= 0.0 {
                return fail(path, "radius", format!("must be > 0, got {radius}"));
            }
            (colour, intensity, Some(samples))
        }
    };
    check(path, "colour", fields::non_negative_channels(*colour))?;
    check(path, "intensity", fields::non_negative(*intensity))?;
    match samples {
        Some(samples) => check(path, "samples", fields::sample_count((*samples).into())),
        None => Ok(()),
    }
}

// ---------------------------------------------------------------------------------------

pub(super) fn finite(path: &FieldPath, name: &str, value: f32) -> Check {
    check(path, name, fields::finite(value))
}

fn finite_vec(path: &FieldPath, child: impl Child, value: Vec3) -> Check {
    check(path, child, fields::finite_vec(value))
}

fn coordinate_vec(path: &FieldPath, child: impl Child, value: Vec3) -> Check {
    check(path, child, fields::coordinate_vec(value))
}

fn position(path: &FieldPath, child: impl Child, value: DVec3) -> Check {
    check(path, child, fields::position(value))
}

fn coordinate(path: &FieldPath, name: &str, value: f32) -> Check {
    check(path, name, fields::coordinate(value))
}

/// The index and value of the first component for which `bad` holds.
fn first_component(value: Vec3, bad: impl Fn(f32) -> bool) -> Option<(usize, f32)> {
    value.to_array().into_iter().enumerate().find(|&(_, c)| bad(c))
}

/// [`first_component`] of a 64-bit vector.
fn first_dcomponent(value: DVec3, bad: impl Fn(f64) -> bool) -> Option<(usize, f64)> {
    value.to_array().into_iter().enumerate().find(|&(_, c)| bad(c))
}

mod objects;
use objects::object;

#[cfg(test)]
mod tests;
