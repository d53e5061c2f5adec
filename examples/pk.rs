#[path = "../tests/common/mod.rs"]
mod common;
use penumbra::math::{Ray, RayPacket};
use penumbra::store::{SoaStore, TraversalCost};
use penumbra::trace::packet::{closest_hits, LANES};
use penumbra::trace::{closest_hit_costed, TraceScene};
fn main() {
    let path = common::shared_model("bunny.obj").unwrap();
    let mesh = common::mesh_asset(&path, penumbra::accel::MESH_LAMBDA);
    println!("mesh grid dims {:?} tris {}", mesh.grid.dims, mesh.data.indices.len());
    let s: TraceScene<SoaStore> = common::mesh_scene(mesh, penumbra::accel::DEFAULT_LAMBDA);
    let (w, h) = (640u32, 480u32);
    let rays: Vec<Ray> =
        (0..w * h).map(|p| s.camera.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5, w, h)).collect();
    let mut single = TraversalCost::default();
    for r in &rays {
        closest_hit_costed(&s, r, 0.0, f32::INFINITY, &mut single);
    }
    let mut packed = TraversalCost::default();
    let mut fallback = 0;
    for by in (0..h).step_by(4) {
        for bx in (0..w).step_by(4) {
            let mut p = RayPacket::<LANES>::default();
            for lane in 0..LANES {
                let (x, y) = (bx + lane as u32 % 4, by + lane as u32 / 4);
                p.set(lane, &rays[(y * w + x) as usize], 0.0, f32::INFINITY);
            }
            let _ = closest_hits(&s, &p, &mut packed);
            let _ = &mut fallback;
        }
    }
    let n = rays.len() as f64;
    println!("single: cells/ray {:.2} tests/ray {:.2}", single.cells as f64 / n, single.tests as f64 / n);
    println!("packet: cells/ray {:.3} tests/ray {:.2}", packed.cells as f64 / n, packed.tests as f64 / n);
}
