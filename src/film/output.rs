//! Writing films: sRGB encoding, tone-mapped 8/16-bit PNG and linear half/float EXR with AOVs
//! and metadata, and reading metadata and EXR files back. Every file goes to a temporary file
//! in the target folder that is synced and then renamed, so a crash never leaves a half-written
//! image behind.
//!
//! Formats ([`OutputFormat`]): `png8`, `png16` (tone-mapped, sRGB; AOVs as viewable
//! `{stem}.{aov}.png` files, see `aov_png`), `exr-half`, `exr-float` (linear, not tone-mapped;
//! AOVs as parts of the same file, see `exr_io`).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};

use super::aov::Aovs;
use super::aov_png::aov_images;
use super::exr_io::{decode_exr, encode_exr, read_exr_metadata, reserved_key, LEGEND_KEY};
pub use super::format::{OutputFormat, PngCompression};
use super::metadata::Metadata;
use super::png_io::{encode_png, film_samples, read_png_metadata, Samples};
use super::tonemap::{encode_srgb8, ToneMapping};
use super::Film;

/// Failure to write or read an output file.
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
    /// The `png` crate rejected the image or its text chunks.
    #[error("{path}: cannot encode PNG: {source}")]
    Png {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: png::EncodingError,
    },
    /// The `exr` crate could not encode or decode the file.
    #[error("{path}: EXR error: {source}")]
    Exr {
        /// The file's path.
        path: PathBuf,
        /// The cause.
        source: exr::error::Error,
    },
    /// A file could not be read or understood.
    #[error("{path}: cannot read image: {message}")]
    Read {
        /// The file's path.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A metadata entry cannot be stored.
    #[error("{path}: metadata key `{key}`: {reason}")]
    Metadata {
        /// The output path.
        path: PathBuf,
        /// The offending key.
        key: String,
        /// Why it cannot be stored.
        reason: &'static str,
    },
    /// The AOV buffers do not match the film's size.
    #[error("{path}: AOVs do not match the {width}×{height} film: {message}")]
    AovSize {
        /// The output path.
        path: PathBuf,
        /// Film width.
        width: u32,
        /// Film height.
        height: u32,
        /// Which buffer is wrong.
        message: String,
    },
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
    persist(path, stage(path, bytes)?)
}

/// Makes sure `path` can be written before any work is done, the way every command treats
/// its outputs: missing parent folders are created, a folder at `path` itself is refused, and
/// the folder is proven writable by creating (and removing) a temporary file there, as the
/// final atomic write will.
///
/// # Examples
/// ```
/// # use penumbra::film::prepare_output;
/// let dir = tempfile::tempdir().unwrap();
/// prepare_output(&dir.path().join("new/folder/image.png")).unwrap();
/// assert!(dir.path().join("new/folder").is_dir());
/// assert!(prepare_output(dir.path()).is_err());
/// ```
pub fn prepare_output(path: &Path) -> Result<(), OutputError> {
    let io = |source| OutputError::Io { path: path.to_path_buf(), source };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    if path.is_dir() {
        return Err(io(std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a folder, not a file")));
    }
    tempfile::Builder::new().prefix(".penumbra-").suffix(".tmp").tempfile_in(dir).map_err(io)?;
    Ok(())
}

/// Writes `bytes` to a synced temporary file in `path`'s folder (removed again if dropped).
fn stage(path: &Path, bytes: &[u8]) -> Result<tempfile::NamedTempFile, OutputError> {
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
    Ok(tmp)
}

/// Renames a staged temporary file to `path` (on error it is removed when dropped).
fn persist(path: &Path, tmp: tempfile::NamedTempFile) -> Result<(), OutputError> {
    tmp.persist(path).map_err(|e| OutputError::Io { path: path.to_path_buf(), source: e.error })?;
    // The rename is durable once the folder's entry is: sync the folder too (Unix; elsewhere
    // folders cannot be opened for syncing).
    #[cfg(unix)]
    {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|source| OutputError::Io { path: dir.to_path_buf(), source })?;
    }
    Ok(())
}

/// Writes the film in `format`, with its AOVs and metadata, and returns every file written
/// (the main image first).
///
/// - PNG: the film is tone-mapped with `tone` and sRGB-encoded; each metadata entry becomes a
///   `tEXt` chunk (`iTXt` if not Latin-1). Each AOV present goes to `{stem}.{aov}.png` beside
///   `path` as an 8-bit viewable rendering with its scale in extra entries (see `aov_png`).
/// - EXR: linear values, `tone` is ignored; AOVs become parts of the same file and metadata
///   entries string attributes (see `exr_io`).
///
/// All files are encoded first, then staged as synced temporary files, then renamed into place,
/// so an encoding or write error leaves no new file behind.
///
/// # Examples
/// ```
/// # use penumbra::film::{write_image, Film, Metadata, OutputFormat, ToneMapping};
/// # let dir = tempfile::tempdir()?;
/// let path = dir.path().join("frame.exr");
/// let written = write_image(&Film::new(4, 4), None, &path, OutputFormat::ExrFloat,
///     &ToneMapping::default(), &Metadata::default())?;
/// assert_eq!(written, vec![path]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_image(
    film: &Film,
    aovs: Option<&Aovs>,
    path: &Path,
    format: OutputFormat,
    tone: &ToneMapping,
    meta: &Metadata,
) -> Result<Vec<PathBuf>, OutputError> {
    write_image_with(film, aovs, path, (format, PngCompression::default()), tone, meta)
}

/// [`write_image`], PNG files compressed at `compression` (the pixels are the same at every
/// level; EXR files ignore it).
pub fn write_image_with(
    film: &Film,
    aovs: Option<&Aovs>,
    path: &Path,
    (format, compression): (OutputFormat, PngCompression),
    tone: &ToneMapping,
    meta: &Metadata,
) -> Result<Vec<PathBuf>, OutputError> {
    let meta_error = |(key, reason)| OutputError::Metadata { path: path.to_path_buf(), key, reason };
    meta.validate().map_err(meta_error)?;
    if let Some(aovs) = aovs {
        check_aov_sizes(film, aovs, path)?;
    }
    let files = if format.is_exr() {
        encode_exr_file(film, aovs, path, format, meta)?
    } else {
        encode_png_files(film, aovs, path, (format, compression), tone, meta)?
    };
    let staged = files.iter().map(|(p, bytes)| stage(p, bytes)).collect::<Result<Vec<_>, _>>()?;
    for ((p, _), tmp) in files.iter().zip(staged) {
        persist(p, tmp)?;
    }
    Ok(files.into_iter().map(|(p, _)| p).collect())
}

/// Encodes the EXR file in memory.
fn encode_exr_file(
    film: &Film,
    aovs: Option<&Aovs>,
    path: &Path,
    format: OutputFormat,
    meta: &Metadata,
) -> Result<Vec<(PathBuf, Vec<u8>)>, OutputError> {
    if let Some(key) = reserved_key(meta) {
        let reason = "the name is reserved by OpenEXR";
        return Err(OutputError::Metadata { path: path.to_path_buf(), key: key.to_owned(), reason });
    }
    let mut meta = meta.clone();
    if let Some(aovs) = aovs.filter(|a| a.object.is_some()) {
        meta.set(LEGEND_KEY, super::exr_io::legend(&aovs.object_names));
    }
    let bytes = encode_exr(film, aovs, format == OutputFormat::ExrHalf, &meta)
        .map_err(|source| OutputError::Exr { path: path.to_path_buf(), source })?;
    Ok(vec![(path.to_path_buf(), bytes)])
}

/// Encodes the main PNG and one PNG per AOV in memory.
fn encode_png_files(
    film: &Film,
    aovs: Option<&Aovs>,
    path: &Path,
    (format, compression): (OutputFormat, PngCompression),
    tone: &ToneMapping,
    meta: &Metadata,
) -> Result<Vec<(PathBuf, Vec<u8>)>, OutputError> {
    let png_error = |p: &Path| {
        let p = p.to_path_buf();
        move |source| OutputError::Png { path: p, source }
    };
    let samples = film_samples(film, tone, format == OutputFormat::Png16);
    let main = encode_png(film.width, film.height, &samples, meta, compression).map_err(png_error(path))?;
    let mut files = vec![(path.to_path_buf(), main)];
    for image in aovs.map(aov_images).unwrap_or_default() {
        let aov_path = aov_png_path(path, image.name);
        let bytes = encode_png(
            film.width,
            film.height,
            &Samples::Eight(image.rgb),
            &meta.merged(&image.extra),
            compression,
        )
        .map_err(png_error(&aov_path))?;
        files.push((aov_path, bytes));
    }
    Ok(files)
}

/// `{folder}/{stem}.{aov}.png` for the image at `path`.
fn aov_png_path(path: &Path, aov: &str) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!("{stem}.{aov}.png"))
}

/// Checks every AOV buffer present has one value per film pixel.
fn check_aov_sizes(film: &Film, aovs: &Aovs, path: &Path) -> Result<(), OutputError> {
    let n = film.pixels.len();
    let lens = [
        ("depth", aovs.depth.as_ref().map(Vec::len)),
        ("normal", aovs.normal.as_ref().map(Vec::len)),
        ("albedo", aovs.albedo.as_ref().map(Vec::len)),
        ("object", aovs.object.as_ref().map(Vec::len)),
        ("cost", aovs.cost.as_ref().map(Vec::len)),
    ];
    let bad = if (aovs.width, aovs.height) != (film.width, film.height) {
        Some(format!("AOVs are {}×{}", aovs.width, aovs.height))
    } else {
        lens.iter()
            .find(|(_, len)| len.is_some_and(|l| l != n))
            .map(|(name, len)| format!("{name} has {} values, not {n}", len.unwrap_or(0)))
    };
    match bad {
        Some(message) => Err(OutputError::AovSize {
            path: path.to_path_buf(),
            width: film.width,
            height: film.height,
            message,
        }),
        None => Ok(()),
    }
}

/// PNG files start with these bytes.
const PNG_MAGIC: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1A, b'\n'];
/// EXR files start with these bytes.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2F, 0x31, 0x01];

/// Reads the metadata of a PNG (text chunks: `tEXt`, then `zTXt`, then `iTXt`) or an EXR file
/// (string attributes, sorted by key), recognised by its first bytes.
pub fn read_metadata(path: &Path) -> Result<Metadata, OutputError> {
    let read_error = |message: String| OutputError::Read { path: path.to_path_buf(), message };
    let mut magic = [0u8; 8];
    let mut file = std::fs::File::open(path).map_err(|e| read_error(e.to_string()))?;
    let got = file.read(&mut magic).map_err(|e| read_error(e.to_string()))?;
    drop(file);
    if got == 8 && magic == PNG_MAGIC {
        read_png_metadata(path).map_err(read_error)
    } else if got >= 4 && magic[..4] == EXR_MAGIC {
        read_exr_metadata(path).map_err(|source| OutputError::Exr { path: path.to_path_buf(), source })
    } else {
        Err(read_error("neither a PNG nor an EXR file".into()))
    }
}

/// Reads an EXR file written by [`write_image`] (or any EXR with `R`, `G`, `B` channels) back
/// into a film and the AOV layers it holds.
pub fn read_exr(path: &Path) -> Result<(Film, Aovs), OutputError> {
    decode_exr(path)
        .map_err(|source| OutputError::Exr { path: path.to_path_buf(), source })?
        .map_err(|message| OutputError::Read { path: path.to_path_buf(), message })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::fixtures::{random_aovs, random_film};
    use crate::film::ToneOperator;

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

    /// File names in `dir`, sorted.
    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn tone_mapping_never_touches_exr_values() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("linear.exr");
        let film = random_film(9, 8, 21);
        let tone = ToneMapping { operator: ToneOperator::Aces, exposure: 3.0, white: 2.0 };
        write_image(&film, None, &path, OutputFormat::ExrFloat, &tone, &Metadata::default()).unwrap();
        assert_eq!(read_exr(&path).unwrap().0, film);
    }

    #[test]
    fn writes_leave_no_temporary_files() {
        let dir = tempfile::tempdir().unwrap();
        let (film, aovs) = (random_film(6, 4, 1), random_aovs(6, 4, 2));
        let tone = ToneMapping::default();
        for (name, format) in [("a.png", OutputFormat::Png8), ("b.png", OutputFormat::Png16)] {
            write_image(&film, Some(&aovs), &dir.path().join(name), format, &tone, &Metadata::default())
                .unwrap();
        }
        for (name, format) in [("c.exr", OutputFormat::ExrHalf), ("d.exr", OutputFormat::ExrFloat)] {
            write_image(&film, Some(&aovs), &dir.path().join(name), format, &tone, &Metadata::default())
                .unwrap();
        }
        // Overwriting replaces the file in place.
        write_image(
            &film,
            None,
            &dir.path().join("d.exr"),
            OutputFormat::ExrFloat,
            &tone,
            &Metadata::default(),
        )
        .unwrap();
        let aov_names = ["albedo", "cost", "depth", "normal", "object"];
        let mut expect: Vec<String> = ["a", "b"]
            .iter()
            .flat_map(|s| aov_names.iter().map(move |a| format!("{s}.{a}.png")).chain([format!("{s}.png")]))
            .chain(["c.exr".into(), "d.exr".into()])
            .collect();
        expect.sort();
        assert_eq!(listing(dir.path()), expect);
        assert!(read_exr(&dir.path().join("d.exr")).unwrap().1.depth.is_none());
    }

    #[test]
    fn write_image_into_a_missing_folder_names_the_path_and_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let (film, aovs) = (random_film(2, 2, 1), random_aovs(2, 2, 1));
        for (name, format) in [("o.png", OutputFormat::Png16), ("o.exr", OutputFormat::ExrHalf)] {
            let path = dir.path().join("missing").join(name);
            let err =
                write_image(&film, Some(&aovs), &path, format, &ToneMapping::default(), &Metadata::default())
                    .unwrap_err();
            assert!(err.to_string().contains(&path.display().to_string()), "{err}");
            assert!(listing(dir.path()).is_empty());
        }
    }

    #[test]
    fn bad_metadata_and_mismatched_aovs_fail_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.png");
        let tone = ToneMapping::default();
        let film = random_film(3, 3, 1);
        let meta = Metadata { entries: vec![("世界".into(), "v".into())] };
        let err = write_image(&film, None, &path, OutputFormat::Png8, &tone, &meta).unwrap_err();
        assert!(matches!(err, OutputError::Metadata { .. }) && err.to_string().contains("x.png"), "{err}");
        let err = write_image(
            &film,
            Some(&random_aovs(3, 2, 1)),
            &path,
            OutputFormat::Png8,
            &tone,
            &Metadata::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("3×2"), "{err}");
        let mut aovs = random_aovs(3, 3, 1);
        aovs.cost.as_mut().unwrap().pop();
        let err = write_image(&film, Some(&aovs), &path, OutputFormat::ExrHalf, &tone, &Metadata::default())
            .unwrap_err();
        assert!(err.to_string().contains("cost has 8 values"), "{err}");
        assert!(listing(dir.path()).is_empty());
    }

    #[test]
    fn reading_something_else_fails_with_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("notes.txt");
        std::fs::write(&path, "hello").unwrap();
        let err = read_metadata(&path).unwrap_err();
        assert!(err.to_string().contains("notes.txt"), "{err}");
        assert!(read_exr(&path).unwrap_err().to_string().contains("notes.txt"));
        assert!(read_metadata(&dir.path().join("absent.png"))
            .unwrap_err()
            .to_string()
            .contains("absent.png"));
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
