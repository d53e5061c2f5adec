//! The rule every authored value obeys, one function per kind of field, in one place: the
//! scene validator ([`super::validate`]) puts the file's field path in front of a broken rule,
//! a script write puts its property name there, and both print the same words (`must be in
//! (0, 180) degrees, got 200`). Each function returns the rule's text when the value breaks it.
//!
//! Rules that span several objects (a pixel's radiance sum, a lens beyond the world's limit)
//! live in [`super::limits`].

use std::fmt;

use glam::{DVec3, Vec3};

use super::error::number;
use super::locate::FieldPath;
use super::rules::{
    coordinate_rule, shininess_rule, DEGENERATE_TOLERANCE, MAX_ADAPTIVE_DEPTH, MAX_COORDINATE, MAX_DEPTH,
    MAX_IMAGE_SIZE, MAX_SAMPLES, MAX_SECONDARY_RAYS, MAX_SHININESS,
};

/// `Err(rule)` when a value breaks its field's rule.
pub type Rule = Result<(), String>;

/// Names of a vector's components.
pub(super) const AXES: [&str; 3] = ["x", "y", "z"];
/// Names of a colour's channels.
pub(super) const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// Any finite number.
pub fn finite(value: f32) -> Rule {
    match value.is_finite() {
        true => Ok(()),
        false => Err(format!("must be a finite number, got {value}")),
    }
}

/// A vector finite in every component.
pub fn finite_vec(value: Vec3) -> Rule {
    match first_component(value, |c| !c.is_finite()) {
        None => Ok(()),
        Some((i, c)) => Err(format!("must be a finite number in every component, got {} = {c}", AXES[i])),
    }
}

/// A point, extent or scale: finite and within ±[`MAX_COORDINATE`] in every component.
pub fn coordinate_vec(value: Vec3) -> Rule {
    finite_vec(value)?;
    match first_component(value, |c| c.abs() > MAX_COORDINATE) {
        None => Ok(()),
        Some((i, c)) => Err(format!("{}, got {} = {c:e}", coordinate_rule(), AXES[i])),
    }
}

/// A position (64-bit): finite and within ±[`MAX_COORDINATE`] in every component, the
/// magnitude compared at 32-bit precision like every other coordinate.
pub fn position(value: DVec3) -> Rule {
    if let Some((i, c)) = first_dcomponent(value, |c| !c.is_finite()) {
        return Err(format!("must be a finite number in every component, got {} = {c}", AXES[i]));
    }
    match first_dcomponent(value, |c| (c as f32).abs() > MAX_COORDINATE) {
        None => Ok(()),
        Some((i, c)) => Err(format!("{}, got {} = {c:e}", coordinate_rule(), AXES[i])),
    }
}

/// A finite value within ±[`MAX_COORDINATE`].
pub fn coordinate(value: f32) -> Rule {
    finite(value)?;
    match value.abs() <= MAX_COORDINATE {
        true => Ok(()),
        false => Err(format!("{}, got {value:e}", coordinate_rule())),
    }
}

/// A finite vector other than zero.
pub fn non_zero_vec(value: Vec3) -> Rule {
    finite_vec(value)?;
    match value == Vec3::ZERO {
        true => Err("must be non-zero, got (0, 0, 0)".into()),
        false => Ok(()),
    }
}

/// A finite value in `[0, 1]`.
pub fn unit_interval(value: f32) -> Rule {
    finite(value)?;
    match (0.0..=1.0).contains(&value) {
        true => Ok(()),
        false => Err(format!("must be in [0, 1], got {value}")),
    }
}

/// A colour in `[0, 1]` in every channel (a reflectance such as `kd`).
pub fn unit_channels(value: Vec3) -> Rule {
    finite_vec(value)?;
    match first_component(value, |c| !(0.0..=1.0).contains(&c)) {
        None => Ok(()),
        Some((i, c)) => Err(format!("must be in [0, 1] in every channel, got {} = {c}", CHANNELS[i])),
    }
}

/// A colour `>= 0` in every channel (light, emission, absorption).
pub fn non_negative_channels(value: Vec3) -> Rule {
    finite_vec(value)?;
    match first_component(value, |c| c < 0.0) {
        None => Ok(()),
        Some((i, c)) => Err(format!("must be >= 0 in every channel, got {} = {c}", CHANNELS[i])),
    }
}

/// A finite value `>= 0` (a lens radius, a light's intensity, an adaptive threshold).
pub fn non_negative(value: f32) -> Rule {
    finite(value)?;
    match value >= 0.0 {
        true => Ok(()),
        false => Err(format!("must be >= 0, got {value}")),
    }
}

/// A finite value `> 0` (a focus distance, an index of refraction).
pub fn positive(value: f32) -> Rule {
    finite(value)?;
    match value > 0.0 {
        true => Ok(()),
        false => Err(format!("must be > 0, got {value}")),
    }
}

/// The vertical field of view: in (0, 180) degrees.
pub fn fov_deg(value: f32) -> Rule {
    finite(value)?;
    match value > 0.0 && value < 180.0 {
        true => Ok(()),
        false => Err(format!("must be in (0, 180) degrees, got {value}")),
    }
}

/// The camera's pose: `look_at` differs from `position` and `up` is not parallel to the view
/// direction. The error names the field that breaks it (`look_at` or `up`).
pub fn view(position: DVec3, look_at: DVec3, up: Vec3) -> Result<(), (&'static str, String)> {
    let view = look_at - position;
    if view == DVec3::ZERO {
        return Err(("look_at", format!("must differ from `position`, both are {}", dvec(look_at))));
    }
    finite_vec(up).map_err(|rule| ("up", rule))?;
    if up == Vec3::ZERO {
        return Err(("up", "must be non-zero, got (0, 0, 0)".into()));
    }
    let sine = up.as_dvec3().normalize().cross(view.normalize()).length();
    if sine < DEGENERATE_TOLERANCE {
        let rule = format!(
            "must not be parallel to the view direction `look_at - position` = {}, got {}",
            vec(view.as_vec3()),
            vec(up)
        );
        return Err(("up", rule));
    }
    Ok(())
}

/// An image side: 1..=[`MAX_IMAGE_SIZE`] pixels.
pub fn image_size(size: i64) -> Rule {
    in_range(size, 1, MAX_IMAGE_SIZE, " pixels")
}

/// A sample count: 1..=[`MAX_SAMPLES`].
pub fn sample_count(samples: i64) -> Rule {
    in_range(samples, 1, MAX_SAMPLES, "")
}

/// The reflection and refraction depth: 0..=[`MAX_DEPTH`].
pub fn max_depth(depth: i64) -> Rule {
    in_range(depth, 0, MAX_DEPTH, "")
}

/// Secondary rays per camera sample: 1..=[`MAX_SECONDARY_RAYS`].
pub fn max_secondary_rays(rays: i64) -> Rule {
    in_range(rays, 1, MAX_SECONDARY_RAYS, "")
}

/// The deepest adaptive subdivision: 1..=[`MAX_ADAPTIVE_DEPTH`].
pub fn adaptive_depth(depth: i64) -> Rule {
    in_range(depth, 1, MAX_ADAPTIVE_DEPTH, "")
}

fn in_range(value: i64, lo: u32, hi: u32, unit: &str) -> Rule {
    match (i64::from(lo)..=i64::from(hi)).contains(&value) {
        true => Ok(()),
        false => Err(format!("must be in {lo}..={hi}{unit}, got {value}")),
    }
}

/// The Phong exponent: in [0, [`MAX_SHININESS`]].
pub fn shininess(value: f32) -> Rule {
    non_negative(value)?;
    match value <= MAX_SHININESS {
        true => Ok(()),
        false => Err(format!("{}, got {}", shininess_rule(), number(value.into()))),
    }
}

/// Transmittance: a grey `kt` is one number in [0, 1], a tinted one is in [0, 1] per channel.
pub fn kt(kt: Vec3) -> Rule {
    match is_grey(kt) {
        true => unit_interval(kt.x),
        false => unit_channels(kt),
    }
}

/// Energy: `kr + kt <= 1` (in `kt`'s largest channel), allowing for rounding in sums such as
/// `0.08 + 0.92`.
pub fn kr_plus_kt(kr: f32, kt: Vec3) -> Rule {
    let largest = kt.max_element();
    if kr + largest <= 1.0 + 4.0 * f32::EPSILON {
        return Ok(());
    }
    let channel = if is_grey(kt) { String::new() } else { " in its largest channel".to_owned() };
    Err(format!("`kr + kt` must be <= 1{channel}, got {kr} + {largest} = {}", kr + largest))
}

fn is_grey(v: Vec3) -> bool {
    v.x == v.y && v.y == v.z
}

/// The index and value of the first component for which `bad` holds.
fn first_component(value: Vec3, bad: impl Fn(f32) -> bool) -> Option<(usize, f32)> {
    value.to_array().into_iter().enumerate().find(|&(_, c)| bad(c))
}

/// [`first_component`] of a 64-bit vector.
fn first_dcomponent(value: DVec3, bad: impl Fn(f64) -> bool) -> Option<(usize, f64)> {
    value.to_array().into_iter().enumerate().find(|&(_, c)| bad(c))
}

/// A vector as RON writes it: `(1, 0.5, -2)`.
pub(super) fn vec(value: Vec3) -> String {
    format!("({}, {}, {})", value.x, value.y, value.z)
}

/// A 64-bit vector as RON writes it.
pub(super) fn dvec(value: DVec3) -> String {
    format!("({}, {}, {})", value.x, value.y, value.z)
}

// Broken rules under their field paths -----------------------------------------------------

/// The first rule a scene breaks: which field, and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Violation {
    /// The offending field, e.g. `objects[2].shape.radius`.
    pub path: FieldPath,
    /// What is wrong and what is allowed, e.g. `must be > 0, got -1`.
    pub rule: String,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "field `{}`: {}", self.path, self.rule)
    }
}

impl std::error::Error for Violation {}

/// A field's check: `Err` holds the first rule broken, under the field's path.
pub type Check = Result<(), Violation>;

/// A field name or a list index under a path.
pub(super) trait Child {
    fn under(self, path: &FieldPath) -> FieldPath;
}

impl Child for &str {
    fn under(self, path: &FieldPath) -> FieldPath {
        path.clone().field(self)
    }
}

impl Child for usize {
    fn under(self, path: &FieldPath) -> FieldPath {
        path.clone().index(self)
    }
}

pub(super) fn fail(path: &FieldPath, child: impl Child, rule: String) -> Check {
    Err(Violation { path: child.under(path), rule })
}

/// A field's value rule under the field's path.
pub(super) fn check(path: &FieldPath, child: impl Child, rule: Rule) -> Check {
    rule.map_err(|rule| Violation { path: child.under(path), rule })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rule_names_the_allowed_range_and_the_value_got() {
        assert_eq!(fov_deg(200.0).unwrap_err(), "must be in (0, 180) degrees, got 200");
        assert_eq!(fov_deg(f32::NAN).unwrap_err(), "must be a finite number, got NaN");
        assert_eq!(image_size(0).unwrap_err(), "must be in 1..=16384 pixels, got 0");
        assert_eq!(sample_count(-3).unwrap_err(), "must be in 1..=4096, got -3");
        assert_eq!(max_depth(65).unwrap_err(), "must be in 0..=64, got 65");
        assert_eq!(
            unit_channels(Vec3::new(0.5, 1.2, 0.0)).unwrap_err(),
            "must be in [0, 1] in every channel, got g = 1.2"
        );
        assert_eq!(positive(0.0).unwrap_err(), "must be > 0, got 0");
        assert_eq!(
            kr_plus_kt(0.5, Vec3::splat(0.6)).unwrap_err(),
            "`kr + kt` must be <= 1, got 0.5 + 0.6 = 1.1"
        );
        assert!(kr_plus_kt(0.5, Vec3::new(0.6, 0.1, 0.1)).unwrap_err().contains("in its largest channel"));
        assert!(kr_plus_kt(0.08, Vec3::splat(0.92)).is_ok());
    }

    #[test]
    fn values_on_the_edges_of_their_ranges_are_accepted() {
        assert!(fov_deg(179.9).is_ok() && fov_deg(180.0).is_err() && fov_deg(0.0).is_err());
        assert!(image_size(1).is_ok() && image_size(16384).is_ok() && image_size(16385).is_err());
        assert!(max_depth(0).is_ok() && sample_count(0).is_err() && sample_count(4096).is_ok());
        assert!(unit_interval(0.0).is_ok() && unit_interval(1.0).is_ok() && unit_interval(-0.0).is_ok());
        assert!(non_negative(0.0).is_ok() && positive(f32::MIN_POSITIVE).is_ok());
        assert!(shininess(1e4).is_ok() && shininess(1.0001e4).is_err() && shininess(-1.0).is_err());
    }

    #[test]
    fn the_view_rule_names_the_field_that_breaks_it() {
        let (p, ahead) = (DVec3::ZERO, DVec3::Z);
        assert_eq!(view(p, p, Vec3::Y).unwrap_err().0, "look_at");
        assert_eq!(view(p, ahead, Vec3::ZERO).unwrap_err(), ("up", "must be non-zero, got (0, 0, 0)".into()));
        assert_eq!(view(p, ahead, Vec3::Z).unwrap_err().0, "up");
        assert!(view(p, ahead, Vec3::Y).is_ok());
    }
}
