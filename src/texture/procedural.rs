//! Procedural patterns as pure functions of texture coordinates (s, t): checker, stripes,
//! gradient and fractal Perlin noise, each giving which colour or how far to blend, plus
//! [`mix`] to turn a blend weight into a colour.
//!
//! Every function is total: non-finite coordinates select the first colour (`a`), and huge
//! ones neither panic nor overflow.

use std::cell::RefCell;

use noise::{NoiseFn, Perlin};

use crate::math::{Vec2, Vec3};

/// The most octaves [`fbm`] sums; more are clamped to this.
pub const MAX_OCTAVES: u32 = 16;

/// Period of the noise crate's Perlin lattice (its permutation table has 256 entries).
const PERIOD: f64 = 256.0;

/// Whether (s, t) lies on the first colour of a unit checker: floor(s) + floor(t) even.
#[inline]
pub fn checker(st: Vec2) -> bool {
    if !st.is_finite() {
        return true;
    }
    // floor() of a finite f32 is an integer and rem_euclid on it is exact: parity is 0 or 1.
    st.x.floor().rem_euclid(2.0) + st.y.floor().rem_euclid(2.0) != 1.0
}

/// Whether s lies on the first colour of unit stripes across s: floor(s) even.
#[inline]
pub fn stripe(st: Vec2) -> bool {
    !st.x.is_finite() || st.x.floor().rem_euclid(2.0) == 0.0
}

/// The blend weight of a gradient along s: s clamped to [0, 1] (0 for NaN).
#[inline]
pub fn gradient(st: Vec2) -> f32 {
    if st.x.is_nan() {
        0.0
    } else {
        st.x.clamp(0.0, 1.0)
    }
}

/// `a` at `f` = 0 blending linearly to `b` at `f` = 1, kept within the box spanned by `a` and `b`.
#[inline]
pub fn mix(a: Vec3, b: Vec3, f: f32) -> Vec3 {
    let f = if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) };
    (a * (1.0 - f) + b * f).max(a.min(b)).min(a.max(b))
}

/// Fractal Perlin noise at (s, t) remapped from [−1, 1] to [0, 1] and clamped (0 when not finite).
///
/// Sums `octaves` (clamped to 1..=[`MAX_OCTAVES`]) octaves of `noise::Perlin`, octave i seeded
/// `seed + i` (wrapping) at frequency 2^i with amplitude 0.5^(i+1), normalised by the sum of
/// amplitudes: `noise::Fbm<Perlin>` with lacunarity 2 and persistence 0.5.
///
/// # Examples
/// ```
/// # use penumbra::texture::procedural::fbm;
/// # use penumbra::math::Vec2;
/// let n = fbm(Vec2::new(0.3, 0.7), 4, 7);
/// assert!((0.0..=1.0).contains(&n));
/// assert_eq!(n, fbm(Vec2::new(0.3, 0.7), 4, 7));
/// ```
pub fn fbm(st: Vec2, octaves: u32, seed: u32) -> f32 {
    if !st.is_finite() {
        return 0.0;
    }
    let n = fbm_signed(f64::from(st.x), f64::from(st.y), octaves, seed);
    (((n + 1.0) * 0.5) as f32).clamp(0.0, 1.0)
}

/// The generators of every octave for one seed.
struct Octaves {
    seed: u32,
    perlin: [Perlin; MAX_OCTAVES as usize],
}

impl Octaves {
    fn new(seed: u32) -> Self {
        Self { seed, perlin: std::array::from_fn(|i| Perlin::new(seed.wrapping_add(i as u32))) }
    }
}

/// Direct-mapped cache slots (by seed) per thread.
const CACHE_SLOTS: usize = 8;

thread_local! {
    /// Building a Perlin generator shuffles a permutation table, too slow per lookup, and
    /// `Texture` stays plain data: so each thread keeps the generators of recent seeds.
    static OCTAVES: RefCell<[Option<Box<Octaves>>; CACHE_SLOTS]> =
        const { RefCell::new([const { None }; CACHE_SLOTS]) };
}

/// The normalised fBm sum in [−1, 1] at finite (x, y).
fn fbm_signed(x: f64, y: f64, octaves: u32, seed: u32) -> f64 {
    let octaves = octaves.clamp(1, MAX_OCTAVES) as usize;
    OCTAVES.with_borrow_mut(|slots| {
        let slot = &mut slots[seed as usize % CACHE_SLOTS];
        if slot.as_ref().is_some_and(|o| o.seed != seed) {
            *slot = None;
        }
        let gens = slot.get_or_insert_with(|| Box::new(Octaves::new(seed)));
        let (mut x, mut y) = (x, y);
        let (mut total, mut norm, mut amplitude) = (0.0, 0.0, 0.5);
        for perlin in &gens.perlin[..octaves] {
            // Perlin noise repeats every PERIOD units and fmod is exact, so wrapping changes no
            // value but keeps the lattice index math in range for huge coordinates.
            total += amplitude * perlin.get([x.rem_euclid(PERIOD), y.rem_euclid(PERIOD)]);
            norm += amplitude;
            amplitude *= 0.5;
            x *= 2.0;
            y *= 2.0;
        }
        total / norm
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use noise::{Fbm, MultiFractal};

    #[test]
    fn checker_parity() {
        assert!(checker(Vec2::new(0.25, 0.25)));
        assert!(!checker(Vec2::new(1.25, 0.25)));
        assert!(!checker(Vec2::new(-0.25, 0.25)));
        assert!(checker(Vec2::new(-0.25, -0.25)));
        assert!(checker(Vec2::new(1.0, 1.0)));
        assert!(!checker(Vec2::new(0.999, 1.0)));
        assert!(checker(Vec2::new(-3e38, 1e30)));
        assert!(checker(Vec2::new(f32::NAN, 0.5)));
    }

    #[test]
    fn stripes_across_s() {
        assert!(stripe(Vec2::new(0.5, 9.7)));
        assert!(!stripe(Vec2::new(1.5, 0.0)));
        assert!(!stripe(Vec2::new(-0.5, 0.0)));
        assert!(stripe(Vec2::new(-1.5, 0.0)));
        assert!(stripe(Vec2::new(2.0, 0.0)));
        assert!(stripe(Vec2::new(f32::INFINITY, 0.0)));
    }

    #[test]
    fn gradient_and_mix() {
        assert_eq!(gradient(Vec2::new(0.25, 3.0)), 0.25);
        assert_eq!(gradient(Vec2::new(-1.0, 0.0)), 0.0);
        assert_eq!(gradient(Vec2::new(2.0, 0.0)), 1.0);
        assert_eq!(gradient(Vec2::new(f32::NAN, 0.0)), 0.0);
        let (a, b) = (Vec3::new(1.0, 0.0, 0.5), Vec3::new(0.0, 2.0, 0.5));
        assert_eq!(mix(a, b, 0.0), a);
        assert_eq!(mix(a, b, 1.0), b);
        assert_eq!(mix(a, b, 0.5), Vec3::new(0.5, 1.0, 0.5));
        assert_eq!(mix(a, b, f32::NAN), a);
    }

    #[test]
    fn fbm_matches_the_noise_crates_fbm() {
        for (seed, octaves) in [(0u32, 1u32), (7, 4), (123_456, 8), (9, 16)] {
            let reference = Fbm::<Perlin>::new(seed)
                .set_octaves(octaves as usize)
                .set_lacunarity(2.0)
                .set_persistence(0.5);
            for (x, y) in [(0.3f32, 0.7f32), (12.34, 5.67), (-3.21, 4.55), (100.1, -250.3)] {
                let want = reference.get([f64::from(x), f64::from(y)]);
                let got = fbm_signed(f64::from(x), f64::from(y), octaves, seed);
                assert!(
                    (got - want).abs() < 1e-12,
                    "seed {seed} octaves {octaves} ({x}, {y}): {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn fbm_is_bounded_varied_and_seeded() {
        let grid: Vec<Vec2> =
            (0..20).flat_map(|i| (0..20).map(move |j| Vec2::new(i as f32 * 0.37, j as f32 * 0.41))).collect();
        let values: Vec<f32> = grid.iter().map(|&p| fbm(p, 5, 42)).collect();
        let (lo, hi) = values.iter().fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        assert!(lo >= 0.0 && hi <= 1.0, "{lo}..{hi}");
        assert!(hi - lo > 0.1, "{lo}..{hi}");
        let again: Vec<f32> = grid.iter().map(|&p| fbm(p, 5, 42)).collect();
        assert_eq!(values, again);
        let other: Vec<f32> = grid.iter().map(|&p| fbm(p, 5, 43)).collect();
        assert_ne!(values, other);
        // Seeds sharing a cache slot (42 and 50) still get their own generators.
        let slot_mate: Vec<f32> = grid.iter().map(|&p| fbm(p, 5, 50)).collect();
        assert_ne!(values, slot_mate);
        assert_eq!(values, grid.iter().map(|&p| fbm(p, 5, 42)).collect::<Vec<_>>());
    }

    #[test]
    fn fbm_is_total() {
        for p in [Vec2::splat(1e30), Vec2::new(-3.4e38, 3.4e38), Vec2::new(-1e-30, 0.0)] {
            let n = fbm(p, 16, u32::MAX);
            assert!((0.0..=1.0).contains(&n), "{p}: {n}");
        }
        assert_eq!(fbm(Vec2::new(f32::NAN, 0.0), 3, 1), 0.0);
        // Octave counts outside 1..=16 are clamped.
        let p = Vec2::new(0.3, 0.7);
        assert_eq!(fbm(p, 0, 3), fbm(p, 1, 3));
        assert_eq!(fbm(p, 99, 3), fbm(p, 16, 3));
    }
}
