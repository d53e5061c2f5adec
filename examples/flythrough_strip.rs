//! Renders four frames of the shipped fly-through (`scripts/flythrough.rhai` over
//! `scenes/flythrough.ron`) side by side: `cargo run --release --example flythrough_strip
//! [OUT.png]` (default `docs/flythrough.png`). Frames 0, 40, 80 and 119 of 24 fps: the
//! camera glides down the avenue while the focus stays on the bouncing orange ball.

use std::path::{Path, PathBuf};

use image::{imageops, ImageEncoder, RgbImage};
use penumbra::film::{encode_srgb8, write_atomically};
use penumbra::scene;
use penumbra::script::{Animation, Limits, Script};
use penumbra::trace::render;

const SIZE: (u32, u32) = (320, 180);
const FRAMES: [u32; 4] = [0, 40, 80, 119];

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args().nth(1).map_or_else(|| root.join("docs/flythrough.png"), PathBuf::from);
    let mut desc = scene::load_scene(&root.join("scenes/flythrough.ron"))?;
    (desc.camera.width, desc.camera.height) = SIZE;
    desc.settings.aa.samples = 4;
    let script = Script::load(&root.join("scripts/flythrough.rhai"), Limits::default())?;
    let mut animation: Animation = Animation::new(&desc, &script, 24.0)?;

    let mut strip = RgbImage::new(SIZE.0 * FRAMES.len() as u32, SIZE.1);
    for (i, &n) in FRAMES.iter().enumerate() {
        let snapshot = animation.step_to(n)?;
        let (film, stats) = render(&snapshot, &animation.world().world().render_settings());
        println!("frame {n:>3}: {} rays, {:.3} s", stats.rays.total(), stats.times.trace);
        let pixels = encode_srgb8(&film);
        let tile = RgbImage::from_raw(SIZE.0, SIZE.1, pixels).expect("one RGB triple per pixel");
        imageops::replace(&mut strip, &tile, i64::from(i as u32 * SIZE.0), 0);
    }
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png).write_image(
        strip.as_raw(),
        strip.width(),
        strip.height(),
        image::ExtendedColorType::Rgb8,
    )?;
    write_atomically(&out, &png)?;
    println!("wrote {}", out.display());
    Ok(())
}
