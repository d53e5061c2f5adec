//! `update_bounds`: world-space geometry and bounds of entities whose shape or transform changed.

use std::time::Instant;

use bevy_ecs::prelude::{Changed, DetectChangesMut, Mut, Or, Query, ResMut};

use crate::world::components::{Shape, Transform, WorldAabb, WorldShape};
use crate::world::resources::StageClock;

/// Recomputes `WorldShape` and `WorldAabb` for entities whose `Shape` or `Transform` changed.
///
/// Writes go through `set_if_neq`, so an assignment of an equal value does not trigger a
/// grid rebuild. A bounded entity whose world geometry changed while its box stayed equal is
/// still marked changed: the grid's exact overlap tests depend on the geometry, not the box.
#[allow(clippy::type_complexity)]
pub fn update_bounds(
    mut changed: Query<
        (&Shape, &Transform, Mut<WorldShape>, Mut<WorldAabb>),
        Or<(Changed<Shape>, Changed<Transform>)>,
    >,
    mut clock: ResMut<StageClock>,
) {
    let started = Instant::now();
    for (shape, transform, mut world_shape, mut aabb) in &mut changed {
        let placed = shape.0.place(&transform.to_affine());
        let bounds = placed.bounds().unwrap_or(crate::math::Aabb::EMPTY);
        let geometry_changed = world_shape.set_if_neq(WorldShape(placed));
        let bounds_changed = aabb.set_if_neq(WorldAabb(bounds));
        if geometry_changed && !bounds_changed && aabb.is_bounded() {
            aabb.set_changed();
        }
    }
    clock.bounds = started.elapsed().as_secs_f64();
}
