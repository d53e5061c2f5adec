//! Point sets over the unit square and disk: the `n` points of a [`Pattern`], addressed one at
//! a time so a caller can revisit any of them.
//!
//! Strata come from [`strata`]: an `nx × ny` grid with `nx * ny == n` exactly, as close to
//! square as `n`'s divisors allow (a prime `n` gives `n × 1` strips). Point `i` belongs to
//! stratum `i` in row-major order. Like pbrt's `StratifiedSampler`, [`sample_square`] shuffles
//! which stratum a camera sample gets, independently per dimension, with [`permute`] so that
//! the strata of different dimensions (pixel, lens, light) are not paired up.

use super::rng::{hash, permute, uniform2, SampleKey};
use super::warp::{concentric_disk, ONE_MINUS_EPSILON};
use super::Pattern;
use glam::Vec2;

/// The stratum grid `(nx, ny)` for `n` points: `nx * ny == n`, `nx ≥ ny`, `ny` the largest
/// divisor of `n` not above `√n`; `n == 0` is treated as 1.
///
/// # Examples
/// ```
/// use penumbra::sample::pattern::strata;
/// assert_eq!(strata(12), (4, 3));
/// assert_eq!(strata(7), (7, 1));
/// assert_eq!(strata(0), (1, 1));
/// ```
#[inline]
pub fn strata(n: u32) -> (u32, u32) {
    let n = n.max(1);
    let mut ny = floor_sqrt(n);
    while !n.is_multiple_of(ny) {
        ny -= 1;
    }
    (n / ny, ny)
}

/// ⌊√n⌋ in a few instructions (`u32::isqrt` is a software loop, and every area-light and
/// camera sample asks for strata): `f64`'s square root is correctly rounded, and no `u32` lies
/// close enough below a square (within 1/(2√n), far above f64's rounding) for it to round up.
#[inline]
fn floor_sqrt(n: u32) -> u32 {
    f64::from(n).sqrt() as u32
}

/// The `[lo, hi)` bounds of cell `i` of `cells` equal cells of `[0, 1)`, as `f32`.
#[inline]
fn cell_bounds(i: u32, cells: u32) -> (f32, f32) {
    let size = cells as f32;
    (i as f32 / size, (i + 1) as f32 / size)
}

/// The largest float below `x` (for `x > 0`).
#[inline]
fn prev_float(x: f32) -> f32 {
    f32::from_bits(x.to_bits() - 1)
}

/// Places `u ∈ [0,1)` inside cell `i` of `cells`, strictly below the cell's upper bound
/// (`lo ≤ prev_float(hi)` always holds, so [`clamp_lane`] is `f32::clamp` here).
#[inline(always)]
fn jitter_in_cell(i: u32, cells: u32, u: f32) -> f32 {
    let (lo, hi) = cell_bounds(i, cells);
    clamp_lane(lo + u * (hi - lo), lo, prev_float(hi))
}

/// The `i`-th of `n` points of `pattern` in `[0,1)²`, with `u ∈ [0,1)²` its random input.
///
/// Grid: the centre of stratum `i` (row-major over [`strata`]); Jittered: stratum `i`'s corner
/// plus `u` times the stratum size; Random: `u`. Every result is strictly below 1. `i` is taken
/// modulo `n`.
///
/// # Examples
/// ```
/// use penumbra::sample::{pattern::square_point, Pattern};
/// use glam::Vec2;
/// assert_eq!(square_point(Pattern::Grid, 4, 3, Vec2::ZERO), Vec2::new(0.75, 0.75));
/// assert_eq!(square_point(Pattern::Jittered, 4, 1, Vec2::ZERO), Vec2::new(0.5, 0.0));
/// ```
pub fn square_point(pattern: Pattern, n: u32, i: u32, u: Vec2) -> Vec2 {
    square_point_in(pattern, strata(n), i, u)
}

/// [`square_point`] with `n`'s [`strata`] already worked out (they cost a loop of divisions;
/// a caller drawing many points of the same `n` finds them once).
#[inline]
pub fn square_point_in(pattern: Pattern, (nx, ny): (u32, u32), i: u32, u: Vec2) -> Vec2 {
    let n = nx * ny;
    // Callers mostly pass a stratum already below `n`: a predictable branch spares a division.
    let i = if i < n { i } else { i % n };
    let (ix, iy) = (i % nx, i / nx);
    let p = match pattern {
        Pattern::Random => u,
        Pattern::Grid => Vec2::new((ix as f32 + 0.5) / nx as f32, (iy as f32 + 0.5) / ny as f32),
        Pattern::Jittered => Vec2::new(
            jitter_in_cell(ix, nx, u.x.clamp(0.0, ONE_MINUS_EPSILON)),
            jitter_in_cell(iy, ny, u.y.clamp(0.0, ONE_MINUS_EPSILON)),
        ),
    };
    p.clamp(Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON))
}

/// [`square_point_in`] of `N` points at once: lane `k` is `square_point_in(pattern, strata,
/// i[k], Vec2::new(ux[k], uy[k]))` for `ux[k]` and `uy[k]` in `[0, 1)`, the same bits, worked
/// out lane by lane so that the lanes' divisions share instructions. Inline it into a
/// [`crate::simd::SimdLevel::run`] closure to get the level's vectors.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
pub fn square_points_in<const N: usize>(
    pattern: Pattern,
    (nx, ny): (u32, u32),
    i: &[u32; N],
    ux: &[f32; N],
    uy: &[f32; N],
) -> [Vec2; N] {
    let n = nx * ny;
    // Callers mostly pass strata already below `n`: then no lane needs reducing.
    let i = match i.iter().all(|&i| i < n) {
        true => *i,
        false => i.map(|i| i - quotient(i, n) * n),
    };
    let (mut ix, mut iy) = ([0u32; N], [0u32; N]);
    for k in 0..N {
        iy[k] = quotient(i[k], nx);
        ix[k] = i[k] - iy[k] * nx;
    }
    // Each axis in loops of its own, the pattern chosen outside them: loops the compiler
    // vectorises.
    let (x, y) = (axis_points(pattern, &ix, nx, ux), axis_points(pattern, &iy, ny, uy));
    std::array::from_fn(|k| Vec2::new(x[k], y[k]))
}

/// One axis of [`square_points_in`]: the coordinates of `N` points in cells `cell` of
/// `cells`, with random inputs `u`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
fn axis_points<const N: usize>(pattern: Pattern, cell: &[u32; N], cells: u32, u: &[f32; N]) -> [f32; N] {
    let mut v = [0.0f32; N];
    match pattern {
        Pattern::Random => v = *u,
        Pattern::Grid => {
            for k in 0..N {
                v[k] = (cell[k] as f32 + 0.5) / cells as f32;
            }
        }
        Pattern::Jittered => {
            for k in 0..N {
                v[k] = jitter_in_cell(cell[k], cells, clamp_lane(u[k], 0.0, ONE_MINUS_EPSILON));
            }
        }
    }
    // `Vec2::clamp` to [0, 1): on these values (never NaN, never -0) the same as `clamp_lane`.
    v.map(|v| clamp_lane(v, 0.0, ONE_MINUS_EPSILON))
}

/// `a / b` for `b ≥ 1`, through `f64` so that lanes can share it (there is no vector integer
/// division): exact, because the quotient of two `u32`s is at least `1/b` from the next
/// integer above it unless it is an integer, and `f64` rounds it by less than `2³²/b · 2⁻⁵³`.
#[inline(always)]
fn quotient(a: u32, b: u32) -> u32 {
    (f64::from(a) / f64::from(b)) as u32
}

/// `f32::clamp` without its assertion (which keeps a loop from being vectorised): the same
/// comparisons in the same order.
#[inline(always)]
fn clamp_lane(mut x: f32, lo: f32, hi: f32) -> f32 {
    if x < lo {
        x = lo;
    }
    if x > hi {
        x = hi;
    }
    x
}

/// All `n` points of `pattern` for one key and dimension: point `i` uses
/// `uniform2(key, dim, i)`.
///
/// # Examples
/// ```
/// use penumbra::sample::{pattern::square_points, rng::SampleKey, Pattern};
/// let key = SampleKey { seed: 1, frame: 0, pixel: 0, sample: 0 };
/// let points: Vec<_> = square_points(Pattern::Jittered, 9, &key, 0).collect();
/// assert_eq!(points.len(), 9);
/// ```
pub fn square_points(
    pattern: Pattern,
    n: u32,
    key: &SampleKey,
    dim: u32,
) -> impl Iterator<Item = glam::Vec2> {
    let key = *key;
    (0..n.max(1)).map(move |i| square_point(pattern, n, i, uniform2(&key, dim, i)))
}

/// The `i`-th of `n` points of `pattern` mapped onto the unit disk by the concentric map.
pub fn disk_point(pattern: Pattern, n: u32, i: u32, u: Vec2) -> Vec2 {
    concentric_disk(square_point(pattern, n, i, u))
}

/// [`disk_point`] with `n`'s [`strata`] already worked out.
#[inline]
pub fn disk_point_in(pattern: Pattern, strata: (u32, u32), i: u32, u: Vec2) -> Vec2 {
    concentric_disk(square_point_in(pattern, strata, i, u))
}

/// Camera sample `key.sample` of `n` (one per pixel sample) in dimension `dim`, as pbrt's
/// `StratifiedSampler`: the stratum is `permute(key.sample, n, …)` with a permutation seeded by
/// everything but the sample number, so the `n` samples of a pixel cover every stratum once
/// and different dimensions pair strata differently. The jitter is `uniform2(key, dim, 0)`.
///
/// # Examples
/// ```
/// use penumbra::sample::{pattern::sample_square, rng::SampleKey, Pattern};
/// let key = |sample| SampleKey { seed: 3, frame: 0, pixel: 8, sample };
/// let lens: Vec<_> = (0..16).map(|s| sample_square(Pattern::Jittered, 16, &key(s), 1)).collect();
/// assert!(lens.iter().all(|p| p.x < 1.0 && p.y < 1.0));
/// ```
pub fn sample_square(pattern: Pattern, n: u32, key: &SampleKey, dim: u32) -> Vec2 {
    let pixel_key = SampleKey { sample: 0, ..*key };
    let stratum = permute(key.sample, n, hash(&pixel_key, dim, u32::MAX));
    square_point(pattern, n, stratum, uniform2(key, dim, 0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn quotients_through_f64_are_exact() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u32
        };
        let edges = [0, 1, 2, 3, 255, 256, 65_535, 65_536, 65_537, u32::MAX / 2, u32::MAX - 1, u32::MAX];
        for &a in &edges {
            for &b in edges.iter().filter(|&&b| b > 0) {
                assert_eq!(quotient(a, b), a / b, "{a} / {b}");
            }
        }
        for _ in 0..200_000 {
            let (a, b) = (next(), next() >> (next() % 32));
            if b > 0 {
                assert_eq!(quotient(a, b), a / b, "{a} / {b}");
                // Just below and at a multiple: where a rounding up would show.
                let m = (a / b) * b;
                assert_eq!(quotient(m, b), m / b);
                if m > 0 {
                    assert_eq!(quotient(m - 1, b), (m - 1) / b, "{} / {b}", m - 1);
                }
            }
        }
    }

    const SIZES: [u32; 11] = [1, 2, 3, 4, 6, 7, 9, 12, 16, 64, 100];
    const PATTERNS: [Pattern; 3] = [Pattern::Grid, Pattern::Random, Pattern::Jittered];

    fn key(pixel: u32) -> SampleKey {
        SampleKey { seed: 17, frame: 2, pixel, sample: 0 }
    }

    /// The stratum (row-major) containing `p`, under the bounds `square_point` uses.
    fn stratum_of(p: Vec2, n: u32) -> u32 {
        let (nx, ny) = strata(n);
        let find = |x: f32, cells: u32| {
            (0..cells)
                .find(|&c| {
                    let (lo, hi) = cell_bounds(c, cells);
                    lo <= x && x < hi
                })
                .expect("every point of [0,1) is in some cell")
        };
        find(p.y, ny) * nx + find(p.x, nx)
    }

    #[test]
    fn strata_take_the_integer_square_root_at_every_square() {
        // The only places a rounded square root could go wrong: next to each square.
        for k in 1..=u32::from(u16::MAX) {
            for n in [k * k - 1, k * k, k * k + 1, k * k + 2 * k] {
                assert_eq!(floor_sqrt(n), n.isqrt(), "n {n}");
            }
        }
        assert_eq!(floor_sqrt(u32::MAX), u32::MAX.isqrt());
        assert_eq!(strata(u32::MAX), (u32::MAX / 65535, 65535));
    }

    #[test]
    fn strata_multiply_to_n_and_are_as_square_as_possible() {
        for n in 0..=1000u32 {
            let (nx, ny) = strata(n);
            assert_eq!(nx * ny, n.max(1));
            assert!(nx >= ny);
            let best = (1..=n.max(1)).filter(|d| n.max(1) % d == 0 && d * d <= n.max(1)).max();
            assert_eq!(Some(ny), best, "n {n}");
        }
        assert_eq!(strata(16), (4, 4));
        assert_eq!(strata(6), (3, 2));
    }

    #[test]
    fn grid_and_jittered_put_exactly_one_point_in_each_stratum() {
        for n in SIZES {
            for pattern in [Pattern::Grid, Pattern::Jittered] {
                for k in 0..50 {
                    let mut seen = vec![false; n as usize];
                    for (i, p) in square_points(pattern, n, &key(k), 0).enumerate() {
                        let s = stratum_of(p, n);
                        assert_eq!(s, i as u32, "{pattern:?} n {n}: point {i} at {p}");
                        assert!(!seen[s as usize]);
                        seen[s as usize] = true;
                    }
                    assert!(seen.iter().all(|&s| s), "{pattern:?} n {n}");
                }
                // Extreme jitter stays inside its stratum too.
                for i in 0..n {
                    for u in [Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON)] {
                        let p = square_point(pattern, n, i, u);
                        assert_eq!(stratum_of(p, n), i, "{pattern:?} n {n} i {i} u {u}");
                    }
                }
            }
        }
    }

    #[test]
    fn all_points_lie_in_the_half_open_unit_square() {
        let in_square = |p: Vec2| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y);
        for pattern in PATTERNS {
            for n in SIZES {
                for k in 0..20 {
                    assert!(square_points(pattern, n, &key(k), 1).all(in_square));
                }
                for i in 0..n {
                    for u in [Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON), Vec2::ONE] {
                        let p = square_point(pattern, n, i, u);
                        assert!(in_square(p), "{pattern:?} n {n} i {i} u {u}: {p}");
                    }
                }
            }
        }
    }

    #[test]
    fn random_and_jittered_means_converge_to_the_centre() {
        for pattern in [Pattern::Random, Pattern::Jittered] {
            let mut sum = glam::DVec2::ZERO;
            let mut count = 0u32;
            for k in 0..4000 {
                for p in square_points(pattern, 16, &key(k), 0) {
                    sum += p.as_dvec2();
                    count += 1;
                }
            }
            let mean = sum / f64::from(count);
            assert!((mean - glam::DVec2::splat(0.5)).abs().max_element() < 0.005, "{pattern:?}: {mean}");
        }
    }

    /// Variance over many keys of the `n`-point estimate of `∫∫ x·y = 1/4`.
    fn estimator_variance(pattern: Pattern, n: u32) -> f64 {
        const KEYS: u32 = 2000;
        let estimates: Vec<f64> = (0..KEYS)
            .map(|k| {
                let sum: f64 = square_points(pattern, n, &key(k), 5).map(|p| f64::from(p.x * p.y)).sum();
                sum / f64::from(n)
            })
            .collect();
        let mean = estimates.iter().sum::<f64>() / f64::from(KEYS);
        assert!((mean - 0.25).abs() < 0.01, "{pattern:?}: mean {mean}");
        estimates.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / f64::from(KEYS - 1)
    }

    #[test]
    fn jittered_has_lower_variance_than_random_on_a_smooth_integrand() {
        let random = estimator_variance(Pattern::Random, 16);
        let jittered = estimator_variance(Pattern::Jittered, 16);
        assert!(jittered < random / 4.0, "jittered {jittered} vs random {random}");
    }

    #[test]
    fn sample_square_covers_every_stratum_once_per_pixel_and_decorrelates_dimensions() {
        for n in SIZES {
            let strata_in = |dim: u32| -> Vec<u32> {
                (0..n)
                    .map(|s| {
                        let k = SampleKey { sample: s, ..key(9) };
                        stratum_of(sample_square(Pattern::Jittered, n, &k, dim), n)
                    })
                    .collect()
            };
            let (a, b) = (strata_in(0), strata_in(1));
            for order in [&a, &b] {
                let mut sorted = order.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "n {n}");
            }
            if n >= 16 {
                assert_ne!(a, b, "n {n}: dimensions pair strata identically");
            }
        }
    }

    #[test]
    fn disk_points_lie_in_the_unit_disk_with_mean_at_the_origin() {
        const N: u32 = 64_000;
        let mut sum = Vec2::ZERO;
        for i in 0..N {
            let p = disk_point(Pattern::Random, N, i, uniform2(&key(0), 0, i));
            assert!(p.length_squared() <= 1.0 + 1e-6, "{p}");
            sum += p;
        }
        let mean = sum / N as f32;
        assert!(mean.length() < 0.01, "{mean}");
        for pattern in PATTERNS {
            for i in 0..16 {
                let p = disk_point(pattern, 16, i, Vec2::splat(ONE_MINUS_EPSILON));
                assert!(p.length_squared() <= 1.0 + 1e-6, "{pattern:?}: {p}");
            }
        }
    }

    #[test]
    fn disk_points_are_uniform_in_area_by_ring_and_sector_chi_square() {
        const N: u32 = 64_000;
        const RINGS: usize = 8;
        const SECTORS: usize = 8;
        // χ² critical value for 63 degrees of freedom at p = 0.001.
        const CHI2_CRIT: f64 = 103.44;
        for pattern in [Pattern::Random, Pattern::Jittered] {
            let mut bins = [0u32; RINGS * SECTORS];
            for i in 0..N {
                let p = disk_point(pattern, N, i, uniform2(&key(1), 0, i));
                // Equal-area rings: r² in [k/8, (k+1)/8).
                let ring = ((p.length_squared() * RINGS as f32) as usize).min(RINGS - 1);
                let angle = p.y.atan2(p.x) + PI;
                let sector = ((angle / (2.0 * PI) * SECTORS as f32) as usize).min(SECTORS - 1);
                bins[ring * SECTORS + sector] += 1;
            }
            let expected = f64::from(N) / (RINGS * SECTORS) as f64;
            let chi2: f64 = bins.iter().map(|&b| (f64::from(b) - expected).powi(2) / expected).sum();
            assert!(chi2 < CHI2_CRIT, "{pattern:?}: chi2 {chi2}");
        }
    }
}
