//! Scene loading errors: every validation rule and every kind of RON error must name the
//! right line, column and field, and say what is wrong. Each case changes one line of a
//! small valid scene; expected columns are found by searching the changed line.

use penumbra::scene::{load_scene, parse_scene, SceneError, ToneOperator};

/// A small valid scene using every type; tests change one line of it.
const BASE: &str = r#"// A minimal valid scene; each test changes one line.
Scene(
    camera: (
        position: (0.0, 1.0, -5.0),
        look_at: (0.0, 0.0, 0.0),
        up: (0.0, 1.0, 0.0),
        fov_deg: 45.0,
        width: 64,
        height: 48,
    ),
    settings: (
        max_depth: 5,
        min_contribution: 0.001,
        background: (0.1, 0.1, 0.1),
        ambient: (0.1, 0.1, 0.1),
        seed: 1,
    ),
    materials: [
        (name: "red", kd: (0.8, 0.1, 0.1), ks: 0.5, shininess: 32.0, kr: 0.2, kt: 0.0, ior: 1.5, glossiness: 0.0),
        (name: "white", kd: (0.9, 0.9, 0.9)),
    ],
    lights: [
        Point(position: (0.0, 5.0, -5.0), colour: (1.0, 1.0, 1.0), intensity: 1.0),
        Directional(direction: (0.0, -1.0, 0.0), colour: (1.0, 1.0, 1.0), intensity: 0.5),
    ],
    objects: [
        (name: "ball", shape: Sphere(centre: (0.0, 1.0, 0.0), radius: 1.0), material: "red"),
        (name: "floor", shape: Plane(point: (0.0, 0.0, 0.0), normal: (0.0, 1.0, 0.0)), material: "white"),
        (shape: Triangle(vertices: ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))), material: "red"),
        (shape: Polygon(vertices: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]), material: "white"),
        (shape: Box(min: (-1.0, 0.0, -1.0), max: (1.0, 1.0, 1.0)), material: "red", transform: (translate: (0.0, 0.0, 0.0), rotate_deg: (0.0, 30.0, 0.0), scale: (1.0, 2.0, 1.0))),
    ],
)
"#;

/// `BASE` with `from` replaced by `to` on the 1-based `line` (which must contain `from`).
fn edit(line: usize, from: &str, to: &str) -> String {
    edit_text(BASE, line, from, to)
}

fn edit_text(text: &str, line: usize, from: &str, to: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let target = &mut lines[line - 1];
    assert!(target.contains(from), "line {line} `{target}` lacks `{from}`");
    *target = target.replacen(from, to, 1);
    lines.join("\n") + "\n"
}

/// The 1-based character column of the first `needle` on `line` of `text`; a `|` in the
/// needle marks the column within it (`"radius: |0.0"` is the column of `0.0`).
fn col_of(text: &str, line: usize, needle: &str) -> usize {
    let target = text.lines().nth(line - 1).expect("line exists");
    let (before, after) = needle.split_once('|').unwrap_or(("", needle));
    let whole = format!("{before}{after}");
    let byte = target.find(&whole).unwrap_or_else(|| panic!("line {line} `{target}` lacks `{whole}`"));
    target[..byte].chars().count() + before.chars().count() + 1
}

/// Asserts that `text` fails at `line`, at the column where `at` starts on that line (see
/// [`col_of`]), in
/// `field`, with a rule containing each of `rule_parts`.
fn assert_invalid(text: &str, line: usize, at: &str, field: &str, rule_parts: &[&str]) {
    let col = col_of(text, line, at);
    let error = parse_scene(text, "bad.ron").expect_err("the scene must be rejected");
    let message = error.to_string();
    let SceneError::Invalid { path, line: got_line, col: got_col, field: got_field, rule } = error else {
        panic!("expected SceneError::Invalid, got {message}");
    };
    assert_eq!(path, "bad.ron");
    assert_eq!((got_line, got_col, got_field.as_str()), (line, col, field), "{message}");
    for part in rule_parts {
        assert!(rule.contains(part), "rule `{rule}` lacks `{part}`");
    }
    assert!(message.starts_with(&format!("bad.ron:{line}:{col}: field `{field}`: ")), "{message}");
}

#[test]
fn the_base_scene_and_the_shipped_scenes_are_valid() {
    parse_scene(BASE, "base.ron").expect("BASE is valid");
    for file in ["scenes/default.ron", "scenes/every_type.ron"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
        if let Err(error) = load_scene(&path) {
            panic!("{error}");
        }
    }
    let every = load_scene(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/every_type.ron"))
        .expect("valid");
    let kinds: Vec<&str> = every.objects.iter().map(|o| o.shape.kind()).collect();
    for kind in ["sphere", "plane", "triangle", "polygon", "box", "mesh"] {
        assert!(kinds.contains(&kind), "every_type.ron lacks a {kind}");
    }
    use penumbra::scene::LightDesc;
    let light_kinds = [
        ("Point", (|l| matches!(l, LightDesc::Point { .. })) as fn(&LightDesc) -> bool),
        ("Directional", |l| matches!(l, LightDesc::Directional { .. })),
        ("Rect", |l| matches!(l, LightDesc::Rect { .. })),
        ("Disk", |l| matches!(l, LightDesc::Disk { .. })),
    ];
    for (kind, is_kind) in light_kinds {
        assert!(every.lights.iter().any(is_kind), "every_type.ron lacks a {kind} light");
    }
    assert!(
        every.camera.aperture > 0.0 && every.camera.focus_on.is_some(),
        "every_type.ron lacks depth of field"
    );
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let error = load_scene("no/such/dir/scene.ron".as_ref()).expect_err("missing");
    assert!(matches!(error, SceneError::Io { .. }));
    assert!(error.to_string().starts_with("no/such/dir/scene.ron: cannot read scene: "), "{error}");
}

// ---------------------------------------------------------------------------------------
// Camera
// ---------------------------------------------------------------------------------------

#[test]
fn fov_must_be_strictly_between_0_and_180() {
    for bad in ["0.0", "180.0", "-10.0", "200.0"] {
        let text = edit(7, "45.0", bad);
        assert_invalid(
            &text,
            7,
            bad,
            "camera.fov_deg",
            &["must be in (0, 180)", &format!("got {}", &bad[..bad.len() - 2])],
        );
    }
    parse_scene(&edit(7, "45.0", "179.9"), "ok.ron").expect("179.9 is allowed");
}

#[test]
fn image_size_must_be_1_to_16384() {
    assert_invalid(&edit(8, "64", "0"), 8, "0", "camera.width", &["must be in 1..=16384", "got 0"]);
    assert_invalid(&edit(9, "48", "16385"), 9, "16385", "camera.height", &["1..=16384", "got 16385"]);
    parse_scene(&edit(9, "48", "16384"), "ok.ron").expect("16384 is allowed");
}

#[test]
fn look_at_must_differ_from_position() {
    let text = edit(5, "(0.0, 0.0, 0.0)", "(0.0, 1.0, -5.0)");
    assert_invalid(&text, 5, "(0.0, 1.0, -5.0)", "camera.look_at", &["must differ from `position`"]);
}

#[test]
fn up_must_be_non_zero() {
    let text = edit(6, "(0.0, 1.0, 0.0)", "(0.0, 0.0, 0.0)");
    assert_invalid(&text, 6, "(0.0, 0.0, 0.0)", "camera.up", &["must be non-zero"]);
}

#[test]
fn up_must_not_be_parallel_to_the_view_at_any_scale() {
    // The view direction is (0, -1, 5); a multiple of it is parallel, however long.
    let text = edit(6, "(0.0, 1.0, 0.0)", "(0.0, -1000.0, 5000.0)");
    assert_invalid(&text, 6, "(0.0, -1000.0", "camera.up", &["must not be parallel to the view direction"]);
}

#[test]
fn a_defaulted_up_is_reported_at_the_camera() {
    // Without `up`, the default (0, 1, 0) is parallel to a camera looking straight down.
    let text = edit(6, "up: (0.0, 1.0, 0.0),", "");
    let text = edit_text(&text, 4, "(0.0, 1.0, -5.0)", "(0.0, 5.0, 0.0)");
    assert_invalid(&text, 3, "(", "camera.up", &["must not be parallel"]);
}

// ---------------------------------------------------------------------------------------
// Settings
// ---------------------------------------------------------------------------------------

#[test]
fn max_depth_is_at_most_64() {
    assert_invalid(&edit(12, "5", "65"), 12, "65", "settings.max_depth", &["must be in 0..=64", "got 65"]);
}

#[test]
fn min_contribution_is_in_0_1() {
    assert_invalid(
        &edit(13, "0.001", "1.5"),
        13,
        "1.5",
        "settings.min_contribution",
        &["must be in [0, 1]", "got 1.5"],
    );
    assert_invalid(
        &edit(13, "0.001", "-0.1"),
        13,
        "-0.1",
        "settings.min_contribution",
        &["must be in [0, 1]"],
    );
}

#[test]
fn background_and_ambient_are_non_negative() {
    let text = edit(14, "(0.1, 0.1, 0.1)", "(0.1, -0.5, 0.1)");
    assert_invalid(&text, 14, "(0.1, -0.5", "settings.background", &[">= 0", "g = -0.5"]);
    let text = edit(15, "(0.1, 0.1, 0.1)", "(0.1, 0.1, -2.0)");
    assert_invalid(&text, 15, "(0.1, 0.1, -2.0)", "settings.ambient", &[">= 0", "b = -2"]);
}

// ---------------------------------------------------------------------------------------
// Materials
// ---------------------------------------------------------------------------------------

#[test]
fn material_names_are_non_empty_and_unique() {
    assert_invalid(&edit(20, "\"white\"", "\"\""), 20, "\"\"", "materials[1].name", &["must not be empty"]);
    let text = edit(20, "\"white\"", "\"red\"");
    assert_invalid(
        &text,
        20,
        "\"red\"",
        "materials[1].name",
        &["duplicate material name `red`", "materials[0]"],
    );
}

#[test]
fn kd_channels_are_in_0_1() {
    let text = edit(20, "(0.9, 0.9, 0.9)", "(0.9, 1.2, 0.9)");
    assert_invalid(&text, 20, "(0.9, 1.2", "materials[1].kd", &["must be in [0, 1]", "g = 1.2"]);
}

#[test]
fn ks_kr_kt_and_glossiness_are_in_0_1() {
    for (field, from, to) in [
        ("ks", "ks: 0.5", "ks: 1.2"),
        ("kr", "kr: 0.2", "kr: -0.1"),
        ("kt", "kt: 0.0", "kt: 1.5"),
        ("glossiness", "glossiness: 0.0", "glossiness: 2.0"),
    ] {
        let text = edit(19, from, to);
        let value = to.split(": ").nth(1).expect("value");
        let got = format!("got {}", value.trim_end_matches(".0"));
        let at = to.replace(": ", ": |");
        assert_invalid(&text, 19, &at, &format!("materials[0].{field}"), &["must be in [0, 1]", &got]);
    }
}

#[test]
fn kr_plus_kt_is_at_most_1_and_reported_at_kt() {
    let text = edit(19, "kt: 0.0", "kt: 0.9");
    assert_invalid(&text, 19, "0.9, ior", "materials[0].kt", &["`kr + kt` must be <= 1", "0.2 + 0.9"]);
    parse_scene(&edit(19, "kt: 0.0", "kt: 0.8"), "ok.ron").expect("0.2 + 0.8 is exactly 1");
}

#[test]
fn ior_is_positive_and_shininess_non_negative() {
    assert_invalid(
        &edit(19, "ior: 1.5", "ior: 0.0"),
        19,
        "0.0, glossiness",
        "materials[0].ior",
        &["must be > 0", "got 0"],
    );
    let text = edit(19, "shininess: 32.0", "shininess: -1.0");
    assert_invalid(&text, 19, "-1.0", "materials[0].shininess", &["must be >= 0", "got -1"]);
}

// ---------------------------------------------------------------------------------------
// Lights
// ---------------------------------------------------------------------------------------

#[test]
fn light_colour_and_intensity_are_non_negative() {
    let text = edit(23, "colour: (1.0, 1.0, 1.0)", "colour: (-1.0, 1.0, 1.0)");
    assert_invalid(&text, 23, "(-1.0", "lights[0].colour", &[">= 0 in every channel", "r = -1"]);
    let text = edit(24, "intensity: 0.5", "intensity: -0.5");
    assert_invalid(&text, 24, "-0.5", "lights[1].intensity", &["must be >= 0", "got -0.5"]);
}

#[test]
fn directional_light_direction_is_non_zero() {
    let text = edit(24, "(0.0, -1.0, 0.0)", "(0.0, 0.0, 0.0)");
    assert_invalid(&text, 24, "(0.0, 0.0, 0.0)", "lights[1].direction", &["must be non-zero"]);
}

// ---------------------------------------------------------------------------------------
// Objects and shapes
// ---------------------------------------------------------------------------------------

#[test]
fn object_material_must_be_defined_and_the_message_lists_the_defined_ones() {
    let text = edit(28, "material: \"white\"", "material: \"chalk\"");
    assert_invalid(
        &text,
        28,
        "\"chalk\"",
        "objects[1].material",
        &["material `chalk` is not defined; defined: `red`, `white`"],
    );
}

#[test]
fn explicit_object_names_are_unique() {
    let text = edit(28, "\"floor\"", "\"ball\"");
    assert_invalid(&text, 28, "\"ball\"", "objects[1].name", &["duplicate object name `ball`", "objects[0]"]);
}

#[test]
fn sphere_radius_is_positive() {
    for bad in ["0.0", "-2.0"] {
        let text = edit(27, "radius: 1.0", &format!("radius: {bad}"));
        assert_invalid(&text, 27, &format!("radius: |{bad}"), "objects[0].shape.radius", &["must be > 0"]);
    }
}

#[test]
fn coordinates_radii_and_scales_lie_within_1e18() {
    // Beyond ±1e18 a squared distance overflows f32; 1e18 itself is accepted (as a centre, or
    // as a radius, but not both: the sphere must also fit, see tests/combined_validation.rs).
    for (centre, radius) in [("1e18", "1.0"), ("0.0", "1e18")] {
        let to = format!("centre: (0.0, {centre}, 0.0), radius: {radius}");
        let ok = edit(27, "centre: (0.0, 1.0, 0.0), radius: 1.0", &to);
        parse_scene(&ok, "ok.ron").unwrap_or_else(|e| panic!("{e}"));
    }
    let cases = [
        (
            27,
            "centre: (0.0, 1.0, 0.0)",
            "centre: (0.0, -2e18, 0.0)",
            "(0.0, -2e18",
            "objects[0].shape.centre",
            "y = -2e18",
        ),
        (27, "radius: 1.0", "radius: 5e18", "5e18", "objects[0].shape.radius", "got 5e18"),
        (
            28,
            "point: (0.0, 0.0, 0.0)",
            "point: (3e20, 0.0, 0.0)",
            "(3e20",
            "objects[1].shape.point",
            "x = 3e20",
        ),
        (
            29,
            "(1.0, 0.0, 0.0), (0.0, 1.0",
            "(1.0, 0.0, 1e19), (0.0, 1.0",
            "(1.0, 0.0, 1e19)",
            "objects[2].shape.vertices[1]",
            "z = 1e19",
        ),
        (
            31,
            "scale: (1.0, 2.0, 1.0)",
            "scale: (1.0, 2e18, 1.0)",
            "(1.0, 2e18",
            "objects[4].transform.scale",
            "y = 2e18",
        ),
        (
            31,
            "translate: (0.0, 0.0, 0.0)",
            "translate: (0.0, 0.0, 1e30)",
            "(0.0, 0.0, 1e30)",
            "objects[4].transform.translate",
            "z = 1e30",
        ),
        (
            23,
            "position: (0.0, 5.0, -5.0)",
            "position: (0.0, 5e25, -5.0)",
            "(0.0, 5e25",
            "lights[0].position",
            "y = 5e25",
        ),
    ];
    for (line, from, to, at, field, got) in cases {
        let text = edit(line, from, to);
        assert_invalid(&text, line, at, field, &["must lie within ±1e18", got]);
    }
}

#[test]
fn plane_normal_is_non_zero() {
    let text = edit(28, "normal: (0.0, 1.0, 0.0)", "normal: (0.0, 0.0, 0.0)");
    assert_invalid(&text, 28, "(0.0, 0.0, 0.0)),", "objects[1].shape.normal", &["must be non-zero"]);
}

#[test]
fn triangles_must_not_be_degenerate_at_any_scale() {
    let collinear = "((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (2.0, 2.0, 2.0))";
    let text = edit(29, "((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))", collinear);
    assert_invalid(&text, 29, collinear, "objects[2].shape.vertices", &["non-zero area", "collinear"]);
    let sliver = "((0.0, 0.0, 0.0), (1000.0, 0.0, 0.0), (500.0, 0.0000001, 0.0))";
    let text = edit(29, "((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))", sliver);
    assert_invalid(&text, 29, sliver, "objects[2].shape.vertices", &["non-zero area"]);
    // Tiny and huge but well-shaped triangles are fine.
    for scale in ["0.00001", "100000.0"] {
        let tri = format!("((0.0, 0.0, 0.0), ({scale}, 0.0, 0.0), (0.0, {scale}, 0.0))");
        let text = edit(29, "((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))", &tri);
        parse_scene(&text, "ok.ron").unwrap_or_else(|e| panic!("{e}"));
    }
}

const SQUARE: &str = "[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]";

fn polygon(vertices: &str) -> String {
    edit(30, SQUARE, vertices)
}

#[test]
fn polygons_need_three_vertices() {
    let two = "[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)]";
    assert_invalid(&polygon(two), 30, two, "objects[3].shape.vertices", &["at least 3 vertices", "got 2"]);
}

#[test]
fn polygons_must_be_planar_at_any_scale() {
    let bent = "[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.1), (0.0, 1.0, 0.0)]";
    assert_invalid(
        &polygon(bent),
        30,
        "(0.0, 0.0, 0.0), (1.0, 0.0",
        "objects[3].shape.vertices[0]",
        &["plane of the polygon"],
    );
    // The same 1e-6 relative bend is fine on a big or a small polygon.
    for s in ["1000.0", "0.001"] {
        let v = |x: &str, y: &str, z: &str| format!("({x}, {y}, {z})");
        let z = format!("{}", s.parse::<f64>().expect("number") * 1e-6);
        let flat_enough = format!(
            "[{}, {}, {}, {}]",
            v("0.0", "0.0", "0.0"),
            v(s, "0.0", "0.0"),
            v(s, s, &z),
            v("0.0", s, "0.0")
        );
        parse_scene(&polygon(&flat_enough), "ok.ron").unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn polygons_must_be_convex() {
    let dart = "[(0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (1.0, 0.5, 0.0), (2.0, 2.0, 0.0), (0.0, 2.0, 0.0)]";
    assert_invalid(&polygon(dart), 30, "(1.0, 0.5, 0.0)", "objects[3].shape.vertices[2]", &["non-convex"]);
}

#[test]
fn polygons_must_not_wind_twice() {
    // A pentagram: every turn has the same sign, but the outline crosses itself.
    let c = |k: f64| {
        let a = std::f64::consts::TAU * k / 5.0;
        format!("({:.6}, {:.6}, 0.0)", a.cos(), a.sin())
    };
    let star = format!("[{}, {}, {}, {}, {}]", c(0.0), c(2.0), c(4.0), c(1.0), c(3.0));
    assert_invalid(&polygon(&star), 30, &star, "objects[3].shape.vertices", &["winds 2 times"]);
}

#[test]
fn polygons_must_not_be_degenerate() {
    let line = "[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.0, 0.0)]";
    assert_invalid(&polygon(line), 30, line, "objects[3].shape.vertices", &["non-zero area"]);
    let repeated = "[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]";
    let at = "(1.0, 0.0, 0.0), (0.0, 1.0";
    assert_invalid(
        &polygon(repeated),
        30,
        at,
        "objects[3].shape.vertices[2]",
        &["repeats the previous vertex"],
    );
    // A corner on a straight edge is allowed: the polygon is still convex.
    let on_edge = "[(0.0, 0.0, 0.0), (0.5, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]";
    parse_scene(&polygon(on_edge), "ok.ron").unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn box_max_exceeds_min_on_every_axis() {
    let text = edit(31, "max: (1.0, 1.0, 1.0)", "max: (1.0, 0.0, 1.0)");
    assert_invalid(
        &text,
        31,
        "(1.0, 0.0, 1.0)",
        "objects[4].shape.max",
        &["greater than `min` on every axis", "on y"],
    );
}

#[test]
fn transform_scale_is_non_zero() {
    let text = edit(31, "scale: (1.0, 2.0, 1.0)", "scale: (1.0, 0.0, 1.0)");
    assert_invalid(&text, 31, "(1.0, 0.0, 1.0)))", "objects[4].transform.scale", &["non-zero", "y = 0"]);
}

#[test]
fn spheres_need_a_uniform_scale() {
    let text = edit(27, "material: \"red\")", "material: \"red\", transform: (scale: (2.0, 2.0, 1.0)))");
    assert_invalid(
        &text,
        27,
        "(2.0, 2.0, 1.0)",
        "objects[0].transform.scale",
        &["must be uniform for a sphere"],
    );
    // A mirror image is still a sphere.
    let text = edit(27, "material: \"red\")", "material: \"red\", transform: (scale: (2.0, -2.0, 2.0)))");
    parse_scene(&text, "ok.ron").unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn the_first_violation_in_document_order_is_reported() {
    let text = edit(27, "radius: 1.0", "radius: -1.0");
    let text = edit_text(&text, 7, "45.0", "0.0");
    assert_invalid(&text, 7, "0.0", "camera.fov_deg", &["(0, 180)"]);
}

// ---------------------------------------------------------------------------------------
// Distribution effects: depth of field, anti-aliasing, adaptive sampling, glossy rays and
// area lights. `EFFECTS` gives every new field explicitly; `BASE` gives none of them.
// ---------------------------------------------------------------------------------------

/// A small valid scene that sets every distribution-effect field; tests change one line.
const EFFECTS: &str = r#"// Every distribution effect; each test changes one line.
Scene(
    camera: (
        position: (0.0, 1.0, -5.0),
        look_at: (0.0, 0.0, 0.0),
        fov_deg: 45.0,
        width: 64,
        height: 48,
        aperture: 0.1,
        focus_distance: 5.0,
        lens: (samples: 4, pattern: Grid),
    ),
    settings: (
        aa: (samples: 16, pattern: Random, filter: Tent),
        adaptive: (threshold: 0.1, max_depth: 2),
        glossy: (samples: 4, pattern: Jittered),
    ),
    materials: [(name: "m", kd: (0.5, 0.5, 0.5), kr: 0.5, glossiness: 0.2)],
    lights: [
        Rect(corner: (-1.0, 4.0, -1.0), edge_u: (2.0, 0.0, 0.0), edge_v: (0.0, 0.0, 2.0), colour: (1.0, 1.0, 1.0), intensity: 1.0, samples: 16, pattern: Jittered),
        Disk(centre: (0.0, 4.0, 0.0), normal: (0.0, -1.0, 0.0), radius: 0.5, colour: (1.0, 1.0, 1.0), intensity: 1.0, samples: 8, pattern: Grid),
    ],
    objects: [(shape: Sphere(centre: (0.0, 0.0, 0.0), radius: 1.0), material: "m")],
)
"#;

/// `EFFECTS` with `from` replaced by `to` on the 1-based `line`.
fn effects(line: usize, from: &str, to: &str) -> String {
    edit_text(EFFECTS, line, from, to)
}

#[test]
fn every_effect_field_is_read_as_written() {
    use penumbra::scene::{Filter, LightDesc, Pattern};
    let scene = parse_scene(EFFECTS, "effects.ron").unwrap_or_else(|e| panic!("{e}"));
    let camera = &scene.camera;
    assert_eq!((camera.aperture, camera.focus_distance, camera.focus_on), (0.1, Some(5.0), None));
    assert_eq!((camera.lens.samples, camera.lens.pattern), (4, Pattern::Grid));
    let settings = &scene.settings;
    assert_eq!(
        (settings.aa.samples, settings.aa.pattern, settings.aa.filter),
        (16, Pattern::Random, Filter::Tent)
    );
    let adaptive = settings.adaptive.expect("adaptive is on");
    assert_eq!((adaptive.threshold, adaptive.max_depth), (0.1, 2));
    assert_eq!((settings.glossy.samples, settings.glossy.pattern), (4, Pattern::Jittered));
    assert!(matches!(scene.lights[0], LightDesc::Rect { samples: 16, pattern: Pattern::Jittered, .. }));
    assert!(matches!(
        scene.lights[1],
        LightDesc::Disk { radius: 0.5, samples: 8, pattern: Pattern::Grid, .. }
    ));
    let text = effects(10, "focus_distance: 5.0", "focus_on: (0.0, 0.5, 0.0)");
    let scene = parse_scene(&text, "ok.ron").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        (scene.camera.focus_distance, scene.camera.focus_on),
        (None, Some(glam::DVec3::new(0.0, 0.5, 0.0)))
    );
}

#[test]
fn every_effect_field_has_its_default_when_absent() {
    use glam::Vec3;
    use penumbra::scene::{AdaptiveSettings, AntiAliasing, Filter, LightDesc, Pattern, Sampling};
    let scene = parse_scene(BASE, "base.ron").expect("valid");
    let camera = &scene.camera;
    assert_eq!((camera.aperture, camera.focus_distance, camera.focus_on), (0.0, None, None));
    assert_eq!(camera.lens, Sampling { samples: 1, pattern: Pattern::Jittered });
    let settings = &scene.settings;
    assert_eq!(settings.aa, AntiAliasing { samples: 1, pattern: Pattern::Jittered, filter: Filter::Box });
    assert_eq!(settings.adaptive, None);
    assert_eq!(settings.glossy, Sampling { samples: 8, pattern: Pattern::Jittered });
    // A partly written struct takes the missing fields from its own defaults.
    let text = effects(11, "(samples: 4, pattern: Grid)", "(pattern: Grid)");
    let text = edit_text(&text, 14, "(samples: 16, pattern: Random, filter: Tent)", "(samples: 4)");
    let text = edit_text(&text, 15, "(threshold: 0.1, max_depth: 2)", "()");
    let text = edit_text(&text, 16, "(samples: 4, pattern: Jittered)", "(pattern: Grid)");
    let text =
        edit_text(&text, 20, ", colour: (1.0, 1.0, 1.0), intensity: 1.0, samples: 16, pattern: Jittered", "");
    let text =
        edit_text(&text, 21, ", colour: (1.0, 1.0, 1.0), intensity: 1.0, samples: 8, pattern: Grid", "");
    let scene = parse_scene(&text, "partial.ron").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.camera.lens, Sampling { samples: 1, pattern: Pattern::Grid });
    assert_eq!(
        scene.settings.aa,
        AntiAliasing { samples: 4, pattern: Pattern::Jittered, filter: Filter::Box }
    );
    assert_eq!(scene.settings.adaptive, Some(AdaptiveSettings { threshold: 0.05, max_depth: 3 }));
    // `glossy` keeps its own default of 8 samples when only the pattern is given.
    assert_eq!(scene.settings.glossy, Sampling { samples: 8, pattern: Pattern::Grid });
    for light in &scene.lights {
        let (LightDesc::Rect { colour, intensity, samples, pattern, .. }
        | LightDesc::Disk { colour, intensity, samples, pattern, .. }) = light
        else {
            panic!("expected an area light, got {light:?}");
        };
        assert_eq!((*colour, *intensity, *samples, *pattern), (Vec3::ONE, 1.0, 16, Pattern::Jittered));
    }
    // `adaptive: None` spells out the default: off.
    let text = effects(15, "(threshold: 0.1, max_depth: 2)", "None");
    assert_eq!(parse_scene(&text, "off.ron").expect("valid").settings.adaptive, None);
}

#[test]
fn aperture_is_non_negative_and_finite() {
    assert_invalid(&effects(9, "0.1", "-0.1"), 9, "-0.1", "camera.aperture", &["must be >= 0", "got -0.1"]);
    assert_invalid(&effects(9, "0.1", "NaN"), 9, "NaN", "camera.aperture", &["must be a finite number"]);
    parse_scene(&effects(9, "0.1", "0.0"), "ok.ron").expect("a pinhole is allowed");
}

#[test]
fn focus_distance_is_positive() {
    for bad in ["0.0", "-2.0"] {
        let text = effects(10, "5.0", bad);
        let got = format!("got {}", bad.trim_end_matches(".0"));
        assert_invalid(&text, 10, bad, "camera.focus_distance", &["must be > 0", &got]);
    }
    let text = effects(10, "5.0", "inf");
    assert_invalid(&text, 10, "inf", "camera.focus_distance", &["must be a finite number"]);
}

#[test]
fn focus_distance_and_focus_on_are_exclusive_and_reported_at_focus_on() {
    let text = effects(10, "focus_distance: 5.0,", "focus_distance: 5.0, focus_on: (0.0, 0.0, 0.0),");
    assert_invalid(
        &text,
        10,
        "(0.0, 0.0, 0.0)",
        "camera.focus_on",
        &["must not be given together with `focus_distance`"],
    );
}

#[test]
fn focus_on_must_be_in_front_of_the_camera() {
    // The camera at (0, 1, -5) looks along (0, -1, 5): (0, 1, -6) is behind it and
    // (1, 1, -5) is beside it, at depth 0.
    for point in ["(0.0, 1.0, -6.0)", "(1.0, 1.0, -5.0)"] {
        let text = effects(10, "focus_distance: 5.0", &format!("focus_on: {point}"));
        assert_invalid(&text, 10, point, "camera.focus_on", &["must be in front of the camera", "at depth "]);
    }
    let text = effects(10, "focus_distance: 5.0", "focus_on: (0.0, NaN, 0.0)");
    assert_invalid(&text, 10, "(0.0, NaN", "camera.focus_on", &["must be a finite number", "y = NaN"]);
    // Anywhere in front is fine, however far to the side.
    parse_scene(&effects(10, "focus_distance: 5.0", "focus_on: (100.0, 1.0, -4.9)"), "ok.ron")
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn every_sample_count_is_1_to_4096() {
    let cases = [
        (11, "samples: 4, pattern: Grid", "camera.lens.samples"),
        (14, "samples: 16, pattern: Random", "settings.aa.samples"),
        (16, "samples: 4, pattern: Jittered", "settings.glossy.samples"),
        (20, "samples: 16, pattern: Jittered", "lights[0].samples"),
        (21, "samples: 8, pattern: Grid", "lights[1].samples"),
    ];
    for (line, from, field) in cases {
        for bad in ["0", "4097"] {
            let to = from.replacen(from.split(", ").next().expect("samples"), &format!("samples: {bad}"), 1);
            let text = effects(line, from, &to);
            let at = format!("samples: |{bad},");
            assert_invalid(&text, line, &at, field, &["must be in 1..=4096", &format!("got {bad}")]);
        }
        let to = from.replacen(from.split(", ").next().expect("samples"), "samples: 4096", 1);
        parse_scene(&effects(line, from, &to), "ok.ron").unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn adaptive_threshold_is_non_negative_and_depth_is_1_to_6() {
    let text = effects(15, "threshold: 0.1", "threshold: -0.1");
    assert_invalid(&text, 15, "-0.1", "settings.adaptive.threshold", &["must be >= 0", "got -0.1"]);
    let text = effects(15, "threshold: 0.1", "threshold: inf");
    assert_invalid(&text, 15, "inf", "settings.adaptive.threshold", &["must be a finite number"]);
    for bad in ["0", "7"] {
        let text = effects(15, "max_depth: 2", &format!("max_depth: {bad}"));
        let at = format!("max_depth: |{bad})");
        assert_invalid(
            &text,
            15,
            &at,
            "settings.adaptive.max_depth",
            &["must be in 1..=6", &format!("got {bad}")],
        );
    }
    parse_scene(&effects(15, "threshold: 0.1, max_depth: 2", "threshold: 0.0, max_depth: 6"), "ok.ron")
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn rect_light_edges_are_non_zero() {
    let text = effects(20, "edge_u: (2.0, 0.0, 0.0)", "edge_u: (0.0, 0.0, 0.0)");
    assert_invalid(&text, 20, "(0.0, 0.0, 0.0), edge_v", "lights[0].edge_u", &["must be non-zero"]);
    let text = effects(20, "edge_v: (0.0, 0.0, 2.0)", "edge_v: (0.0, 0.0, 0.0)");
    assert_invalid(&text, 20, "(0.0, 0.0, 0.0), colour", "lights[0].edge_v", &["must be non-zero"]);
    let text = effects(20, "corner: (-1.0, 4.0, -1.0)", "corner: (-1.0, 4.0, inf)");
    assert_invalid(
        &text,
        20,
        "(-1.0, 4.0, inf)",
        "lights[0].corner",
        &["must be a finite number", "z = inf"],
    );
}

#[test]
fn rect_light_edges_are_not_parallel_at_any_scale() {
    let text = effects(20, "edge_v: (0.0, 0.0, 2.0)", "edge_v: (-4.0, 0.0, 0.0)");
    assert_invalid(
        &text,
        20,
        "(-4.0, 0.0, 0.0)",
        "lights[0].edge_v",
        &["must not be parallel to `edge_u` = (2, 0, 0)", "got (-4, 0, 0)"],
    );
    // Nearly parallel long edges are a sliver, however long...
    let sliver = "edge_u: (1000.0, 0.0, 0.0), edge_v: (1000.0, 0.0001, 0.0)";
    let text = effects(20, "edge_u: (2.0, 0.0, 0.0), edge_v: (0.0, 0.0, 2.0)", sliver);
    assert_invalid(&text, 20, "(1000.0, 0.0001", "lights[0].edge_v", &["must not be parallel"]);
    // ...while tiny or huge square lights are fine.
    for s in ["0.0001", "10000.0"] {
        let square = format!("edge_u: ({s}, 0.0, 0.0), edge_v: (0.0, 0.0, {s})");
        let text = effects(20, "edge_u: (2.0, 0.0, 0.0), edge_v: (0.0, 0.0, 2.0)", &square);
        parse_scene(&text, "ok.ron").unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn area_light_colour_and_intensity_are_non_negative() {
    let text = effects(20, "colour: (1.0, 1.0, 1.0)", "colour: (1.0, -0.5, 1.0)");
    assert_invalid(&text, 20, "(1.0, -0.5", "lights[0].colour", &[">= 0 in every channel", "g = -0.5"]);
    let text = effects(21, "intensity: 1.0", "intensity: -1.0");
    assert_invalid(&text, 21, "intensity: |-1.0", "lights[1].intensity", &["must be >= 0", "got -1"]);
}

#[test]
fn disk_light_radius_is_positive_and_normal_non_zero() {
    for bad in ["0.0", "-0.5"] {
        let text = effects(21, "radius: 0.5", &format!("radius: {bad}"));
        let got = format!("got {}", bad.trim_end_matches(".0"));
        assert_invalid(&text, 21, &format!("radius: |{bad}"), "lights[1].radius", &["must be > 0", &got]);
    }
    let text = effects(21, "normal: (0.0, -1.0, 0.0)", "normal: (0.0, 0.0, 0.0)");
    assert_invalid(&text, 21, "(0.0, 0.0, 0.0)", "lights[1].normal", &["must be non-zero"]);
    // The normal comes before the radius in the schema, so it is reported first.
    let text = effects(21, "normal: (0.0, -1.0, 0.0), radius: 0.5", "normal: (0.0, 0.0, 0.0), radius: 0.0");
    assert_invalid(&text, 21, "(0.0, 0.0, 0.0)", "lights[1].normal", &["must be non-zero"]);
}

#[test]
fn effect_fields_follow_document_order() {
    // A bad lens (camera) is reported before a bad anti-aliasing count (settings).
    let text = effects(11, "samples: 4", "samples: 0");
    let text = edit_text(&text, 14, "samples: 16", "samples: 0");
    assert_invalid(&text, 11, "0, pattern", "camera.lens.samples", &["1..=4096"]);
}

#[test]
fn wrong_types_in_effect_fields_say_what_was_expected() {
    let text = effects(11, "pattern: Grid", "pattern: 3");
    assert_invalid(
        &text,
        11,
        "3)",
        "camera.lens.pattern",
        &["expected a pattern: `Grid`, `Random` or `Jittered`, found `3`"],
    );
    let text = effects(14, "filter: Tent", "filter: \"Tent\"");
    assert_invalid(&text, 14, "\"Tent\"", "settings.aa.filter", &["expected a filter: `Box` or `Tent`"]);
    let text = effects(14, "filter: Tent", "filter: Gauss");
    assert_invalid(
        &text,
        14,
        "Gauss",
        "settings.aa.filter",
        &["unknown variant `Gauss`; expected one of `Box`, `Tent`"],
    );
    let text = effects(21, "samples: 8", "samples: 2.5");
    assert_invalid(&text, 21, "2.5", "lights[1].samples", &["expected a whole number (32-bit, unsigned)"]);
    let text = effects(10, "focus_distance: 5.0", "focus_on: (0.0, 0.0)");
    assert_invalid(&text, 10, "(0.0, 0.0)", "camera.focus_on", &["expected a vector `(x, y, z)`"]);
    let text = effects(15, "(threshold: 0.1, max_depth: 2)", "0.1");
    assert_invalid(&text, 15, "0.1", "settings.adaptive", &["expected a struct in parentheses", "or `None`"]);
    let text = effects(11, "samples: 4", "sample: 4");
    assert_invalid(
        &text,
        11,
        "sample:",
        "camera.lens.sample",
        &["unknown field `sample`; expected one of `samples`, `pattern`"],
    );
    let text = effects(21, "Disk(", "Sphere(");
    assert_invalid(&text, 21, "Sphere", "lights[1]", &["unknown variant `Sphere`", "`Rect`, `Disk`"]);
}

#[test]
fn every_shipped_scene_loads() {
    let mut names = Vec::new();
    for path in crate::common::shipped_scenes() {
        load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        names.push(path.file_name().expect("file name").to_string_lossy().into_owned());
    }
    for expected in ["default.ron", "every_type.ron", "effects_aa.ron", "showcase.ron"] {
        assert!(names.iter().any(|name| name == expected), "scenes/ lacks {expected}");
    }
}

// ---------------------------------------------------------------------------------------
// Non-finite numbers and RON errors
// ---------------------------------------------------------------------------------------

#[test]
fn non_finite_numbers_are_rejected() {
    for bad in ["NaN", "inf", "-inf", "1e40"] {
        let text = edit(27, "radius: 1.0", &format!("radius: {bad}"));
        assert_invalid(&text, 27, bad, "objects[0].shape.radius", &["must be a finite number"]);
        // Positions are 64-bit: 1e40 is finite there, and beyond the coordinate limit.
        let rule = if bad == "1e40" { "must lie within ±1e18" } else { "must be a finite number" };
        let text = edit(4, "(0.0, 1.0, -5.0)", &format!("(0.0, {bad}, -5.0)"));
        assert_invalid(&text, 4, "(0.0", "camera.position", &[rule, "y = "]);
    }
}

#[test]
fn an_unknown_field_is_named_with_the_allowed_ones() {
    let text = edit(27, "radius: 1.0", "radius2: 1.0");
    assert_invalid(
        &text,
        27,
        "radius2",
        "objects[0].shape.radius2",
        &["unknown field `radius2`; expected one of `centre`, `radius`"],
    );
}

#[test]
fn a_missing_field_is_reported_at_its_struct() {
    let text = edit(27, ", radius: 1.0", "");
    assert_invalid(&text, 27, "Sphere(", "objects[0].shape.radius", &["missing required field `radius`"]);
    let text = edit(8, "width: 64,", "");
    assert_invalid(&text, 3, "(", "camera.width", &["missing required field `width`"]);
}

#[test]
fn an_unknown_variant_lists_the_shapes() {
    let text = edit(27, "Sphere(", "Ball(");
    assert_invalid(&text, 27, "Ball", "objects[0].shape", &["unknown variant `Ball`", "`Sphere`, `Plane`"]);
}

#[test]
fn wrong_types_say_what_was_expected() {
    let text = edit(27, "radius: 1.0", "radius: \"big\"");
    assert_invalid(&text, 27, "\"big\"", "objects[0].shape.radius", &["expected a number, found `\"big\"`"]);
    let text = edit(8, "64", "6.4");
    assert_invalid(&text, 8, "6.4", "camera.width", &["expected a whole number", "found `6.4`"]);
    let text = edit(8, "64", "-4");
    assert_invalid(
        &text,
        8,
        "-4",
        "camera.width",
        &["expected a whole number", "found `-4`", "out of range"],
    );
    let text = edit(4, "(0.0, 1.0, -5.0)", "(0.0, 1.0)");
    assert_invalid(
        &text,
        4,
        "(0.0, 1.0)",
        "camera.position",
        &["expected a vector `(x, y, z)`", "found `(0.0, 1.0)`"],
    );
    let text = edit(20, "\"white\"", "white");
    assert_invalid(
        &text,
        20,
        "white",
        "materials[1].name",
        &["expected a string in double quotes", "found `white`"],
    );
    let text = edit(5, "(0.0, 0.0, 0.0)", "(0.0, 0.0, zero)");
    assert_invalid(&text, 5, "zero", "camera.look_at[2]", &["expected a number, found `zero`"]);
}

#[test]
fn syntax_errors_keep_rons_position_and_message() {
    let text = edit(7, "45.0,", "45.0 4");
    assert_invalid(&text, 7, "45.0 |4", "camera", &["Expected comma"]);
    let text = edit(27, "material: \"red\")", "material: \"red\";");
    assert_invalid(&text, 27, ";", "objects[0]", &["Expected comma"]);
    let text = edit(2, "Scene(", "Scenery(");
    assert_invalid(&text, 2, "Scenery", "Scene", &["expected `Scene(`, found `Scenery(`"]);
}

// ---------------------------------------------------------------------------------------
// Robustness: no input makes the loader panic.
// ---------------------------------------------------------------------------------------

/// A small deterministic generator (SplitMix64).
struct SplitMix(u64);

impl SplitMix {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) % n as u64) as usize
    }
}

#[test]
fn every_prefix_of_the_default_scene_loads_or_fails_cleanly() {
    let text = penumbra::scene::load::DEFAULT_SCENE_SOURCE;
    for (end, _) in text.char_indices() {
        if let Err(SceneError::Invalid { line, col, .. }) = parse_scene(&text[..end], "cut.ron") {
            assert!(line >= 1 && col >= 1);
        }
    }
}

#[test]
fn random_deletions_and_insertions_load_or_fail_cleanly() {
    let mut rng = SplitMix(7);
    let junk = ['(', ')', '[', ']', ',', ':', '"', '/', '*', '#', 'r', '-', '.', 'é', '\n', '\'', '\\'];
    for text in [penumbra::scene::load::DEFAULT_SCENE_SOURCE, BASE] {
        for _ in 0..300 {
            let mut chars: Vec<char> = text.chars().collect();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(chars.len());
                match rng.below(2) {
                    0 => {
                        chars.remove(at);
                    }
                    _ => chars.insert(at, junk[rng.below(junk.len())]),
                }
            }
            let mutated: String = chars.into_iter().collect();
            let _ = parse_scene(&mutated, "fuzz.ron");
        }
    }
    for nasty in ["", " ", "Scene", "(", "[[[[", "/*", "r#\"", "\u{feff}Scene()", "Scene(camera: (((((((((("]
    {
        assert!(parse_scene(nasty, "nasty.ron").is_err());
    }
}

/// `EFFECTS` with a tone-mapping line added to its settings (line 17).
fn tonemapped(tonemap: &str) -> String {
    EFFECTS.replacen(
        "        glossy: (samples: 4, pattern: Jittered),\n",
        &format!("        glossy: (samples: 4, pattern: Jittered),\n        tonemap: {tonemap},\n"),
        1,
    )
}

#[test]
fn tonemap_parses_with_defaults_and_every_operator() {
    let scene = parse_scene(EFFECTS, "bad.ron").unwrap();
    assert_eq!(scene.settings.tonemap, penumbra::scene::ToneMapping::default());
    for (text, op) in
        [("Clamp", ToneOperator::Clamp), ("Reinhard", ToneOperator::Reinhard), ("Aces", ToneOperator::Aces)]
    {
        let scene =
            parse_scene(&tonemapped(&format!("(operator: {text}, exposure: 1.5, white: 8)")), "bad.ron")
                .unwrap();
        assert_eq!(scene.settings.tonemap.operator, op);
        assert_eq!((scene.settings.tonemap.exposure, scene.settings.tonemap.white), (1.5, 8.0));
    }
}

#[test]
fn tonemap_exposure_is_bounded_and_white_is_positive() {
    let text = tonemapped("(operator: Reinhard, exposure: 31)");
    assert_invalid(&text, 17, "31", "settings.tonemap.exposure", &["must be in [-30, 30] stops", "got 31"]);
    let text = tonemapped("(operator: Reinhard, white: 0)");
    assert_invalid(&text, 17, "0)", "settings.tonemap.white", &["must be > 0", "got 0"]);
    let text = tonemapped("(exposure: inf)");
    assert_invalid(&text, 17, "inf", "settings.tonemap.exposure", &["finite"]);
    let text = tonemapped("(operator: Filmic)");
    let err = parse_scene(&text, "bad.ron").unwrap_err().to_string();
    assert!(err.contains("bad.ron:17:") && err.contains("tonemap.operator"), "{err}");
}
