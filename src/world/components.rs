//! Components of scene entities: authored data (`Shape`, `Transform`, `MaterialRef`, `Light`,
//! `Visible`, `Name`) and data the systems derive from it (`WorldShape`, `WorldAabb`).

use bevy_ecs::prelude::Component;

use crate::geom;
use crate::math::{Aabb, Affine3A, Quat, Vec3};
use crate::store::MaterialId;
use crate::trace;

pub use bevy_ecs::name::Name;

/// Object-space geometry of a renderable entity.
#[derive(Component, Debug, Clone, PartialEq)]
pub struct Shape(pub geom::Shape);

/// Object-to-world placement: scale, then rotate, then translate.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// Translation.
    pub translation: Vec3,
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
    pub const IDENTITY: Self = Self { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };

    /// A pure translation.
    pub fn from_translation(translation: Vec3) -> Self {
        Self { translation, ..Self::IDENTITY }
    }

    /// The scene file's convention: rotate about X, then Y, then Z, by angles in degrees.
    pub fn from_scene(translate: Vec3, rotate_deg: Vec3, scale: Vec3) -> Self {
        let r = rotate_deg * (std::f32::consts::PI / 180.0);
        let rotation = Quat::from_rotation_z(r.z) * Quat::from_rotation_y(r.y) * Quat::from_rotation_x(r.x);
        Self { translation: translate, rotation, scale }
    }

    /// The affine object-to-world map.
    pub fn to_affine(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
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

/// A light source entity.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct Light(pub trace::Light);

/// World-space geometry, derived from `Shape` and `Transform` by `update_bounds`.
#[derive(Component, Debug, Clone, PartialEq)]
pub struct WorldShape(pub geom::Placed);

/// World-space bounds, derived by `update_bounds`; [`Aabb::EMPTY`] for unbounded geometry
/// (planes), which the grid does not index.
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
