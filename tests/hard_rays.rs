//! The table of hard rays: one row per case nobody thinks about, each with its expected outcome
//! derived independently (f64 geometry, the grid's own wall coordinates, a closed mesh's
//! topology), run through the grid (`closest_hit`) and through brute force
//! (`closest_hit_brute`), which must agree with the expectation and with each other.

mod common;

use std::sync::Arc;

use glam::DVec3;
use penumbra::camera::Camera;
use penumbra::geom::mesh::icosphere;
use penumbra::geom::{MeshId, Shape};
use penumbra::math::{offset_distance, Affine3A, Ray, Vec3};
use penumbra::store::{Hit, MaterialId, MeshAsset, PlacedObject};
use penumbra::trace::{closest_hit, closest_hit_brute, Material, SceneTables, TraceScene};

/// What a row expects of the first hit.
#[derive(Debug, Clone, Copy)]
enum Expect {
    /// No hit in the range.
    Miss,
    /// A hit at this t (relative tolerance `tol`), on object `object` of the scene's objects.
    Hit { t: f64, tol: f64, object: u32 },
    /// Walking the ray from hit to hit meets the surface exactly this many times.
    Crossings(u32),
}

/// One row: a name, a scene, a ray (built from the scene, so it can use the grid's walls) and
/// the expectation.
struct Row {
    name: &'static str,
    scene: fn() -> Arc<TraceScene>,
    ray: fn(&TraceScene) -> (Ray, f32),
    expect: fn(&TraceScene, &Ray) -> Expect,
}

fn tables() -> SceneTables {
    SceneTables {
        materials: vec![Material::default()],
        lights: Vec::new(),
        camera: Camera::look_at(Vec3::new(0.0, 0.0, -10.0), Vec3::ZERO, Vec3::Y, 0.8),
        background: Vec3::ZERO,
        ambient: Vec3::ZERO,
    }
}

fn placed(shape: Shape, to_world: Affine3A) -> PlacedObject {
    PlacedObject { geometry: shape.place(&to_world.as_daffine3(), DVec3::ZERO), material: MaterialId(0) }
}

/// A unit sphere at the origin, with a far-away small sphere so the grid has several cells.
fn sphere_scene() -> Arc<TraceScene> {
    let objects = [
        placed(Shape::Sphere { centre: DVec3::ZERO, radius: 1.0 }, Affine3A::IDENTITY),
        placed(Shape::Sphere { centre: DVec3::splat(6.0), radius: 0.5 }, Affine3A::IDENTITY),
    ];
    Arc::new(TraceScene::build(&objects, tables(), 8.0))
}

/// The box [-1, 1]³ and a far sphere.
fn box_scene() -> Arc<TraceScene> {
    let objects = [
        placed(Shape::Cuboid { min: DVec3::splat(-1.0), max: DVec3::ONE }, Affine3A::IDENTITY),
        placed(Shape::Sphere { centre: DVec3::splat(6.0), radius: 0.5 }, Affine3A::IDENTITY),
    ];
    Arc::new(TraceScene::build(&objects, tables(), 8.0))
}

/// A closed icosphere mesh (radius 1, 320 triangles) as an instance, and a far sphere.
fn mesh_scene() -> Arc<TraceScene> {
    let asset = Arc::new(MeshAsset::new("ico", icosphere(Vec3::ZERO, 1.0, 2), 2.0));
    let shape = Shape::Mesh { mesh: MeshId(0), bounds: asset.data.bounds };
    let objects = [
        placed(shape, Affine3A::IDENTITY),
        placed(Shape::Sphere { centre: DVec3::splat(6.0), radius: 0.5 }, Affine3A::IDENTITY),
    ];
    Arc::new(TraceScene::build_with_meshes(&objects, &[asset], tables(), 8.0))
}

/// A 4×4×4 lattice of spheres of radius 0.3 at integer points: grid walls fall between them.
fn lattice_scene() -> Arc<TraceScene> {
    let mut objects = Vec::new();
    for z in 0..4 {
        for y in 0..4 {
            for x in 0..4 {
                let centre = DVec3::new(x as f64, y as f64, z as f64);
                objects.push(placed(Shape::Sphere { centre, radius: 0.3 }, Affine3A::IDENTITY));
            }
        }
    }
    Arc::new(TraceScene::build(&objects, tables(), 2.0))
}

/// The nearest hit of `ray` with every sphere of `scene`'s lattice (or any sphere list), in
/// f64: an independent reference.
fn f64_sphere_hit(centre: Vec3, radius: f32, ray: &Ray, t_min: f64) -> Option<f64> {
    let (o, d, c) = (ray.origin.as_dvec3(), ray.dir.as_dvec3(), centre.as_dvec3());
    let f = o - c;
    let b = f.dot(d);
    let disc = b * b - d.dot(d) * (f.dot(f) - (radius as f64).powi(2));
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    [(-b - s) / d.dot(d), (-b + s) / d.dot(d)].into_iter().find(|&t| t > t_min)
}

fn lattice_expect(_: &TraceScene, ray: &Ray) -> Expect {
    let mut best: Option<(f64, u32)> = None;
    let mut id = 0;
    for z in 0..4 {
        for y in 0..4 {
            for x in 0..4 {
                if let Some(t) = f64_sphere_hit(Vec3::new(x as f32, y as f32, z as f32), 0.3, ray, 1e-9) {
                    if best.is_none_or(|(b, _)| t < b) {
                        best = Some((t, id));
                    }
                }
                id += 1;
            }
        }
    }
    best.map_or(Expect::Miss, |(t, object)| Expect::Hit { t, tol: 1e-5, object })
}

fn unit_sphere_expect(_: &TraceScene, ray: &Ray) -> Expect {
    f64_sphere_hit(Vec3::ZERO, 1.0, ray, 0.0).map_or(Expect::Miss, |t| Expect::Hit {
        t,
        tol: 1e-5,
        object: 0,
    })
}

/// The slab method in f64 on [-1, 1]³.
fn unit_box_expect(_: &TraceScene, ray: &Ray) -> Expect {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for a in 0..3 {
        if d[a] == 0.0 {
            if o[a].abs() > 1.0 {
                return Expect::Miss;
            }
            continue;
        }
        let (ta, tb) = ((-1.0 - o[a]) / d[a], (1.0 - o[a]) / d[a]);
        t0 = t0.max(ta.min(tb));
        t1 = t1.min(ta.max(tb));
    }
    if t0 > t1 {
        return Expect::Miss;
    }
    let t = if t0 > 0.0 { t0 } else { t1 };
    Expect::Hit { t, tol: 1e-5, object: 0 }
}

fn from(origin: [f32; 3], dir: [f32; 3]) -> (Ray, f32) {
    (Ray::new(Vec3::from_array(origin), Vec3::from_array(dir).normalize()), f32::INFINITY)
}

/// A ray at `angle` radians from the tangent of the unit sphere, from distance 10 on -z: it
/// passes the sphere at height ~1 ± 10·angle.
fn grazing(angle: f64) -> (Ray, f32) {
    let o = DVec3::new(0.0, 0.0, -10.0);
    let tangent = (1.0f64 / 10.0).asin();
    let a = tangent + angle;
    let d = DVec3::new(0.0, a.sin(), a.cos());
    (Ray::new(o.as_vec3(), d.as_vec3()), f32::INFINITY)
}

/// A point on the grid's wall `i` of `axis`, elsewhere at `rest`.
fn on_wall(s: &TraceScene, axis: usize, i: u32, rest: [f32; 3]) -> Vec3 {
    let mut p = Vec3::from_array(rest);
    p[axis] = s.grid.plane(axis, i);
    p
}

fn rows() -> Vec<Row> {
    macro_rules! row {
        ($name:expr, $scene:expr, $ray:expr, $expect:expr) => {
            Row { name: $name, scene: $scene, ray: $ray, expect: $expect }
        };
    }
    vec![
        // Axis-parallel, both signs, every axis.
        row!("+x into sphere", sphere_scene, |_| from([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]), unit_sphere_expect),
        row!("-x into sphere", sphere_scene, |_| from([5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]), unit_sphere_expect),
        row!("+y into sphere", sphere_scene, |_| from([0.0, -5.0, 0.0], [0.0, 1.0, 0.0]), unit_sphere_expect),
        row!("-y into sphere", sphere_scene, |_| from([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]), unit_sphere_expect),
        row!("+z into sphere", sphere_scene, |_| from([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), unit_sphere_expect),
        row!("-z into sphere", sphere_scene, |_| from([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]), unit_sphere_expect),
        row!(
            "+x off axis misses",
            sphere_scene,
            |_| from([-5.0, 1.5, 0.0], [1.0, 0.0, 0.0]),
            unit_sphere_expect
        ),
        row!("-z into box", box_scene, |_| from([0.3, -0.2, 5.0], [0.0, 0.0, -1.0]), unit_box_expect),
        row!("+y into box", box_scene, |_| from([0.3, -5.0, 0.7], [0.0, 1.0, 0.0]), unit_box_expect),
        // -0.0 components.
        row!(
            "-0.0 in y and z",
            sphere_scene,
            |_| from([-5.0, 0.2, 0.1], [1.0, -0.0, -0.0]),
            unit_sphere_expect
        ),
        row!("-0.0 in x", sphere_scene, |_| from([0.1, -5.0, 0.3], [-0.0, 1.0, 0.0]), unit_sphere_expect),
        row!(
            "-0.0 in x and y, -z",
            box_scene,
            |_| from([0.5, 0.5, 5.0], [-0.0, -0.0, -1.0]),
            unit_box_expect
        ),
        row!(
            "-0.0 along a lattice row",
            lattice_scene,
            |_| from([-2.0, 1.0, 2.0], [1.0, -0.0, 0.0]),
            lattice_expect
        ),
        // Starting exactly on a cell wall, a cell edge and a grid corner.
        row!(
            "start on a cell wall",
            lattice_scene,
            |s| (
                Ray::new(on_wall(s, 0, 2, [0.0, 1.1, 2.0]), Vec3::new(1.0, 0.1, 0.05).normalize()),
                f32::INFINITY
            ),
            lattice_expect
        ),
        row!(
            "start on a cell edge",
            lattice_scene,
            |s| {
                let mut p = on_wall(s, 0, 1, [0.0, 0.0, 1.2]);
                p.y = s.grid.plane(1, 1);
                (Ray::new(p, Vec3::new(0.3, 1.0, 0.2).normalize()), f32::INFINITY)
            },
            lattice_expect
        ),
        row!(
            "start on a grid corner",
            lattice_scene,
            |s| {
                let p = Vec3::new(s.grid.plane(0, 0), s.grid.plane(1, 0), s.grid.plane(2, 0));
                (Ray::new(p, Vec3::ONE.normalize()), f32::INFINITY)
            },
            lattice_expect
        ),
        row!(
            "start on the far corner, going back",
            lattice_scene,
            |s| {
                let [x, y, z] = s.grid.dims;
                let p = Vec3::new(s.grid.plane(0, x), s.grid.plane(1, y), s.grid.plane(2, z));
                (Ray::new(p, -Vec3::ONE.normalize()), f32::INFINITY)
            },
            lattice_expect
        ),
        // Exactly along a cell wall, on each axis.
        row!(
            "along an x wall",
            lattice_scene,
            |s| (Ray::new(on_wall(s, 0, 1, [0.0, -2.0, 1.0]), Vec3::Y), f32::INFINITY),
            lattice_expect
        ),
        row!(
            "along a y wall",
            lattice_scene,
            |s| (Ray::new(on_wall(s, 1, 2, [-2.0, 0.0, 2.0]), Vec3::X), f32::INFINITY),
            lattice_expect
        ),
        row!(
            "along a z wall",
            lattice_scene,
            |s| (Ray::new(on_wall(s, 2, 1, [1.0, -2.0, 0.0]), Vec3::Y), f32::INFINITY),
            lattice_expect
        ),
        row!(
            "along a cell edge",
            lattice_scene,
            |s| {
                let mut p = on_wall(s, 0, 1, [0.0, 0.0, -2.0]);
                p.y = s.grid.plane(1, 1);
                (Ray::new(p, Vec3::Z), f32::INFINITY)
            },
            lattice_expect
        ),
        row!(
            "along a lattice row through centres",
            lattice_scene,
            |_| from([-2.0, 2.0, 3.0], [1.0, 0.0, 0.0]),
            lattice_expect
        ),
        row!(
            "diagonal through the lattice",
            lattice_scene,
            |_| from([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]),
            lattice_expect
        ),
        // Grazing the unit sphere, 1e-7 rad and 1e-6 rad either side of the tangent.
        row!("graze 1e-7 rad inside", sphere_scene, |_| grazing(-1e-7), unit_sphere_expect),
        row!("graze 1e-7 rad outside", sphere_scene, |_| grazing(1e-7), unit_sphere_expect),
        row!("graze 1e-6 rad inside", sphere_scene, |_| grazing(-1e-6), unit_sphere_expect),
        row!("graze 1e-6 rad outside", sphere_scene, |_| grazing(1e-6), unit_sphere_expect),
        row!(
            "graze a box edge from outside",
            box_scene,
            |_| from([-5.0, 1.0 + 1e-6, 0.0], [1.0, 0.0, 0.0]),
            unit_box_expect
        ),
        row!("along a box face", box_scene, |_| from([-5.0, 1.0, 0.2], [1.0, 0.0, 0.0]), unit_box_expect),
        row!(
            "through a box corner",
            box_scene,
            |_| from([-4.0, -4.0, -4.0], [1.0, 1.0, 1.0]),
            unit_box_expect
        ),
        // Shared edges and vertices of a closed mesh: in once, out once, whatever the direction.
        row!("mesh vertex, head on", mesh_scene, |s| at_mesh_vertex(s, 0, Vec3::ZERO), |_, _| {
            Expect::Crossings(2)
        }),
        row!(
            "mesh vertex, oblique",
            mesh_scene,
            |s| at_mesh_vertex(s, 5, Vec3::new(-0.5, 0.3, 0.4)),
            |_, _| Expect::Crossings(2)
        ),
        row!("mesh edge midpoint", mesh_scene, |s| at_mesh_edge(s, 3, Vec3::ZERO), |_, _| Expect::Crossings(
            2
        )),
        row!(
            "mesh edge midpoint, oblique",
            mesh_scene,
            |s| at_mesh_edge(s, 17, Vec3::new(0.4, -0.5, 0.2)),
            |_, _| Expect::Crossings(2)
        ),
        row!(
            "mesh vertex of a later face",
            mesh_scene,
            |s| at_mesh_vertex(s, 40, Vec3::new(0.0, 0.3, -0.2)),
            |_, _| Expect::Crossings(2)
        ),
        row!("mesh through its centre", mesh_scene, |_| from([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), |_, _| {
            Expect::Crossings(2)
        }),
        // Starting inside.
        row!(
            "inside the sphere",
            sphere_scene,
            |_| from([0.2, 0.1, 0.0], [0.3, -1.0, 0.5]),
            unit_sphere_expect
        ),
        row!("inside the box", box_scene, |_| from([0.2, 0.1, 0.0], [0.3, -1.0, 0.5]), unit_box_expect),
        row!("inside the mesh", mesh_scene, |_| from([0.1, 0.1, 0.1], [0.2, 0.9, -0.4]), |_, _| {
            Expect::Crossings(1)
        }),
        // Ranges.
        row!(
            "t_max short of the sphere",
            sphere_scene,
            |_| (Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), 3.9),
            |_, _| Expect::Miss
        ),
        row!(
            "t_max just past the sphere",
            sphere_scene,
            |_| (Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), 4.0001),
            unit_sphere_expect
        ),
        row!("pointing away", sphere_scene, |_| from([-5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]), |_, _| {
            Expect::Miss
        }),
        row!(
            "outside the grid entirely",
            lattice_scene,
            |_| from([-2.0, 9.0, 1.0], [1.0, 0.0, 0.0]),
            lattice_expect
        ),
    ]
}

/// A ray from outside through vertex `k` of the icosphere, heading inwards (towards the centre,
/// tilted by `tilt`), so it crosses the surface there rather than touching it.
fn at_mesh_vertex(s: &TraceScene, k: usize, tilt: Vec3) -> (Ray, f32) {
    let p = s.store_mesh_vertex(k);
    let d = (tilt - p).normalize();
    (Ray::new(p - d * 4.0, d), f32::INFINITY)
}

/// A ray from outside through the midpoint of an edge of face `f`, heading inwards.
fn at_mesh_edge(s: &TraceScene, f: usize, tilt: Vec3) -> (Ray, f32) {
    let (a, b) = s.store_mesh_edge(f);
    let d = (tilt - (a + b) * 0.5).normalize();
    (Ray::new((a + b) * 0.5 - d * 4.0, d), f32::INFINITY)
}

/// Reading the test mesh back out of a snapshot.
trait MeshAccess {
    fn store_mesh_vertex(&self, k: usize) -> Vec3;
    fn store_mesh_edge(&self, f: usize) -> (Vec3, Vec3);
}

impl MeshAccess for TraceScene {
    fn store_mesh_vertex(&self, k: usize) -> Vec3 {
        use penumbra::store::PrimitiveStore;
        self.store.meshes()[0].asset.data.positions[k]
    }

    fn store_mesh_edge(&self, f: usize) -> (Vec3, Vec3) {
        use penumbra::store::PrimitiveStore;
        let data = &self.store.meshes()[0].asset.data;
        let [a, b, _] = data.indices[f];
        (data.positions[a as usize], data.positions[b as usize])
    }
}

/// Number of surface crossings along a ray: hit, step past it, hit again.
fn crossings(s: &TraceScene, ray: &Ray, find: impl Fn(&TraceScene, &Ray, f32, f32) -> Option<Hit>) -> u32 {
    let (mut n, mut t) = (0, 0.0);
    while let Some(h) = find(s, ray, t, f32::INFINITY) {
        if h.object != 0 {
            break;
        }
        n += 1;
        t = h.t;
        assert!(n < 10, "runaway crossings");
    }
    n
}

fn check(
    row: &Row,
    scene: &TraceScene,
    ray: &Ray,
    t_max: f32,
    name: &str,
    find: fn(&TraceScene, &Ray, f32, f32) -> Option<Hit>,
) {
    let got = find(scene, ray, 0.0, t_max);
    match (row.expect)(scene, ray) {
        Expect::Miss => {
            assert!(got.is_none_or(|h| h.object != 0), "{}: {name} found {got:?}, expected a miss", row.name)
        }
        Expect::Hit { t, tol, object } => {
            let h = got.unwrap_or_else(|| panic!("{}: {name} missed, expected t = {t}", row.name));
            assert_eq!(h.object, object, "{}: {name} hit the wrong object", row.name);
            assert!(
                ((h.t as f64) - t).abs() <= tol * t.abs().max(1.0),
                "{}: {name} t = {}, expected {t}",
                row.name,
                h.t
            );
            assert!(h.t > 0.0 && h.t < t_max, "{}: {name} t = {} outside (0, {t_max})", row.name, h.t);
        }
        Expect::Crossings(n) => assert_eq!(crossings(scene, ray, find), n, "{}: {name}", row.name),
    }
}

#[test]
fn every_hard_ray_gives_its_expected_outcome_through_the_grid_and_brute_force() {
    let rows = rows();
    assert!(rows.len() >= 40, "{} rows", rows.len());
    for row in &rows {
        let scene = (row.scene)();
        let (ray, t_max) = (row.ray)(&scene);
        check(row, &scene, &ray, t_max, "grid", closest_hit);
        check(row, &scene, &ray, t_max, "brute force", closest_hit_brute);
        let (g, b) = (closest_hit(&scene, &ray, 0.0, t_max), closest_hit_brute(&scene, &ray, 0.0, t_max));
        assert_eq!(
            g.map(|h| (h.t, h.object, h.prim)),
            b.map(|h| (h.t, h.object, h.prim)),
            "{}: grid and brute force differ",
            row.name
        );
    }
}

#[test]
fn secondary_rays_leave_tiny_and_huge_spheres_without_acne() {
    // From points all over a sphere of radius 1e-4 and 1e4, a ray offset as the integrator
    // offsets it and leaving into the outer hemisphere never hits the sphere it left.
    for radius in [1e-4f32, 1.0, 1e4] {
        let centre = Vec3::new(0.3, -0.2, 0.1) * radius * 3.0;
        let objects = [placed(Shape::Sphere { centre: centre.as_dvec3(), radius }, Affine3A::IDENTITY)];
        let mut tables = tables();
        tables.camera = Camera::look_at(centre - Vec3::Z * radius * 10.0, centre, Vec3::Y, 0.8);
        let scene: TraceScene = TraceScene::build(&objects, tables, 2.0);
        let mut rng = common::rng(radius.to_bits() as u64);
        for _ in 0..20_000 {
            let n = common::unit_vector(&mut rng);
            let p = centre + n * radius;
            let mut d = common::unit_vector(&mut rng);
            if d.dot(n) < 0.0 {
                d = -d;
            }
            let eps = offset_distance(p, scene.offset_floor);
            let ray = Ray::new(p + n * eps, d);
            assert!(
                closest_hit(&scene, &ray, 0.0, f32::INFINITY).is_none(),
                "radius {radius}: acne at {p} towards {d}"
            );
        }
    }
}

#[test]
fn the_default_scene_scaled_by_powers_of_ten_renders_the_same_image() {
    use penumbra::film::encode_srgb8;
    use penumbra::scene::{default_scene, spawn_world, LightDesc};
    use penumbra::world::SceneWorld;
    let image = |k: f32| {
        let mut desc = default_scene();
        desc.camera.position *= f64::from(k);
        desc.camera.look_at *= f64::from(k);
        desc.camera.width = 160;
        desc.camera.height = 120;
        for o in &mut desc.objects {
            o.transform.translate *= f64::from(k);
            o.transform.scale *= k;
        }
        for l in &mut desc.lights {
            if let LightDesc::Point { position, .. } = l {
                *position *= f64::from(k);
            }
        }
        let mut world: SceneWorld = spawn_world(&desc);
        let scene = world.update();
        encode_srgb8(&penumbra::trace::render(&scene, &world.render_settings()).0)
    };
    let unit = image(1.0);
    for k in [1e-6f32, 1e-3, 1e3, 1e6] {
        let scaled = image(k);
        let pixels = unit.len() / 3;
        let off =
            (0..pixels).filter(|&p| (0..3).any(|c| unit[3 * p + c].abs_diff(scaled[3 * p + c]) > 1)).count();
        assert!(
            off as f64 <= pixels as f64 * 1e-3,
            "scale {k}: {off} of {pixels} pixels differ by more than 1/255"
        );
    }
}
