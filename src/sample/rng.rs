//! Counter-based randomness: every random number is a pure function of
//! `(seed, frame, pixel, sample, dimension, index)`, so an image is bit-identical for any thread
//! count, tile order, shard or resume, and any sample can be revisited out of order.
//!
//! The hash absorbs the key one 64-bit word at a time, each followed by a full 64-bit
//! finalizer (Stafford's "Mix13" variant of the SplitMix64/murmur3 finalizer):
//!
//! ```text
//! h = mix(seed ^ K)
//! h = mix(h ^ (pixel << 32 | sample))
//! h = mix(h ^ (frame << 32 | dim))
//! h = mix(h ^ index)
//! ```
//!
//! `mix` is a bijection on `u64` with full avalanche (every input bit flips each output bit with
//! probability ≈ ½), and `h ^ word` is a bijection in the word, so two keys that differ in exactly
//! one field always hash differently, and neighbouring pixels, dimensions and indices are
//! decorrelated. There is no generator state: [`SampleStream`] only counts dimensions.
//!
//! [`permute`] is Kensler's hashed permutation (pbrt's `PermutationElement`), used to shuffle
//! stratum order independently per dimension.

use glam::Vec2;

/// Identifies one camera sample: the hash input shared by all dimensions along its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SampleKey {
    /// Seed of all randomness (from the render settings).
    pub seed: u64,
    /// Frame number.
    pub frame: u32,
    /// Pixel id, `y * width + x` (or a lattice id chosen by the caller).
    pub pixel: u32,
    /// Sample number within the pixel.
    pub sample: u32,
}

/// Offset that keeps an all-zero key away from `mix`'s fixed point at zero (2⁶⁴ / φ).
const SEED_OFFSET: u64 = 0x9E37_79B9_7F4A_7C15;

/// Scale from a 24-bit integer to `[0, 1)`: `2⁻²⁴`.
const INV_2_24: f32 = 1.0 / (1u32 << 24) as f32;

/// Stafford's Mix13 64-bit finalizer: a bijection with full avalanche.
#[inline(always)]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A 64-bit hash of every field of `key`, the dimension `dim` and the point `index`.
///
/// # Examples
/// ```
/// use penumbra::sample::rng::{hash, SampleKey};
/// let key = SampleKey { seed: 7, frame: 0, pixel: 12, sample: 3 };
/// assert_eq!(hash(&key, 2, 0), hash(&key, 2, 0));
/// assert_ne!(hash(&key, 2, 0), hash(&key, 3, 0));
/// ```
#[inline]
pub fn hash(key: &SampleKey, dim: u32, index: u32) -> u64 {
    Dimension::new(key, dim).hash(index)
}

/// One dimension of one key: [`hash`] and [`uniform2`] of its points with the part that does
/// not depend on the point (three of the hash's four mixing rounds) done once, for callers
/// that draw many points of the same dimension (an area light's or a glossy cone's samples).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dimension(u64);

impl Dimension {
    /// Dimension `dim` of `key`.
    #[inline]
    pub fn new(key: &SampleKey, dim: u32) -> Self {
        let mut h = mix(key.seed ^ SEED_OFFSET);
        h = mix(h ^ ((u64::from(key.pixel) << 32) | u64::from(key.sample)));
        Self(mix(h ^ ((u64::from(key.frame) << 32) | u64::from(dim))))
    }

    /// [`hash`] of point `index`.
    #[inline(always)]
    pub fn hash(self, index: u32) -> u64 {
        mix(self.0 ^ u64::from(index))
    }

    /// [`uniform2`] of point `index`.
    #[inline]
    pub fn uniform2(self, index: u32) -> Vec2 {
        let h = self.hash(index);
        Vec2::new(unit_f32(h >> 40), unit_f32(h >> 16))
    }

    /// [`Self::uniform2`] of `N` points at once, as the arrays of their `x` and `y`: the same
    /// bits, worked out lane by lane. Inline it into a [`crate::simd::SimdLevel::run`] closure
    /// to get the level's vectors.
    #[inline(always)]
    pub fn uniform2_lanes<const N: usize>(self, index: &[u32; N]) -> ([f32; N], [f32; N]) {
        let h = index.map(|i| self.hash(i));
        (h.map(|h| unit_f32(h >> 40)), h.map(|h| unit_f32(h >> 16)))
    }
}

/// Converts 24 random bits (the low 24 of `bits`) to a float in `[0, 1)`; exact, never 1.0.
#[inline(always)]
fn unit_f32(bits: u64) -> f32 {
    (bits & 0x00FF_FFFF) as f32 * INV_2_24
}

/// A uniform value in `[0, 1)` from the top 24 bits of [`hash`]; never returns 1.0.
///
/// # Examples
/// ```
/// use penumbra::sample::rng::{uniform, SampleKey};
/// let u = uniform(&SampleKey::default(), 0, 0);
/// assert!((0.0..1.0).contains(&u));
/// ```
#[inline]
pub fn uniform(key: &SampleKey, dim: u32, index: u32) -> f32 {
    unit_f32(hash(key, dim, index) >> 40)
}

/// Two independent uniform values in `[0, 1)`: bits 40..64 and 16..40 of one [`hash`].
///
/// The first component equals [`uniform`] for the same arguments.
#[inline]
pub fn uniform2(key: &SampleKey, dim: u32, index: u32) -> Vec2 {
    Dimension::new(key, dim).uniform2(index)
}

/// Sequential allocation of dimensions along one camera sample's path.
///
/// Each call takes the next unused dimension id, so the values depend only on the key and the
/// position in the sequence, never on what other samples or threads did.
///
/// # Examples
/// ```
/// use penumbra::sample::rng::{uniform, SampleKey, SampleStream};
/// let key = SampleKey { seed: 1, frame: 0, pixel: 5, sample: 0 };
/// let mut stream = SampleStream::new(key);
/// let a = stream.next_1d(); // dimension 0
/// let _lens = stream.next_2d(); // dimension 1
/// assert_eq!(a, uniform(&key, 0, 0));
/// assert_eq!(stream.take_dim(), 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SampleStream {
    key: SampleKey,
    next_dim: u32,
}

impl SampleStream {
    /// A stream for `key`, starting at dimension 0.
    pub fn new(key: SampleKey) -> Self {
        Self { key, next_dim: 0 }
    }

    /// A stream for `key` whose first dimension is `first_dim` (the ones below are reserved
    /// by the caller).
    pub fn starting_at(key: SampleKey, first_dim: u32) -> Self {
        Self { key, next_dim: first_dim }
    }

    /// The key this stream hashes.
    pub fn key(&self) -> &SampleKey {
        &self.key
    }

    /// Returns the next unused dimension id and advances past it.
    pub fn take_dim(&mut self) -> u32 {
        let dim = self.next_dim;
        self.next_dim = self.next_dim.wrapping_add(1);
        dim
    }

    /// One uniform value in `[0, 1)` from the next dimension (`index` 0).
    pub fn next_1d(&mut self) -> f32 {
        let dim = self.take_dim();
        uniform(&self.key, dim, 0)
    }

    /// Two uniform values in `[0, 1)` from the next dimension (`index` 0).
    pub fn next_2d(&mut self) -> Vec2 {
        let dim = self.take_dim();
        uniform2(&self.key, dim, 0)
    }
}

/// The element at position `index` of a pseudo-random permutation of `0..n` chosen by `seed`.
///
/// For a fixed `(n, seed)`, `index ↦ permute(index, n, seed)` is a bijection on `0..n`
/// (Kensler 2013, "Correlated Multi-Jittered Sampling", as pbrt's `PermutationElement`: a hash
/// that is invertible on the next power of two, cycle-walked back into range). `index` is taken
/// modulo `n`; `n == 0` is treated as 1. Unlike the C original, the final offset is added in
/// 64 bits, so it stays a bijection when the 32-bit sum would wrap.
///
/// # Examples
/// ```
/// use penumbra::sample::rng::permute;
/// let mut seen: Vec<u32> = (0..10).map(|i| permute(i, 10, 42)).collect();
/// seen.sort_unstable();
/// assert_eq!(seen, (0..10).collect::<Vec<_>>());
/// ```
pub fn permute(index: u32, n: u32, seed: u64) -> u32 {
    Permutation::new(n, seed).at(index)
}

/// The permutation of [`permute`] for one `(n, seed)`, its seed folded and its offset reduced
/// once, for callers that take many of its elements.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Permutation {
    /// `n`, at least 1.
    l: u32,
    /// The mask of the next power of two minus one.
    w: u32,
    /// The seed folded into 32 well-mixed bits.
    p: u32,
    /// `p mod l`: the final offset.
    offset: u32,
}

impl Permutation {
    /// The permutation of `0..n` chosen by `seed`.
    #[inline]
    pub fn new(n: u32, seed: u64) -> Self {
        let l = n.max(1);
        // Fold the 64-bit seed into 32 well-mixed bits.
        let p = (mix(seed ^ SEED_OFFSET) >> 32) as u32;
        let mut w = l - 1;
        w |= w >> 1;
        w |= w >> 2;
        w |= w >> 4;
        w |= w >> 8;
        w |= w >> 16;
        Self { l, w, p, offset: p % l }
    }

    /// The element at position `index` (taken modulo `n`).
    #[inline]
    pub fn at(self, index: u32) -> u32 {
        let l = self.l;
        // Callers mostly pass an index already below `l`: a predictable branch spares them a
        // division.
        let mut i = if index < l { index } else { index % l };
        // Every step is a bijection on the low bits under the mask `w`, so the loop visits a
        // cycle of that bijection and stops at the first element inside `0..l`.
        loop {
            i = self.step(i);
            if i < l {
                break;
            }
        }
        // `(i + p) mod l` without a 64-bit division: `i < l` and `offset < l`, so one
        // subtraction reduces the sum (in 64 bits: it may pass 2³²).
        self.shifted(i)
    }

    /// [`Self::at`] of `N` indices, each below `n`, at once: the same elements, worked out
    /// lane by lane so that the lanes' steps share instructions (each lane walks its cycle until
    /// it lands in `0..n`, as [`Self::at`] does). Inline it into a
    /// [`crate::simd::SimdLevel::run`] closure to get the level's vectors.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn at_lanes<const N: usize>(self, index: &[u32; N]) -> [u32; N] {
        debug_assert!(index.iter().all(|&i| i < self.l));
        let mut i = *index;
        let mut walking = [true; N];
        while walking.contains(&true) {
            for k in 0..N {
                let next = self.step(i[k]);
                i[k] = if walking[k] { next } else { i[k] };
                walking[k] &= i[k] >= self.l;
            }
        }
        i.map(|i| self.shifted(i))
    }

    /// One step of the walk: a bijection on the bits under the mask `w`.
    #[inline(always)]
    fn step(self, mut i: u32) -> u32 {
        let Self { w, p, .. } = self;
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^ (i >> 5)
    }

    /// `(i + offset) mod n` for `i < n`.
    #[inline(always)]
    fn shifted(self, i: u32) -> u32 {
        let Self { l, offset, .. } = self;
        let sum = u64::from(i) + u64::from(offset);
        (if sum >= u64::from(l) { sum - u64::from(l) } else { sum }) as u32
    }
}

#[cfg(test)]
mod tests;
