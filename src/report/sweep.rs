//! What a report sweeps: axes of sample counts (and AA patterns, adaptive thresholds), the
//! reference's settings and the runs per point, from a RON file or chosen for the scene.
//!
//! ```ron
//! Sweep(
//!     axes: [
//!         Aa(samples: [1, 4, 16, 64], patterns: [Grid, Random, Jittered]),
//!         Adaptive(thresholds: [0.2, 0.05, 0.02], depths: [3]),
//!         AreaLight(samples: [1, 4, 16, 64]),
//!         Glossy(samples: [1, 4, 16, 64]),
//!         Lens(samples: [1, 4, 16]),
//!         Time(samples: [1, 2, 4, 8]),
//!     ],
//!     reference: (aa: 64, lens: 16, area_light: 256, glossy: 256, time: 4),
//! )
//! ```
//!
//! While one axis varies, every other effect keeps the scene's own setting: each curve shows
//! what that one sample count buys in the image a user would ship. `Time` is the shutter's
//! samples (`camera.time.samples`, time samples per camera sample); it changes the image only
//! where something moves while the shutter is open, which takes a script (`penumbra report
//! --script`).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::sample::adaptive::AdaptiveSettings;
use crate::sample::Pattern;
use crate::scene::locate::{path_at, position_of, FieldPath};
use crate::scene::validate::{MAX_ADAPTIVE_DEPTH, MAX_NOISE_SAMPLES, MAX_SAMPLES};
use crate::scene::{AdaptiveDesc, LightDesc, NoiseDesc, SceneDesc};
use crate::trace::Effects;

/// Why a sweep file could not be loaded; displays like a scene error,
/// `file:line:col: field `axes[0].samples[1]`: rule`.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The sweep file could not be read.
    #[error("{}: cannot read sweep: {source}", path.display())]
    Io {
        /// The path as given.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The sweep text is malformed or breaks a rule.
    #[error("{path}:{line}:{col}: field `{field}`: {rule}")]
    Invalid {
        /// Where the text came from.
        path: String,
        /// 1-based line of the offending value.
        line: usize,
        /// 1-based column of the offending value.
        col: usize,
        /// The field, e.g. `axes[0].samples[1]`.
        field: String,
        /// What is wrong and what is allowed.
        rule: String,
    },
}

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
        /// AA samples per batch (default 4: a stratified batch; one sample per batch gives up
        /// stratification and measured 2-3x worse).
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
    fn check(&self) -> Result<(), (String, String)> {
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
                d.settings.adaptive = Some(AdaptiveDesc { threshold, max_depth });
                d.settings.noise = None;
            }
            Setting::AreaLight(n) => set_area_samples(&mut d, n),
            Setting::Glossy(n) => d.settings.glossy.samples = n,
            Setting::Lens(n) => d.camera.lens.samples = n,
            Setting::Time(n) => d.camera.time.samples = n,
            Setting::Noise(target_error, aa, min_samples, max_samples) => {
                d.settings.adaptive = None;
                d.settings.aa.samples = aa;
                d.settings.noise =
                    Some(NoiseDesc { target_error, min_samples, max_samples, time_limit: None });
            }
        }
        d
    }
}

fn set_area_samples(d: &mut SceneDesc, n: u32) {
    for light in &mut d.lights {
        if let LightDesc::Rect { samples, .. } | LightDesc::Disk { samples, .. } = light {
            *samples = n;
        }
    }
}

/// How the reference is rendered: every effect's sample count, far above the sweep's.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ReferenceSettings {
    /// AA samples (jittered, box or the scene's filter; adaptive off).
    pub aa: u32,
    /// Lens samples per camera sample (with an aperture).
    pub lens: u32,
    /// Area-light samples.
    pub area_light: u32,
    /// Glossy/blurry rays.
    pub glossy: u32,
    /// Time samples per camera sample (where something moves).
    pub time: u32,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        Self { aa: 64, lens: 16, area_light: 256, glossy: 256, time: 4 }
    }
}

impl ReferenceSettings {
    /// The scene as the reference renders it.
    pub fn apply(&self, desc: &SceneDesc) -> SceneDesc {
        let mut d = desc.clone();
        d.settings.aa.samples = self.aa;
        d.settings.aa.pattern = Pattern::Jittered;
        d.settings.adaptive = None;
        d.settings.noise = None;
        d.camera.lens.samples = self.lens;
        d.settings.glossy.samples = self.glossy;
        d.camera.time.samples = self.time;
        d.camera.time.pattern = Pattern::Jittered;
        set_area_samples(&mut d, self.area_light);
        d
    }

    /// `aa 64 jittered, lens 16, area_light 256, …`, naming only the effects the scene uses.
    pub fn describe(&self, effects: &Effects) -> String {
        let mut parts = vec![format!("aa {} jittered", self.aa)];
        if effects.lens {
            parts.push(format!("lens {}", self.lens));
        }
        if effects.area_lights {
            parts.push(format!("area_light {}", self.area_light));
        }
        if effects.glossy || effects.blurry {
            parts.push(format!("glossy {}", self.glossy));
        }
        if effects.motion {
            parts.push(format!("time {}", self.time));
        }
        parts.join(", ")
    }
}

/// A whole sweep.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename = "Sweep", deny_unknown_fields)]
pub struct SweepDesc {
    /// The axes, in order.
    pub axes: Vec<Axis>,
    /// The reference's settings.
    #[serde(default)]
    pub reference: ReferenceSettings,
}

/// Sample counts the default sweep tries (and, for noise-driven sampling, target errors).
const COUNTS: [u32; 4] = [1, 4, 16, 64];

impl SweepDesc {
    /// The sweep a scene with `effects` calls for: AA (three patterns) and adaptive always;
    /// area-light, glossy, lens and time samples only when the scene has area lights, glossy
    /// or blurry materials, an aperture, or something moving while the shutter is open.
    pub fn default_for(effects: &Effects) -> Self {
        let mut axes = vec![
            Axis::Aa {
                samples: COUNTS.to_vec(),
                patterns: vec![Pattern::Grid, Pattern::Random, Pattern::Jittered],
            },
            Axis::Adaptive { thresholds: vec![0.2, 0.1, 0.05, 0.02], depths: vec![3] },
            Axis::Noise { targets: vec![0.04, 0.02, 0.01, 0.005], aa: 4, min_samples: 8, max_samples: 4096 },
        ];
        if effects.area_lights {
            axes.push(Axis::AreaLight { samples: COUNTS.to_vec() });
        }
        if effects.glossy || effects.blurry {
            axes.push(Axis::Glossy { samples: COUNTS.to_vec() });
        }
        if effects.lens {
            axes.push(Axis::Lens { samples: COUNTS.to_vec() });
        }
        if effects.motion {
            axes.push(Axis::Time { samples: vec![1, 2, 4, 8] });
        }
        Self { axes, reference: ReferenceSettings::default() }
    }

    /// Reads a sweep file; errors name the file, line, column, field and rule.
    pub fn load(path: &Path) -> Result<Self, SweepError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| SweepError::Io { path: path.to_path_buf(), source })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses sweep text; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, SweepError> {
        let invalid = |(line, col): (usize, usize), field: String, rule: String| SweepError::Invalid {
            path: origin.to_owned(),
            line,
            col,
            field: if field.is_empty() { "Sweep".to_owned() } else { field },
            rule,
        };
        let at =
            |field: &str| FieldPath::parse(field).and_then(|path| position_of(text, &path)).unwrap_or((1, 1));
        let sweep: SweepDesc = ron::from_str(text).map_err(|e| {
            let (line, col) = (e.span.start.line, e.span.start.col);
            invalid((line, col), path_at(text, line, col).to_string(), e.code.to_string())
        })?;
        if sweep.axes.is_empty() {
            return Err(invalid(at("axes"), "axes".into(), "lists no axis; give at least one".into()));
        }
        for (i, axis) in sweep.axes.iter().enumerate() {
            axis.check().map_err(|(field, rule)| {
                let field = format!("axes[{i}].{field}");
                invalid(at(&field), field, format!("{}: {rule}", axis.name()))
            })?;
        }
        let r = &sweep.reference;
        let counts = [
            ("aa", r.aa),
            ("lens", r.lens),
            ("area_light", r.area_light),
            ("glossy", r.glossy),
            ("time", r.time),
        ];
        for (name, n) in counts {
            if !(1..=MAX_SAMPLES).contains(&n) {
                let field = format!("reference.{name}");
                return Err(invalid(at(&field), field, format!("must be in 1..={MAX_SAMPLES}, got {n}")));
            }
        }
        Ok(sweep)
    }

    /// Every variant, axis by axis.
    pub fn variants(&self) -> Vec<Variant> {
        self.axes.iter().flat_map(Axis::variants).collect()
    }
}

/// The setting an effect's cost is measured with, "off": one sample (or adaptive off; for
/// `time`, no shutter: the cost of motion blur itself).
pub fn cheapest(axis: &str, desc: &SceneDesc) -> Option<SceneDesc> {
    let mut d = desc.clone();
    match axis {
        "aa" => d.settings.aa.samples = 1,
        "adaptive" => d.settings.adaptive = None,
        "area_light" => set_area_samples(&mut d, 1),
        "glossy" => d.settings.glossy.samples = 1,
        "lens" => d.camera.lens.samples = 1,
        "time" => d.camera.shutter = None,
        "noise" => d.settings.noise = None,
        _ => return None,
    }
    Some(d)
}

/// Adaptive settings of a scene, for reports that mention them.
pub fn adaptive_of(desc: &SceneDesc) -> Option<AdaptiveSettings> {
    desc.settings
        .adaptive
        .as_ref()
        .map(|a| AdaptiveSettings { threshold: a.threshold, max_depth: a.max_depth })
}

#[cfg(test)]
mod tests;
