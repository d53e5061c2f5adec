//! Question: when one object moves among many mesh instances, what does the frame's rebuild
//! cost next to building everything again?
//!
//! Scene: 100 instances of the full Stanford bunny (69,451 triangles; from `../shared/models/`,
//! or the shipped 4,500-triangle `scenes/bunny_res3.obj` when that is absent) on a 10×10 lattice
//! with random rotations, through the ECS World. Each iteration moves one bunny (the camera stays
//! still: a moving camera places every object anew, since snapshots are relative to it) and runs
//! the frame schedule: `update_bounds`, `rebuild_grid` (the top level over 100 instances) and
//! `build_snapshot`. The full rebuild is what the frame would cost if the moved mesh's grid had
//! to be rebuilt too (the mesh grid plus the top level): the cost a single-level grid over
//! world-space triangles pays on every move, at the least.
//!
//! Groups `rebuild/top_level` and `rebuild/full`; then a table with the ratio (target < 1 %).
//!
//! Run: `cargo bench --bench rebuild`.

#[path = "../tests/common/mod.rs"]
mod common;
mod harness;

use std::fmt::Write;
use std::hint::black_box;
use std::path::PathBuf;

use criterion::Criterion;
use harness::rays::median;
use penumbra::accel::{GridBuilder, DEFAULT_LAMBDA, MESH_LAMBDA};
use penumbra::scene::{parse_scene_at, spawn_world, SceneDesc};
use penumbra::store::{MeshAsset, PrimitiveStore};
use penumbra::world::components::Transform;
use penumbra::world::SceneWorld;
use rand::RngExt;

const INSTANCES: usize = 100;

fn bunny_path() -> PathBuf {
    common::shared_model("bunny.obj").unwrap_or_else(|| {
        eprintln!("rebuild: ../shared/models/bunny.obj not found; using scenes/bunny_res3.obj");
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny_res3.obj")
    })
}

/// 100 bunnies as a scene description (so they go through the loader and the World).
fn scene() -> SceneDesc {
    let path = bunny_path();
    let mut rng = common::rng(100);
    let mut objects = String::new();
    for i in 0..INSTANCES {
        let (x, z) = ((i % 10) as f32 * 3.0 - 13.5, (i / 10) as f32 * 3.0 - 13.5);
        let yaw: f32 = rng.random_range(0.0..360.0);
        let _ = writeln!(
            objects,
            "(name: \"bunny_{i}\", shape: Mesh(file: {:?}), material: \"m\", \
             transform: (translate: ({x}, 0, {z}), rotate_deg: (0, {yaw}, 0), scale: (15, 15, 15))),",
            path.display().to_string()
        );
    }
    let text = format!(
        "Scene(camera: (position: (0, 20, -40), look_at: (0, 0, 0), fov_deg: 40, width: 64, height: 48),
               materials: [(name: \"m\", kd: (0.7, 0.6, 0.5))],
               lights: [Point(position: (0, 30, -10))],
               objects: [{objects}])"
    );
    parse_scene_at(&text, "rebuild bench", std::path::Path::new(".")).expect("bench scene is valid")
}

/// Moves bunny 0 back and forth by `dx` and runs the frame schedule.
fn move_one(world: &mut SceneWorld, bunny: bevy_ecs::entity::Entity, step: &mut f32) -> usize {
    *step = -*step;
    world.world_mut().get_mut::<Transform>(bunny).expect("bunny").translation.x += f64::from(*step);
    world.update().store.bounded_count() as usize
}

/// What a move would cost if the mesh's grid had to be rebuilt too.
fn full(desc: &SceneDesc, world: &SceneWorld) -> usize {
    let data = desc.assets.meshes.assets()[0].data.clone();
    let asset = MeshAsset::new("bench", data, MESH_LAMBDA);
    let index = world.world().resource::<penumbra::world::resources::GridIndex>();
    let bounds: Vec<_> = index
        .entities
        .iter()
        .map(|&e| world.world().get::<penumbra::world::components::WorldAabb>(e).expect("aabb").0)
        .collect();
    let top = GridBuilder::new(DEFAULT_LAMBDA).build(&bounds, |_, _| true);
    asset.grid.reference_count() + top.reference_count()
}

fn main() {
    let desc = scene();
    let mut world: SceneWorld = spawn_world(&desc);
    world.update();
    let bunny = world.entity("bunny_0").expect("bunny_0");
    let mut step = 0.5f32;
    harness::run(
        10,
        |c: &mut Criterion| {
            let mut group = c.benchmark_group("rebuild");
            group.bench_function("top_level", |b| b.iter(|| move_one(&mut world, bunny, &mut step)));
            group.bench_function("full", |b| b.iter(|| full(black_box(&desc), &world)));
            group.finish();
        },
        || {
            let mut world: SceneWorld = spawn_world(&desc);
            world.update();
            let bunny = world.entity("bunny_0").expect("bunny_0");
            let mut step = 0.5f32;
            let before = world.grid_rebuilds();
            let top = median(21, || move_one(&mut world, bunny, &mut step)).as_secs_f64();
            let rebuilds = world.grid_rebuilds() - before;
            let clock = world.stage_clock();
            let full = median(5, || full(&desc, &world)).as_secs_f64();
            let asset = &desc.assets.meshes.assets()[0];
            println!(
                "\nrebuild: {INSTANCES} instances of a {}-triangle mesh; one moves per frame ({rebuilds} top-level rebuilds in 21 frames, 0 mesh-grid rebuilds)",
                asset.data.triangle_count()
            );
            println!("  frame after a move (bounds + top-level grid + snapshot): {:.3} ms (median of 21; last frame: grid {:.3} ms, snapshot {:.3} ms)", top * 1e3, clock.grid_build * 1e3, clock.snapshot * 1e3);
            println!(
                "  full rebuild (mesh grid + top level):                     {:.3} ms (median of 5)",
                full * 1e3
            );
            println!("  ratio: {:.3} % (target < 1 %)", 100.0 * top / full);
        },
    );
}
