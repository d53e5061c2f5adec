//! The files a frame is made from: the scene, the script and every mesh the scene names, each
//! with where it was read and the SHA-256 of its bytes.
//!
//! Every output records its [`Inputs`] (the `penumbra.inputs` metadata entry, and a frames
//! folder's job), so that `penumbra info --rerender` can refuse to re-render from changed files
//! and `penumbra status` can say *which* input made a frame stale. The fingerprint of a frame
//! covers the role and hash of every file, never its path: moving unchanged files keeps frames
//! current.
//!
//! Names are kept as the user wrote them (the scene and script as given on the command line, a
//! mesh as the scene names it, relative to the scene's folder), beside the absolute path, so a
//! re-render works from any folder and can be pointed at moved files (`--scene`, `--script`).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::{SceneDesc, ShapeDesc, DEFAULT_SCENE_ORIGIN, DEFAULT_SCENE_SOURCE};

/// Hex SHA-256 of `bytes`.
///
/// # Examples
/// ```
/// # use penumbra::scene::inputs::sha256_hex;
/// assert_eq!(&sha256_hex(b"abc")[..8], "ba7816bf");
/// ```
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// What an input file is to the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InputRole {
    /// The RON scene file (or the built-in scene).
    Scene,
    /// The Rhai script of an animation or sweep.
    Script,
    /// A Wavefront OBJ file the scene names.
    Mesh,
    /// A material library (`.mtl`) a mesh's materials come from.
    Library,
    /// An image a texture is read from.
    Texture,
}

impl std::fmt::Display for InputRole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            InputRole::Scene => "scene",
            InputRole::Script => "script",
            InputRole::Mesh => "mesh",
            InputRole::Library => "material library",
            InputRole::Texture => "texture",
        })
    }
}

/// One file a frame was made from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputFile {
    /// What the file is to the frame.
    pub role: InputRole,
    /// The name as the user wrote it: a scene or script as given on the command line, a mesh
    /// as the scene names it (relative to the scene's folder unless absolute).
    pub name: String,
    /// Where it was read, absolute (`None` for the built-in scene).
    pub path: Option<PathBuf>,
    /// Hex SHA-256 of its bytes.
    pub sha256: String,
}

impl InputFile {
    /// The file `name`, read at `path`, with the hash of `bytes` (its contents).
    pub fn new(role: InputRole, name: impl Into<String>, path: &Path, bytes: &[u8]) -> Self {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        Self { role, name: name.into(), path: Some(path), sha256: sha256_hex(bytes) }
    }

    /// Reads the file at `path` and records it as `name`.
    pub fn read(role: InputRole, name: impl Into<String>, path: &Path) -> Result<Self, InputError> {
        let bytes = std::fs::read(path).map_err(|source| InputError::Read {
            role,
            path: path.to_path_buf(),
            source,
        })?;
        Ok(Self::new(role, name, path, &bytes))
    }

    /// `role name`, e.g. `mesh bunny.obj`, for messages.
    pub fn label(&self) -> String {
        format!("{} {}", self.role, self.name)
    }
}

/// An input that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file could not be read.
    #[error("{}: cannot read the {role}: {source}", path.display())]
    Read {
        /// What it is.
        role: InputRole,
        /// Where it was looked for.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// How a recorded input compares with the file now at its place.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum InputCheck {
    /// Same bytes.
    Unchanged,
    /// The file is gone (or unreadable).
    Missing {
        /// Where it was looked for.
        path: PathBuf,
    },
    /// Other bytes.
    Changed {
        /// Where it was read.
        path: PathBuf,
        /// The hash of its bytes now.
        sha256: String,
    },
}

/// Every file a frame is made from, in a fixed order: the scene, then the script (if any), then
/// the meshes in the order the scene first names them, then their material libraries, then
/// the texture images (the scene's textures', then the libraries').
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Inputs {
    /// The files.
    pub files: Vec<InputFile>,
}

impl Inputs {
    /// The inputs of the built-in default scene (compiled in: no file).
    pub fn builtin() -> Self {
        Self {
            files: vec![InputFile {
                role: InputRole::Scene,
                name: DEFAULT_SCENE_ORIGIN.to_owned(),
                path: None,
                sha256: sha256_hex(DEFAULT_SCENE_SOURCE.as_bytes()),
            }],
        }
    }

    /// The inputs of `desc`, loaded from `scene` (named `name`) whose bytes were `source`: the
    /// scene and every mesh file it names, each read and hashed.
    pub fn of_scene(name: &str, scene: &Path, source: &[u8], desc: &SceneDesc) -> Result<Self, InputError> {
        let mut files = vec![InputFile::new(InputRole::Scene, name, scene, source)];
        let base = scene.parent().unwrap_or_else(|| Path::new(""));
        for mesh in mesh_names(desc) {
            files.push(InputFile::read(InputRole::Mesh, mesh.clone(), &base.join(&mesh))?);
        }
        for (role, name) in asset_names(desc, base) {
            files.push(InputFile::read(role, name.clone(), &base.join(&name))?);
        }
        Ok(Self { files })
    }

    /// Adds the script `name`, read at `path` with contents `source`, after the scene.
    pub fn with_script(mut self, name: &str, path: &Path, source: &[u8]) -> Self {
        let at = self.files.iter().take_while(|f| f.role == InputRole::Scene).count();
        self.files.insert(at, InputFile::new(InputRole::Script, name, path, source));
        self
    }

    /// The file of `role` (the first, for meshes).
    pub fn get(&self, role: InputRole) -> Option<&InputFile> {
        self.files.iter().find(|f| f.role == role)
    }

    /// The fingerprint of the contents: role and hash of every file in order (no paths, so
    /// moving unchanged files changes nothing).
    pub fn fingerprint(&self) -> String {
        let mut h = Sha256::new();
        for f in &self.files {
            let role = f.role.to_string();
            for part in [role.as_bytes(), f.sha256.as_bytes()] {
                h.update((part.len() as u64).to_le_bytes());
                h.update(part);
            }
        }
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The inputs as one line of JSON (the `penumbra.inputs` metadata value).
    pub fn to_json(&self) -> String {
        // Cannot fail: plain strings and paths (non-UTF-8 paths are written lossily).
        serde_json::to_string(&self.files).unwrap_or_else(|_| "[]".into())
    }

    /// Inputs from [`Inputs::to_json`]'s text.
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text).map(|files| Self { files })
    }
}

/// Compares a recorded input with the file at `path` now.
pub fn check(recorded: &InputFile, path: &Path) -> InputCheck {
    match std::fs::read(path) {
        Err(_) => InputCheck::Missing { path: path.to_path_buf() },
        Ok(bytes) => {
            let sha256 = sha256_hex(&bytes);
            match sha256 == recorded.sha256 {
                true => InputCheck::Unchanged,
                false => InputCheck::Changed { path: path.to_path_buf(), sha256 },
            }
        }
    }
}

/// The mesh files `desc` names, each once, in the order of first mention.
pub fn mesh_names(desc: &SceneDesc) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for object in &desc.objects {
        if let ShapeDesc::Mesh { file, .. } = &object.shape {
            if !names.contains(file) {
                names.push(file.clone());
            }
        }
    }
    names
}

/// The material libraries of the loaded meshes and every texture image (the scene's, then the
/// libraries'), each once in order of first mention, named relative to `base` (the scene's
/// folder) where they lie under it.
pub fn asset_names(desc: &SceneDesc, base: &Path) -> Vec<(InputRole, String)> {
    // Compared as absolute paths: the scene may have been loaded through another spelling of
    // its folder (`scenes`, `./scenes`, `/work/scenes`).
    let absolute = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let base_abs = absolute(base);
    let relative = |p: &Path| {
        let p = absolute(p);
        p.strip_prefix(&base_abs).unwrap_or(&p).to_string_lossy().into_owned()
    };
    let mut names: Vec<(InputRole, String)> = Vec::new();
    let mut add = |role: InputRole, name: String| {
        if !names.iter().any(|(_, n)| *n == name) {
            names.push((role, name));
        }
    };
    let assets = desc.assets.meshes.assets();
    for m in assets.iter().flat_map(|a| &a.data.materials) {
        if !m.file.as_os_str().is_empty() {
            add(InputRole::Library, relative(&m.file));
        }
    }
    for file in super::texture::texture_files(desc) {
        add(InputRole::Texture, file);
    }
    for m in assets.iter().flat_map(|a| &a.data.materials) {
        for map in [&m.map_kd, &m.map_bump].into_iter().flatten() {
            add(InputRole::Texture, relative(&super::mesh_materials::library_path(m, map)));
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

    fn scene_with_meshes(dir: &Path) -> (PathBuf, SceneDesc) {
        write(dir, "a.obj", TRIANGLE);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        write(&dir.join("sub"), "b.obj", TRIANGLE);
        let text = r#"Scene(
            camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 40, width: 8, height: 8),
            materials: [(name: "m", kd: (1, 1, 1))],
            lights: [Point(position: (0, 5, -5))],
            objects: [
                (name: "a", shape: Mesh(file: "a.obj"), material: "m"),
                (name: "b", shape: Mesh(file: "sub/b.obj", smooth: false), material: "m"),
                (name: "a2", shape: Mesh(file: "a.obj", smooth: false), material: "m"),
            ],
        )"#;
        let scene = write(dir, "s.ron", text);
        (scene.clone(), crate::scene::load_scene(&scene).unwrap())
    }

    /// The inputs of `desc`, loaded from `scene` as `s.ron`.
    fn inputs_of(scene: &Path, desc: &SceneDesc) -> Inputs {
        Inputs::of_scene("s.ron", scene, &std::fs::read(scene).unwrap(), desc).unwrap()
    }

    #[test]
    fn a_scene_lists_itself_and_each_mesh_file_once_in_order() {
        let tmp = tempfile::tempdir().unwrap();
        let (scene, desc) = scene_with_meshes(tmp.path());
        let inputs = inputs_of(&scene, &desc);
        let names: Vec<_> = inputs.files.iter().map(|f| (f.role, f.name.as_str())).collect();
        assert_eq!(
            names,
            [(InputRole::Scene, "s.ron"), (InputRole::Mesh, "a.obj"), (InputRole::Mesh, "sub/b.obj")]
        );
        assert_eq!(inputs.files[1].sha256, sha256_hex(TRIANGLE.as_bytes()));
        assert!(inputs.files.iter().all(|f| f.path.as_ref().is_some_and(|p| p.is_absolute())));
        let with = inputs.clone().with_script("f.rhai", Path::new("f.rhai"), b"fn frame(t) {}");
        assert_eq!(with.files[1].role, InputRole::Script);
        assert_eq!(Inputs::from_json(&with.to_json()).unwrap(), with);
    }

    #[test]
    fn the_fingerprint_follows_every_file_s_contents_but_not_its_place() {
        let tmp = tempfile::tempdir().unwrap();
        let (scene, desc) = scene_with_meshes(tmp.path());
        let before = inputs_of(&scene, &desc);
        let mut moved = before.clone();
        moved.files[1].path = Some(PathBuf::from("/elsewhere/a.obj"));
        moved.files[1].name = "elsewhere.obj".into();
        assert_eq!(moved.fingerprint(), before.fingerprint());

        write(&tmp.path().join("sub"), "b.obj", "v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n");
        let after = inputs_of(&scene, &desc);
        assert_ne!(after.fingerprint(), before.fingerprint());
        assert_eq!(check(&before.files[1], tmp.path().join("a.obj").as_ref()), InputCheck::Unchanged);
        assert!(matches!(
            check(&before.files[2], tmp.path().join("sub/b.obj").as_ref()),
            InputCheck::Changed { .. }
        ));
        assert!(matches!(
            check(&before.files[2], tmp.path().join("gone.obj").as_ref()),
            InputCheck::Missing { .. }
        ));
    }

    #[test]
    fn a_missing_mesh_is_an_error_naming_its_path() {
        let tmp = tempfile::tempdir().unwrap();
        let (scene, desc) = scene_with_meshes(tmp.path());
        std::fs::remove_file(tmp.path().join("a.obj")).unwrap();
        let error = Inputs::of_scene("s.ron", &scene, b"", &desc).unwrap_err().to_string();
        assert!(error.contains("a.obj") && error.contains("cannot read the mesh"), "{error}");
    }

    #[test]
    fn the_built_in_scene_has_no_path() {
        let inputs = Inputs::builtin();
        assert_eq!(inputs.files.len(), 1);
        assert_eq!(inputs.files[0].path, None);
        assert_eq!(inputs.files[0].sha256, sha256_hex(DEFAULT_SCENE_SOURCE.as_bytes()));
    }
}
