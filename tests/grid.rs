//! The grid traversal against brute force: on seeded random scenes, `closest_hit` (planes, then
//! a 3D DDA over the uniform grid) must return exactly the hit that testing every object
//! returns, and `transmittance` the same product as crossing every object, for families of
//! hard rays: axis-parallel with `-0.0` components, on and along cell walls, through cell
//! corners and edges, grazing, missing, shadow-style with a finite `t_max`, and at huge and tiny
//! scales and on degenerate grids.

use crate::common;

use common::{point_in, rng, unit_vector};
use glam::{DAffine3, DVec3};
use penumbra::accel::UniformGrid;
use penumbra::geom::Placed;
use penumbra::math::{Aabb, Ray, Vec3};
use penumbra::store::{Hit, NoTally, PlacedObject, PrimitiveStore};
use penumbra::testing::closest_hit_brute;
use penumbra::trace::transmittance;
use penumbra::trace::{closest_hit, Material, TraceScene};
use rand::rngs::StdRng;
use rand::RngExt;

/// Relative tolerance on `t` between the grid's hit and brute force's.
const T_REL: f32 = 1e-6;

/// Rays per family per scene; nine families give well over 10,000 rays per scene.
const PER_FAMILY: usize = 1200;

/// The kinds of hard ray the tests draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Family {
    /// Origin outside the grid, aimed at a random point inside.
    OutsideIn,
    /// Origin inside the grid, uniform direction.
    Inside,
    /// Direction exactly ±X, ±Y or ±Z, the other components `0.0` or `-0.0`.
    AxisParallel,
    /// Origin exactly on a cell wall (`grid.plane`), half of them travelling inside the wall.
    OnWall,
    /// Through, from, or along cell corners and edges.
    CornerEdge,
    /// Rays that never enter the grid's box.
    Miss,
    /// Tangent to a sphere of the scene.
    Grazing,
    /// Shadow-style segment between two points (finite `t_max`, sometimes `t_min > 0`).
    Segment,
    /// Primary rays of the snapshot's camera.
    Camera,
}

/// One query: a ray and its parametric range.
#[derive(Debug, Clone, Copy)]
struct Query {
    family: Family,
    ray: Ray,
    t_min: f32,
    t_max: f32,
}

fn query(family: Family, origin: Vec3, dir: Vec3) -> Query {
    Query { family, ray: Ray::new(origin, dir), t_min: 0.0, t_max: f32::INFINITY }
}

/// A random wall index on `axis`, walls `0..=dims` included.
fn wall(rng: &mut StdRng, grid: &UniformGrid, axis: usize) -> u32 {
    rng.random_range(0..=grid.dims[axis])
}

/// A random exact cell corner (every coordinate a `grid.plane` value).
fn corner(rng: &mut StdRng, grid: &UniformGrid) -> Vec3 {
    let [i, j, k] = [0, 1, 2].map(|a| wall(rng, grid, a));
    Vec3::new(grid.plane(0, i), grid.plane(1, j), grid.plane(2, k))
}

/// A signed axis direction whose other two components are randomly `0.0` or `-0.0`.
fn axis_dir(rng: &mut StdRng, axis: usize) -> Vec3 {
    let mut d = Vec3::new(
        if rng.random::<bool>() { -0.0 } else { 0.0 },
        if rng.random::<bool>() { -0.0 } else { 0.0 },
        if rng.random::<bool>() { -0.0 } else { 0.0 },
    );
    d[axis] = if rng.random::<bool>() { -1.0 } else { 1.0 };
    d
}

/// All families of hard rays for one scene.
fn queries(seed: u64, scene: &TraceScene, objects: &[PlacedObject]) -> Vec<Query> {
    let mut rng = rng(seed ^ 0x005e_ed0f_4a75);
    let grid = &*scene.grid;
    let b = grid.bounds;
    let centre = (b.min + b.max) * 0.5;
    let diag = b.extent().length();
    let wide = Aabb::new(b.min - b.extent() * 0.2, b.max + b.extent() * 0.2);
    let spheres: Vec<(Vec3, f32)> = objects
        .iter()
        .filter_map(|o| match o.geometry {
            Placed::Sphere { centre, radius } => Some((centre, radius)),
            _ => None,
        })
        .collect();
    let mut out = Vec::new();
    for _ in 0..PER_FAMILY {
        // Outside in.
        let origin = centre + unit_vector(&mut rng) * diag * rng.random_range(0.6f32..2.0);
        let target = point_in(&mut rng, b.min, b.max);
        out.push(query(Family::OutsideIn, origin, (target - origin).normalize()));

        // Inside.
        out.push(query(Family::Inside, point_in(&mut rng, b.min, b.max), unit_vector(&mut rng)));

        // Axis-parallel, from inside or a little outside the grid.
        let axis = rng.random_range(0..3);
        out.push(query(
            Family::AxisParallel,
            point_in(&mut rng, wide.min, wide.max),
            axis_dir(&mut rng, axis),
        ));

        // On a wall; half of them move inside the wall plane (component exactly ±0).
        let axis = rng.random_range(0..3);
        let mut origin = point_in(&mut rng, b.min, b.max);
        origin[axis] = grid.plane(axis, wall(&mut rng, grid, axis));
        let mut dir = unit_vector(&mut rng);
        if rng.random::<bool>() {
            dir[axis] = if rng.random::<bool>() { -0.0 } else { 0.0 };
            dir = dir.normalize();
        }
        out.push(query(Family::OnWall, origin, dir));

        // Corners and edges: through a corner from outside, out of a corner, along an edge.
        let c = corner(&mut rng, grid);
        let q = match rng.random_range(0..4) {
            0 => {
                let origin = centre + unit_vector(&mut rng) * diag;
                query(Family::CornerEdge, origin, (c - origin).normalize())
            }
            1 => query(Family::CornerEdge, c, unit_vector(&mut rng)),
            2 => {
                let axis = rng.random_range(0..3);
                query(Family::CornerEdge, c, axis_dir(&mut rng, axis))
            }
            _ => {
                // Diagonal inside a wall plane, through the corners of square-ish cells.
                let axis = rng.random_range(0..3);
                let mut d = Vec3::new(
                    if rng.random::<bool>() { 1.0 } else { -1.0 },
                    if rng.random::<bool>() { 1.0 } else { -1.0 },
                    if rng.random::<bool>() { 1.0 } else { -1.0 },
                ) * grid.cell_size;
                d[axis] = -0.0;
                query(Family::CornerEdge, c, d.normalize())
            }
        };
        out.push(q);

        // Missing: from outside, pointing away from the box along every axis it lies beyond.
        let origin = centre + unit_vector(&mut rng) * diag * rng.random_range(0.6f32..2.0);
        let mut dir = unit_vector(&mut rng);
        for a in 0..3 {
            if origin[a] > b.max[a] {
                dir[a] = dir[a].abs();
            } else if origin[a] < b.min[a] {
                dir[a] = -dir[a].abs();
            }
        }
        out.push(query(Family::Miss, origin, dir.normalize()));

        // Grazing: tangent to a random sphere, starting some way before the tangent point.
        if let Some(&(c, r)) = spheres.get(rng.random_range(0..spheres.len().max(1))) {
            let d = unit_vector(&mut rng);
            let u = unit_vector(&mut rng);
            let u = (u - d * u.dot(d)).normalize();
            let p = c + u * r;
            out.push(query(Family::Grazing, p - d * diag * rng.random_range(0.05f32..1.0), d));
        }

        // Segment between two points, as a shadow ray; sometimes with t_min > 0.
        let from = point_in(&mut rng, b.min, b.max);
        let to = point_in(&mut rng, wide.min, wide.max);
        let dist = (to - from).length();
        let mut q = query(Family::Segment, from, (to - from) / dist);
        q.t_max = dist;
        if rng.random::<bool>() {
            q.t_min = dist * rng.random_range(0.0f32..0.5);
        }
        out.push(q);

        // Camera rays.
        let (px, py) = (rng.random::<f32>() * 64.0, rng.random::<f32>() * 64.0);
        out.push(Query {
            family: Family::Camera,
            ray: scene.camera.ray(px, py, 64, 64),
            t_min: 0.0,
            t_max: f32::INFINITY,
        });
    }
    out
}

/// Outcome of comparing the grid with brute force over many queries.
#[derive(Debug, Default)]
struct Tally {
    rays: usize,
    hits: usize,
    /// Rays and hits per family, in [`Family`] order of first appearance.
    per_family: Vec<(Family, usize, usize)>,
    /// Exact ties: two different surfaces hit at the same `t` (coplanar overlapping geometry).
    ties: Vec<String>,
    mismatches: Vec<String>,
}

impl Tally {
    fn count(&mut self, family: Family, hit: bool) {
        self.rays += 1;
        self.hits += hit as usize;
        match self.per_family.iter_mut().find(|f| f.0 == family) {
            Some(f) => {
                f.1 += 1;
                f.2 += hit as usize;
            }
            None => self.per_family.push((family, 1, hit as usize)),
        }
    }
}

/// True when `a` and `b` are within [`T_REL`] of each other.
fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= T_REL * b.abs()
}

/// How the grid's answer relates to brute force's.
#[derive(Debug, PartialEq, Eq)]
enum Verdict {
    Same,
    /// A different surface at the same `t`, and that surface really is hit there.
    Tie,
    Different,
}

fn judge(scene: &TraceScene, q: &Query, grid: Option<Hit>, brute: Option<Hit>) -> Verdict {
    match (grid, brute) {
        (None, None) => Verdict::Same,
        (Some(g), Some(b)) if close(g.t, b.t) && (g.object, g.prim) == (b.object, b.prim) => Verdict::Same,
        (Some(g), Some(b)) if close(g.t, b.t) => {
            // Re-derive the grid's hit on its own: it must be a genuine hit of that object.
            let again = match g.object.kind() {
                penumbra::store::ObjectKind::Bounded(id) => {
                    scene.store.intersect_bounded(id, &q.ray, q.t_min, q.t_max, &mut NoTally)
                }
                _ => None,
            };
            if again.is_some_and(|h| h.t == g.t) {
                Verdict::Tie
            } else {
                Verdict::Different
            }
        }
        _ => Verdict::Different,
    }
}

fn compare(scene: &TraceScene, queries: &[Query], label: &str, tally: &mut Tally) {
    for q in queries {
        let g = closest_hit(scene, &q.ray, q.t_min, q.t_max);
        let b = closest_hit_brute(scene, &q.ray, q.t_min, q.t_max);
        tally.count(q.family, b.is_some());
        let line = || {
            format!("{label} {:?}: {:?} [{}, {}]: grid {g:?} brute {b:?}", q.family, q.ray, q.t_min, q.t_max)
        };
        match judge(scene, q, g, b) {
            Verdict::Same => {}
            Verdict::Tie => tally.ties.push(line()),
            Verdict::Different => tally.mismatches.push(line()),
        }
    }
}

/// No mismatches at all, and no ties either unless `ties_allowed`.
fn assert_clean(tally: &Tally, ties_allowed: bool) {
    println!(
        "{} rays, {} hits, {} ties; per family (rays, hits): {:?}",
        tally.rays,
        tally.hits,
        tally.ties.len(),
        tally.per_family
    );
    assert!(
        tally.mismatches.is_empty(),
        "{} of {} rays differ; first ones:\n{}",
        tally.mismatches.len(),
        tally.rays,
        tally.mismatches.iter().take(8).cloned().collect::<Vec<_>>().join("\n")
    );
    assert!(
        ties_allowed || tally.ties.is_empty(),
        "unexpected ties:\n{}",
        tally.ties.iter().take(8).cloned().collect::<Vec<_>>().join("\n")
    );
}

/// Grid densities the scenes cycle through, so several resolutions are exercised.
const LAMBDAS: [f32; 5] = [0.5, 1.0, 3.0, 8.0, 20.0];

#[test]
fn grid_matches_brute_force_on_random_mixed_scenes_for_every_ray_family() {
    let mut tally = Tally::default();
    for seed in 0..24u64 {
        let n = 50 + (seed as usize * 37) % 400;
        let objects = common::random_mixed(seed, n);
        let scene = common::scene(&objects, LAMBDAS[seed as usize % LAMBDAS.len()]);
        let qs = queries(seed, &scene, &objects);
        assert!(qs.len() >= 10_000);
        compare(&scene, &qs, &format!("seed {seed} n {n}"), &mut tally);
    }
    assert!(tally.hits > tally.rays / 5, "too few hits to prove anything: {tally:?}");
    assert_clean(&tally, false);
}

#[test]
fn grid_matches_brute_force_on_random_sphere_clouds() {
    let mut tally = Tally::default();
    for seed in 100..110u64 {
        let objects = common::random_spheres(seed, 1000, 20.0);
        let scene = common::scene(&objects, LAMBDAS[seed as usize % LAMBDAS.len()]);
        compare(&scene, &queries(seed, &scene, &objects), &format!("spheres seed {seed}"), &mut tally);
    }
    assert_clean(&tally, false);
}

#[test]
fn grid_matches_brute_force_at_huge_and_tiny_scales() {
    for extent in [1.0e5f32, 1.0e-4] {
        let mut tally = Tally::default();
        for seed in 200..204u64 {
            let objects = common::random_mixed_in(seed, 300, extent, 1);
            let mut tables = common::simple_tables();
            tables.camera = penumbra::camera::Camera::look_at(
                Vec3::new(0.2, 0.3, 3.0) * extent,
                Vec3::ZERO,
                Vec3::Y,
                60f32.to_radians(),
            );
            let scene = TraceScene::build(&objects, tables, 4.0);
            compare(
                &scene,
                &queries(seed, &scene, &objects),
                &format!("extent {extent} seed {seed}"),
                &mut tally,
            );
        }
        assert!(tally.hits > tally.rays / 5, "extent {extent}: {tally:?}");
        assert_clean(&tally, false);
    }
}

/// Brute-force transmittance: every crossing of every object in `(0, t_max)`.
fn transmittance_brute(scene: &TraceScene, ray: &Ray, t_max: f32) -> Vec3 {
    let store = &scene.store;
    let kt = |h: &Hit| scene.material(store.material(h)).kt;
    let mut pass = Vec3::ONE;
    for i in 0..store.unbounded_count() {
        if let Some(h) = store.intersect_unbounded(i, ray, 0.0, t_max) {
            pass *= kt(&h);
        }
    }
    for id in 0..store.bounded_count() {
        let mut t_lo = 0.0;
        while let Some(h) = store.intersect_bounded(id, ray, t_lo, t_max, &mut NoTally) {
            pass *= kt(&h);
            t_lo = h.t;
        }
    }
    pass
}

#[test]
fn transmittance_equals_the_brute_force_product_over_all_crossings() {
    let materials = vec![
        // Grey and tinted: every channel is multiplied on its own.
        Material { kt: Vec3::ZERO, ..Material::default() },
        Material { kt: Vec3::new(0.5, 0.6, 0.7), ..Material::default() },
        Material { kt: Vec3::splat(0.9), ..Material::default() },
        Material { kt: Vec3::new(0.75, 0.95, 0.5), ..Material::default() },
        Material { kt: Vec3::splat(0.95), ..Material::default() },
    ];
    let (mut rays, mut partial, mut bad) = (0usize, 0usize, Vec::new());
    for seed in 300..310u64 {
        let objects = common::random_mixed_in(seed, 200, 10.0, materials.len() as u32);
        // Mostly transparent: opaque objects only one time in ten.
        let objects: Vec<PlacedObject> = objects
            .into_iter()
            .enumerate()
            .map(|(i, mut o)| {
                if o.material.0 == 0 && i % 10 != 0 {
                    o.material.0 = 1;
                }
                o
            })
            .collect();
        let tables = common::tables_with(materials.clone(), Vec3::new(0.0, 0.0, 30.0));
        let scene = TraceScene::build(&objects, tables, LAMBDAS[seed as usize % LAMBDAS.len()]);
        for q in queries(seed, &scene, &objects) {
            let t_max =
                if q.t_max.is_finite() { q.t_max } else { 1e3 * scene.grid.bounds.extent().max_element() };
            let g = transmittance(&scene, &q.ray, t_max);
            let b = transmittance_brute(&scene, &q.ray, t_max);
            rays += 1;
            partial += (b.x > 0.0 && b.x < 1.0) as usize;
            // The factors are multiplied in a different order: allow a few ulps per factor.
            let same = (g == Vec3::ZERO) == (b == Vec3::ZERO) && (g - b).abs().cmple(1e-5 * b).all();
            if !same {
                bad.push(format!("seed {seed} {:?} {:?} t_max {t_max}: grid {g} brute {b}", q.family, q.ray));
            }
        }
    }
    assert!(partial > rays / 10, "too few partially transmitted rays: {partial} of {rays}");
    assert!(bad.is_empty(), "{} of {rays} differ:\n{}", bad.len(), bad[..bad.len().min(8)].join("\n"));
}

/// A degenerate scene must still build a small grid and trace exactly like brute force.
///
/// `ties_allowed` is for scenes with overlapping coplanar surfaces, where two objects are hit
/// at bit-identical `t` and either answer is right.
fn check_degenerate(objects: &[PlacedObject], label: &str, ties_allowed: bool) -> TraceScene {
    let scene = common::scene(objects, 4.0);
    let mut tally = Tally::default();
    compare(&scene, &queries(7, &scene, objects), label, &mut tally);
    println!("{label}: grid dims {:?}", scene.grid.dims);
    assert_clean(&tally, ties_allowed);
    scene
}

fn sphere(centre: Vec3, radius: f32) -> PlacedObject {
    PlacedObject { geometry: Placed::Sphere { centre, radius }, material: penumbra::store::MaterialId(0) }
}

#[test]
fn single_object_grid_traces_like_brute_force() {
    let scene = check_degenerate(&[sphere(Vec3::new(1.0, 2.0, 3.0), 0.5)], "one sphere", false);
    assert!(scene.grid.cell_count() <= 8, "dims {:?}", scene.grid.dims);
}

#[test]
fn objects_all_at_one_point_trace_like_brute_force() {
    // Concentric spheres and triangles fanned around the same point.
    let p = Vec3::new(3.0, -2.0, 5.0);
    let mut objects: Vec<PlacedObject> = (1..=20).map(|i| sphere(p, 0.01 * i as f32)).collect();
    let mut r = rng(11);
    for _ in 0..20 {
        let vertices = [p, p + unit_vector(&mut r) * 0.1, p + unit_vector(&mut r) * 0.1];
        objects.push(PlacedObject {
            geometry: penumbra::geom::Shape::Triangle { vertices: vertices.map(Vec3::as_dvec3) }
                .place(&DAffine3::IDENTITY, DVec3::ZERO),
            material: penumbra::store::MaterialId(0),
        });
    }
    let scene = check_degenerate(&objects, "one point", false);
    assert!(scene.grid.cell_count() <= 40 * 8, "dims {:?}", scene.grid.dims);
}

#[test]
fn flat_scene_in_one_plane_keeps_a_small_grid_and_traces_like_brute_force() {
    // Triangles, polygons and flat boxes all lying in the plane z = 0.5.
    let mut r = rng(12);
    let mut objects = Vec::new();
    for i in 0..60 {
        let c = point_in(&mut r, Vec3::new(-5.0, -5.0, 0.5), Vec3::new(5.0, 5.0, 0.5));
        let flat = |v: Vec3| Vec3::new(v.x, v.y, 0.0);
        let shape = match i % 3 {
            0 => penumbra::geom::Shape::Triangle {
                vertices: [c, c + flat(unit_vector(&mut r)), c + flat(unit_vector(&mut r))]
                    .map(Vec3::as_dvec3),
            },
            1 => penumbra::geom::Shape::Polygon {
                vertices: [c, c + Vec3::X, c + Vec3::new(1.0, 1.0, 0.0), c + Vec3::Y]
                    .map(Vec3::as_dvec3)
                    .to_vec(),
            },
            _ => penumbra::geom::Shape::Cuboid {
                min: (c - Vec3::new(0.3, 0.2, 0.0)).as_dvec3(),
                max: (c + Vec3::new(0.3, 0.2, 0.0)).as_dvec3(),
            },
        };
        objects.push(PlacedObject {
            geometry: shape.place(&DAffine3::IDENTITY, DVec3::ZERO),
            material: penumbra::store::MaterialId(0),
        });
    }
    let scene = check_degenerate(&objects, "flat", true);
    // About λ·N = 240 cells; a flat box must not blow up to the per-axis cap.
    assert!(scene.grid.cell_count() <= 4 * 240, "dims {:?}", scene.grid.dims);
}

/// Geometry that lies exactly on the grid's cell walls: boxes whose faces are walls, triangles
/// in a wall plane, spheres whose extreme point touches a wall. Two anchor spheres fix the
/// scene's bounds, so a first build tells the walls and the second build has the same ones.
fn wall_aligned_scene(seed: u64, n: usize) -> (TraceScene, Vec<PlacedObject>, Vec<Vec3>) {
    let anchors = [sphere(Vec3::splat(-6.0), 0.1), sphere(Vec3::splat(6.0), 0.1)];
    let mut probe: Vec<PlacedObject> = anchors.to_vec();
    probe.extend((0..n).map(|_| sphere(Vec3::ZERO, 1.0)));
    let walls = common::scene(&probe, 2.0).grid.clone();
    let g = &*walls;
    let mut r = rng(seed);
    let mut tangent_points = Vec::new();
    let mut objects: Vec<PlacedObject> = anchors.to_vec();
    // Wall indices well inside the anchors' box.
    let inner = |r: &mut StdRng, a: usize| r.random_range(2..g.dims[a] - 2);
    for k in 0..n {
        let shape = match k % 3 {
            0 => {
                let lo = [0, 1, 2].map(|a| inner(&mut r, a));
                let min = Vec3::new(g.plane(0, lo[0]), g.plane(1, lo[1]), g.plane(2, lo[2]));
                let max = Vec3::new(g.plane(0, lo[0] + 1), g.plane(1, lo[1] + 2), g.plane(2, lo[2] + 1));
                penumbra::geom::Shape::Cuboid { min: min.as_dvec3(), max: max.as_dvec3() }
            }
            1 => {
                let a = r.random_range(0..3);
                let w = g.plane(a, inner(&mut r, a));
                let c = point_in(&mut r, Vec3::splat(-4.0), Vec3::splat(4.0));
                let mut vertices = [c, c + unit_vector(&mut r), c + unit_vector(&mut r)];
                for v in &mut vertices {
                    v[a] = w;
                }
                penumbra::geom::Shape::Triangle { vertices: vertices.map(Vec3::as_dvec3) }
            }
            _ => {
                let a = r.random_range(0..3);
                let w = g.plane(a, inner(&mut r, a));
                let radius = r.random_range(0.2f32..0.8);
                let mut centre = point_in(&mut r, Vec3::splat(-4.0), Vec3::splat(4.0));
                let side = if r.random::<bool>() { 1.0 } else { -1.0 };
                centre[a] = w - side * radius;
                let mut top = centre;
                top[a] += side * radius;
                tangent_points.push(top);
                penumbra::geom::Shape::Sphere { centre: centre.as_dvec3(), radius }
            }
        };
        objects.push(PlacedObject {
            geometry: shape.place(&DAffine3::IDENTITY, DVec3::ZERO),
            material: penumbra::store::MaterialId(0),
        });
    }
    let scene = common::scene(&objects, 2.0);
    assert_eq!((scene.grid.bounds, scene.grid.dims), (g.bounds, g.dims), "walls moved between builds");
    (scene, objects, tangent_points)
}

#[test]
fn geometry_lying_on_cell_walls_is_found_like_brute_force() {
    let mut tally = Tally::default();
    for seed in 400..406u64 {
        let (scene, objects, tops) = wall_aligned_scene(seed, 150);
        let mut qs = queries(seed, &scene, &objects);
        // Rays tangent to each sphere at the point that touches a wall, in every direction
        // inside the tangent plane, from both sides.
        let mut r = rng(seed + 1);
        for &p in &tops {
            for _ in 0..40 {
                let n = objects
                    .iter()
                    .find_map(|o| match o.geometry {
                        Placed::Sphere { centre, radius }
                            if ((p - centre).length() - radius).abs() < 1e-5 =>
                        {
                            Some((p - centre).normalize())
                        }
                        _ => None,
                    })
                    .unwrap_or(Vec3::Z);
                let d = unit_vector(&mut r);
                let d = (d - n * d.dot(n)).normalize();
                qs.push(query(Family::Grazing, p - d * r.random_range(0.01f32..5.0), d));
            }
        }
        compare(&scene, &qs, &format!("walls seed {seed}"), &mut tally);
    }
    // Boxes sharing a wall face and triangles lying in that wall are hit at bit-identical t:
    // genuine ties, where either surface is the right answer.
    assert_clean(&tally, true);
}

#[test]
fn transmittance_through_geometry_on_cell_walls_counts_each_crossing_once() {
    let materials = vec![Material { kt: Vec3::splat(0.5), ..Material::default() }];
    let mut bad = Vec::new();
    let mut rays = 0;
    for seed in 410..414u64 {
        let (scene, objects, _) = wall_aligned_scene(seed, 150);
        let mut scene = scene;
        scene.materials = materials.clone();
        scene.effects.transmission = true;
        for q in queries(seed, &scene, &objects) {
            let t_max = if q.t_max.is_finite() { q.t_max } else { 100.0 };
            let (g, b) = (transmittance(&scene, &q.ray, t_max), transmittance_brute(&scene, &q.ray, t_max));
            rays += 1;
            if !(g - b).abs().cmple(1e-5 * b).all() {
                bad.push(format!("seed {seed} {:?} {:?} t_max {t_max}: grid {g} brute {b}", q.family, q.ray));
            }
        }
    }
    assert!(bad.is_empty(), "{} of {rays} differ:\n{}", bad.len(), bad[..bad.len().min(8)].join("\n"));
}
