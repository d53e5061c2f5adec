//! The axes of a sweep file (`Aa`, `Adaptive`, `AreaLight`, …): what each varies, its
//! defaults, the variants it expands to and the rules its values must keep.

use serde::Deserialize;

use super::{Setting, Variant};
use crate::sample::Pattern;
use crate::scene::validate::{MAX_ADAPTIVE_DEPTH, MAX_NOISE_SAMPLES, MAX_SAMPLES};

/// One axis of a sweep.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Axis {
    /// Anti-aliasing samples per pixel, for each pattern.
    Aa {
        /// Sample counts.
        samples: Vec<u32>,
        /// Patterns (default: jittered only).
        #[serde(default = "jittered")]
        patterns: Vec<Pattern>,
    },
    /// Adaptive supersampling: every threshold at every depth.
    Adaptive {
        /// Corner thresholds.
        thresholds: Vec<f32>,
        /// Deepest levels (default 3).
        #[serde(default = "depth_3")]
        depths: Vec<u32>,
    },
    /// Shadow samples of every area light.
    AreaLight {
        /// Sample counts.
        samples: Vec<u32>,
    },
    /// Rays per glossy reflection or blurry refraction.
    Glossy {
        /// Sample counts.
        samples: Vec<u32>,
    },
    /// Lens samples per camera sample.
    Lens {
        /// Sample counts.
        samples: Vec<u32>,
    },
    /// Time samples per camera sample (motion blur: the shutter's samples).
    Time {
        /// Sample counts.
        samples: Vec<u32>,
    },
    /// Noise-driven adaptive sampling: every target error, in batches of `aa` AA samples (with
    /// the scene's lens, time and effect samples).
    Noise {
        /// Target errors (display units, 0..1).
        targets: Vec<f32>,
        /// AA samples per batch (default 4; a pixel's samples are stratified across batches
        /// whatever the size, which sets how finely a pixel's count grows and how many effect
        /// samples each camera sample takes).
        #[serde(default = "four")]
        aa: u32,
        /// Camera samples every pixel takes first (default 8).
        #[serde(default = "eight")]
        min_samples: u32,
        /// Camera samples no pixel exceeds (default 4096).
        #[serde(default = "many")]
        max_samples: u32,
    },
}

fn four() -> u32 {
    4
}

fn eight() -> u32 {
    8
}

fn many() -> u32 {
    4096
}

fn jittered() -> Vec<Pattern> {
    vec![Pattern::Jittered]
}

fn depth_3() -> Vec<u32> {
    vec![3]
}

impl Axis {
    /// The axis name in tables and plots.
    pub fn name(&self) -> &'static str {
        match self {
            Axis::Aa { .. } => "aa",
            Axis::Adaptive { .. } => "adaptive",
            Axis::AreaLight { .. } => "area_light",
            Axis::Glossy { .. } => "glossy",
            Axis::Lens { .. } => "lens",
            Axis::Time { .. } => "time",
            Axis::Noise { .. } => "noise",
        }
    }

    /// Every variant of the axis.
    pub fn variants(&self) -> Vec<Variant> {
        let counts =
            |samples: &[u32], make: fn(u32) -> Setting| samples.iter().map(|&n| make(n)).collect::<Vec<_>>();
        let settings = match self {
            Axis::Aa { samples, patterns } => {
                patterns.iter().flat_map(|&p| samples.iter().map(move |&n| Setting::Aa(n, p))).collect()
            }
            Axis::Adaptive { thresholds, depths } => depths
                .iter()
                .flat_map(|&d| thresholds.iter().map(move |&t| Setting::Adaptive(t, d)))
                .collect(),
            Axis::AreaLight { samples } => counts(samples, Setting::AreaLight),
            Axis::Glossy { samples } => counts(samples, Setting::Glossy),
            Axis::Lens { samples } => counts(samples, Setting::Lens),
            Axis::Time { samples } => counts(samples, Setting::Time),
            Axis::Noise { targets, aa, min_samples, max_samples } => {
                targets.iter().map(|&t| Setting::Noise(t, *aa, *min_samples, *max_samples)).collect()
            }
        };
        settings.into_iter().map(|setting| Variant { axis: self.name(), setting }).collect()
    }

    /// The first rule the axis breaks, if any: the field (`samples`, `patterns`, ...) and
    /// the rule. With `samples`, the index of the offending value is in the field.
    pub(super) fn check(&self) -> Result<(), (String, String)> {
        let counts = |samples: &[u32]| -> Result<(), (String, String)> {
            if samples.is_empty() {
                return Err(("samples".into(), "lists no values; give at least one sample count".into()));
            }
            match samples.iter().position(|n| !(1..=MAX_SAMPLES).contains(n)) {
                Some(i) => Err((
                    format!("samples[{i}]"),
                    format!("sample count must be in 1..={MAX_SAMPLES}, got {}", samples[i]),
                )),
                None => Ok(()),
            }
        };
        match self {
            Axis::Aa { samples, patterns } if patterns.is_empty() => {
                counts(samples)?;
                Err(("patterns".into(), "lists no values; give at least one pattern".into()))
            }
            Axis::Aa { samples, .. }
            | Axis::AreaLight { samples }
            | Axis::Glossy { samples }
            | Axis::Lens { samples }
            | Axis::Time { samples } => counts(samples),
            Axis::Noise { targets, aa, min_samples, max_samples } => {
                if targets.is_empty() {
                    return Err(("targets".into(), "lists no values; give at least one target error".into()));
                }
                if let Some(i) = targets.iter().position(|t| !(0.0..=1.0).contains(t)) {
                    return Err((
                        format!("targets[{i}]"),
                        format!("target error must be in [0, 1], got {}", targets[i]),
                    ));
                }
                if !(1..=MAX_SAMPLES).contains(aa) {
                    return Err(("aa".into(), format!("must be in 1..={MAX_SAMPLES}, got {aa}")));
                }
                if !(1..=MAX_NOISE_SAMPLES).contains(min_samples) {
                    return Err((
                        "min_samples".into(),
                        format!("must be in 1..={MAX_NOISE_SAMPLES}, got {min_samples}"),
                    ));
                }
                if !(*min_samples..=MAX_NOISE_SAMPLES).contains(max_samples) {
                    let rule = format!("must be in min_samples..={MAX_NOISE_SAMPLES}, got {max_samples}");
                    return Err(("max_samples".into(), rule));
                }
                Ok(())
            }
            Axis::Adaptive { thresholds, depths } => {
                if thresholds.is_empty() {
                    return Err(("thresholds".into(), "lists no values; give at least one threshold".into()));
                }
                if depths.is_empty() {
                    return Err(("depths".into(), "lists no values; give at least one depth".into()));
                }
                if let Some(i) = thresholds.iter().position(|t| !(t.is_finite() && *t >= 0.0)) {
                    return Err((
                        format!("thresholds[{i}]"),
                        format!("threshold must be finite and >= 0, got {}", thresholds[i]),
                    ));
                }
                match depths.iter().position(|d| !(1..=MAX_ADAPTIVE_DEPTH).contains(d)) {
                    Some(i) => Err((
                        format!("depths[{i}]"),
                        format!("depth must be in 1..={MAX_ADAPTIVE_DEPTH}, got {}", depths[i]),
                    )),
                    None => Ok(()),
                }
            }
        }
    }
}
