//! Reading PNG images back into linear films: 8- or 16-bit grey or RGB (palette and low-bit
//! grey images expanded to 8 bits, alpha ignored), decoded from sRGB to linear light. What the
//! PNG lost when it was written (values above 1 clamped or tone-mapped, quantisation) stays lost.

use std::io::BufReader;
use std::path::Path;

use png::{BitDepth, ColorType, Decoder, Transformations};

use super::output::OutputError;
use super::tonemap::srgb_to_linear;
use super::Film;
use crate::math::Vec3;

/// A PNG decoded to linear light.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearPng {
    /// The linear film (sRGB decoded; grey images give equal channels).
    pub film: Film,
    /// Bits per sample in the file after expansion: 8 or 16.
    pub bits: u8,
    /// Pixels with a colour channel at the largest code value, which may have been clipped.
    pub saturated: usize,
}

/// Reads an 8- or 16-bit PNG (grey, grey-alpha, RGB, RGBA or palette) as linear light.
pub fn read_png_linear(path: &Path) -> Result<LinearPng, OutputError> {
    let read_error = |message: String| OutputError::Read { path: path.to_path_buf(), message };
    let file = std::fs::File::open(path).map_err(|e| read_error(e.to_string()))?;
    let mut decoder = Decoder::new(BufReader::new(file));
    decoder.set_transformations(Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| read_error(e.to_string()))?;
    let size = reader.output_buffer_size().ok_or_else(|| read_error("image too large".into()))?;
    let mut buf = vec![0u8; size];
    let frame = reader.next_frame(&mut buf).map_err(|e| read_error(e.to_string()))?;
    let channels = match frame.color_type {
        ColorType::Grayscale => 1,
        ColorType::GrayscaleAlpha => 2,
        ColorType::Rgb => 3,
        ColorType::Rgba => 4,
        ColorType::Indexed => return Err(read_error("palette not expanded".into())),
    };
    let (bits, max) = match frame.bit_depth {
        BitDepth::Eight => (8u8, 255u32),
        BitDepth::Sixteen => (16, 65535),
        other => return Err(read_error(format!("unsupported bit depth {other:?}"))),
    };
    let (width, height) = (frame.width, frame.height);
    let bytes_per_sample = usize::from(bits / 8);
    let line = frame.line_size;
    let sample = |row: &[u8], i: usize| -> u32 {
        match bytes_per_sample {
            1 => u32::from(row[i]),
            // PNG stores 16-bit samples big-endian.
            _ => u32::from(u16::from_be_bytes([row[2 * i], row[2 * i + 1]])),
        }
    };
    let mut pixels = Vec::with_capacity(width as usize * height as usize);
    let mut saturated = 0;
    for y in 0..height as usize {
        let row = &buf[y * line..(y + 1) * line];
        for x in 0..width as usize {
            let base = x * channels;
            let codes: [u32; 3] = match channels {
                1 | 2 => [sample(row, base); 3],
                _ => [sample(row, base), sample(row, base + 1), sample(row, base + 2)],
            };
            saturated += usize::from(codes.contains(&max));
            let linear = codes.map(|c| srgb_to_linear(c as f32 / max as f32));
            pixels.push(Vec3::from_array(linear));
        }
    }
    Ok(LinearPng { film: Film { width, height, pixels }, bits, saturated })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::fixtures::random_film;
    use crate::film::{write_image, Metadata, OutputFormat, ToneMapping};

    #[test]
    fn srgb_decoding_inverts_encoding() {
        for i in 0..=1000 {
            let v = i as f32 / 1000.0;
            let back = srgb_to_linear(crate::film::linear_to_srgb(v));
            assert!((back - v).abs() < 1e-5, "{v} -> {back}");
        }
    }

    #[test]
    fn png8_and_png16_read_back_within_their_quantisation() {
        let dir = tempfile::tempdir().unwrap();
        // Values in [0, 1): nothing is clamped.
        let mut film = random_film(7, 5, 3);
        film.pixels.iter_mut().for_each(|p| *p = (*p / 5000.0).min(Vec3::splat(0.999)));
        for (format, bits, tolerance) in [(OutputFormat::Png8, 8, 4e-3), (OutputFormat::Png16, 16, 2e-5)] {
            let path = dir.path().join(format!("{format}.png"));
            write_image(&film, None, &path, format, &ToneMapping::default(), &Metadata::default()).unwrap();
            let png = read_png_linear(&path).unwrap();
            assert_eq!((png.film.width, png.film.height, png.bits), (7, 5, bits));
            assert_eq!(png.saturated, 0);
            let worst = film
                .pixels
                .iter()
                .zip(&png.film.pixels)
                .map(|(a, b)| (*a - *b).abs().max_element())
                .fold(0.0, f32::max);
            assert!(worst < tolerance, "{format}: worst error {worst}");
        }
    }

    #[test]
    fn clipped_pixels_are_counted_and_non_pngs_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let film = Film { width: 2, height: 1, pixels: vec![Vec3::splat(3.0), Vec3::splat(0.5)] };
        write_image(&film, None, &path, OutputFormat::Png8, &ToneMapping::default(), &Metadata::default())
            .unwrap();
        assert_eq!(read_png_linear(&path).unwrap().saturated, 1);
        std::fs::write(&path, b"not a png").unwrap();
        let e = read_png_linear(&path).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{}: cannot read image", path.display())), "{e}");
    }
}
