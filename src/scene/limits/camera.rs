//! The camera's combined rules: the lens and the focus point within the coordinate limit, and
//! a pixel's camera samples within [`MAX_CAMERA_SAMPLES`].

use glam::DVec3;

use super::PixelTerms;
use super::{beyond, violation, MAX_CAMERA_SAMPLES};
use crate::scene::error::number as num;
use crate::scene::format::CameraDesc;
use crate::scene::rules::MAX_COORDINATE;
use crate::scene::validate::Violation;

/// The lens rule for a camera whose fields are each valid; the path is relative to the camera
/// (`aperture`, `focus_distance`).
pub fn lens_violation(camera: &CameraDesc) -> Option<Violation> {
    lens_rule(camera.position, camera.look_at, camera.aperture, camera.focus_distance)
}

/// The lens rule on a camera's parts (a script's camera checks it on the World's rig): the
/// lens and the focus point at `focus_distance` (when given) within the coordinate limit.
pub fn lens_rule(
    position: DVec3,
    look_at: DVec3,
    aperture: f32,
    focus_distance: Option<f32>,
) -> Option<Violation> {
    let (camera_aperture, aperture) = (aperture, f64::from(aperture));
    if aperture > 0.0 {
        let reach = position.abs() + DVec3::splat(aperture);
        if let Some((axis, c)) = beyond(reach) {
            let rule = format!(
                "the lens must lie within ±{MAX_COORDINATE:e} (`position` ± `aperture` on every axis), \
                 but |position.{axis}| + aperture = {}; got aperture {}",
                num(c),
                num(camera_aperture.into())
            );
            return Some(violation("aperture", rule));
        }
    }
    if let Some(distance) = focus_distance {
        let forward = (look_at - position).normalize_or_zero();
        let focus = position + forward * f64::from(distance);
        if let Some((axis, c)) = beyond(focus) {
            let rule = format!(
                "the focus point `position + focus_distance × view direction` must lie within \
                 ±{MAX_COORDINATE:e}, but its {axis} is {}; got focus_distance {}",
                num(c),
                num(distance.into())
            );
            return Some(violation("focus_distance", rule));
        }
    }
    None
}

/// The camera-samples rule: `settings.aa.samples` × `camera.lens.samples` (with an aperture)
/// × `camera.time.samples` ≤ [`MAX_CAMERA_SAMPLES`], reported at `camera.time.samples` (the
/// only factor that can push the product past it). Adaptive renders trace at most
/// `camera.lens.samples` (with an aperture) × `camera.time.samples` rays per lattice point (a
/// pixel corner), so the AA samples do not count there.
pub fn camera_samples_violation(terms: &PixelTerms) -> Option<Violation> {
    let r = &terms.render;
    let lens = if terms.aperture > 0.0 { u64::from(r.lens.samples) } else { 1 };
    let per_position = match r.adaptive {
        Some(_) => lens,
        None => u64::from(r.aa.samples) * lens,
    };
    let n = per_position * u64::from(r.time.samples);
    (n > MAX_CAMERA_SAMPLES).then(|| {
        let aa = match r.adaptive {
            Some(_) => "a pixel corner (settings.adaptive) takes".to_owned(),
            None => format!("a pixel takes settings.aa.samples {} ×", r.aa.samples),
        };
        let rule = format!(
            "{aa} camera.lens.samples {lens} (with camera.aperture > 0) × camera.time.samples {} = {n} \
             camera samples, more than {MAX_CAMERA_SAMPLES}; lower one of them",
            r.time.samples
        );
        violation("camera.time.samples", rule)
    })
}
