//! Renders four frames of the shipped motion-blur scene (`scripts/motion.rhai` over
//! `scenes/motion.ron`) twice, without a shutter (top row) and with the scene's 180° shutter
//! (bottom row), and prints what the blur cost: `cargo run --release --example motion_strip
//! [OUT.png]` (default `docs/motion.png`). Frames 2, 4, 6 and 8 of 24 fps: the ball streaks
//! across the view, the bar spins on its plinth and the camera pans after the ball.

use std::path::{Path, PathBuf};

use image::{imageops, ImageEncoder, RgbImage};
use penumbra::film::{encode_srgb8, write_atomically};
use penumbra::scene;
use penumbra::script::{Animation, Limits, Script};
use penumbra::trace::render;

const SIZE: (u32, u32) = (320, 180);
const FRAMES: [u32; 4] = [2, 4, 6, 8];

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args().nth(1).map_or_else(|| root.join("docs/motion.png"), PathBuf::from);
    let script = Script::load(&root.join("scripts/motion.rhai"), Limits::default())?;
    let mut strip = RgbImage::new(SIZE.0 * FRAMES.len() as u32, 2 * SIZE.1);
    for (row, shutter) in [None, Some((0.0, 0.5))].into_iter().enumerate() {
        let mut desc = scene::load_scene(&root.join("scenes/motion.ron"))?;
        (desc.camera.width, desc.camera.height) = SIZE;
        desc.camera.shutter = shutter;
        let mut animation: Animation = Animation::new(&desc, &script, 24.0)?;
        let (mut rays, mut seconds) = (0, 0.0);
        for (i, &n) in FRAMES.iter().enumerate() {
            let snapshot = animation.step_to(n)?;
            let (film, stats) = render(&snapshot, &animation.world().world().render_settings());
            rays += stats.rays.total();
            seconds += stats.times.trace;
            let tile =
                RgbImage::from_raw(SIZE.0, SIZE.1, encode_srgb8(&film)).expect("one RGB triple per pixel");
            imageops::replace(
                &mut strip,
                &tile,
                i64::from(i as u32 * SIZE.0),
                i64::from(row as u32 * SIZE.1),
            );
        }
        let label = if shutter.is_some() { "shutter (0, 0.5)" } else { "no shutter      " };
        println!("{label}: {rays} rays, {seconds:.3} s trace over {} frames", FRAMES.len());
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
