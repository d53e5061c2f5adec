//! `rebuild_grid`: the uniform grid over bounded entities, rebuilt only when one changed.

use std::sync::Arc;
use std::time::Instant;

use bevy_ecs::prelude::{Changed, Entity, Query, RemovedComponents, Res, ResMut};

use crate::accel::GridBuilder;
use crate::world::components::{WorldAabb, WorldShape};
use crate::world::resources::{GridIndex, GridRebuilds, SceneSettings, StageClock};

/// Run condition of [`rebuild_grid`]: some bounded geometry changed (spawned entities count as
/// changed) or a `WorldAabb` was removed (despawned entity).
///
/// Both parts run every frame (`or_eager` semantics): the removal reader must be drained each
/// frame, or a stale removal would trigger a rebuild on a later, unchanged frame.
pub fn grid_needs_rebuild(
    changed: Query<&WorldAabb, Changed<WorldAabb>>,
    mut removed: RemovedComponents<WorldAabb>,
) -> bool {
    // An unbounded entity (a plane) that moved changes nothing the grid indexes.
    let any_changed = changed.iter().any(WorldAabb::is_bounded);
    let any_removed = removed.read().count() > 0;
    any_changed || any_removed
}

/// Rebuilds the grid over every bounded entity, in entity order (so the grid, and every image,
/// is independent of query iteration order), and counts the rebuild.
pub fn rebuild_grid(
    objects: Query<(Entity, &WorldAabb, &WorldShape)>,
    settings: Res<SceneSettings>,
    mut index: ResMut<GridIndex>,
    mut rebuilds: ResMut<GridRebuilds>,
    mut clock: ResMut<StageClock>,
) {
    let started = Instant::now();
    let mut bounded: Vec<(Entity, &WorldAabb, &WorldShape)> =
        objects.iter().filter(|(_, aabb, _)| aabb.is_bounded()).collect();
    bounded.sort_unstable_by_key(|(e, _, _)| *e);
    let bounds: Vec<_> = bounded.iter().map(|(_, aabb, _)| aabb.0).collect();
    let grid =
        GridBuilder::new(settings.lambda).build(&bounds, |id, cell| bounded[id as usize].2 .0.overlaps(cell));
    *index = GridIndex { grid: Arc::new(grid), entities: bounded.iter().map(|(e, _, _)| *e).collect() };
    rebuilds.0 += 1;
    clock.grid_build = started.elapsed().as_secs_f64();
}
