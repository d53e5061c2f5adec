//! Progressive point sequences for noise-driven sampling: every prefix of a pixel's points is
//! stratified, so a pixel that stops after any number of samples has a well-spread set, and one
//! that goes on keeps that spread as it grows.
//!
//! The sequence is the first two dimensions of Sobol's sequence, a (0, 2)-sequence in base 2:
//! every aligned block of `2^m` points is a (0, m, 2)-net (each of the `2^m` elementary boxes
//! of area `2^-m`, `2^a × 2^b` with `a + b = m`, holds exactly one point). It is randomised
//! the way Burley ("Practical Hash-based Owen Scrambling", JCGT 2020) describes:
//!
//! - each coordinate is **Owen-scrambled** (a nested uniform scramble: a digit's flip depends
//!   on the digits above it), with Vegdahl's hash ("Building a Better LK Hash", 2021), which
//!   keeps the net property and makes every point uniformly distributed;
//! - the **index is shuffled** by a nested scramble of its own, which maps every aligned block
//!   of `2^m` indices onto another aligned block: the prefix is still a net, while each
//!   dimension (pixel position, lens, an area light, …) visits its points in an order of its
//!   own, so dimensions are not paired up.
//!
//! A [`Progressive`] is one such sequence, seeded by a pixel's [`Dimension`] and a
//! **replicate** number. Noise-driven sampling interleaves independent replicates, so that the
//! spread of their means is an unbiased estimate of the error of their average
//! (see [`crate::sample::noise`]).
//!
//! Everything is integer arithmetic and one exact conversion to `f32`: the same bits on every
//! CPU and SIMD level.

use glam::Vec2;

use super::rng::Dimension;

/// Scale from a 24-bit integer to `[0, 1)`: `2⁻²⁴`.
const INV_2_24: f32 = 1.0 / (1u32 << 24) as f32;

/// Index of a dimension's hash that seeds its progressive replicates (far above any point
/// index a sample draws, below the permutation seed's).
const REPLICATE_SEEDS: u32 = u32::MAX - 1;

/// Point `i` of Sobol's first two dimensions, as 32-bit binary fractions: the first is the
/// van der Corput radical inverse (the bits of `i` reversed), the second applies the generator
/// matrix whose direction numbers are `v₀ = 2³¹`, `v_{k+1} = v_k ^ (v_k >> 1)`: Pascal's
/// triangle mod 2, so digit `j` (from the top) is the parity of the bits `k ⊇ j` of `i`
/// (Lucas: `C(k, j)` is odd exactly when `j`'s bits are among `k`'s). That superset parity is
/// five shift-and-xor steps over all 32 bits at once, not a loop over `i`'s bits (a shuffled
/// index has all 32).
#[inline]
pub fn sobol2(i: u32) -> (u32, u32) {
    let mut a = i;
    a ^= (a >> 1) & 0x5555_5555;
    a ^= (a >> 2) & 0x3333_3333;
    a ^= (a >> 4) & 0x0f0f_0f0f;
    a ^= (a >> 8) & 0x00ff_00ff;
    a ^= (a >> 16) & 0x0000_ffff;
    (i.reverse_bits(), a.reverse_bits())
}

/// Vegdahl's Laine–Karras style hash: every output bit depends only on the input bits at or
/// below it, so applied to bit-reversed values it is a nested (Owen) permutation.
#[inline]
fn lk_hash(mut x: u32, seed: u32) -> u32 {
    x ^= x.wrapping_mul(0x3d20_adea);
    x = x.wrapping_add(seed);
    x = x.wrapping_mul((seed >> 16) | 1);
    x ^= x.wrapping_mul(0x0552_6c56);
    x ^= x.wrapping_mul(0x53a2_2864);
    x
}

/// A nested uniform (Owen) scramble of the binary fraction `x`, chosen by `seed`: a bijection
/// on `u32` that maps every aligned block of `2^m` values onto an aligned block of `2^m`.
#[inline]
pub fn owen_scramble(x: u32, seed: u32) -> u32 {
    lk_hash(x.reverse_bits(), seed).reverse_bits()
}

/// The top 24 bits of a binary fraction as a float in `[0, 1)`, exactly.
#[inline]
fn unit(x: u32) -> f32 {
    (x >> 8) as f32 * INV_2_24
}

/// One randomised progressive sequence over `[0, 1)²` (see the module notes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progressive {
    shuffle: u32,
    x: u32,
    y: u32,
}

impl Progressive {
    /// Replicate `replicate` of the sequence of a pixel's dimension `dim`.
    #[inline]
    pub fn new(dim: Dimension, replicate: u32) -> Self {
        let a = dim.hash(REPLICATE_SEEDS.wrapping_sub(replicate.wrapping_mul(2)));
        let b = dim.hash(REPLICATE_SEEDS.wrapping_sub(replicate.wrapping_mul(2)).wrapping_sub(1));
        Self { shuffle: a as u32, x: (a >> 32) as u32, y: b as u32 }
    }

    /// Point `i` of the sequence in `[0, 1)²`.
    #[inline]
    pub fn point(self, i: u32) -> Vec2 {
        let (x, y) = sobol2(owen_scramble(i, self.shuffle));
        Vec2::new(unit(owen_scramble(x, self.x)), unit(owen_scramble(y, self.y)))
    }

    /// Point `i` of the sequence's first coordinate alone, in `[0, 1)` (a stratified 1D
    /// sequence: every aligned block of `2^m` points has one in each interval of `2^-m`).
    #[inline]
    pub fn point1(self, i: u32) -> f32 {
        unit(owen_scramble(owen_scramble(i, self.shuffle).reverse_bits(), self.x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::rng::SampleKey;

    fn sequence(pixel: u32, dim: u32, replicate: u32) -> Progressive {
        let key = SampleKey { seed: 3, frame: 0, pixel, sample: u32::MAX };
        Progressive::new(Dimension::new(&key, dim), replicate)
    }

    /// Whether `points` (2^m of them) put exactly one point in every elementary box of area
    /// 2^-m, for every shape 2^a × 2^(m-a).
    fn is_net(points: &[Vec2]) -> bool {
        let m = points.len().trailing_zeros();
        assert_eq!(points.len(), 1 << m);
        (0..=m).all(|a| {
            let (nx, ny) = (1u32 << a, 1u32 << (m - a));
            let mut seen = vec![false; points.len()];
            points.iter().all(|p| {
                let cell = (p.y * ny as f32) as usize * nx as usize + (p.x * nx as f32) as usize;
                !std::mem::replace(&mut seen[cell], true)
            })
        })
    }

    #[test]
    fn the_unscrambled_sequence_is_sobols() {
        // Sobol's first points in two dimensions, in index (not Gray-code) order.
        let expected = [(0.0, 0.0), (0.5, 0.5), (0.25, 0.75), (0.75, 0.25), (0.125, 0.625), (0.625, 0.125)];
        for (i, &(x, y)) in expected.iter().enumerate() {
            let (sx, sy) = sobol2(i as u32);
            assert_eq!((unit(sx), unit(sy)), (x, y), "point {i}");
        }
    }

    #[test]
    fn the_second_dimension_equals_its_direction_numbers() {
        // The textbook construction: xor the direction number of every set bit of i.
        let by_directions = |mut i: u32| {
            let (mut y, mut v) = (0u32, 1u32 << 31);
            while i != 0 {
                if i & 1 != 0 {
                    y ^= v;
                }
                i >>= 1;
                v ^= v >> 1;
            }
            y
        };
        let mut i = 0u32;
        for k in 0..100_000u32 {
            assert_eq!(sobol2(i).1, by_directions(i), "i = {i:#x}");
            i = i.wrapping_mul(0x9e37_79b9).wrapping_add(k); // spread over all 32 bits
        }
        for i in (0..4096).chain([u32::MAX, 1 << 31, 0xdead_beef]) {
            assert_eq!(sobol2(i).1, by_directions(i), "i = {i:#x}");
        }
    }

    #[test]
    fn the_scramble_is_nested_a_bijection_on_blocks() {
        // The values of an aligned block of 2^m map onto one aligned block of 2^m.
        for seed in [0u32, 1, 0xdead_beef, 0x1234_5678] {
            for m in [1u32, 3, 8] {
                for block in [0u32, 5, 1000] {
                    let base = block << m;
                    let mut out: Vec<u32> = (0..1u32 << m).map(|i| owen_scramble(base + i, seed)).collect();
                    let high = out[0] >> m;
                    assert!(out.iter().all(|v| v >> m == high), "seed {seed} m {m}");
                    out.sort_unstable();
                    out.dedup();
                    assert_eq!(out.len(), 1 << m);
                }
            }
            // The top bit of the fraction flips the same way for every value: a bijection on halves.
            let flips: Vec<u32> = (0..64).map(|i| (owen_scramble(i << 26, seed) ^ (i << 26)) >> 31).collect();
            assert!(flips.iter().all(|&f| f == flips[0]));
        }
    }

    #[test]
    fn every_power_of_two_prefix_and_aligned_block_is_a_net() {
        for (pixel, dim, replicate) in [(0, 0, 0), (17, 1, 1), (4096, 5, 0), (9, 2, 3)] {
            let s = sequence(pixel, dim, replicate);
            let points: Vec<Vec2> = (0..1024).map(|i| s.point(i)).collect();
            for m in 0..=10 {
                assert!(is_net(&points[..1 << m]), "prefix of 2^{m} ({pixel}, {dim}, {replicate})");
            }
            for block in 0..8 {
                assert!(is_net(&points[block * 128..(block + 1) * 128]), "block {block}");
            }
            // In one dimension too: every aligned block of 2^m has one point per 2^-m interval.
            for m in 0..=8u32 {
                let mut cells: Vec<u32> =
                    (0..1u32 << m).map(|i| (s.point1(i) * (1u32 << m) as f32) as u32).collect();
                cells.sort_unstable();
                assert_eq!(cells, (0..1u32 << m).collect::<Vec<_>>(), "1D prefix of 2^{m}");
            }
        }
    }

    #[test]
    fn sequences_are_uniform_and_differ_by_dimension_and_replicate() {
        // The mean of each coordinate over many pixels' first point is about ½ (each point is
        // uniformly distributed), and the first points of two replicates or dimensions differ.
        let n = 4096;
        let mean: Vec2 = (0..n).map(|p| sequence(p, 3, 0).point(0)).sum::<Vec2>() / n as f32;
        assert!((mean - Vec2::splat(0.5)).abs().max_element() < 0.02, "{mean}");
        let third: Vec2 = (0..n).map(|p| sequence(p, 3, 1).point(2)).sum::<Vec2>() / n as f32;
        assert!((third - Vec2::splat(0.5)).abs().max_element() < 0.02, "{third}");
        let differ = (0..64).filter(|&p| sequence(p, 3, 0).point(0) != sequence(p, 3, 1).point(0)).count();
        assert_eq!(differ, 64);
        let differ = (0..64).filter(|&p| sequence(p, 3, 0).point(1) != sequence(p, 4, 0).point(1)).count();
        assert_eq!(differ, 64);
        // Every value lies in [0, 1).
        let s = sequence(1, 1, 0);
        assert!((0..10_000).all(|i| {
            let p = s.point(i);
            (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y) && (0.0..1.0).contains(&s.point1(i))
        }));
    }

    #[test]
    fn a_stratified_estimate_beats_independent_points() {
        // The mean of a disc's indicator over 64 points: the progressive sequence's error over
        // many pixels is well below independent uniform points' (about 1/8 of a unit square's
        // variance is left at 64 points for an edge, against 1/64·p(1-p) for random points).
        let inside = |p: Vec2| f32::from(u8::from((p - Vec2::splat(0.5)).length_squared() < 0.16));
        let truth = std::f32::consts::PI * 0.16;
        let (mut sobol, mut random) = (0.0f64, 0.0f64);
        for pixel in 0..400 {
            let s = sequence(pixel, 2, 0);
            let key = SampleKey { seed: 3, frame: 0, pixel, sample: 0 };
            let d = Dimension::new(&key, 2);
            let a = (0..64).map(|i| inside(s.point(i))).sum::<f32>() / 64.0 - truth;
            let b = (0..64).map(|i| inside(d.uniform2(i))).sum::<f32>() / 64.0 - truth;
            sobol += f64::from(a * a);
            random += f64::from(b * b);
        }
        assert!(sobol * 4.0 < random, "squared errors: progressive {sobol}, random {random}");
    }
}
