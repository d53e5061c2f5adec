//! Traversal cost: a histogram of small counts, the per-worker tally of cells visited and
//! primitive tests per ray, and the frame's mean and p99 figures.

use serde::Serialize;

/// Buckets of a [`CostHistogram`]: exact below 32, then four per power of two up to 2^20.
const BUCKETS: usize = 96;

/// A histogram of small counts with bounded relative error (≤ 25 % above 32), cheap enough
/// to update once per ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CostHistogram {
    buckets: [u64; BUCKETS],
}

impl Default for CostHistogram {
    fn default() -> Self {
        Self { buckets: [0; BUCKETS] }
    }
}

impl CostHistogram {
    #[inline]
    fn bucket(v: u32) -> usize {
        if v < 32 {
            return v as usize;
        }
        let e = 31 - v.leading_zeros(); // ≥ 5
        let sub = (v >> (e - 2)) & 3;
        (32 + (e as usize - 5) * 4 + sub as usize).min(BUCKETS - 1)
    }

    /// The largest value that falls into bucket `b`.
    fn upper(b: usize) -> u64 {
        if b < 32 {
            return b as u64;
        }
        let e = (b - 32) / 4 + 5;
        let sub = ((b - 32) % 4) as u64;
        ((4 + sub + 1) << (e - 2)) - 1
    }

    /// Counts one value.
    #[inline]
    pub fn record(&mut self, v: u32) {
        self.record_many(v, 1);
    }

    /// Counts the value `v` `n` times.
    #[inline]
    pub fn record_many(&mut self, v: u32, n: u64) {
        self.buckets[Self::bucket(v)] += n;
    }

    /// Adds another histogram.
    pub fn add(&mut self, o: &CostHistogram) {
        for (a, b) in self.buckets.iter_mut().zip(&o.buckets) {
            *a += b;
        }
    }

    /// Number of values counted.
    pub fn count(&self) -> u64 {
        self.buckets.iter().sum()
    }

    /// The `q`-quantile (0 ≤ q ≤ 1), as the upper end of its bucket (exact below 32).
    pub fn quantile(&self, q: f64) -> u64 {
        let n = self.count();
        if n == 0 {
            return 0;
        }
        let rank = ((q * n as f64).ceil() as u64).clamp(1, n);
        let mut seen = 0;
        for (b, &c) in self.buckets.iter().enumerate() {
            seen += c;
            if seen >= rank {
                return Self::upper(b);
            }
        }
        Self::upper(BUCKETS - 1)
    }
}

/// Traversal work of the rays of a render: cells visited and primitive tests, per ray.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraversalTally {
    /// Rays recorded.
    pub rays: u64,
    /// Cells visited in all.
    pub cells: u64,
    /// Primitive tests in all.
    pub tests: u64,
    /// Cells per ray.
    pub cells_per_ray: CostHistogram,
    /// Tests per ray.
    pub tests_per_ray: CostHistogram,
}

impl TraversalTally {
    /// Counts one ray's cost.
    #[inline]
    pub fn record(&mut self, cost: crate::store::TraversalCost) {
        self.record_many(cost, 1);
    }

    /// Counts `rays` rays that each cost `cost` (the lanes of a packet, its cost shared out):
    /// the same tally as that many [`Self::record`] calls.
    #[inline]
    pub fn record_many(&mut self, cost: crate::store::TraversalCost, rays: u64) {
        self.rays += rays;
        self.cells += u64::from(cost.cells) * rays;
        self.tests += u64::from(cost.tests) * rays;
        self.cells_per_ray.record_many(cost.cells, rays);
        self.tests_per_ray.record_many(cost.tests, rays);
    }

    /// Adds another tally.
    pub fn add(&mut self, o: &TraversalTally) {
        self.rays += o.rays;
        self.cells += o.cells;
        self.tests += o.tests;
        self.cells_per_ray.add(&o.cells_per_ray);
        self.tests_per_ray.add(&o.tests_per_ray);
    }

    /// Mean, p99 and max-bucket figures for the statistics.
    pub fn summary(&self) -> TraversalStats {
        let mean = |sum: u64| if self.rays == 0 { 0.0 } else { sum as f64 / self.rays as f64 };
        TraversalStats {
            rays: self.rays,
            cells_mean: mean(self.cells),
            cells_p99: self.cells_per_ray.quantile(0.99),
            tests_mean: mean(self.tests),
            tests_p99: self.tests_per_ray.quantile(0.99),
        }
    }
}

/// Per-ray traversal figures: mean and 99th percentile of cells visited and primitive tests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct TraversalStats {
    /// Rays these figures cover (every traced ray except AOV probes).
    pub rays: u64,
    /// Mean cells visited per ray (both grid levels).
    pub cells_mean: f64,
    /// 99th percentile of cells visited per ray (upper end of its histogram bucket).
    pub cells_p99: u64,
    /// Mean primitive tests per ray (objects and triangles).
    pub tests_mean: f64,
    /// 99th percentile of primitive tests per ray.
    pub tests_p99: u64,
}
