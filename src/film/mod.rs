//! The film: a linear-light RGB image ([`Film`]), and its encoding to files.
//!
//! This module owns the display transform ([`tonemap`]: exposure, the tone operators and the
//! sRGB curve), the arbitrary output variables ([`aov`]), writing images atomically in every
//! output format ([`output`]: 8- and 16-bit PNG, half and float EXR, each with its
//! provenance [`metadata`]), reading PNGs back in linear light ([`png_read`]) and the image
//! metrics reports compare with ([`metrics`]: RMSE, PSNR, SSIM, error heat maps). It depends
//! on nothing above it: the tracer hands it pixels, the command line hands it paths.

pub mod aov;
mod aov_png;
mod exr_io;
mod format;
pub mod metadata;
pub mod metrics;
pub mod output;
mod png_io;
pub mod png_read;
pub mod tonemap;

pub use aov::{AovSet, Aovs};
pub use metadata::Metadata;
pub use metrics::{error_heatmap, luminance_srgb, psnr, rmse, ssim, ssim_map};
pub use output::{
    prepare_output, read_exr, read_metadata, write_atomically, write_image, write_image_with, write_png,
    OutputError, OutputFormat, PngCompression,
};
pub use png_read::{read_png_linear, LinearPng};
pub use tonemap::{encode_srgb8, linear_to_srgb, srgb_to_linear, tone_map, ToneMapping, ToneOperator};

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
        // Zeroed by the allocator (fresh pages need no writing), not element by element: a
        // frame's film is allocated on the renderer's serial path.
        Self { width, height, pixels: bytemuck::zeroed_vec(width as usize * height as usize) }
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

/// Fixtures shared by the film tests.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::{AovSet, Aovs, Film};
    use crate::math::Vec3;

    /// A deterministic stream of floats in [0, 1) (xorshift32).
    pub(crate) fn unit_floats(seed: u32) -> impl Iterator<Item = f32> {
        let mut x = seed.max(1);
        std::iter::repeat_with(move || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            (x >> 8) as f32 / (1 << 24) as f32
        })
    }

    /// A `w × h` film of values in [0, 20), with exact zeros and some large values mixed in.
    pub(crate) fn random_film(w: u32, h: u32, seed: u32) -> Film {
        let mut r = unit_floats(seed);
        let mut next = move || r.next().unwrap_or(0.0);
        let pixels = (0..w * h)
            .map(|i| match i % 7 {
                0 => Vec3::new(0.0, next() * 20.0, 0.0),
                3 => Vec3::new(next() * 5000.0, next(), next() * 1e-3),
                _ => Vec3::new(next() * 20.0, next() * 20.0, next() * 20.0),
            })
            .collect();
        Film { width: w, height: h, pixels }
    }

    /// All AOVs of a `w × h` image: background (depth +∞, id 0) on every fifth pixel.
    pub(crate) fn random_aovs(w: u32, h: u32, seed: u32) -> Aovs {
        let set = AovSet { depth: true, normal: true, albedo: true, object: true, cost: true };
        let mut aovs = Aovs::new(set, w, h);
        let mut r = unit_floats(seed);
        let mut next = move || r.next().unwrap_or(0.0);
        for i in 0..(w * h) as usize {
            let hit = i % 5 != 0;
            if hit {
                let n = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize_or(Vec3::Z);
                aovs.depth.as_mut().unwrap()[i] = 0.1 + next() * 100.0;
                aovs.normal.as_mut().unwrap()[i] = n;
                aovs.albedo.as_mut().unwrap()[i] = Vec3::new(next(), next(), next());
                aovs.object.as_mut().unwrap()[i] = 1 + (i as u32 % 3);
            }
            aovs.cost.as_mut().unwrap()[i] = (next() * 300.0) as u32 + 1;
        }
        aovs.object_names = vec!["floor".into(), "ball, red".into(), "Grüße 世界".into()];
        aovs
    }
}
