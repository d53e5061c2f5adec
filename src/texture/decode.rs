//! Reading image files into a [`Raster`]: PNG and JPEG through `image` (8- or 16-bit, grey or
//! colour, alpha ignored, sRGB-decoded unless told the values are linear) and OpenEXR through
//! `exr` (always linear, alpha ignored). The format follows the file's extension.

use std::path::Path;

use exr::prelude::{ReadChannels as _, ReadLayers as _};
use image::{DynamicImage, ImageFormat};

use super::raster::{ColourSpace, Raster, TextureError};
use crate::math::Vec3;

/// The file formats a texture can be read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Png,
    Jpeg,
    Exr,
}

impl Format {
    /// The format named by `name`'s extension, case-insensitive.
    fn from_name(name: &Path) -> Result<Self, TextureError> {
        let extension = name.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
        match extension.to_ascii_lowercase().as_str() {
            "png" => Ok(Self::Png),
            "jpg" | "jpeg" => Ok(Self::Jpeg),
            "exr" => Ok(Self::Exr),
            _ => Err(TextureError::UnsupportedExtension { extension }),
        }
    }
}

impl Raster {
    /// Loads PNG or JPEG (sRGB-decoded unless `space` is Linear) or EXR (always linear), chosen
    /// by the file's extension, case-insensitive.
    pub fn load(path: &Path, space: ColourSpace) -> Result<Raster, TextureError> {
        let format = Format::from_name(path)?;
        let bytes = std::fs::read(path)?;
        decode_as(format, &bytes, space)
    }

    /// Same as [`Raster::load`], from bytes already read; `name` gives the format (extension).
    ///
    /// # Examples
    /// ```
    /// # use penumbra::texture::{ColourSpace, Raster};
    /// let err = Raster::decode("wood.tga".as_ref(), &[], ColourSpace::Srgb).unwrap_err();
    /// assert!(err.to_string().contains("tga"));
    /// ```
    pub fn decode(name: &Path, bytes: &[u8], space: ColourSpace) -> Result<Raster, TextureError> {
        decode_as(Format::from_name(name)?, bytes, space)
    }
}

/// Decodes `bytes` as `format`.
fn decode_as(format: Format, bytes: &[u8], space: ColourSpace) -> Result<Raster, TextureError> {
    match format {
        Format::Png => decode_ldr(bytes, ImageFormat::Png, "PNG", space),
        Format::Jpeg => decode_ldr(bytes, ImageFormat::Jpeg, "JPEG", space),
        Format::Exr => decode_exr(bytes),
    }
}

/// A decoder's message as a one-line [`TextureError::Decode`].
fn decode_error(format: &'static str, reason: impl std::fmt::Display) -> TextureError {
    let reason = reason.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
    TextureError::Decode { format, reason }
}

/// PNG or JPEG through `image`: 8-bit images through a 256-entry table, deeper ones per value.
fn decode_ldr(
    bytes: &[u8],
    format: ImageFormat,
    label: &'static str,
    space: ColourSpace,
) -> Result<Raster, TextureError> {
    let img = image::load_from_memory_with_format(bytes, format).map_err(|e| decode_error(label, e))?;
    let (width, height) = (img.width(), img.height());
    let texels: Vec<Vec3> = match img {
        DynamicImage::ImageLuma8(_)
        | DynamicImage::ImageLumaA8(_)
        | DynamicImage::ImageRgb8(_)
        | DynamicImage::ImageRgba8(_) => {
            let table = table8(space);
            let lookup = |c: u8| table[usize::from(c)];
            img.into_rgb8().pixels().map(|p| Vec3::new(lookup(p[0]), lookup(p[1]), lookup(p[2]))).collect()
        }
        _ => {
            let lookup = |c: u16| to_linear(f64::from(c) / 65535.0, space) as f32;
            img.into_rgb16().pixels().map(|p| Vec3::new(lookup(p[0]), lookup(p[1]), lookup(p[2]))).collect()
        }
    };
    Raster::new(width, height, texels)
}

/// The linear value of an encoded value `c` in [0, 1].
fn to_linear(c: f64, space: ColourSpace) -> f64 {
    match space {
        ColourSpace::Linear => c,
        ColourSpace::Srgb => srgb_to_linear(c),
    }
}

/// The exact piecewise IEC 61966-2-1 sRGB decoding curve.
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear values of the 256 8-bit codes.
fn table8(space: ColourSpace) -> [f32; 256] {
    std::array::from_fn(|i| to_linear(i as f64 / 255.0, space) as f32)
}

/// OpenEXR through `exr`: the first layer with R, G and B channels, at full resolution.
fn decode_exr(bytes: &[u8]) -> Result<Raster, TextureError> {
    /// Row-major texels and the row length.
    type Pixels = (usize, Vec<Vec3>);
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size: exr::math::Vec2<usize>, _: &exr::image::RgbChannels| -> Pixels {
                (size.width(), vec![Vec3::ZERO; size.area()])
            },
            |(row, texels): &mut Pixels, at: exr::math::Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                if let Some(t) = texels.get_mut(at.y() * *row + at.x()) {
                    *t = Vec3::new(r, g, b);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| decode_error("EXR", e))?;
    let size = image.layer_data.size;
    let too_big = || decode_error("EXR", format!("image of {}x{} texels is too large", size.x(), size.y()));
    let width = u32::try_from(size.width()).map_err(|_| too_big())?;
    let height = u32::try_from(size.height()).map_err(|_| too_big())?;
    Raster::new(width, height, image.layer_data.channel_data.pixels.1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::codecs::jpeg::JpegEncoder;
    use image::codecs::png::PngEncoder;
    use image::{ExtendedColorType, ImageEncoder};

    fn png(width: u32, height: u32, data: &[u8], colour: ExtendedColorType) -> Vec<u8> {
        let mut out = Vec::new();
        PngEncoder::new(&mut out).write_image(data, width, height, colour).unwrap();
        out
    }

    fn near(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }

    #[test]
    fn srgb_table_matches_the_iec_curve() {
        let t = table8(ColourSpace::Srgb);
        assert_eq!(t[0], 0.0);
        assert_eq!(t[255], 1.0);
        let low = 10.0 / 255.0 / 12.92;
        assert!((f64::from(t[10]) - low).abs() < 1e-6, "{}", t[10]);
        let mid = ((128.0 / 255.0 + 0.055) / 1.055_f64).powf(2.4);
        assert!((f64::from(t[128]) - mid).abs() < 1e-6, "{}", t[128]);
        assert!((t[128] - 0.2158605).abs() < 1e-6, "{}", t[128]);
        let lin = table8(ColourSpace::Linear);
        for i in [0usize, 1, 10, 128, 200, 255] {
            assert_eq!(lin[i], (i as f64 / 255.0) as f32);
        }
    }

    #[test]
    fn decodes_an_rgb_png() {
        // 2×1: pure red (sRGB 255,0,0) and grey 128.
        let bytes = png(2, 1, &[255, 0, 0, 128, 128, 128], ExtendedColorType::Rgb8);
        let r = Raster::decode(Path::new("a.PNG"), &bytes, ColourSpace::Srgb).unwrap();
        assert_eq!((r.width(), r.height()), (2, 1));
        assert_eq!(r.texel(0, 0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(r.texel(1, 0), Vec3::splat(table8(ColourSpace::Srgb)[128]));
        let r = Raster::decode(Path::new("a.png"), &bytes, ColourSpace::Linear).unwrap();
        assert_eq!(r.texel(1, 0), Vec3::splat((128.0f64 / 255.0) as f32));
    }

    #[test]
    fn decodes_grey_alpha_and_16_bit_pngs() {
        // Grey + alpha: alpha ignored, grey copied to all channels; rows top to bottom.
        let bytes = png(1, 2, &[255, 0, 10, 255], ExtendedColorType::La8);
        let r = Raster::decode(Path::new("g.png"), &bytes, ColourSpace::Srgb).unwrap();
        assert_eq!(r.texel(0, 0), Vec3::ONE);
        assert_eq!(r.texel(0, 1), Vec3::splat((10.0f64 / 255.0 / 12.92) as f32));
        // RGBA with zero alpha keeps its colour.
        let bytes = png(1, 1, &[0, 255, 0, 0], ExtendedColorType::Rgba8);
        let r = Raster::decode(Path::new("g.png"), &bytes, ColourSpace::Linear).unwrap();
        assert_eq!(r.texel(0, 0), Vec3::new(0.0, 1.0, 0.0));
        // 16-bit RGB: the encoder takes native-endian u16 samples.
        let samples: [u16; 3] = [65535, 32768, 0];
        let data: Vec<u8> = samples.iter().flat_map(|s| s.to_ne_bytes()).collect();
        let bytes = png(1, 1, &data, ExtendedColorType::Rgb16);
        let r = Raster::decode(Path::new("d.png"), &bytes, ColourSpace::Srgb).unwrap();
        let mid = srgb_to_linear(32768.0 / 65535.0) as f32;
        assert_eq!(r.texel(0, 0), Vec3::new(1.0, mid, 0.0));
    }

    #[test]
    fn decodes_a_jpeg_approximately() {
        // 8×8 flat colour survives JPEG at quality 100 to within a few codes.
        let data: Vec<u8> = std::iter::repeat_n([200u8, 100, 50], 64).flatten().collect();
        let mut bytes = Vec::new();
        JpegEncoder::new_with_quality(&mut bytes, 100)
            .write_image(&data, 8, 8, ExtendedColorType::Rgb8)
            .unwrap();
        let r = Raster::decode(Path::new("x.JpG"), &bytes, ColourSpace::Linear).unwrap();
        assert_eq!((r.width(), r.height()), (8, 8));
        let want = Vec3::new(200.0, 100.0, 50.0) / 255.0;
        assert!(near(r.texel(3, 4), want, 4.0 / 255.0), "{}", r.texel(3, 4));
        let r = Raster::decode(Path::new("x.jpeg"), &bytes, ColourSpace::Srgb).unwrap();
        let want = Vec3::new(0.577_580, 0.127_438, 0.031_896);
        assert!(near(r.texel(3, 4), want, 0.02), "{}", r.texel(3, 4));
    }

    #[test]
    fn loads_an_exr_file_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.exr");
        let value = |x: usize, y: usize| (x as f32 * 0.5 + 2.0, y as f32 * 10.0, 7.25_f32, 0.0_f32);
        exr::prelude::write_rgba_file(&path, 3, 2, value).unwrap();
        let r = Raster::load(&path, ColourSpace::Srgb).unwrap();
        assert_eq!((r.width(), r.height()), (3, 2));
        for (x, y) in [(0u32, 0u32), (2, 0), (1, 1), (2, 1)] {
            let (a, b, c, _) = value(x as usize, y as usize);
            assert_eq!(r.texel(x, y), Vec3::new(a, b, c), "({x}, {y})");
        }
    }

    #[test]
    fn exr_with_a_nan_texel_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nan.exr");
        exr::prelude::write_rgb_file(&path, 2, 2, |x, y| {
            (if (x, y) == (1, 1) { f32::NAN } else { 1.0 }, 0.0_f32, 0.0_f32)
        })
        .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let err = Raster::decode(&path, &bytes, ColourSpace::Linear).unwrap_err();
        assert!(matches!(err, TextureError::NonFinite { x: 1, y: 1 }), "{err:?}");
    }

    #[test]
    fn unsupported_extension_is_an_error() {
        for name in ["wood.tga", "wood", "wood.png.bak"] {
            let err = Raster::decode(Path::new(name), b"", ColourSpace::Srgb).unwrap_err();
            assert!(matches!(err, TextureError::UnsupportedExtension { .. }), "{err:?}");
            let msg = err.to_string();
            assert!(msg.starts_with("unsupported texture extension"), "{msg}");
            assert!(msg.contains(".png, .jpg, .jpeg or .exr"), "{msg}");
        }
        let err = Raster::decode(Path::new("wood.TGA"), b"", ColourSpace::Srgb).unwrap_err();
        assert!(err.to_string().contains("`TGA`"), "{err}");
        // load checks the extension before touching the file system.
        let err = Raster::load(Path::new("/no/such/dir/x.bmp"), ColourSpace::Srgb).unwrap_err();
        assert!(matches!(err, TextureError::UnsupportedExtension { .. }), "{err:?}");
    }

    #[test]
    fn corrupt_bytes_and_missing_files_are_errors() {
        let junk = b"definitely not an image file";
        for (name, label) in [("a.png", "PNG"), ("a.jpg", "JPEG"), ("a.exr", "EXR")] {
            let err = Raster::decode(Path::new(name), junk, ColourSpace::Srgb).unwrap_err();
            let msg = err.to_string();
            assert!(matches!(err, TextureError::Decode { .. }), "{err:?}");
            assert!(msg.starts_with(&format!("cannot decode {label}: ")), "{msg}");
            assert!(!msg.contains('\n') && msg.len() > label.len() + 16, "{msg}");
        }
        // A truncated PNG.
        let bytes = png(2, 1, &[1, 2, 3, 4, 5, 6], ExtendedColorType::Rgb8);
        let err =
            Raster::decode(Path::new("a.png"), &bytes[..bytes.len() / 2], ColourSpace::Srgb).unwrap_err();
        assert!(matches!(err, TextureError::Decode { format: "PNG", .. }), "{err:?}");
        let dir = tempfile::tempdir().unwrap();
        let err = Raster::load(&dir.path().join("missing.png"), ColourSpace::Srgb).unwrap_err();
        assert!(matches!(err, TextureError::Read(_)), "{err:?}");
        assert!(err.to_string().starts_with("cannot read texture file: "), "{err}");
    }
}
