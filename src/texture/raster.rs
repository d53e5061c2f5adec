//! Image textures in memory: the [`Raster`] (linear RGB texels, row 0 at the top), its
//! bilinear lookup with [`Wrap`] modes, and the [`TextureError`]s an image texture can raise.
//!
//! Reading files into a `Raster` ([`Raster::load`], [`Raster::decode`]) lives in the sibling
//! `decode` module. In the RON scene format, `wrap: Repeat` / `wrap: Clamp` and
//! `colour_space: Srgb` / `colour_space: Linear` deserialize straight into [`Wrap`] and
//! [`ColourSpace`].

use crate::math::{Vec2, Vec3};

/// How lookups outside [0, 1] behave.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
pub enum Wrap {
    /// The image tiles the plane (negative coordinates included).
    #[default]
    Repeat,
    /// Edge texels extend outwards.
    Clamp,
}

/// How a file's values map to linear light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
pub enum ColourSpace {
    /// Values are sRGB-encoded and are decoded with the IEC 61966-2-1 curve.
    #[default]
    Srgb,
    /// Values are already linear (only scaled to [0, 1]).
    Linear,
}

/// Why an image texture could not be used.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The file could not be read.
    #[error("cannot read texture file: {0}")]
    Read(#[from] std::io::Error),
    /// The decoder refused the bytes.
    #[error("cannot decode {format}: {reason}")]
    Decode {
        /// The format tried (`PNG`, `JPEG`, `EXR`).
        format: &'static str,
        /// The decoder's message, on one line.
        reason: String,
    },
    /// The file's extension names no format we read.
    #[error("unsupported texture extension `{extension}`: expected .png, .jpg, .jpeg or .exr")]
    UnsupportedExtension {
        /// The extension as written (empty when there is none).
        extension: String,
    },
    /// The image has no texels.
    #[error("texture has zero size ({width}x{height})")]
    ZeroSize {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
    },
    /// A texel is NaN or infinite.
    #[error("texel ({x}, {y}) is not finite")]
    NonFinite {
        /// Column, from the left.
        x: u32,
        /// Row, from the top.
        y: u32,
    },
    /// The texel count does not match the size.
    #[error("texture size {width}x{height} does not match its {len} texels")]
    SizeMismatch {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Texels given.
        len: usize,
    },
}

/// An image in linear RGB, row 0 at the top of the picture (v = 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Raster {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl Raster {
    /// A raster from row-major texels (row 0 at the top); sizes must be ≥ 1 and match, texels finite.
    ///
    /// # Examples
    /// ```
    /// # use penumbra::texture::Raster;
    /// # use penumbra::math::Vec3;
    /// let r = Raster::new(2, 1, vec![Vec3::ZERO, Vec3::ONE]).unwrap();
    /// assert_eq!(r.texel(1, 0), Vec3::ONE);
    /// ```
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Result<Self, TextureError> {
        if width == 0 || height == 0 {
            return Err(TextureError::ZeroSize { width, height });
        }
        let expected = (width as usize).checked_mul(height as usize);
        if expected != Some(texels.len()) {
            return Err(TextureError::SizeMismatch { width, height, len: texels.len() });
        }
        if let Some(i) = texels.iter().position(|t| !t.is_finite()) {
            // i < width * height, so both fit in u32.
            let x = (i % width as usize) as u32;
            let y = (i / width as usize) as u32;
            return Err(TextureError::NonFinite { x, y });
        }
        Ok(Self { width, height, texels })
    }

    /// Width in texels.
    #[inline]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    #[inline]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texel in column `x`, row `y` (row 0 at the top); indices past the edge are clamped.
    #[inline]
    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        debug_assert!(x < self.width && y < self.height, "texel ({x}, {y}) outside raster");
        let x = x.min(self.width - 1) as usize;
        let y = y.min(self.height - 1) as usize;
        self.texels[y * self.width as usize + x]
    }

    /// Bilinear lookup at (s, t): texel centres at ((x + 0.5)/w, 1 − (y + 0.5)/h), so t = 0 is
    /// the bottom row and s = 0 the left edge; `wrap` decides neighbours outside [0, 1].
    ///
    /// Non-finite coordinates return texel (0, 0); huge ones return some valid texel blend.
    pub fn bilinear(&self, st: Vec2, wrap: Wrap) -> Vec3 {
        if !st.is_finite() {
            return self.texels[0];
        }
        // Continuous texel coordinates (f64 so huge |s| keeps index math in range), texel
        // centres on integers.
        let fx = f64::from(st.x) * f64::from(self.width) - 0.5;
        let fy = (1.0 - f64::from(st.y)) * f64::from(self.height) - 0.5;
        let (x0, x1, wx) = axis(fx, self.width, wrap);
        let (y0, y1, wy) = axis(fy, self.height, wrap);
        let top = self.texel(x0, y0) * (1.0 - wx) + self.texel(x1, y0) * wx;
        let bottom = self.texel(x0, y1) * (1.0 - wx) + self.texel(x1, y1) * wx;
        top * (1.0 - wy) + bottom * wy
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.texels.capacity() * std::mem::size_of::<Vec3>()
    }
}

/// The two neighbouring texel indices along one axis and the weight of the second, for a
/// finite continuous coordinate `f` (texel centres on integers) over `n ≥ 1` texels.
#[inline]
fn axis(f: f64, n: u32, wrap: Wrap) -> (u32, u32, f32) {
    let base = f.floor();
    // In [0, 1) up to rounding; cast to f32 may round to 1.0, which is still a valid weight.
    let w = (f - base) as f32;
    let last = f64::from(n - 1);
    match wrap {
        Wrap::Repeat => {
            let n_f = f64::from(n);
            // rem_euclid may round up to exactly n for tiny negatives: clamp to the last index.
            let i0 = base.rem_euclid(n_f).min(last) as u32;
            let i1 = if i0 + 1 >= n { 0 } else { i0 + 1 };
            (i0, i1, w)
        }
        Wrap::Clamp => {
            let i0 = base.clamp(0.0, last) as u32;
            let i1 = (base + 1.0).clamp(0.0, last) as u32;
            (i0, i1, w)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32) -> Vec3 {
        Vec3::splat(x)
    }

    /// 2×2: top row 1, 2; bottom row 3, 4.
    fn two_by_two() -> Raster {
        Raster::new(2, 2, vec![v(1.0), v(2.0), v(3.0), v(4.0)]).unwrap()
    }

    /// 3×2: top row 0, 1, 2; bottom row 10, 20, 30 (distinct per channel to catch swaps).
    fn three_by_two() -> Raster {
        let t = [0.0, 1.0, 2.0, 10.0, 20.0, 30.0];
        Raster::new(3, 2, t.iter().map(|&x| Vec3::new(x, x + 100.0, -x)).collect()).unwrap()
    }

    fn near(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }

    #[test]
    fn new_rejects_bad_sizes_and_texels() {
        assert!(matches!(Raster::new(0, 1, vec![]), Err(TextureError::ZeroSize { width: 0, height: 1 })));
        assert!(matches!(
            Raster::new(2, 2, vec![v(0.0); 3]),
            Err(TextureError::SizeMismatch { width: 2, height: 2, len: 3 })
        ));
        let mut t = vec![v(0.0); 6];
        t[4] = Vec3::new(0.0, f32::NAN, 0.0);
        let err = Raster::new(3, 2, t).unwrap_err();
        assert!(matches!(err, TextureError::NonFinite { x: 1, y: 1 }), "{err:?}");
        assert_eq!(err.to_string(), "texel (1, 1) is not finite");
    }

    #[test]
    fn texel_centres_return_the_texel_exactly() {
        let r = two_by_two();
        for wrap in [Wrap::Repeat, Wrap::Clamp] {
            assert_eq!(r.bilinear(Vec2::new(0.25, 0.75), wrap), v(1.0));
            assert_eq!(r.bilinear(Vec2::new(0.75, 0.75), wrap), v(2.0));
            assert_eq!(r.bilinear(Vec2::new(0.25, 0.25), wrap), v(3.0));
            assert_eq!(r.bilinear(Vec2::new(0.75, 0.25), wrap), v(4.0));
        }
        let r = three_by_two();
        for (x, y) in [(0u32, 0u32), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)] {
            let st = Vec2::new((x as f32 + 0.5) / 3.0, 1.0 - (y as f32 + 0.5) / 2.0);
            let got = r.bilinear(st, Wrap::Clamp);
            assert!(near(got, r.texel(x, y), 1e-4), "({x}, {y}): {got} vs {}", r.texel(x, y));
        }
    }

    #[test]
    fn halfway_between_centres_is_the_mean() {
        let r = two_by_two();
        assert_eq!(r.bilinear(Vec2::new(0.5, 0.75), Wrap::Clamp), v(1.5));
        assert_eq!(r.bilinear(Vec2::new(0.25, 0.5), Wrap::Clamp), v(2.0));
        assert_eq!(r.bilinear(Vec2::new(0.5, 0.5), Wrap::Clamp), v(2.5));
        let r = three_by_two();
        // Between columns 1 and 2 of the bottom row: s = 2/3, t = 0.25.
        let got = r.bilinear(Vec2::new(2.0 / 3.0, 0.25), Wrap::Clamp);
        assert!(near(got, Vec3::new(25.0, 125.0, -25.0), 1e-4), "{got}");
    }

    #[test]
    fn repeat_wraps_across_edges() {
        let r = two_by_two();
        // s = 0 is halfway between the last column (x = 1) and the first (x = 0).
        assert_eq!(r.bilinear(Vec2::new(0.0, 0.75), Wrap::Repeat), v(1.5));
        // s slightly below 0 blends the last and first columns: fx = -0.75, so column 1 (2.0)
        // weighs 0.75 and column 0 (1.0) weighs 0.25.
        let got = r.bilinear(Vec2::new(-0.125, 0.75), Wrap::Repeat);
        assert_eq!(got, v(2.0 * 0.75 + 1.0 * 0.25));
        // Right edge behaves the same: s = 1.0 is between column 1 and column 0 again.
        assert_eq!(r.bilinear(Vec2::new(1.0, 0.75), Wrap::Repeat), v(1.5));
        // t = 1 (top edge) is between row 0 (top) and row 1 (bottom, wrapped) in column 0.
        assert_eq!(r.bilinear(Vec2::new(0.25, 1.0), Wrap::Repeat), v(2.0));
        // t = 0 (bottom edge) likewise.
        assert_eq!(r.bilinear(Vec2::new(0.25, 0.0), Wrap::Repeat), v(2.0));
        let r = three_by_two();
        // s = 0 on the bottom row: mean of 30 (last column) and 10 (first).
        let got = r.bilinear(Vec2::new(0.0, 0.25), Wrap::Repeat);
        assert!(near(got, Vec3::new(20.0, 120.0, -20.0), 1e-4), "{got}");
    }

    #[test]
    fn repeat_tiles_negative_and_large_coordinates() {
        let r = two_by_two();
        for (ds, dt) in [(-1.0, 0.0), (-3.0, -2.0), (5.0, 7.0), (1024.0, -4096.0)] {
            for (s, t, want) in [(0.25, 0.75, 1.0), (0.75, 0.75, 2.0), (0.25, 0.25, 3.0), (0.75, 0.25, 4.0)] {
                let got = r.bilinear(Vec2::new(s + ds, t + dt), Wrap::Repeat);
                assert_eq!(got, v(want), "({s}+{ds}, {t}+{dt})");
            }
        }
        // Huge coordinates: no panic, some texel blend within range.
        for st in [Vec2::splat(1e30), Vec2::splat(-1e30), Vec2::new(3.4e38, -3.4e38)] {
            for wrap in [Wrap::Repeat, Wrap::Clamp] {
                let got = r.bilinear(st, wrap);
                assert!(got.min_element() >= 1.0 && got.max_element() <= 4.0, "{st}: {got}");
            }
        }
    }

    #[test]
    fn clamp_extends_edge_texels() {
        let r = two_by_two();
        assert_eq!(r.bilinear(Vec2::new(-0.5, 0.75), Wrap::Clamp), v(1.0));
        assert_eq!(r.bilinear(Vec2::new(0.0, 0.75), Wrap::Clamp), v(1.0));
        assert_eq!(r.bilinear(Vec2::new(7.0, 0.75), Wrap::Clamp), v(2.0));
        assert_eq!(r.bilinear(Vec2::new(0.25, 9.0), Wrap::Clamp), v(1.0));
        assert_eq!(r.bilinear(Vec2::new(0.25, -9.0), Wrap::Clamp), v(3.0));
        assert_eq!(r.bilinear(Vec2::new(-2.0, -2.0), Wrap::Clamp), v(3.0));
        assert_eq!(r.bilinear(Vec2::new(3.0, 3.0), Wrap::Clamp), v(2.0));
    }

    #[test]
    fn t_near_one_reads_the_top_row() {
        let r = three_by_two();
        // Column 0 (its centre s = 1/6 is not exact in f32): top (row 0) is 0, bottom (row 1) 10.
        let top = r.bilinear(Vec2::new(0.5 / 3.0, 0.95), Wrap::Clamp).x;
        assert!(top.abs() < 1e-4, "{top}");
        let bottom = r.bilinear(Vec2::new(0.5 / 3.0, 0.05), Wrap::Clamp).x;
        assert!((bottom - 10.0).abs() < 1e-4, "{bottom}");
        // Exact on the 2×2: top-left texel 1, bottom-left 3.
        assert_eq!(two_by_two().bilinear(Vec2::new(0.25, 0.99), Wrap::Clamp), v(1.0));
        assert_eq!(two_by_two().bilinear(Vec2::new(0.25, 0.01), Wrap::Clamp), v(3.0));
        // With Repeat, t = 0.95 is 0.4 texel above row 0's centre: weight 0.4 on the wrapped bottom row.
        let got = r.bilinear(Vec2::new(0.5 / 3.0, 0.95), Wrap::Repeat).x;
        assert!((got - 4.0).abs() < 1e-4, "{got}");
    }

    #[test]
    fn non_finite_coordinates_return_texel_zero() {
        let r = three_by_two();
        for st in [Vec2::new(f32::NAN, 0.5), Vec2::new(0.5, f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)] {
            for wrap in [Wrap::Repeat, Wrap::Clamp] {
                assert_eq!(r.bilinear(st, wrap), r.texel(0, 0));
            }
        }
    }

    #[test]
    fn memory_counts_texels() {
        let r = three_by_two();
        assert!(r.memory_bytes() >= 6 * 12);
        assert_eq!((r.width(), r.height()), (3, 2));
    }
}
