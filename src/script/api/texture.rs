//! The scene's textures as scripts see them: `texture("water")` is a handle whose `offset`,
//! `scale` and `rotation` are the texture's (u, v) transform, as the scene's `textures` entry
//! gives it (`(s, t) = R(rotation)·((u, v) ⊙ scale) + offset`), so a script can scroll water
//! or turn a pattern:
//!
//! ```rhai
//! fn frame(t) {
//!     let water = texture("water");
//!     water.offset = [0.25 * t, 0];      // or vec3(0.25 * t, 0, 0)
//!     water.offset.y += 0.01;            // reads as vec3(u, v, 0)
//!     water.scale = 2;                   // one number: the same in u and v
//!     water.rotation = 10 * t;           // degrees, counter-clockwise
//! }
//! ```
//!
//! A pair of coordinates is written as an array `[u, v]` or a `vec3(u, v, 0)` (z must be 0:
//! textures have two coordinates) and reads back as `vec3(u, v, 0)`, so vector arithmetic and
//! `lerp` work on it. Every write is checked with the scene format's rules for `textures`
//! (finite in 32-bit floats, scale non-zero) and fails naming the texture and the property,
//! e.g. ``texture `water`: scale must be non-zero in every component, got (0, 1)``. Also
//! `has_texture(name)` and `texture_names()`.

use glam::{DVec2, DVec3, Vec3};
use rhai::{Array, Dynamic, Engine, ImmutableString};

use super::convert::{error, number, type_name, ScriptResult};
use super::properties::unknown_name;
use crate::scene::format::{TextureDesc, TextureKindDesc};
use crate::scene::locate::FieldPath;
use crate::scene::texture::check_textures;
use crate::script::lent::{Lent, LentWorld};
use crate::texture::UvTransform;
use crate::world::resources::Textures;

/// Texture properties scripts can write.
pub const TEXTURE_PROPERTIES: &[&str] = &["offset", "scale", "rotation"];

/// Handle on one named texture.
#[derive(Clone)]
pub struct TextureHandle {
    lent: LentWorld,
    index: usize,
    name: ImmutableString,
}

/// The scene's texture names, in table order (none without a texture table).
fn names(lent: &mut Lent) -> ScriptResult<Vec<String>> {
    Ok(lent.scene()?.world.get_resource::<Textures>().map(|t| t.names.clone()).unwrap_or_default())
}

/// Registers `texture(name)`, `has_texture(name)`, `texture_names()` and the texture handle's
/// properties over the World `lent` holds during calls.
pub fn register(engine: &mut Engine, lent: &LentWorld) {
    engine.register_type_with_name::<TextureHandle>("texture");
    let l = lent.clone();
    engine.register_fn("texture", move |name: ImmutableString| -> ScriptResult<TextureHandle> {
        let index = find(&names(&mut *l.get()?)?, &name)?;
        Ok(TextureHandle { lent: l.clone(), index, name })
    });
    let l = lent.clone();
    engine.register_fn("has_texture", move |name: ImmutableString| -> ScriptResult<bool> {
        Ok(names(&mut *l.get()?)?.iter().any(|n| *n == name))
    });
    let l = lent.clone();
    engine.register_fn("texture_names", move || -> ScriptResult<Array> {
        Ok(names(&mut *l.get()?)?.into_iter().map(Dynamic::from).collect())
    });
    engine.register_fn("to_string", |t: &mut TextureHandle| format!("texture(\"{}\")", t.name));
    engine.register_get("name", |t: &mut TextureHandle| t.name.to_string());

    engine.register_get("offset", |t: &mut TextureHandle| t.read(|u| u.offset.as_dvec2().extend(0.0)));
    engine.register_set("offset", |t: &mut TextureHandle, v: Dynamic| -> ScriptResult<()> {
        t.write("offset", |u, what| {
            u.offset = uv_pair(&v, what, false)?.as_vec2();
            Ok(())
        })
    });
    engine.register_get("scale", |t: &mut TextureHandle| t.read(|u| u.scale.as_dvec2().extend(0.0)));
    engine.register_set("scale", |t: &mut TextureHandle, v: Dynamic| -> ScriptResult<()> {
        t.write("scale", |u, what| {
            u.scale = uv_pair(&v, what, true)?.as_vec2();
            Ok(())
        })
    });
    engine.register_get("rotation", |t: &mut TextureHandle| t.read(|u| f64::from(u.rotate_deg)));
    engine.register_set("rotation", |t: &mut TextureHandle, v: Dynamic| -> ScriptResult<()> {
        t.write("rotation", |u, what| {
            u.rotate_deg = number(&v, what)? as f32;
            Ok(())
        })
    });
}

/// The index of the texture called `name` among `names`, or an error that suggests the
/// closest name and lists the names there are.
fn find(names: &[String], name: &str) -> ScriptResult<usize> {
    match names.iter().position(|n| n == name) {
        Some(index) => Ok(index),
        None => error(unknown_name("texture", name, names.iter().map(String::as_str))),
    }
}

/// A (u, v) pair: `[u, v]`, `vec3(u, v, 0)`, or (`uniform`) one number for both.
fn uv_pair(value: &Dynamic, what: &str, uniform: bool) -> ScriptResult<DVec2> {
    let expected = match uniform {
        true => "[u, v], vec3(u, v, 0) or one number",
        false => "[u, v] or vec3(u, v, 0)",
    };
    if let Some(v) = value.clone().try_cast::<DVec3>() {
        return match v.z {
            0.0 => Ok(v.truncate()),
            z => error(format!("{what} must be {expected} (textures have two coordinates), got z = {z}")),
        };
    }
    if let Some(array) = value.clone().try_cast::<Array>() {
        return match array.as_slice() {
            [u, v] => Ok(DVec2::new(number(u, what)?, number(v, what)?)),
            _ => error(format!("{what} must be {expected}, got an array of {} elements", array.len())),
        };
    }
    if uniform && (value.is_int() || value.is_float()) {
        return Ok(DVec2::splat(number(value, what)?));
    }
    error(format!("{what} must be {expected}, got {}", type_name(value)))
}

/// Checks a texture's transform with the scene format's rules for `textures`; the error
/// names the texture and `field`.
fn check(name: &str, t: &UvTransform, field: &str) -> ScriptResult<()> {
    let desc = TextureDesc {
        name: name.to_owned(),
        kind: TextureKindDesc::Checker { a: Vec3::ONE, b: Vec3::ZERO },
        scale: t.scale,
        offset: t.offset,
        rotate_deg: t.rotate_deg,
    };
    match check_textures(&FieldPath::root(), std::slice::from_ref(&desc)) {
        Ok(()) => Ok(()),
        Err(v) => error(format!("texture `{name}`: {field} {}", v.rule)),
    }
}

impl TextureHandle {
    fn read<T>(&self, f: impl FnOnce(&UvTransform) -> T) -> ScriptResult<T> {
        let mut lent = self.lent.get()?;
        let scene = lent.scene()?;
        match scene.world.get_resource::<Textures>().and_then(|t| t.table.get(self.index)) {
            Some(texture) => Ok(f(texture.transform())),
            None => error(format!("texture `{}` is not in the scene", self.name)),
        }
    }

    /// Sets `field` with `set` (given ``texture `name`: field`` for its errors), keeping the
    /// new transform only if the scene format's rules accept it. The table is replaced (a new
    /// `Arc`, the other textures shared) only when the transform differs from the table's in
    /// the `f32` the tracer uses, so a frame that writes the values already there keeps the
    /// same bits in every snapshot.
    fn write(
        &self,
        field: &str,
        set: impl FnOnce(&mut UvTransform, &str) -> ScriptResult<()>,
    ) -> ScriptResult<()> {
        let what = format!("texture `{}`: {field}", self.name);
        let mut next = self.read(|u| *u)?;
        set(&mut next, &what)?;
        check(&self.name, &next, field)?;
        let mut lent = self.lent.get()?;
        let mut scene = lent.scene()?;
        let index = self.index;
        let unchanged =
            scene.world.get_resource::<Textures>().and_then(|t| t.table.get(index)).map(|t| *t.transform());
        if unchanged == Some(next) {
            return Ok(());
        }
        scene.change_resource(|textures: &mut Textures| {
            let mut table = textures.table.to_vec();
            table[index] = table[index].with_transform(next);
            textures.table = table.into();
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(script: &str, uniform: bool) -> Result<DVec2, String> {
        let value = crate::script::api::testing::eval::<Dynamic>(script);
        uv_pair(&value, "texture `w`: offset", uniform).map_err(|e| e.to_string())
    }

    #[test]
    fn pairs_are_arrays_flat_vectors_or_for_scales_one_number() {
        assert_eq!(pair("[1, 2.5]", false), Ok(DVec2::new(1.0, 2.5)));
        assert_eq!(pair("vec3(0.5, -1, 0)", false), Ok(DVec2::new(0.5, -1.0)));
        assert_eq!(pair("3", true), Ok(DVec2::splat(3.0)));
        let e = pair("3", false).unwrap_err();
        assert!(e.contains("texture `w`: offset must be [u, v] or vec3(u, v, 0), got i64"), "{e}");
        let e = pair("vec3(1, 2, 3)", false).unwrap_err();
        assert!(e.contains("textures have two coordinates), got z = 3"), "{e}");
        let e = pair("[1, 2, 3]", true).unwrap_err();
        assert!(e.contains("got an array of 3 elements"), "{e}");
        let e = pair("[1, \"a\"]", false).unwrap_err();
        assert!(e.contains("must be a number, got string"), "{e}");
    }

    #[test]
    fn the_scene_formats_rules_apply_in_f32() {
        let uv = |offset: DVec2, scale: DVec2, rotation_deg: f64| UvTransform {
            offset: offset.as_vec2(),
            scale: scale.as_vec2(),
            rotate_deg: rotation_deg as f32,
        };
        assert!(check("w", &uv(DVec2::new(0.5, 3.0), DVec2::ONE, 45.0), "offset").is_ok());
        let e = check("w", &uv(DVec2::new(f64::NAN, 0.0), DVec2::ONE, 0.0), "offset").unwrap_err();
        assert!(e.to_string().contains("texture `w`: offset must be a finite number"), "{e}");
        // Finite in f64, infinite in f32.
        assert!(check("w", &uv(DVec2::new(1e300, 0.0), DVec2::ONE, 0.0), "offset").is_err());
        let e = check("w", &uv(DVec2::ZERO, DVec2::new(1.0, 1e-50), 0.0), "scale").unwrap_err();
        assert!(e.to_string().contains("texture `w`: scale must be non-zero in every component"), "{e}");
        assert!(check("w", &uv(DVec2::ZERO, DVec2::ONE, f64::INFINITY), "rotation").is_err());
    }
}
