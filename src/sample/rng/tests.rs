//! Tests of `src/sample/rng.rs`.

use super::*;

fn key(seed: u64, frame: u32, pixel: u32, sample: u32) -> SampleKey {
    SampleKey { seed, frame, pixel, sample }
}

/// Every (seed, frame, pixel, sample, dim) of a small box, in row-major order.
fn grid_of_inputs() -> Vec<(SampleKey, u32)> {
    let mut out = Vec::new();
    for seed in [0u64, 1, u64::MAX] {
        for frame in 0..3 {
            for pixel in [0u32, 1, 640, 641, 1_000_000] {
                for sample in 0..4 {
                    for dim in 0..5 {
                        out.push((key(seed, frame, pixel, sample), dim));
                    }
                }
            }
        }
    }
    out
}

#[test]
fn revisiting_inputs_in_reverse_or_shuffled_order_gives_identical_values() {
    let inputs = grid_of_inputs();
    let forward: Vec<(u64, Vec2)> =
        inputs.iter().map(|(k, d)| (hash(k, *d, 3), uniform2(k, *d, 3))).collect();
    for i in (0..inputs.len()).rev() {
        let (k, d) = inputs[i];
        assert_eq!(forward[i], (hash(&k, d, 3), uniform2(&k, d, 3)));
    }
    let n = inputs.len() as u32;
    for j in 0..n {
        let i = permute(j, n, 99) as usize;
        let (k, d) = inputs[i];
        assert_eq!(forward[i], (hash(&k, d, 3), uniform2(&k, d, 3)));
    }
}

#[test]
fn sample_stream_replays_the_same_sequence_from_the_key_alone() {
    let k = key(5, 2, 77, 9);
    let mut a = SampleStream::new(k);
    let first: Vec<f32> = (0..8).map(|_| a.next_1d()).collect();
    let pair = a.next_2d();
    let mut b = SampleStream::new(k);
    let second: Vec<f32> = (0..8).map(|_| b.next_1d()).collect();
    assert_eq!(first, second);
    assert_eq!(pair, b.next_2d());
    assert_eq!(pair, uniform2(&k, 8, 0));
    assert_eq!(*b.key(), k);
    assert_eq!(b.take_dim(), 9);
}

#[test]
fn changing_any_one_field_changes_the_value() {
    for base in grid_of_inputs() {
        let (k, d) = base;
        for index in [0u32, 7] {
            let h = hash(&k, d, index);
            let variants = [
                hash(&SampleKey { seed: k.seed ^ 1, ..k }, d, index),
                hash(&SampleKey { seed: k.seed ^ (1 << 63), ..k }, d, index),
                hash(&SampleKey { frame: k.frame + 1, ..k }, d, index),
                hash(&SampleKey { pixel: k.pixel ^ 1, ..k }, d, index),
                hash(&SampleKey { sample: k.sample + 1, ..k }, d, index),
                hash(&k, d + 1, index),
                hash(&k, d, index + 1),
            ];
            for v in variants {
                assert_ne!(h, v, "{k:?} dim {d} index {index}");
            }
        }
    }
    // The 24-bit floats differ too (a collision would be a 2⁻²⁴ fluke, not a pattern).
    let k = key(3, 1, 10, 2);
    let u = uniform(&k, 4, 0);
    assert_ne!(u, uniform(&key(4, 1, 10, 2), 4, 0));
    assert_ne!(u, uniform(&key(3, 2, 10, 2), 4, 0));
    assert_ne!(u, uniform(&key(3, 1, 11, 2), 4, 0));
    assert_ne!(u, uniform(&key(3, 1, 10, 3), 4, 0));
    assert_ne!(u, uniform(&k, 5, 0));
    assert_ne!(u, uniform(&k, 4, 1));
}

#[test]
fn uniform_is_in_the_unit_interval_with_mean_one_half_and_passes_chi_square() {
    const N: u32 = 100_000;
    const BINS: usize = 16;
    // χ² critical value for 15 degrees of freedom at p = 0.001.
    const CHI2_CRIT: f64 = 37.70;
    let mut bins = [0u32; BINS];
    let mut sum = 0.0f64;
    for p in 0..N {
        let u = uniform(&key(2024, 0, p, 0), 0, 0);
        assert!((0.0..1.0).contains(&u));
        sum += f64::from(u);
        bins[(u * BINS as f32) as usize] += 1;
    }
    let mean = sum / f64::from(N);
    assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
    let expected = f64::from(N) / BINS as f64;
    let chi2: f64 = bins.iter().map(|&b| (f64::from(b) - expected).powi(2) / expected).sum();
    assert!(chi2 < CHI2_CRIT, "chi2 {chi2}");
}

#[test]
fn uniform_never_returns_one() {
    assert_eq!(unit_f32(u64::MAX), 1.0 - INV_2_24);
    assert_eq!(unit_f32(0), 0.0);
    assert!(unit_f32(u64::MAX) < 1.0);
}

fn correlation(pairs: impl Iterator<Item = (f32, f32)>) -> f64 {
    let (mut n, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0f64, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (x, y) in pairs {
        let (x, y) = (f64::from(x), f64::from(y));
        n += 1.0;
        sx += x;
        sy += y;
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
    }
    let cov = sxy / n - (sx / n) * (sy / n);
    let vx = sxx / n - (sx / n).powi(2);
    let vy = syy / n - (sy / n).powi(2);
    cov / (vx * vy).sqrt()
}

/// Correlations between neighbouring pixels, dimensions, indices and the two halves of
/// `uniform2`, over `n` keys with `seed`.
fn neighbour_correlations(seed: u64, n: u32) -> [(&'static str, f64); 4] {
    let k = |p: u32| key(seed, 0, p, 0);
    let pixels = correlation((0..n).map(|p| (uniform(&k(p), 0, 0), uniform(&k(p + 1), 0, 0))));
    let dims = correlation((0..n).map(|p| (uniform(&k(p), 0, 0), uniform(&k(p), 1, 0))));
    let indices = correlation((0..n).map(|i| (uniform(&k(0), 0, i), uniform(&k(0), 0, i + 1))));
    let pair = correlation((0..n).map(|p| {
        let v = uniform2(&k(p), 0, 0);
        (v.x, v.y)
    }));
    [("pixels", pixels), ("dims", dims), ("indices", indices), ("uniform2", pair)]
}

#[test]
fn adjacent_pixels_dimensions_and_indices_are_uncorrelated() {
    // At 100k values one standard error is 1/√100k ≈ 0.0032, so the 0.01 bound is ≈ 3σ and
    // holds for this fixed seed (seed 11 gives -0.012 on dims by chance). The 1M-value check
    // over several seeds (0.005 ≈ 5σ) is what rules out a structural correlation.
    for (what, c) in neighbour_correlations(0, 100_000) {
        assert!(c.abs() < 0.01, "{what}: corr {c}");
    }
    for seed in 0..4 {
        for (what, c) in neighbour_correlations(seed, 1_000_000) {
            assert!(c.abs() < 0.005, "seed {seed} {what}: corr {c}");
        }
    }
}

#[test]
fn permute_is_a_bijection_for_every_n_up_to_257_and_several_seeds() {
    for seed in [0u64, 1, 2, 0xDEAD_BEEF, u64::MAX, 1 << 40] {
        for n in 1..=257u32 {
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let j = permute(i, n, seed);
                assert!(j < n, "n {n} seed {seed}: {j}");
                assert!(!seen[j as usize], "n {n} seed {seed}: {j} twice");
                seen[j as usize] = true;
            }
        }
    }
}

#[test]
fn permute_keeps_its_values() {
    // Computed by the version that reduced `(i + p) mod n` with a 64-bit division (before
    // `Permutation` reduced the offset once): every image's strata depend on these.
    let cases: [(u32, u32, u64, u32); 12] = [
        (0, 16, 1, 13),
        (5, 16, 1, 9),
        (15, 16, 3735928559, 3),
        (3, 10, 42, 6),
        (9, 10, 42, 0),
        (100, 257, 7, 67),
        (1, 3, u64::MAX, 0),
        (12345, 100000, 99, 62736),
        (4000000000, 4294967295, 3, 487368322),
        (4294967294, 4294967295, 12, 2368662622),
        (7, 4000000000, 5, 827656666),
        (2500000000, 3000000000, 77, 502435107),
    ];
    for (index, n, seed, expected) in cases {
        assert_eq!(permute(index, n, seed), expected, "permute({index}, {n}, {seed})");
        assert_eq!(Permutation::new(n, seed).at(index), expected);
    }
}

#[test]
fn a_dimension_hashes_every_field_in_four_rounds() {
    let k = key(3, 9, 77, 5);
    for dim in [0, 1, 40] {
        let d = Dimension::new(&k, dim);
        for index in [0, 1, 1000, u32::MAX] {
            // The hash as the sampling module defines it, round by round.
            let mut h = mix(k.seed ^ SEED_OFFSET);
            h = mix(h ^ ((u64::from(k.pixel) << 32) | u64::from(k.sample)));
            h = mix(h ^ ((u64::from(k.frame) << 32) | u64::from(dim)));
            let h = mix(h ^ u64::from(index));
            assert_eq!(d.hash(index), h);
            assert_eq!(d.uniform2(index), Vec2::new(unit_f32(h >> 40), unit_f32(h >> 16)));
        }
    }
}

#[test]
fn permute_treats_zero_length_as_one_and_depends_on_the_seed() {
    assert_eq!(permute(0, 0, 5), 0);
    assert_eq!(permute(3, 1, 5), 0);
    let a: Vec<u32> = (0..64).map(|i| permute(i, 64, 1)).collect();
    let b: Vec<u32> = (0..64).map(|i| permute(i, 64, 2)).collect();
    assert_ne!(a, b);
    assert_ne!(a, (0..64).collect::<Vec<_>>());
}

#[test]
fn permute_over_many_seeds_looks_like_a_random_permutation() {
    const SEEDS: u64 = 10_000;
    for n in [2u32, 4, 8, 16, 64, 100] {
        let (mut fixed, mut displacement) = (0u64, 0u64);
        for seed in 0..SEEDS {
            for i in 0..n {
                let j = permute(i, n, seed);
                fixed += u64::from(i == j);
                displacement += u64::from(i.abs_diff(j));
            }
        }
        // A uniform random permutation has 1 fixed point and mean |i - π(i)| of (n²-1)/3n.
        let fixed = fixed as f64 / SEEDS as f64;
        let mean_disp = displacement as f64 / (SEEDS as f64 * f64::from(n));
        let expected_disp = f64::from(n * n - 1) / (3.0 * f64::from(n));
        assert!((fixed - 1.0).abs() < 0.05, "n {n}: {fixed} fixed points");
        assert!((mean_disp / expected_disp - 1.0).abs() < 0.02, "n {n}: {mean_disp}");
    }
}

#[test]
fn hash_values_are_frozen_so_images_stay_reproducible_across_versions() {
    let k = key(42, 3, 1234, 5);
    assert_eq!(hash(&SampleKey::default(), 0, 0), 0x1957_a760_4e21_5178);
    assert_eq!(hash(&k, 6, 7), 0x0135_d5fd_b61b_58bc);
    assert_eq!(uniform2(&k, 6, 7), Vec2::new(0.0047276616, 0.99105996));
    let p: Vec<u32> = (0..8).map(|i| permute(i, 8, 0)).collect();
    assert_eq!(p, [3, 2, 6, 4, 5, 1, 7, 0]);
}
