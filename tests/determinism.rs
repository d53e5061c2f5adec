//! Same scene, settings and seed give bit-identical images for any number of threads.

use penumbra::film::encode_srgb8;
use penumbra::scene;
use penumbra::trace::{render, RenderSettings};
use penumbra::world::SceneWorld;

fn render_with_threads(threads: usize, settings: RenderSettings) -> (Vec<u32>, Vec<u8>) {
    let mut world: SceneWorld = scene::spawn_world(&scene::default_scene());
    let snapshot = world.update();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    let (film, stats) = pool.install(|| render(&snapshot, &settings));
    assert_eq!(stats.threads, threads);
    let bits = film.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect();
    (bits, encode_srgb8(&film))
}

#[test]
fn one_two_and_three_threads_give_identical_bytes() {
    let mut world: SceneWorld = scene::spawn_world(&scene::default_scene());
    // Odd sizes leave partial tiles at the right and bottom edges.
    let settings = RenderSettings { width: 203, height: 117, ..world.render_settings() };
    drop(world.update());
    let (bits_1, png_1) = render_with_threads(1, settings);
    let (bits_2, png_2) = render_with_threads(2, settings);
    let (bits_3, png_3) = render_with_threads(3, settings);
    assert!(bits_1 == bits_2 && bits_2 == bits_3, "linear films differ between thread counts");
    assert!(png_1 == png_2 && png_2 == png_3, "encoded images differ between thread counts");
}
