//! The script's mirror of the scene's texture transforms, and its write-back into the World's
//! [`Textures`] table.
//!
//! Scripts animate a texture's (u, v) transform (`let w = texture("water"); w.offset = [t, 0];`):
//! the mirror keeps each texture's offset, scale and rotation as the script wrote them (in
//! `f64`, so a value set is the value got back). [`apply_texture_writes`] replaces the table
//! only when a written transform differs, in `f32`, from the one the table holds: a frame that
//! writes nothing, or writes the values already there, keeps the same `Arc` and so the same
//! bits in every snapshot. Texture transforms are not motion-blurred: a frame uses the
//! transforms at shutter open.

use std::sync::Arc;

use bevy_ecs::prelude::Mut;
use glam::DVec2;

use crate::texture::UvTransform;
use crate::world::resources::Textures;

/// One named texture's transform as a script sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureState {
    /// Its scene name.
    pub name: String,
    /// Added to the scaled and rotated (u, v).
    pub offset: DVec2,
    /// Per-axis scale of (u, v), non-zero.
    pub scale: DVec2,
    /// Counter-clockwise rotation of the scaled (u, v), in degrees.
    pub rotation_deg: f64,
    /// Written since the last apply.
    pub dirty: bool,
}

impl TextureState {
    /// The mirror of one texture of the table.
    pub fn new(name: &str, transform: &UvTransform) -> Self {
        Self {
            name: name.to_owned(),
            offset: transform.offset.as_dvec2(),
            scale: transform.scale.as_dvec2(),
            rotation_deg: f64::from(transform.rotate_deg),
            dirty: false,
        }
    }

    /// The engine transform (rounded to `f32`).
    pub fn transform(&self) -> UvTransform {
        UvTransform {
            scale: self.scale.as_vec2(),
            offset: self.offset.as_vec2(),
            rotate_deg: self.rotation_deg as f32,
        }
    }
}

/// The mirror of every texture of `textures`, in table order.
pub fn texture_states(textures: &Textures) -> Vec<TextureState> {
    textures
        .table
        .iter()
        .zip(&textures.names)
        .map(|(t, name)| TextureState::new(name, t.transform()))
        .collect()
}

/// Moves the transforms the script wrote into `textures`: a new table, with only the changed
/// textures replaced, when at least one written transform differs from the table's; then
/// clears the record of writes. `textures` is borrowed mutably only when it changes, so an
/// unchanged frame triggers no change detection.
pub fn apply_texture_writes(mirror: &mut [TextureState], textures: Option<Mut<Textures>>) {
    if !mirror.iter().any(|t| t.dirty) {
        return;
    }
    if let Some(mut textures) = textures {
        let changed: Vec<(usize, UvTransform)> = mirror
            .iter()
            .enumerate()
            .filter(|(_, t)| t.dirty)
            .map(|(i, t)| (i, t.transform()))
            .filter(|(i, wanted)| textures.table.get(*i).is_some_and(|old| old.transform() != wanted))
            .collect();
        if !changed.is_empty() {
            let mut table = textures.table.to_vec();
            for (i, wanted) in changed {
                table[i] = table[i].with_transform(wanted);
            }
            textures.table = Arc::from(table);
        }
    }
    for t in mirror.iter_mut() {
        t.dirty = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Vec2, Vec3};
    use crate::texture::Texture;
    use bevy_ecs::prelude::{DetectChanges, World};

    fn textures() -> Textures {
        let checker = Texture::Checker { a: Vec3::ONE, b: Vec3::ZERO, transform: UvTransform::default() };
        let stripes = Texture::Stripes { a: Vec3::ONE, b: Vec3::ZERO, transform: UvTransform::default() };
        Textures { table: Arc::from(vec![checker, stripes]), names: vec!["tiles".into(), "bands".into()] }
    }

    fn apply(world: &mut World, mirror: &mut [TextureState]) {
        let textures = world.get_resource_mut::<Textures>();
        apply_texture_writes(mirror, textures);
    }

    #[test]
    fn only_a_changed_transform_replaces_the_table() {
        let mut world = World::new();
        world.insert_resource(textures());
        let mut mirror = texture_states(world.resource::<Textures>());
        assert_eq!(mirror.len(), 2);
        assert_eq!(mirror[0].transform(), UvTransform::IDENTITY);
        let before = world.resource::<Textures>().table.clone();

        // The same value written: the same table, not even marked changed.
        world.clear_trackers();
        mirror[0].dirty = true;
        apply(&mut world, &mut mirror);
        assert!(Arc::ptr_eq(&before, &world.resource::<Textures>().table));
        assert!(!world.resource_ref::<Textures>().is_changed());
        assert!(!mirror[0].dirty);

        // A new offset for one texture: a new table, the other texture as it was.
        mirror[1].offset = DVec2::new(0.5, -2.0);
        mirror[1].dirty = true;
        apply(&mut world, &mut mirror);
        let after = world.resource::<Textures>().table.clone();
        assert!(!Arc::ptr_eq(&before, &after));
        assert_eq!(after[0], before[0]);
        assert_eq!(after[1].transform().offset, Vec2::new(0.5, -2.0));
        assert!(world.resource_ref::<Textures>().is_changed());
    }

    #[test]
    fn a_difference_finer_than_f32_changes_nothing() {
        let mut world = World::new();
        world.insert_resource(textures());
        let mut mirror = texture_states(world.resource::<Textures>());
        let before = world.resource::<Textures>().table.clone();
        mirror[0].scale = DVec2::new(1.0 + 1e-12, 1.0);
        mirror[0].dirty = true;
        apply(&mut world, &mut mirror);
        assert!(Arc::ptr_eq(&before, &world.resource::<Textures>().table));
        assert_eq!(mirror[0].scale.x, 1.0 + 1e-12, "the mirror keeps what the script wrote");
    }
}
