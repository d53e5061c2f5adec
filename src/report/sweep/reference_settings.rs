//! How a sweep's reference is rendered: every effect's sample count, applied to the scene and
//! described for the report.

use serde::Deserialize;

use super::set_area_samples;
use crate::sample::Pattern;
use crate::scene::SceneDesc;
use crate::trace::Effects;

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
