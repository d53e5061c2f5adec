//! Render statistics: rays by kind, time per stage, grid figures.

use std::time::Duration;

use serde::Serialize;

use super::effects::Effects;

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
    }
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
    /// Building the grid (zero on frames that reuse it).
    pub grid_build: f64,
    /// Flattening the World into the snapshot.
    pub snapshot: f64,
    /// Tracing.
    pub trace: f64,
    /// Encoding and writing the image.
    pub write: f64,
}

/// Figures about the grid a frame was traced with.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
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
}

/// Statistics of one rendered frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
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
    /// Seconds per stage.
    pub times: StageTimes,
    /// Grid figures.
    pub grid: GridStats,
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
            "image      {}x{}, {} threads, {} camera samples per pixel, effects: {}\n\
             rays       {} total: camera {}, lens {}, shadow {}, area shadow {}, reflection {}, glossy {}, refraction {}, blurry {}\n\
             adaptive   {} points traced, {} reused, {} subdivisions\n\
             speed      {:.2} Mrays/s\n\
             grid       {}x{}x{} cells, {} objects, {} references, {} B grid, {} B store\n\
             time (ms)  load {:.2}, script {:.2}, world {:.2}, grid build {:.2}, snapshot {:.2}, trace {:.2}, write {:.2}",
            self.width,
            self.height,
            self.threads,
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
            self.mrays_per_s(),
            self.grid.dims[0],
            self.grid.dims[1],
            self.grid.dims[2],
            self.grid.objects,
            self.grid.references,
            self.grid.grid_bytes,
            self.grid.store_bytes,
            t.load * 1e3,
            t.script * 1e3,
            t.world_update * 1e3,
            t.grid_build * 1e3,
            t.snapshot * 1e3,
            t.trace * 1e3,
            t.write * 1e3,
        )
    }
}
