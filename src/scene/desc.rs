//! A described scene: the scene file as written ([`SceneFile`]) and, side by side, the assets
//! it names, loaded ([`SceneAssets`]: meshes with their grids, the texture table). Loading
//! ([`super::load_scene`], [`super::SceneBuilder`]) makes one; spawning a World
//! ([`super::spawn_world`]) reads both halves.
//!
//! The file's fields read through the description (`scene.camera`, `scene.objects`), as the
//! description is its file plus what the file names; the assets are `scene.assets`.

use std::ops::{Deref, DerefMut};
use std::path::PathBuf;
use std::sync::Arc;

use super::format::SceneFile;
use super::mesh::MeshLibrary;
use crate::texture::{Texture, TextureId};

/// A scene file and the assets it names, loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneDesc {
    /// The file as written (and validated).
    pub file: SceneFile,
    /// What the file names, loaded from disk.
    pub assets: SceneAssets,
}

/// The assets a scene file names, loaded: not part of the file's text.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneAssets {
    /// The meshes the objects name, loaded and gridded.
    pub meshes: MeshLibrary,
    /// The textures of the file's `textures`, in order, then the images of the meshes' `.mtl`
    /// libraries.
    pub texture_table: Arc<[Texture]>,
    /// Where in `texture_table` each `.mtl` library image went, by its path.
    pub library_textures: Vec<(PathBuf, TextureId)>,
}

impl Default for SceneAssets {
    fn default() -> Self {
        Self {
            meshes: MeshLibrary::default(),
            texture_table: Arc::from(Vec::new()),
            library_textures: Vec::new(),
        }
    }
}

impl SceneDesc {
    /// A scene file with no assets loaded: for scenes whose objects name no mesh and whose
    /// materials name no texture (spawning a mesh object needs its loaded mesh).
    pub fn without_assets(file: SceneFile) -> Self {
        Self { file, assets: SceneAssets::default() }
    }
}

impl Deref for SceneDesc {
    type Target = SceneFile;

    fn deref(&self) -> &SceneFile {
        &self.file
    }
}

impl DerefMut for SceneDesc {
    fn deref_mut(&mut self) -> &mut SceneFile {
        &mut self.file
    }
}
