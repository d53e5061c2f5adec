//! Property tests (proptest; strategies in `tests/common/mod.rs`): the grid agrees with brute
//! force, a ray and its reverse see the same crossings of a closed mesh, hits lie inside the
//! asked range, and shading normals are unit and face the ray.

use crate::common;

use common::strategies;
use penumbra::math::Ray;
use penumbra::store::{MaterialId, PlacedObject, PrimitiveStore};
use penumbra::testing::closest_hit_brute;
use penumbra::trace::{closest_hit, facing_normals, TraceScene};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn the_grid_finds_what_brute_force_finds(
        scene in strategies::scene(),
        rays in proptest::collection::vec(strategies::ray(12.0), 100),
    ) {
        for ray in &rays {
            let g = closest_hit(&scene, ray, 0.0, f32::INFINITY).map(|h| (h.t, h.object, h.prim));
            let b = closest_hit_brute(&scene, ray, 0.0, f32::INFINITY).map(|h| (h.t, h.object, h.prim));
            prop_assert_eq!(g, b, "ray {:?}", ray);
        }
    }

    #[test]
    fn hits_lie_strictly_inside_the_range_asked_for(
        scene in strategies::scene(),
        rays in proptest::collection::vec((strategies::ray(12.0), 0.0f32..5.0, 0.0f32..30.0), 100),
    ) {
        for (ray, t_min, length) in &rays {
            let t_max = t_min + length;
            if let Some(h) = closest_hit(&scene, ray, *t_min, t_max) {
                prop_assert!(h.t > *t_min && h.t < t_max, "t {} outside ({}, {})", h.t, t_min, t_max);
            }
        }
    }

    #[test]
    fn normals_are_unit_and_shading_faces_the_ray(
        scene in strategies::scene(),
        rays in proptest::collection::vec(strategies::ray(12.0), 100),
    ) {
        for ray in &rays {
            let Some(hit) = closest_hit(&scene, ray, 0.0, f32::INFINITY) else { continue };
            let sp = scene.store.surface(&hit, ray);
            prop_assert!((sp.normal.length() - 1.0).abs() < 1e-4, "normal {}", sp.normal);
            prop_assert!((sp.shading.length() - 1.0).abs() < 1e-4, "shading {}", sp.shading);
            let (_, n, ns) = facing_normals(&sp, ray.dir);
            prop_assert!(n.dot(ray.dir) <= 0.0 && ns.dot(ray.dir) < 0.0 || n.dot(ray.dir) == 0.0);
        }
    }

    #[test]
    fn a_ray_and_its_reverse_cross_a_closed_mesh_at_the_same_points(
        to_world in strategies::placement(2.0),
        line in (strategies::point(1.5), strategies::direction()),
    ) {
        let mesh = strategies::sphere_mesh();
        let shape = penumbra::geom::Shape::Mesh { mesh: penumbra::geom::MeshId(0), bounds: mesh.data.bounds };
        let objects = [PlacedObject { geometry: shape.place(&to_world.as_daffine3(), glam::DVec3::ZERO), material: MaterialId(0) }];
        let scene: TraceScene = TraceScene::build_with_meshes(&objects, &[mesh], common::simple_tables(), 2.0);
        // A line through a point near the instance, traced from 40 units away both ways.
        let (p, d) = (to_world.transform_point3(line.0 * 0.5), line.1);
        let forward = crossings(&scene, &Ray::new(p - d * 40.0, d));
        let backward = crossings(&scene, &Ray::new(p + d * 40.0, -d));
        prop_assert_eq!(forward.len(), backward.len(), "{:?} vs {:?}", forward, backward);
        prop_assert!(forward.len().is_multiple_of(2), "a closed mesh is crossed an even number of times: {:?}", forward);
        for (f, b) in forward.iter().zip(backward.iter().rev()) {
            prop_assert!((f + b - 80.0).abs() < 1e-3, "crossing at {} forward, {} backward", f, b);
        }
    }
}

/// The ray parameters of every crossing along `ray`.
fn crossings(scene: &TraceScene, ray: &Ray) -> Vec<f32> {
    let mut out = Vec::new();
    let mut t = 0.0;
    while let Some(h) = closest_hit(scene, ray, t, f32::INFINITY) {
        out.push(h.t);
        t = h.t;
        if out.len() > 16 {
            break;
        }
    }
    out
}
