//! Conversions from Rhai values to engine values, with errors that say what was expected.
//!
//! Scripts mix integers and floats freely (`vec3(0, 1.5, 2)`, `camera().fov = 40`), so every
//! numeric parameter of the API accepts either and converts here. Errors are runtime errors
//! without a position: Rhai attaches the position of the call or assignment that failed.

use glam::DVec3;
use rhai::{Dynamic, EvalAltResult, FLOAT, INT};

use super::path::Path;
use super::scene::{CameraHandle, EntityHandle, SettingsHandle};
use super::texture::TextureHandle;

/// What API functions return: a value or a Rhai runtime error.
pub type ScriptResult<T> = Result<T, Box<EvalAltResult>>;

/// A runtime error with `message` (Rhai adds the position).
pub fn error<T>(message: impl Into<String>) -> ScriptResult<T> {
    Err(message.into().into())
}

/// The script name of `value`'s type: `vec3`, `path`, `entity`, `texture` rather than Rust paths.
pub fn type_name(value: &Dynamic) -> &'static str {
    if value.is::<DVec3>() {
        "vec3"
    } else if value.is::<Path>() {
        "path"
    } else if value.is::<EntityHandle>() {
        "entity"
    } else if value.is::<CameraHandle>() {
        "camera"
    } else if value.is::<SettingsHandle>() {
        "settings"
    } else if value.is::<TextureHandle>() {
        "texture"
    } else {
        value.type_name()
    }
}

/// `value` as a vector, named `what` in the error.
pub fn vector(value: &Dynamic, what: &str) -> ScriptResult<DVec3> {
    match value.clone().try_cast::<DVec3>() {
        Some(v) => Ok(v),
        None => error(format!("{what} must be a vec3, e.g. vec3(0, 1, 2), got {}", type_name(value))),
    }
}

/// `value` as a float: an integer or a float, named `what` in the error.
pub fn number(value: &Dynamic, what: &str) -> ScriptResult<f64> {
    if let Ok(f) = value.as_float() {
        return Ok(f);
    }
    if let Ok(i) = value.as_int() {
        return Ok(i as f64);
    }
    error(format!("{what} must be a number, got {}", type_name(value)))
}

/// `value` as a finite float.
pub fn finite(value: &Dynamic, what: &str) -> ScriptResult<f64> {
    let f = number(value, what)?;
    match f.is_finite() {
        true => Ok(f),
        false => error(format!("{what} must be a finite number, got {f}")),
    }
}

/// `value` as an integer; a float is accepted when it is a whole number.
pub fn integer(value: &Dynamic, what: &str) -> ScriptResult<INT> {
    if let Ok(i) = value.as_int() {
        return Ok(i);
    }
    if let Ok(f) = value.as_float() {
        let f = f as FLOAT;
        if f.fract() == 0.0 && f.abs() < 2f64.powi(53) {
            return Ok(f as INT);
        }
        return error(format!("{what} must be a whole number, got {f}"));
    }
    error(format!("{what} must be a whole number, got {}", type_name(value)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_and_floats_are_numbers_and_strings_are_not() {
        assert_eq!(number(&Dynamic::from_int(3), "x").unwrap(), 3.0);
        assert_eq!(number(&Dynamic::from_float(2.5), "x").unwrap(), 2.5);
        let e = number(&Dynamic::from("a"), "fov").unwrap_err();
        assert!(e.to_string().contains("fov must be a number, got string"), "{e}");
        assert!(finite(&Dynamic::from_float(f64::NAN), "x").is_err());
        assert_eq!(integer(&Dynamic::from_float(4.0), "n").unwrap(), 4);
        assert!(integer(&Dynamic::from_float(4.5), "n").is_err());
    }
}
