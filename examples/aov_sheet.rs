//! Renders the showcase scene with adaptive supersampling and every AOV, and tiles the image
//! and its AOV PNGs side by side: `cargo run --release --example aov_sheet [OUT.png]` (default
//! `docs/aovs.png`). Order: image, depth, normal / albedo, object, cost.

use std::path::{Path, PathBuf};

use anyhow::Context;
use image::{imageops, ImageEncoder, RgbImage};
use penumbra::film::{write_atomically, write_image, AovSet, Metadata, OutputFormat, ToneMapping};
use penumbra::scene::{self, AdaptiveSettings};
use penumbra::trace::render_with_aovs;
use penumbra::world::SceneWorld;

const SIZE: (u32, u32) = (320, 240);

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args().nth(1).map_or_else(|| root.join("docs/aovs.png"), PathBuf::from);
    let mut desc = scene::load_scene(&root.join("scenes/showcase.ron"))?;
    (desc.camera.width, desc.camera.height) = SIZE;
    desc.settings.adaptive = Some(AdaptiveSettings { threshold: 0.05, max_depth: 3 });
    let mut world: SceneWorld = scene::spawn_world(&desc);
    let snapshot = world.update();
    let all = AovSet { depth: true, normal: true, albedo: true, object: true, cost: true };
    let (film, aovs, stats) = render_with_aovs(&snapshot, &world.render_settings(), all);
    println!("{}", stats.summary());

    let dir = tempfile::tempdir()?;
    let tone = ToneMapping::default();
    let files = write_image(
        &film,
        aovs.as_ref(),
        &dir.path().join("showcase.png"),
        OutputFormat::Png8,
        &tone,
        &Metadata::default(),
    )?;
    let mut sheet = RgbImage::new(SIZE.0 * 3, SIZE.1 * 2);
    for (i, name) in [
        "showcase.png",
        "showcase.depth.png",
        "showcase.normal.png",
        "showcase.albedo.png",
        "showcase.object.png",
        "showcase.cost.png",
    ]
    .iter()
    .enumerate()
    {
        let path =
            files.iter().find(|p| p.ends_with(name)).with_context(|| format!("{name} was not written"))?;
        let tile = image::open(path)?.to_rgb8();
        imageops::replace(
            &mut sheet,
            &tile,
            i64::from(i as u32 % 3 * SIZE.0),
            i64::from(i as u32 / 3 * SIZE.1),
        );
    }
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png).write_image(
        sheet.as_raw(),
        sheet.width(),
        sheet.height(),
        image::ExtendedColorType::Rgb8,
    )?;
    write_atomically(&out, &png)?;
    println!("wrote {}", out.display());
    Ok(())
}
