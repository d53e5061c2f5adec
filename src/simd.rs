//! Instruction-set levels of the packet tracer, detected once and dispatched safely.
//!
//! The packet kernels ([`crate::trace::packet`]) are written as plain loops over fixed-width
//! lane arrays. [`SimdLevel::run`] calls them inside a function compiled with the level's
//! target features (through `pulp`, which checks the CPU before it enables anything), so LLVM
//! turns the same loops into SSE2, AVX2 or AVX-512 code. No `unsafe` here: `pulp` confines it.
//!
//! Every level performs the same IEEE operations in the same order: Rust never contracts a
//! multiply and an add into a fused one, vectorising element-wise float arithmetic does not
//! reorder it, and the kernels use no approximate reciprocal or square root. So a frame traced
//! at any level, or by the single-ray reference path (`scalar`), is the same bits: a cluster of
//! mixed CPUs renders one sequence.

use std::cell::Cell;
use std::fmt;
use std::str::FromStr;

/// Which path traces a frame's rays: the single-ray reference, or packets at an instruction
/// set level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SimdLevel {
    /// The best level this CPU has ([`SimdLevel::detect`]).
    #[default]
    Auto,
    /// Single rays through the scalar DDA: the reference every other level must equal.
    Scalar,
    /// Packets, compiled for the x86-64 baseline (SSE2) or the target's default.
    Baseline,
    /// Packets, with AVX2 and FMA enabled (x86-64-v3).
    Avx2,
    /// Packets, with AVX-512 F/BW/CD/DQ/VL enabled (x86-64-v4).
    Avx512,
}

thread_local! {
    /// The level of this thread's single-ray kernels (see [`single_ray_level`]).
    static SINGLE_RAY: Cell<SimdLevel> = const { Cell::new(SimdLevel::Auto) };
}

/// The level at which single rays run their SIMD kernels on this thread (one ray against a grid
/// cell's triangles at once: [`crate::geom::triangle::nearest_in_block`]): resolved, `Scalar`
/// for one primitive at a time. [`SimdLevel::Auto`] unless [`with_single_ray_level`] says
/// otherwise. The single-ray tracer is reached through many layers of the store; a level
/// scoped to the thread spares each of them a parameter, and every level gives the same bits.
#[inline]
pub fn single_ray_level() -> SimdLevel {
    match SINGLE_RAY.with(Cell::get) {
        SimdLevel::Auto => SimdLevel::detect(),
        level => level,
    }
}

/// Runs `f` with this thread's single-ray kernels at `level` (resolved), then restores the
/// previous level; the renderer wraps each tile in it with the frame's `--simd`.
pub fn with_single_ray_level<R>(level: SimdLevel, f: impl FnOnce() -> R) -> R {
    struct Restore(SimdLevel);
    impl Drop for Restore {
        fn drop(&mut self) {
            SINGLE_RAY.with(|c| c.set(self.0));
        }
    }
    let _restore = Restore(SINGLE_RAY.with(|c| c.replace(level.resolve())));
    f()
}

impl SimdLevel {
    /// Every level, in the order they are listed.
    pub const ALL: [SimdLevel; 5] =
        [SimdLevel::Auto, SimdLevel::Scalar, SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512];

    /// The best level this CPU supports (detected once per process).
    pub fn detect() -> SimdLevel {
        static DETECTED: std::sync::OnceLock<SimdLevel> = std::sync::OnceLock::new();
        *DETECTED.get_or_init(SimdLevel::probe)
    }

    /// Asks the CPU for the best level it supports.
    fn probe() -> SimdLevel {
        #[cfg(target_arch = "x86_64")]
        {
            if pulp::x86::V4::try_new().is_some() {
                return SimdLevel::Avx512;
            }
            if pulp::x86::V3::try_new().is_some() {
                return SimdLevel::Avx2;
            }
        }
        SimdLevel::Baseline
    }

    /// True when this CPU can run the level (`Auto`, `Scalar` and `Baseline` always can).
    pub fn available(self) -> bool {
        match self {
            SimdLevel::Auto | SimdLevel::Scalar | SimdLevel::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2 => pulp::x86::V3::try_new().is_some(),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx512 => pulp::x86::V4::try_new().is_some(),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The concrete level a render uses: `Auto` becomes the detected one, and a level this CPU
    /// lacks falls back to the best one it has (the image is the same either way; the CLI
    /// refuses such a request before it gets here).
    pub fn resolve(self) -> SimdLevel {
        match self {
            SimdLevel::Auto => SimdLevel::detect(),
            level if level.available() => level,
            _ => SimdLevel::detect(),
        }
    }

    /// True for the levels that trace packets.
    pub fn packets(self) -> bool {
        !matches!(self.resolve(), SimdLevel::Scalar)
    }

    /// Runs `f` compiled for this level's target features; `Auto` is resolved first. On levels
    /// the CPU lacks it runs `f` as it is.
    ///
    /// Only code inlined into the level's entry point gets the features, so mark the closure
    /// `#[inline(always)]` (and what it calls, down to the kernels): `level.run(#[inline(always)]
    /// || closest_hits(...))`. A closure left to the inliner is compiled once, for the baseline.
    #[inline(always)]
    pub fn run<R>(self, f: impl FnOnce() -> R) -> R {
        match self.resolve() {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx512 => match pulp::x86::V4::try_new() {
                Some(v4) => v4.vectorize(f),
                None => f(),
            },
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2 => match pulp::x86::V3::try_new() {
                Some(v3) => v3.vectorize(f),
                None => f(),
            },
            _ => f(),
        }
    }

    /// The level's name as `--simd` takes it.
    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Auto => "auto",
            SimdLevel::Scalar => "scalar",
            SimdLevel::Baseline => "baseline",
            SimdLevel::Avx2 => "avx2",
            SimdLevel::Avx512 => "avx512",
        }
    }
}

impl fmt::Display for SimdLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A `--simd` value that names no level.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown SIMD level `{0}` (expected one of auto, scalar, baseline, avx2, avx512)")]
pub struct UnknownSimdLevel(pub String);

impl FromStr for SimdLevel {
    type Err = UnknownSimdLevel;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        SimdLevel::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| UnknownSimdLevel(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for level in SimdLevel::ALL {
            assert_eq!(level.name().parse::<SimdLevel>(), Ok(level));
        }
        assert!("sse9".parse::<SimdLevel>().unwrap_err().to_string().contains("avx512"));
    }

    #[test]
    fn auto_resolves_to_an_available_packet_level() {
        let level = SimdLevel::Auto.resolve();
        assert!(level.available() && level != SimdLevel::Auto && level != SimdLevel::Scalar);
        assert!(SimdLevel::Scalar.resolve() == SimdLevel::Scalar && !SimdLevel::Scalar.packets());
    }

    #[test]
    fn every_level_runs_the_same_float_arithmetic() {
        let a: Vec<f32> = (0..64).map(|i| 1.0 + i as f32 * 0.37).collect();
        let f = || a.iter().map(|&x| (x * 1.1 + 0.3) / (x + 2.0).sqrt()).collect::<Vec<f32>>();
        let want = f();
        for level in SimdLevel::ALL {
            assert_eq!(level.run(f), want, "{level}");
        }
    }
}
