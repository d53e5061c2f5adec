//! The settings a sweep's axes expand to, as variants: their labels and parameters for tables
//! and plots, and the scene each one renders.

use super::set_area_samples;
use crate::sample::Pattern;
use crate::scene::{AdaptiveSettings, NoiseSettings, SceneDesc};

/// One setting of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Setting {
    /// AA samples and pattern (adaptive off).
    Aa(u32, Pattern),
    /// Adaptive threshold and depth.
    Adaptive(f32, u32),
    /// Area-light samples.
    AreaLight(u32),
    /// Glossy/blurry rays.
    Glossy(u32),
    /// Lens samples.
    Lens(u32),
    /// Time samples.
    Time(u32),
    /// Noise-driven sampling: target error, AA samples per batch, minimum and maximum samples.
    Noise(f32, u32, u32, u32),
}

/// A point of the sweep: its axis and setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variant {
    /// Axis name.
    pub axis: &'static str,
    /// The setting.
    pub setting: Setting,
}

fn pattern_name(p: Pattern) -> &'static str {
    match p {
        Pattern::Grid => "grid",
        Pattern::Random => "random",
        Pattern::Jittered => "jittered",
    }
}

impl Variant {
    /// Label for tables and plots, e.g. `aa 16 jittered` or `area_light 4`: the axis name is
    /// the effect name `penumbra render --samples` takes.
    pub fn label(&self) -> String {
        match self.setting {
            Setting::Aa(n, p) => format!("aa {n} {}", pattern_name(p)),
            Setting::Adaptive(t, d) => format!("adaptive {t}:{d}"),
            Setting::AreaLight(n) => format!("area_light {n}"),
            Setting::Glossy(n) => format!("glossy {n}"),
            Setting::Lens(n) => format!("lens {n}"),
            Setting::Time(n) => format!("time {n}"),
            Setting::Noise(t, ..) => format!("noise {t}"),
        }
    }

    /// Parameter names and values.
    pub fn params(&self) -> Vec<(String, String)> {
        let pair = |k: &str, v: String| (k.to_owned(), v);
        match self.setting {
            Setting::Aa(n, p) => {
                vec![pair("samples", n.to_string()), pair("pattern", pattern_name(p).into())]
            }
            Setting::Adaptive(t, d) => vec![pair("threshold", t.to_string()), pair("depth", d.to_string())],
            Setting::AreaLight(n) | Setting::Glossy(n) | Setting::Lens(n) | Setting::Time(n) => {
                vec![pair("samples", n.to_string())]
            }
            Setting::Noise(t, aa, lo, hi) => vec![
                pair("target_error", t.to_string()),
                pair("aa", aa.to_string()),
                pair("min_samples", lo.to_string()),
                pair("max_samples", hi.to_string()),
            ],
        }
    }

    /// The scene with this setting applied.
    pub fn apply(&self, desc: &SceneDesc) -> SceneDesc {
        let mut d = desc.clone();
        match self.setting {
            Setting::Aa(n, p) => {
                d.settings.aa.samples = n;
                d.settings.aa.pattern = p;
                d.settings.adaptive = None;
                d.settings.noise = None;
            }
            Setting::Adaptive(threshold, max_depth) => {
                d.settings.adaptive = Some(AdaptiveSettings { threshold, max_depth });
                d.settings.noise = None;
            }
            Setting::AreaLight(n) => set_area_samples(&mut d, n),
            Setting::Glossy(n) => d.settings.glossy.samples = n,
            Setting::Lens(n) => d.camera.lens.samples = n,
            Setting::Time(n) => d.camera.time.samples = n,
            Setting::Noise(target_error, aa, min_samples, max_samples) => {
                d.settings.adaptive = None;
                d.settings.aa.samples = aa;
                d.settings.noise = Some(NoiseSettings {
                    target_error,
                    min_samples,
                    max_samples,
                    time_limit: None,
                    rounds: None,
                });
            }
        }
        d
    }
}
