//! Renders every effect scene (`scenes/effects_*.ron` and `scenes/showcase.ron`) at a small
//! size and tiles them into one PNG: `cargo run --release --example contact_sheet [OUT.png]`
//! (default `docs/effects.png`). Tiles are in file-name order, left to right, top to bottom.

use std::path::{Path, PathBuf};

use anyhow::Context;
use image::{imageops, ImageEncoder, RgbImage};
use penumbra::film::{encode_srgb8, write_atomically};
use penumbra::scene;
use penumbra::trace::render;
use penumbra::world::SceneWorld;

const TILE: (u32, u32) = (320, 240);
const COLUMNS: u32 = 3;

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args().nth(1).map_or_else(|| root.join("docs/effects.png"), PathBuf::from);
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(root.join("scenes"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            (name.starts_with("effects_") || name == "showcase.ron") && name.ends_with(".ron")
        })
        .collect();
    scenes.sort();
    let rows = (scenes.len() as u32).div_ceil(COLUMNS);
    let mut sheet = RgbImage::new(TILE.0 * COLUMNS, TILE.1 * rows);
    for (i, path) in scenes.iter().enumerate() {
        let mut desc = scene::load_scene(path)?;
        (desc.camera.width, desc.camera.height) = TILE;
        let mut world: SceneWorld = scene::spawn_world(&desc);
        let snapshot = world.update();
        let (film, stats) = render(&snapshot, &world.render_settings());
        println!(
            "{:<40} {:>8.1} ms {:>10} rays",
            path.display(),
            stats.times.trace * 1e3,
            stats.rays.total()
        );
        let tile = RgbImage::from_raw(film.width, film.height, encode_srgb8(&film)).context("tile size")?;
        let (x, y) = (i as u32 % COLUMNS * TILE.0, i as u32 / COLUMNS * TILE.1);
        imageops::replace(&mut sheet, &tile, i64::from(x), i64::from(y));
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
