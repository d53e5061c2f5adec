//! `update_bounds`: camera-relative geometry and bounds of entities whose shape or transform
//! changed, or of every entity when the camera moved.

use std::time::Instant;

use bevy_ecs::prelude::{DetectChanges, DetectChangesMut, Mut, Query, Ref, Res, ResMut};

use crate::world::components::{Shape, Transform, WorldAabb, WorldShape};
use crate::world::resources::{CameraRig, FrameOrigin, StageClock};

/// Recomputes `WorldShape` and `WorldAabb` relative to the camera position
/// ([`FrameOrigin`]): for entities whose `Shape` or `Transform` changed, and for every entity
/// when the camera moved since the last frame (the placement depends on the origin, so a
/// moving camera rebuilds the top-level grid; mesh grids are in object space and never are).
///
/// Writes go through `set_if_neq`, so an assignment of an equal value does not trigger a
/// grid rebuild. A bounded entity whose world geometry changed while its box stayed equal is
/// still marked changed: the grid's exact overlap tests depend on the geometry, not the box.
/// Every entity's geometry is a function of its own components and the camera position only,
/// so a frame derived alone equals the same frame reached through any sequence of frames.
#[allow(clippy::type_complexity)]
pub fn update_bounds(
    mut objects: Query<(Ref<Shape>, Ref<Transform>, Mut<WorldShape>, Mut<WorldAabb>)>,
    rig: Res<CameraRig>,
    mut origin: ResMut<FrameOrigin>,
    mut clock: ResMut<StageClock>,
) {
    let started = Instant::now();
    let moved = origin.set_if_neq(FrameOrigin(rig.position));
    let origin = origin.0;
    for (shape, transform, mut world_shape, mut aabb) in &mut objects {
        if !(moved || shape.is_changed() || transform.is_changed()) {
            continue;
        }
        let placed = shape.0.place(&transform.to_affine(), origin);
        let bounds = placed.bounds().unwrap_or(crate::math::Aabb::EMPTY);
        let geometry_changed = world_shape.set_if_neq(WorldShape(placed));
        let bounds_changed = aabb.set_if_neq(WorldAabb(bounds));
        if geometry_changed && !bounds_changed && aabb.is_bounded() {
            aabb.set_changed();
        }
    }
    clock.bounds = started.elapsed().as_secs_f64();
}
