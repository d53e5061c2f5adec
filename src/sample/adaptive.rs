//! Adaptive supersampling by recursive corner subdivision (the seed report's rule).
//!
//! The caller traces the `(W+1) × (H+1)` lattice of pixel corners once. For each pixel,
//! [`refine_pixel`] looks at a square's four corner colours: where any two differ by more than
//! the threshold in some channel, and the square is shallower than `max_depth`, it splits into
//! four, needing its centre and four edge midpoints. The pixel's value is the area-weighted
//! mean of the leaf squares, each leaf the mean of its corners.
//!
//! A point that averages several camera samples (a lens's or a shutter's, [`PointSample`])
//! reports their spread, and refinement sees it:
//! - **Noise is not an edge.** Corners differ by noise alone by up to a few of their standard
//!   errors, so a square splits only where its corners differ by more than the threshold plus
//!   [`NOISE_Z`] standard errors of its noisiest corner. Points deeper down take fewer samples
//!   (one, at the finest levels), whose spread cannot be measured: a square then uses the
//!   per-sample spread of its shallower corners, or failing those its parent's.
//! - **A leaf weights its corners by their samples**, so that a split square's mean is not
//!   noisier than before it split (with area weights, a square split once into points of a
//!   quarter of the samples had about the same variance, for five more points' rays).
//!
//! Where no point takes more than one sample (a pinhole, nothing moving), both rules are the
//! seed's, bit for bit. Splitting where the spread alone is large (noise, not contrast) does
//! not pay here: the new points take a quarter of their parent's samples or fewer, so they add
//! little; measured on `effects_dof`, it made lower thresholds trace more rays for a larger
//! error. Noise-driven sampling ([`crate::sample::noise`]) is the mode for that.
//!
//! A corner colour that is not finite (NaN or ±∞) is dropped and counted
//! ([`AdaptiveStats::dropped`]): a leaf averages its finite corners, a square the sub-squares
//! that kept any, and a pixel that kept nothing is black. Means are taken so that colours near
//! `f32::MAX` cannot overflow them.
//!
//! Every sample point sits on an integer lattice of `R = 2^max_depth` steps per pixel
//! ([`LatticePoint`]), so points shared between sub-squares and between neighbouring pixels
//! have one name and are traced once through a shared cache. Because `trace` is a pure
//! function of the lattice point, the result does not depend on refinement order or on what the
//! cache already holds.

use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::hash::{BuildHasher, BuildHasherDefault, Hasher};
use std::ops::{Add, AddAssign};

/// Settings of adaptive supersampling (the scene file's `settings.adaptive`, which replaces
/// `aa` when given).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AdaptiveSettings {
    /// A square splits when two of its corners differ by more than this in some channel;
    /// finite, ≥ 0. Default 0.05.
    pub threshold: f32,
    /// Deepest subdivision level: the finest squares are `2^-max_depth` pixels wide; 1..=6 in
    /// a scene file. Default 3.
    pub max_depth: u32,
}

impl AdaptiveSettings {
    /// The deepest level honoured; `max_depth` above it is treated as this (`4^12` leaves per
    /// pixel is far past any useful refinement and keeps lattice coordinates well inside `u32`
    /// for images up to 2²⁰ pixels wide).
    pub const DEPTH_LIMIT: u32 = 12;

    /// The effective depth, `max_depth` capped at [`Self::DEPTH_LIMIT`].
    pub fn depth(&self) -> u32 {
        self.max_depth.min(Self::DEPTH_LIMIT)
    }

    /// Lattice steps per pixel, `R = 2^depth()`.
    pub fn resolution(&self) -> u32 {
        1 << self.depth()
    }

    /// The lattice point of pixel corner `(x, y)` (corner `(W, H)` is the image's far corner).
    pub fn corner(&self, x: u32, y: u32) -> LatticePoint {
        let r = self.resolution();
        debug_assert!(
            x.checked_mul(r).is_some() && y.checked_mul(r).is_some(),
            "pixel ({x}, {y}) is outside the u32 lattice at resolution {r}"
        );
        LatticePoint { x: x.wrapping_mul(r), y: y.wrapping_mul(r) }
    }
}

impl Default for AdaptiveSettings {
    fn default() -> Self {
        Self { threshold: 0.05, max_depth: 3 }
    }
}

/// A sample position on the finest lattice: image position `(x / R, y / R)` in pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LatticePoint {
    /// Column, in `1/R` pixel steps from the image's left edge.
    pub x: u32,
    /// Row, in `1/R` pixel steps from the image's top edge.
    pub y: u32,
}

impl LatticePoint {
    /// Image position in pixels for lattice resolution `resolution` (see
    /// [`AdaptiveSettings::resolution`]).
    pub fn position(self, resolution: u32) -> Vec2 {
        let r = f64::from(resolution.max(1));
        Vec2::new((f64::from(self.x) / r) as f32, (f64::from(self.y) / r) as f32)
    }
}

/// Counts of the work adaptive refinement did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AdaptiveStats {
    /// Points traced (cache misses).
    pub traced: u64,
    /// Points found in the cache instead of traced.
    pub reused: u64,
    /// Squares split into four.
    pub subdivisions: u64,
    /// Leaf corners dropped because their colour was not finite (a lattice point counts once
    /// for each leaf square it is a corner of).
    pub dropped: u64,
}

impl Add for AdaptiveStats {
    type Output = Self;

    fn add(self, rhs: Self) -> Self {
        Self {
            traced: self.traced + rhs.traced,
            reused: self.reused + rhs.reused,
            subdivisions: self.subdivisions + rhs.subdivisions,
            dropped: self.dropped + rhs.dropped,
        }
    }
}

impl AddAssign for AdaptiveStats {
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

/// Standard errors of a square's noisiest corner by which its corners may differ before the
/// difference counts as contrast: four corners' noise alone spans less than this about 90 % of
/// the time.
pub const NOISE_Z: f32 = 3.0;

/// A lattice point's colour and the spread of the camera samples it averages.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSample {
    /// The point's colour: the mean of its samples (non-finite when none was finite).
    pub colour: Vec3,
    /// Camera samples the colour averages (at least 1).
    pub samples: u32,
    /// The unbiased per-channel variance of one sample about the colour, where at least two
    /// were finite; `None` otherwise.
    pub spread: Option<Vec3>,
}

impl PointSample {
    /// A point of one sample (no measurable spread).
    pub fn single(colour: Vec3) -> Self {
        Self { colour, samples: 1, spread: None }
    }
}

impl From<Vec3> for PointSample {
    fn from(colour: Vec3) -> Self {
        Self::single(colour)
    }
}

/// The largest per-channel difference between any two of `corners`, less `allowance` in each
/// channel.
fn contrast(corners: &[Vec3; 4], allowance: Vec3) -> f32 {
    let hi = corners[1..].iter().fold(corners[0], |m, c| m.max(*c));
    let lo = corners[1..].iter().fold(corners[0], |m, c| m.min(*c));
    (hi - lo - allowance).max_element()
}

/// The per-sample variance a square's corners measure: the largest of those that measured one
/// (per channel), else `inherited`.
fn square_spread(c: &[PointSample; 4], inherited: Option<Vec3>) -> Option<Vec3> {
    c.iter().filter_map(|p| p.spread).reduce(Vec3::max).or(inherited)
}

/// The mean of `values`, (colour, weight) pairs, all finite, weights at least 1:
/// `(w₀v₀ + w₁v₁ + …) / Σw`, which for unit weights has the bits of the plain mean
/// `(v₀ + v₁ + …) / n`; where that sum overflows, `Σ v / Σw · w` instead (finite: at most the
/// largest value). `None` when empty.
fn finite_mean(values: &[(Vec3, f32)]) -> Option<Vec3> {
    let (&(first, w), rest) = values.split_first()?;
    let total = rest.iter().fold(w, |t, &(_, w)| t + w);
    let mean = rest.iter().fold(first * w, |sum, &(v, w)| sum + v * w) / total;
    if mean.is_finite() {
        return Some(mean);
    }
    Some(values.iter().fold(Vec3::ZERO, |sum, &(v, w)| sum + v / total * w).min(Vec3::splat(f32::MAX)))
}

/// A leaf square's finite corners, each weighted by the camera samples it averages (so that a
/// corner of many samples is not drowned by a deeper one of few: with area weights, a square
/// split once would have about the same variance as before it split), and how many there are.
/// Without a lens or a shutter every weight is 1 and the leaf is the plain mean.
fn leaf_corners(c: [PointSample; 4]) -> ([(Vec3, f32); 4], usize) {
    let mut kept = [(Vec3::ZERO, 1.0); 4];
    let mut n = 0;
    for p in c.into_iter().filter(|p| p.colour.is_finite()) {
        kept[n] = (p.colour, p.samples.max(1) as f32);
        n += 1;
    }
    (kept, n)
}

/// A cache of traced lattice points with [`PointHasher`]: what the renderer refines with.
pub type PointCache<P> = HashMap<LatticePoint, P, BuildHasherDefault<PointHasher>>;

/// Hashes a [`LatticePoint`] with one rotate, xor and multiply per coordinate (the Fx hash of
/// rustc). The standard map's SipHash resists keys chosen to collide, which lattice points, the
/// renderer's own, are not; it cost 3 % of `scenes/effects_adaptive.ron`'s instructions. Only
/// lookups depend on the hash, never an order, so the image does not.
#[derive(Debug, Clone, Copy, Default)]
pub struct PointHasher(u64);

impl PointHasher {
    #[inline(always)]
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

impl Hasher for PointHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }

    #[inline]
    fn write_u32(&mut self, word: u32) {
        self.add(u64::from(word));
    }

    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
}

/// The recursion's fixed context: one pixel's refinement.
struct Refiner<'a, P, F, S> {
    threshold: f32,
    depth: u32,
    cache: &'a mut HashMap<LatticePoint, P, S>,
    trace: &'a mut F,
    stats: &'a mut AdaptiveStats,
}

impl<P: Copy + Into<PointSample>, F: FnMut(LatticePoint) -> P, S: BuildHasher> Refiner<'_, P, F, S> {
    /// The sample at `(x, y)`: from the cache, else traced and remembered.
    fn fetch(&mut self, x: u32, y: u32) -> PointSample {
        let p = LatticePoint { x, y };
        if let Some(c) = self.cache.get(&p) {
            self.stats.reused += 1;
            return (*c).into();
        }
        self.stats.traced += 1;
        let c = (self.trace)(p);
        self.cache.insert(p, c);
        c.into()
    }

    /// Whether the square with corners `c` splits, given the per-sample variance `spread` its
    /// corners measure (see the module documentation).
    fn splits(&self, c: &[PointSample; 4], spread: Option<Vec3>) -> bool {
        let colours = c.map(|p| p.colour);
        let Some(spread) = spread else {
            // A NaN contrast compares false, so it does not subdivide.
            return contrast(&colours, Vec3::ZERO) > self.threshold;
        };
        // The noisiest corner is the one of fewest samples: its mean's standard error.
        let fewest = c.iter().map(|p| p.samples.max(1)).min().unwrap_or(1);
        let error = (spread / fewest as f32).sqrt();
        contrast(&colours, NOISE_Z * error) > self.threshold
    }

    /// Mean colour over the square at `(x, y)` of side `size` at `level`, with corner samples
    /// `c` in the order top-left, top-right, bottom-left, bottom-right, and the per-sample
    /// variance its parent measured (`inherited`); `None` when every sample it would average
    /// was dropped as non-finite.
    fn square(
        &mut self,
        x: u32,
        y: u32,
        size: u32,
        c: [PointSample; 4],
        level: u32,
        inherited: Option<Vec3>,
    ) -> Option<Vec3> {
        let spread = square_spread(&c, inherited);
        if level >= self.depth || !self.splits(&c, spread) {
            let (kept, n) = leaf_corners(c);
            self.stats.dropped += (4 - n) as u64;
            return finite_mean(&kept[..n]);
        }
        self.stats.subdivisions += 1;
        let h = size / 2;
        // Fixed fetch order, so `trace` sees a deterministic sequence for a given cache.
        let top = self.fetch(x + h, y);
        let left = self.fetch(x, y + h);
        let centre = self.fetch(x + h, y + h);
        let right = self.fetch(x + size, y + h);
        let bottom = self.fetch(x + h, y + size);
        let tl = self.square(x, y, h, [c[0], top, left, centre], level + 1, spread);
        let tr = self.square(x + h, y, h, [top, c[1], centre, right], level + 1, spread);
        let bl = self.square(x, y + h, h, [left, centre, c[2], bottom], level + 1, spread);
        let br = self.square(x + h, y + h, h, [centre, right, bottom, c[3]], level + 1, spread);
        let (mut kept, mut n) = ([(Vec3::ZERO, 1.0); 4], 0);
        for q in [tl, tr, bl, br].into_iter().flatten() {
            kept[n] = (q, 1.0);
            n += 1;
        }
        finite_mean(&kept[..n])
    }
}

/// The adaptively supersampled colour of pixel `(px, py)`.
///
/// `corners` are the samples already traced at the pixel's corners, in the order (0,0), (1,0),
/// (0,1), (1,1): top-left, top-right, bottom-left, bottom-right. Points inside are looked up in
/// `cache` (counted as `reused`) or traced with `trace` (counted as `traced`) and inserted; any
/// hasher serves (the renderer's is a [`PointCache`]).
/// Samples are colours, or [`PointSample`]s where points average several camera samples and
/// their spread counts (see the module documentation).
/// `trace` must be a pure function of the lattice point; then the result is independent of
/// the order pixels are refined in and of the cache's contents, bit for bit. Non-finite
/// colours are dropped and counted in `stats.dropped` (see the module documentation).
///
/// # Examples
/// ```
/// use penumbra::sample::adaptive::{refine_pixel, AdaptiveSettings, AdaptiveStats};
/// use glam::Vec3;
/// use std::collections::HashMap;
/// let settings = AdaptiveSettings { threshold: 0.1, max_depth: 3 };
/// let r = settings.resolution() as f32;
/// // White left of x = 0.5 pixels, black right of it.
/// let mut trace = |p: penumbra::sample::adaptive::LatticePoint| {
///     if (p.x as f32 / r) < 0.5 { Vec3::ONE } else { Vec3::ZERO }
/// };
/// let corners = [Vec3::ONE, Vec3::ZERO, Vec3::ONE, Vec3::ZERO];
/// let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
/// let c = refine_pixel(0, 0, corners, &settings, &mut cache, &mut trace, &mut stats);
/// assert!((c.x - 0.5).abs() <= 1.0 / 8.0);
/// assert!(stats.subdivisions > 0);
/// ```
pub fn refine_pixel<P: Copy + Into<PointSample>, S: BuildHasher>(
    px: u32,
    py: u32,
    corners: [P; 4],
    settings: &AdaptiveSettings,
    cache: &mut HashMap<LatticePoint, P, S>,
    trace: &mut impl FnMut(LatticePoint) -> P,
    stats: &mut AdaptiveStats,
) -> Vec3 {
    let origin = settings.corner(px, py);
    let mut refiner = Refiner { threshold: settings.threshold, depth: settings.depth(), cache, trace, stats };
    let corners = corners.map(Into::into);
    refiner.square(origin.x, origin.y, settings.resolution(), corners, 0, None).unwrap_or(Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corner colours of pixel `(px, py)` under `trace`, in `refine_pixel`'s order.
    fn corners_of(
        px: u32,
        py: u32,
        settings: &AdaptiveSettings,
        trace: &mut impl FnMut(LatticePoint) -> Vec3,
    ) -> [Vec3; 4] {
        [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| trace(settings.corner(px + dx, py + dy)))
    }

    #[test]
    fn flat_colour_traces_nothing_and_returns_the_colour() {
        let settings = AdaptiveSettings { threshold: 0.0, max_depth: 6 };
        let colour = Vec3::new(0.2, 0.5, 0.9);
        let mut calls = 0;
        let mut trace = |_: LatticePoint| {
            calls += 1;
            colour
        };
        let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
        let c = refine_pixel(3, 4, [colour; 4], &settings, &mut cache, &mut trace, &mut stats);
        assert_eq!(c, colour);
        assert_eq!(calls, 0);
        assert_eq!(stats, AdaptiveStats::default());
        assert!(cache.is_empty());
    }

    #[test]
    fn contrast_equal_to_the_threshold_does_not_subdivide_and_depth_zero_never_does() {
        let corners = [Vec3::ZERO, Vec3::splat(0.25), Vec3::ZERO, Vec3::ZERO];
        let mut trace = |_: LatticePoint| -> Vec3 { panic!("nothing should be traced") };
        let mut stats = AdaptiveStats::default();
        for settings in [
            AdaptiveSettings { threshold: 0.25, max_depth: 4 },
            AdaptiveSettings { threshold: 0.0, max_depth: 0 },
        ] {
            let mut cache = HashMap::new();
            let c = refine_pixel(0, 0, corners, &settings, &mut cache, &mut trace, &mut stats);
            assert_eq!(c, Vec3::splat(0.0625));
        }
        assert_eq!(stats, AdaptiveStats::default());
    }

    #[test]
    fn vertical_edge_subdivides_only_along_the_edge_and_matches_its_coverage() {
        const DEPTH: u32 = 5;
        let settings = AdaptiveSettings { threshold: 0.5, max_depth: DEPTH };
        let r = settings.resolution();
        // Pixel (2, 1); white left of image x = 2.3, black right of it: coverage 0.3.
        let edge = 2.3f32;
        let colour = |p: LatticePoint| {
            if p.position(r).x < edge {
                Vec3::ONE
            } else {
                Vec3::ZERO
            }
        };
        let corners = corners_of(2, 1, &settings, &mut { colour });
        let mut traced_x = Vec::new();
        let mut trace = |p: LatticePoint| {
            traced_x.push(p.position(r).x);
            colour(p)
        };
        let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
        let c = refine_pixel(2, 1, corners, &settings, &mut cache, &mut trace, &mut stats);
        assert!((c.x - 0.3).abs() <= 1.0 / (1u32 << DEPTH) as f32, "{c}");
        assert!(c.x == c.y && c.y == c.z);
        // One column of squares straddles the edge at each level: 1 + 2 + … + 2^(D-1).
        assert_eq!(stats.subdivisions, (1 << DEPTH) - 1);
        // Level d splits the 2^d squares of the edge's column, adding 2^d centres, 2^d left and
        // 2^d right midpoints and 2^d + 1 top/bottom midpoints: 4·(2^D - 1) + D points in all,
        // against (2^D + 1)² - 4 = 1085 for uniform subdivision.
        assert_eq!(stats.traced, 4 * ((1 << DEPTH) - 1) + u64::from(DEPTH));
        assert_eq!(traced_x.len() as u64, stats.traced);
        // Past level 0 (the whole pixel) everything traced is in the left half, near the edge.
        assert!(traced_x.iter().all(|x| (2.0..=3.0).contains(x)));
        assert_eq!(traced_x.iter().filter(|x| **x > 2.5).count(), 1, "{traced_x:?}");
    }

    #[test]
    fn shared_midpoints_are_traced_once_within_and_across_pixels() {
        // A negative threshold subdivides everything: depth 2 visits all 5×5 lattice points.
        let settings = AdaptiveSettings { threshold: -1.0, max_depth: 2 };
        let mut calls: HashMap<LatticePoint, u32> = HashMap::new();
        let mut trace = |p: LatticePoint| {
            *calls.entry(p).or_default() += 1;
            Vec3::new(p.x as f32, p.y as f32, 0.0)
        };
        let mut cache = HashMap::new();
        let mut first = AdaptiveStats::default();
        refine_pixel(0, 0, [Vec3::ZERO; 4], &settings, &mut cache, &mut trace, &mut first);
        // 25 points less the 4 given corners; 5 lookups in each of 5 squares, 4 of them repeats.
        assert_eq!(first, AdaptiveStats { traced: 21, reused: 4, subdivisions: 5, dropped: 0 });
        let mut second = AdaptiveStats::default();
        refine_pixel(1, 0, [Vec3::ZERO; 4], &settings, &mut cache, &mut trace, &mut second);
        // The three interior points of the shared edge come from the first pixel.
        assert_eq!(second, AdaptiveStats { traced: 18, reused: 7, subdivisions: 5, dropped: 0 });
        assert_eq!(first + second, AdaptiveStats { traced: 39, reused: 11, subdivisions: 10, dropped: 0 });
        assert!(calls.values().all(|&n| n == 1));
        assert_eq!(calls.len(), 39);
    }

    /// A pure scene on the lattice: a disc edge, a hard line and a gradient.
    fn scene(r: u32) -> impl FnMut(LatticePoint) -> Vec3 {
        move |p: LatticePoint| {
            let q = p.position(r);
            let disc = if (q - Vec2::new(2.7, 1.9)).length() < 1.6 { 1.0 } else { 0.0 };
            let line = if q.x + 0.37 * q.y > 4.1 { 0.8 } else { 0.1 };
            Vec3::new(disc, line, q.x / 6.0)
        }
    }

    /// Refines pixels of a 6×4 image in `order`, sharing `cache`; returns colour bits by pixel id
    /// (zero for pixels not in `order`).
    fn refine_image(
        order: &[u32],
        settings: &AdaptiveSettings,
        cache: &mut HashMap<LatticePoint, Vec3>,
        stats: &mut AdaptiveStats,
    ) -> Vec<[u32; 3]> {
        let mut trace = scene(settings.resolution());
        let mut out = vec![[0; 3]; 24];
        for &id in order {
            let (px, py) = (id % 6, id / 6);
            let corners = corners_of(px, py, settings, &mut trace);
            let c = refine_pixel(px, py, corners, settings, cache, &mut trace, stats);
            out[id as usize] = c.to_array().map(f32::to_bits);
        }
        out
    }

    #[test]
    fn refinement_order_and_cache_contents_do_not_change_a_bit() {
        let settings = AdaptiveSettings { threshold: 0.05, max_depth: 4 };
        let forward: Vec<u32> = (0..24).collect();
        let reverse: Vec<u32> = forward.iter().rev().copied().collect();
        let (mut fwd_cache, mut fwd_stats) = (HashMap::new(), AdaptiveStats::default());
        let a = refine_image(&forward, &settings, &mut fwd_cache, &mut fwd_stats);
        let (mut rev_cache, mut rev_stats) = (HashMap::new(), AdaptiveStats::default());
        let b = refine_image(&reverse, &settings, &mut rev_cache, &mut rev_stats);
        assert_eq!(a, b);
        assert!(fwd_stats.subdivisions > 24, "the scene should need refinement");
        // Each distinct point is traced once whatever the order.
        assert_eq!(fwd_stats.traced, rev_stats.traced);
        assert_eq!(fwd_stats.traced, fwd_cache.len() as u64);
        assert_eq!(fwd_stats.subdivisions, rev_stats.subdivisions);
        // A fresh cache per pixel, and a cache already full, give the same bits too.
        for id in 0..24u32 {
            let (mut fresh, mut stats) = (HashMap::new(), AdaptiveStats::default());
            let alone = refine_image(&[id], &settings, &mut fresh, &mut stats);
            assert_eq!(alone[id as usize], a[id as usize], "pixel {id}");
        }
        let mut full_stats = AdaptiveStats::default();
        let c = refine_image(&forward, &settings, &mut fwd_cache, &mut full_stats);
        assert_eq!(a, c);
        assert_eq!(full_stats.traced, 0);
    }

    /// A point of `samples` samples with per-sample variance `spread` (grey).
    fn noisy(colour: f32, samples: u32, spread: f32) -> PointSample {
        PointSample { colour: Vec3::splat(colour), samples, spread: Some(Vec3::splat(spread)) }
    }

    #[test]
    fn corners_that_differ_by_their_noise_alone_do_not_split_and_an_edge_beyond_it_does() {
        let settings = AdaptiveSettings { threshold: 0.05, max_depth: 3 };
        // 16 samples of per-sample variance 0.04 (σ 0.2): each corner's standard error is 0.05,
        // so noise alone may part them by 3 × 0.05 = 0.15 past the threshold.
        let corners =
            [noisy(0.5, 16, 0.04), noisy(0.6, 16, 0.04), noisy(0.45, 16, 0.04), noisy(0.55, 16, 0.04)];
        let mut trace = |_: LatticePoint| -> PointSample { panic!("noise is not contrast") };
        let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
        refine_pixel(0, 0, corners, &settings, &mut cache, &mut trace, &mut stats);
        assert_eq!(stats.subdivisions, 0);
        // The same colours without a measured spread: the seed's rule splits them.
        let bare = corners.map(|p| p.colour);
        let mut flat = |_: LatticePoint| Vec3::splat(0.5);
        refine_pixel(0, 0, bare, &settings, &mut HashMap::new(), &mut flat, &mut stats);
        assert!(stats.subdivisions > 0);
        // An edge (0 against 1) splits through the same noise and finds its coverage.
        let edge = [noisy(0.0, 16, 0.04), noisy(1.0, 16, 0.04), noisy(0.0, 16, 0.04), noisy(1.0, 16, 0.04)];
        let r = settings.resolution();
        let mut sharp =
            |p: LatticePoint| PointSample::single(Vec3::splat(if p.x < r / 2 { 0.0 } else { 1.0 }));
        let mut stats = AdaptiveStats::default();
        let c = refine_pixel(0, 0, edge, &settings, &mut HashMap::new(), &mut sharp, &mut stats);
        assert!(stats.subdivisions > 0 && (c.x - 0.5).abs() < 0.1, "{c} after {stats:?}");
    }

    #[test]
    fn a_leaf_weights_its_corners_by_their_samples_and_equal_counts_keep_the_equal_mean() {
        let settings = AdaptiveSettings { threshold: f32::INFINITY, max_depth: 3 };
        let leaf = |corners: [PointSample; 4]| {
            let mut trace = |_: LatticePoint| -> PointSample { panic!("nothing splits") };
            let mut stats = AdaptiveStats::default();
            refine_pixel(0, 0, corners, &settings, &mut HashMap::new(), &mut trace, &mut stats)
        };
        let corners = [noisy(1.0, 16, 0.0), noisy(0.0, 4, 0.0), noisy(0.0, 4, 0.0), noisy(0.0, 4, 0.0)];
        assert_eq!(leaf(corners), Vec3::splat(16.0 / 28.0));
        // Equal counts weigh alike: the plain mean (the same bits, for a power of two).
        let colours = [0.1f32, 0.7, 0.3, 0.9].map(Vec3::splat);
        let corners = colours.map(|c| PointSample { colour: c, samples: 4, spread: None });
        assert_eq!(leaf(corners), (colours[0] + colours[1] + colours[2] + colours[3]) / 4.0);
    }

    #[test]
    fn a_nan_corner_is_dropped_and_counted_and_the_leaf_is_the_mean_of_the_others() {
        let settings = AdaptiveSettings { threshold: 0.5, max_depth: 0 };
        let corners =
            [Vec3::splat(f32::NAN), Vec3::splat(0.2), Vec3::splat(0.4), Vec3::new(0.6, 0.6, f32::INFINITY)];
        let mut trace = |_: LatticePoint| -> Vec3 { panic!("depth 0 traces nothing") };
        let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
        let c = refine_pixel(0, 0, corners, &settings, &mut cache, &mut trace, &mut stats);
        assert_eq!(stats.dropped, 2);
        assert!((c - Vec3::splat(0.3)).abs().max_element() < 1e-7, "{c}");
        // Nothing kept: black, every corner counted.
        let mut none = AdaptiveStats::default();
        let c = refine_pixel(0, 0, [Vec3::splat(f32::NAN); 4], &settings, &mut cache, &mut trace, &mut none);
        assert_eq!((c, none.dropped), (Vec3::ZERO, 4));
    }

    #[test]
    fn a_subdivided_pixel_averages_the_squares_that_kept_samples() {
        // Everything subdivides once; the lattice point in the pixel's centre is NaN, so each
        // of the four leaves drops one corner and keeps three.
        let settings = AdaptiveSettings { threshold: -1.0, max_depth: 1 };
        let r = settings.resolution();
        let mut trace =
            |p: LatticePoint| if p == (LatticePoint { x: r / 2, y: r / 2 }) { Vec3::NAN } else { Vec3::ONE };
        let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
        let c = refine_pixel(0, 0, [Vec3::ONE; 4], &settings, &mut cache, &mut trace, &mut stats);
        assert_eq!((c, stats.dropped, stats.subdivisions), (Vec3::ONE, 4, 1));
    }

    #[test]
    fn colours_near_the_largest_float_average_without_overflow() {
        let big = Vec3::splat(3e38);
        let unit = |v: Vec3| (v, 1.0);
        assert_eq!(finite_mean(&[unit(big); 4]), Some(big));
        assert_eq!(finite_mean(&[unit(big), unit(big), unit(Vec3::ZERO)]), Some(Vec3::splat(2e38)));
        assert_eq!(finite_mean(&[unit(Vec3::splat(f32::MAX)); 3]).map(|m| m.is_finite()), Some(true));
        assert_eq!(finite_mean(&[]), None);
        // Weights that overflow the weighted sum: the fallback stays finite and right.
        let weighted = finite_mean(&[(big, 16.0), (big, 4.0), (Vec3::ZERO, 4.0)]).unwrap();
        assert!((weighted / 2.5e38 - Vec3::ONE).abs().max_element() < 1e-6, "{weighted}");
        // Ordinary colours keep the bits of the plain sum times a quarter.
        let c = [
            Vec3::new(0.1, 0.7, 1e-3),
            Vec3::new(0.3, 0.2, -0.0),
            Vec3::splat(0.9),
            Vec3::new(2.5, 0.0, 0.3),
        ];
        assert_eq!(finite_mean(&c.map(unit)), Some((c[0] + c[1] + c[2] + c[3]) * 0.25));
        let settings = AdaptiveSettings { threshold: f32::MAX, max_depth: 3 };
        let mut trace = |_: LatticePoint| -> Vec3 { panic!("a flat pixel traces nothing") };
        let (mut cache, mut stats) = (HashMap::new(), AdaptiveStats::default());
        assert_eq!(refine_pixel(0, 0, [big; 4], &settings, &mut cache, &mut trace, &mut stats), big);
    }
}
