//! The script's view of the World: a plain-data mirror of the camera, the render settings,
//! every named entity and every texture's transform, with a record of what the script wrote.
//!
//! The mirror is taken from the World once, when the script is attached; from then on the
//! script is the only writer, so reads come from the mirror and writes are exact (a value set
//! is the value got back). [`apply_script_writes`] moves only what the script wrote into the
//! World, through `set_if_neq`, so an entity the script did not touch, or set to the value it
//! already had, triggers no change detection and no grid rebuild.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use bevy_ecs::prelude::{Entity, Resource};
use glam::{DVec3, EulerRot, Quat, Vec3};

use crate::store::MaterialId;
use crate::trace::Material;
use crate::world::components::Transform;
use crate::world::resources::{CameraRig, Focus};

use super::texture::TextureState;

mod sync;
pub use sync::apply_script_writes;

/// The mirror, shared between the engine's API functions and the World's input system.
#[derive(Resource, Clone, Default)]
pub struct SharedState(pub Arc<Mutex<ScriptState>>);

impl SharedState {
    /// Locks the mirror. API functions never panic while holding it, so a poisoned lock
    /// still holds consistent data.
    pub fn lock(&self) -> MutexGuard<'_, ScriptState> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// Everything a script reads and writes.
#[derive(Debug, Clone, Default)]
pub struct ScriptState {
    /// The camera.
    pub camera: CameraState,
    /// Render settings.
    pub settings: SettingsState,
    /// Named entities in spawn order.
    pub entities: Vec<EntityState>,
    /// Index of each entity by name.
    pub by_name: HashMap<String, usize>,
    /// The scene's named textures' transforms, in table order.
    pub textures: Vec<TextureState>,
    /// The frame being made.
    pub clock: Clock,
    /// The camera was written since the last apply.
    pub camera_dirty: bool,
    /// The settings were written since the last apply.
    pub settings_dirty: bool,
}

/// The frame being made: its number, time in seconds and the frame rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    /// Frame number.
    pub frame: u32,
    /// Seconds since frame 0: `frame / fps`.
    pub time: f64,
    /// Frames per second.
    pub fps: f64,
}

impl Default for Clock {
    fn default() -> Self {
        Self { frame: 0, time: 0.0, fps: 24.0 }
    }
}

impl Clock {
    /// Frame `frame` at `fps` frames per second.
    pub fn at(frame: u32, fps: f64) -> Self {
        Self { frame, time: frame as f64 / fps, fps }
    }

    /// Frame `frame` at `fps`, a fraction `offset` of the frame interval later (a shutter's
    /// opening or closing): time `(frame + offset) / fps`. `offset` 0 is [`Clock::at`].
    pub fn at_offset(frame: u32, offset: f32, fps: f64) -> Self {
        match offset {
            0.0 => Self::at(frame, fps),
            _ => Self { frame, time: (f64::from(frame) + f64::from(offset)) / fps, fps },
        }
    }
}

/// The camera as a script sees it (angles in degrees).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraState {
    /// Eye position.
    pub position: DVec3,
    /// Point looked at.
    pub look_at: DVec3,
    /// Up direction.
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
    /// Lens radius.
    pub aperture: f64,
    /// What is kept sharp.
    pub focus: FocusState,
}

impl Default for CameraState {
    fn default() -> Self {
        Self {
            position: DVec3::ZERO,
            look_at: DVec3::Z,
            up: DVec3::Y,
            fov_deg: 45.0,
            aperture: 0.0,
            focus: FocusState::LookAt,
        }
    }
}

/// What the camera keeps sharp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FocusState {
    /// The plane through the look-at point.
    LookAt,
    /// The plane at this distance along the view direction.
    Distance(f64),
    /// The plane through this point.
    Point(DVec3),
    /// The plane through this entity's centre, wherever it moves (`focus_on`).
    Entity(usize),
}

/// Render settings a script can change.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SettingsState {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Anti-aliasing samples per pixel.
    pub samples: u32,
    /// Lens samples per camera sample.
    pub lens_samples: u32,
    /// Time samples per camera sample (motion blur).
    pub time_samples: u32,
    /// Rays per glossy reflection or blurry refraction.
    pub glossy_samples: u32,
    /// Adaptive supersampling: (threshold, deepest level), or off.
    pub adaptive: Option<(f64, u32)>,
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Colour of escaping rays (read only; for the radiance rule).
    pub background: Vec3,
    /// Ambient light (read only; for the radiance rule).
    pub ambient: Vec3,
    /// Secondary rays one camera sample may trace.
    pub max_secondary_rays: u32,
    /// Seed of all randomness.
    pub seed: u64,
}

/// What kind of entity a name refers to, as far as scripts care.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EntityKind {
    /// A renderable object; `pivot` is its object-space centre (the centre of its bounds, or
    /// a plane's point), which the transform carries to the world.
    Object {
        /// Object-space centre.
        pivot: DVec3,
        /// Spheres accept only uniform scales.
        uniform_scale: bool,
        /// Object-space bounds (`None` for a plane), for the world-space extent rule.
        bounds: Option<(DVec3, DVec3)>,
    },
    /// A light source; directional lights have no position.
    Light {
        /// Point and area lights can be moved; directional lights cannot.
        positioned: bool,
    },
}

/// One named entity as a script sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct EntityState {
    /// The World's entity.
    pub entity: Entity,
    /// Its scene name.
    pub name: String,
    /// Object or light.
    pub kind: EntityKind,
    /// Translation (objects) or position (point lights; the centre of area lights).
    pub position: DVec3,
    /// Rotation about X, then Y, then Z, in degrees (objects).
    pub rotation_deg: DVec3,
    /// Per-axis scale (objects).
    pub scale: DVec3,
    /// Whether it takes part in the frame.
    pub visible: bool,
    /// Its material parameters (objects; not meshes whose faces take their file's materials).
    pub material: Option<MaterialState>,
    /// A mesh whose faces take their materials from its file (`materials: FromFile`): scripts
    /// cannot set one material for it.
    pub faces_own_materials: bool,
    /// Its colour and intensity (lights).
    pub light: Option<LightTerms>,
    /// Position or scale written since the last apply.
    pub transform_dirty: bool,
    /// Rotation written at least once (until then the World's rotation is kept as is).
    pub rotation_written: bool,
    /// Visibility written since the last apply.
    pub visible_dirty: bool,
    /// Material written since the last apply.
    pub material_dirty: bool,
    /// Light colour or intensity written since the last apply.
    pub light_dirty: bool,
}

/// A light's colour and intensity, as the scene format has them (the World keeps only their
/// product, the radiance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightTerms {
    /// Linear RGB colour.
    pub colour: DVec3,
    /// Scale of the colour.
    pub intensity: f64,
}

/// An object's material parameters, and its private copy once a script has changed them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialState {
    /// Current parameters (f64, as the script wrote them).
    pub params: MaterialParams,
    /// The entity's own material id, made on the first write so that other objects sharing
    /// the scene material keep theirs.
    pub private: Option<MaterialId>,
}

/// Phong parameters in script precision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialParams {
    /// Diffuse reflectance.
    pub kd: DVec3,
    /// Specular reflectance.
    pub ks: f64,
    /// Phong exponent.
    pub shininess: f64,
    /// Mirror reflectance.
    pub kr: f64,
    /// Transmittance.
    pub kt: f64,
    /// Index of refraction.
    pub ior: f64,
    /// Blur of reflection and refraction.
    pub glossiness: f64,
    /// What scripts do not set, carried through unchanged: emission, Fresnel and textures.
    pub fixed: FixedMaterialParts,
}

/// The parts of a material scripts leave as the scene gave them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedMaterialParts {
    /// The colour of `kt` (its channels over the largest; white for grey glass): scripts set
    /// `kt`'s strength, the tint stays.
    pub kt_tint: Vec3,
    /// Beer–Lambert absorption.
    pub absorption: Vec3,
    /// Emitted light.
    pub emission: Vec3,
    /// Schlick's Fresnel term on or off.
    pub fresnel: bool,
    /// Textures.
    pub maps: crate::trace::material::Maps,
}

impl From<&Material> for MaterialParams {
    fn from(m: &Material) -> Self {
        Self {
            kd: m.kd.as_dvec3(),
            ks: m.ks as f64,
            shininess: m.shininess as f64,
            kr: m.kr as f64,
            kt: m.kt.max_element() as f64,
            ior: m.ior as f64,
            glossiness: m.glossiness as f64,
            fixed: FixedMaterialParts {
                kt_tint: match m.kt.max_element() {
                    k if k > 0.0 && !(m.kt.x == m.kt.y && m.kt.y == m.kt.z) => m.kt / k,
                    _ => Vec3::ONE,
                },
                emission: m.emission,
                fresnel: m.fresnel,
                absorption: m.absorption,
                maps: m.maps,
            },
        }
    }
}

impl MaterialParams {
    /// The engine material.
    pub fn to_material(&self) -> Material {
        Material {
            kd: self.kd.as_vec3(),
            ks: self.ks as f32,
            shininess: self.shininess as f32,
            kr: self.kr as f32,
            kt: self.fixed.kt_tint * self.kt as f32,
            ior: self.ior as f32,
            glossiness: self.glossiness as f32,
            emission: self.fixed.emission,
            fresnel: self.fixed.fresnel,
            absorption: self.fixed.absorption,
            maps: self.fixed.maps,
        }
    }
}

impl EntityState {
    /// World-space centre: the object's pivot under its transform, or a light's position.
    pub fn centre(&self) -> DVec3 {
        match self.kind {
            EntityKind::Object { pivot, .. } => {
                let rotation = rotation_from_degrees(self.rotation_deg).as_dquat();
                self.position + rotation * (self.scale * pivot)
            }
            EntityKind::Light { .. } => self.position,
        }
    }
}

/// The rotation of the scene convention: about X, then Y, then Z, by angles in degrees.
pub fn rotation_from_degrees(deg: DVec3) -> Quat {
    Transform::from_scene(DVec3::ZERO, deg.as_vec3(), Vec3::ONE).rotation
}

/// Angles in degrees (about X, then Y, then Z) of a rotation; the inverse of
/// [`rotation_from_degrees`] up to rounding.
pub fn degrees_from_rotation(q: Quat) -> DVec3 {
    let (z, y, x) = q.to_euler(EulerRot::ZYX);
    DVec3::new(x as f64, y as f64, z as f64) * (180.0 / std::f64::consts::PI)
}

impl ScriptState {
    /// The entity called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.by_name.get(name).copied()
    }

    /// The texture called `name`.
    pub fn texture_index(&self, name: &str) -> Option<usize> {
        self.textures.iter().position(|t| t.name == name)
    }

    /// The camera focus distance along the view direction, resolved as the renderer will.
    pub fn focus_distance(&self) -> f64 {
        match self.camera.focus {
            // What the script wrote reads back exactly.
            FocusState::Distance(d) => d,
            _ => f64::from(self.rig().focus_distance()),
        }
    }

    /// The camera rig the mirror describes; a focus entity is resolved to its current centre.
    pub(crate) fn rig(&self) -> CameraRig {
        let c = &self.camera;
        CameraRig {
            position: c.position,
            look_at: c.look_at,
            up: c.up.as_vec3(),
            fov_y: (c.fov_deg as f32).to_radians(),
            aperture: c.aperture as f32,
            focus: match c.focus {
                FocusState::LookAt => Focus::LookAt,
                FocusState::Distance(d) => Focus::Distance(d as f32),
                FocusState::Point(p) => Focus::Point(p),
                FocusState::Entity(i) => Focus::Point(self.entities[i].centre()),
            },
        }
    }

    /// True when the focus follows an entity (its motion moves the focal plane).
    fn focus_follows_entity(&self) -> bool {
        matches!(self.camera.focus, FocusState::Entity(_))
    }
}

#[cfg(test)]
mod tests;
