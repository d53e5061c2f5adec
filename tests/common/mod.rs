//! Shared, seeded fixtures for the integration tests and benches (in the spirit of bvh's
//! `testbase.rs`): random scenes as `Vec<PlacedObject>`, simple tables, and snapshot builders.
//!
//! Every generator is a pure function of its seed, so a failure names the seed that shows it.

use glam::{DAffine3, DVec3};
use penumbra::camera::Camera;
use penumbra::geom::Shape;
use penumbra::math::{Affine3A, Quat, Vec3};
use penumbra::store::{MaterialId, PlacedObject};
use penumbra::trace::{Material, SceneTables, TraceScene};
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};

/// The seeded generator every fixture uses.
#[allow(dead_code)]
pub fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// A uniformly random point in the box `[lo, hi]`.
#[allow(dead_code)]
pub fn point_in(rng: &mut StdRng, lo: Vec3, hi: Vec3) -> Vec3 {
    Vec3::new(
        lo.x + (hi.x - lo.x) * rng.random::<f32>(),
        lo.y + (hi.y - lo.y) * rng.random::<f32>(),
        lo.z + (hi.z - lo.z) * rng.random::<f32>(),
    )
}

/// A uniformly random unit vector (rejection sampling in the unit ball).
#[allow(dead_code)]
pub fn unit_vector(rng: &mut StdRng) -> Vec3 {
    loop {
        let v = point_in(rng, Vec3::splat(-1.0), Vec3::ONE);
        let l2 = v.length_squared();
        if l2 > 1e-4 && l2 <= 1.0 {
            return v / l2.sqrt();
        }
    }
}

fn object(shape: Shape, to_world: &Affine3A, material: u32) -> PlacedObject {
    PlacedObject {
        geometry: shape.place(&to_world.as_daffine3(), DVec3::ZERO),
        material: MaterialId(material),
    }
}

/// `n` spheres with centres uniform in `[-extent/2, extent/2]³` and radii a random fraction
/// (0.1–0.4) of the mean spacing `extent / ∛n`, so density stays similar for every `n`.
#[allow(dead_code)]
pub fn random_spheres(seed: u64, n: usize, extent: f32) -> Vec<PlacedObject> {
    let mut rng = rng(seed);
    let half = Vec3::splat(0.5 * extent);
    let spacing = extent / (n.max(1) as f32).cbrt();
    (0..n)
        .map(|_| {
            let centre = point_in(&mut rng, -half, half);
            let radius = spacing * rng.random_range(0.1f32..0.4);
            object(Shape::Sphere { centre: centre.as_dvec3(), radius }, &Affine3A::IDENTITY, 0)
        })
        .collect()
}

/// `n` random triangles in `[-extent/2, extent/2]³`, each about one mean spacing across.
#[allow(dead_code)]
pub fn random_triangles(seed: u64, n: usize, extent: f32) -> Vec<PlacedObject> {
    let mut rng = rng(seed);
    let half = Vec3::splat(0.5 * extent);
    let spacing = extent / (n.max(1) as f32).cbrt();
    (0..n)
        .map(|_| {
            let c = point_in(&mut rng, -half, half);
            let vertices =
                [0; 3].map(|_| c + unit_vector(&mut rng) * spacing * rng.random_range(0.2f32..0.6));
            object(Shape::Triangle { vertices: vertices.map(Vec3::as_dvec3) }, &Affine3A::IDENTITY, 0)
        })
        .collect()
}

/// A random convex polygon: `k` points on an ellipse in a random plane around `c`.
fn random_polygon(rng: &mut StdRng, c: Vec3, size: f32) -> Shape {
    let n = unit_vector(rng);
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let (a, b) = (size * rng.random_range(0.3f32..1.0), size * rng.random_range(0.3f32..1.0));
    let k = rng.random_range(4usize..8);
    let phase = rng.random::<f32>() * std::f32::consts::TAU;
    let vertices = (0..k)
        .map(|i| {
            let ang = phase + i as f32 / k as f32 * std::f32::consts::TAU;
            (c + u * (a * ang.cos()) + v * (b * ang.sin())).as_dvec3()
        })
        .collect();
    Shape::Polygon { vertices }
}

/// A mixed scene of `n` bounded objects in `[-extent/2, extent/2]³`: spheres, triangles,
/// polygons and rotated, non-uniformly scaled boxes (all placed through [`Shape::place`]),
/// plus one or two planes outside the cloud. Materials cycle over `materials` ids.
#[allow(dead_code)]
pub fn random_mixed_in(seed: u64, n: usize, extent: f32, materials: u32) -> Vec<PlacedObject> {
    let mut rng = rng(seed);
    let half = Vec3::splat(0.5 * extent);
    let size = extent / (n.max(1) as f32).cbrt();
    let mut objects: Vec<PlacedObject> = (0..n)
        .map(|_| {
            let c = point_in(&mut rng, -half, half);
            let m = rng.random_range(0..materials.max(1));
            match rng.random_range(0..4) {
                0 => {
                    let radius = size * rng.random_range(0.1f32..0.5);
                    object(Shape::Sphere { centre: c.as_dvec3(), radius }, &Affine3A::IDENTITY, m)
                }
                1 => {
                    let vertices =
                        [0; 3].map(|_| c + unit_vector(&mut rng) * size * rng.random_range(0.2f32..0.8));
                    object(Shape::Triangle { vertices: vertices.map(Vec3::as_dvec3) }, &Affine3A::IDENTITY, m)
                }
                2 => object(random_polygon(&mut rng, c, size * 0.6), &Affine3A::IDENTITY, m),
                _ => {
                    let axis = unit_vector(&mut rng);
                    let rot = Quat::from_axis_angle(axis, rng.random::<f32>() * std::f32::consts::TAU);
                    let scale = Vec3::new(
                        rng.random_range(0.5f32..2.0),
                        rng.random_range(0.5f32..2.0),
                        rng.random_range(0.5f32..2.0),
                    );
                    let to_world = Affine3A::from_scale_rotation_translation(scale * size * 0.3, rot, c);
                    object(Shape::Cuboid { min: DVec3::splat(-0.5), max: DVec3::splat(0.5) }, &to_world, m)
                }
            }
        })
        .collect();
    // A floor below the cloud, and sometimes a tilted back wall.
    let floor = Shape::Plane { point: DVec3::new(0.0, -0.75 * f64::from(extent), 0.0), normal: Vec3::Y };
    objects.push(object(floor, &Affine3A::IDENTITY, 0));
    if rng.random::<bool>() {
        let normal = Vec3::new(0.2, 0.1, -1.0);
        let wall = Shape::Plane { point: DVec3::new(0.0, 0.0, 1.5 * f64::from(extent)), normal };
        objects.push(object(wall, &Affine3A::IDENTITY, 0));
    }
    objects
}

/// [`random_mixed_in`] over a 10-unit cloud with a single material.
#[allow(dead_code)]
pub fn random_mixed(seed: u64, n: usize) -> Vec<PlacedObject> {
    random_mixed_in(seed, n, 10.0, 1)
}

/// Tables with the given materials, no lights, and a camera looking at the origin from `eye`.
#[allow(dead_code)]
pub fn tables_with(materials: Vec<Material>, eye: Vec3) -> SceneTables {
    SceneTables {
        materials,
        lights: Vec::new(),
        camera: Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 60f32.to_radians()),
        background: Vec3::ZERO,
        ambient: Vec3::ZERO,
    }
}

/// One default (opaque) material, no lights, camera on +z.
#[allow(dead_code)]
pub fn simple_tables() -> SceneTables {
    tables_with(vec![Material::default()], Vec3::new(0.0, 0.0, 30.0))
}

/// A snapshot of `objects` with [`simple_tables`] and grid density `lambda`.
#[allow(dead_code)]
pub fn scene(objects: &[PlacedObject], lambda: f32) -> TraceScene {
    TraceScene::build(objects, simple_tables(), lambda)
}

/// A model from `../shared/models/` (beside the repository), if present: benches use the full
/// bunny, dragon and teapot from there and skip them with a note when absent.
#[allow(dead_code)]
pub fn shared_model(file: &str) -> Option<std::path::PathBuf> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models").join(file);
    path.exists().then_some(path)
}

/// A mesh asset loaded from `path` with smooth normals and grid density `lambda`.
#[allow(dead_code)]
pub fn mesh_asset(path: &std::path::Path, lambda: f32) -> std::sync::Arc<penumbra::store::MeshAsset> {
    let data = penumbra::scene::obj::load_obj(path, true).expect("model loads");
    std::sync::Arc::new(penumbra::store::MeshAsset::new(path.display().to_string(), data, lambda))
}

/// The map that scales a mesh's bounds to a largest extent of `extent`, centred on the y axis
/// and resting on y = 0 (ANCHORS.md's mesh scenes use 2.4).
#[allow(dead_code)]
pub fn fit_on_ground(bounds: &penumbra::math::Aabb, extent: f32) -> Affine3A {
    let scale = extent / bounds.extent().max_element();
    let centre = (bounds.min + bounds.max) * 0.5;
    let offset = Vec3::new(-centre.x * scale, -bounds.min.y * scale, -centre.z * scale);
    Affine3A::from_scale_rotation_translation(Vec3::splat(scale), Quat::IDENTITY, offset)
}

/// ANCHORS.md's mesh scene: the mesh fitted to extent 2.4 on a ground plane, one point light,
/// Phong, a camera framing it (640×480 is what the anchors use).
#[allow(dead_code)]
pub fn mesh_scene<S: penumbra::store::PrimitiveStore>(
    mesh: std::sync::Arc<penumbra::store::MeshAsset>,
    lambda: f32,
) -> TraceScene<S> {
    let to_world = fit_on_ground(&mesh.data.bounds, 2.4);
    let shape = Shape::Mesh { mesh: penumbra::geom::MeshId(0), bounds: mesh.data.bounds };
    let objects = vec![
        PlacedObject {
            geometry: Shape::Plane { point: DVec3::ZERO, normal: Vec3::Y }
                .place(&DAffine3::IDENTITY, DVec3::ZERO),
            material: MaterialId(0),
        },
        PlacedObject { geometry: shape.place(&to_world.as_daffine3(), DVec3::ZERO), material: MaterialId(1) },
    ];
    let tables = SceneTables {
        materials: vec![
            Material { kd: Vec3::splat(0.5), ..Material::default() },
            Material { kd: Vec3::new(0.75, 0.62, 0.5), ks: 0.4, shininess: 50.0, ..Material::default() },
        ],
        lights: vec![penumbra::trace::Light::Point {
            position: MESH_LIGHT,
            radiance: Vec3::ONE,
            falloff: Default::default(),
        }],
        camera: Camera::look_at(
            Vec3::new(0.0, 1.6, -4.6),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            40f32.to_radians(),
        ),
        background: Vec3::new(0.6, 0.7, 0.85),
        ambient: Vec3::splat(0.1),
    };
    TraceScene::build_with_meshes(&objects, &[mesh], tables, lambda)
}

/// The point light of [`mesh_scene`].
#[allow(dead_code)]
pub const MESH_LIGHT: Vec3 = Vec3::new(-3.0, 6.0, -5.0);

/// Proptest strategies shared by the property tests: scenes of spheres, boxes, triangles and
/// mesh instances, and rays.
#[allow(dead_code)]
pub mod strategies {
    use std::sync::Arc;

    use proptest::prelude::*;

    use penumbra::geom::mesh::icosphere;
    use penumbra::geom::{MeshId, Shape};
    use penumbra::math::{Affine3A, Quat, Ray, Vec3};
    use penumbra::store::{MaterialId, MeshAsset, PlacedObject};
    use penumbra::trace::TraceScene;

    /// A point in `[-r, r]³`.
    pub fn point(r: f32) -> impl Strategy<Value = Vec3> {
        (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    /// A unit vector (zero components and `-0.0` included now and then).
    pub fn direction() -> impl Strategy<Value = Vec3> {
        let component = prop_oneof![8 => -1.0f32..1.0, 1 => Just(0.0f32), 1 => Just(-0.0f32)];
        (component.clone(), component.clone(), component)
            .prop_filter_map("non-zero", |(x, y, z)| Vec3::new(x, y, z).try_normalize())
    }

    /// A ray starting in `[-r, r]³`.
    pub fn ray(r: f32) -> impl Strategy<Value = Ray> {
        (point(r), direction()).prop_map(|(o, d)| Ray::new(o, d))
    }

    /// An object-to-world map: translation in `[-r, r]³`, any rotation, scale 0.3–2 per axis.
    pub fn placement(r: f32) -> impl Strategy<Value = Affine3A> {
        (point(r), direction(), 0.0f32..6.3, (0.3f32..2.0, 0.3f32..2.0, 0.3f32..2.0)).prop_map(
            |(t, axis, angle, (sx, sy, sz))| {
                Affine3A::from_scale_rotation_translation(
                    Vec3::new(sx, sy, sz),
                    Quat::from_axis_angle(axis, angle),
                    t,
                )
            },
        )
    }

    /// The shared mesh of the random scenes: a closed icosphere of 320 triangles.
    pub fn sphere_mesh() -> Arc<MeshAsset> {
        Arc::new(MeshAsset::new("icosphere", icosphere(Vec3::ZERO, 1.0, 2), 2.0))
    }

    /// One random object: sphere, box, triangle or mesh instance (`MeshId(0)`).
    pub fn object(r: f32, mesh_bounds: penumbra::math::Aabb) -> impl Strategy<Value = PlacedObject> {
        let shape = prop_oneof![
            (point(r), 0.1f32..1.5)
                .prop_map(|(centre, radius)| Shape::Sphere { centre: centre.as_dvec3(), radius }),
            (point(1.0), 0.1f32..1.5).prop_map(|(min, e)| Shape::Cuboid {
                min: min.as_dvec3(),
                max: (min + Vec3::splat(e)).as_dvec3()
            }),
            (point(r), point(1.5), point(1.5)).prop_filter_map("non-degenerate", |(a, b, c)| {
                let (b, c) = (a + b, a + c);
                ((b - a).cross(c - a).length() > 1e-3)
                    .then_some(Shape::Triangle { vertices: [a, b, c].map(Vec3::as_dvec3) })
            }),
            Just(Shape::Mesh { mesh: MeshId(0), bounds: mesh_bounds }),
        ];
        (shape, placement(r)).prop_map(|(shape, to_world)| {
            // Spheres need a uniform scale: place them by translation only.
            let to_world = match shape {
                Shape::Sphere { .. } | Shape::Triangle { .. } => {
                    Affine3A::from_translation(to_world.translation.into())
                }
                _ => to_world,
            };
            PlacedObject {
                geometry: shape.place(&to_world.as_daffine3(), glam::DVec3::ZERO),
                material: MaterialId(0),
            }
        })
    }

    /// A random scene of 1–40 objects in `[-8, 8]³` with a grid of density 0.5–8.
    pub fn scene() -> impl Strategy<Value = TraceScene> {
        let mesh = sphere_mesh();
        let bounds = mesh.data.bounds;
        (proptest::collection::vec(object(8.0, bounds), 1..40), 0.5f32..8.0).prop_map(
            move |(objects, lambda)| {
                TraceScene::build_with_meshes(
                    &objects,
                    std::slice::from_ref(&mesh),
                    super::simple_tables(),
                    lambda,
                )
            },
        )
    }
}

/// Waits for `child` at most `limit`, then returns its output; kills it and fails past that (a
/// refusal that came after the work would run for minutes).
#[allow(dead_code)]
pub fn wait_at_most(mut child: std::process::Child, limit: std::time::Duration) -> std::process::Output {
    let started = std::time::Instant::now();
    while child.try_wait().expect("the child can be polled").is_none() {
        if started.elapsed() > limit {
            child.kill().expect("the child can be killed");
            panic!("still running after {limit:?}: the check came after the work");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().expect("the child's output")
}

/// Runs `command` (a shell command line) under a pseudo-terminal (util-linux `script`) in
/// `dir` and returns what the terminal showed; `None` where `script` is not installed. Fails if
/// the command fails.
#[allow(dead_code)]
pub fn on_a_terminal(dir: &std::path::Path, command: &str) -> Option<String> {
    let script = ["/usr/bin/script", "/bin/script"].into_iter().find(|p| std::path::Path::new(p).exists())?;
    let out = std::process::Command::new(script)
        .args(["-qec", command, "/dev/null"])
        .current_dir(dir)
        .env("TERM", "xterm")
        .stdin(std::process::Stdio::null())
        .output()
        .expect("script runs");
    let shown = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{shown}");
    Some(shown)
}

/// The shipped scenes (`scenes/*.ron`, sorted) that can load here: ANCHORS.md's mesh scenes
/// read the full models from `../shared/models/`, which a checkout need not have, so a scene
/// naming a model that is absent is left out, with a note on stderr.
#[allow(dead_code)]
pub fn shipped_scenes() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenes/")
        .map(|e| e.expect("a readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .filter(|p| {
            let text = std::fs::read_to_string(p).expect("a readable scene");
            let models_here = text
                .split('"')
                .filter(|s| s.contains("shared/models/"))
                .all(|s| p.parent().expect("in scenes/").join(s).exists());
            if !models_here {
                eprintln!(
                    "skipped {}: its model is not in ../shared/models/ beside this checkout",
                    p.display()
                );
            }
            models_here
        })
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 10, "only {} shipped scenes", scenes.len());
    scenes
}
