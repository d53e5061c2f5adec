//! The display transform: tone mapping from linear scene radiance to display values in [0, 1],
//! then the sRGB transfer curve (and its inverse, for images read back).
//! Exposure (in stops) scales first; then one operator: clamp, Reinhard with a white point, or
//! an ACES-fitted filmic curve. Only 8- and 16-bit outputs are tone-mapped; EXR stays linear.

use serde::Deserialize;

use super::Film;
use crate::math::Vec3;

/// The curve that maps exposed linear values into [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
pub enum ToneOperator {
    /// `min(x, 1)`.
    #[default]
    Clamp,
    /// Extended Reinhard: `x (1 + x / w²) / (1 + x)`, reaching 1 at the white point `w`.
    Reinhard,
    /// Narkowicz's fit of the ACES filmic curve.
    Aces,
}

/// Exposure and operator: the scene file's `settings.tonemap`, and what the film applies.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ToneMapping {
    /// `Clamp`, `Reinhard` or `Aces` (filmic). Default `Clamp`.
    pub operator: ToneOperator,
    /// Exposure in stops (linear values × 2^exposure first), in [-30, 30] in a scene file.
    /// Default 0.
    pub exposure: f32,
    /// White point of `Reinhard` (the exposed value that maps to 1), > 0. Default 4.
    pub white: f32,
}

impl Default for ToneMapping {
    fn default() -> Self {
        Self { operator: ToneOperator::Clamp, exposure: 0.0, white: 4.0 }
    }
}

/// Tone-maps one linear colour: scales by `2^exposure`, then applies the operator per channel;
/// the result is in [0, 1]. Negative or non-finite inputs (NaN, ±∞) map to 0, never NaN.
///
/// # Examples
/// ```
/// # use penumbra::film::{tonemap::tone_map, ToneMapping, ToneOperator};
/// # use penumbra::math::Vec3;
/// let tm = ToneMapping { operator: ToneOperator::Reinhard, exposure: 0.0, white: 4.0 };
/// assert_eq!(tone_map(Vec3::splat(4.0), &tm), Vec3::ONE);
/// ```
pub fn tone_map(c: Vec3, tm: &ToneMapping) -> Vec3 {
    let scale = tm.exposure.exp2();
    Vec3::from_array(c.to_array().map(|v| map_channel(v * scale, tm)))
}

/// The operator's curve on one exposed channel value.
#[inline]
fn map_channel(x: f32, tm: &ToneMapping) -> f32 {
    // NaN and ±∞ (also after exposure) are not usable values.
    if !x.is_finite() || x <= 0.0 {
        return 0.0;
    }
    let y = match tm.operator {
        ToneOperator::Clamp => x,
        ToneOperator::Reinhard => {
            let w = tm.white.max(f32::MIN_POSITIVE);
            x * (1.0 + x / (w * w)) / (1.0 + x)
        }
        ToneOperator::Aces => (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14),
    };
    // Reinhard's quotient can overflow to NaN for huge x; treat that as fully white.
    if y.is_nan() {
        1.0
    } else {
        y.clamp(0.0, 1.0)
    }
}

/// The sRGB transfer function of a linear value in [0, 1] (values outside are clamped).
#[inline]
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB bytes of a film, row-major RGB.
pub fn encode_srgb8(film: &Film) -> Vec<u8> {
    film.pixels.iter().flat_map(|c| c.to_array().map(srgb8)).collect()
}

/// The 8-bit sRGB code of a linear value, `(linear_to_srgb(v) · 255 + 0.5)` truncated (NaN
/// and values at or below 0 give 0, values at or above 1 give 255), without its `powf`: the
/// code is the number of its 255 steps (`srgb8_steps`) at or below `v`, found by a
/// branch-free binary search. The same bytes as the formula for every `f32` (a test checks all
/// of them in [0, 1]); the `powf` was a fifth of a PNG write's instructions.
#[inline]
pub fn srgb8(v: f32) -> u8 {
    let steps = srgb8_steps();
    let mut code = 0;
    for half in [128, 64, 32, 16, 8, 4, 2, 1] {
        if steps[code + half] <= v {
            code += half;
        }
    }
    code as u8
}

/// Where the 8-bit sRGB code steps up: entry `b` (1 to 255) is the least `f32` whose code by
/// the formula is at least `b`, found by bisecting `f32` bit patterns in [0, 1] (the formula
/// only rises with `v`: every step of it rounds monotonically); entry 0 is never read.
fn srgb8_steps() -> &'static [f32; 256] {
    static STEPS: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    STEPS.get_or_init(|| {
        let code = |bits: u32| (linear_to_srgb(f32::from_bits(bits)) * 255.0 + 0.5) as u8;
        let mut steps = [f32::NEG_INFINITY; 256];
        for (b, step) in steps.iter_mut().enumerate().skip(1) {
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if usize::from(code(mid)) >= b {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            *step = f32::from_bits(lo);
        }
        steps
    })
}

/// The inverse of [`linear_to_srgb`]: the linear value of an sRGB-encoded
/// value in [0, 1] (values outside are clamped).
#[inline]
pub fn srgb_to_linear(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formula [`srgb8`] replaces.
    fn srgb8_by_formula(v: f32) -> u8 {
        (linear_to_srgb(v) * 255.0 + 0.5) as u8
    }

    #[test]
    fn srgb8_equals_the_formula_on_every_float_in_0_to_1() {
        use rayon::prelude::*;
        let last = 1.0f32.to_bits();
        let mismatch = (0..=last / 65536).into_par_iter().find_map_any(|chunk| {
            let bits = chunk * 65536..=(chunk * 65536 + 65535).min(last);
            bits.map(f32::from_bits).find(|&v| srgb8(v) != srgb8_by_formula(v))
        });
        assert_eq!(mismatch, None);
        let outside = [-0.0, -1e-30, -1.0, 1.0 + f32::EPSILON, 2.0, 1e30, f32::INFINITY, f32::NEG_INFINITY];
        for v in outside.into_iter().chain([f32::NAN, -f32::NAN]) {
            assert_eq!(srgb8(v), srgb8_by_formula(v), "{v}");
        }
        // Every code is reached, each from its own threshold.
        let steps = srgb8_steps();
        for b in 1..=255u8 {
            let step = steps[usize::from(b)];
            assert_eq!((srgb8(step), srgb8(f32::from_bits(step.to_bits() - 1))), (b, b - 1));
        }
    }

    #[test]
    fn srgb_curve_hits_known_points() {
        assert_eq!(linear_to_srgb(0.0), 0.0);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
        let white = Film { width: 1, height: 1, pixels: vec![crate::math::Vec3::ONE] };
        assert_eq!(encode_srgb8(&white), vec![255, 255, 255]);
        // Mid-grey 0.5 in sRGB is about 0.214 linear.
        assert!((linear_to_srgb(0.214_041) - 0.5).abs() < 1e-4);
    }

    fn tm(operator: ToneOperator, exposure: f32, white: f32) -> ToneMapping {
        ToneMapping { operator, exposure, white }
    }

    fn ramp() -> impl Iterator<Item = f32> {
        (0..1000).map(|i| i as f32 * 20.0 / 999.0)
    }

    #[test]
    fn each_operator_matches_its_formula_on_a_ramp() {
        let w = 4.0;
        for x in ramp() {
            let c = Vec3::splat(x);
            let clamp = tone_map(c, &tm(ToneOperator::Clamp, 0.0, w)).x;
            assert_eq!(clamp, x.min(1.0), "clamp at {x}");
            let reinhard = tone_map(c, &tm(ToneOperator::Reinhard, 0.0, w)).x;
            let expect = (x * (1.0 + x / (w * w)) / (1.0 + x)).clamp(0.0, 1.0);
            assert!((reinhard - expect).abs() <= 1e-6, "reinhard at {x}: {reinhard} vs {expect}");
            let aces = tone_map(c, &tm(ToneOperator::Aces, 0.0, w)).x;
            let expect = ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
            assert!((aces - expect).abs() <= 1e-6, "aces at {x}: {aces} vs {expect}");
        }
    }

    #[test]
    fn exposure_plus_one_doubles_linear_values() {
        for i in 0..100 {
            let x = i as f32 * 0.49 / 99.0;
            let out = tone_map(Vec3::new(x, x * 0.5, x * 0.25), &tm(ToneOperator::Clamp, 1.0, 4.0));
            assert_eq!(out, Vec3::new(2.0 * x, x, 0.5 * x));
        }
        let half = tone_map(Vec3::splat(0.25), &tm(ToneOperator::Clamp, -1.0, 4.0));
        assert_eq!(half, Vec3::splat(0.125));
    }

    #[test]
    fn reinhard_maps_the_white_point_to_one() {
        for w in [0.5_f32, 1.0, 2.0, 4.0, 11.2, 100.0] {
            let out = tone_map(Vec3::splat(w), &tm(ToneOperator::Reinhard, 0.0, w));
            assert!((out.x - 1.0).abs() < 1e-6, "white {w} maps to {}", out.x);
            let above = tone_map(Vec3::splat(w * 3.0), &tm(ToneOperator::Reinhard, 0.0, w));
            assert_eq!(above.x, 1.0);
        }
    }

    #[test]
    fn operators_are_monotonic() {
        for op in [ToneOperator::Clamp, ToneOperator::Reinhard, ToneOperator::Aces] {
            let mut prev = 0.0;
            for x in ramp() {
                let y = tone_map(Vec3::splat(x), &tm(op, 0.0, 4.0)).x;
                assert!(y >= prev, "{op:?} decreases at {x}: {prev} -> {y}");
                assert!((0.0..=1.0).contains(&y));
                prev = y;
            }
        }
    }

    #[test]
    fn bad_inputs_map_to_zero_never_nan() {
        for op in [ToneOperator::Clamp, ToneOperator::Reinhard, ToneOperator::Aces] {
            let c = Vec3::new(f32::NAN, -1.0, f32::INFINITY);
            assert_eq!(tone_map(c, &tm(op, 0.0, 4.0)), Vec3::ZERO, "{op:?}");
            assert_eq!(tone_map(Vec3::splat(f32::NEG_INFINITY), &tm(op, 2.0, 4.0)), Vec3::ZERO);
            let huge = tone_map(Vec3::splat(f32::MAX), &tm(op, 0.0, 4.0));
            assert!(huge.is_finite() && huge.x <= 1.0, "{op:?}: {huge}");
        }
    }
}
