//! Scene loading errors: every validation rule and every kind of RON error must name the
//! right line, column and field, and say what is wrong. Each case changes one line of a
//! small valid scene; expected columns are found by searching the changed line.

use penumbra::scene::{load_scene, parse_scene, SceneError};

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
    for kind in ["sphere", "plane", "triangle", "polygon", "box"] {
        assert!(kinds.contains(&kind), "every_type.ron lacks a {kind}");
    }
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
// Non-finite numbers and RON errors
// ---------------------------------------------------------------------------------------

#[test]
fn non_finite_numbers_are_rejected() {
    for bad in ["NaN", "inf", "-inf", "1e40"] {
        let text = edit(27, "radius: 1.0", &format!("radius: {bad}"));
        assert_invalid(&text, 27, bad, "objects[0].shape.radius", &["must be a finite number"]);
        let text = edit(4, "(0.0, 1.0, -5.0)", &format!("(0.0, {bad}, -5.0)"));
        assert_invalid(&text, 4, "(0.0", "camera.position", &["must be a finite number", "y = "]);
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
