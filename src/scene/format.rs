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

pub use crate::trace::light::Falloff;

pub use crate::film::{ToneMapping, ToneOperator};
pub use crate::sample::{Filter, Pattern};

/// A whole scene file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
pub struct SceneDesc {
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
    /// The meshes the objects name, loaded and gridded by `load_scene` (not part of the file).
    #[serde(skip)]
    pub meshes: super::mesh::MeshLibrary,
    /// The textures of `textures`, in order, then the images of the meshes' `.mtl` libraries,
    /// loaded by `load_scene` (not part of the file).
    #[serde(skip)]
    pub texture_table: std::sync::Arc<[crate::texture::Texture]>,
    /// Where in `texture_table` each `.mtl` library image went, by its path (not part of the
    /// file).
    #[serde(skip)]
    pub library_textures: Vec<(std::path::PathBuf, crate::texture::TextureId)>,
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
    pub lens: SamplingDesc,
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
    pub time: SamplingDesc,
}

/// How many points a distribution effect takes over its domain, and how they are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SamplingDesc {
    /// Number of samples, 1..=4096. Default 1 (`settings.glossy`: 8).
    pub samples: u32,
    /// Placement of the samples. Default `Jittered`.
    pub pattern: Pattern,
}

impl Default for SamplingDesc {
    fn default() -> Self {
        Self { samples: 1, pattern: Pattern::Jittered }
    }
}

/// Anti-aliasing: camera samples per pixel and how they are placed and weighted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AaDesc {
    /// Camera samples per pixel, 1..=4096. Default 1.
    pub samples: u32,
    /// Placement of the samples over the pixel footprint. Default `Jittered`.
    pub pattern: Pattern,
    /// Reconstruction filter. Default `Box`.
    pub filter: Filter,
}

impl Default for AaDesc {
    fn default() -> Self {
        Self { samples: 1, pattern: Pattern::Jittered, filter: Filter::Box }
    }
}

/// Adaptive supersampling by recursive corner subdivision; when on it replaces `aa`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AdaptiveDesc {
    /// A square is subdivided while its corner colours differ by more than this; finite, ≥ 0.
    /// Default 0.05.
    pub threshold: f32,
    /// Deepest subdivision level, 1..=6. Default 3.
    pub max_depth: u32,
}

impl Default for AdaptiveDesc {
    fn default() -> Self {
        Self { threshold: 0.05, max_depth: 3 }
    }
}

/// Noise-driven adaptive sampling: every pixel takes batches of camera samples (each batch the
/// scene's `aa` set, with lens and time samples) in rounds until its estimated error on the
/// display is below `target_error`. Not together with `adaptive`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NoiseDesc {
    /// A pixel stops once the standard error of its mean, in display units (sRGB, 0..1; 0.01
    /// is about 2.5/255), is at most this; finite, in [0, 1]. 0 samples to `max_samples`.
    /// Default 0.01.
    pub target_error: f32,
    /// Camera samples every pixel takes first, 1..=65536 (rounded up to whole batches, at
    /// least two). Default 16.
    pub min_samples: u32,
    /// Camera samples no pixel exceeds, `min_samples..=65536` (rounded up to whole batches).
    /// Default 1024.
    pub max_samples: u32,
    /// Seconds of tracing after which no further round starts (the image is always
    /// complete), finite and > 0. Default none.
    pub time_limit: Option<f32>,
}

impl Default for NoiseDesc {
    fn default() -> Self {
        let s = crate::sample::NoiseSettings::default();
        Self {
            target_error: s.target_error,
            min_samples: s.min_samples,
            max_samples: s.max_samples,
            time_limit: None,
        }
    }
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
    pub aa: AaDesc,
    /// Adaptive supersampling; replaces `aa` when given. Default none (off).
    pub adaptive: Option<AdaptiveDesc>,
    /// Noise-driven adaptive sampling in batches of the `aa` set; not with `adaptive`.
    /// Default none (off).
    pub noise: Option<NoiseDesc>,
    /// Rays per glossy reflection or blurry refraction at the first bounce (deeper bounces
    /// use one). Default 8, `Jittered`; a `glossy: (...)` without `samples` also gets 8.
    #[serde(deserialize_with = "glossy_sampling")]
    pub glossy: SamplingDesc,
    /// Secondary rays (reflection, refraction, glossy, blurry) one camera sample may trace;
    /// a ray tree that would grow past it is cut and counted in the statistics. In
    /// 1..=16777216. Default 1024.
    pub max_secondary_rays: u32,
    /// How 8- and 16-bit outputs map linear light to display values (EXR stays linear).
    /// Default: clamp, exposure 0.
    pub tonemap: ToneMapDesc,
}

/// Tone mapping of 8- and 16-bit outputs.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ToneMapDesc {
    /// `Clamp`, `Reinhard` or `Aces` (filmic). Default `Clamp`.
    pub operator: ToneOperator,
    /// Exposure in stops (linear values × 2^exposure), in [-30, 30]. Default 0.
    pub exposure: f32,
    /// White point of `Reinhard`: the exposed value that maps to 1, > 0. Default 4.
    pub white: f32,
}

impl Default for ToneMapDesc {
    fn default() -> Self {
        let t = ToneMapping::default();
        Self { operator: t.operator, exposure: t.exposure, white: t.white }
    }
}

impl Default for SettingsDesc {
    fn default() -> Self {
        Self {
            max_depth: 5,
            min_contribution: 1e-3,
            background: Vec3::ZERO,
            ambient: Vec3::splat(0.1),
            seed: 0,
            aa: AaDesc::default(),
            adaptive: None,
            noise: None,
            glossy: SamplingDesc { samples: DEFAULT_GLOSSY_SAMPLES, pattern: Pattern::Jittered },
            max_secondary_rays: crate::trace::integrator::DEFAULT_MAX_SECONDARY_RAYS,
            tonemap: ToneMapDesc::default(),
        }
    }
}

/// A named Phong material.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDesc {
    /// Unique name that objects refer to.
    pub name: String,
    /// Diffuse reflectance (RGB), each channel in [0, 1].
    pub kd: Vec3,
    /// Specular reflectance in [0, 1]. Default 0.
    #[serde(default)]
    pub ks: f32,
    /// Phong exponent, ≥ 0. Default 32.
    #[serde(default = "default_shininess")]
    pub shininess: f32,
    /// Mirror reflectance in [0, 1]. Default 0.
    #[serde(default)]
    pub kr: f32,
    /// Transmittance in [0, 1]: a number, or a colour `(r, g, b)` for tinted glass (its
    /// shadows are tinted too); `kr + kt` must not exceed 1 in any channel. Default 0.
    #[serde(default, deserialize_with = "grey_or_colour")]
    pub kt: Vec3,
    /// Index of refraction, > 0. Default 1.5.
    #[serde(default = "default_ior")]
    pub ior: f32,
    /// Blur of reflection and refraction in [0, 1]: rays spread over a cone of half-angle
    /// `glossiness × 45°` around the mirror (`kr`) or refracted (`kt`) direction; 0 is a
    /// perfect mirror. Default 0.
    #[serde(default)]
    pub glossiness: f32,
    /// Light the surface gives off towards every viewer (linear RGB, each channel ≥ 0): a lamp
    /// shade that glows. It lights nothing else (use a light for that). Default black.
    #[serde(default)]
    pub emission: Vec3,
    /// Balance `kr` and `kt` by Schlick's Fresnel term (for glass, water): the part of `kt`
    /// that the surface reflects at each angle moves to the mirror, so reflection grows at
    /// grazing angles and `kr + kt` is kept. Default false.
    #[serde(default)]
    pub fresnel: bool,
    /// Beer–Lambert absorption inside the material per unit of distance (RGB, each channel
    /// ≥ 0): light travelling `d` inside keeps `exp(−absorption·d)`, so thick glass is darker
    /// than thin. Applies to rays inside the object (refraction), not to shadow rays. Default 0.
    #[serde(default)]
    pub absorption: Vec3,
    /// Name of a texture in `textures` that `kd` is multiplied by. Default none.
    #[serde(default)]
    pub kd_texture: Option<String>,
    /// Name of a texture in `textures` whose mean of channels `ks` is multiplied by. Default
    /// none.
    #[serde(default)]
    pub ks_texture: Option<String>,
    /// Name of a texture in `textures` used as a height map (the mean of its channels, 0 to 1)
    /// that tilts the shading normal: the surface looks displaced along its normal. Default
    /// none.
    #[serde(default)]
    pub bump_texture: Option<String>,
    /// How far heights 0 to 1 of `bump_texture` displace the surface, as a fraction of the
    /// length of one unit of (u, v) on it, so bumps scale with the object; finite, negative for
    /// dents. Default 0.01.
    #[serde(default = "default_bump_depth")]
    pub bump_depth: f32,
}

fn default_bump_depth() -> f32 {
    DEFAULT_BUMP_DEPTH
}

/// [`MaterialDesc::bump_depth`] when the scene gives none.
pub const DEFAULT_BUMP_DEPTH: f32 = 0.01;

/// A named texture: a colour that varies over surfaces, by their (u, v) coordinates.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    /// Unique name that materials refer to.
    pub name: String,
    /// What the texture is.
    pub kind: TextureKindDesc,
    /// Scale of (u, v) before the lookup: a checker with scale (4, 4) has four squares per
    /// unit of u; each component non-zero and finite. Default (1, 1).
    #[serde(default = "default_uv_scale")]
    pub scale: Vec2,
    /// Added to the scaled and rotated (u, v); finite. Scripts animate it. Default (0, 0).
    #[serde(default)]
    pub offset: Vec2,
    /// Rotation of the scaled (u, v) about the origin, counter-clockwise, in degrees; finite.
    /// Default 0.
    #[serde(default)]
    pub rotate_deg: f32,
}

/// The kinds of texture.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum TextureKindDesc {
    /// An image file (PNG, JPEG or EXR) relative to the scene, looked up bilinearly; t = 0 is
    /// the picture's bottom row.
    Image {
        /// File name, relative to the scene's folder.
        file: String,
        /// `Repeat` (tile) or `Clamp` (edge texels extend). Default `Repeat`.
        #[serde(default)]
        wrap: crate::texture::Wrap,
        /// `Srgb` (8- and 16-bit pictures, decoded to linear) or `Linear`; EXR is always
        /// linear. Default `Srgb`.
        #[serde(default)]
        colour_space: crate::texture::ColourSpace,
    },
    /// Unit squares alternating `a` and `b` (`a` where ⌊s⌋ + ⌊t⌋ is even).
    Checker {
        /// First colour (linear RGB, each channel in [0, 1]).
        a: Vec3,
        /// Second colour.
        b: Vec3,
    },
    /// Stripes one unit wide across s, alternating `a` and `b`.
    Stripes {
        /// First colour.
        a: Vec3,
        /// Second colour.
        b: Vec3,
    },
    /// `a` at s = 0 blending linearly to `b` at s = 1, clamped outside.
    Gradient {
        /// Colour at s = 0.
        a: Vec3,
        /// Colour at s = 1.
        b: Vec3,
    },
    /// Fractal Perlin noise blending `a` (0) to `b` (1).
    Noise {
        /// Colour where the noise is lowest.
        a: Vec3,
        /// Colour where it is highest.
        b: Vec3,
        /// Octaves of detail, 1..=16. Default 4.
        #[serde(default = "default_octaves")]
        octaves: u32,
        /// Seed of the noise. Default 0.
        #[serde(default)]
        seed: u32,
    },
}

fn default_uv_scale() -> Vec2 {
    Vec2::ONE
}

fn default_octaves() -> u32 {
    4
}

impl MaterialDesc {
    /// The engine material these parameters describe.
    /// Textures are looked up by name in `textures` (the scene's table; validated, so a name
    /// missing there is left untextured).
    pub fn material(&self, textures: &[TextureDesc]) -> crate::trace::Material {
        let find = |name: &Option<String>| {
            let name = name.as_deref()?;
            let i = textures.iter().position(|t| t.name == name)?;
            Some(crate::texture::TextureId(i as u32))
        };
        crate::trace::Material {
            kd: self.kd,
            ks: self.ks,
            shininess: self.shininess,
            kr: self.kr,
            kt: self.kt,
            ior: self.ior,
            glossiness: self.glossiness,
            emission: self.emission,
            fresnel: self.fresnel,
            absorption: self.absorption,
            maps: crate::trace::material::Maps {
                kd: find(&self.kd_texture),
                ks: find(&self.ks_texture),
                bump: find(&self.bump_texture)
                    .map(|texture| crate::trace::material::Bump { texture, depth: self.bump_depth }),
            },
        }
    }

    /// The description of an engine material, under `name`; its textures named from `textures`
    /// (the names of the scene's texture table).
    pub fn describe(name: &str, m: &crate::trace::Material, textures: &[String]) -> Self {
        let crate::trace::Material {
            kd,
            ks,
            shininess,
            kr,
            kt,
            ior,
            glossiness,
            emission,
            fresnel,
            absorption,
            maps,
        } = *m;
        let named =
            |t: Option<crate::texture::TextureId>| t.and_then(|t| textures.get(t.0 as usize).cloned());
        Self {
            name: name.to_owned(),
            kd,
            ks,
            shininess,
            kr,
            kt,
            ior,
            glossiness,
            emission,
            fresnel,
            absorption,
            kd_texture: named(maps.kd),
            ks_texture: named(maps.ks),
            bump_texture: named(maps.bump.map(|b| b.texture)),
            bump_depth: maps.bump.map_or(DEFAULT_BUMP_DEPTH, |b| b.depth),
        }
    }
}

/// A light source.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum LightDesc {
    /// A point light, by default with no distance falloff (as in classic Phong and POV-Ray).
    Point {
        /// Position.
        position: DVec3,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// `None` or `InverseSquare` (colour × intensity arrives one unit away). Default `None`.
        #[serde(default)]
        falloff: Falloff,
    },
    /// A spot light: a point light shining into a cone, with a soft edge.
    Spot {
        /// Position.
        position: DVec3,
        /// The point the cone's axis aims at; must differ from `position`.
        look_at: DVec3,
        /// Half-angle of the cone in degrees, in (0, 90]: no light outside it.
        cone_deg: f32,
        /// Width of the soft edge in degrees, in [0, cone_deg]: the light fades smoothly from
        /// full at `cone_deg − soft_deg` to nothing at `cone_deg`. Default 5 (at most `cone_deg`).
        #[serde(default)]
        soft_deg: Option<f32>,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// `None` or `InverseSquare`. Default `None`.
        #[serde(default)]
        falloff: Falloff,
    },
    /// A light infinitely far away, shining along `direction`.
    Directional {
        /// Direction the light travels in (from the light towards the scene); non-zero.
        direction: Vec3,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
    },
    /// A parallelogram area light `corner + s·edge_u + t·edge_v` (s, t in [0, 1]), emitting
    /// to both sides, invisible to camera rays unless `visible`; colour × intensity is spread over the samples.
    Rect {
        /// One corner.
        corner: DVec3,
        /// First edge from `corner`; non-zero.
        edge_u: Vec3,
        /// Second edge from `corner`; non-zero and not parallel to `edge_u`.
        edge_v: Vec3,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// Shadow rays per shading point, 1..=4096. Default 16.
        #[serde(default = "default_light_samples")]
        samples: u32,
        /// Placement of the samples over the light. Default `Jittered`.
        #[serde(default)]
        pattern: Pattern,
        /// `None` or `InverseSquare`, from each sample's point. Default `None`.
        #[serde(default)]
        falloff: Falloff,
        /// Whether camera, reflection and refraction rays see the light (it shows colour ×
        /// intensity, from both sides); it never casts a shadow. Default false.
        #[serde(default)]
        visible: bool,
    },
    /// A disk area light, emitting to both sides, invisible to camera rays unless `visible`; colour ×
    /// intensity is spread over the samples.
    Disk {
        /// Centre.
        centre: DVec3,
        /// Normal of the disk's plane; non-zero.
        normal: Vec3,
        /// Radius, > 0.
        radius: f32,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// Shadow rays per shading point, 1..=4096. Default 16.
        #[serde(default = "default_light_samples")]
        samples: u32,
        /// Placement of the samples over the light. Default `Jittered`.
        #[serde(default)]
        pattern: Pattern,
        /// `None` or `InverseSquare`, from each sample's point. Default `None`.
        #[serde(default)]
        falloff: Falloff,
        /// Whether camera, reflection and refraction rays see the light (it shows colour ×
        /// intensity, from both sides); it never casts a shadow. Default false.
        #[serde(default)]
        visible: bool,
    },
}

/// One renderable object.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    /// Unique name (scripts address objects by it). Default: the shape kind and index, e.g. `sphere_3`.
    #[serde(default)]
    pub name: Option<String>,
    /// Geometry in object space.
    pub shape: ShapeDesc,
    /// Name of a material defined in `materials`.
    pub material: String,
    /// Placement in the world. Default: identity.
    #[serde(default)]
    pub transform: TransformDesc,
}

/// Geometry of an object, in object space.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeDesc {
    /// A sphere; `radius` > 0.
    Sphere {
        /// Centre.
        centre: DVec3,
        /// Radius, > 0.
        radius: f32,
    },
    /// An infinite plane through `point` with the given (non-zero) normal.
    Plane {
        /// Any point on the plane.
        point: DVec3,
        /// Normal; need not be unit length, must be non-zero.
        normal: Vec3,
    },
    /// A single triangle; must have non-zero area.
    Triangle {
        /// The three corners, counter-clockwise seen from the front.
        vertices: [DVec3; 3],
    },
    /// A convex planar polygon of at least three vertices, in order around its boundary.
    Polygon {
        /// The corners in order.
        vertices: Vec<DVec3>,
    },
    /// An axis-aligned box (in object space; a rotation in `transform` orients it).
    #[serde(rename = "Box")]
    Cuboid {
        /// Minimum corner.
        min: DVec3,
        /// Maximum corner; strictly greater than `min` on every axis.
        max: DVec3,
    },
    /// A triangle mesh from a Wavefront OBJ file, placed by the object's `transform`. Every
    /// object naming the same file (and `smooth` and `materials`) shares one copy of it and one
    /// grid.
    Mesh {
        /// The OBJ file, relative to the scene file.
        file: String,
        /// Phong shading with interpolated vertex normals (the file's, or computed weighted by
        /// area and angle); `false` shows flat facets. Default `true`.
        #[serde(default = "default_true")]
        smooth: bool,
        /// `Object`: the object's `material` everywhere; `FromFile`: each face's material from
        /// the file's `.mtl` libraries (`mtllib`, `usemtl`), a scene material of the same name
        /// taking the place of the library's. Default `Object`.
        #[serde(default)]
        materials: MeshMaterials,
    },
}

/// Where a mesh's materials come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
pub enum MeshMaterials {
    /// The object's `material`, on every face.
    #[default]
    Object,
    /// The OBJ's `.mtl` libraries, face by face (faces before any `usemtl` take the object's
    /// `material`); a scene material named like a library material replaces it.
    FromFile,
}

impl ShapeDesc {
    /// For a mesh, the key its asset is loaded under: file, `smooth`, and whether its faces
    /// carry the file's materials.
    pub fn mesh_key(&self) -> Option<(&str, bool, bool)> {
        match self {
            ShapeDesc::Mesh { file, smooth, materials } => {
                Some((file, *smooth, *materials == MeshMaterials::FromFile))
            }
            _ => None,
        }
    }
}

fn default_true() -> bool {
    true
}

impl ShapeDesc {
    /// Lower-case kind name, used for default object names (`sphere`, `plane`, ...).
    pub fn kind(&self) -> &'static str {
        match self {
            ShapeDesc::Sphere { .. } => "sphere",
            ShapeDesc::Plane { .. } => "plane",
            ShapeDesc::Triangle { .. } => "triangle",
            ShapeDesc::Polygon { .. } => "polygon",
            ShapeDesc::Cuboid { .. } => "box",
            ShapeDesc::Mesh { .. } => "mesh",
        }
    }
}

/// Object-to-world placement: scale, then rotate (X, then Y, then Z, in degrees), then translate.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TransformDesc {
    /// Translation.
    pub translate: DVec3,
    /// Rotation in degrees about X, then Y, then Z.
    pub rotate_deg: Vec3,
    /// Per-axis scale, each non-zero; spheres require a uniform scale.
    pub scale: Vec3,
}

impl Default for TransformDesc {
    fn default() -> Self {
        Self { translate: DVec3::ZERO, rotate_deg: Vec3::ZERO, scale: Vec3::ONE }
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

/// `settings.glossy` as written: like [`SamplingDesc`], but an omitted `samples` is 8, not 1.
#[derive(Deserialize)]
#[serde(rename = "SamplingDesc", default, deny_unknown_fields)]
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

fn glossy_sampling<'de, D: Deserializer<'de>>(deserializer: D) -> Result<SamplingDesc, D::Error> {
    let GlossySampling { samples, pattern } = GlossySampling::deserialize(deserializer)?;
    Ok(SamplingDesc { samples, pattern })
}
