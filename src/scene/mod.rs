//! Scene files: the RON format, its validation with file positions, and loading.
//!
//! A scene is a RON file deserialized into [`SceneDesc`] (the schema lives in [`format`](mod@format) and
//! `docs/scene-format.md`). [`load_scene`] and [`parse_scene`] parse and [`validate`] it and
//! report any problem as a [`SceneError`] naming the file, line, column and field:
//!
//! ```text
//! scenes/bad.ron:12:51: field `objects[0].shape.radius`: must be > 0, got -1
//! ```
//!
//! [`locate`] maps field paths to source positions, since ron keeps none for values after
//! deserialization. [`default_scene`] is the built-in `scenes/default.ron`. [`spawn_world`]
//! turns a validated scene into a World of entities. [`obj`] imports Wavefront OBJ meshes.
//! [`inputs`] lists and hashes the files a frame is made from (scene, script, meshes).
//! [`limits`] checks what fields produce together (world-space sizes, the lens, summed
//! radiance).
//! [`SceneBuilder`] puts the same description together in code, checked by the same rules.
//! [`rules`] is the table of numeric limits every check reads.
//! [`ray_tree`] bounds a camera sample's ray tree and warns when the ray budget would cut it.
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
