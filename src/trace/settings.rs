//! How a snapshot is rendered: image size, depth, seed, and the sample counts and patterns of
//! every distribution effect. The renderer ([`super::render()`]) and the integrator read it.

use serde::Deserialize;

use crate::sample::{AdaptiveSettings, Filter, Pattern};

/// Default of [`RenderSettings::max_secondary_rays`]: the secondary rays one camera sample may
/// trace. The shipped scenes use at most a few hundred (see `docs/scene-format.md`).
pub const DEFAULT_MAX_SECONDARY_RAYS: u32 = 1024;

/// A sample count and the pattern that places the samples: the scene file's `lens`, `time`
/// and `glossy` fields, and the renderer's setting for each effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Sampling {
    /// Number of samples, 1..=4096. Default 1 (`settings.glossy` in a scene file: 8).
    pub samples: u32,
    /// Placement of the samples. Default `Jittered`.
    pub pattern: Pattern,
}

impl Default for Sampling {
    fn default() -> Self {
        Self { samples: 1, pattern: Pattern::Jittered }
    }
}

/// Anti-aliasing: camera samples per pixel, their pattern and the filter footprint (the scene
/// file's `settings.aa`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AntiAliasing {
    /// Camera samples per pixel, 1..=4096. Default 1.
    pub samples: u32,
    /// Placement of the samples over the pixel footprint. Default `Jittered`.
    pub pattern: Pattern,
    /// Reconstruction filter: the pixel (`Box`) or a tent two pixels wide. Default `Box`.
    pub filter: Filter,
}

impl Default for AntiAliasing {
    fn default() -> Self {
        Self { samples: 1, pattern: Pattern::Jittered, filter: Filter::Box }
    }
}

impl AntiAliasing {
    /// The sample count and pattern, as every other effect's [`Sampling`].
    pub fn sampling(&self) -> Sampling {
        Sampling { samples: self.samples, pattern: self.pattern }
    }
}

/// How to render a snapshot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Minimum path weight worth tracing.
    pub min_contribution: f32,
    /// Seed of all randomness.
    pub seed: u64,
    /// Frame number (part of every random sample's key).
    pub frame: u32,
    /// Anti-aliasing (ignored when `adaptive` is on).
    pub aa: AntiAliasing,
    /// Adaptive supersampling by corner subdivision; replaces `aa` when set.
    pub adaptive: Option<AdaptiveSettings>,
    /// Noise-driven adaptive sampling: batches of the fixed sample set (`aa` × lens × time)
    /// until each pixel's estimated error is low; ignored when `adaptive` is set.
    pub noise: Option<crate::sample::NoiseSettings>,
    /// Lens samples per camera sample (only when the camera has an aperture).
    pub lens: Sampling,
    /// Rays per glossy reflection or blurry refraction at the first bounce.
    pub glossy: Sampling,
    /// Secondary rays (reflection, refraction, glossy, blurry) one camera sample may trace;
    /// see `RayBudget` in `trace/path.rs`.
    pub max_secondary_rays: u32,
    /// Which path traces the rays: packets at an instruction-set level, or single rays (the
    /// image is the same bits on every one).
    pub simd: crate::simd::SimdLevel,
    /// When the shutter is open (motion blur). The tracer reads only the snapshot's motion,
    /// which the World derives over this interval; kept here so it is in every frame's
    /// provenance.
    pub shutter: Option<crate::camera::Shutter>,
    /// Time samples per camera sample where something moves while the shutter is open (each
    /// AA position and lens point is traced at this many times); ignored elsewhere.
    pub time: Sampling,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            max_depth: 5,
            min_contribution: 1e-3,
            seed: 0,
            frame: 0,
            aa: AntiAliasing::default(),
            adaptive: None,
            noise: None,
            lens: Sampling::default(),
            glossy: Sampling { samples: 8, pattern: Pattern::Jittered },
            max_secondary_rays: DEFAULT_MAX_SECONDARY_RAYS,
            simd: crate::simd::SimdLevel::Auto,
            shutter: None,
            time: Sampling::default(),
        }
    }
}
