//! The scene file's lights.

use super::*;

/// A light source.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum LightDesc {
    /// A point light, by default with no distance falloff (as in classic Phong and POV-Ray).
    Point {
        /// Position.
        position: DVec3,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// `None` or `InverseSquare` (colour × intensity arrives one unit away). Default `None`.
        #[serde(default)]
        falloff: Falloff,
    },
    /// A spot light: a point light shining into a cone, with a soft edge.
    Spot {
        /// Position.
        position: DVec3,
        /// The point the cone's axis aims at; must differ from `position`.
        look_at: DVec3,
        /// Half-angle of the cone in degrees, in (0, 90]: no light outside it.
        cone_deg: f32,
        /// Width of the soft edge in degrees, in [0, cone_deg]: the light fades smoothly from
        /// full at `cone_deg − soft_deg` to nothing at `cone_deg`. Default 5 (at most `cone_deg`).
        #[serde(default)]
        soft_deg: Option<f32>,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// `None` or `InverseSquare`. Default `None`.
        #[serde(default)]
        falloff: Falloff,
    },
    /// A light infinitely far away, shining along `direction`.
    Directional {
        /// Direction the light travels in (from the light towards the scene); non-zero.
        direction: Vec3,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
    },
    /// A parallelogram area light `corner + s·edge_u + t·edge_v` (s, t in [0, 1]), emitting
    /// to both sides, invisible to camera rays unless `visible`; colour × intensity is spread over the samples.
    Rect {
        /// One corner.
        corner: DVec3,
        /// First edge from `corner`; non-zero.
        edge_u: Vec3,
        /// Second edge from `corner`; non-zero and not parallel to `edge_u`.
        edge_v: Vec3,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// Shadow rays per shading point, 1..=4096. Default 16.
        #[serde(default = "default_light_samples")]
        samples: u32,
        /// Placement of the samples over the light. Default `Jittered`.
        #[serde(default)]
        pattern: Pattern,
        /// `None` or `InverseSquare`, from each sample's point. Default `None`.
        #[serde(default)]
        falloff: Falloff,
        /// Whether camera, reflection and refraction rays see the light (it shows colour ×
        /// intensity, from both sides); it never casts a shadow. Default false.
        #[serde(default)]
        visible: bool,
    },
    /// A disk area light, emitting to both sides, invisible to camera rays unless `visible`; colour ×
    /// intensity is spread over the samples.
    Disk {
        /// Centre.
        centre: DVec3,
        /// Normal of the disk's plane; non-zero.
        normal: Vec3,
        /// Radius, > 0.
        radius: f32,
        /// Linear RGB colour, each channel ≥ 0. Default white.
        #[serde(default = "default_colour")]
        colour: Vec3,
        /// Scale of the colour, ≥ 0. Default 1.
        #[serde(default = "default_intensity")]
        intensity: f32,
        /// Shadow rays per shading point, 1..=4096. Default 16.
        #[serde(default = "default_light_samples")]
        samples: u32,
        /// Placement of the samples over the light. Default `Jittered`.
        #[serde(default)]
        pattern: Pattern,
        /// `None` or `InverseSquare`, from each sample's point. Default `None`.
        #[serde(default)]
        falloff: Falloff,
        /// Whether camera, reflection and refraction rays see the light (it shows colour ×
        /// intensity, from both sides); it never casts a shadow. Default false.
        #[serde(default)]
        visible: bool,
    },
}

impl LightDesc {
    /// The light's colour and intensity (its radiance is their product).
    pub fn terms(&self) -> (Vec3, f32) {
        match *self {
            LightDesc::Point { colour, intensity, .. }
            | LightDesc::Spot { colour, intensity, .. }
            | LightDesc::Directional { colour, intensity, .. }
            | LightDesc::Rect { colour, intensity, .. }
            | LightDesc::Disk { colour, intensity, .. } => (colour, intensity),
        }
    }
}
