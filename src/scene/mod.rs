//! Scene files: the RON format, its validation with file positions, and loading.
//!
//! A scene file is RON deserialized into [`SceneFile`] (the schema lives in
//! [`format`](mod@format) and `docs/scene-format.md`; its sampling, adaptive and tone-mapping
//! parts are the engine's own types). [`load_scene`] and [`parse_scene`] parse and
//! [`validate`] it, load what it names and return a [`SceneDesc`]: the file and its loaded
//! [`SceneAssets`] (meshes, textures) side by side. Any problem is a [`SceneError`] naming the
//! file, line, column and field:
//!
//! ```text
//! scenes/bad.ron:12:51: field `objects[0].shape.radius`: must be > 0, got -1
//! ```
//!
//! This module owns:
//! - the schema ([`format`](mod@format)), the loaded description ([`desc`]) and loading
//!   ([`load`], [`mesh`], [`obj`], [`mtl`], [`mesh_materials`], [`texture`]);
//! - the rules: [`fields`] (each value's rule, shared with script writes), [`rules`] (the
//!   numeric limits), [`validate`](mod@validate) (the file's rules in document order) and [`limits`] (what
//!   fields produce together: world-space sizes, the lens, summed radiance);
//! - [`locate`], which maps field paths to source positions (ron keeps none for values);
//! - [`SceneBuilder`], the same description put together in code and checked by the same rules;
//! - [`spawn_world`], which turns a description into a World of entities, and
//!   [`default_scene`], the built-in `scenes/default.ron`;
//! - [`inputs`] (the files a frame is made from, hashed) and [`ray_tree`] (a camera sample's
//!   ray tree against the ray budget).
//!
//! [`validate`]: validate::validate
pub mod builder;
pub mod desc;
pub mod error;
pub mod fields;
pub mod format;
pub mod inputs;
pub mod limits;
pub mod load;
pub mod locate;
pub mod mesh;
pub mod mesh_materials;
pub mod mtl;
pub mod obj;
pub mod ray_tree;
pub mod rules;
pub mod spawn;
pub mod texture;
pub mod validate;

pub use builder::SceneBuilder;
pub use desc::{SceneAssets, SceneDesc};
pub use error::SceneError;
pub use format::*;
pub use load::{
    default_scene, load_scene, parse_scene, parse_scene_at, DEFAULT_SCENE_ORIGIN, DEFAULT_SCENE_SOURCE,
};
pub use spawn::spawn_world;

pub(crate) use load::finish_scene;
