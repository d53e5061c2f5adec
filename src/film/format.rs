//! Output file formats and their names on the command line: `png8`, `png16`, `exr-half`,
//! `exr-float`, and the default format for a file extension; and how hard PNG files are
//! compressed (`fast`, `balanced`, `high`).

use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// File format of [`write_image`](super::write_image).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OutputFormat {
    /// 8-bit sRGB PNG, tone-mapped.
    Png8,
    /// 16-bit sRGB PNG, tone-mapped.
    Png16,
    /// OpenEXR with 16-bit float colour, linear (magnitudes above 65504 become ∞).
    ExrHalf,
    /// OpenEXR with 32-bit float colour, linear.
    ExrFloat,
}

impl OutputFormat {
    /// The default format for a file name: `.png` → [`Png8`](Self::Png8), `.exr` →
    /// [`ExrHalf`](Self::ExrHalf) (case-insensitive); `None` for anything else.
    ///
    /// # Examples
    /// ```
    /// # use penumbra::film::OutputFormat;
    /// # use std::path::Path;
    /// assert_eq!(OutputFormat::from_path(Path::new("out.EXR")), Some(OutputFormat::ExrHalf));
    /// assert_eq!(OutputFormat::from_path(Path::new("out.jpg")), None);
    /// ```
    pub fn from_path(path: &Path) -> Option<OutputFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(OutputFormat::Png8),
            "exr" => Some(OutputFormat::ExrHalf),
            _ => None,
        }
    }

    /// True for the EXR formats (linear, not tone-mapped, AOVs inside the file).
    pub fn is_exr(&self) -> bool {
        matches!(self, OutputFormat::ExrHalf | OutputFormat::ExrFloat)
    }

    /// The name [`FromStr`] accepts.
    pub fn name(&self) -> &'static str {
        match self {
            OutputFormat::Png8 => "png8",
            OutputFormat::Png16 => "png16",
            OutputFormat::ExrHalf => "exr-half",
            OutputFormat::ExrFloat => "exr-float",
        }
    }
}

impl fmt::Display for OutputFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for OutputFormat {
    type Err = String;

    /// Parses `png8`, `png16`, `exr-half` or `exr-float` (case-insensitive).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "png8" => Ok(OutputFormat::Png8),
            "png16" => Ok(OutputFormat::Png16),
            "exr-half" => Ok(OutputFormat::ExrHalf),
            "exr-float" => Ok(OutputFormat::ExrFloat),
            _ => Err(format!("unknown output format `{s}`; expected png8, png16, exr-half or exr-float")),
        }
    }
}

/// How hard a PNG file's image data is compressed. The pixels are the same at every level;
/// only the file's size and the time spent writing it differ. Measured on 320×240 to 1280×960
/// renders (shipped scenes and `benches/compare` twins, docs/compare.md): `balanced` takes
/// 14–31× as long as `fast` for files 7–26 % smaller, `high` 2.5–3.4× as long again for 1–3 %
/// smaller still.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum PngCompression {
    /// A DEFLATE tuned for PNG (the `fdeflate` crate): milliseconds for a large frame.
    #[default]
    Fast,
    /// zlib-style compression at its usual level.
    Balanced,
    /// zlib-style compression at its highest level.
    High,
}

impl PngCompression {
    /// The name [`FromStr`] accepts.
    pub fn name(&self) -> &'static str {
        match self {
            PngCompression::Fast => "fast",
            PngCompression::Balanced => "balanced",
            PngCompression::High => "high",
        }
    }

    /// The `png` crate's level.
    pub(crate) fn level(&self) -> png::Compression {
        match self {
            PngCompression::Fast => png::Compression::Fast,
            PngCompression::Balanced => png::Compression::Balanced,
            PngCompression::High => png::Compression::High,
        }
    }
}

impl fmt::Display for PngCompression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PngCompression {
    type Err = String;

    /// Parses `fast`, `balanced` or `high` (case-insensitive).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "fast" => Ok(PngCompression::Fast),
            "balanced" => Ok(PngCompression::Balanced),
            "high" => Ok(PngCompression::High),
            _ => Err(format!("unknown PNG compression `{s}`; expected fast, balanced or high")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_compressions_parse_from_their_names() {
        for c in [PngCompression::Fast, PngCompression::Balanced, PngCompression::High] {
            assert_eq!(c.to_string().parse::<PngCompression>(), Ok(c));
        }
        assert_eq!("HIGH".parse(), Ok(PngCompression::High));
        let err = "best".parse::<PngCompression>().unwrap_err();
        assert!(["best", "fast", "balanced", "high"].iter().all(|o| err.contains(o)), "{err}");
        assert_eq!(PngCompression::default(), PngCompression::Fast);
    }

    #[test]
    fn formats_parse_from_names_and_paths() {
        for f in [OutputFormat::Png8, OutputFormat::Png16, OutputFormat::ExrHalf, OutputFormat::ExrFloat] {
            assert_eq!(f.to_string().parse::<OutputFormat>(), Ok(f));
        }
        assert_eq!("EXR-Float".parse(), Ok(OutputFormat::ExrFloat));
        let err = "tiff".parse::<OutputFormat>().unwrap_err();
        assert!(["tiff", "png8", "png16", "exr-half", "exr-float"].iter().all(|o| err.contains(o)), "{err}");
        assert_eq!(OutputFormat::from_path(Path::new("a/b.PNG")), Some(OutputFormat::Png8));
        assert_eq!(OutputFormat::from_path(Path::new("b.exr")), Some(OutputFormat::ExrHalf));
        assert_eq!(OutputFormat::from_path(Path::new("b")), None);
        assert!(OutputFormat::ExrFloat.is_exr() && !OutputFormat::Png16.is_exr());
    }
}
