//! Textures: colours that vary over a surface. This module owns the closed set of texture
//! kinds ([`Texture`]: image, checker, stripes, gradient, noise), the mapping from a surface's
//! (u, v) into a texture's own (s, t) ([`UvTransform`]) and the id of a texture in a
//! snapshot's texture table ([`TextureId`]).
//!
//! `raster` holds image textures (loading and bilinear lookup) and `procedural` the pure
//! pattern functions. Every lookup returns a finite linear RGB colour, whatever the (u, v).

mod decode;
pub mod procedural;
pub mod raster;

use std::sync::Arc;

pub use raster::{ColourSpace, Raster, TextureError, Wrap};

use crate::math::{Vec2, Vec3};

/// Index of a texture in a snapshot's texture table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct TextureId(pub u32);

/// Maps a surface's (u, v) into a texture's own coordinates: scaled, then rotated about the
/// origin by `rotate_deg` (counter-clockwise), then offset: st = R(rotate) · (uv ⊙ scale) + offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform {
    /// Per-axis scale, applied first.
    pub scale: Vec2,
    /// Translation, applied last.
    pub offset: Vec2,
    /// Counter-clockwise rotation about the origin in degrees, applied after scaling.
    pub rotate_deg: f32,
}

impl Default for UvTransform {
    /// The identity: scale (1, 1), no offset, no rotation.
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl UvTransform {
    /// The transform that leaves (u, v) unchanged.
    pub const IDENTITY: UvTransform = UvTransform { scale: Vec2::ONE, offset: Vec2::ZERO, rotate_deg: 0.0 };

    /// The texture coordinates of surface coordinates `uv`; `uv` itself, bit for bit, when
    /// this is the identity.
    ///
    /// # Examples
    /// ```
    /// # use penumbra::texture::UvTransform;
    /// # use glam::Vec2;
    /// let t = UvTransform { scale: Vec2::splat(2.0), offset: Vec2::new(0.5, 0.0), rotate_deg: 0.0 };
    /// assert_eq!(t.apply(Vec2::new(1.0, 1.0)), Vec2::new(2.5, 2.0));
    /// ```
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        if self.is_identity() {
            return uv;
        }
        let scaled = uv * self.scale;
        let rotated = if self.rotate_deg == 0.0 {
            scaled
        } else {
            let (sin, cos) = self.rotate_deg.to_radians().sin_cos();
            Vec2::new(cos * scaled.x - sin * scaled.y, sin * scaled.x + cos * scaled.y)
        };
        rotated + self.offset
    }

    /// Whether [`apply`](Self::apply) returns its input unchanged.
    #[inline]
    pub fn is_identity(&self) -> bool {
        self.scale == Vec2::ONE && self.offset == Vec2::ZERO && self.rotate_deg == 0.0
    }
}

/// A colour that varies over a surface.
#[derive(Debug, Clone, PartialEq)]
pub enum Texture {
    /// An image, looked up bilinearly.
    Image {
        /// The texels, shared between textures using the same file.
        raster: Arc<Raster>,
        /// Behaviour outside [0, 1].
        wrap: Wrap,
        /// Surface (u, v) to image (s, t).
        transform: UvTransform,
    },
    /// Squares of `a` and `b`, one unit of (transformed) uv each: `a` where floor(s) + floor(t) is even.
    Checker {
        /// Colour of the even squares.
        a: Vec3,
        /// Colour of the odd squares.
        b: Vec3,
        /// Surface (u, v) to pattern (s, t).
        transform: UvTransform,
    },
    /// Stripes across s, one unit wide each, alternating `a` (floor(s) even) and `b`.
    Stripes {
        /// Colour of the even stripes.
        a: Vec3,
        /// Colour of the odd stripes.
        b: Vec3,
        /// Surface (u, v) to pattern (s, t).
        transform: UvTransform,
    },
    /// `a` at s = 0 blending linearly to `b` at s = 1, clamped outside.
    Gradient {
        /// Colour at s ≤ 0.
        a: Vec3,
        /// Colour at s ≥ 1.
        b: Vec3,
        /// Surface (u, v) to pattern (s, t).
        transform: UvTransform,
    },
    /// Fractal Perlin noise (fBm of `octaves` octaves, 1..=16) in (s, t), remapped to [0, 1]
    /// and clamped, blending `a` (0) to `b` (1).
    Noise {
        /// Colour where the noise is 0.
        a: Vec3,
        /// Colour where the noise is 1.
        b: Vec3,
        /// Octaves summed, 1..=16 (clamped).
        octaves: u32,
        /// Selects the noise pattern.
        seed: u32,
        /// Surface (u, v) to pattern (s, t).
        transform: UvTransform,
    },
}

impl Texture {
    /// The linear RGB colour at surface coordinates `uv`; finite for any `uv`, NaN included.
    ///
    /// # Examples
    /// ```
    /// # use penumbra::texture::{Texture, UvTransform};
    /// # use glam::{Vec2, Vec3};
    /// let t = Texture::Checker { a: Vec3::ONE, b: Vec3::ZERO, transform: UvTransform::default() };
    /// assert_eq!(t.eval(Vec2::new(0.25, 0.25)), Vec3::ONE);
    /// assert_eq!(t.eval(Vec2::new(1.25, 0.25)), Vec3::ZERO);
    /// ```
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let st = self.transform().apply(uv);
        match self {
            Texture::Image { raster, wrap, .. } => raster.bilinear(st, *wrap),
            Texture::Checker { a, b, .. } => pick(procedural::checker(st), *a, *b),
            Texture::Stripes { a, b, .. } => pick(procedural::stripe(st), *a, *b),
            Texture::Gradient { a, b, .. } => procedural::mix(*a, *b, procedural::gradient(st)),
            Texture::Noise { a, b, octaves, seed, .. } => {
                procedural::mix(*a, *b, procedural::fbm(st, *octaves, *seed))
            }
        }
    }

    /// The texture's transform.
    pub fn transform(&self) -> &UvTransform {
        match self {
            Texture::Image { transform, .. }
            | Texture::Checker { transform, .. }
            | Texture::Stripes { transform, .. }
            | Texture::Gradient { transform, .. }
            | Texture::Noise { transform, .. } => transform,
        }
    }

    /// The same texture with another transform (scripts animate texture offsets).
    pub fn with_transform(&self, transform: UvTransform) -> Texture {
        let mut texture = self.clone();
        match &mut texture {
            Texture::Image { transform: t, .. }
            | Texture::Checker { transform: t, .. }
            | Texture::Stripes { transform: t, .. }
            | Texture::Gradient { transform: t, .. }
            | Texture::Noise { transform: t, .. } => *t = transform,
        }
        texture
    }
}

/// `a` when `first`, else `b`.
#[inline]
fn pick(first: bool, a: Vec3, b: Vec3) -> Vec3 {
    if first {
        a
    } else {
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Vec3 = Vec3::new(1.0, 0.5, 0.0);
    const B: Vec3 = Vec3::new(0.0, 0.25, 2.0);

    fn near2(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() <= 1e-6
    }

    fn all_variants() -> Vec<Texture> {
        let raster = Raster::new(2, 1, vec![Vec3::new(0.1, 0.2, 0.3), Vec3::ONE]).unwrap();
        let t = UvTransform::default();
        vec![
            Texture::Image { raster: Arc::new(raster.clone()), wrap: Wrap::Repeat, transform: t },
            Texture::Image { raster: Arc::new(raster), wrap: Wrap::Clamp, transform: t },
            Texture::Checker { a: A, b: B, transform: t },
            Texture::Stripes { a: A, b: B, transform: t },
            Texture::Gradient { a: A, b: B, transform: t },
            Texture::Noise { a: A, b: B, octaves: 6, seed: 3, transform: t },
        ]
    }

    #[test]
    fn identity_transform_keeps_the_bits() {
        let t = UvTransform::default();
        assert!(t.is_identity());
        for uv in [Vec2::new(-0.0, 0.1), Vec2::new(f32::NAN, 1e-40), Vec2::new(3.0e38, -7.5)] {
            let got = t.apply(uv);
            assert_eq!((got.x.to_bits(), got.y.to_bits()), (uv.x.to_bits(), uv.y.to_bits()));
        }
        assert!(!UvTransform { rotate_deg: 360.0, ..t }.is_identity());
        assert!(!UvTransform { offset: Vec2::new(0.0, 1.0), ..t }.is_identity());
    }

    #[test]
    fn transform_scales_rotates_then_offsets() {
        let t = UvTransform { scale: Vec2::new(2.0, 3.0), ..Default::default() };
        assert_eq!(t.apply(Vec2::new(0.5, 1.0)), Vec2::new(1.0, 3.0));
        let t = UvTransform { offset: Vec2::new(0.25, -1.0), ..Default::default() };
        assert_eq!(t.apply(Vec2::new(0.5, 1.0)), Vec2::new(0.75, 0.0));
        let t = UvTransform { rotate_deg: 90.0, ..Default::default() };
        assert!(near2(t.apply(Vec2::new(1.0, 0.0)), Vec2::new(0.0, 1.0)));
        assert!(near2(t.apply(Vec2::new(0.0, 1.0)), Vec2::new(-1.0, 0.0)));
        // All three: (1, 1) ⊙ (2, 1) = (2, 1); rotated 90° → (−1, 2); offset (10, 20) → (9, 22).
        let t = UvTransform { scale: Vec2::new(2.0, 1.0), offset: Vec2::new(10.0, 20.0), rotate_deg: 90.0 };
        assert!(near2(t.apply(Vec2::new(1.0, 1.0)), Vec2::new(9.0, 22.0)), "{}", t.apply(Vec2::ONE));
        let t = UvTransform { rotate_deg: -45.0, ..Default::default() };
        let h = std::f32::consts::FRAC_1_SQRT_2;
        assert!(near2(t.apply(Vec2::new(1.0, 0.0)), Vec2::new(h, -h)));
    }

    #[test]
    fn checker_colours() {
        let t = Texture::Checker { a: A, b: B, transform: UvTransform::default() };
        assert_eq!(t.eval(Vec2::new(0.25, 0.25)), A);
        assert_eq!(t.eval(Vec2::new(1.25, 0.25)), B);
        assert_eq!(t.eval(Vec2::new(-0.25, 0.25)), B);
        assert_eq!(t.eval(Vec2::new(1.25, 1.25)), A);
        let scaled = t.with_transform(UvTransform { scale: Vec2::splat(2.0), ..Default::default() });
        assert_eq!(scaled.eval(Vec2::new(0.75, 0.25)), B);
        assert_eq!(scaled.eval(Vec2::new(0.25, 0.25)), A);
        assert_eq!(scaled.transform().scale, Vec2::splat(2.0));
        assert_eq!(t.transform(), &UvTransform::default());
    }

    #[test]
    fn stripes_and_gradient_colours() {
        let id = UvTransform::default();
        let s = Texture::Stripes { a: A, b: B, transform: id };
        assert_eq!(s.eval(Vec2::new(0.5, 0.9)), A);
        assert_eq!(s.eval(Vec2::new(1.5, 0.9)), B);
        assert_eq!(s.eval(Vec2::new(-0.5, 0.9)), B);
        assert_eq!(s.eval(Vec2::new(2.5, -7.0)), A);
        let g = Texture::Gradient { a: A, b: B, transform: id };
        let quarter = A + 0.25 * (B - A);
        assert!((g.eval(Vec2::new(0.25, 0.0)) - quarter).abs().max_element() < 1e-6);
        assert_eq!(g.eval(Vec2::new(0.0, 0.0)), A);
        assert_eq!(g.eval(Vec2::new(-1.0, 0.0)), A);
        assert_eq!(g.eval(Vec2::new(1.0, 0.0)), B);
        assert_eq!(g.eval(Vec2::new(2.0, 0.0)), B);
        // An offset slides the gradient: s = u + 0.5.
        let moved = g.with_transform(UvTransform { offset: Vec2::new(0.5, 0.0), ..id });
        assert!((moved.eval(Vec2::new(-0.25, 0.0)) - quarter).abs().max_element() < 1e-6);
    }

    #[test]
    fn noise_stays_between_its_colours() {
        let n = Texture::Noise { a: A, b: B, octaves: 5, seed: 11, transform: UvTransform::default() };
        let (lo, hi) = (A.min(B), A.max(B));
        let mut seen = Vec::new();
        for i in 0..16 {
            for j in 0..16 {
                let c = n.eval(Vec2::new(i as f32 * 0.31, j as f32 * 0.27 - 2.0));
                assert!(c.cmpge(lo).all() && c.cmple(hi).all(), "{c}");
                seen.push(c);
            }
        }
        assert!(seen.iter().any(|c| (*c - seen[0]).length() > 0.05), "noise is constant");
        let same = Texture::Noise { a: A, b: B, octaves: 5, seed: 11, transform: UvTransform::default() };
        let other = Texture::Noise { a: A, b: B, octaves: 5, seed: 12, transform: UvTransform::default() };
        let p = Vec2::new(1.37, 2.71);
        assert_eq!(n.eval(p), same.eval(p));
        let grid = |t: &Texture| (0..64).map(|k| t.eval(Vec2::new(k as f32 * 0.13, 0.5))).collect::<Vec<_>>();
        assert_ne!(grid(&n), grid(&other));
    }

    #[test]
    fn image_texture_reads_its_raster_through_the_transform() {
        let raster = Arc::new(Raster::new(2, 1, vec![Vec3::splat(1.0), Vec3::splat(3.0)]).unwrap());
        let t = Texture::Image { raster, wrap: Wrap::Clamp, transform: UvTransform::default() };
        assert_eq!(t.eval(Vec2::new(0.25, 0.5)), Vec3::splat(1.0));
        assert_eq!(t.eval(Vec2::new(0.5, 0.5)), Vec3::splat(2.0));
        let shifted = t.with_transform(UvTransform { offset: Vec2::new(0.5, 0.0), ..Default::default() });
        assert_eq!(shifted.eval(Vec2::new(0.25, 0.5)), Vec3::splat(3.0));
        assert!(matches!(shifted, Texture::Image { wrap: Wrap::Clamp, .. }));
    }

    #[test]
    fn eval_is_finite_for_non_finite_uv() {
        let odd = [
            Vec2::new(f32::NAN, 0.5),
            Vec2::new(0.5, f32::NAN),
            Vec2::splat(f32::INFINITY),
            Vec2::splat(f32::NEG_INFINITY),
            Vec2::new(f32::INFINITY, f32::NEG_INFINITY),
            Vec2::splat(3.4e38),
            Vec2::splat(-1e30),
        ];
        let transforms = [
            UvTransform::default(),
            UvTransform { scale: Vec2::splat(1e30), offset: Vec2::splat(-1e38), rotate_deg: 33.0 },
        ];
        for texture in all_variants() {
            for transform in transforms {
                let texture = texture.with_transform(transform);
                for uv in odd {
                    let c = texture.eval(uv);
                    assert!(c.is_finite(), "{texture:?} at {uv}: {c}");
                }
            }
        }
    }

    #[test]
    fn texture_ids_order_by_index() {
        assert!(TextureId(1) < TextureId(2));
        assert_eq!(TextureId::default(), TextureId(0));
    }
}
