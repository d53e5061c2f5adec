//! The meshes a scene names: each distinct `(file, smooth)` pair is read once (OBJ through
//! [`super::obj`]), gets its object-space grid, and is shared by every object that names it.
//!
//! ```ron
//! (name: "bunny", shape: Mesh(file: "bunny_res3.obj", smooth: true), material: "clay",
//!  transform: (translate: (0, -0.6, 0), scale: (10, 10, 10))),
//! ```
//!
//! Paths are relative to the scene file. A file that cannot be read or parsed is reported at
//! the scene's `file` field, with the OBJ file's own line in the rule.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::SceneError;
use super::format::SceneFile;
use super::locate::{position_of, FieldPath};
use super::obj::{load_obj, load_obj_with_materials};
use crate::accel::MESH_LAMBDA;
use crate::geom::MeshId;
use crate::store::MeshAsset;

/// One loaded mesh and the key it was loaded under.
#[derive(Debug, Clone)]
struct Entry {
    file: String,
    smooth: bool,
    /// Loaded with its file's materials (`materials: FromFile`).
    from_file: bool,
    asset: Arc<MeshAsset>,
}

/// The loaded meshes of a scene, in first-use order (which defines their [`MeshId`]s).
#[derive(Debug, Clone, Default)]
pub struct MeshLibrary {
    entries: Vec<Entry>,
}

impl PartialEq for MeshLibrary {
    /// Two libraries are equal when they hold the same files loaded the same way.
    fn eq(&self, other: &Self) -> bool {
        self.entries.len() == other.entries.len()
            && self
                .entries
                .iter()
                .zip(&other.entries)
                .all(|(a, b)| a.file == b.file && a.smooth == b.smooth && a.from_file == b.from_file)
    }
}

impl MeshLibrary {
    /// The id and asset of `file` loaded with `smooth` (without its file's materials), if
    /// loaded.
    pub fn get(&self, file: &str, smooth: bool) -> Option<(MeshId, &Arc<MeshAsset>)> {
        self.get_key((file, smooth, false))
    }

    /// The id and asset loaded under `(file, smooth, from_file)` ([`ShapeDesc::mesh_key`](super::ShapeDesc::mesh_key)), if
    /// loaded.
    pub fn get_key(
        &self,
        (file, smooth, from_file): (&str, bool, bool),
    ) -> Option<(MeshId, &Arc<MeshAsset>)> {
        self.entries
            .iter()
            .position(|e| e.file == file && e.smooth == smooth && e.from_file == from_file)
            .map(|i| (MeshId(i as u32), &self.entries[i].asset))
    }

    /// Every asset, in id order.
    pub fn assets(&self) -> Vec<Arc<MeshAsset>> {
        self.entries.iter().map(|e| e.asset.clone()).collect()
    }

    /// Number of distinct meshes.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when the scene has no meshes.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Seconds spent building the meshes' grids: +0.0 for a scene without meshes.
    pub fn grid_build_seconds(&self) -> f64 {
        // Not `.sum()`: std's float sum starts at -0.0, which prints as "-0.00".
        self.entries.iter().fold(0.0, |total, e| total + e.asset.build_seconds)
    }

    /// Adds an already loaded asset under `(file, smooth)` (for scenes built in code).
    pub fn insert(&mut self, file: impl Into<String>, smooth: bool, asset: Arc<MeshAsset>) -> MeshId {
        self.insert_key(file, smooth, false, asset)
    }

    /// Adds an already loaded asset under `(file, smooth, from_file)`.
    pub fn insert_key(
        &mut self,
        file: impl Into<String>,
        smooth: bool,
        from_file: bool,
        asset: Arc<MeshAsset>,
    ) -> MeshId {
        let file = file.into();
        if let Some((id, _)) = self.get_key((&file, smooth, from_file)) {
            return id;
        }
        self.entries.push(Entry { file, smooth, from_file, asset });
        MeshId(self.entries.len() as u32 - 1)
    }
}

/// Loads every mesh `scene` names, relative to `base` (the scene file's folder). `text` and
/// `origin` are the scene's source and name, for error positions.
pub fn load_meshes(
    scene: &SceneFile,
    base: &Path,
    text: &str,
    origin: &str,
) -> Result<MeshLibrary, SceneError> {
    let mut meshes = MeshLibrary::default();
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(key @ (file, smooth, from_file)) = object.shape.mesh_key() else {
            continue;
        };
        if meshes.get_key(key).is_some() {
            continue;
        }
        let path = resolve(base, file);
        let loaded = match from_file {
            false => load_obj(&path, smooth).map_err(|e| e.to_string()),
            true => {
                load_obj_with_materials(&path, smooth).map_err(|e| e.to_string()).and_then(|(data, _)| {
                    super::mesh_materials::check(&data.materials)?;
                    Ok(data)
                })
            }
        };
        let data = loaded.map_err(|error| {
            let field = FieldPath::root().field("objects").index(i).field("shape").field("file");
            let (line, col) = position_of(text, &field).unwrap_or((1, 1));
            SceneError::Invalid {
                path: origin.to_owned(),
                line,
                col,
                field: field.to_string(),
                rule: format!("cannot load mesh: {error}"),
            }
        })?;
        let asset = MeshAsset::new(file, data, MESH_LAMBDA);
        meshes.insert_key(file, smooth, from_file, Arc::new(asset));
    }
    Ok(meshes)
}

/// `file` relative to `base`, unless absolute.
pub(super) fn resolve(base: &Path, file: &str) -> PathBuf {
    let p = Path::new(file);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::mesh::icosphere;

    #[test]
    fn a_library_without_meshes_spent_plus_zero_seconds_on_grids() {
        let seconds = MeshLibrary::default().grid_build_seconds();
        assert_eq!(seconds.to_bits(), 0.0f64.to_bits(), "{seconds:?} is not +0.0");
    }

    #[test]
    fn grid_build_seconds_add_up_over_the_assets() {
        let mut library = MeshLibrary::default();
        let asset = Arc::new(MeshAsset::new("ball", icosphere(crate::math::Vec3::ZERO, 1.0, 1), MESH_LAMBDA));
        library.insert("ball.obj", true, asset.clone());
        library.insert("ball.obj", false, asset.clone());
        assert_eq!(library.grid_build_seconds(), 2.0 * asset.build_seconds);
    }
}
