//! The per-camera-sample budget of secondary rays: the per-worker tally and the frame's figures.

use serde::Serialize;

/// Per-worker figures of the secondary-ray budget, summed over camera samples.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BudgetTally {
    /// Camera samples whose ray tree the budget cut (at least one ray refused).
    pub cut_samples: u64,
    /// Secondary rays refused, over all camera samples.
    pub refused_rays: u64,
    /// Most secondary rays one camera sample traced.
    pub max_per_sample: u32,
}

impl BudgetTally {
    /// Counts one camera sample that traced `traced` secondary rays and was refused `refused`.
    #[inline]
    pub fn record(&mut self, traced: u32, refused: u32) {
        self.cut_samples += u64::from(refused > 0);
        self.refused_rays += u64::from(refused);
        self.max_per_sample = self.max_per_sample.max(traced);
    }

    /// Adds another tally.
    pub fn add(&mut self, o: &BudgetTally) {
        self.cut_samples += o.cut_samples;
        self.refused_rays += o.refused_rays;
        self.max_per_sample = self.max_per_sample.max(o.max_per_sample);
    }
}

/// What the per-camera-sample budget of secondary rays did in a frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct BudgetStats {
    /// The budget: secondary rays (reflection, refraction, glossy, blurry) one camera sample may trace.
    pub max_secondary_rays: u32,
    /// Camera samples whose ray tree the budget cut (0 means no pixel was changed by it).
    pub cut_samples: u64,
    /// Secondary rays refused, over all camera samples.
    pub refused_rays: u64,
    /// Most secondary rays one camera sample traced.
    pub max_per_sample: u32,
}

impl BudgetStats {
    /// The frame's figures from the budget `limit` and the summed `tally`.
    pub fn new(limit: u32, tally: &BudgetTally) -> Self {
        Self {
            max_secondary_rays: limit,
            cut_samples: tally.cut_samples,
            refused_rays: tally.refused_rays,
            max_per_sample: tally.max_per_sample,
        }
    }
}
