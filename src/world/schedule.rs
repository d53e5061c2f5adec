//! The per-frame schedule: external input, bounds, then the grid (only when needed), then the
//! snapshot.

use bevy_ecs::prelude::{IntoScheduleConfigs, Schedule, SystemSet};

use crate::store::PrimitiveStore;
use crate::world::systems::{build_snapshot, grid_needs_rebuild, rebuild_grid, update_bounds};

/// The stages of a frame, in order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FrameSystems {
    /// Apply writes from outside the World (a script's camera, transforms, materials).
    Input,
    /// Derive world geometry and bounds from shapes and transforms.
    Bounds,
    /// Rebuild the grid if bounded geometry changed.
    Grid,
    /// Flatten the World into a `TraceScene`.
    Snapshot,
}

/// The frame schedule for a store layout `S`.
pub fn build_schedule<S: PrimitiveStore + 'static>() -> Schedule {
    let mut schedule = Schedule::default();
    schedule.configure_sets(
        (FrameSystems::Input, FrameSystems::Bounds, FrameSystems::Grid, FrameSystems::Snapshot).chain(),
    );
    schedule.add_systems((
        update_bounds.in_set(FrameSystems::Bounds),
        rebuild_grid.run_if(grid_needs_rebuild).in_set(FrameSystems::Grid),
        build_snapshot::<S>.in_set(FrameSystems::Snapshot),
    ));
    schedule
}
