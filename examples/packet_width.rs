//! Which packet shape pays: camera rays of the full bunny and dragon (ANCHORS.md's mesh scene,
//! 640×480) traced as packets of 4×2, 4×4, 8×2, 8×4 and 8×8 pixels at the best SIMD level, one
//! thread, interleaved, medians of 7 (Mrays/s). Reads the models from `../shared/models/` and
//! skips those that are absent. Run: `cargo run --release --example packet_width`.

#[path = "../tests/common/mod.rs"]
mod common;

use penumbra::math::{Ray, RayPacket};
use penumbra::simd::SimdLevel;
use penumbra::store::{SoaStore, TraversalCost};
use penumbra::trace::packet::closest_hits;
use penumbra::trace::TraceScene;

/// Seconds to trace `rays` (`w × h`, row-major) in packets of `N` rays, `bw` pixels wide.
fn time<const N: usize>(scene: &TraceScene<SoaStore>, rays: &[Ray], w: u32, h: u32, bw: u32) -> f64 {
    let bh = N as u32 / bw;
    let level = SimdLevel::Auto.resolve();
    let started = std::time::Instant::now();
    for by in (0..h).step_by(bh as usize) {
        for bx in (0..w).step_by(bw as usize) {
            let mut p = RayPacket::<N>::default();
            for lane in 0..N {
                let (x, y) = (bx + lane as u32 % bw, by + lane as u32 / bw);
                if x < w && y < h {
                    p.set(lane, &rays[(y * w + x) as usize], 0.0, f32::INFINITY);
                }
            }
            std::hint::black_box(level.run(
                #[inline(always)]
                || closest_hits(scene, &p, &mut TraversalCost::default()),
            ));
        }
    }
    started.elapsed().as_secs_f64()
}

fn main() {
    let (w, h) = (640u32, 480u32);
    for model in ["bunny.obj", "dragon.obj"] {
        let Some(path) = common::shared_model(model) else {
            eprintln!("packet_width: ../shared/models/{model} not found; skipping it");
            continue;
        };
        let mesh = common::mesh_asset(&path, penumbra::accel::MESH_LAMBDA);
        let scene: TraceScene<SoaStore> = common::mesh_scene(mesh, penumbra::accel::DEFAULT_LAMBDA);
        let rays: Vec<Ray> =
            (0..w * h).map(|p| scene.camera.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5, w, h)).collect();
        let shapes = ["4x2", "4x4", "8x2", "8x4", "8x8"];
        let mut times: [Vec<f64>; 5] = Default::default();
        for _ in 0..7 {
            times[0].push(time::<8>(&scene, &rays, w, h, 4));
            times[1].push(time::<16>(&scene, &rays, w, h, 4));
            times[2].push(time::<16>(&scene, &rays, w, h, 8));
            times[3].push(time::<32>(&scene, &rays, w, h, 8));
            times[4].push(time::<64>(&scene, &rays, w, h, 8));
        }
        for (shape, t) in shapes.iter().zip(&mut times) {
            t.sort_by(f64::total_cmp);
            println!("{model} {shape}: {:.2} Mrays/s", rays.len() as f64 / t[3] / 1e6);
        }
    }
}
