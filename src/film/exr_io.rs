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

/// A named part with the given channels (sorted, as the format requires).
fn layer(name: &str, size: Vec2<usize>, channels: Vec<AnyChannel<FlatSamples>>, other: Metadata) -> AnyLayer {
    let mut attributes = LayerAttributes::named(text(name));
    for (k, v) in other.entries {
        attributes.other.insert(text(&k), AttributeValue::Text(text(&v)));
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

/// The metadata entries of an EXR file: every string attribute outside the reserved names, from
/// all parts (the first part wins on duplicates), sorted by key.
pub(crate) fn read_exr_metadata(path: &Path) -> Result<Metadata, exr::error::Error> {
    let meta = exr::meta::MetaData::read_from_file(path, false)?;
    let mut out = Metadata::default();
    for header in &meta.headers {
        for attrs in [&header.own_attributes.other, &header.shared_attributes.other] {
            for (name, value) in attrs {
                let key = untext(name);
                if let (AttributeValue::Text(v), None) = (value, out.get(&key)) {
                    out.entries.push((key, untext(v)));
                }
            }
        }
    }
    out.entries.sort();
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
        for (k, v) in &layer.attributes.other {
            if let (true, AttributeValue::Text(t)) = (untext(k) == LEGEND_KEY, v) {
                legend.get_or_insert_with(|| untext(t));
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
