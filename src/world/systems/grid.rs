//! `rebuild_grid`: the uniform grid over bounded entities, rebuilt only when one changed.

use std::sync::Arc;
use std::time::Instant;

use bevy_ecs::prelude::{Added, Changed, Entity, Has, Query, RemovedComponents, Res, ResMut, Without};

use crate::accel::GridBuilder;
use crate::world::components::{Motion, Visible, WorldAabb, WorldShape};
use crate::world::resources::{GridIndex, GridRebuilds, SceneSettings, StageClock};

/// Run condition of [`rebuild_grid`]: some visible bounded geometry changed (spawned entities
/// count as changed), a bounded entity was hidden or shown, or a `WorldAabb` was removed
/// (despawned entity).
///
/// Both parts run every frame (`or_eager` semantics): the removal reader must be drained each
/// frame, or a stale removal would trigger a rebuild on a later, unchanged frame.
///
/// An entity that moves while the shutter is open ([`Motion`]) is not in the grid: its changes
/// rebuild nothing, but its starting or stopping to move does.
#[allow(clippy::type_complexity)]
pub fn grid_needs_rebuild(
    changed: Query<(&WorldAabb, Option<&Visible>, Has<Motion>), Changed<WorldAabb>>,
    toggled: Query<(&WorldAabb, Has<Motion>), Changed<Visible>>,
    started: Query<&WorldAabb, Added<Motion>>,
    mut removed: RemovedComponents<WorldAabb>,
    mut stopped: RemovedComponents<Motion>,
) -> bool {
    // An unbounded entity (a plane) that moved changes nothing the grid indexes, and neither
    // does a hidden one.
    let any_changed =
        changed.iter().any(|(aabb, visible, moving)| aabb.is_bounded() && is_visible(visible) && !moving);
    let any_toggled = toggled.iter().any(|(aabb, moving)| aabb.is_bounded() && !moving);
    let any_started = started.iter().any(WorldAabb::is_bounded);
    let any_removed = removed.read().count() > 0;
    let any_stopped = stopped.read().count() > 0;
    any_changed || any_toggled || any_started || any_removed || any_stopped
}

/// True unless the entity carries `Visible(false)`.
pub fn is_visible(visible: Option<&Visible>) -> bool {
    visible.is_none_or(|v| v.0)
}

/// Rebuilds the grid over every visible bounded entity that does not move while the shutter is open, in entity order (so the grid, and every image,
/// is independent of query iteration order), and counts the rebuild.
pub fn rebuild_grid(
    objects: Query<(Entity, &WorldAabb, &WorldShape, Option<&Visible>), Without<Motion>>,
    settings: Res<SceneSettings>,
    mut index: ResMut<GridIndex>,
    mut rebuilds: ResMut<GridRebuilds>,
    mut clock: ResMut<StageClock>,
) {
    let started = Instant::now();
    let mut bounded: Vec<(Entity, &WorldAabb, &WorldShape)> = objects
        .iter()
        .filter(|(_, aabb, _, visible)| aabb.is_bounded() && is_visible(*visible))
        .map(|(e, aabb, shape, _)| (e, aabb, shape))
        .collect();
    bounded.sort_unstable_by_key(|(e, _, _)| *e);
    let bounds: Vec<_> = bounded.iter().map(|(_, aabb, _)| aabb.0).collect();
    let grid =
        GridBuilder::new(settings.lambda).build(&bounds, |id, cell| bounded[id as usize].2 .0.overlaps(cell));
    *index = GridIndex { grid: Arc::new(grid), entities: bounded.iter().map(|(e, _, _)| *e).collect() };
    rebuilds.0 += 1;
    clock.grid_build = started.elapsed().as_secs_f64();
}
