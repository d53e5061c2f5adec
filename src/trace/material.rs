//! Phong material parameters, in engine form, with the optional parts a material pays for
//! only when it uses them: textures on its colours, emission, and Schlick's Fresnel term.

use crate::math::Vec3;
use crate::texture::TextureId;

/// A Phong material with mirror reflection and transmission.
///
/// Laid out by hand: each colour starts a 16-byte block (offsets 0, 16, 32, 48), followed by
/// one `f32`. A lane's shading copies its material with 16-byte moves and reads a colour back
/// at once; a colour across two of those stores was a load the CPU could not forward (18 % of
/// `shade_packet`'s own samples on the spheres twin, commit 16a4b3c).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(16))]
pub struct Material {
    /// Diffuse reflectance (RGB); multiplied by [`Maps::kd`] where that is set.
    pub kd: Vec3,
    /// Specular reflectance; multiplied by the mean of [`Maps::ks`]'s colour where set.
    pub ks: f32,
    /// Transmittance (RGB: tinted glass passes some colours more than others).
    pub kt: Vec3,
    /// Phong exponent.
    pub shininess: f32,
    /// Light the surface gives off towards every viewer (a glowing lamp shade); it lights
    /// nothing else. Zero for most materials.
    pub emission: Vec3,
    /// Mirror reflectance.
    pub kr: f32,
    /// Beer–Lambert absorption inside the material, per unit of distance (RGB, ≥ 0): light
    /// that travels `d` inside keeps `exp(−absorption·d)`. Zero for most materials.
    pub absorption: Vec3,
    /// Index of refraction.
    pub ior: f32,
    /// Blur of reflection and refraction in [0, 1] (used by distribution effects).
    pub glossiness: f32,
    /// Whether `kr` and `kt` are balanced by Schlick's Fresnel term at each hit
    /// ([`Material::fresnel_split`]): glass reflects more at grazing angles.
    pub fresnel: bool,
    /// Textures on the material's colours.
    pub maps: Maps,
}

/// The textures a material's colours are multiplied by, and its bump map, as indices into the
/// snapshot's texture table.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Maps {
    /// Texture of the diffuse colour.
    pub kd: Option<TextureId>,
    /// Texture of the specular reflectance (its channels' mean).
    pub ks: Option<TextureId>,
    /// A height map (its channels' mean) that tilts the shading normal, and its depth.
    pub bump: Option<Bump>,
}

/// A bump map: the surface seen as displaced along its normal by the texture's height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bump {
    /// The height texture (the mean of its channels, 0 to 1).
    pub texture: TextureId,
    /// How far heights 0 to 1 displace the surface, as a fraction of the length of one unit of
    /// (u, v) on it (so bumps scale with the object); may be negative (dents).
    pub depth: f32,
}

impl Maps {
    /// True when nothing is textured: the material is the same everywhere.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.kd.is_none() && self.ks.is_none() && self.bump.is_none()
    }

    /// Every texture named.
    pub fn textures(&self) -> impl Iterator<Item = TextureId> {
        [self.kd, self.ks, self.bump.map(|b| b.texture)].into_iter().flatten()
    }
}

impl Default for Material {
    fn default() -> Self {
        Self {
            kd: Vec3::splat(0.5),
            ks: 0.0,
            shininess: 32.0,
            kr: 0.0,
            kt: Vec3::ZERO,
            ior: 1.5,
            glossiness: 0.0,
            emission: Vec3::ZERO,
            fresnel: false,
            absorption: Vec3::ZERO,
            maps: Maps::default(),
        }
    }
}

impl Material {
    /// True when the material mirrors some light: `kr > 0`, or Fresnel moving part of `kt`
    /// to the mirror.
    #[inline]
    pub fn reflects(&self) -> bool {
        self.kr > 0.0 || (self.fresnel && self.transmits())
    }

    /// True when some light passes through the material (`kt` > 0 in some channel).
    #[inline]
    pub fn transmits(&self) -> bool {
        self.kt.max_element() > 0.0
    }

    /// The mirror and transmission weights at a hit whose incoming direction makes cosine
    /// `cos_i` (in [0, 1]) with the normal, arriving from outside (`entering`) or from inside
    /// the material: `(kr, kt)` unchanged without Fresnel; with it, the part `F` that Schlick's
    /// approximation reflects moves from `kt` to the (untinted) mirror,
    /// `(kr + F·max(kt), (1 − F)·kt)`, so `kr + kt` is kept (in `kt`'s largest channel).
    #[inline]
    pub fn fresnel_split(&self, cos_i: f32, entering: bool) -> (f32, Vec3) {
        if !self.fresnel || !self.transmits() {
            return (self.kr, self.kt);
        }
        let (n1, n2) = if entering { (1.0, self.ior) } else { (self.ior, 1.0) };
        let f = schlick(cos_i, n1, n2);
        (self.kr + self.kt.max_element() * f, self.kt * (1.0 - f))
    }
}

/// Schlick's approximation of the Fresnel reflectance of a dielectric boundary from index `n1`
/// into `n2`, for a ray making cosine `cos_i` with the normal: `R0 + (1 − R0)(1 − cos)^5`
/// with `R0 = ((n1 − n2)/(n1 + n2))²`, where `cos` is the cosine on the less dense side (the
/// refracted angle's when `n1 > n2`); 1 under total internal reflection.
#[inline]
pub fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
    let cos_i = cos_i.clamp(0.0, 1.0);
    let cos = if n1 > n2 {
        let sin2_t = (n1 / n2).powi(2) * (1.0 - cos_i * cos_i);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        (1.0 - sin2_t).sqrt()
    } else {
        cos_i
    };
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schlick_matches_the_formula_at_several_angles_and_is_one_beyond_the_critical_angle() {
        // Air into glass: R0 = (0.5/2.5)^2 = 0.04.
        for deg in [0.0f64, 30.0, 60.0, 80.0, 89.9] {
            let c = deg.to_radians().cos();
            let formula = 0.04 + 0.96 * (1.0 - c).powi(5);
            let got = schlick(c as f32, 1.0, 1.5) as f64;
            assert!((got - formula).abs() < 1e-6, "{deg}°: {got} vs {formula}");
        }
        assert!((schlick(1.0, 1.0, 1.5) - 0.04).abs() < 1e-7);
        assert!((schlick(0.0, 1.0, 1.5) - 1.0).abs() < 1e-6, "grazing reflects everything");
        // Glass into air uses the refracted (air-side) angle: at 30° inside, sin_t = 0.75.
        let inside = 30f64.to_radians();
        let cos_t = (1.0 - (1.5 * inside.sin()).powi(2)).sqrt();
        let formula = 0.04 + 0.96 * (1.0 - cos_t).powi(5);
        assert!((schlick(inside.cos() as f32, 1.5, 1.0) as f64 - formula).abs() < 1e-6);
        // Beyond the critical angle (41.8° for 1.5): total internal reflection.
        assert_eq!(schlick(45f32.to_radians().cos(), 1.5, 1.0), 1.0);
    }

    #[test]
    fn the_fresnel_split_keeps_kr_plus_kt_and_only_applies_when_asked() {
        let kt = Vec3::new(0.8, 0.4, 0.2);
        let glass = Material { kr: 0.1, kt, ior: 1.5, fresnel: true, ..Material::default() };
        for cos in [1.0f32, 0.7, 0.3, 0.05] {
            let (kr, split) = glass.fresnel_split(cos, true);
            let f = schlick(cos, 1.0, 1.5);
            assert_eq!((kr, split), (0.1 + 0.8 * f, kt * (1.0 - f)));
            assert!((kr + split.x - 0.9).abs() < 1e-6, "the largest channel keeps kr + kt");
        }
        assert!(
            glass.fresnel_split(0.05, true).0 > glass.fresnel_split(1.0, true).0,
            "grazing reflects more"
        );
        let plain = Material { fresnel: false, ..glass };
        assert_eq!(plain.fresnel_split(0.05, true), (0.1, kt));
    }
}
