//! The RON scene schema: the serde types a `scenes/*.ron` file deserializes into.
//!
//! These types are the documented file format; they hold exactly what the file says, in
//! file units (degrees, scene units). [`super::validate`] checks the rules that serde cannot
//! express (ranges, geometry, references) and [`super::load`] ties the two together.
//!
//! ```ron
//! Scene(
//!     camera: (position: (0, 1.5, -6), look_at: (0, 0.8, 0), up: (0, 1, 0),
//!              fov_deg: 45, width: 640, height: 480,
//!              aperture: 0.1, focus_on: (0, 1, 0), lens: (samples: 8, pattern: Jittered)),
//!     settings: (max_depth: 5, min_contribution: 0.001, background: (0.05, 0.07, 0.1),
//!                ambient: (0.1, 0.1, 0.1), seed: 7,
//!                aa: (samples: 4, pattern: Jittered, filter: Box), adaptive: None,
//!                glossy: (samples: 8)),
//!     materials: [
//!         (name: "matte", kd: (0.8, 0.2, 0.2)),
//!         (name: "mirror", kd: (0.05, 0.05, 0.05), ks: 0.9, shininess: 200, kr: 0.9),
//!         (name: "glass", kd: (0, 0, 0), ks: 0.5, shininess: 300, kr: 0.1, kt: 0.9, ior: 1.5),
//!     ],
//!     lights: [
//!         Point(position: (-4, 6, -3), colour: (1, 1, 1), intensity: 0.8),
//!         Directional(direction: (1, -1, 1), colour: (1, 0.95, 0.9), intensity: 0.3),
//!         Rect(corner: (-1, 4, -1), edge_u: (2, 0, 0), edge_v: (0, 0, 1), samples: 16),
//!         Disk(centre: (2, 3, 0), normal: (0, -1, 0), radius: 0.5, pattern: Grid),
//!     ],
//!     objects: [
//!         (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "matte"),
//!         (name: "ball", shape: Sphere(centre: (0, 1, 0), radius: 1), material: "mirror"),
//!         (shape: Triangle(vertices: ((0, 0, 0), (1, 0, 0), (0, 1, 0))), material: "matte"),
//!         (shape: Polygon(vertices: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]), material: "matte"),
//!         (shape: Box(min: (-1, 0, -1), max: (1, 1, 1)), material: "glass",
//!          transform: (translate: (2, 0, 0), rotate_deg: (0, 30, 0), scale: (1, 1, 1))),
//!     ],
//! )
//! ```
//!
//! Vectors and colours are RON tuples `(x, y, z)`; integers are accepted where floats are
//! expected. Positions (the camera's `position`, `look_at` and `focus_on`, lights' `position`,
//! `corner` and `centre`, shapes' points and `transform.translate`) are 64-bit floats, so
//! `1000000.1` keeps every digit; the renderer subtracts the camera position before rounding
//! to 32 bits. Directions, sizes, angles and colours are 32-bit. Colours are linear RGB. Sample patterns ([`Pattern`]) and filters ([`Filter`])
//! are the sampler's own types, written as bare names.

use glam::{DVec3, Vec2, Vec3};
use serde::{Deserialize, Deserializer};

mod light;
mod material;
mod object;

pub use light::*;
pub use material::*;
pub use object::*;

pub use crate::trace::light::Falloff;

pub use crate::film::{ToneMapping, ToneOperator};
pub use crate::sample::{AdaptiveSettings, NoiseSettings};
pub use crate::sample::{Filter, Pattern};
pub use crate::trace::{AntiAliasing, Sampling};

/// A whole scene file, as written: what [`super::SceneDesc`] holds beside the assets it
/// names.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
pub struct SceneFile {
    /// The pinhole camera.
    pub camera: CameraDesc,
    /// Render settings; every field has a default.
    #[serde(default)]
    pub settings: SettingsDesc,
    /// Named materials, referenced by objects; their order defines material ids.
    pub materials: Vec<MaterialDesc>,
    /// Named textures, referenced by materials (`kd_texture`, `ks_texture`). Default none.
    #[serde(default)]
    pub textures: Vec<TextureDesc>,
    /// Light sources.
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    /// Renderable objects.
    pub objects: Vec<ObjectDesc>,
}

impl SceneFile {
    /// The tracer's settings this file gives: its `settings`, and the camera's image size,
    /// lens, time samples and shutter (frame 0, SIMD level `auto`).
    pub fn render_settings(&self) -> crate::trace::RenderSettings {
        let (c, s) = (&self.camera, &self.settings);
        crate::trace::RenderSettings {
            width: c.width,
            height: c.height,
            max_depth: s.max_depth,
            min_contribution: s.min_contribution,
            seed: s.seed,
            frame: 0,
            aa: s.aa,
            adaptive: s.adaptive,
            noise: s.noise,
            lens: c.lens,
            glossy: s.glossy,
            max_secondary_rays: s.max_secondary_rays,
            simd: crate::simd::SimdLevel::Auto,
            // Validated on load: `0 <= open <= close <= 1`.
            shutter: c.shutter.and_then(|(open, close)| crate::camera::Shutter::new(open, close).ok()),
            time: c.time,
        }
    }
}

/// The camera: where it is, where it looks and the image it makes.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    pub position: DVec3,
    /// Point the camera looks at; must differ from `position`.
    pub look_at: DVec3,
    /// Up direction; must not be parallel to the view direction. Default `(0, 1, 0)`.
    #[serde(default = "default_up")]
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_deg: f32,
    /// Image width in pixels, 1..=16384.
    pub width: u32,
    /// Image height in pixels, 1..=16384.
    pub height: u32,
    /// Lens radius, ≥ 0, in scene units. Default 0: a pinhole, everything in focus.
    #[serde(default)]
    pub aperture: f32,
    /// Distance from the eye to the plane in focus, along the view direction, > 0. Exclusive
    /// with `focus_on`; with neither, it is `|look_at - position|`. Default none.
    #[serde(default)]
    pub focus_distance: Option<f32>,
    /// A point to focus on: the focus distance is its depth along the view direction, so it
    /// must lie in front of the camera. Exclusive with `focus_distance`. Default none.
    #[serde(default)]
    pub focus_on: Option<DVec3>,
    /// Lens samples per camera sample, used only when `aperture` > 0. Default 1, `Jittered`.
    #[serde(default)]
    pub lens: Sampling,
    /// Motion blur: when the shutter is open, `(open, close)` as fractions of the frame
    /// interval, `0 <= open <= close <= 1` (`(0.0, 0.5)` is a film camera's 180° shutter).
    /// With a shutter, `animate` runs the script at both ends of the interval and whatever
    /// moved between them (objects, the camera) is blurred along its motion; each camera
    /// sample takes a time in the interval. Default none: every frame is an instant.
    #[serde(default)]
    pub shutter: Option<(f32, f32)>,
    /// Time samples per camera sample, used only where something moves while the shutter is
    /// open: each AA position (and lens point) is traced at this many times, stratified over
    /// the shutter interval with the pixel's other samples. Default 1, `Jittered` (`Grid` puts
    /// each time at its stratum's middle, `Random` anywhere in the interval).
    #[serde(default)]
    pub time: Sampling,
}

/// Render settings stored with the scene.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SettingsDesc {
    /// Maximum recursion depth of reflection and refraction (0 = primary rays only). Default 5, at most 64.
    pub max_depth: u32,
    /// A secondary ray is not traced once its path weight falls below this, in [0, 1]. Default 0.001.
    pub min_contribution: f32,
    /// Colour of rays that hit nothing. Default black.
    pub background: Vec3,
    /// Ambient light, multiplied by each material's `kd`. Default `(0.1, 0.1, 0.1)`.
    pub ambient: Vec3,
    /// Seed of every random choice the renderer makes. Default 0.
    pub seed: u64,
    /// Anti-aliasing. Default 1 sample per pixel, `Jittered`, `Box`.
    pub aa: AntiAliasing,
    /// Adaptive supersampling; replaces `aa` when given. Default none (off).
    pub adaptive: Option<AdaptiveSettings>,
    /// Noise-driven adaptive sampling in batches of the `aa` set; not with `adaptive`.
    /// Default none (off).
    pub noise: Option<NoiseSettings>,
    /// Rays per glossy reflection or blurry refraction at the first bounce (deeper bounces
    /// use one). Default 8, `Jittered`; a `glossy: (...)` without `samples` also gets 8.
    #[serde(deserialize_with = "glossy_sampling")]
    pub glossy: Sampling,
    /// Secondary rays (reflection, refraction, glossy, blurry) one camera sample may trace;
    /// a ray tree that would grow past it is cut and counted in the statistics. In
    /// 1..=16777216. Default 1024.
    pub max_secondary_rays: u32,
    /// How 8- and 16-bit outputs map linear light to display values (EXR stays linear).
    /// Default: clamp, exposure 0.
    pub tonemap: ToneMapping,
}

impl Default for SettingsDesc {
    fn default() -> Self {
        Self {
            max_depth: 5,
            min_contribution: 1e-3,
            background: Vec3::ZERO,
            ambient: Vec3::splat(0.1),
            seed: 0,
            aa: AntiAliasing::default(),
            adaptive: None,
            noise: None,
            glossy: Sampling { samples: DEFAULT_GLOSSY_SAMPLES, pattern: Pattern::Jittered },
            max_secondary_rays: crate::trace::DEFAULT_MAX_SECONDARY_RAYS,
            tonemap: ToneMapping::default(),
        }
    }
}

impl CameraDesc {
    /// A pinhole camera at `position` looking at `look_at` (up `+y`) with a vertical field of
    /// view of `fov_deg` degrees, making `width × height` images; every other field takes the
    /// default a scene file gives it.
    pub fn new(position: DVec3, look_at: DVec3, fov_deg: f32, width: u32, height: u32) -> Self {
        Self {
            position,
            look_at,
            up: default_up(),
            fov_deg,
            width,
            height,
            aperture: 0.0,
            focus_distance: None,
            focus_on: None,
            lens: Sampling::default(),
            shutter: None,
            time: Sampling::default(),
        }
    }
}

fn default_up() -> Vec3 {
    Vec3::Y
}
fn default_shininess() -> f32 {
    32.0
}
fn default_ior() -> f32 {
    1.5
}
fn default_colour() -> Vec3 {
    Vec3::ONE
}
fn default_intensity() -> f32 {
    1.0
}
fn default_light_samples() -> u32 {
    16
}

/// Default `settings.glossy.samples`.
const DEFAULT_GLOSSY_SAMPLES: u32 = 8;

/// `settings.glossy` as written: like [`Sampling`], but an omitted `samples` is 8, not 1.
#[derive(Deserialize)]
#[serde(rename = "Sampling", default, deny_unknown_fields)]
struct GlossySampling {
    samples: u32,
    pattern: Pattern,
}

impl Default for GlossySampling {
    fn default() -> Self {
        Self { samples: DEFAULT_GLOSSY_SAMPLES, pattern: Pattern::Jittered }
    }
}

/// A colour written as one number (grey, every channel the same) or as `(r, g, b)`.
fn grey_or_colour<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec3, D::Error> {
    struct GreyOrColour;
    impl<'de> serde::de::Visitor<'de> for GreyOrColour {
        type Value = Vec3;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a number or a colour (r, g, b)")
        }
        fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Vec3, E> {
            Ok(Vec3::splat(v as f32))
        }
        fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Vec3, E> {
            Ok(Vec3::splat(v as f32))
        }
        fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Vec3, E> {
            Ok(Vec3::splat(v as f32))
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Vec3, A::Error> {
            let mut c = [0.0f32; 3];
            for (i, slot) in c.iter_mut().enumerate() {
                *slot = seq.next_element()?.ok_or_else(|| serde::de::Error::invalid_length(i, &self))?;
            }
            if seq.next_element::<f32>()?.is_some() {
                return Err(serde::de::Error::invalid_length(4, &self));
            }
            Ok(Vec3::from_array(c))
        }
    }
    deserializer.deserialize_any(GreyOrColour)
}

fn glossy_sampling<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Sampling, D::Error> {
    let GlossySampling { samples, pattern } = GlossySampling::deserialize(deserializer)?;
    Ok(Sampling { samples, pattern })
}
