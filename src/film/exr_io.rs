//! OpenEXR encoding and decoding of a film and its AOVs, linear and never tone-mapped.
//!
//! File layout (one multi-part file through the exr crate's layers, ZIP-compressed scan lines):
//! - part `beauty`: channels `R`, `G`, `B` (half or float);
//! - part `depth`: `depth.Z`, always 32-bit float (depth needs the precision; +∞ = background);
//! - part `normal`: `normal.X`, `normal.Y`, `normal.Z`; part `albedo`: `albedo.R/G/B`
//!   (half or float, like the beauty);
//! - part `object`: `object.id` and part `cost`: `cost.count`, both 32-bit unsigned integers.
//!
//! Channel names are fully qualified, so readers that flatten parts see `depth.Z` and so on.
//! Metadata entries become string attributes of the `beauty` header, stored as UTF-8 bytes.

use std::path::Path;

use exr::meta::attribute::AttributeValue;
use exr::prelude::traits::{ReadChannels, ReadLayers, WritableImage};
use exr::prelude::{
    f16, AnyChannel, AnyChannels, Encoding, FlatSamples, Image, ImageAttributes, IntegerBounds, Layer,
    LayerAttributes, SmallVec, Text, Vec2,
};

use super::aov::Aovs;
use super::metadata::Metadata;
use super::Film;
use crate::math::Vec3;

/// Name of the part holding the colour channels.
pub(crate) const MAIN_LAYER: &str = "beauty";

/// A layer of arbitrary channels, as the exr crate reads and writes them.
type AnyLayer = Layer<AnyChannels<FlatSamples>>;

/// An exr `Text` holding the UTF-8 bytes of `s` (the crate's own conversion panics outside
/// Latin-1).
fn text(s: &str) -> Text {
    Text::from_bytes_unchecked(SmallVec::from_slice(s.as_bytes()))
}

/// Decodes EXR text bytes: UTF-8 when valid, else Latin-1 (one char per byte).
pub(crate) fn untext(t: &Text) -> String {
    match std::str::from_utf8(t.bytes()) {
        Ok(s) => s.to_owned(),
        Err(_) => t.bytes().iter().map(|&b| char::from(b)).collect(),
    }
}

/// The metadata key, if any, that collides with an attribute name the EXR format reserves.
pub(crate) fn reserved_key(meta: &Metadata) -> Option<&str> {
    meta.entries
        .iter()
        .map(|(k, _)| k.as_str())
        .find(|k| exr::meta::header::standard_names::ALL.contains(&k.as_bytes()))
}

/// Float samples, rounded to half when `half`.
fn floats(values: impl Iterator<Item = f32>, half: bool) -> FlatSamples {
    if half {
        FlatSamples::F16(values.map(f16::from_f32).collect())
    } else {
        FlatSamples::F32(values.collect())
    }
}

/// Three channels `{prefix}{names[i]}` from a colour buffer.
fn vec3_channels(prefix: &str, names: [&str; 3], data: &[Vec3], half: bool) -> Vec<AnyChannel<FlatSamples>> {
    (0..3)
        .map(|i| {
            AnyChannel::new(text(&format!("{prefix}{}", names[i])), floats(data.iter().map(|v| v[i]), half))
        })
        .collect()
}

/// Name of the single attribute that carries all metadata entries, as a JSON list of
/// `[key, value]` pairs. One attribute, not one per entry: the exr crate keeps attributes in a
/// hash map and writes them in its iteration order, which would make the file's bytes differ
/// from run to run.
const BUNDLE_KEY: &str = "penumbra.metadata";

/// The metadata entries among a header's attributes: the bundle, expanded in order, then any
/// other string attribute (written by other tools), sorted by key.
fn entries_of(attrs: &std::collections::HashMap<Text, AttributeValue>) -> Vec<(String, String)> {
    let mut loose: Vec<(String, String)> = Vec::new();
    let mut bundled: Vec<(String, String)> = Vec::new();
    for (name, value) in attrs {
        let AttributeValue::Text(v) = value else { continue };
        let (key, value) = (untext(name), untext(v));
        if key == BUNDLE_KEY {
            bundled = serde_json::from_str(&value).unwrap_or_default();
        } else {
            loose.push((key, value));
        }
    }
    loose.sort();
    bundled.extend(loose);
    bundled
}

/// A named part with the given channels (sorted, as the format requires).
fn layer(name: &str, size: Vec2<usize>, channels: Vec<AnyChannel<FlatSamples>>, other: Metadata) -> AnyLayer {
    let mut attributes = LayerAttributes::named(text(name));
    if !other.entries.is_empty() {
        let bundle = serde_json::to_string(&other.entries).unwrap_or_default();
        attributes.other.insert(text(BUNDLE_KEY), AttributeValue::Text(text(&bundle)));
    }
    Layer::new(size, attributes, Encoding::SMALL_LOSSLESS, AnyChannels::sort(SmallVec::from_vec(channels)))
}

/// Encodes the film (and AOVs) as an EXR file in memory; `half` picks 16-bit colour channels.
/// The caller has checked that the AOVs match the film's size.
pub(crate) fn encode_exr(
    film: &Film,
    aovs: Option<&Aovs>,
    half: bool,
    meta: &Metadata,
) -> Result<Vec<u8>, exr::error::Error> {
    let size = Vec2(film.width as usize, film.height as usize);
    let main = vec3_channels("", ["R", "G", "B"], &film.pixels, half);
    let mut layers = vec![layer(MAIN_LAYER, size, main, meta.clone())];
    if let Some(aovs) = aovs {
        if let Some(depth) = &aovs.depth {
            let z = AnyChannel::new(text("depth.Z"), FlatSamples::F32(depth.clone()));
            layers.push(layer("depth", size, vec![z], Metadata::default()));
        }
        if let Some(normal) = &aovs.normal {
            let channels = vec3_channels("normal.", ["X", "Y", "Z"], normal, half);
            layers.push(layer("normal", size, channels, Metadata::default()));
        }
        if let Some(albedo) = &aovs.albedo {
            let channels = vec3_channels("albedo.", ["R", "G", "B"], albedo, half);
            layers.push(layer("albedo", size, channels, Metadata::default()));
        }
        if let Some(object) = &aovs.object {
            let id = AnyChannel::new(text("object.id"), FlatSamples::U32(object.clone()));
            layers.push(layer("object", size, vec![id], Metadata::default()));
        }
        if let Some(cost) = &aovs.cost {
            let count = AnyChannel::new(text("cost.count"), FlatSamples::U32(cost.clone()));
            layers.push(layer("cost", size, vec![count], Metadata::default()));
        }
    }
    let image = Image::from_layers(ImageAttributes::new(IntegerBounds::from_dimensions(size)), layers);
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes)?;
    Ok(bytes.into_inner())
}

/// The metadata entries of an EXR file, in the order they were written (then any foreign string
/// attributes, sorted), from all parts (the first part wins on duplicates).
pub(crate) fn read_exr_metadata(path: &Path) -> Result<Metadata, exr::error::Error> {
    let meta = exr::meta::MetaData::read_from_file(path, false)?;
    let mut out = Metadata::default();
    for header in &meta.headers {
        for attrs in [&header.own_attributes.other, &header.shared_attributes.other] {
            for (key, value) in entries_of(attrs) {
                if out.get(&key).is_none() {
                    out.entries.push((key, value));
                }
            }
        }
    }
    Ok(out)
}

/// Failure to make sense of an EXR file's contents (the file itself parsed).
pub(crate) type Malformed = String;

/// Reads an EXR file back into a film and AOVs: colour from channels `R`, `G`, `B` (unqualified,
/// in an unnamed or `beauty` part), AOVs from `depth.Z`, `normal.X/Y/Z`, `albedo.R/G/B`,
/// `object.id` and `cost.count` (qualified by channel or by part name), object names from the
/// `penumbra.aov.object.legend` attribute.
pub(crate) fn decode_exr(path: &Path) -> Result<Result<(Film, Aovs), Malformed>, exr::error::Error> {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)?;
    Ok(assemble(&image.layer_data))
}

/// Collects channels by qualified name and builds the film and AOV buffers.
fn assemble(layers: &[AnyLayer]) -> Result<(Film, Aovs), Malformed> {
    let Some(first) = layers.first() else { return Err("no image parts".into()) };
    let (w, h) = (first.size.0, first.size.1);
    let n = w * h;
    let mut channels: Vec<(String, &FlatSamples)> = Vec::new();
    let mut legend = None;
    for layer in layers {
        let part = layer.attributes.layer_name.as_ref().map(untext);
        for ch in &layer.channel_data.list {
            let name = untext(&ch.name);
            let qualified = match &part {
                Some(p) if p != MAIN_LAYER && !name.contains('.') => format!("{p}.{name}"),
                _ => name,
            };
            if ch.sample_data.len() != n {
                return Err(format!("channel `{qualified}` is not {w}×{h} like the first part"));
            }
            channels.push((qualified, &ch.sample_data));
        }
        for (k, v) in entries_of(&layer.attributes.other) {
            if k == LEGEND_KEY {
                legend.get_or_insert(v);
            }
        }
    }
    let find = |name: &str| channels.iter().find(|(n, _)| n == name).map(|(_, s)| *s);
    let f32s = |s: &FlatSamples| s.values_as_f32().collect::<Vec<f32>>();
    let vec3s = |names: [&str; 3]| -> Option<Vec<Vec3>> {
        let [x, y, z] = names.map(|c| find(c).map(f32s));
        let (x, y, z) = (x?, y?, z?);
        Some((0..n).map(|i| Vec3::new(x[i], y[i], z[i])).collect())
    };
    let u32s = |s: &FlatSamples| match s {
        FlatSamples::U32(v) => v.clone(),
        other => other.values_as_f32().map(|v| v.round().max(0.0) as u32).collect(),
    };
    let pixels = vec3s(["R", "G", "B"]).ok_or("no R, G, B channels")?;
    let width = u32::try_from(w).map_err(|_| "image too wide")?;
    let height = u32::try_from(h).map_err(|_| "image too tall")?;
    let aovs = Aovs {
        width,
        height,
        depth: find("depth.Z").map(f32s),
        normal: vec3s(["normal.X", "normal.Y", "normal.Z"]),
        albedo: vec3s(["albedo.R", "albedo.G", "albedo.B"]),
        object: find("object.id").map(u32s),
        cost: find("cost.count").map(u32s),
        object_names: legend.map(|l| parse_legend(&l)).unwrap_or_default(),
    };
    Ok((Film { width, height, pixels }, aovs))
}

/// Metadata key of the object-id legend.
pub(crate) const LEGEND_KEY: &str = "penumbra.aov.object.legend";

/// The legend `1=name,2=name…` of object ids `1..=names.len()`.
pub(crate) fn legend(names: &[String]) -> String {
    names.iter().enumerate().map(|(i, name)| format!("{}={name}", i + 1)).collect::<Vec<_>>().join(",")
}

/// Parses a legend back into names by id (missing ids get empty names). A comma belongs to a
/// name unless the text after it starts with `digits=`.
pub(crate) fn parse_legend(legend: &str) -> Vec<String> {
    let mut entries: Vec<(usize, String)> = Vec::new();
    for segment in legend.split(',') {
        let id = segment.split_once('=').and_then(|(id, _)| id.parse::<usize>().ok().map(|i| (i, id.len())));
        match (id, entries.last_mut()) {
            (Some((id, len)), _) if id > 0 => entries.push((id, segment[len + 1..].to_owned())),
            (_, Some((_, name))) => {
                name.push(',');
                name.push_str(segment);
            }
            (_, None) => {}
        }
    }
    let count = entries.iter().map(|(id, _)| *id).max().unwrap_or(0);
    let mut names = vec![String::new(); count.min(1 << 20)];
    for (id, name) in entries {
        if let Some(slot) = names.get_mut(id - 1) {
            *slot = name;
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::fixtures::{random_aovs, random_film};
    use crate::film::output::{read_exr, read_metadata, write_image, OutputFormat};
    use crate::film::tonemap::ToneMapping;

    #[test]
    fn the_same_image_and_metadata_always_encode_to_the_same_bytes() {
        // Regression: one attribute per entry came out in hash-map order, different each run.
        let film = random_film(7, 5, 3);
        let mut meta = Metadata::default();
        for i in 0..12 {
            meta.set(format!("penumbra.key{i}"), format!("value {i}"));
        }
        let first = encode_exr(&film, None, false, &meta).unwrap();
        for _ in 0..8 {
            assert!(
                encode_exr(&film, None, false, &meta).unwrap() == first,
                "EXR bytes differ between encodes"
            );
        }
    }

    /// Writes `film` (and `aovs`) as EXR into a fresh folder and reads it back.
    fn round_trip(
        film: &Film,
        aovs: Option<&Aovs>,
        format: OutputFormat,
        meta: &Metadata,
    ) -> (Film, Aovs, Metadata) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame.exr");
        let written = write_image(film, aovs, &path, format, &ToneMapping::default(), meta).unwrap();
        assert_eq!(written, vec![path.clone()], "AOVs live inside the EXR");
        let (film, aovs) = read_exr(&path).unwrap();
        (film, aovs, read_metadata(&path).unwrap())
    }

    fn bits(film: &Film) -> Vec<[u32; 3]> {
        film.pixels.iter().map(|c| c.to_array().map(f32::to_bits)).collect()
    }

    #[test]
    fn float_exr_round_trips_bit_for_bit() {
        let film = random_film(37, 23, 7);
        assert!(film.pixels.iter().any(|c| c.x == 0.0) && film.pixels.iter().any(|c| c.x > 1.0));
        let (back, aovs, _) = round_trip(&film, None, OutputFormat::ExrFloat, &Metadata::default());
        assert_eq!((back.width, back.height), (37, 23));
        assert_eq!(bits(&back), bits(&film));
        assert_eq!(aovs, Aovs { width: 37, height: 23, ..Default::default() });
    }

    #[test]
    fn half_exr_is_within_half_precision() {
        let film = random_film(16, 9, 3);
        let (back, _, _) = round_trip(&film, None, OutputFormat::ExrHalf, &Metadata::default());
        for (a, b) in film.pixels.iter().zip(&back.pixels) {
            for i in 0..3 {
                assert!((a[i] - b[i]).abs() <= 1e-3 * a[i].abs() + 1e-7, "{} vs {}", a[i], b[i]);
            }
        }
    }

    #[test]
    fn aov_layers_round_trip_in_both_precisions() {
        let film = random_film(12, 10, 11);
        let aovs = random_aovs(12, 10, 5);
        assert!(aovs.depth.as_ref().unwrap().contains(&f32::INFINITY));
        let (_, back, meta) = round_trip(&film, Some(&aovs), OutputFormat::ExrFloat, &Metadata::default());
        assert_eq!(back, aovs);
        assert_eq!(meta.get(LEGEND_KEY), Some("1=floor,2=ball, red,3=Grüße 世界"));
        let (_, half, _) = round_trip(&film, Some(&aovs), OutputFormat::ExrHalf, &Metadata::default());
        // Depth stays 32-bit float and ids/costs integers even in half mode.
        assert_eq!(half.depth, aovs.depth);
        assert_eq!(half.object, aovs.object);
        assert_eq!(half.cost, aovs.cost);
        assert_eq!(half.object_names, aovs.object_names);
        for (a, b) in aovs.normal.as_ref().unwrap().iter().zip(half.normal.as_ref().unwrap()) {
            assert!((*a - *b).abs().max_element() <= 1e-3, "{a} vs {b}");
        }
        for (a, b) in aovs.albedo.as_ref().unwrap().iter().zip(half.albedo.as_ref().unwrap()) {
            assert!((*a - *b).abs().max_element() <= 1e-3, "{a} vs {b}");
        }
    }

    #[test]
    fn half_files_have_the_documented_parts_channels_and_types() {
        use exr::meta::attribute::SampleType;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("layout.exr");
        let aovs = random_aovs(4, 3, 1);
        let tone = ToneMapping::default();
        write_image(
            &random_film(4, 3, 1),
            Some(&aovs),
            &path,
            OutputFormat::ExrHalf,
            &tone,
            &Metadata::default(),
        )
        .unwrap();
        let meta = exr::meta::MetaData::read_from_file(&path, true).unwrap();
        let parts: Vec<(String, Vec<(String, SampleType)>)> = meta
            .headers
            .iter()
            .map(|h| {
                let name = h.own_attributes.layer_name.as_ref().map(untext).unwrap_or_default();
                (name, h.channels.list.iter().map(|c| (untext(&c.name), c.sample_type)).collect())
            })
            .collect();
        let f16 = SampleType::F16;
        let expect = |name: &str, chans: &[(&str, SampleType)]| {
            (name.to_owned(), chans.iter().map(|(c, t)| ((*c).to_owned(), *t)).collect::<Vec<_>>())
        };
        assert_eq!(
            parts,
            vec![
                expect("beauty", &[("B", f16), ("G", f16), ("R", f16)]),
                expect("depth", &[("depth.Z", SampleType::F32)]),
                expect("normal", &[("normal.X", f16), ("normal.Y", f16), ("normal.Z", f16)]),
                expect("albedo", &[("albedo.B", f16), ("albedo.G", f16), ("albedo.R", f16)]),
                expect("object", &[("object.id", SampleType::U32)]),
                expect("cost", &[("cost.count", SampleType::U32)]),
            ]
        );
    }

    #[test]
    fn metadata_round_trips_through_exr() {
        let mut meta = Metadata::default();
        meta.set("penumbra.seed", "42");
        meta.set("penumbra.scene", "spheres.ron");
        meta.set("Comment", "Grüße, 世界 🌍");
        for format in [OutputFormat::ExrHalf, OutputFormat::ExrFloat] {
            let (_, _, back) = round_trip(&Film::new(2, 2), None, format, &meta);
            assert_eq!(back.entries, meta.entries, "{format}: entries come back in written order");
        }
    }

    #[test]
    fn reserved_exr_attribute_names_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.exr");
        let meta = Metadata { entries: vec![("channels".into(), "RGB".into())] };
        let err =
            write_image(&Film::new(1, 1), None, &path, OutputFormat::ExrHalf, &ToneMapping::default(), &meta)
                .unwrap_err();
        assert!(err.to_string().contains("channels") && err.to_string().contains("x.exr"), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn legends_round_trip_including_commas_in_names() {
        let names: Vec<String> = ["floor", "ball, red", "a=b", "世界"].map(String::from).to_vec();
        let text = legend(&names);
        assert_eq!(text, "1=floor,2=ball, red,3=a=b,4=世界");
        assert_eq!(parse_legend(&text), names);
        assert!(parse_legend("").is_empty());
        assert_eq!(parse_legend("2=x"), vec![String::new(), "x".into()]);
    }

    #[test]
    fn exr_text_is_utf8_with_latin1_fallback() {
        assert_eq!(untext(&text("Grüße 世界")), "Grüße 世界");
        let latin1 = Text::from_bytes_unchecked(SmallVec::from_slice(&[b'c', b'a', b'f', 0xE9]));
        assert_eq!(untext(&latin1), "café");
    }
}
