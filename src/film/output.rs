//! Writing films: sRGB encoding and atomic PNG output (temporary file in the target folder,
//! then rename), so a crash never leaves a half-written image behind.

use std::io::Write;
use std::path::{Path, PathBuf};

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};

use super::Film;

/// Failure to write an output file.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file (or its temporary sibling) could not be created, written or renamed.
    #[error("{path}: cannot write output: {source}")]
    Io {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The encoder rejected the image.
    #[error("{path}: cannot encode PNG: {source}")]
    Encode {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: image::ImageError,
    },
}

/// The sRGB transfer function of a linear value in [0, 1] (values outside are clamped).
#[inline]
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB bytes of a film, row-major RGB.
pub fn encode_srgb8(film: &Film) -> Vec<u8> {
    film.pixels.iter().flat_map(|c| c.to_array().map(|v| (linear_to_srgb(v) * 255.0 + 0.5) as u8)).collect()
}

/// Writes the film as an 8-bit sRGB PNG, atomically (see [`write_atomically`]).
pub fn write_png(film: &Film, path: &Path) -> Result<(), OutputError> {
    let mut png = Vec::new();
    PngEncoder::new(&mut png)
        .write_image(&encode_srgb8(film), film.width, film.height, ExtendedColorType::Rgb8)
        .map_err(|source| OutputError::Encode { path: path.to_path_buf(), source })?;
    write_atomically(path, &png)
}

/// Writes `bytes` to `path` atomically: they go to a temporary file in the same folder, are
/// synced, and the file is renamed into place, so readers see the old file or the whole new one.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let io = |source| OutputError::Io { path: path.to_path_buf(), source };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".penumbra-").suffix(".tmp");
    // Temporary files are private (0600) by default; the finished output is an ordinary file.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let mut tmp = builder.tempfile_in(dir).map_err(io)?;
    tmp.as_file_mut().write_all(bytes).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    // On error the temporary file is removed when `tmp` drops.
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_hits_known_points() {
        assert_eq!(linear_to_srgb(0.0), 0.0);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
        let white = Film { width: 1, height: 1, pixels: vec![crate::math::Vec3::ONE] };
        assert_eq!(encode_srgb8(&white), vec![255, 255, 255]);
        // Mid-grey 0.5 in sRGB is about 0.214 linear.
        assert!((linear_to_srgb(0.214_041) - 0.5).abs() < 1e-4);
    }

    #[test]
    fn png_round_trips_and_leaves_no_temporary_files() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.png");
        let mut film = Film::new(3, 2);
        film.set(2, 1, crate::math::Vec3::new(1.0, 0.214_041, 0.0));
        write_png(&film, &path).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        assert_eq!((img.width(), img.height()), (3, 2));
        let [r, g, b] = img.get_pixel(2, 1).0;
        assert_eq!((r, b), (255, 0));
        assert!((127..=128).contains(&g), "linear 0.214 is sRGB mid-grey, got {g}");
        assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0]);
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, vec![std::ffi::OsString::from("out.png")]);
    }

    #[test]
    fn writing_into_a_missing_folder_fails_cleanly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing").join("out.png");
        let err = write_png(&Film::new(1, 1), &path).unwrap_err();
        assert!(err.to_string().contains("missing"), "{err}");
        assert!(!path.exists());
    }
}
