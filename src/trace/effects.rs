//! The effects a snapshot needs, derived once from its materials, lights and camera, so the
//! integrator's code for an absent effect never runs.

use super::light::Light;
use super::material::Material;
use crate::camera::Camera;

/// Scene-level effects present in a snapshot. (Image-level ones, anti-aliasing and adaptive
/// supersampling, come from `RenderSettings`.)
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Effects {
    /// Some material is a sharp mirror (kr > 0, glossiness 0).
    pub reflection: bool,
    /// Some material reflects glossily (kr > 0, glossiness > 0).
    pub glossy: bool,
    /// Some material transmits (kt > 0): shadow rays must accumulate transmittance.
    pub transmission: bool,
    /// Some material refracts blurrily (kt > 0, glossiness > 0).
    pub blurry: bool,
    /// Some light has an area (soft shadows).
    pub area_lights: bool,
    /// The camera has a finite aperture (depth of field).
    pub lens: bool,
    /// Something moves while the shutter is open (motion blur): camera samples carry a time.
    pub motion: bool,
    /// Some area light is visible to camera, reflection and refraction rays.
    pub visible_lights: bool,
    /// Some material has a texture.
    pub textures: bool,
}

impl Effects {
    /// Names of the effects present, for reports (`reflection`, `glossy`, …).
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.reflection, "reflection"),
            (self.glossy, "glossy"),
            (self.transmission, "transmission"),
            (self.blurry, "blurry"),
            (self.area_lights, "area_lights"),
            (self.lens, "lens"),
            (self.motion, "motion"),
            (self.visible_lights, "visible_lights"),
            (self.textures, "textures"),
        ]
        .iter()
        .filter_map(|&(on, name)| on.then_some(name))
        .collect()
    }

    /// The effects of a scene.
    pub fn of(materials: &[Material], lights: &[Light], camera: &Camera) -> Self {
        let any = |f: fn(&Material) -> bool| materials.iter().any(f);
        Self {
            reflection: any(|m| m.reflects() && m.glossiness == 0.0),
            glossy: any(|m| m.reflects() && m.glossiness > 0.0),
            transmission: any(|m| m.transmits()),
            blurry: any(|m| m.transmits() && m.glossiness > 0.0),
            area_lights: lights.iter().any(Light::is_area),
            lens: camera.has_lens(),
            motion: false,
            visible_lights: lights.iter().any(Light::is_visible),
            textures: any(|m| !m.maps.is_empty()),
        }
    }
}
