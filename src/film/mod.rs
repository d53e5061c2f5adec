//! The film: a linear-light RGB image, and its encoding to files.

pub mod aov;
mod aov_png;
mod exr_io;
pub mod metadata;
pub mod metrics;
pub mod output;
mod png_io;
pub mod tonemap;

pub use aov::{AovSet, Aovs};
pub use metadata::Metadata;
pub use metrics::{psnr, rmse};
pub use output::{
    encode_srgb8, linear_to_srgb, read_exr, read_metadata, write_atomically, write_image, write_png,
    OutputError, OutputFormat,
};
pub use tonemap::{tone_map, ToneMapping, ToneOperator};

use crate::math::Vec3;

/// A linear RGB image, row-major from the top-left corner.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear colours.
    pub pixels: Vec<Vec3>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![Vec3::ZERO; width as usize * height as usize] }
    }

    /// The colour at `(x, y)`.
    #[inline]
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Sets the colour at `(x, y)`.
    #[inline]
    pub fn set(&mut self, x: u32, y: u32, c: Vec3) {
        self.pixels[(y * self.width + x) as usize] = c;
    }
}
