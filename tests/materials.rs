//! Materials, textures and lights users expect: checked against analytic values (texture
//! lookups through each shape's coordinates, Schlick's Fresnel, inverse-square falloff, a visible
//! light's radiance, Beer–Lambert absorption, a bump map's tilt), OBJ materials and their
//! errors, and the inputs a frame records.

use std::path::Path;

use penumbra::math::{Ray, Vec3};
use penumbra::scene::{self, inputs::InputRole, inputs::Inputs, SceneDesc};
use penumbra::trace::{render, TraceScene};
use penumbra::world::SceneWorld;

/// Parses a scene whose files lie in `base`.
fn desc_at(text: &str, base: &Path) -> SceneDesc {
    scene::parse_scene_at(text, "materials-test.ron", base).unwrap_or_else(|e| panic!("{e}"))
}

fn desc(text: &str) -> SceneDesc {
    desc_at(text, Path::new("."))
}

/// Renders `d`: the linear film, row by row, and the snapshot it was traced from.
fn render_desc(d: &SceneDesc) -> (Vec<Vec3>, std::sync::Arc<TraceScene>) {
    let mut world: SceneWorld = scene::spawn_world(d);
    let snapshot = world.update();
    let (film, _) = render(&snapshot, &world.render_settings());
    (film.pixels, snapshot)
}

/// The ray through the centre of pixel `(x, y)` of `d`'s camera (one sample per pixel goes
/// there), in the snapshot's camera-relative space.
fn pixel_ray(scene: &TraceScene, d: &SceneDesc, x: u32, y: u32) -> Ray {
    scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, d.camera.width, d.camera.height)
}

/// A camera 10 units above the origin looking straight down (+z up in the picture), unlit
/// (ambient white, no lights), so a pixel shows `kd` × its texture.
const LOOKING_DOWN: &str =
    "camera: (position: (0, 10, 0), look_at: (0, 0, 0), up: (0, 0, 1), fov_deg: 60, width: 41, height: 41),
    settings: (max_depth: 0, ambient: (1, 1, 1), background: (0.25, 0.5, 0.75))";

fn checker(u: f32, v: f32, a: Vec3, b: Vec3) -> Vec3 {
    if (u.floor() + v.floor()) as i64 % 2 == 0 {
        a
    } else {
        b
    }
}

#[test]
fn a_checker_on_a_plane_shows_its_colours_where_the_world_coordinates_say() {
    let (a, b) = (Vec3::new(0.9, 0.2, 0.1), Vec3::new(0.1, 0.3, 0.8));
    for (scale, offset, rotate) in [(1.0f32, 0.0f32, 0.0f32), (2.0, 0.25, 0.0), (0.5, 0.0, 90.0)] {
        let text = format!(
            "Scene({LOOKING_DOWN},
            textures: [(name: \"c\", kind: Checker(a: (0.9, 0.2, 0.1), b: (0.1, 0.3, 0.8)), scale: ({scale}, {scale}), offset: ({offset}, 0), rotate_deg: {rotate})],
            materials: [(name: \"m\", kd: (1, 1, 1), kd_texture: Some(\"c\"))],
            objects: [(shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"m\")])"
        );
        let d = desc(&text);
        let (pixels, scene) = render_desc(&d);
        let (mut checked, mut seen_a, mut seen_b) = (0, 0, 0);
        for y in 0..41 {
            for x in 0..41 {
                let ray = pixel_ray(&scene, &d, x, y);
                // World point on the floor (the camera is at (0, 10, 0)).
                let p =
                    ray.origin + ray.dir * (-(ray.origin.y + 10.0) / ray.dir.y) + Vec3::new(0.0, 10.0, 0.0);
                // The floor's coordinates: u along +x, v along −z; then the texture's transform.
                let (u, v) = (p.x * scale, -p.z * scale);
                let (u, v) = if rotate == 90.0 { (-v, u) } else { (u, v) };
                let (s, t) = (u + offset, v);
                if (s - s.round()).abs() < 1e-3 || (t - t.round()).abs() < 1e-3 {
                    continue; // on a square's edge
                }
                let want = checker(s, t, a, b);
                assert_eq!(pixels[(y * 41 + x) as usize], want, "pixel ({x}, {y}) at {p}, scale {scale}");
                checked += 1;
                seen_a += usize::from(want == a);
                seen_b += usize::from(want == b);
            }
        }
        assert!(checked > 1500 && seen_a > 100 && seen_b > 100, "{checked} {seen_a} {seen_b}");
    }
}

/// Writes `files` into a fresh folder.
fn folder(files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temporary folder");
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).expect("write test file");
    }
    dir
}

/// A 2 × 2 quad on the floor, (−1, −1) to (1, 1) in x and z, with `vt` running u along +x and
/// v along +z.
const QUAD_OBJ: &str =
    "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 4/4 3/3 2/2\n";

#[test]
fn a_mesh_is_textured_by_its_vt_coordinates() {
    let dir = folder(&[("quad.obj", QUAD_OBJ.as_bytes())]);
    let text = format!(
        "Scene({LOOKING_DOWN},
        textures: [(name: \"ramp\", kind: Gradient(a: (0, 0, 0), b: (1, 0.5, 0.25)))],
        materials: [(name: \"m\", kd: (1, 1, 1), kd_texture: Some(\"ramp\"))],
        objects: [(shape: Mesh(file: \"quad.obj\", smooth: false), material: \"m\")])"
    );
    let d = desc_at(&text, dir.path());
    let (pixels, scene) = render_desc(&d);
    let mut checked = 0;
    for y in 0..41 {
        for x in 0..41 {
            let ray = pixel_ray(&scene, &d, x, y);
            let p = ray.origin + ray.dir * (-(ray.origin.y + 10.0) / ray.dir.y);
            if p.x.abs() > 0.99 || p.z.abs() > 0.99 {
                continue;
            }
            let u = (p.x + 1.0) / 2.0;
            let got = pixels[(y * 41 + x) as usize];
            let want = Vec3::new(1.0, 0.5, 0.25) * u;
            assert!((got - want).abs().max_element() < 1e-4, "pixel ({x}, {y}): {got} against {want}");
            checked += 1;
        }
    }
    assert!(checked > 30, "{checked}");

    // Without `vt` the same material is refused, at the object, naming the mesh.
    let flat = QUAD_OBJ
        .lines()
        .filter(|l| !l.starts_with("vt"))
        .map(|l| l.replace("/1", "").replace("/2", "").replace("/3", "").replace("/4", "") + "\n")
        .collect::<String>();
    let dir = folder(&[("quad.obj", flat.as_bytes())]);
    let error = scene::parse_scene_at(&text, "bad.ron", dir.path()).unwrap_err().to_string();
    assert!(
        error.contains("objects[0].material") && error.contains("no texture coordinates (`vt` lines)"),
        "{error}"
    );
}

/// Two triangles of the quad, one with each of the library's materials.
const TWO_MATERIALS_OBJ: &str =
    "mtllib m.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl red\nf 1 4 2\nusemtl blue\nf 2 4 3\n";
const TWO_MATERIALS_MTL: &str =
    "# two colours\nnewmtl red\nKd 0.8 0.1 0.1\n\nnewmtl blue\nKd 0.1 0.2 0.9\nKs 0.5 0.5 0.5\nNs 10\n";

#[test]
fn a_mesh_takes_its_faces_materials_from_its_mtl_and_the_scene_overrides_them_by_name() {
    let dir = folder(&[("q.obj", TWO_MATERIALS_OBJ.as_bytes()), ("m.mtl", TWO_MATERIALS_MTL.as_bytes())]);
    let scene_with = |extra: &str| {
        format!(
            "Scene({LOOKING_DOWN},
            materials: [(name: \"fallback\", kd: (0.5, 0.5, 0.5)){extra}],
            objects: [(shape: Mesh(file: \"q.obj\", smooth: false, materials: FromFile), material: \"fallback\")])"
        )
    };
    // The triangle (1, 4, 2) covers x + z < 0 (seen from above, +z up in the picture).
    let colours = |d: &SceneDesc| {
        let (pixels, scene) = render_desc(d);
        let (mut lower, mut upper) = (None, None);
        for y in 0..41 {
            for x in 0..41 {
                let ray = pixel_ray(&scene, d, x, y);
                let p = ray.origin + ray.dir * (-(ray.origin.y + 10.0) / ray.dir.y);
                if p.x.abs() > 0.9 || p.z.abs() > 0.9 || (p.x + p.z).abs() < 0.1 {
                    continue;
                }
                let slot = if p.x + p.z < 0.0 { &mut lower } else { &mut upper };
                let got = pixels[(y * 41 + x) as usize];
                assert_eq!(*slot.get_or_insert(got), got, "one colour per triangle");
            }
        }
        (lower.expect("seen"), upper.expect("seen"))
    };
    let d = desc_at(&scene_with(""), dir.path());
    assert_eq!(colours(&d), (Vec3::new(0.8, 0.1, 0.1), Vec3::new(0.1, 0.2, 0.9)));
    let d = desc_at(&scene_with(", (name: \"blue\", kd: (0, 1, 0))"), dir.path());
    assert_eq!(colours(&d), (Vec3::new(0.8, 0.1, 0.1), Vec3::new(0.0, 1.0, 0.0)), "the scene's `blue` wins");
    // Without `FromFile` the object's own material is everywhere.
    let plain = scene_with("").replace(", materials: FromFile", "");
    assert_eq!(colours(&desc_at(&plain, dir.path())), (Vec3::splat(0.5), Vec3::splat(0.5)));

    // The library and its images are inputs of the frame.
    let inputs = Inputs::of_scene("s.ron", &dir.path().join("s.ron"), b"", &d).expect("inputs");
    let library: Vec<_> = inputs.files.iter().filter(|f| f.role == InputRole::Library).collect();
    assert_eq!(library.len(), 1, "{inputs:?}");
    assert_eq!(library[0].name, "m.mtl");
}

#[test]
fn mtl_errors_name_the_library_and_its_line() {
    let cases = [
        ("newmtl red\nKd 0.8 x 0.1\n", "m.mtl:2"),
        ("Kd 0.8 0.1 0.1\n", "m.mtl:1"),
        (
            "newmtl red\nKd 0.8 1.5 0.1\nnewmtl blue\n",
            "m.mtl:1: material `red`: Kd must be in [0, 1] in every channel, got 1.5",
        ),
    ];
    for (mtl, want) in cases {
        let dir = folder(&[("q.obj", TWO_MATERIALS_OBJ.as_bytes()), ("m.mtl", mtl.as_bytes())]);
        let text = format!(
            "Scene({LOOKING_DOWN}, materials: [(name: \"f\", kd: (0.5, 0.5, 0.5))],
            objects: [(shape: Mesh(file: \"q.obj\", materials: FromFile), material: \"f\")])"
        );
        let error = scene::parse_scene_at(&text, "s.ron", dir.path()).unwrap_err().to_string();
        assert!(error.contains("objects[0].shape.file") && error.contains(want), "{mtl:?}: {error}");
    }
}

#[test]
fn an_image_texture_and_an_mtl_image_are_recorded_inputs_and_a_changed_image_changes_the_fingerprint() {
    let png = |colour: [u8; 3]| {
        let mut bytes = Vec::new();
        let image = image::RgbImage::from_pixel(2, 2, image::Rgb(colour));
        image.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).expect("encode");
        bytes
    };
    let mtl = "newmtl red\nmap_Kd tex/red.png\n";
    let obj =
        "mtllib m.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl red\nf 1/1 3/3 2/2\n";
    let dir =
        folder(&[("q.obj", obj.as_bytes()), ("m.mtl", mtl.as_bytes()), ("floor.png", &png([200, 100, 50]))]);
    std::fs::create_dir(dir.path().join("tex")).expect("folder");
    std::fs::write(dir.path().join("tex/red.png"), png([255, 0, 0])).expect("write");
    let text = format!(
        "Scene({LOOKING_DOWN},
        textures: [(name: \"floor\", kind: Image(file: \"floor.png\"))],
        materials: [(name: \"f\", kd: (1, 1, 1), kd_texture: Some(\"floor\"))],
        objects: [
            (shape: Plane(point: (0, -1, 0), normal: (0, 1, 0)), material: \"f\"),
            (shape: Mesh(file: \"q.obj\", materials: FromFile), material: \"f\"),
        ])"
    );
    let d = desc_at(&text, dir.path());
    let scene_path = dir.path().join("s.ron");
    let inputs = Inputs::of_scene("s.ron", &scene_path, text.as_bytes(), &d).expect("inputs");
    let named: Vec<(InputRole, &str)> = inputs.files.iter().map(|f| (f.role, f.name.as_str())).collect();
    assert_eq!(
        named,
        [
            (InputRole::Scene, "s.ron"),
            (InputRole::Mesh, "q.obj"),
            (InputRole::Library, "m.mtl"),
            (InputRole::Texture, "floor.png"),
            (InputRole::Texture, "tex/red.png"),
        ]
    );
    // The sRGB texel 200/255 is decoded to linear light: the floor shows it, times kd = 1.
    let (pixels, _) = render_desc(&d);
    let linear = |c: f32| ((c / 255.0 + 0.055) / 1.055).powf(2.4);
    let corner = pixels[0];
    assert!(
        (corner - Vec3::new(linear(200.0), linear(100.0), linear(50.0))).abs().max_element() < 1e-5,
        "{corner}"
    );
    // A changed image is a changed input.
    std::fs::write(dir.path().join("tex/red.png"), png([254, 0, 0])).expect("write");
    let d2 = desc_at(&text, dir.path());
    let changed = Inputs::of_scene("s.ron", &scene_path, text.as_bytes(), &d2).expect("inputs");
    assert_ne!(inputs.fingerprint(), changed.fingerprint());
}

/// Schlick's approximation, written out independently of the renderer.
fn schlick(cos: f64, n1: f64, n2: f64) -> f64 {
    let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}

#[test]
fn fresnel_glass_reflects_what_schlick_says_at_every_angle() {
    // A glass floor over a black one, under a white sky: a pixel shows the reflected sky,
    // F(θ) × kt, the refracted ray finding black below.
    let text = "Scene(
        camera: (position: (0, 1, -3), look_at: (0, 0, 0), fov_deg: 70, width: 9, height: 41),
        settings: (max_depth: 3, ambient: (0, 0, 0), background: (1, 1, 1)),
        materials: [
            (name: \"glass\", kd: (0, 0, 0), kt: 0.9, ior: 1.5, fresnel: true),
            (name: \"black\", kd: (0, 0, 0)),
        ],
        objects: [
            (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"glass\"),
            (shape: Plane(point: (0, -1, 0), normal: (0, 1, 0)), material: \"black\"),
        ])";
    let d = desc(text);
    let (pixels, scene) = render_desc(&d);
    let mut angles = Vec::new();
    for y in 0..41 {
        let ray = pixel_ray(&scene, &d, 4, y);
        if ray.dir.y >= -1e-3 {
            continue; // the sky
        }
        let cos = f64::from(-ray.dir.y / ray.dir.length());
        let want = 0.9 * schlick(cos, 1.0, 1.5);
        let got = pixels[(y * 9 + 4) as usize];
        assert!(
            (f64::from(got.x) - want).abs() < 2e-6 && got.x == got.y,
            "row {y}: cos {cos}: {got} against {want}"
        );
        angles.push(cos.acos().to_degrees());
    }
    let (lo, hi) = angles.iter().fold((f64::MAX, 0.0f64), |(lo, hi), &a| (lo.min(a), hi.max(a)));
    assert!(lo < 55.0 && hi > 85.0, "angles {lo}..{hi}");
    // Without Fresnel the floor reflects nothing (kr = 0).
    let (plain, _) = render_desc(&desc(&text.replace(", fresnel: true", "")));
    assert_eq!(plain[40 * 9 + 4], Vec3::ZERO);
}

#[test]
fn inverse_square_falloff_lights_a_floor_as_the_analytic_value_and_none_does_not_fall_off() {
    for (height, falloff) in [(2.0f32, "InverseSquare"), (4.0, "InverseSquare"), (4.0, "None")] {
        let text = format!(
            "Scene(
            camera: (position: (0, 10, 0), look_at: (0, 0, 0), up: (0, 0, 1), fov_deg: 30, width: 21, height: 21),
            settings: (max_depth: 0, ambient: (0, 0, 0)),
            materials: [(name: \"m\", kd: (0.5, 0.5, 0.5))],
            lights: [Point(position: (0, {height}, 0), colour: (1, 0.5, 0.25), intensity: 8, falloff: {falloff})],
            objects: [(shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"m\")])"
        );
        let (pixels, _) = render_desc(&desc(&text));
        // The centre pixel looks straight down at the point under the light: N·L = 1.
        let got = pixels[10 * 21 + 10];
        let radiance = Vec3::new(8.0, 4.0, 2.0) * 0.5;
        let want = if falloff == "None" { radiance } else { radiance / (height * height) };
        assert!(
            (got - want).abs().max_element() <= 1e-6 * want.max_element(),
            "{height} {falloff}: {got} against {want}"
        );
    }
}

#[test]
fn a_visible_light_is_seen_with_its_radiance_directly_and_in_a_mirror_and_an_invisible_one_is_not() {
    let scene_with = |visible: bool, mirror: bool| {
        let floor = if mirror {
            "(name: \"floor\", kd: (0, 0, 0), kr: 0.5)"
        } else {
            "(name: \"floor\", kd: (0, 0, 0))"
        };
        format!(
            "Scene(
            camera: (position: (0, 1, 0), look_at: (0, {}, 0), up: (0, 0, 1), fov_deg: 20, width: 11, height: 11),
            settings: (max_depth: 2, ambient: (0, 0, 0), background: (0.1, 0.1, 0.1)),
            materials: [{floor}],
            lights: [Rect(corner: (-1, 3, -1), edge_u: (2, 0, 0), edge_v: (0, 0, 2), colour: (1, 0.5, 0.25), intensity: 2, visible: {visible})],
            objects: [(shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"floor\")])",
            if mirror { -1 } else { 3 }
        )
    };
    let centre = |text: &str| render_desc(&desc(text)).0[5 * 11 + 5];
    let radiance = Vec3::new(2.0, 1.0, 0.5);
    assert_eq!(centre(&scene_with(true, false)), radiance, "looking up at the light");
    assert_eq!(centre(&scene_with(false, false)), Vec3::splat(0.1), "an invisible light: the background");
    assert_eq!(centre(&scene_with(true, true)), 0.5 * radiance, "its reflection in a half mirror");
    // Seen from above it does not cast a shadow on itself nor light itself: it is a light.
}

#[test]
fn emission_shows_on_its_own_and_lights_nothing_else() {
    let text = "Scene(
        camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 30, width: 21, height: 21),
        settings: (max_depth: 2, ambient: (0, 0, 0)),
        materials: [(name: \"lamp\", kd: (0, 0, 0), emission: (0.3, 0.2, 0.1)), (name: \"wall\", kd: (1, 1, 1))],
        objects: [
            (shape: Sphere(centre: (0, 0, 0), radius: 1), material: \"lamp\"),
            (shape: Plane(point: (0, 0, 2), normal: (0, 0, -1)), material: \"wall\"),
        ])";
    let (pixels, _) = render_desc(&desc(text));
    assert_eq!(pixels[10 * 21 + 10], Vec3::new(0.3, 0.2, 0.1));
    assert_eq!(pixels[0], Vec3::ZERO, "the wall beside it stays dark");
}

#[test]
fn light_through_absorbing_glass_keeps_exp_of_minus_sigma_times_the_distance() {
    // A glass slab 2 units thick, ior 1 (no bending), seen straight through against white.
    for (sigma, thick) in [((0.5f32, 0.1f32, 0.0f32), 2.0f32), ((0.2, 0.4, 1.0), 0.5)] {
        let text = format!(
            "Scene(
            camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 10, width: 5, height: 5),
            settings: (max_depth: 4, ambient: (0, 0, 0), background: (1, 1, 1)),
            materials: [(name: \"glass\", kd: (0, 0, 0), kt: 1, ior: 1, absorption: ({}, {}, {}))],
            objects: [(shape: Box(min: (-1, -1, 0), max: (1, 1, {thick})), material: \"glass\")])",
            sigma.0, sigma.1, sigma.2
        );
        let got = render_desc(&desc(&text)).0[2 * 5 + 2];
        let want = Vec3::new((-sigma.0 * thick).exp(), (-sigma.1 * thick).exp(), (-sigma.2 * thick).exp());
        assert!((got - want).abs().max_element() < 1e-5, "{sigma:?}: {got} against {want}");
    }
}

#[test]
fn tinted_glass_casts_a_tinted_shadow_each_channel_multiplied_per_crossing() {
    let text = "Scene(
        camera: (position: (0, 3, -6), look_at: (0, 0, 0), fov_deg: 40, width: 8, height: 8),
        materials: [(name: \"glass\", kd: (0, 0, 0), kt: (0.9, 0.5, 0.2)), (name: \"floor\", kd: (1, 1, 1))],
        lights: [Point(position: (0, 5, 0))],
        objects: [
            (shape: Sphere(centre: (0, 1, 0), radius: 0.5), material: \"glass\"),
            (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"floor\"),
        ])";
    let d = desc(text);
    let (_, scene) = render_desc(&d);
    // From the floor under the ball up to the light (camera-relative: the camera is at (0, 3, -6)).
    let floor = Vec3::new(0.0, -3.0 + 1e-3, 6.0);
    let pass = penumbra::trace::transmittance(&scene, &Ray::new(floor, Vec3::Y), 4.99);
    let kt = Vec3::new(0.9, 0.5, 0.2);
    assert_eq!(pass, Vec3::ONE * kt * kt, "two crossings of the ball");
    let beside = penumbra::trace::transmittance(&scene, &Ray::new(floor + Vec3::X * 2.0, Vec3::Y), 5.0);
    assert_eq!(beside, Vec3::ONE);
}

#[test]
fn a_spot_light_is_full_under_its_axis_and_dark_outside_its_cone() {
    let text = "Scene(
        camera: (position: (0, 10, 0), look_at: (0, 0, 0), up: (0, 0, 1), fov_deg: 60, width: 41, height: 41),
        settings: (max_depth: 0, ambient: (0, 0, 0)),
        materials: [(name: \"m\", kd: (1, 1, 1))],
        lights: [Spot(position: (0, 4, 0), look_at: (0, 0, 0), cone_deg: 20, soft_deg: 5, intensity: 2)],
        objects: [(shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"m\")])";
    let d = desc(text);
    let (pixels, scene) = render_desc(&d);
    for y in 0..41 {
        for x in 0..41 {
            let ray = pixel_ray(&scene, &d, x, y);
            let p = ray.origin + ray.dir * (-(ray.origin.y + 10.0) / ray.dir.y);
            let to = Vec3::new(0.0, -10.0 + 4.0, 0.0) - p;
            let angle = (to.normalize().dot(Vec3::Y)).acos().to_degrees();
            let lit = pixels[(y * 41 + x) as usize].x;
            let n_dot_l = to.normalize().y;
            if angle < 14.9 {
                assert!((lit - 2.0 * n_dot_l).abs() < 1e-5, "({x}, {y}) at {angle}°: {lit}");
            } else if angle > 20.1 {
                assert_eq!(lit, 0.0, "({x}, {y}) at {angle}°");
            }
        }
    }
}

#[test]
fn a_bump_ramp_tilts_the_shading_normal_by_its_slope() {
    // Height = the gradient's s = 0.1·u + 0.5 (u along +x on the floor), depth 5: the floor
    // looks displaced by 0.5·u, a slope of 0.5, so light from straight above arrives at
    // N·L = 1/√1.25 instead of 1.
    let text = |depth: f32| {
        format!(
            "Scene(
            camera: (position: (0, 10, 0), look_at: (0, 0, 0), up: (0, 0, 1), fov_deg: 30, width: 11, height: 11),
            settings: (max_depth: 0, ambient: (0, 0, 0)),
            textures: [(name: \"ramp\", kind: Gradient(a: (0, 0, 0), b: (1, 1, 1)), scale: (0.1, 0.1), offset: (0.5, 0))],
            materials: [(name: \"m\", kd: (1, 1, 1), bump_texture: Some(\"ramp\"), bump_depth: {depth})],
            lights: [Directional(direction: (0, -1, 0))],
            objects: [(shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: \"m\")])"
        )
    };
    let flat = render_desc(&desc(&text(0.0))).0;
    let bumped = render_desc(&desc(&text(5.0))).0;
    for i in 0..121 {
        assert_eq!(flat[i], Vec3::ONE, "a flat floor faces the light");
        assert!((bumped[i].x - 1.0 / 1.25f32.sqrt()).abs() < 1e-3, "pixel {i}: {}", bumped[i]);
    }
}

/// FNV-1a over the bits of every channel of every pixel.
fn film_hash(pixels: &[Vec3]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for c in pixels.iter().flat_map(|p| p.to_array()) {
        for b in c.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x100000001b3);
        }
    }
    h
}

#[test]
fn scenes_without_the_new_features_render_the_same_bits_as_before_them() {
    // Hashes of the linear films rendered by the code before textures, visible lights,
    // falloff, Fresnel and coloured `kt` existed (commit d4a1458, at 64 pixels wide). Except
    // effects_dof's: its AA 1 lens samples each take a pixel position of their own since the
    // lens anti-aliases (issue 19; it was 0x7e43cfcf78e33357), a change of sampling, not of
    // materials. And except effects_glossy's: since the Phong highlight raises `R·V` to a whole
    // shininess by squaring in 64-bit floats instead of libm's `powf` (within an ulp of the exact
    // power either way), some of its highlights round differently in the last bits (it was
    // 0xe3d8bf6c3b5744c3); its 8-bit image is the same bytes, at 64 and at 640 pixels wide.
    let before = [
        ("default", 0xa3e25336fccb5a7b_u64),
        ("spheres", 0x51c3ee7fb1ef2d2d),
        ("effects_soft_shadows", 0x67d21a1a83151fd5),
        ("effects_glossy", 0x13b498bf9feeffc2),
        ("effects_dof", 0x8577b96ac7d3e6c0),
        ("bunny", 0x5f16055a6a454a29),
        ("showcase", 0x374877f19cb0eaa1),
    ];
    for (name, want) in before {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.ron"));
        let mut d = scene::load_scene(&path).expect("shipped scene");
        let aspect = f64::from(d.camera.height) / f64::from(d.camera.width);
        d.camera.width = 64;
        d.camera.height = ((64.0 * aspect).round() as u32).max(1);
        let (pixels, _) = render_desc(&d);
        assert_eq!(film_hash(&pixels), want, "{name} changed");
    }
}

#[test]
fn every_new_rule_is_reported_at_its_field_with_line_and_column() {
    let base = "Scene(
    camera: (position: (0, 1, -5), look_at: (0, 0, 0), fov_deg: 45, width: 8, height: 8),
    textures: [(name: \"t\", kind: Checker(a: (1, 1, 1), b: (0, 0, 0)), scale: (1, 1))],
    materials: [(name: \"m\", kd: (0.5, 0.5, 0.5), kd_texture: Some(\"t\"), kt: 0.5)],
    lights: [Spot(position: (0, 5, 0), look_at: (0, 0, 0), cone_deg: 20, soft_deg: 5)],
    objects: [(shape: Sphere(centre: (0, 0, 0), radius: 1), material: \"m\")],
)";
    desc(base);
    let cases = [
        (
            "kd_texture: Some(\"t\")",
            "kd_texture: Some(\"wood\")",
            4,
            "materials[0].kd_texture",
            "names no texture `wood` (defined: `t`)",
        ),
        ("scale: (1, 1)", "scale: (1, 0)", 3, "textures[0].scale", "must be non-zero in every component"),
        ("b: (0, 0, 0)", "b: (0, -1, 0)", 3, "textures[0].kind.b", "must be >= 0 in every channel"),
        (
            "Checker(a: (1, 1, 1), b: (0, 0, 0))",
            "Noise(a: (1, 1, 1), b: (0, 0, 0), octaves: 17)",
            3,
            "textures[0].kind.octaves",
            "must be in 1..=16, got 17",
        ),
        ("cone_deg: 20", "cone_deg: 95", 5, "lights[0].cone_deg", "must be in (0, 90] degrees, got 95"),
        (
            "soft_deg: 5",
            "soft_deg: 25",
            5,
            "lights[0].soft_deg",
            "must be in [0, cone_deg] = [0, 20] degrees, got 25",
        ),
        (
            "look_at: (0, 0, 0), cone",
            "look_at: (0, 5, 0), cone",
            5,
            "lights[0].look_at",
            "must differ from `position`",
        ),
        (
            "kt: 0.5",
            "kt: (0.5, 1.5, 0.2)",
            4,
            "materials[0].kt",
            "must be in [0, 1] in every channel, got g = 1.5",
        ),
        (
            "kt: 0.5",
            "kt: (0.5, 0.9, 0.2), kr: 0.5",
            4,
            "materials[0].kt",
            "`kr + kt` must be <= 1 in its largest channel",
        ),
        (
            "kt: 0.5",
            "kt: 0.5, emission: (0, -1, 0)",
            4,
            "materials[0].emission",
            "must be >= 0 in every channel",
        ),
        (
            "kt: 0.5",
            "kt: 0.5, absorption: (0, 0, -2)",
            4,
            "materials[0].absorption",
            "must be >= 0 in every channel",
        ),
    ];
    for (from, to, line, field, rule) in cases {
        assert!(base.contains(from), "{from}");
        let text = base.replacen(from, to, 1);
        let error = scene::parse_scene(&text, "rules.ron").expect_err(to).to_string();
        assert!(
            error.starts_with(&format!("rules.ron:{line}:"))
                && error.contains(&format!("field `{field}`"))
                && error.contains(rule),
            "{to}: {error}"
        );
    }
    // An image that cannot be read names the file field and the file.
    let text = base.replacen("Checker(a: (1, 1, 1), b: (0, 0, 0))", "Image(file: \"missing.png\")", 1);
    let error = scene::parse_scene(&text, "rules.ron").expect_err("missing image").to_string();
    assert!(error.contains("field `textures[0].kind.file`") && error.contains("missing.png"), "{error}");
}

#[test]
fn a_script_cannot_set_one_material_on_a_mesh_whose_faces_take_their_files() {
    use penumbra::script::{Animation, Limits, Script};
    let dir = folder(&[("q.obj", TWO_MATERIALS_OBJ.as_bytes()), ("m.mtl", TWO_MATERIALS_MTL.as_bytes())]);
    let text = format!(
        "Scene({LOOKING_DOWN}, materials: [(name: \"f\", kd: (0.5, 0.5, 0.5))],
        objects: [(name: \"table\", shape: Mesh(file: \"q.obj\", materials: FromFile), material: \"f\")])"
    );
    let d = desc_at(&text, dir.path());
    let script = Script::from_source(
        "t.rhai",
        "fn frame(t) { let e = entity(\"table\"); e.kd = vec3(1, 0, 0); }",
        Limits::default(),
    )
    .expect("compiles");
    let mut animation: Animation = Animation::new(&d, &script, 24.0).expect("starts");
    let error = animation.step_to(0).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(error.contains("entity `table` takes its faces' materials from its file"), "{error}");
}
