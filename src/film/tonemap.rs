//! Tone mapping: from linear scene radiance to display values in [0, 1], before sRGB encoding.
//! Exposure (in stops) scales first; then one operator: clamp, Reinhard with a white point, or
//! an ACES-fitted filmic curve. Only 8- and 16-bit outputs are tone-mapped; EXR stays linear.

use serde::Deserialize;

/// The curve that maps exposed linear values into [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
pub enum ToneOperator {
    /// `min(x, 1)`.
    #[default]
    Clamp,
    /// Extended Reinhard: `x (1 + x / w²) / (1 + x)`, reaching 1 at the white point `w`.
    Reinhard,
    /// Narkowicz's fit of the ACES filmic curve.
    Aces,
}

/// Exposure and operator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToneMapping {
    /// The operator.
    pub operator: ToneOperator,
    /// Exposure in stops: linear values are multiplied by `2^exposure` first.
    pub exposure: f32,
    /// White point of `Reinhard` (the exposed value that maps to 1), > 0.
    pub white: f32,
}

impl Default for ToneMapping {
    fn default() -> Self {
        Self { operator: ToneOperator::Clamp, exposure: 0.0, white: 4.0 }
    }
}
