//! The scene's textures: their rules ([`check_textures`], and materials' references to them,
//! [`check_references`]), and loading them into the engine's table ([`load_textures`]): image
//! files read relative to the scene, each file decoded once however many textures name it.
//!
//! ```ron
//! textures: [
//!     (name: "tiles", kind: Checker(a: (0.9, 0.9, 0.85), b: (0.2, 0.2, 0.25)), scale: (0.5, 0.5)),
//!     (name: "wood", kind: Image(file: "wood.png", wrap: Repeat), rotate_deg: 90),
//! ],
//! materials: [(name: "floor", kd: (1, 1, 1), kd_texture: Some("tiles"))],
//! ```

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use super::desc::SceneDesc;
use super::error::{shown, SceneError};
use super::fields::{self, check, fail, Violation};
use super::format::{MaterialDesc, SceneFile, TextureDesc, TextureKindDesc};
use super::locate::{position_of, FieldPath};
use crate::texture::{Raster, Texture, UvTransform};

/// Largest accepted number of noise octaves.
pub const MAX_OCTAVES: u32 = 16;

type Check = Result<(), Violation>;

/// The rules of `textures`: unique, non-empty names, finite transforms with non-zero scales,
/// colours ≥ 0, octaves in 1..=[`MAX_OCTAVES`], a non-empty image file name.
pub fn check_textures(root: &FieldPath, textures: &[TextureDesc]) -> Check {
    let mut names: HashMap<&str, usize> = HashMap::new();
    for (i, texture) in textures.iter().enumerate() {
        let path = root.clone().field("textures").index(i);
        check_texture(&path, texture)?;
        if let Some(first) = names.insert(&texture.name, i) {
            let rule = format!(
                "duplicate texture name `{}`, already used by textures[{first}]",
                shown(&texture.name)
            );
            return fail(&path, "name", rule);
        }
    }
    Ok(())
}

fn check_texture(path: &FieldPath, texture: &TextureDesc) -> Check {
    if texture.name.trim().is_empty() {
        return fail(path, "name", "must not be empty".into());
    }
    // Variant names are transparent to paths: `textures[0].kind.file`.
    let variant = path.clone().field("kind");
    match &texture.kind {
        TextureKindDesc::Image { file, .. } => {
            if file.trim().is_empty() {
                return fail(&variant, "file", "must name an image file (PNG, JPEG or EXR)".into());
            }
        }
        TextureKindDesc::Checker { a, b }
        | TextureKindDesc::Stripes { a, b }
        | TextureKindDesc::Gradient { a, b } => {
            check(&variant, "a", fields::non_negative_channels(*a))?;
            check(&variant, "b", fields::non_negative_channels(*b))?;
        }
        TextureKindDesc::Noise { a, b, octaves, .. } => {
            check(&variant, "a", fields::non_negative_channels(*a))?;
            check(&variant, "b", fields::non_negative_channels(*b))?;
            if !(1..=MAX_OCTAVES).contains(octaves) {
                return fail(&variant, "octaves", format!("must be in 1..={MAX_OCTAVES}, got {octaves}"));
            }
        }
    }
    for (name, value) in [("scale", texture.scale), ("offset", texture.offset)] {
        if let Some(c) = value.to_array().into_iter().find(|c| !c.is_finite()) {
            return fail(path, name, format!("must be a finite number in every component, got {c}"));
        }
    }
    if texture.scale.to_array().contains(&0.0) {
        return fail(
            path,
            "scale",
            format!("must be non-zero in every component, got ({}, {})", texture.scale.x, texture.scale.y),
        );
    }
    check(path, "rotate_deg", fields::finite(texture.rotate_deg))
}

/// A material's texture names must name textures of the scene.
pub fn check_references(path: &FieldPath, material: &MaterialDesc, textures: &[TextureDesc]) -> Check {
    let named = [
        ("kd_texture", &material.kd_texture),
        ("ks_texture", &material.ks_texture),
        ("bump_texture", &material.bump_texture),
    ];
    for (field, name) in named {
        let Some(name) = name else { continue };
        if !textures.iter().any(|t| &t.name == name) {
            let known: Vec<String> = textures.iter().map(|t| format!("`{}`", shown(&t.name))).collect();
            let known = if known.is_empty() {
                "the scene defines no `textures`".to_owned()
            } else {
                format!("defined: {}", known.join(", "))
            };
            return fail(path, field, format!("names no texture `{}` ({known})", shown(name)));
        }
    }
    Ok(())
}

impl TextureDesc {
    /// The texture's (u, v) transform.
    pub fn transform(&self) -> UvTransform {
        UvTransform { scale: self.scale, offset: self.offset, rotate_deg: self.rotate_deg }
    }
}

/// The image files the scene's textures name, in order of first mention, each once.
pub fn texture_files(desc: &SceneFile) -> Vec<String> {
    let mut files: Vec<String> = Vec::new();
    for t in &desc.textures {
        if let TextureKindDesc::Image { file, .. } = &t.kind {
            if !files.contains(file) {
                files.push(file.clone());
            }
        }
    }
    files
}

/// Builds `scene.assets.texture_table`: procedural textures from their parameters, image textures
/// decoded from their files (relative to `base`; one decode per file and colour space).
/// Errors name the scene's `file` field and say why the image could not be used. Also checks
/// that every mesh drawn with a textured material has texture coordinates.
pub fn load_textures(scene: &mut SceneDesc, base: &Path, text: &str, origin: &str) -> Result<(), SceneError> {
    let located = |field: FieldPath, rule: String| {
        let (line, col) = position_of(text, &field).unwrap_or((1, 1));
        SceneError::Invalid { path: origin.to_owned(), line, col, field: field.to_string(), rule }
    };
    let mut decoded: HashMap<(String, bool), Arc<Raster>> = HashMap::new();
    let mut table = Vec::with_capacity(scene.textures.len());
    for (i, t) in scene.textures.iter().enumerate() {
        let transform = t.transform();
        let texture = match &t.kind {
            TextureKindDesc::Image { file, wrap, colour_space } => {
                let key = (file.clone(), *colour_space == crate::texture::ColourSpace::Linear);
                let raster = match decoded.get(&key) {
                    Some(raster) => raster.clone(),
                    None => {
                        let path = super::mesh::resolve(base, file);
                        let raster = read_raster(&path, *colour_space).map_err(|rule| {
                            let field =
                                FieldPath::root().field("textures").index(i).field("kind").field("file");
                            located(field, rule)
                        })?;
                        let raster = Arc::new(raster);
                        decoded.insert(key, raster.clone());
                        raster
                    }
                };
                Texture::Image { raster, wrap: *wrap, transform }
            }
            TextureKindDesc::Checker { a, b } => Texture::Checker { a: *a, b: *b, transform },
            TextureKindDesc::Stripes { a, b } => Texture::Stripes { a: *a, b: *b, transform },
            TextureKindDesc::Gradient { a, b } => Texture::Gradient { a: *a, b: *b, transform },
            TextureKindDesc::Noise { a, b, octaves, seed } => {
                Texture::Noise { a: *a, b: *b, octaves: *octaves, seed: *seed, transform }
            }
        };
        table.push(texture);
    }
    let meshes = scene.assets.meshes.assets();
    scene.assets.library_textures = super::mesh_materials::load_library_textures(&meshes, &mut table)
        .map_err(|rule| {
            let i = scene.objects.iter().position(|o| o.shape.mesh_key().is_some_and(|k| k.2)).unwrap_or(0);
            located(
                FieldPath::root().field("objects").index(i).field("shape").field("file"),
                format!("cannot load mesh: {rule}"),
            )
        })?;
    scene.assets.texture_table = Arc::from(table);
    check_mesh_uvs(scene).map_err(|v| located(v.path, v.rule))
}

/// A textured material on a mesh without `vt` coordinates would show one colour: refused, for
/// the object's material and (with `materials: FromFile`) its library's.
fn check_mesh_uvs(scene: &SceneDesc) -> Check {
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(key @ (file, _, from_file)) = object.shape.mesh_key() else { continue };
        let Some((_, asset)) = scene.assets.meshes.get_key(key) else { continue };
        if !asset.data.uvs.is_empty() {
            continue;
        }
        let textured =
            |m: &MaterialDesc| m.kd_texture.is_some() || m.ks_texture.is_some() || m.bump_texture.is_some();
        let own = scene.materials.iter().find(|m| m.name == object.material).filter(|m| textured(m));
        let library = asset.data.materials.iter().filter(|_| from_file).find(|m| {
            let overridden = scene.materials.iter().find(|d| d.name == m.name);
            overridden.map_or(m.map_kd.is_some() || m.map_bump.is_some(), textured)
        });
        let name = match (own, library) {
            (Some(m), _) => m.name.clone(),
            (None, Some(m)) => m.name.clone(),
            (None, None) => continue,
        };
        let path = FieldPath::root().field("objects").index(i);
        let rule = format!(
            "is textured (material `{}`) but the mesh `{}` has no texture coordinates (`vt` lines)",
            shown(&name),
            shown(file)
        );
        return fail(&path, "material", rule);
    }
    Ok(())
}

fn read_raster(path: &Path, space: crate::texture::ColourSpace) -> Result<Raster, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read texture {}: {e}", path.display()))?;
    Raster::decode(path, &bytes, space).map_err(|e| format!("cannot use texture {}: {e}", path.display()))
}
