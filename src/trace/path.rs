//! The state one camera sample's path carries down the recursion: limits, the secondary-ray
//! budget, its sample stream and its share of each effect's per-pixel samples.

use super::settings::{RenderSettings, Sampling};
use super::stats::RayCounts;
use crate::math::{Vec2, Vec3};
use crate::sample::dims::{FIRST_PATH_DIM, PERMUTATION_SEED};
use crate::sample::pattern::{square_point_in, square_points_in, strata};
use crate::sample::rng::{Dimension, Permutation, SampleKey, SampleStream};
use crate::sample::sobol::Progressive;
use crate::sample::Pattern;

/// The secondary rays (reflection, refraction, glossy, blurry) one camera sample may still
/// trace: a per-sample counter carried down the recursion, so the rays it refuses depend only
/// on the sample, never on threads or tile order.
///
/// Rays are granted depth-first in the order the integrator asks for them (reflection before
/// refraction, a cone's rays in turn), but a node first sets aside one ray for each sibling
/// still to come (the refraction while the reflection's tree is traced, the rest of a cone), so
/// a tree that outgrows the budget loses its deepest rays, not its shallow siblings. A tree
/// that fits is never cut: every ray set aside is asked for later, so `spent + reserved`
/// never exceeds the rays the whole tree asks for. Shadow rays are not counted: each shading
/// point sends a bounded number (one per point light, `samples` per area light), and the
/// budget bounds the shading points to one plus the secondary rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayBudget {
    limit: u32,
    spent: u32,
    reserved: u32,
    refused: u32,
}

impl RayBudget {
    /// A budget of `limit` secondary rays, none spent.
    pub fn new(limit: u32) -> Self {
        Self { limit, spent: 0, reserved: 0, refused: 0 }
    }

    /// Sets aside `n` rays that siblings will ask for later.
    #[inline]
    pub(crate) fn reserve(&mut self, n: u32) {
        self.reserved = self.reserved.saturating_add(n);
    }

    /// Gives back `n` rays set aside by [`Self::reserve`] (their sibling is about to ask).
    #[inline]
    pub(crate) fn release(&mut self, n: u32) {
        debug_assert!(self.reserved >= n, "released more rays than were set aside");
        self.reserved = self.reserved.saturating_sub(n);
    }

    /// Grants one ray if the budget, less what is set aside, has one left; counts a refusal
    /// otherwise.
    #[inline]
    pub(crate) fn grant(&mut self) -> bool {
        if self.spent.saturating_add(self.reserved) < self.limit {
            self.spent += 1;
            true
        } else {
            self.refused = self.refused.saturating_add(1);
            false
        }
    }

    /// Rays granted so far.
    pub fn spent(&self) -> u32 {
        self.spent
    }

    /// Rays refused so far (0 unless the tree was cut).
    pub fn refused(&self) -> u32 {
        self.refused
    }
}

/// Per-path context: recursion limits, sampling budgets, the randomness of the camera sample
/// being traced, and the counters of one worker.
pub struct PathContext<'a> {
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Minimum path weight worth tracing.
    pub min_contribution: f32,
    /// Glossy/blurry rays per pixel at the first bounce (one per path deeper down).
    pub glossy: Sampling,
    /// Randomness of this camera sample: every random choice along the path takes dimensions
    /// from it in traversal order, so the path is a pure function of its key.
    pub stream: SampleStream,
    /// Which camera sample of which pixel this path belongs to.
    pub camera: CameraSample,
    /// Secondary rays this camera sample may still trace.
    pub budget: RayBudget,
    /// Ray counters to add to.
    pub rays: &'a mut RayCounts,
    /// The SIMD level shadow packets are traced at, or `None` for single rays (`--simd scalar`).
    pub packets: Option<crate::simd::SimdLevel>,
    /// Transmittance of the shadow ray towards each of the first [`HINTED_LIGHTS`] lights from
    /// the next shading point, already traced in a packet with its neighbours' (camera hits and
    /// point or directional lights); taken by the first [`super::phong::direct_light`].
    pub shadow_hint: Option<ShadowHint>,
    /// Time of this camera sample in the shutter interval (0 at open, 1 at close): every ray
    /// of the path sees moving objects where they are then. 0 where nothing moves.
    pub time: f32,
}

/// Lights whose shadow rays from camera hits are traced in packets.
pub const HINTED_LIGHTS: usize = 4;

/// Per light (by index), the transmittance of a shading point's shadow ray, where known.
pub type ShadowHint = [Option<Vec3>; HINTED_LIGHTS];

/// A camera sample: its own key, and its place among its pixel's samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CameraSample {
    /// Key of this sample's path stream.
    pub key: SampleKey,
    /// Key shared by all of the pixel's samples: effect patterns are stratified through it.
    pub pixel: SampleKey,
    /// Index of this sample among the pixel's `spp`.
    pub slot: u32,
    /// Camera samples of the pixel: an effect's per-pixel sample count is shared among them.
    pub spp: u32,
    /// Where the sample sits in its pixel's progressive sequences, for noise-driven sampling;
    /// `None` for a fixed set of `spp`.
    pub progressive: Option<Replica>,
}

/// A camera sample's place in noise-driven sampling's progressive sequences
/// ([`crate::sample::sobol`]): which of the pixel's independent replicates it belongs to, and
/// its index among that replicate's camera samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Replica {
    /// The replicate (`0..COUNT`: samples take them in turn).
    pub replicate: u32,
    /// The sample's index within its replicate.
    pub index: u32,
}

impl Replica {
    /// Independent replicates a noise-driven pixel interleaves.
    pub const COUNT: u32 = crate::sample::noise::REPLICATES as u32;

    /// The place of a pixel's camera sample `j` (counting over all its batches).
    #[inline]
    pub fn of(j: u32) -> Self {
        Self { replicate: j % Self::COUNT, index: j / Self::COUNT }
    }

    /// Point `index` of this replicate in a pixel's dimension, placed in `[0, 1)²` by
    /// `pattern`: jittered, the replicate's progressive `sequence`; random, an independent pair
    /// of the dimension's `points`; grid, the stratum centres of `strata` in turn.
    #[inline]
    pub fn place(
        self,
        pattern: Pattern,
        sequence: Progressive,
        points: Dimension,
        strata: (u32, u32),
    ) -> Vec2 {
        match pattern {
            Pattern::Jittered => sequence.point(self.index),
            Pattern::Random => {
                points.uniform2(self.index.wrapping_mul(Self::COUNT).wrapping_add(self.replicate))
            }
            Pattern::Grid => square_point_in(Pattern::Grid, strata, self.index, Vec2::ZERO),
        }
    }
}

impl CameraSample {
    /// A sample that is its pixel's only one (adaptive lattice points, single rays).
    pub fn single(key: SampleKey) -> Self {
        Self { key, pixel: key, slot: 0, spp: 1, progressive: None }
    }
}

impl<'a> PathContext<'a> {
    /// The context of the path of `camera` under `settings`.
    pub fn new(settings: &RenderSettings, camera: CameraSample, rays: &'a mut RayCounts) -> Self {
        let level = settings.simd.resolve();
        Self {
            max_depth: settings.max_depth,
            min_contribution: settings.min_contribution,
            glossy: settings.glossy,
            stream: SampleStream::starting_at(camera.key, FIRST_PATH_DIM),
            camera: CameraSample { spp: camera.spp.max(1), ..camera },
            budget: RayBudget::new(settings.max_secondary_rays),
            rays,
            packets: (level != crate::simd::SimdLevel::Scalar).then_some(level),
            shadow_hint: None,
            time: 0.0,
        }
    }

    /// This context for a path at time `s` of a scene with motion: single rays only (packets
    /// share no time), every ray at `s`.
    pub fn at_time(mut self, s: f32) -> Self {
        self.packets = None;
        self.time = s;
        self
    }

    /// Ends the path: adds what the budget did to the ray counters.
    pub fn finish(self) {
        self.rays.budget.record(self.budget.spent(), self.budget.refused());
    }

    /// Rays a glossy or blurry cone traces at `depth`: this camera sample's share of
    /// `glossy.samples` at the first bounce, one deeper down (what [`scatter`] asks for).
    #[inline]
    pub(crate) fn cone_rays(&self, depth: u32) -> u32 {
        if depth == 0 {
            self.glossy.samples.max(1).div_ceil(self.camera.spp)
        } else {
            1
        }
    }

    /// This camera sample's share of an effect that takes `n` samples per pixel, its points
    /// placed in `[0, 1)²` by `pattern`: `ceil(n / spp)` of them.
    ///
    /// - In a fixed set, the pixel's `spp` samples share one `pattern` of `n` points: across
    ///   them the strata are a permutation of `0..n`, so the pixel's points stay stratified.
    /// - In noise-driven sampling ([`CameraSample::progressive`]), jittered points are the
    ///   next of the sample's replicate's progressive sequence in this dimension, so however
    ///   many samples a pixel takes, its points stay stratified; random points are independent;
    ///   grid points cycle through the `n` stratum centres.
    pub fn effect_samples(&mut self, n: u32, pattern: Pattern) -> EffectSamples {
        let n = n.max(1);
        let dim = self.stream.take_dim();
        let c = &self.camera;
        let share = n.div_ceil(c.spp);
        let points = Dimension::new(&c.pixel, dim);
        let (first, source) = match c.progressive {
            None => (
                c.slot.wrapping_mul(share),
                Source::Fixed(Permutation::new(n, points.hash(PERMUTATION_SEED))),
            ),
            Some(r) => (
                r.index.wrapping_mul(share),
                Source::Progressive(Progressive::new(points, r.replicate), r.replicate),
            ),
        };
        EffectSamples {
            points,
            n,
            strata: strata(n),
            pattern,
            next: first,
            end: first.wrapping_add(share),
            source,
        }
    }
}

/// Where an effect's points come from.
#[derive(Debug, Clone, Copy)]
enum Source {
    /// A fixed set: the order its strata are visited in.
    Fixed(Permutation),
    /// Noise-driven sampling: the replicate's sequence, and the replicate.
    Progressive(Progressive, u32),
}

/// One camera sample's share of an effect's per-pixel samples, as points in `[0, 1)²`; see
/// [`PathContext::effect_samples`].
#[derive(Debug, Clone)]
pub struct EffectSamples {
    /// The pixel's random pairs in this effect's dimension.
    points: Dimension,
    n: u32,
    strata: (u32, u32),
    pattern: Pattern,
    next: u32,
    end: u32,
    source: Source,
}

impl EffectSamples {
    /// Samples this camera sample takes.
    pub fn taken(&self) -> u32 {
        self.end.wrapping_sub(self.next)
    }

    /// Samples of the whole pixel (the pattern's size).
    pub fn pattern_size(&self) -> u32 {
        self.n
    }

    /// The next `N` points (fewer where fewer are left) into `out`, and how many: the points
    /// [`Iterator::next`] would give, the same bits. A fixed set's points are worked out lane by
    /// lane where `N` of them are left below the pattern's size, so that their steps share
    /// instructions; inline it into a [`crate::simd::SimdLevel::run`] closure to get the
    /// level's vectors.
    #[inline(always)]
    pub fn fill<const N: usize>(&mut self, out: &mut [Vec2; N]) -> usize {
        let g = self.next;
        let whole = self.taken() as usize >= N && g.checked_add(N as u32).is_some_and(|end| end <= self.n);
        match self.source {
            Source::Fixed(order) if whole => {
                let index: [u32; N] = std::array::from_fn(|k| g + k as u32);
                let strata = order.at_lanes(&index);
                let (ux, uy) = self.points.uniform2_lanes(&index);
                *out = square_points_in(self.pattern, self.strata, &strata, &ux, &uy);
                self.next = g + N as u32;
                N
            }
            _ => out.iter_mut().zip(self.by_ref()).map(|(slot, point)| *slot = point).count(),
        }
    }
}

impl Iterator for EffectSamples {
    type Item = Vec2;

    #[inline]
    fn next(&mut self) -> Option<Vec2> {
        if self.next == self.end {
            return None;
        }
        let g = self.next;
        self.next = self.next.wrapping_add(1);
        Some(match self.source {
            Source::Fixed(order) => {
                // `g` mostly lies below `n` (a camera sample's share of a fixed set): a predictable
                // branch spares a division.
                let stratum = if g < self.n { g } else { g % self.n };
                square_point_in(self.pattern, self.strata, order.at(stratum), self.points.uniform2(g))
            }
            Source::Progressive(sequence, replicate) => {
                Replica { replicate, index: g }.place(self.pattern, sequence, self.points, self.strata)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::SimdLevel;

    /// `fill` gives the points `next` gives, in the same order, whatever share of a fixed set
    /// or of a noise-driven replicate the camera sample takes, and at every SIMD level.
    #[test]
    fn filled_lanes_are_the_points_next_gives() {
        let settings = RenderSettings::default();
        let key = SampleKey { seed: 5, frame: 2, pixel: 77, sample: 0 };
        let mut cases = 0;
        for (n, spp) in [(256, 16), (256, 1), (17, 1), (40, 3), (16, 16), (100, 7), (1, 1), (33, 2)] {
            for slot in [0, spp / 2, spp - 1] {
                for progressive in [None, Some(Replica::of(slot + 9))] {
                    for pattern in [Pattern::Jittered, Pattern::Grid, Pattern::Random] {
                        let camera = CameraSample { key, pixel: key, slot, spp, progressive };
                        let mut rays = RayCounts::default();
                        let mut ctx = PathContext::new(&settings, camera, &mut rays);
                        let samples = ctx.effect_samples(n, pattern);
                        let want: Vec<Vec2> = samples.clone().collect();
                        for level in SimdLevel::ALL.into_iter().filter(|l| l.available()) {
                            let mut samples = samples.clone();
                            let mut got = Vec::new();
                            loop {
                                let mut lanes = [Vec2::NAN; 16];
                                let count = level.run(
                                    #[inline(always)]
                                    || samples.fill(&mut lanes),
                                );
                                got.extend_from_slice(&lanes[..count]);
                                if count < lanes.len() {
                                    break;
                                }
                            }
                            let bits = |v: &[Vec2]| {
                                v.iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect::<Vec<_>>()
                            };
                            assert_eq!(
                                bits(&got),
                                bits(&want),
                                "n {n}, spp {spp}, slot {slot}, {progressive:?}, {pattern:?}, {level:?}"
                            );
                            assert_eq!(samples.next(), None);
                            cases += usize::from(want.len() >= 16 && progressive.is_none());
                        }
                    }
                }
            }
        }
        assert!(cases > 0, "no case took the lane-wise path");
    }

    #[test]
    fn a_budget_grants_up_to_its_limit_less_the_rays_set_aside() {
        let mut budget = RayBudget::new(3);
        budget.reserve(1);
        assert!(budget.grant());
        assert!(budget.grant());
        assert!(!budget.grant(), "the last ray is set aside for a sibling");
        budget.release(1);
        assert!(budget.grant(), "the sibling gets it");
        assert!(!budget.grant());
        assert_eq!((budget.spent(), budget.refused()), (3, 2));
    }

    #[test]
    fn a_budget_that_holds_the_tree_refuses_nothing() {
        // Four rays asked for, two of them set aside first: exactly four fit.
        let mut budget = RayBudget::new(4);
        budget.reserve(2);
        assert!(budget.grant() && budget.grant());
        budget.release(2);
        assert!(budget.grant() && budget.grant());
        assert_eq!((budget.spent(), budget.refused()), (4, 0));
    }
}
