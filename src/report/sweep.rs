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
//!
//! `axis` holds the axes of a sweep file and their rules, `variant` the settings they expand to
//! and how each is applied to a scene, `reference_settings` how the reference is rendered.

mod axis;
mod reference_settings;
mod variant;

use std::path::{Path, PathBuf};

use serde::Deserialize;

pub use self::axis::Axis;
pub use self::reference_settings::ReferenceSettings;
pub use self::variant::{Setting, Variant};
use crate::sample::adaptive::AdaptiveSettings;
use crate::sample::Pattern;
use crate::scene::locate::{path_at, position_of, FieldPath};
use crate::scene::validate::MAX_SAMPLES;
use crate::scene::{LightDesc, SceneDesc};
use crate::trace::Effects;

/// Why a sweep file could not be loaded; displays like a scene error,
/// ``file:line:col: field `axes[0].samples[1]`: rule``.
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

/// Sets the samples of every area light (rect and disk) to `n`.
fn set_area_samples(d: &mut SceneDesc, n: u32) {
    for light in &mut d.lights {
        if let LightDesc::Rect { samples, .. } | LightDesc::Disk { samples, .. } = light {
            *samples = n;
        }
    }
}

#[cfg(test)]
mod tests;
