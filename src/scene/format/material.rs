//! The scene file's materials and textures.

use super::*;

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

impl MaterialDesc {
    /// A matte material `name` of diffuse colour `kd`; every other field takes the default a
    /// scene file gives it (the engine material's default, [`crate::trace::Material`]).
    pub fn new(name: &str, kd: impl Into<Vec3>) -> Self {
        Self::describe(name, &crate::trace::Material { kd: kd.into(), ..Default::default() }, &[])
    }
}
