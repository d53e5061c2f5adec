//! Renders the showcase scene with adaptive supersampling and every AOV, and tiles the image
//! and its AOV PNGs side by side: `cargo run --release --example aov_sheet [OUT.png]` (default
//! `docs/aovs.png`). Order: image, depth, normal / albedo, object, cost.
//!
//! Then the same for noise-driven sampling on `effects_soft_shadows` (batches of one AA
//! sample, target 0.01): the image beside its cost AOV, in `docs/noise_cost.png` (or beside
//! OUT, as `OUT-noise.png`): the samples gather at the silhouettes.

use std::path::{Path, PathBuf};

use anyhow::Context;
use image::{imageops, ImageEncoder, RgbImage};
use penumbra::film::{write_atomically, write_image, AovSet, Metadata, OutputFormat, ToneMapping};
use penumbra::sample::NoiseSettings;
use penumbra::scene::{self, AdaptiveSettings, SceneDesc};
use penumbra::trace::render_with_aovs;
use penumbra::world::SceneWorld;

const SIZE: (u32, u32) = (320, 240);

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args().nth(1).map_or_else(|| root.join("docs/aovs.png"), PathBuf::from);
    let noise_out = match std::env::args().nth(1) {
        Some(_) => out.with_file_name(format!(
            "{}-noise.png",
            out.file_stem().map_or("sheet".into(), |s| s.to_string_lossy())
        )),
        None => root.join("docs/noise_cost.png"),
    };

    let mut desc = scene::load_scene(&root.join("scenes/showcase.ron"))?;
    desc.settings.adaptive = Some(AdaptiveSettings { threshold: 0.05, max_depth: 3 });
    let all = AovSet { depth: true, normal: true, albedo: true, object: true, cost: true };
    let names = ["", "depth", "normal", "albedo", "object", "cost"];
    sheet(&mut desc, all, &names, 3, &out)?;

    let mut desc = scene::load_scene(&root.join("scenes/effects_soft_shadows.ron"))?;
    desc.settings.aa.samples = 1;
    desc.settings.noise = Some(NoiseSettings { target_error: 0.01, ..NoiseSettings::default() });
    sheet(&mut desc, AovSet { cost: true, ..AovSet::default() }, &["", "cost"], 2, &noise_out)
}

/// Renders `desc` at [`SIZE`] with the AOVs `wanted` and writes the image and the AOVs named
/// in `names` (`""` the image itself) tiled `columns` wide to `out`.
fn sheet(
    desc: &mut SceneDesc,
    wanted: AovSet,
    names: &[&str],
    columns: u32,
    out: &Path,
) -> anyhow::Result<()> {
    (desc.camera.width, desc.camera.height) = SIZE;
    let mut world: SceneWorld = scene::spawn_world(desc);
    let snapshot = world.update();
    let (film, aovs, stats) = render_with_aovs(&snapshot, &world.render_settings(), wanted);
    println!("{}", stats.summary());

    let dir = tempfile::tempdir()?;
    let tone = ToneMapping::default();
    let files = write_image(
        &film,
        aovs.as_ref(),
        &dir.path().join("sheet.png"),
        OutputFormat::Png8,
        &tone,
        &Metadata::default(),
    )?;
    let rows = (names.len() as u32).div_ceil(columns);
    let mut sheet = RgbImage::new(SIZE.0 * columns, SIZE.1 * rows);
    for (i, name) in names.iter().enumerate() {
        let file = match *name {
            "" => "sheet.png".to_owned(),
            aov => format!("sheet.{aov}.png"),
        };
        let path =
            files.iter().find(|p| p.ends_with(&file)).with_context(|| format!("{file} was not written"))?;
        let tile = image::open(path)?.to_rgb8();
        let (x, y) = (i as u32 % columns * SIZE.0, i as u32 / columns * SIZE.1);
        imageops::replace(&mut sheet, &tile, i64::from(x), i64::from(y));
    }
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png).write_image(
        sheet.as_raw(),
        sheet.width(),
        sheet.height(),
        image::ExtendedColorType::Rgb8,
    )?;
    write_atomically(out, &png)?;
    println!("wrote {}", out.display());
    Ok(())
}
