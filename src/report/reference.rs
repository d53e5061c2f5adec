//! Reference images read from a file (`penumbra report --reference FILE`): a linear EXR, as
//! `penumbra render --format exr-float` writes, or an 8- or 16-bit PNG decoded from sRGB to
//! linear light, recognised by their first bytes.
//!
//! A PNG was tone-mapped before it was written, so it holds less than an EXR: values above 1
//! are clipped and every value is quantised (8-bit PNGs put an error floor of about 1e-3 under
//! RMSE). A PNG that Penumbra wrote records its tone mapping (`penumbra.tonemap`): with the
//! clamp operator (the default), its exposure is undone exactly; with Reinhard or ACES it is
//! refused, since those curves cannot be undone without large errors in the highlights. A PNG
//! without that record is taken as clamp with no exposure.

use std::io::Read;
use std::path::Path;

use super::run::ReportError;
use crate::film::{read_exr, read_metadata, read_png_linear, Film, Metadata};

/// The metadata key under which `penumbra render` records a PNG's tone mapping, as the
/// `Debug` form of `ToneMapping`, e.g. `ToneMapping { operator: Clamp, exposure: 0.0, white: 4.0 }`.
pub const TONEMAP_KEY: &str = "penumbra.tonemap";

/// A reference image read from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceFile {
    /// The linear image.
    pub film: Film,
    /// Its metadata (empty when it has none).
    pub meta: Metadata,
    /// What it is, e.g. `ref.png (8-bit PNG, sRGB decoded to linear)`.
    pub description: String,
    /// Caveats to tell the user (a PNG's clipping and quantisation).
    pub notes: Vec<String>,
}

/// The operator name and exposure in a `penumbra.tonemap` value; `None` when unreadable.
fn tone_of(value: &str) -> Option<(&str, f32)> {
    let field = |name: &str| {
        let rest = &value[value.find(&format!("{name}: "))? + name.len() + 2..];
        Some(rest.split([',', ' ', '}']).next().unwrap_or(rest))
    };
    Some((field("operator")?, field("exposure")?.parse().ok()?))
}

/// Reads a reference image (EXR or PNG, by its first bytes).
pub fn read_reference(path: &Path) -> Result<ReferenceFile, ReportError> {
    let name = path.display().to_string();
    let refuse = |message: String| ReportError::Reference { path: name.clone(), message };
    let mut magic = [0u8; 8];
    let got = std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut magic))
        .map_err(|e| refuse(format!("cannot read the reference: {e}")))?;
    let kind = if got == 8 && magic == *b"\x89PNG\r\n\x1a\n" {
        "png"
    } else if got >= 4 && magic[..4] == [0x76, 0x2F, 0x31, 0x01] {
        "exr"
    } else {
        return Err(refuse(
            "not a PNG or EXR file; --reference takes a linear EXR (`penumbra render --format \
             exr-float`, preferred) or an 8/16-bit sRGB PNG"
                .into(),
        ));
    };
    // Metadata is optional: a reference from another program may have none we can read.
    let meta = read_metadata(path).unwrap_or_default();
    if kind == "exr" {
        let (film, _) = read_exr(path).map_err(|e| refuse(format!("cannot read the EXR: {}", inner(&e))))?;
        return Ok(ReferenceFile { film, meta, description: format!("{name} (linear EXR)"), notes: vec![] });
    }

    let png = read_png_linear(path).map_err(|e| refuse(format!("cannot read the PNG: {}", inner(&e))))?;
    let mut film = png.film;
    let mut notes = Vec::new();
    match meta.get(TONEMAP_KEY) {
        Some(value) => match tone_of(value) {
            Some(("Clamp", exposure)) if exposure.is_finite() => {
                if exposure != 0.0 {
                    let undo = (-exposure).exp2();
                    film.pixels.iter_mut().for_each(|p| *p *= undo);
                    notes.push(format!("{name}: its exposure of {exposure} stops is undone"));
                }
            }
            Some((operator, _)) => {
                return Err(refuse(format!(
                    "this PNG was tone-mapped with {operator}, which cannot be undone exactly; \
                     use a PNG rendered with `--tonemap clamp` or, better, an EXR \
                     (`penumbra render --format exr-float`)"
                )))
            }
            None => {
                return Err(refuse(format!(
                    "its tone mapping `{value}` is not understood; use an EXR reference \
                     (`penumbra render --format exr-float`)"
                )))
            }
        },
        None => notes.push(format!("{name}: no tone mapping recorded; taken as clamp, exposure 0")),
    }
    let clipped = match png.saturated {
        0 => String::new(),
        n => format!(", and {n} pixel(s) at full white may have been clipped"),
    };
    notes.push(format!(
        "{name}: this {}-bit PNG reference is clamped to [0, 1] and quantised{clipped}; an EXR \
         reference (`penumbra render --format exr-float`) measures small errors better",
        png.bits
    ));
    Ok(ReferenceFile {
        film,
        meta,
        description: format!("{name} ({}-bit PNG, sRGB decoded to linear)", png.bits),
        notes,
    })
}

/// The message of a film error without its path (the report's error names the file once).
fn inner(e: &crate::film::OutputError) -> String {
    use crate::film::OutputError;
    match e {
        OutputError::Exr { source, .. } => source.to_string(),
        OutputError::Read { message, .. } => message.clone(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::{write_image, OutputFormat, ToneMapping, ToneOperator};
    use crate::math::Vec3;

    fn film() -> Film {
        let pixels = (0..12).map(|i| Vec3::new(i as f32 / 20.0, 0.3, 0.02 * i as f32)).collect();
        Film { width: 4, height: 3, pixels }
    }

    fn write(dir: &Path, name: &str, format: OutputFormat, tone: ToneMapping) -> std::path::PathBuf {
        let mut meta = Metadata::default();
        meta.set(TONEMAP_KEY, format!("{tone:?}"));
        let path = dir.join(name);
        write_image(&film(), None, &path, format, &tone, &meta).unwrap();
        path
    }

    fn worst(a: &Film, b: &Film) -> f32 {
        a.pixels.iter().zip(&b.pixels).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f32::max)
    }

    #[test]
    fn the_recorded_tone_mapping_parses() {
        let tone = ToneMapping { operator: ToneOperator::Clamp, exposure: -1.5, white: 4.0 };
        assert_eq!(tone_of(&format!("{tone:?}")), Some(("Clamp", -1.5)));
        assert_eq!(tone_of("nonsense"), None);
    }

    #[test]
    fn pngs_and_exrs_read_as_linear_and_exposure_is_undone() {
        let dir = tempfile::tempdir().unwrap();
        let clamp = ToneMapping::default();
        let exr = read_reference(&write(dir.path(), "r.exr", OutputFormat::ExrFloat, clamp)).unwrap();
        assert_eq!(exr.film, film());
        assert!(exr.notes.is_empty() && exr.description.ends_with("(linear EXR)"));
        let png16 = read_reference(&write(dir.path(), "r16.png", OutputFormat::Png16, clamp)).unwrap();
        assert!(worst(&png16.film, &film()) < 2e-5, "{}", worst(&png16.film, &film()));
        assert!(png16.description.contains("16-bit PNG"));
        let png8 = read_reference(&write(dir.path(), "r8.png", OutputFormat::Png8, clamp)).unwrap();
        assert!(worst(&png8.film, &film()) < 4e-3);
        assert!(png8.notes.iter().any(|n| n.contains("8-bit PNG reference is clamped")), "{:?}", png8.notes);
        let brighter = ToneMapping { exposure: 0.5, ..clamp };
        let png = read_reference(&write(dir.path(), "e.png", OutputFormat::Png16, brighter)).unwrap();
        assert!(worst(&png.film, &film()) < 2e-5, "exposure not undone: {}", worst(&png.film, &film()));
    }

    #[test]
    fn filmic_pngs_and_other_files_are_refused_plainly() {
        let dir = tempfile::tempdir().unwrap();
        let aces = ToneMapping { operator: ToneOperator::Aces, ..ToneMapping::default() };
        let e =
            read_reference(&write(dir.path(), "a.png", OutputFormat::Png8, aces)).unwrap_err().to_string();
        assert!(e.contains("a.png: this PNG was tone-mapped with Aces") && e.contains("exr-float"), "{e}");
        let text = dir.path().join("x.exr");
        std::fs::write(&text, "hello").unwrap();
        let e = read_reference(&text).unwrap_err().to_string();
        assert!(e.ends_with("x.exr: not a PNG or EXR file; --reference takes a linear EXR (`penumbra render --format exr-float`, preferred) or an 8/16-bit sRGB PNG"), "{e}");
        let mut broken = vec![0x76, 0x2F, 0x31, 0x01];
        broken.extend_from_slice(&[0; 20]);
        std::fs::write(&text, broken).unwrap();
        let e = read_reference(&text).unwrap_err().to_string();
        assert_eq!(e.matches("x.exr").count(), 1, "{e}");
    }
}
