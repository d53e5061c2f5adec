//! Image metrics against a reference: RMSE and PSNR over linear RGB, mean SSIM (Wang et al. 2004)
//! over display-encoded luminance, and a false-colour map of the luminance error.
//!
//! SSIM follows the reference implementation (`ssim_index.m`): an 11×11 Gaussian window with
//! σ = 1.5 and normalised weights, K1 = 0.01, K2 = 0.03, L = 1, and only windows that lie fully
//! inside the image ("valid" filtering), without the later automatic downsampling step.

use rayon::prelude::*;

use super::{linear_to_srgb, Film};
use crate::math::Vec3;

/// Side of the SSIM window in pixels, shrunk to the image where the image is smaller.
const SSIM_WINDOW: usize = 11;
/// Standard deviation of the SSIM Gaussian window in pixels.
const SSIM_SIGMA: f64 = 1.5;
/// C1 = (K1·L)² with K1 = 0.01 and L = 1.
const SSIM_C1: f64 = 0.01 * 0.01;
/// C2 = (K2·L)² with K2 = 0.03 and L = 1.
const SSIM_C2: f64 = 0.03 * 0.03;
/// Heatmap scale when no pixel differs.
const MIN_ERROR_SCALE: f64 = 1e-6;

/// Root-mean-square error over all channels of two films of the same size (`None` if the
/// sizes differ).
pub fn rmse(image: &Film, reference: &Film) -> Option<f64> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return None;
    }
    let n = image.pixels.len() * 3;
    if n == 0 {
        return Some(0.0);
    }
    let sum: f64 = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, b)| (*a - *b).to_array().iter().map(|d| f64::from(*d).powi(2)).sum::<f64>())
        .sum();
    Some((sum / n as f64).sqrt())
}

/// Peak signal-to-noise ratio in dB for a peak value of 1 (∞ for identical films).
pub fn psnr(image: &Film, reference: &Film) -> Option<f64> {
    rmse(image, reference).map(|e| -20.0 * e.log10())
}

/// Per-pixel sRGB-encoded Rec.709 luminance of the colour clamped to [0, 1] (NaN counts as 0).
pub fn luminance_srgb(film: &Film) -> Vec<f64> {
    let unit = |c: f32| if c > 0.0 { c.min(1.0) } else { 0.0 };
    film.pixels
        .iter()
        .map(|p| {
            let y = 0.2126 * unit(p.x) + 0.7152 * unit(p.y) + 0.0722 * unit(p.z);
            f64::from(linear_to_srgb(y))
        })
        .collect()
}

/// Mean SSIM of [`luminance_srgb`] of two films (`None` if the sizes differ; 1 for empty films).
///
/// Images narrower or shorter than 11 pixels use a window shrunk to the image along that axis.
///
/// # Examples
/// ```
/// # use penumbra::film::{ssim, Film};
/// let reference = Film::new(32, 24);
/// assert_eq!(ssim(&reference, &reference), Some(1.0));
/// assert_eq!(ssim(&reference, &Film::new(24, 32)), None);
/// ```
pub fn ssim(image: &Film, reference: &Film) -> Option<f64> {
    same_size(image, reference)?;
    let (w, h) = (image.width as usize, image.height as usize);
    Some(ssim_luma(&luminance_srgb(image), &luminance_srgb(reference), w, h))
}

/// SSIM of every window fully inside the image: `(width, height, values)`, row-major.
pub fn ssim_map(image: &Film, reference: &Film) -> Option<(u32, u32, Vec<f64>)> {
    same_size(image, reference)?;
    let (w, h) = (image.width as usize, image.height as usize);
    let (mw, mh, map) = ssim_map_luma(&luminance_srgb(image), &luminance_srgb(reference), w, h);
    // The valid region is no larger than the film, whose sides are u32.
    Some((mw as u32, mh as u32, map))
}

/// Inferno false colours of |Y(image) − Y(reference)| over linear luminance, divided by the
/// returned scale and clamped to 1 (`None` if the sizes differ).
///
/// The scale is the 99th percentile (nearest rank) of the non-zero errors, or 1e-6 if none,
/// so a few fireflies do not wash out the map. NaN or infinite errors show as the top colour.
///
/// # Examples
/// ```
/// # use penumbra::film::{error_heatmap, Film};
/// let reference = Film::new(4, 4);
/// let (map, scale) = error_heatmap(&reference, &reference).unwrap();
/// assert_eq!((map.dimensions(), scale), ((4, 4), 1e-6));
/// ```
pub fn error_heatmap(image: &Film, reference: &Film) -> Option<(image::RgbImage, f64)> {
    same_size(image, reference)?;
    let errors: Vec<f64> = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, b)| (luminance_linear(*a) - luminance_linear(*b)).abs())
        .collect();
    let scale = robust_scale(&errors);
    let heatmap = image::RgbImage::from_fn(image.width, image.height, |x, y| {
        let e = errors[y as usize * image.width as usize + x as usize];
        let t = if e.is_finite() { (e / scale).min(1.0) } else { 1.0 };
        image::Rgb(inferno(t))
    });
    Some((heatmap, scale))
}

/// `Some(())` when both films have the same size.
fn same_size(a: &Film, b: &Film) -> Option<()> {
    ((a.width, a.height) == (b.width, b.height)).then_some(())
}

/// Rec.709 luminance of a linear colour, unclamped.
fn luminance_linear(c: Vec3) -> f64 {
    0.2126 * f64::from(c.x) + 0.7152 * f64::from(c.y) + 0.0722 * f64::from(c.z)
}

/// Nearest-rank 99th percentile of the finite non-zero values, or [`MIN_ERROR_SCALE`].
fn robust_scale(errors: &[f64]) -> f64 {
    let mut nonzero: Vec<f64> = errors.iter().copied().filter(|e| e.is_finite() && *e > 0.0).collect();
    if nonzero.is_empty() {
        return MIN_ERROR_SCALE;
    }
    let rank = (99 * nonzero.len()).div_ceil(100);
    *nonzero.select_nth_unstable_by(rank - 1, f64::total_cmp).1
}

/// Matplotlib's "inferno" (CC0) sampled at t = k/8, as sRGB in [0, 1].
const INFERNO: [[f64; 3]; 9] = [
    [0.001462, 0.000466, 0.013866],
    [0.129285, 0.047293, 0.290788],
    [0.341500, 0.062325, 0.429425],
    [0.540920, 0.134729, 0.415123],
    [0.735683, 0.215906, 0.330245],
    [0.890341, 0.347957, 0.198286],
    [0.977092, 0.550850, 0.039050],
    [0.976108, 0.789974, 0.196018],
    [0.988362, 0.998364, 0.644924],
];

/// The inferno colour at `t` in [0, 1], linearly interpolated between the anchors.
fn inferno(t: f64) -> [u8; 3] {
    let pos = t.clamp(0.0, 1.0) * (INFERNO.len() - 1) as f64;
    let i = (pos as usize).min(INFERNO.len() - 2);
    let f = pos - i as f64;
    let (lo, hi) = (INFERNO[i], INFERNO[i + 1]);
    std::array::from_fn(|c| ((lo[c] + f * (hi[c] - lo[c])) * 255.0).round() as u8)
}

/// Mean SSIM of two `width × height` luminance arrays (1 when the image is empty).
fn ssim_luma(a: &[f64], b: &[f64], width: usize, height: usize) -> f64 {
    let (_, _, map) = ssim_map_luma(a, b, width, height);
    if map.is_empty() {
        return 1.0;
    }
    map.iter().sum::<f64>() / map.len() as f64
}

/// Normalised Gaussian taps of length `n` centred on the middle of the window.
fn gaussian_taps(n: usize) -> Vec<f64> {
    let centre = (n as f64 - 1.0) / 2.0;
    let taps: Vec<f64> =
        (0..n).map(|i| (-(i as f64 - centre).powi(2) / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp()).collect();
    let sum: f64 = taps.iter().sum();
    taps.into_iter().map(|t| t / sum).collect()
}

/// SSIM of each valid window of two `width × height` luminance arrays.
///
/// The Gaussian is separable, so each output row sums its window's rows into per-column
/// moments (a, b, a², b², ab), then slides the horizontal taps along them.
fn ssim_map_luma(a: &[f64], b: &[f64], width: usize, height: usize) -> (usize, usize, Vec<f64>) {
    debug_assert_eq!((a.len(), b.len()), (width * height, width * height));
    if width == 0 || height == 0 {
        return (0, 0, Vec::new());
    }
    let (kw, kh) = (SSIM_WINDOW.min(width), SSIM_WINDOW.min(height));
    let (gx, gy) = (gaussian_taps(kw), gaussian_taps(kh));
    let (mw, mh) = (width - kw + 1, height - kh + 1);
    let mut map = vec![0.0; mw * mh];
    map.par_chunks_mut(mw).enumerate().for_each(|(oy, out)| {
        // Vertical pass: weighted column moments over rows oy..oy + kh.
        let mut cols = vec![[0.0f64; 5]; width];
        for (j, g) in gy.iter().enumerate() {
            let row = (oy + j) * width;
            for ((m, va), vb) in cols.iter_mut().zip(&a[row..row + width]).zip(&b[row..row + width]) {
                m[0] += g * va;
                m[1] += g * vb;
                m[2] += g * (va * va);
                m[3] += g * (vb * vb);
                m[4] += g * (va * vb);
            }
        }
        // Horizontal pass and the SSIM formula.
        for (ox, s) in out.iter_mut().enumerate() {
            let mut m = [0.0f64; 5];
            for (g, col) in gx.iter().zip(&cols[ox..ox + kw]) {
                for (acc, v) in m.iter_mut().zip(col) {
                    *acc += g * v;
                }
            }
            *s = ssim_from_moments(m);
        }
    });
    (mw, mh, map)
}

/// SSIM of one window from its weighted moments `[E a, E b, E a², E b², E ab]`.
#[inline]
fn ssim_from_moments([ma, mb, maa, mbb, mab]: [f64; 5]) -> f64 {
    let (var_a, var_b, cov) = (maa - ma * ma, mbb - mb * mb, mab - ma * mb);
    ((2.0 * (ma * mb) + SSIM_C1) * (2.0 * cov + SSIM_C2))
        / ((ma * ma + mb * mb + SSIM_C1) * (var_a + var_b + SSIM_C2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64: a seeded stream of floats in [0, 1).
    struct SplitMix64(u64);

    impl SplitMix64 {
        fn next_f64(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            (z ^ (z >> 31)) as f64 / 2f64.powi(64)
        }
    }

    fn random_film(w: u32, h: u32, rng: &mut SplitMix64) -> Film {
        let pixels = (0..w * h)
            .map(|_| Vec3::new(rng.next_f64() as f32, rng.next_f64() as f32, rng.next_f64() as f32))
            .collect();
        Film { width: w, height: h, pixels }
    }

    /// SSIM map by a direct double loop: 2D weights exp(−r²/2σ²) normalised over the window,
    /// and two-pass central moments.
    fn brute_force_map(a: &[f64], b: &[f64], w: usize, h: usize) -> Vec<f64> {
        let (kw, kh) = (w.min(11), h.min(11));
        let (cx, cy) = ((kw as f64 - 1.0) / 2.0, (kh as f64 - 1.0) / 2.0);
        let weight = |i: usize, j: usize| (-((i as f64 - cx).powi(2) + (j as f64 - cy).powi(2)) / 4.5).exp();
        let total: f64 = (0..kh).flat_map(|j| (0..kw).map(move |i| (i, j))).map(|(i, j)| weight(i, j)).sum();
        let mut map = Vec::new();
        for oy in 0..=h - kh {
            for ox in 0..=w - kw {
                let px = |j: usize, i: usize| (oy + j) * w + ox + i;
                let window = || (0..kh).flat_map(|j| (0..kw).map(move |i| (i, j)));
                let mean = |v: &[f64]| window().map(|(i, j)| weight(i, j) / total * v[px(j, i)]).sum::<f64>();
                let (ma, mb) = (mean(a), mean(b));
                let (mut va, mut vb, mut cov) = (0.0, 0.0, 0.0);
                for (i, j) in window() {
                    let (da, db, wt) = (a[px(j, i)] - ma, b[px(j, i)] - mb, weight(i, j) / total);
                    va += wt * da * da;
                    vb += wt * db * db;
                    cov += wt * da * db;
                }
                let (c1, c2) = (1e-4, 9e-4);
                map.push(
                    ((2.0 * ma * mb + c1) * (2.0 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2)),
                );
            }
        }
        map
    }

    #[test]
    fn rmse_of_a_uniform_offset_is_the_offset() {
        let a = Film::new(4, 3);
        let mut b = Film::new(4, 3);
        b.pixels.iter_mut().for_each(|p| *p = Vec3::splat(0.25));
        assert!((rmse(&a, &b).unwrap() - 0.25).abs() < 1e-12);
        assert!((psnr(&a, &b).unwrap() - 12.0412).abs() < 1e-3);
        assert_eq!(rmse(&a, &a), Some(0.0));
        assert_eq!(psnr(&a, &a), Some(f64::INFINITY));
        assert_eq!(rmse(&a, &Film::new(3, 4)), None);
    }

    #[test]
    fn rmse_weights_every_channel_equally() {
        let a = Film::new(1, 1);
        let mut b = Film::new(1, 1);
        b.pixels[0] = Vec3::new(0.3, 0.0, 0.0);
        assert!((rmse(&a, &b).unwrap() - 0.3 / 3f64.sqrt()).abs() < 1e-7);
    }

    #[test]
    fn luminance_is_clamped_rec709_then_srgb_encoded() {
        let srgb = |y: f64| if y <= 0.0031308 { 12.92 * y } else { 1.055 * y.powf(1.0 / 2.4) - 0.055 };
        let cases = [
            (Vec3::ZERO, 0.0),
            (Vec3::ONE, 1.0),
            (Vec3::splat(5.0), 1.0),
            (Vec3::new(0.5, 0.2, 0.1), srgb(0.2126 * 0.5 + 0.7152 * 0.2 + 0.0722 * 0.1)),
            (Vec3::new(2.0, -1.0, 0.5), srgb(0.2126 + 0.0722 * 0.5)),
            (Vec3::new(0.0, 0.002, 0.0), 12.92 * 0.7152 * 0.002),
            (Vec3::new(f32::NAN, 0.0, 0.0), 0.0),
        ];
        let film = Film { width: cases.len() as u32, height: 1, pixels: cases.iter().map(|c| c.0).collect() };
        for (got, (colour, want)) in luminance_srgb(&film).iter().zip(cases) {
            assert!((got - want).abs() < 1e-6, "{colour}: {got} vs {want}");
        }
    }

    #[test]
    fn identical_images_have_ssim_one_everywhere() {
        let mut rng = SplitMix64(1);
        for (w, h) in [(40, 30), (11, 11), (5, 17), (1, 1)] {
            let film = random_film(w, h, &mut rng);
            assert_eq!(ssim(&film, &film), Some(1.0), "{w}×{h}");
            let (mw, mh, map) = ssim_map(&film, &film).unwrap();
            assert_eq!((mw, mh), (w.saturating_sub(10).max(1), h.saturating_sub(10).max(1)));
            assert_eq!(map.len(), (mw * mh) as usize);
            assert!(map.iter().all(|s| (s - 1.0).abs() < 1e-12));
        }
        assert_eq!(ssim(&Film::new(0, 0), &Film::new(0, 0)), Some(1.0));
    }

    #[test]
    fn mismatched_sizes_give_none() {
        let (a, b) = (Film::new(12, 13), Film::new(13, 12));
        assert_eq!(ssim(&a, &b), None);
        assert_eq!(ssim_map(&a, &b), None);
        assert_eq!(error_heatmap(&a, &b), None);
    }

    #[test]
    fn ssim_is_symmetric_and_at_most_one() {
        let mut rng = SplitMix64(7);
        for (w, h) in [(40, 30), (13, 17), (7, 3), (11, 64)] {
            for _ in 0..4 {
                let (a, b) = (random_film(w, h, &mut rng), random_film(w, h, &mut rng));
                let (ab, ba) = (ssim(&a, &b).unwrap(), ssim(&b, &a).unwrap());
                assert!((ab - ba).abs() < 1e-12, "{w}×{h}: {ab} vs {ba}");
                assert!(ab <= 1.0 + 1e-12 && ab > -1.0, "{w}×{h}: {ab}");
            }
        }
    }

    #[test]
    fn separable_ssim_matches_the_brute_force_double_loop() {
        let mut rng = SplitMix64(42);
        for (w, h) in [(40, 30), (6, 20), (23, 4), (3, 2)] {
            let a: Vec<f64> = (0..w * h).map(|_| rng.next_f64()).collect();
            // Correlated with `a` so that the covariance term matters.
            let b: Vec<f64> = a.iter().map(|v| 0.6 * v + 0.4 * rng.next_f64()).collect();
            let (mw, mh, map) = ssim_map_luma(&a, &b, w, h);
            assert_eq!((mw, mh), (w - w.min(11) + 1, h - h.min(11) + 1));
            let brute = brute_force_map(&a, &b, w, h);
            assert_eq!(map.len(), brute.len());
            for (k, (s, t)) in map.iter().zip(&brute).enumerate() {
                assert!((s - t).abs() < 1e-9, "{w}×{h} window {k}: {s} vs {t}");
            }
            let mean = brute.iter().sum::<f64>() / brute.len() as f64;
            assert!((ssim_luma(&a, &b, w, h) - mean).abs() < 1e-9);
        }
    }

    #[test]
    fn uniform_offset_leaves_only_the_luminance_term() {
        let (mu, c1) = (0.4, 1e-4);
        for delta in [0.0, 0.01, 0.1, -0.3] {
            for (w, h) in [(30, 20), (4, 4), (1, 1)] {
                let x = vec![mu; w * h];
                let y = vec![mu + delta; w * h];
                let want = (2.0 * mu * (mu + delta) + c1) / (mu * mu + (mu + delta) * (mu + delta) + c1);
                let got = ssim_luma(&x, &y, w, h);
                assert!((got - want).abs() < 1e-12, "δ = {delta}, {w}×{h}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn checkerboard_noise_matches_the_closed_form() {
        // y = μ + d·(−1)^(x+y). Over a window at (ox, oy) the Gaussian-weighted mean of the
        // pattern is m = ±d·s² with s = Σ g_i (−1)^i, its variance d² − m², and the covariance
        // with the constant x is 0.
        let (w, h, mu, d, c1, c2) = (31, 24, 0.5, 0.1, 1e-4, 9e-4);
        let g: Vec<f64> = (0..11).map(|i| (-((i as f64 - 5.0).powi(2)) / 4.5).exp()).collect();
        let s = g.iter().enumerate().map(|(i, g)| if i % 2 == 0 { *g } else { -g }).sum::<f64>()
            / g.iter().sum::<f64>();
        let x = vec![mu; w * h];
        let y: Vec<f64> =
            (0..w * h).map(|k| if (k % w + k / w) % 2 == 0 { mu + d } else { mu - d }).collect();
        let (mw, mh, map) = ssim_map_luma(&x, &y, w, h);
        assert_eq!((mw, mh), (21, 14));
        for (k, got) in map.iter().enumerate() {
            let m = if (k % mw + k / mw) % 2 == 0 { d * s * s } else { -d * s * s };
            let want =
                (2.0 * mu * (mu + m) + c1) / (mu * mu + (mu + m) * (mu + m) + c1) * c2 / (d * d - m * m + c2);
            assert!((got - want).abs() < 1e-10, "window {k}: {got} vs {want}");
        }
        // The same expectation from the brute-force moments, and close to C2 / (d² + C2).
        let brute = brute_force_map(&x, &y, w, h);
        assert!(map.iter().zip(&brute).all(|(s, t)| (s - t).abs() < 1e-10));
        assert!((ssim_luma(&x, &y, w, h) - c2 / (d * d + c2)).abs() < 1e-3);
    }

    #[test]
    fn ssim_falls_as_noise_rises() {
        let (w, h) = (48, 40);
        let reference = Film {
            width: w,
            height: h,
            pixels: (0..w * h)
                .map(|k| {
                    let (x, y) = ((k % w) as f32 / w as f32, (k / w) as f32 / h as f32);
                    Vec3::new(0.2 + 0.3 * x, 0.25 + 0.2 * y, 0.3 + 0.1 * (x * 9.0).sin())
                })
                .collect(),
        };
        let mut rng = SplitMix64(3);
        let noise: Vec<f32> = (0..w * h).map(|_| (2.0 * rng.next_f64() - 1.0) as f32).collect();
        let scores: Vec<f64> = [0.01f32, 0.04, 0.15]
            .iter()
            .map(|amp| {
                let pixels =
                    reference.pixels.iter().zip(&noise).map(|(p, n)| *p + Vec3::splat(amp * n)).collect();
                ssim(&Film { pixels, ..reference.clone() }, &reference).unwrap()
            })
            .collect();
        assert!(1.0 > scores[0] && scores[0] > scores[1] && scores[1] > scores[2], "{scores:?}");
    }

    #[test]
    fn heatmap_of_identical_images_is_the_bottom_colour() {
        let film = random_film(9, 7, &mut SplitMix64(5));
        let (map, scale) = error_heatmap(&film, &film).unwrap();
        assert_eq!((map.dimensions(), scale), ((9, 7), 1e-6));
        // Matplotlib's inferno(0) is #000004.
        assert!(map.pixels().all(|p| p.0 == [0x00, 0x00, 0x04]));
    }

    #[test]
    fn heatmap_of_one_differing_pixel_is_the_top_colour() {
        let reference = Film::new(6, 5);
        let mut image = reference.clone();
        image.set(4, 2, Vec3::new(0.0, 0.5, 0.0));
        let (map, scale) = error_heatmap(&image, &reference).unwrap();
        assert!((scale - 0.7152 * 0.5).abs() < 1e-9);
        for (x, y, p) in map.enumerate_pixels() {
            // Matplotlib's inferno(1) is #fcffa4.
            let want = if (x, y) == (4, 2) { [0xfc, 0xff, 0xa4] } else { [0x00, 0x00, 0x04] };
            assert_eq!(p.0, want, "({x}, {y})");
        }
    }

    #[test]
    fn heatmap_scale_is_the_99th_percentile_and_colours_brighten() {
        // Errors 1..=200 (in units of 0.001) plus zeros: the nearest-rank 99th percentile of the
        // 200 non-zero errors is the 198th smallest.
        let (w, h) = (25, 10);
        let reference = Film::new(w, h);
        let mut image = reference.clone();
        for k in 0..200 {
            image.pixels[k] = Vec3::splat((k + 1) as f32 * 1e-3);
        }
        let (map, scale) = error_heatmap(&image, &reference).unwrap();
        assert!((scale - 0.198).abs() < 1e-6, "{scale}");
        let luma = |p: &image::Rgb<u8>| {
            0.2126 * f64::from(p.0[0]) + 0.7152 * f64::from(p.0[1]) + 0.0722 * f64::from(p.0[2])
        };
        let ys: Vec<f64> = (0..200u32).map(|k| luma(map.get_pixel(k % w, k / w))).collect();
        assert!(ys.windows(2).all(|p| p[0] <= p[1]), "{ys:?}");
        assert_eq!(map.get_pixel(199 % w, 199 / w).0, [0xfc, 0xff, 0xa4]);
        assert_eq!(map.get_pixel(w - 1, h - 1).0, [0x00, 0x00, 0x04]);
        // Matplotlib's inferno(0.5) is #bc3754, within the interpolation's rounding.
        let mid = map.get_pixel(98 % w, 98 / w).0;
        assert!(mid.iter().zip([0xbc, 0x37, 0x54]).all(|(a, b)| a.abs_diff(b) <= 2), "{mid:?}");
    }

    #[test]
    fn heatmap_marks_non_finite_errors_at_the_top() {
        let reference = Film::new(3, 1);
        let mut image = reference.clone();
        image.pixels[0] = Vec3::new(f32::NAN, 0.0, 0.0);
        image.pixels[1] = Vec3::splat(0.25);
        let (map, scale) = error_heatmap(&image, &reference).unwrap();
        assert!((scale - 0.25).abs() < 1e-9);
        assert_eq!(map.get_pixel(0, 0).0, [0xfc, 0xff, 0xa4]);
        assert_eq!(map.get_pixel(1, 0).0, [0xfc, 0xff, 0xa4]);
        assert_eq!(map.get_pixel(2, 0).0, [0x00, 0x00, 0x04]);
    }
}
