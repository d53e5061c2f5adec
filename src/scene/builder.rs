//! Building a scene in code: the same [`SceneDesc`] a file describes, put together by method
//! calls, and checked by exactly the rules a file is ([`SceneBuilder::build`] runs the loader's
//! validation, mesh and texture loading and limits).
//!
//! ```
//! use penumbra::scene::{CameraDesc, MaterialDesc, SceneBuilder};
//! use penumbra::math::DVec3;
//!
//! let scene = SceneBuilder::new(CameraDesc::new(DVec3::new(0.0, 1.0, -4.0), DVec3::ZERO, 45.0, 64, 48))
//!     .material(MaterialDesc::new("red", [0.8, 0.1, 0.1]))
//!     .sphere(DVec3::ZERO, 1.0, "red")
//!     .point_light(DVec3::new(-3.0, 5.0, -3.0), 1.0)
//!     .build()
//!     .unwrap();
//! assert_eq!(scene.objects.len(), 1);
//!
//! // A broken value is refused with the rule a scene file would break.
//! let error = SceneBuilder::new(CameraDesc::new(DVec3::new(0.0, 1.0, -4.0), DVec3::ZERO, 45.0, 64, 48))
//!     .material(MaterialDesc::new("red", [0.8, 0.1, 0.1]))
//!     .sphere(DVec3::ZERO, -1.0, "red")
//!     .build()
//!     .unwrap_err();
//! assert_eq!(error.to_string(), "<SceneBuilder>: field `objects[0].shape.radius`: must be > 0, got -1");
//! ```

use std::path::{Path, PathBuf};

use super::format::{
    CameraDesc, LightDesc, MaterialDesc, ObjectDesc, SceneFile, SettingsDesc, ShapeDesc, TransformDesc,
};
use super::{finish_scene, SceneDesc, SceneError};
use crate::math::{DVec3, Vec3};

/// What errors of a built scene name as their origin (they carry no line or column).
pub const BUILDER_ORIGIN: &str = "<SceneBuilder>";

/// A scene put together in code; see the [module documentation](self).
#[derive(Debug, Clone)]
pub struct SceneBuilder {
    scene: SceneFile,
    base: PathBuf,
}

impl SceneBuilder {
    /// An empty scene seen through `camera`, with default settings.
    pub fn new(camera: CameraDesc) -> Self {
        let scene = SceneFile {
            camera,
            settings: SettingsDesc::default(),
            materials: Vec::new(),
            textures: Vec::new(),
            lights: Vec::new(),
            objects: Vec::new(),
        };
        Self { scene, base: PathBuf::from(".") }
    }

    /// Mesh and texture files are read relative to `base` (default: the working directory).
    pub fn files_relative_to(mut self, base: impl AsRef<Path>) -> Self {
        self.base = base.as_ref().to_path_buf();
        self
    }

    /// Changes the render settings.
    pub fn settings(mut self, change: impl FnOnce(&mut SettingsDesc)) -> Self {
        change(&mut self.scene.settings);
        self
    }

    /// Adds a material; objects name it.
    pub fn material(mut self, material: MaterialDesc) -> Self {
        self.scene.materials.push(material);
        self
    }

    /// Adds a light.
    pub fn light(mut self, light: LightDesc) -> Self {
        self.scene.lights.push(light);
        self
    }

    /// Adds a white point light of `intensity` at `position`, with no falloff.
    pub fn point_light(self, position: DVec3, intensity: f32) -> Self {
        self.light(LightDesc::Point { position, colour: Vec3::ONE, intensity, falloff: Default::default() })
    }

    /// Adds an object.
    pub fn object(mut self, object: ObjectDesc) -> Self {
        self.scene.objects.push(object);
        self
    }

    /// Adds a sphere of `material`.
    pub fn sphere(self, centre: DVec3, radius: f32, material: &str) -> Self {
        self.shape(ShapeDesc::Sphere { centre, radius }, material, TransformDesc::default())
    }

    /// Adds an infinite plane of `material`.
    pub fn plane(self, point: DVec3, normal: Vec3, material: &str) -> Self {
        self.shape(ShapeDesc::Plane { point, normal }, material, TransformDesc::default())
    }

    /// Adds the triangle mesh of an OBJ `file` (relative to [`SceneBuilder::files_relative_to`]),
    /// smooth-shaded in `material`, placed by `transform`.
    pub fn mesh(self, file: &str, material: &str, transform: TransformDesc) -> Self {
        let shape = ShapeDesc::Mesh { file: file.to_owned(), smooth: true, materials: Default::default() };
        self.shape(shape, material, transform)
    }

    fn shape(self, shape: ShapeDesc, material: &str, transform: TransformDesc) -> Self {
        self.object(ObjectDesc { name: None, shape, material: material.to_owned(), transform })
    }

    /// The scene, checked by the rules a scene file is checked by, its meshes and textures
    /// loaded. An error names the field and the rule, with [`BUILDER_ORIGIN`] in place of a file
    /// and no position.
    pub fn build(self) -> Result<SceneDesc, SceneError> {
        finish_scene(self.scene, BUILDER_ORIGIN, &self.base, "").map_err(|error| match error {
            SceneError::Invalid { path, field, rule, .. } => {
                SceneError::Invalid { path, line: 0, col: 0, field, rule }
            }
            other => other,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse_scene;

    fn camera() -> CameraDesc {
        CameraDesc::new(DVec3::new(0.0, 1.0, -4.0), DVec3::ZERO, 45.0, 64, 48)
    }

    #[test]
    fn a_built_scene_equals_the_same_scene_read_from_a_file() {
        let text =
            "Scene(camera: (position: (0, 1, -4), look_at: (0, 0, 0), fov_deg: 45, width: 64, height: 48),
            materials: [(name: \"red\", kd: (0.8, 0.1, 0.1)), (name: \"floor\", kd: (0.5, 0.5, 0.5))],
            lights: [Point(position: (-3, 5, -3), intensity: 0.5)],
            objects: [(shape: Sphere(centre: (0, 0, 0), radius: 1), material: \"red\"),
                      (shape: Plane(point: (0, -1, 0), normal: (0, 1, 0)), material: \"floor\")])";
        let read = parse_scene(text, "same.ron").unwrap();
        let built = SceneBuilder::new(camera())
            .material(MaterialDesc::new("red", [0.8, 0.1, 0.1]))
            .material(MaterialDesc::new("floor", [0.5, 0.5, 0.5]))
            .point_light(DVec3::new(-3.0, 5.0, -3.0), 0.5)
            .sphere(DVec3::ZERO, 1.0, "red")
            .plane(DVec3::new(0.0, -1.0, 0.0), Vec3::Y, "floor")
            .build()
            .unwrap();
        assert_eq!(built.camera, read.camera);
        assert_eq!(built.settings, read.settings);
        assert_eq!(built.materials, read.materials);
        assert_eq!(built.lights, read.lights);
        assert_eq!(built.objects, read.objects);
    }

    #[test]
    fn a_built_scene_breaks_the_rules_a_file_would_with_the_same_words() {
        let built = SceneBuilder::new(camera()).sphere(DVec3::ZERO, 1.0, "missing").build().unwrap_err();
        let text =
            "Scene(camera: (position: (0, 1, -4), look_at: (0, 0, 0), fov_deg: 45, width: 64, height: 48),
            materials: [], objects: [(shape: Sphere(centre: (0, 0, 0), radius: 1), material: \"missing\")])";
        let read = parse_scene(text, "same.ron").unwrap_err();
        let (
            SceneError::Invalid { field: f1, rule: r1, line, .. },
            SceneError::Invalid { field: f2, rule: r2, .. },
        ) = (&built, &read)
        else {
            panic!("both are invalid scenes: {built} / {read}");
        };
        assert_eq!((f1, r1), (f2, r2));
        assert_eq!(*line, 0);
        assert!(built.to_string().starts_with("<SceneBuilder>: field `objects[0].material`"), "{built}");
    }

    #[test]
    fn meshes_are_read_relative_to_the_given_folder() {
        let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let scene = SceneBuilder::new(camera())
            .files_relative_to(&scenes)
            .material(MaterialDesc::new("white", [0.8, 0.8, 0.8]))
            .mesh("bunny_res3.obj", "white", TransformDesc::default())
            .build()
            .unwrap();
        assert_eq!(scene.assets.meshes.len(), 1);
        let missing = SceneBuilder::new(camera())
            .material(MaterialDesc::new("white", [0.8, 0.8, 0.8]))
            .mesh("no/such.obj", "white", TransformDesc::default())
            .build()
            .unwrap_err();
        assert!(missing.to_string().contains("cannot load mesh"), "{missing}");
    }
}
