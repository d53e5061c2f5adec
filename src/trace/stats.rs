//! Render statistics: rays by kind, time per stage, grid figures.

use std::time::Duration;

use serde::ser::SerializeStruct;
use serde::{Serialize, Serializer};

use super::effects::Effects;
use super::finite::DroppedSamples;

mod budget;
mod traversal;

pub use budget::{BudgetStats, BudgetTally};
pub use traversal::{CostHistogram, TraversalStats, TraversalTally};

/// Rays traced, by kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    /// Primary rays from a pinhole camera (aperture 0).
    pub camera: u64,
    /// Primary rays from a thin lens (aperture > 0): one per lens sample.
    pub lens: u64,
    /// Shadow rays towards point and directional lights.
    pub shadow: u64,
    /// Shadow rays towards samples of area lights.
    pub area_shadow: u64,
    /// Mirror-reflection rays.
    pub reflection: u64,
    /// Glossy-reflection rays (a cone around the mirror direction).
    pub glossy: u64,
    /// Refraction rays (including the reflection that replaces one under total internal reflection).
    pub refraction: u64,
    /// Blurry-refraction rays (a cone around the refracted direction).
    pub blurry: u64,
    /// Probe rays of first-hit AOVs (one per pixel, only when such an AOV is asked for).
    pub aov: u64,
    /// Grid cells visited and primitives tested by the rays above (AOV probes excluded).
    #[serde(skip)]
    pub traversal: TraversalTally,
    /// What the per-camera-sample budget of secondary rays did.
    #[serde(skip)]
    pub budget: BudgetTally,
    /// Camera samples given a time in the shutter interval (only where something moves).
    #[serde(skip)]
    pub timed: u64,
}

impl RayCounts {
    /// All rays.
    pub fn total(&self) -> u64 {
        self.primary()
            + self.shadow
            + self.area_shadow
            + self.reflection
            + self.glossy
            + self.refraction
            + self.blurry
            + self.aov
    }

    /// Rays leaving the camera (pinhole or lens).
    pub fn primary(&self) -> u64 {
        self.camera + self.lens
    }

    /// Each kind's count with its name, in declaration order.
    pub fn kinds(&self) -> [(&'static str, u64); 9] {
        [
            ("camera", self.camera),
            ("lens", self.lens),
            ("shadow", self.shadow),
            ("area_shadow", self.area_shadow),
            ("reflection", self.reflection),
            ("glossy", self.glossy),
            ("refraction", self.refraction),
            ("blurry", self.blurry),
            ("aov", self.aov),
        ]
    }

    /// Adds another count.
    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.lens += o.lens;
        self.shadow += o.shadow;
        self.area_shadow += o.area_shadow;
        self.reflection += o.reflection;
        self.glossy += o.glossy;
        self.refraction += o.refraction;
        self.blurry += o.blurry;
        self.aov += o.aov;
        self.traversal.add(&o.traversal);
        self.budget.add(&o.budget);
        self.timed += o.timed;
    }
}

/// What motion blur did in a frame: what moved, and how many camera samples (each the root of
/// a path of rays at its time) were given a time. All zero when nothing moved.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct MotionStats {
    /// Objects whose pose differs between shutter open and close.
    pub moving_objects: u32,
    /// Whether the camera moves while the shutter is open.
    pub camera_moves: bool,
    /// Camera samples traced at a time of their own.
    pub timed_samples: u64,
}

/// Why noise-driven sampling stopped.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseStop {
    /// It was off.
    #[default]
    Off,
    /// Every pixel reached the target error.
    Target,
    /// Every pixel still above the target reached `max_samples`.
    MaxSamples,
    /// The next round would not have fitted in the time limit.
    TimeLimit,
    /// The rounds asked for (`rounds`) were done.
    Rounds,
}

/// What noise-driven adaptive sampling did in a frame (all zero when it was off).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct NoiseStats {
    /// Rounds over the image (round 0 gives every pixel `min_samples`).
    pub rounds: u32,
    /// Camera samples per batch (the fixed set: AA × lens × time).
    pub batch: u32,
    /// Camera samples per pixel: mean, 99th percentile, smallest and largest.
    pub samples_mean: f64,
    /// 99th percentile of camera samples per pixel.
    pub samples_p99: u32,
    /// Fewest camera samples a pixel took.
    pub samples_min: u32,
    /// Most camera samples a pixel took.
    pub samples_max: u32,
    /// The estimated RMSE of the image in linear RGB: the root of the mean, over pixels and
    /// channels, of each pixel's estimated variance of its mean (what an RMSE against a
    /// noise-free reference measures, bias aside).
    pub estimated_rmse: f64,
    /// Mean over pixels of the estimated display error the target is compared with.
    pub mean_display_error: f64,
    /// Pixels whose estimated display error is above the target at the end.
    pub pixels_above_target: u64,
    /// Why the rounds stopped.
    pub stopped_by: NoiseStop,
    /// Seconds the rounds took (tracing and the decisions between rounds).
    pub seconds: f64,
}

/// What adaptive supersampling did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct AdaptiveCounts {
    /// Lattice points traced (pixel corners, then subdivision points).
    pub traced: u64,
    /// Lattice points a sub-square or pixel needed that were already traced by a neighbour.
    pub reused: u64,
    /// Squares subdivided.
    pub subdivisions: u64,
}

/// Wall time of each stage of a frame, in seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StageTimes {
    /// Reading, parsing and validating the scene.
    pub load: f64,
    /// Running the script's `setup`, `frame` or `apply` (animations and sweeps).
    pub script: f64,
    /// Spawning or updating the World (applying writes, transforms, bounds).
    pub world_update: f64,
    /// Building the top-level grid over the scene's objects (zero on frames that reuse it).
    pub grid_build: f64,
    /// Building the mesh assets' own grids (once, when the scene is loaded; zero afterwards).
    pub mesh_grid_build: f64,
    /// Flattening the World into the snapshot.
    pub snapshot: f64,
    /// Tracing.
    pub trace: f64,
    /// Encoding and writing the image.
    pub write: f64,
}

/// Figures about the grid a frame was traced with.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct GridStats {
    /// Cells per axis.
    pub dims: [u32; 3],
    /// Objects indexed.
    pub objects: u32,
    /// Object references stored (an object counts once per overlapped cell).
    pub references: u64,
    /// Bytes of the grid's arrays.
    pub grid_bytes: u64,
    /// Bytes of the primitive store.
    pub store_bytes: u64,
    /// The mesh level (zeros when the scene has no meshes).
    pub meshes: MeshGridStats,
}

/// Figures about the mesh assets: the bottom level of the two-level grid.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct MeshGridStats {
    /// Distinct mesh assets.
    pub assets: u32,
    /// Triangles over all assets (each counted once, however many instances).
    pub triangles: u64,
    /// Triangle references in the mesh grids.
    pub references: u64,
    /// Bytes of the mesh grids.
    pub grid_bytes: u64,
    /// Bytes of the triangles in the tracer's layout.
    pub store_bytes: u64,
    /// Bytes of the indexed mesh data (positions, normals, faces) used for shading.
    pub data_bytes: u64,
    /// Grid bytes per triangle.
    pub grid_bytes_per_triangle: f64,
    /// Layout plus mesh data bytes per triangle.
    pub store_bytes_per_triangle: f64,
}

/// Statistics of one rendered frame. Serializes as its fields plus `mrays_per_s`, the
/// throughput [`RenderStats::mrays_per_s`] derives from them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderStats {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Worker threads used.
    pub threads: usize,
    /// Rays by kind.
    pub rays: RayCounts,
    /// Adaptive supersampling figures (zero when it is off).
    pub adaptive: AdaptiveCounts,
    /// Scene-level effects the frame was traced with.
    pub effects: Effects,
    /// Camera samples per pixel (AA × lens; 0 with adaptive supersampling, which varies).
    pub samples_per_pixel: u32,
    /// Bytes of the AOV buffers (0 when none was asked for).
    pub aov_bytes: u64,
    /// Samples dropped because their radiance was not finite (see [`super::finite`]).
    pub dropped: DroppedSamples,
    /// Seconds per stage.
    pub times: StageTimes,
    /// Grid figures.
    pub grid: GridStats,
    /// Cells visited and primitive tests per ray.
    pub traversal: TraversalStats,
    /// What the per-camera-sample budget of secondary rays did.
    pub ray_budget: BudgetStats,
    /// The path that traced the rays (`--simd`, resolved: never `auto`).
    pub simd: crate::simd::SimdLevel,
    /// Motion blur's figures.
    pub motion: MotionStats,
    /// Noise-driven adaptive sampling's figures.
    pub noise: NoiseStats,
}

impl Serialize for RenderStats {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        // Destructured so that a new field fails to compile until it is serialized here too.
        let Self {
            width,
            height,
            threads,
            rays,
            adaptive,
            effects,
            samples_per_pixel,
            aov_bytes,
            dropped,
            times,
            grid,
            traversal,
            ray_budget,
            simd,
            motion,
            noise,
        } = self;
        let mut s = serializer.serialize_struct("RenderStats", 17)?;
        s.serialize_field("width", width)?;
        s.serialize_field("height", height)?;
        s.serialize_field("threads", threads)?;
        s.serialize_field("rays", rays)?;
        s.serialize_field("mrays_per_s", &self.mrays_per_s())?;
        s.serialize_field("adaptive", adaptive)?;
        s.serialize_field("effects", effects)?;
        s.serialize_field("samples_per_pixel", samples_per_pixel)?;
        s.serialize_field("aov_bytes", aov_bytes)?;
        s.serialize_field("non_finite", dropped)?;
        s.serialize_field("times", times)?;
        s.serialize_field("grid", grid)?;
        s.serialize_field("traversal", traversal)?;
        s.serialize_field("ray_budget", ray_budget)?;
        s.serialize_field("simd", simd.name())?;
        s.serialize_field("motion", motion)?;
        s.serialize_field("noise", noise)?;
        s.end()
    }
}

impl RenderStats {
    /// Million rays per second of trace time.
    pub fn mrays_per_s(&self) -> f64 {
        if self.times.trace > 0.0 {
            self.rays.total() as f64 / self.times.trace / 1e6
        } else {
            0.0
        }
    }

    /// Seconds as `f64` from a duration.
    pub fn secs(d: Duration) -> f64 {
        d.as_secs_f64()
    }

    /// A human-readable multi-line summary.
    pub fn summary(&self) -> String {
        let t = &self.times;
        let r = &self.rays;
        format!(
            "image      {}x{}, {} threads, simd {}, {} camera samples per pixel, effects: {}\n\
             rays       {} total: camera {}, lens {}, shadow {}, area shadow {}, reflection {}, glossy {}, refraction {}, blurry {}\n\
             adaptive   {} points traced, {} reused, {} subdivisions\n\
             motion     {} moving objects, camera {}, {} camera samples timed\n\
             noise      {} rounds of {}-sample batches, samples per pixel mean {:.1}, p99 {}, min {}, max {}; estimated RMSE {:.3e}, mean display error {:.2e}, {} pixels above target, stopped by {:?}\n\
             {}\n\
             speed      {:.2} Mrays/s\n\
             grid       {}x{}x{} cells, {} objects, {} references, {} B grid, {} B store\n\
             meshes     {} assets, {} triangles, {} references, {} B grids ({:.1} B/triangle), {} B triangles + {} B mesh data ({:.1} B/triangle)\n\
             per ray    cells visited mean {:.2}, p99 {}; primitive tests mean {:.2}, p99 {} ({} rays)\n\
             ray budget {} secondary rays per camera sample: {} samples cut, {} rays refused, at most {} used by one sample\n\
             time (ms)  load {:.2}, script {:.2}, world {:.2}, grid build {:.2} (top level) + {:.2} (mesh grids), snapshot {:.2}, trace {:.2}, write {:.2}",
            self.width,
            self.height,
            self.threads,
            self.simd,
            self.samples_per_pixel,
            if self.effects.names().is_empty() { "none".to_string() } else { self.effects.names().join(", ") },
            r.total(),
            r.camera,
            r.lens,
            r.shadow,
            r.area_shadow,
            r.reflection,
            r.glossy,
            r.refraction,
            r.blurry,
            self.adaptive.traced,
            self.adaptive.reused,
            self.adaptive.subdivisions,
            self.motion.moving_objects,
            if self.motion.camera_moves { "moves" } else { "still" },
            self.motion.timed_samples,
            self.noise.rounds,
            self.noise.batch,
            self.noise.samples_mean,
            self.noise.samples_p99,
            self.noise.samples_min,
            self.noise.samples_max,
            self.noise.estimated_rmse,
            self.noise.mean_display_error,
            self.noise.pixels_above_target,
            self.noise.stopped_by,
            self.dropped.summary_line(),
            self.mrays_per_s(),
            self.grid.dims[0],
            self.grid.dims[1],
            self.grid.dims[2],
            self.grid.objects,
            self.grid.references,
            self.grid.grid_bytes,
            self.grid.store_bytes,
            self.grid.meshes.assets,
            self.grid.meshes.triangles,
            self.grid.meshes.references,
            self.grid.meshes.grid_bytes,
            self.grid.meshes.grid_bytes_per_triangle,
            self.grid.meshes.store_bytes,
            self.grid.meshes.data_bytes,
            self.grid.meshes.store_bytes_per_triangle,
            self.traversal.cells_mean,
            self.traversal.cells_p99,
            self.traversal.tests_mean,
            self.traversal.tests_p99,
            self.traversal.rays,
            self.ray_budget.max_secondary_rays,
            self.ray_budget.cut_samples,
            self.ray_budget.refused_rays,
            self.ray_budget.max_per_sample,
            t.load * 1e3,
            t.script * 1e3,
            t.world_update * 1e3,
            t.grid_build * 1e3,
            t.mesh_grid_build * 1e3,
            t.snapshot * 1e3,
            t.trace * 1e3,
            t.write * 1e3,
        )
    }
}

#[cfg(test)]
mod tests;
