//! PNG encoding with text metadata, through the `png` crate: 8- or 16-bit RGB, one `tEXt` chunk
//! per metadata entry (`iTXt`, UTF-8, when the value is not Latin-1), and reading those chunks
//! back.

use std::io::BufReader;
use std::path::Path;

use png::{BitDepth, ColorType, Decoder, Encoder, EncodingError};

use super::format::PngCompression;
use super::metadata::{is_latin1, Metadata};
use super::tonemap::{linear_to_srgb, srgb8};
use super::tonemap::{tone_map, ToneMapping};
use super::Film;

/// Samples of an RGB image ready for the encoder.
pub(crate) enum Samples {
    /// 8 bits per channel.
    Eight(Vec<u8>),
    /// 16 bits per channel.
    Sixteen(Vec<u16>),
}

/// Encodes a `width × height` RGB image with `meta` as text chunks (written before the image
/// data, in entry order: all `tEXt` chunks, then all `iTXt` chunks), its data compressed at
/// `compression`.
pub(crate) fn encode_png(
    width: u32,
    height: u32,
    samples: &Samples,
    meta: &Metadata,
    compression: PngCompression,
) -> Result<Vec<u8>, EncodingError> {
    let mut out = Vec::new();
    let mut encoder = Encoder::new(&mut out, width, height);
    encoder.set_color(ColorType::Rgb);
    encoder.set_compression(compression.level());
    for (key, value) in &meta.entries {
        if is_latin1(value) {
            encoder.add_text_chunk(key.clone(), value.clone())?;
        } else {
            encoder.add_itxt_chunk(key.clone(), value.clone())?;
        }
    }
    let data: Vec<u8> = match samples {
        Samples::Eight(bytes) => {
            encoder.set_depth(BitDepth::Eight);
            bytes.clone()
        }
        Samples::Sixteen(words) => {
            encoder.set_depth(BitDepth::Sixteen);
            // PNG stores 16-bit samples big-endian.
            words.iter().flat_map(|w| w.to_be_bytes()).collect()
        }
    };
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&data)?;
    writer.finish()?;
    Ok(out)
}

/// The tone-mapped, sRGB-encoded samples of a film at 8 or 16 bits, blocks of pixels encoded
/// in parallel (on the calling thread's rayon pool; each sample depends on its pixel alone).
pub(crate) fn film_samples(film: &Film, tone: &ToneMapping, sixteen: bool) -> Samples {
    if sixteen {
        Samples::Sixteen(encode_parallel(film, tone, |v| (linear_to_srgb(v) * 65535.0 + 0.5) as u16))
    } else {
        Samples::Eight(encode_parallel(film, tone, srgb8))
    }
}

/// Each pixel's tone-mapped channels through `encode`, row-major RGB.
fn encode_parallel<T: Copy + Default + Send>(
    film: &Film,
    tone: &ToneMapping,
    encode: impl Fn(f32) -> T + Sync,
) -> Vec<T> {
    use rayon::prelude::*;
    /// Pixels per parallel block.
    const BLOCK: usize = 4096;
    let mut out = vec![T::default(); film.pixels.len() * 3];
    out.par_chunks_mut(BLOCK * 3).zip(film.pixels.par_chunks(BLOCK)).for_each(|(out, pixels)| {
        for (out, &c) in out.chunks_exact_mut(3).zip(pixels) {
            for (o, v) in out.iter_mut().zip(tone_map(c, tone).to_array()) {
                *o = encode(v);
            }
        }
    });
    out
}

/// The text chunks of a PNG file (`tEXt`, then `zTXt`, then `iTXt`; each in file order).
pub(crate) fn read_png_metadata(path: &Path) -> Result<Metadata, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut reader = Decoder::new(BufReader::new(file)).read_info().map_err(|e| e.to_string())?;
    // Text chunks may follow the image data; `finish` skips the pixels and reads them too.
    reader.finish().map_err(|e| e.to_string())?;
    let info = reader.info();
    let mut meta = Metadata::default();
    for chunk in &info.uncompressed_latin1_text {
        meta.entries.push((chunk.keyword.clone(), chunk.text.clone()));
    }
    for chunk in &info.compressed_latin1_text {
        let mut chunk = chunk.clone();
        chunk.decompress_text().map_err(|e| e.to_string())?;
        meta.entries.push((chunk.keyword.clone(), chunk.get_text().map_err(|e| e.to_string())?));
    }
    for chunk in &info.utf8_text {
        let mut chunk = chunk.clone();
        chunk.decompress_text().map_err(|e| e.to_string())?;
        meta.entries.push((chunk.keyword.clone(), chunk.get_text().map_err(|e| e.to_string())?));
    }
    Ok(meta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::fixtures::{random_aovs, random_film};
    use crate::film::output::{read_metadata, write_image, OutputFormat};
    use crate::film::ToneOperator;
    use crate::math::Vec3;

    fn sample_meta() -> Metadata {
        let mut meta = Metadata::default();
        meta.set("Software", "penumbra 0.1");
        meta.set("penumbra.seed", "42");
        meta.set("Comment", "café crème");
        meta.set("penumbra.note", "Grüße, 世界 🌍");
        meta
    }

    #[test]
    fn metadata_round_trips_through_png8_and_png16() {
        let dir = tempfile::tempdir().unwrap();
        let meta = sample_meta();
        for format in [OutputFormat::Png8, OutputFormat::Png16] {
            let path = dir.path().join(format!("{format}.png"));
            write_image(&random_film(5, 4, 2), None, &path, format, &ToneMapping::default(), &meta).unwrap();
            // Latin-1 entries come back first (tEXt), then the others (iTXt); here that is the
            // insertion order.
            assert_eq!(read_metadata(&path).unwrap(), meta, "{format}");
        }
    }

    #[test]
    fn png16_decodes_to_the_expected_16_bit_values() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("deep.png");
        let film = random_film(7, 5, 9);
        let tone = ToneMapping { operator: ToneOperator::Reinhard, exposure: -2.0, white: 6.0 };
        write_image(&film, None, &path, OutputFormat::Png16, &tone, &Metadata::default()).unwrap();
        let decoded = image::open(&path).unwrap();
        assert_eq!(decoded.color(), image::ColorType::Rgb16);
        let decoded = decoded.to_rgb16();
        for (i, c) in film.pixels.iter().enumerate() {
            let expect = tone_map(*c, &tone).to_array().map(|v| (linear_to_srgb(v) * 65535.0 + 0.5) as u16);
            let (x, y) = (i as u32 % film.width, i as u32 / film.width);
            assert_eq!(decoded.get_pixel(x, y).0, expect, "pixel ({x}, {y})");
        }
    }

    #[test]
    fn png8_matches_the_tone_mapped_srgb_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("eight.png");
        let film = random_film(6, 3, 4);
        let tone = ToneMapping { operator: ToneOperator::Aces, exposure: 1.0, white: 4.0 };
        write_image(&film, None, &path, OutputFormat::Png8, &tone, &Metadata::default()).unwrap();
        let Samples::Eight(expect) = film_samples(&film, &tone, false) else { panic!("expected 8 bits") };
        assert_eq!(image::open(&path).unwrap().to_rgb8().into_raw(), expect);
    }

    #[test]
    fn aovs_go_to_separate_pngs_with_their_scales() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame.png");
        let aovs = random_aovs(8, 6, 3);
        let meta = sample_meta();
        let written = write_image(
            &random_film(8, 6, 1),
            Some(&aovs),
            &path,
            OutputFormat::Png16,
            &ToneMapping::default(),
            &meta,
        )
        .unwrap();
        let names: Vec<_> =
            written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
        let expect = [
            "frame.png",
            "frame.depth.png",
            "frame.normal.png",
            "frame.albedo.png",
            "frame.object.png",
            "frame.cost.png",
        ];
        assert_eq!(names, expect);
        for p in &written[1..] {
            let img = image::open(p).unwrap();
            assert_eq!((img.color(), img.width(), img.height()), (image::ColorType::Rgb8, 8, 6), "{p:?}");
            let got = read_metadata(p).unwrap();
            assert_eq!(got.get("penumbra.note"), Some("Grüße, 世界 🌍"), "{p:?}");
        }
        let depth_max = crate::film::aov_png::robust_max(aovs.depth.as_ref().unwrap());
        let depth_meta = read_metadata(&written[1]).unwrap();
        assert_eq!(depth_meta.get("penumbra.aov.depth.max"), Some(depth_max.to_string().as_str()));
        assert_eq!(depth_meta.get("penumbra.aov"), Some("depth"));
        // Background pixel 0 has depth +∞ and is drawn black; object id 0 likewise.
        assert_eq!(image::open(&written[1]).unwrap().to_rgb8().get_pixel(0, 0).0, [0, 0, 0]);
        assert_eq!(image::open(&written[4]).unwrap().to_rgb8().get_pixel(0, 0).0, [0, 0, 0]);
        let legend = read_metadata(&written[4]).unwrap();
        assert_eq!(legend.get("penumbra.aov.object.legend"), Some("1=floor,2=ball, red,3=Grüße 世界"));
        let cost_max = aovs.cost.as_ref().unwrap().iter().max().unwrap().to_string();
        assert_eq!(read_metadata(&written[5]).unwrap().get("penumbra.aov.cost.max"), Some(cost_max.as_str()));
    }

    #[test]
    fn sixteen_bit_samples_follow_the_formula() {
        let film =
            Film { width: 2, height: 1, pixels: vec![Vec3::new(0.0, 0.214_041, 1.0), Vec3::splat(9.0)] };
        let tone = ToneMapping { operator: ToneOperator::Clamp, exposure: 0.0, white: 4.0 };
        let Samples::Sixteen(words) = film_samples(&film, &tone, true) else { panic!("expected 16 bits") };
        let expect = |v: f32| (linear_to_srgb(v) * 65535.0 + 0.5) as u16;
        assert_eq!(words, vec![0, expect(0.214_041), 65535, 65535, 65535, 65535]);
    }

    #[test]
    fn text_chunks_are_written_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.png");
        let mut meta = Metadata::default();
        meta.set("Title", "café");
        meta.set("Comment", "世界");
        let png = encode_png(1, 1, &Samples::Eight(vec![1, 2, 3]), &meta, PngCompression::default()).unwrap();
        std::fs::write(&path, png).unwrap();
        assert_eq!(read_png_metadata(&path).unwrap(), meta);
    }
}
