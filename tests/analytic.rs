//! Analytic images: pixels and single rays whose radiance follows in closed form from the
//! Phong model, Snell's law and the slab-offset formula, computed here independently of the
//! tracer's own code path.

use glam::{DAffine3, DVec3};
use penumbra::accel::DEFAULT_LAMBDA;
use penumbra::camera::Camera;
use penumbra::geom::Shape;
use penumbra::math::{Ray, Vec3};
use penumbra::store::{MaterialId, PlacedObject};
use penumbra::trace::{render, trace_ray, Light, Material, RenderSettings, SceneTables, TraceScene};

const TOL: f32 = 1e-5;

/// Radiance along one deterministic path with up to 8 bounces and no contribution cut-off.
fn radiance(scene: &TraceScene, ray: &Ray) -> Vec3 {
    let settings = RenderSettings { max_depth: 8, min_contribution: 0.0, ..Default::default() };
    trace_ray(scene, &settings, ray)
}

fn object(shape: Shape, material: u32) -> PlacedObject {
    PlacedObject { geometry: shape.place(&DAffine3::IDENTITY, DVec3::ZERO), material: MaterialId(material) }
}

fn scene(
    objects: &[PlacedObject],
    materials: Vec<Material>,
    lights: Vec<Light>,
    camera: Camera,
    ambient: Vec3,
) -> TraceScene {
    let tables = SceneTables { materials, lights, camera, background: Vec3::ZERO, ambient };
    TraceScene::build(objects, tables, DEFAULT_LAMBDA)
}

/// An 11×11 image: pixel (5, 5) is centred exactly on the view axis.
fn centre_pixel(scene: &TraceScene) -> Vec3 {
    let settings = RenderSettings { width: 11, height: 11, max_depth: 5, ..Default::default() };
    let (film, _) = render(scene, &settings);
    film.get(5, 5)
}

fn assert_close(got: Vec3, want: Vec3, what: &str) {
    assert!((got - want).abs().max_element() < TOL, "{what}: got {got}, want {want}");
}

fn head_on_camera() -> Camera {
    Camera::look_at(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 30f32.to_radians())
}

fn point_light(position: Vec3, radiance: Vec3) -> Light {
    Light::Point { position, radiance, falloff: Default::default() }
}

#[test]
fn diffuse_sphere_lit_head_on_is_ambient_plus_kd_times_intensity() {
    let kd = Vec3::new(0.6, 0.4, 0.2);
    let (ambient, intensity) = (Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.9, 0.8, 0.7));
    let m = Material { kd, ..Default::default() };
    let sphere = object(Shape::Sphere { centre: DVec3::ZERO, radius: 1.0 }, 0);
    // The light sits at the eye, so N·L = 1 where the view axis meets the sphere.
    let s = scene(
        &[sphere],
        vec![m],
        vec![point_light(Vec3::new(0.0, 0.0, -5.0), intensity)],
        head_on_camera(),
        ambient,
    );
    assert_close(centre_pixel(&s), ambient * kd + kd * intensity, "centre pixel");
}

#[test]
fn point_in_shadow_receives_ambient_only() {
    let kd = Vec3::new(0.5, 0.7, 0.9);
    let ambient = Vec3::splat(0.15);
    let floor = object(Shape::Plane { point: DVec3::ZERO, normal: Vec3::Y }, 0);
    let blocker = object(Shape::Sphere { centre: DVec3::new(0.0, 2.0, 0.0), radius: 0.5 }, 1);
    let light = point_light(Vec3::new(0.0, 5.0, 0.0), Vec3::ONE);
    // Looking straight down at the origin past the blocker's side is awkward; look from an angle.
    let camera = Camera::look_at(Vec3::new(0.0, 3.0, -3.0), Vec3::ZERO, Vec3::Y, 20f32.to_radians());
    let materials = vec![Material { kd, ..Default::default() }, Material::default()];
    let shadowed = scene(&[floor.clone(), blocker], materials.clone(), vec![light], camera, ambient);
    assert_close(centre_pixel(&shadowed), ambient * kd, "shadowed floor");
    // Without the blocker the same point is lit head-on: N·L = 1.
    let lit = scene(&[floor], materials, vec![light], camera, ambient);
    assert_close(centre_pixel(&lit), ambient * kd + kd, "lit floor");
}

#[test]
fn specular_peak_where_r_dot_v_is_one_adds_ks_times_intensity() {
    let kd = Vec3::splat(0.2);
    let (ks, intensity) = (0.5, 0.8);
    let m = Material { kd, ks, shininess: 50.0, ..Default::default() };
    let sphere = object(Shape::Sphere { centre: DVec3::ZERO, radius: 1.0 }, 0);
    let light = point_light(Vec3::new(0.0, 0.0, -5.0), Vec3::splat(intensity));
    let s = scene(&[sphere], vec![m], vec![light], head_on_camera(), Vec3::ZERO);
    let settings = RenderSettings { width: 11, height: 11, max_depth: 0, ..Default::default() };
    let (film, _) = render(&s, &settings);
    assert_close(film.get(5, 5), kd * intensity + Vec3::splat(ks * intensity), "peak");
    // Away from the peak the highlight falls off far faster than the diffuse term.
    let off = film.get(7, 5);
    assert!(off.x < film.get(5, 5).x - ks * intensity * 0.5, "highlight should be narrow: {off}");
}

#[test]
fn mirror_shows_the_colour_of_what_it_faces() {
    // The camera looks at a mirror; behind the camera a wall lit by ambient light only.
    let wall_kd = Vec3::new(0.2, 0.5, 0.9);
    let ambient = Vec3::ONE;
    let kr = 0.8;
    let mirror = object(Shape::Plane { point: DVec3::new(0.0, 0.0, 2.0), normal: -Vec3::Z }, 0);
    let wall = object(Shape::Plane { point: DVec3::new(0.0, 0.0, -10.0), normal: Vec3::Z }, 1);
    let materials = vec![
        Material { kd: Vec3::ZERO, kr, ..Default::default() },
        Material { kd: wall_kd, ..Default::default() },
    ];
    let s = scene(&[mirror, wall], materials, vec![], head_on_camera(), ambient);
    assert_close(centre_pixel(&s), kr * ambient * wall_kd, "mirror pixel");
}

/// A detector plane `z = 5` lit by a point light near it: its brightness N·L identifies the
/// point where a ray lands. Returns that point's x from the measured radiance.
fn landing_x(scene: &TraceScene, ray: &Ray, light: Vec3) -> f32 {
    let n_dot_l = radiance(scene, ray).x;
    let h = 5.0 - light.z;
    light.x + ((h / n_dot_l).powi(2) - h * h).max(0.0).sqrt()
}

#[test]
fn glass_slab_shifts_a_ray_by_the_analytic_lateral_offset() {
    let (d, ior) = (1.0f32, 1.5f32);
    let light = Vec3::new(-5.0, 0.0, 4.0);
    let detector = object(Shape::Plane { point: DVec3::new(0.0, 0.0, 5.0), normal: -Vec3::Z }, 0);
    let slab = object(
        Shape::Cuboid { min: DVec3::new(-50.0, -50.0, 0.0), max: DVec3::new(50.0, 50.0, f64::from(d)) },
        1,
    );
    let materials = vec![
        Material { kd: Vec3::ONE, ..Default::default() },
        Material { kd: Vec3::ZERO, kt: Vec3::ONE, ior, ..Default::default() },
    ];
    let camera = head_on_camera();
    let lights = vec![point_light(light, Vec3::ONE)];
    let with_slab = scene(&[detector.clone(), slab], materials.clone(), lights.clone(), camera, Vec3::ZERO);
    let without = scene(&[detector], materials, lights, camera, Vec3::ZERO);
    let origin = Vec3::new(0.0, 0.0, -1.0);
    for theta_deg in [10.0f32, 30.0, 50.0, 65.0] {
        let theta = theta_deg.to_radians();
        let ray = Ray::new(origin, Vec3::new(theta.sin(), 0.0, theta.cos()));
        let theta_t = (theta.sin() / ior).asin();
        let lateral = d * (theta - theta_t).sin() / theta_t.cos();
        let straight_x = 6.0 * theta.tan();
        let expected_x = straight_x - lateral / theta.cos();
        let unshifted = landing_x(&without, &ray, light);
        let shifted = landing_x(&with_slab, &ray, light);
        assert!(
            (unshifted - straight_x).abs() < 1e-3,
            "θ={theta_deg}: no slab lands at {unshifted}, want {straight_x}"
        );
        assert!(
            (shifted - expected_x).abs() < 2e-3,
            "θ={theta_deg}: slab shifts to {shifted}, want {expected_x}"
        );
    }
}

#[test]
fn total_internal_reflection_past_the_critical_angle() {
    // A ray inside a glass block heads for its top face. Below the critical angle it leaves
    // through the top and sees the red wall above; past it, it reflects, leaves through the
    // side and sees the green wall beyond.
    let ior = 1.5f32;
    let critical = (1.0 / ior).asin().to_degrees();
    assert!((critical - 41.81).abs() < 0.01);
    let block =
        object(Shape::Cuboid { min: DVec3::new(-10.0, -10.0, 0.0), max: DVec3::new(1.0, 10.0, 1.0) }, 0);
    let red_wall = object(Shape::Plane { point: DVec3::new(0.0, 0.0, 1.2), normal: -Vec3::Z }, 1);
    let green_wall = object(Shape::Plane { point: DVec3::new(3.0, 0.0, 0.0), normal: -Vec3::X }, 2);
    let (red, green) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.8, 0.2));
    let materials = vec![
        Material { kd: Vec3::ZERO, kt: Vec3::ONE, ior, ..Default::default() },
        Material { kd: red, ..Default::default() },
        Material { kd: green, ..Default::default() },
    ];
    let s = scene(&[block, red_wall, green_wall], materials, vec![], head_on_camera(), Vec3::ONE);
    let seen = |theta_deg: f32| {
        let theta = theta_deg.to_radians();
        let ray = Ray::new(Vec3::new(0.0, 0.0, 0.5), Vec3::new(theta.sin(), 0.0, theta.cos()));
        radiance(&s, &ray)
    };
    assert_close(seen(30.0), red, "refracted out of the top");
    assert_close(seen(critical - 2.0), red, "just below the critical angle");
    assert_close(seen(60.0), green, "totally reflected, out of the side");
}
