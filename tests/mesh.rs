//! Meshes: smooth Phong normals, watertight intersection, the two-level grid against brute force,
//! top-level-only rebuilds, SoA = AoS bit for bit, and OBJ errors that name the file and line.

use crate::common;

use std::sync::Arc;

use common::{point_in, rng, unit_vector};
use glam::{DAffine3, DVec3};
use penumbra::camera::Camera;
use penumbra::film::encode_srgb8;
use penumbra::geom::mesh::{icosphere, MeshData};
use penumbra::geom::triangle::{intersect, WatertightRay};
use penumbra::geom::{MeshId, Shape};
use penumbra::math::{Affine3A, Quat, Ray, Vec3};
use penumbra::scene::{self, spawn_world};
use penumbra::store::{AosStore, MaterialId, MeshAsset, PlacedObject, PrimitiveStore, SoaStore};
use penumbra::testing::closest_hit_brute;
use penumbra::trace::{closest_hit, render, Light, Material, RenderSettings, SceneTables, TraceScene};
use penumbra::world::components::Transform;
use penumbra::world::SceneWorld;
use rand::RngExt;

fn asset(data: MeshData) -> Arc<MeshAsset> {
    Arc::new(MeshAsset::new("test", data, penumbra::accel::MESH_LAMBDA))
}

fn lit_tables(eye: Vec3) -> SceneTables {
    SceneTables {
        materials: vec![Material {
            kd: Vec3::new(0.7, 0.5, 0.3),
            ks: 0.4,
            shininess: 30.0,
            ..Material::default()
        }],
        lights: vec![Light::Point {
            position: Vec3::new(-3.0, 4.0, 6.0),
            radiance: Vec3::ONE,
            falloff: Default::default(),
        }],
        camera: Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 30f32.to_radians()),
        background: Vec3::ZERO,
        ambient: Vec3::splat(0.05),
    }
}

/// Every channel's bits, so that images compare bit for bit.
fn bits(film: &penumbra::film::Film) -> Vec<u32> {
    film.pixels.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect()
}

fn settings(w: u32, h: u32) -> RenderSettings {
    RenderSettings { width: w, height: h, ..RenderSettings::default() }
}

#[test]
fn a_tessellated_sphere_with_smooth_normals_matches_the_analytic_sphere_within_2_of_255() {
    // 20480 triangles, exact sphere normals at the vertices; the light is on the camera's side
    // so the terminator (where facets must differ from a sphere) is out of view.
    let eye = Vec3::new(0.0, 0.0, 5.0);
    let mut tables = lit_tables(eye);
    tables.lights = vec![Light::Point {
        position: Vec3::new(2.0, 3.0, 9.0),
        radiance: Vec3::ONE,
        falloff: Default::default(),
    }];
    let mesh = asset(icosphere(Vec3::ZERO, 1.0, 5));
    let inst = Shape::Mesh { mesh: MeshId(0), bounds: mesh.data.bounds };
    let placed = |shape: Shape| {
        vec![PlacedObject {
            geometry: shape.place(&DAffine3::IDENTITY, DVec3::ZERO),
            material: MaterialId(0),
        }]
    };
    let tess: TraceScene = TraceScene::build_with_meshes(&placed(inst), &[mesh], tables.clone(), 2.0);
    let exact: TraceScene =
        TraceScene::build(&placed(Shape::Sphere { centre: DVec3::ZERO, radius: 1.0 }), tables, 2.0);
    let (w, h) = (160, 160);
    let a = encode_srgb8(&render(&tess, &settings(w, h)).0);
    let b = encode_srgb8(&render(&exact, &settings(w, h)).0);
    // Compare pixels well inside the silhouette (where the facets' chord may differ from the
    // sphere, coverage differs, not shading).
    let (mut compared, mut worst) = (0, 0i32);
    for y in 0..h {
        for x in 0..w {
            let ray = exact.camera.ray(x as f32 + 0.5, y as f32 + 0.5, w, h);
            let Some(hit) = closest_hit(&exact, &ray, 0.0, f32::INFINITY) else { continue };
            let n = ray.at(hit.t).normalize();
            if n.dot(-ray.dir) < 0.2 {
                continue;
            }
            let i = ((y * w + x) * 3) as usize;
            for c in 0..3 {
                worst = worst.max((a[i + c] as i32 - b[i + c] as i32).abs());
            }
            compared += 1;
        }
    }
    assert!(compared > 8_000, "compared {compared} pixels");
    assert!(worst <= 2, "largest difference {worst}/255 over {compared} pixels");
}

#[test]
fn at_a_vertex_the_shading_normal_is_the_files_normal() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.5\n\
                vn 0 0 1\nvn 0.6 0 0.8\nvn 0 0.6 0.8\nvn 0.48 0.6 0.64\n\
                f 1//1 2//2 3//3\nf 2//2 4//4 3//3\n";
    let data = scene::obj::parse_obj(text, "quad.obj".as_ref(), true).unwrap();
    let mesh = asset(data.clone());
    let inst = Shape::Mesh { mesh: MeshId(0), bounds: mesh.data.bounds };
    let to_world =
        Affine3A::from_scale_rotation_translation(Vec3::splat(2.0), Quat::from_rotation_y(0.3), Vec3::X);
    let objects = vec![PlacedObject {
        geometry: inst.place(&to_world.as_daffine3(), DVec3::ZERO),
        material: MaterialId(0),
    }];
    let scene: TraceScene = TraceScene::build_with_meshes(&objects, &[mesh], lit_tables(Vec3::Z * 5.0), 2.0);
    let normal_map = to_world.matrix3.inverse().transpose();
    for (k, &p) in data.positions.iter().enumerate() {
        // Aim just inside the vertex so the ray surely hits a triangle that uses it.
        let centre = data.positions.iter().copied().sum::<Vec3>() / data.positions.len() as f32;
        let target = to_world.transform_point3(p + (centre - p) * 1e-4);
        let ray = Ray::new(target + Vec3::new(0.1, 0.2, 3.0), -Vec3::new(0.1, 0.2, 3.0).normalize());
        let hit = closest_hit(&scene, &ray, 0.0, f32::INFINITY).expect("hit");
        let got = scene.store.surface(&hit, &ray).shading;
        let want = normal_map.mul_vec3(data.normals[k]).normalize();
        assert!((got - want).length() < 2e-3, "vertex {k}: {got} vs {want}");
    }
}

#[test]
fn seeded_rays_at_a_closed_sphere_mesh_enter_exactly_once() {
    // Rays at random points, at vertices and at edge midpoints (the crack-prone places), from
    // outside: every triangle is tested (no grid), so each crossing is counted as found.
    let centre = Vec3::new(0.3, -0.2, 0.1);
    let mesh = icosphere(centre, 1.0, 3);
    let tris: Vec<[Vec3; 3]> = mesh.indices.iter().map(|f| f.map(|k| mesh.positions[k as usize])).collect();
    let mut rng = rng(7);
    let (mut crossing, mut touching) = (0u32, 0u32);
    for i in 0..100_000u32 {
        let target = match i % 3 {
            0 => mesh.positions[rng.random_range(0..mesh.positions.len())],
            1 => {
                let f = mesh.indices[rng.random_range(0..mesh.indices.len())];
                let (a, b) = (mesh.positions[f[0] as usize], mesh.positions[f[1] as usize]);
                (a + b) * 0.5
            }
            _ => centre + unit_vector(&mut rng) * rng.random_range(0.0f32..0.9),
        };
        let dir = unit_vector(&mut rng);
        let ray = Ray::new(target - dir * 4.0, dir);
        let w = WatertightRay::new(&ray);
        let mut entries = 0;
        let mut exits = 0;
        for [a, b, c] in &tris {
            if intersect(*a, *b, *c, &w, 0.0, f32::INFINITY).is_some() {
                if (*b - *a).cross(*c - *a).dot(dir) < 0.0 {
                    entries += 1;
                } else {
                    exits += 1;
                }
            }
        }
        // A ray through an inside point, or through a vertex or edge at an angle, crosses the
        // surface: once in, once out. A ray that only touches a vertex or edge of the convex
        // mesh (nearly tangent) may go either way, but never in without out.
        let outward = (target - centre).normalize();
        if i % 3 == 2 || dir.dot(outward).abs() > 0.2 {
            assert_eq!((entries, exits), (1, 1), "ray {i}: {ray:?}");
            crossing += 1;
        } else {
            assert!(entries == exits && entries <= 1, "ray {i}: {entries} in, {exits} out: {ray:?}");
            touching += 1;
        }
    }
    assert!(crossing > 80_000, "{crossing} crossing rays, {touching} near-tangent");
}

/// A random scene of instances of two meshes (rotated, non-uniformly scaled), spheres and a
/// triangle, with the meshes.
fn instanced_scene<S: PrimitiveStore>(seed: u64) -> TraceScene<S> {
    let meshes =
        vec![asset(icosphere(Vec3::ZERO, 1.0, 2)), asset(icosphere(Vec3::new(0.5, 0.0, 0.0), 0.7, 1))];
    let mut rng = rng(seed);
    let mut objects = Vec::new();
    for i in 0..30 {
        let m = i % 2;
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::new(rng.random_range(0.3..1.5), rng.random_range(0.3..1.5), rng.random_range(0.3..1.5)),
            Quat::from_axis_angle(unit_vector(&mut rng), rng.random_range(0.0..6.3)),
            point_in(&mut rng, Vec3::splat(-6.0), Vec3::splat(6.0)),
        );
        let shape = Shape::Mesh { mesh: MeshId(m as u32), bounds: meshes[m].data.bounds };
        objects.push(PlacedObject {
            geometry: shape.place(&to_world.as_daffine3(), DVec3::ZERO),
            material: MaterialId(0),
        });
    }
    for _ in 0..10 {
        let centre = point_in(&mut rng, Vec3::splat(-6.0), Vec3::splat(6.0));
        let shape = Shape::Sphere { centre: centre.as_dvec3(), radius: rng.random_range(0.2..0.8) };
        objects.push(PlacedObject {
            geometry: shape.place(&DAffine3::IDENTITY, DVec3::ZERO),
            material: MaterialId(0),
        });
    }
    TraceScene::build_with_meshes(&objects, &meshes, lit_tables(Vec3::Z * 20.0), 2.0)
}

#[test]
fn the_two_level_grid_finds_the_same_hit_as_brute_force_over_every_triangle() {
    for seed in 0..4 {
        let scene: TraceScene = instanced_scene(seed);
        let mut rng = rng(100 + seed);
        let (mut hits, mut rays) = (0, 0);
        for _ in 0..20_000 {
            let origin = point_in(&mut rng, Vec3::splat(-9.0), Vec3::splat(9.0));
            let ray = Ray::new(origin, unit_vector(&mut rng));
            let g = closest_hit(&scene, &ray, 0.0, f32::INFINITY);
            let b = closest_hit_brute(&scene, &ray, 0.0, f32::INFINITY);
            let key = |h: Option<penumbra::store::Hit>| h.map(|h| (h.t, h.object, h.prim));
            assert_eq!(key(g), key(b), "seed {seed}, ray {ray:?}");
            hits += g.is_some() as u32;
            rays += 1;
        }
        assert!(hits > rays / 20, "seed {seed}: only {hits} of {rays} rays hit");
    }
}

#[test]
fn soa_and_aos_render_identical_images() {
    for seed in 0..2 {
        let soa: TraceScene<SoaStore> = instanced_scene(seed);
        let aos: TraceScene<AosStore> = instanced_scene(seed);
        let (a, _) = render(&soa, &settings(96, 72));
        let (b, _) = render(&aos, &settings(96, 72));
        assert!(bits(&a) == bits(&b), "seed {seed}");
    }
    // The shipped bunny scene through the World, both layouts.
    let desc = scene::load_scene("scenes/bunny.ron".as_ref()).unwrap();
    let frame = |mut world_settings: RenderSettings, soa: bool| {
        world_settings.width = 80;
        world_settings.height = 60;
        if soa {
            let mut w: SceneWorld<SoaStore> = spawn_world(&desc);
            render(&w.update(), &world_settings).0
        } else {
            let mut w: SceneWorld<AosStore> = spawn_world(&desc);
            render(&w.update(), &world_settings).0
        }
    };
    let base = spawn_world::<SoaStore>(&desc).render_settings();
    assert!(bits(&frame(base, true)) == bits(&frame(base, false)));
}

#[test]
fn moving_an_instance_rebuilds_only_the_top_level_and_the_image_shows_it() {
    let desc = scene::load_scene("scenes/bunny.ron".as_ref()).unwrap();
    let mut world: SceneWorld = spawn_world(&desc);
    let mut s = world.render_settings();
    (s.width, s.height) = (96, 72);
    let before = world.update();
    let (image_before, _) = render(&before, &s);
    assert_eq!(world.grid_rebuilds(), 1);
    let bunny = world.entity("bunny").unwrap();
    world.world_mut().get_mut::<Transform>(bunny).unwrap().translation += DVec3::new(0.6, 0.0, 0.0);
    let after = world.update();
    assert_eq!(world.grid_rebuilds(), 2, "the top-level grid is rebuilt once");
    // The mesh level is untouched: the same laid-out triangles and the same mesh grid.
    let (m0, m1) = (before.store.meshes(), after.store.meshes());
    assert_eq!(m0.len(), 2);
    for (a, b) in m0.iter().zip(m1) {
        assert!(Arc::ptr_eq(a, b), "mesh layout rebuilt");
        assert!(Arc::ptr_eq(&a.asset, &b.asset), "mesh asset rebuilt");
    }
    let (image_after, _) = render(&after, &s);
    let changed = image_before.pixels.iter().zip(&image_after.pixels).filter(|(a, b)| a != b).count();
    assert!(changed > 300, "only {changed} pixels changed");
    // A frame where nothing moves rebuilds nothing.
    world.update();
    assert_eq!(world.grid_rebuilds(), 2);
}

#[test]
fn a_bad_obj_is_reported_with_the_scene_position_and_the_obj_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let scene_text = r#"Scene(
    camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 45, width: 8, height: 8),
    materials: [(name: "m", kd: (0.5, 0.5, 0.5))],
    objects: [
        (shape: Mesh(file: "bad.obj"), material: "m"),
    ],
)"#;
    let path = dir.path().join("scene.ron");
    std::fs::write(&path, scene_text).unwrap();
    let err = scene::load_scene(&path).unwrap_err().to_string();
    assert!(err.starts_with(&format!("{}:5:", path.display())), "{err}");
    assert!(err.contains("objects[0].shape.file"), "{err}");
    assert!(err.contains("bad.obj:4"), "{err}");
    // A missing file is named too.
    std::fs::write(&path, scene_text.replace("bad.obj", "missing.obj")).unwrap();
    let err = scene::load_scene(&path).unwrap_err().to_string();
    assert!(err.contains("missing.obj") && err.contains("objects[0].shape.file"), "{err}");
    // An empty mesh.
    std::fs::write(dir.path().join("bad.obj"), "# nothing\nv 0 0 0\n").unwrap();
    std::fs::write(&path, scene_text).unwrap();
    let err = scene::load_scene(&path).unwrap_err().to_string();
    assert!(err.contains("bad.obj") && err.contains("no triangles"), "{err}");
}

#[test]
fn objects_naming_the_same_mesh_share_one_asset() {
    let desc = scene::load_scene("scenes/bunny.ron".as_ref()).unwrap();
    // Three bunnies, two ways of shading them: two assets.
    assert_eq!(desc.assets.meshes.len(), 2);
    assert_eq!(desc.assets.meshes.assets()[0].data.triangle_count(), 4500);
}

#[test]
fn the_cli_renders_both_layouts_alike_and_reports_the_mesh_level() {
    let dir = tempfile::tempdir().unwrap();
    let run = |layout: &str| {
        let (png, json) =
            (dir.path().join(format!("{layout}.png")), dir.path().join(format!("{layout}.json")));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .args(["render", "scenes/bunny.ron", "--width", "64", "--layout", layout, "-o"])
            .arg(&png)
            .arg("--stats")
            .arg(&json)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        (image::open(&png).unwrap().to_rgb8().into_raw(), stats)
    };
    let (soa, stats) = run("soa");
    let (aos, aos_stats) = run("aos");
    assert!(soa == aos, "the layouts render different pixels");
    let meshes = &stats["grid"]["meshes"];
    assert_eq!(meshes["assets"], 2);
    assert_eq!(meshes["triangles"], 2 * 4500);
    assert!(meshes["grid_bytes_per_triangle"].as_f64().unwrap() > 4.0);
    let t = &stats["traversal"];
    assert_eq!(
        t["rays"],
        stats["rays"]["camera"].as_u64().unwrap()
            + stats["rays"]["shadow"].as_u64().unwrap()
            + stats["rays"]["reflection"].as_u64().unwrap()
    );
    assert!(t["cells_p99"].as_f64().unwrap() >= t["cells_mean"].as_f64().unwrap());
    assert!(t["tests_p99"].as_f64().unwrap() >= t["tests_mean"].as_f64().unwrap());
    assert!(stats["times"]["mesh_grid_build"].as_f64().unwrap() > 0.0);
    // The layouts differ in bytes, not in work.
    assert_eq!(t["tests_mean"], aos_stats["traversal"]["tests_mean"]);
}

#[test]
fn the_shipped_bunny_is_a_closed_consistently_oriented_2_manifold() {
    let mesh = penumbra::scene::obj::load_obj("scenes/bunny_res3.obj".as_ref(), false).unwrap();
    // Each directed edge appears once and its reverse once: every edge is shared by exactly two
    // faces, which run along it in opposite directions (no holes, folds or flipped faces).
    let mut directed = std::collections::HashMap::<(u32, u32), u32>::new();
    for &[a, b, c] in &mesh.indices {
        for edge in [(a, b), (b, c), (c, a)] {
            *directed.entry(edge).or_default() += 1;
        }
    }
    let unmatched =
        directed.iter().filter(|&(&(a, b), &n)| n != 1 || directed.get(&(b, a)) != Some(&1)).count();
    assert_eq!(
        unmatched,
        0,
        "{unmatched} of {} directed edges lack exactly one opposite twin",
        directed.len()
    );
    // One closed genus-0 surface (V - E + F = 2), wound counter-clockwise seen from outside.
    let (v, e, f) = (mesh.positions.len() as i64, directed.len() as i64 / 2, mesh.indices.len() as i64);
    assert_eq!(v - e + f, 2);
    let volume: f32 = mesh
        .indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!(volume > 0.0, "signed volume {volume}");
}

#[test]
fn a_scene_without_meshes_reports_plus_zero_mesh_grid_time_and_its_throughput() {
    let dir = tempfile::tempdir().unwrap();
    let (png, json) = (dir.path().join("d.png"), dir.path().join("d.json"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(["render", "scenes/default.ron", "--width", "32", "-o"])
        .arg(&png)
        .arg("--stats")
        .arg(&json)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let printed = String::from_utf8_lossy(&out.stdout);
    assert!(printed.contains("(mesh grids)") && !printed.contains("-0.00"), "{printed}");
    let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let mesh_grid_build = stats["times"]["mesh_grid_build"].as_f64().unwrap();
    assert_eq!(mesh_grid_build.to_bits(), 0.0f64.to_bits(), "{mesh_grid_build:?} is not +0.0");
    // Every ray kind the JSON lists, over the trace time.
    let rays: u64 = stats["rays"].as_object().unwrap().values().map(|n| n.as_u64().unwrap()).sum();
    let trace = stats["times"]["trace"].as_f64().unwrap();
    let mrays = stats["mrays_per_s"].as_f64().expect("the JSON has mrays_per_s");
    assert!(trace > 0.0 && rays > 0);
    let expected = rays as f64 / trace / 1e6;
    assert!((mrays - expected).abs() <= 1e-9 * expected, "{mrays} Mrays/s, expected {expected}");
}
