//! Components of scene entities: authored data (`Shape`, `Transform`, `MaterialRef`, `Light`,
//! `LightTerms`, `Visible`, `Name`) and data the systems derive from it (`WorldShape`, `WorldAabb`).
//!
//! Authored positions are `f64` (a transform's translation, a shape's positions, a light's
//! anchor); derived data is `f32` and relative to the frame's origin, the camera position
//! ([`super::resources::FrameOrigin`]).

use bevy_ecs::prelude::Component;
use glam::{DAffine3, DVec3};

use crate::geom;
use crate::math::{Aabb, Quat, Vec3};
use crate::store::MaterialId;
use crate::trace;

pub use bevy_ecs::name::Name;

/// Object-space geometry of a renderable entity.
#[derive(Component, Debug, Clone, PartialEq)]
pub struct Shape(pub geom::Shape);

/// Object-to-world placement: scale, then rotate, then translate.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// Translation, in `f64` like every authored position.
    pub translation: DVec3,
    /// Rotation.
    pub rotation: Quat,
    /// Per-axis scale (non-zero).
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// No scaling, rotation or translation.
    pub const IDENTITY: Self = Self { translation: DVec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };

    /// A pure translation.
    pub fn from_translation(translation: DVec3) -> Self {
        Self { translation, ..Self::IDENTITY }
    }

    /// The scene file's convention: rotate about X, then Y, then Z, by angles in degrees.
    pub fn from_scene(translate: DVec3, rotate_deg: Vec3, scale: Vec3) -> Self {
        let r = rotate_deg * (std::f32::consts::PI / 180.0);
        let rotation = Quat::from_rotation_z(r.z) * Quat::from_rotation_y(r.y) * Quat::from_rotation_x(r.x);
        Self { translation: translate, rotation, scale }
    }

    /// The affine object-to-world map, in `f64` (rotation and scale are widened exactly).
    pub fn to_affine(&self) -> DAffine3 {
        DAffine3::from_scale_rotation_translation(
            self.scale.as_dvec3(),
            self.rotation.as_dquat(),
            self.translation,
        )
    }
}

/// The material an entity is drawn with (an index into [`super::resources::Materials`]).
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaterialRef(pub MaterialId);

/// Whether an object or light takes part in the frame. Hidden objects are left out of the
/// grid and the snapshot (hiding or showing a bounded object rebuilds the grid); hidden lights
/// cast no light. Entities without the component are visible.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Visible(pub bool);

impl Default for Visible {
    fn default() -> Self {
        Self(true)
    }
}

/// A light source entity: where it is, in `f64`, and the light around that point.
///
/// The light's own positions (a point light's position, a rectangle's corner, a disk's
/// centre: [`trace::Light::anchor`]) are offsets from `anchor`. [`Light::at`] makes them zero,
/// so the snapshot rounds each position once ([`Light::relative_to`]). Directional lights
/// have no position and ignore `anchor`.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// World position the light's positions are measured from.
    pub anchor: DVec3,
    /// The light, its positions relative to `anchor`.
    pub source: trace::Light,
}

impl Light {
    /// `source` moved so that its position, corner or centre is the world point `at`.
    pub fn at(at: DVec3, source: trace::Light) -> Self {
        Self { anchor: at, source: source.translated(-source.anchor()) }
    }

    /// World position of the light's position, corner or centre (`None` for directional
    /// lights).
    pub fn position(&self) -> Option<DVec3> {
        (!matches!(self.source, trace::Light::Directional { .. }))
            .then(|| self.anchor + self.source.anchor().as_dvec3())
    }

    /// The light as a snapshot whose origin is `origin` sees it: `anchor - origin` computed in
    /// `f64` and rounded once to `f32`.
    pub fn relative_to(&self, origin: DVec3) -> trace::Light {
        self.source.translated((self.anchor - origin).as_vec3())
    }
}

/// A light's colour and intensity as the scene gives them. The light's radiance
/// ([`Light::source`]) is their product; scripts read and write the two terms
/// (`key.intensity = 0.5`), and whoever writes them writes the radiance too.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct LightTerms {
    /// Linear RGB colour.
    pub colour: Vec3,
    /// Scale of the colour.
    pub intensity: f32,
}

/// Camera-relative geometry, derived from `Shape`, `Transform` and the frame's origin by
/// `update_bounds`.
#[derive(Component, Debug, Clone, PartialEq)]
pub struct WorldShape(pub geom::Placed);

/// Camera-relative bounds, derived by `update_bounds`; [`Aabb::EMPTY`] for unbounded
/// geometry (planes), which the grid does not index.
///
/// Its change tick means "the gridded geometry changed": `update_bounds` marks it changed
/// whenever a bounded entity's world geometry changes, even if the box itself is equal (a
/// box rotated by 90° about its centre), because the grid's exact overlap tests depend on it.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct WorldAabb(pub Aabb);

impl WorldAabb {
    /// True when the entity is indexed by the grid.
    pub fn is_bounded(&self) -> bool {
        !self.0.is_empty()
    }
}

/// The pose at shutter close of an object that moves while the shutter is open (motion blur);
/// its [`Transform`] is the pose at shutter open. Set each frame by whatever drives the World
/// over the shutter interval (a script, `crate::script`); absent from everything that does not
/// move, which the static grid then holds as before.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Object-to-world placement at shutter close.
    pub close: Transform,
}
