#[path = "../tests/common/mod.rs"]
mod common;
use penumbra::math::{Ray, RayPacket};
use penumbra::simd::SimdLevel;
use penumbra::store::{SoaStore, TraversalCost};
use penumbra::trace::packet::{closest_hits, LANES};
use penumbra::trace::{closest_hit_costed, TraceScene};
fn main() {
    let mode = std::env::args().nth(1).unwrap();
    let path = common::shared_model("bunny.obj").unwrap();
    let mesh = common::mesh_asset(&path, penumbra::accel::MESH_LAMBDA);
    let s: TraceScene<SoaStore> = common::mesh_scene(mesh, penumbra::accel::DEFAULT_LAMBDA);
    let (w, h) = (640u32, 480u32);
    let rays: Vec<Ray> =
        (0..w * h).map(|p| s.camera.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5, w, h)).collect();
    let t = std::time::Instant::now();
    let level = SimdLevel::Auto.resolve();
    let mut found = 0;
    for _ in 0..5 {
        if mode == "single" {
            for r in &rays {
                found += closest_hit_costed(&s, r, 0.0, f32::INFINITY, &mut TraversalCost::default())
                    .is_some() as u32;
            }
        } else {
            for by in (0..h).step_by(4) {
                for bx in (0..w).step_by(4) {
                    let mut p = RayPacket::<LANES>::default();
                    for lane in 0..LANES {
                        let (x, y) = (bx + lane as u32 % 4, by + lane as u32 / 4);
                        p.set(lane, &rays[(y * w + x) as usize], 0.0, f32::INFINITY);
                    }
                    let hits = level.run(
                        #[inline(always)]
                        || closest_hits(&s, &p, &mut TraversalCost::default()),
                    );
                    found += hits.hit.iter().filter(|h| h.is_some()).count() as u32;
                }
            }
        }
    }
    println!("{mode} {found} {:.3}s", t.elapsed().as_secs_f64());
}
