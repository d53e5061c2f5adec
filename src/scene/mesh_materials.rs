//! Materials from OBJ `.mtl` libraries (`Mesh(file: ..., materials: FromFile)`): their value
//! rules ([`check`]), their images ([`load_library_textures`]), and the block of the material
//! table each mesh object draws its faces from ([`MaterialBlocks`]).
//!
//! A library material becomes a Phong material: `kd` = `Kd` (default 0.8, or 1 under a
//! `map_Kd`), `ks` = the mean of `Ks` (default 0), `shininess` = `Ns` (default 32), `kt` =
//! 1 − `d` (`Tr` read as 1 − `d`), `ior` = `Ni` (default 1.5); `map_Kd` becomes a `kd`
//! texture and `map_bump` (or `bump`) a bump map of depth `-bm` × 0.01 (default 0.01). A scene
//! material of the same name takes its place; faces before any `usemtl` take the object's own
//! material.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::shown;
use super::format::{SceneFile, DEFAULT_BUMP_DEPTH};
use super::rules::MAX_SHININESS;
use crate::geom::mesh::ObjMaterial;
use crate::geom::MeshId;
use crate::math::Vec3;
use crate::store::MaterialId;
use crate::store::MeshAsset;
use crate::texture::{ColourSpace, Raster, Texture, TextureId, UvTransform, Wrap};
use crate::trace::material::{Bump, Maps};
use crate::trace::Material;

/// The value rules of a mesh's library materials; the first broken one as
/// `FILE:LINE: material \`NAME\`: STATEMENT RULE`.
pub fn check(materials: &[ObjMaterial]) -> Result<(), String> {
    for m in materials.iter().filter(|m| !m.name.is_empty()) {
        let fail = |statement: &str, rule: String| {
            Err(format!("{}:{}: material `{}`: {statement} {rule}", m.file.display(), m.line, shown(&m.name)))
        };
        for (statement, colour) in [("Kd", m.kd), ("Ks", m.ks)] {
            if let Some(c) = colour {
                if let Some(v) = c.to_array().into_iter().find(|v| !(0.0..=1.0).contains(v)) {
                    return fail(statement, format!("must be in [0, 1] in every channel, got {v}"));
                }
            }
        }
        if let Some(ns) = m.ns {
            if !(0.0..=MAX_SHININESS).contains(&ns) {
                return fail("Ns", format!("must be in [0, {MAX_SHININESS:e}], got {ns}"));
            }
        }
        if let Some(d) = m.d {
            if !(0.0..=1.0).contains(&d) {
                return fail("d", format!("(opacity) must be in [0, 1], got {d}"));
            }
        }
        if let Some(ni) = m.ni {
            if !(ni > 0.0 && ni.is_finite()) {
                return fail("Ni", format!("(index of refraction) must be > 0, got {ni}"));
            }
        }
        if let Some(bm) = m.bump_multiplier {
            if !bm.is_finite() {
                return fail("map_bump", format!("-bm must be a finite number, got {bm}"));
            }
        }
    }
    Ok(())
}

/// Where a library material's image `map` lies: relative to the library's folder, unless
/// absolute.
pub fn library_path(material: &ObjMaterial, map: &Path) -> PathBuf {
    match map.is_absolute() {
        true => map.to_path_buf(),
        false => material.file.parent().unwrap_or_else(|| Path::new("")).join(map),
    }
}

/// Appends the images the loaded meshes' library materials name (`map_Kd`, `map_bump`) to
/// `table` (a scene's texture table), each file once (sRGB, repeating), and returns where each
/// went, by its path. Errors name the library, its line and the image.
pub fn load_library_textures(
    meshes: &[Arc<MeshAsset>],
    table: &mut Vec<Texture>,
) -> Result<Vec<(PathBuf, TextureId)>, String> {
    let mut loaded: HashMap<PathBuf, TextureId> = HashMap::new();
    let mut library_textures = Vec::new();
    for asset in meshes {
        for m in &asset.data.materials {
            for map in [&m.map_kd, &m.map_bump].into_iter().flatten() {
                let path = library_path(m, map);
                if loaded.contains_key(&path) {
                    continue;
                }
                let at = |e: String| {
                    format!("{}:{}: material `{}`: {e}", m.file.display(), m.line, shown(&m.name))
                };
                let bytes = std::fs::read(&path)
                    .map_err(|e| at(format!("cannot read texture {}: {e}", path.display())))?;
                let raster = Raster::decode(&path, &bytes, ColourSpace::Srgb)
                    .map_err(|e| at(format!("cannot use texture {}: {e}", path.display())))?;
                let id = TextureId(table.len() as u32);
                table.push(Texture::Image {
                    raster: Arc::new(raster),
                    wrap: Wrap::Repeat,
                    transform: UvTransform::default(),
                });
                loaded.insert(path.clone(), id);
                library_textures.push((path, id));
            }
        }
    }
    Ok(library_textures)
}

/// The engine material of a library material, its images looked up in `textures` (from
/// [`load_library_textures`]).
pub fn engine_material(m: &ObjMaterial, textures: &[(PathBuf, TextureId)]) -> Material {
    let find = |map: &Option<PathBuf>| {
        let path = library_path(m, map.as_deref()?);
        textures.iter().find(|(p, _)| *p == path).map(|&(_, id)| id)
    };
    let kd_map = find(&m.map_kd);
    let kt = 1.0 - m.d.unwrap_or(1.0);
    Material {
        kd: m.kd.unwrap_or(if kd_map.is_some() { Vec3::ONE } else { Vec3::splat(0.8) }),
        ks: m.ks.map_or(0.0, |ks| ks.element_sum() / 3.0),
        shininess: m.ns.unwrap_or(32.0),
        kt: Vec3::splat(kt),
        ior: m.ni.unwrap_or(1.5),
        maps: Maps {
            kd: kd_map,
            ks: None,
            bump: find(&m.map_bump).map(|texture| Bump {
                texture,
                depth: m.bump_multiplier.unwrap_or(1.0) * DEFAULT_BUMP_DEPTH,
            }),
        },
        ..Material::default()
    }
}

/// The material-table blocks of mesh objects drawn with their file's materials: one block per
/// (mesh, object material), in the order of the mesh's library materials, so a face's
/// material is the block's first id plus its index ([`crate::store::MeshEntry::face_material`]).
#[derive(Debug, Default)]
pub struct MaterialBlocks {
    blocks: HashMap<(MeshId, String), MaterialId>,
}

impl MaterialBlocks {
    /// The first id of the block of mesh `mesh` (its library `materials`) drawn by an object
    /// whose own material is `fallback`, appending the block to `table` and `names` the first
    /// time: each library material, or the scene's material of the same name, or `fallback`
    /// for the faces with none.
    #[allow(clippy::too_many_arguments)]
    pub fn block(
        &mut self,
        mesh: MeshId,
        file: &str,
        materials: &[ObjMaterial],
        fallback: &str,
        scene: &SceneFile,
        library_textures: &[(PathBuf, TextureId)],
        table: &mut Vec<Material>,
        names: &mut Vec<String>,
    ) -> MaterialId {
        let key = (mesh, fallback.to_owned());
        if let Some(&id) = self.blocks.get(&key) {
            return id;
        }
        let first = MaterialId(table.len() as u32);
        let named =
            |name: &str| scene.materials.iter().find(|d| d.name == name).map(|d| d.material(&scene.textures));
        for m in materials {
            let (material, name) = match m.name.as_str() {
                "" => (named(fallback).unwrap_or_default(), format!("{file}: faces without usemtl")),
                name => (
                    named(name).unwrap_or_else(|| engine_material(m, library_textures)),
                    format!("{file}: {name}"),
                ),
            };
            table.push(material);
            names.push(name);
        }
        self.blocks.insert(key, first);
        first
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wood() -> ObjMaterial {
        ObjMaterial {
            name: "wood".into(),
            kd: Some(Vec3::new(0.5, 0.4, 0.3)),
            ks: Some(Vec3::new(0.3, 0.2, 0.1)),
            ns: Some(40.0),
            d: Some(0.25),
            ni: Some(1.33),
            map_kd: Some("wood.png".into()),
            map_bump: Some("wood.png".into()),
            bump_multiplier: Some(0.5),
            file: "models/table.mtl".into(),
            line: 4,
        }
    }

    #[test]
    fn a_library_material_becomes_the_phong_material_its_statements_describe() {
        let textures = vec![(PathBuf::from("models/wood.png"), TextureId(3))];
        let m = engine_material(&wood(), &textures);
        assert_eq!(m.kd, Vec3::new(0.5, 0.4, 0.3));
        assert!((m.ks - 0.2).abs() < 1e-7);
        assert_eq!((m.shininess, m.kt, m.ior, m.kr), (40.0, Vec3::splat(0.75), 1.33, 0.0));
        assert_eq!(m.maps.kd, Some(TextureId(3)));
        assert_eq!(m.maps.bump, Some(Bump { texture: TextureId(3), depth: 0.5 * DEFAULT_BUMP_DEPTH }));
        // Unset statements take the defaults; a map without Kd is not darkened.
        let bare = ObjMaterial { name: "bare".into(), ..ObjMaterial::default() };
        let b = engine_material(&bare, &[]);
        assert_eq!((b.kd, b.ks, b.shininess, b.kt, b.ior), (Vec3::splat(0.8), 0.0, 32.0, Vec3::ZERO, 1.5));
        let mapped = ObjMaterial { map_kd: Some("wood.png".into()), file: "models/t.mtl".into(), ..bare };
        assert_eq!(engine_material(&mapped, &textures).kd, Vec3::ONE);
    }

    #[test]
    fn out_of_range_statements_are_refused_with_the_library_line_and_material() {
        assert_eq!(check(&[wood()]), Ok(()));
        let bad = [
            (
                ObjMaterial { kd: Some(Vec3::new(0.5, 1.5, 0.0)), ..wood() },
                "Kd must be in [0, 1] in every channel, got 1.5",
            ),
            (ObjMaterial { ns: Some(2e4), ..wood() }, "Ns must be in [0, 1e4], got 20000"),
            (ObjMaterial { d: Some(-0.1), ..wood() }, "d (opacity) must be in [0, 1], got -0.1"),
            (ObjMaterial { ni: Some(0.0), ..wood() }, "Ni (index of refraction) must be > 0, got 0"),
        ];
        for (m, rule) in bad {
            assert_eq!(check(&[m]), Err(format!("models/table.mtl:4: material `wood`: {rule}")));
        }
        // The default material of faces without `usemtl` is not checked (it is not from a file).
        assert_eq!(check(&[ObjMaterial::default()]), Ok(()));
    }

    #[test]
    fn a_block_lists_the_library_in_order_with_scene_overrides_and_the_fallback() {
        let desc = crate::scene::default_scene();
        let library = [
            ObjMaterial { name: "wood".into(), ..wood() },
            ObjMaterial::default(),
            ObjMaterial { name: desc.materials[1].name.clone(), ..wood() },
        ];
        let (mut table, mut names) = (vec![Material::default()], vec!["first".to_owned()]);
        let mut blocks = MaterialBlocks::default();
        let fallback = desc.materials[0].name.clone();
        let first = blocks.block(
            MeshId(0),
            "t.obj",
            &library,
            &fallback,
            &desc.file,
            &desc.assets.library_textures,
            &mut table,
            &mut names,
        );
        assert_eq!(first, MaterialId(1));
        assert_eq!(table.len(), 4);
        assert_eq!(table[1], engine_material(&library[0], &[]));
        assert_eq!(
            table[2],
            desc.materials[0].material(&desc.textures),
            "faces without usemtl: the object's"
        );
        assert_eq!(table[3], desc.materials[1].material(&desc.textures), "overridden by the scene's");
        // The same mesh and fallback again: the same block, nothing appended.
        let again = blocks.block(
            MeshId(0),
            "t.obj",
            &library,
            &fallback,
            &desc.file,
            &desc.assets.library_textures,
            &mut table,
            &mut names,
        );
        assert_eq!((again, table.len()), (first, 4));
    }
}
