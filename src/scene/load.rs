//! Loading scenes: RON text → [`SceneDesc`], validated, with every problem reported as a
//! [`SceneError`] that names the file, line, column and field.
//!
//! ron's own errors carry a position; they are mapped to the field that encloses it (via
//! [`path_at`]) and reworded where ron's message names internal types (a wrong type
//! becomes `expected a number, found `"big"``). Validation violations carry a field path and
//! are located with [`position_of`]. RON's `implicit_some` extension is always on, so
//! an optional field such as an object's `name` is written plainly: `name: "ball"`.

use std::path::Path;

use ron::error::{Error as RonError, SpannedError};
use ron::extensions::Extensions;

use super::desc::{SceneAssets, SceneDesc};
use super::error::SceneError;
use super::format::SceneFile;
use super::locate::{path_at, position_of, value_source, FieldPath, Segment};
use super::mesh::load_meshes;
use super::validate::validate;

/// The text of the built-in default scene, `scenes/default.ron`.
pub const DEFAULT_SCENE_SOURCE: &str = include_str!("../../scenes/default.ron");

/// The origin that errors in the built-in default scene report instead of a file name.
pub const DEFAULT_SCENE_ORIGIN: &str = "<built-in default scene>";

/// Parses and validates a scene; `origin` names the text's source in errors.
///
/// # Examples
/// ```
/// use penumbra::scene::parse_scene;
/// let text = "Scene(camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 45,
///                            width: 64, height: 48),
///                    materials: [(name: \"red\", kd: (1, 0, 0))],
///                    objects: [(shape: Sphere(centre: (0, 0, 0), radius: -1), material: \"red\")])";
/// let error = parse_scene(text, "ball.ron").unwrap_err();
/// assert_eq!(error.to_string(), "ball.ron:4:72: field `objects[0].shape.radius`: must be > 0, got -1");
/// ```
pub fn parse_scene(text: &str, origin: &str) -> Result<SceneDesc, SceneError> {
    parse_scene_at(text, origin, Path::new("."))
}

/// [`parse_scene`], with the meshes it names read relative to `base`.
pub fn parse_scene_at(text: &str, origin: &str, base: &Path) -> Result<SceneDesc, SceneError> {
    let scene = ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME)
        .from_str::<SceneFile>(text)
        .map_err(|error| from_ron(text, origin, &error))?;
    finish_scene(scene, origin, base, text)
}

/// Checks a deserialized scene by every rule of the format and loads what it names (meshes
/// relative to `base`, textures), the one path both scene files and [`super::SceneBuilder`]
/// take; `text` is the source positions are looked up in (empty where there is none).
pub(crate) fn finish_scene(
    file: SceneFile,
    origin: &str,
    base: &Path,
    text: &str,
) -> Result<SceneDesc, SceneError> {
    validate(&file).map_err(|violation| {
        let (line, col) = position_of(text, &violation.path).unwrap_or((1, 1));
        invalid(origin, (line, col), &violation.path, violation.rule)
    })?;
    let meshes = load_meshes(&file, base, text, origin)?;
    let mut scene = SceneDesc { file, assets: SceneAssets { meshes, ..SceneAssets::default() } };
    super::texture::load_textures(&mut scene, base, text, origin)?;
    super::limits::check_located(&scene, text, origin)?;
    Ok(scene)
}

/// Reads, parses and validates the scene file at `path`; errors name it as given.
///
/// # Examples
/// ```
/// use penumbra::scene::{load_scene, SceneError};
/// let error = load_scene("no/such/scene.ron".as_ref()).unwrap_err();
/// assert!(matches!(error, SceneError::Io { .. }));
/// ```
pub fn load_scene(path: &Path) -> Result<SceneDesc, SceneError> {
    let text = std::fs::read_to_string(path)
        .map_err(|source| SceneError::Io { path: path.to_path_buf(), source })?;
    let base = path.parent().unwrap_or_else(|| Path::new("."));
    parse_scene_at(&text, &path.display().to_string(), base)
}

/// The built-in default scene (`scenes/default.ron`, compiled in).
///
/// # Examples
/// ```
/// let scene = penumbra::scene::default_scene();
/// assert!(!scene.objects.is_empty());
/// ```
pub fn default_scene() -> SceneDesc {
    // Cannot fail: the built-in text is fixed at compile time and the tests load it.
    parse_scene(DEFAULT_SCENE_SOURCE, DEFAULT_SCENE_ORIGIN).expect("the built-in default scene is valid")
}

fn invalid(origin: &str, (line, col): (usize, usize), field: &FieldPath, rule: String) -> SceneError {
    let field = if field.is_empty() { "Scene".to_owned() } else { field.to_string() };
    SceneError::Invalid { path: origin.to_owned(), line, col, field, rule }
}

/// Maps one of ron's errors to the field it is in and a rule that reads well to a user.
fn from_ron(text: &str, origin: &str, error: &SpannedError) -> SceneError {
    let start = (error.span.start.line, error.span.start.col);
    let at = path_at(text, start.0, start.1);
    match &error.code {
        RonError::NoSuchStructField { expected, found, .. } => {
            let rule = format!("unknown field `{found}`; expected one of {}", quoted(expected));
            invalid(origin, start, &ending_in(at, found), rule)
        }
        RonError::DuplicateStructField { field, .. } => {
            let rule = format!("duplicate field: `{field}` may be given only once");
            invalid(origin, start, &ending_in(at, field), rule)
        }
        RonError::MissingStructField { field, .. } => {
            // ron reports the closing bracket of the incomplete struct; point at its start.
            let path = at.field(field);
            let position = position_of(text, &path).unwrap_or(start);
            invalid(origin, position, &path, format!("missing required field `{field}`"))
        }
        RonError::NoSuchEnumVariant { expected, found, .. } => {
            let rule = format!("unknown variant `{found}`; expected one of {}", quoted(expected));
            invalid(origin, start, &at, rule)
        }
        RonError::ExpectedDifferentStructName { expected, found } => {
            let rule = match *expected {
                "Scene" => format!("expected `Scene(`, found `{found}(`"),
                _ => format!("unexpected name `{found}` before `(`; write just `(`"),
            };
            invalid(origin, start, &at, rule)
        }
        RonError::ExpectedFloat
        | RonError::ExpectedInteger
        | RonError::ExpectedString
        | RonError::ExpectedBoolean
        | RonError::ExpectedArray
        | RonError::ExpectedStructLike
        | RonError::ExpectedNamedStructLike(_)
        | RonError::IntegerOutOfBounds
        | RonError::InvalidValueForType { .. }
        | RonError::ExpectedDifferentLength { .. } => wrong_type(text, origin, start, &at, &error.code),
        // A non-name where a unit variant (`pattern: Grid`) is expected.
        RonError::ExpectedIdentifier | RonError::SuggestRawIdentifier(_) if names_a_variant(&at) => {
            wrong_type(text, origin, start, &at, &error.code)
        }
        RonError::ExpectedComma if inside_value(text, &at, start) => {
            wrong_type(text, origin, start, &at, &error.code)
        }
        code => invalid(origin, start, &at, code.to_string()),
    }
}

/// A value of the wrong type or out of its type's range, reported at the value's start.
fn wrong_type(
    text: &str,
    origin: &str,
    start: (usize, usize),
    at: &FieldPath,
    code: &RonError,
) -> SceneError {
    let position = position_of(text, at).unwrap_or(start);
    let expected = expected_type(at).map_or_else(|| code.to_string(), str::to_owned);
    let mut rule = match value_source(text, at) {
        Some(found) => format!("expected {expected}, found `{}`", excerpt(found)),
        None => format!("expected {expected}"),
    };
    if *code == RonError::IntegerOutOfBounds {
        rule.push_str(" (out of range)");
    }
    invalid(origin, position, at, rule)
}

/// The first line of a value, cut to 40 characters, with `...` if anything was left out.
fn excerpt(source: &str) -> String {
    let first_line = source.lines().next().unwrap_or_default();
    let mut shown: String = first_line.chars().take(40).collect();
    if shown.len() < source.len() {
        shown.push_str("...");
    }
    shown
}

/// Whether `position` lies after the start of the single-line value at `path`: ron stopped
/// part-way through it, as it does on `6.4` where an integer is expected.
fn inside_value(text: &str, path: &FieldPath, (line, col): (usize, usize)) -> bool {
    let (Some((value_line, value_col)), Some(source)) = (position_of(text, path), value_source(text, path))
    else {
        return false;
    };
    !source.contains('\n')
        && value_line == line
        && value_col < col
        && col < value_col + source.chars().count()
}

/// Whether the field at `path` holds a unit variant written as a bare name.
fn names_a_variant(path: &FieldPath) -> bool {
    matches!(path.last(), Some(Segment::Field(name)) if name == "pattern" || name == "filter" || name == "operator")
}

/// `path`, ending in the field `name` (ron's span of an unknown or duplicate field name).
fn ending_in(path: FieldPath, name: &str) -> FieldPath {
    match path.last() {
        Some(Segment::Field(last)) if last == name => path,
        _ => path.field(name),
    }
}

fn quoted(names: &[&str]) -> String {
    names.iter().map(|name| format!("`{name}`")).collect::<Vec<_>>().join(", ")
}

/// What the schema expects at `path`, in words, for wrong-type messages.
fn expected_type(path: &FieldPath) -> Option<&'static str> {
    const VECTOR: &str = "a vector `(x, y, z)` of three numbers";
    let segments = path.segments();
    let parent = segments.len().checked_sub(2).and_then(|i| segments.get(i));
    let expected = match (parent, path.last()?) {
        (Some(Segment::Index(_)), Segment::Index(_)) => "a number",
        (Some(Segment::Field(list)), Segment::Index(_)) => match list.as_str() {
            "materials" | "objects" => "a struct in parentheses `(name: value, ...)`",
            "lights" => "a light: `Point(...)`, `Directional(...)`, `Rect(...)` or `Disk(...)`",
            "vertices" => VECTOR,
            _ => "a number",
        },
        (_, Segment::Field(name)) => match name.as_str() {
            "camera" | "settings" | "transform" | "lens" | "time" | "aa" | "glossy" | "tonemap" => {
                "a struct in parentheses `(name: value, ...)`"
            }
            "adaptive" | "noise" => "a struct in parentheses `(name: value, ...)`, or `None`",
            "shutter" => "a pair of numbers `(open, close)`, or `None`",
            "pattern" => "a pattern: `Grid`, `Random` or `Jittered`",
            "filter" => "a filter: `Box` or `Tent`",
            "operator" => "a tone operator: `Clamp`, `Reinhard` or `Aces`",
            "materials" | "lights" | "objects" => "a list in brackets `[...]`",
            "shape" => "a shape: `Sphere(...)`, `Plane(...)`, `Triangle(...)`, `Polygon(...)` or `Box(...)`",
            "width" | "height" | "max_depth" | "samples" | "max_secondary_rays" | "min_samples"
            | "max_samples" => "a whole number (32-bit, unsigned)",
            "seed" => "a whole number (64-bit, unsigned)",
            "name" | "material" => "a string in double quotes",
            "vertices" => {
                "a list of vectors: `((x, y, z), ...)` for a triangle, `[(x, y, z), ...]` for a polygon"
            }
            "position" | "look_at" | "up" | "background" | "ambient" | "kd" | "colour" | "direction"
            | "centre" | "point" | "normal" | "min" | "max" | "translate" | "rotate_deg" | "scale"
            | "focus_on" | "corner" | "edge_u" | "edge_v" => VECTOR,
            _ => "a number",
        },
        (_, Segment::Index(_)) => return None,
    };
    Some(expected)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_scene_is_valid() {
        let scene = default_scene();
        assert_eq!(scene, parse_scene(DEFAULT_SCENE_SOURCE, "default.ron").unwrap());
        assert!(scene.objects.len() >= 5);
    }

    #[test]
    fn expected_types_follow_the_schema() {
        let expect = |path: &str| FieldPath::parse(path).and_then(|p| expected_type(&p));
        assert_eq!(expect("camera.width"), Some("a whole number (32-bit, unsigned)"));
        assert_eq!(expect("objects[1].shape.vertices[2]"), Some("a vector `(x, y, z)` of three numbers"));
        assert_eq!(expect("objects[1].shape.vertices[2][0]"), Some("a number"));
        assert_eq!(expect("materials[0].kd[1]"), Some("a number"));
        assert_eq!(expect("materials[0].ks"), Some("a number"));
        assert_eq!(expect("camera.aperture"), Some("a number"));
        assert_eq!(expect("camera.focus_on"), Some("a vector `(x, y, z)` of three numbers"));
        assert_eq!(expect("camera.lens.samples"), Some("a whole number (32-bit, unsigned)"));
        assert_eq!(expect("settings.adaptive.max_depth"), Some("a whole number (32-bit, unsigned)"));
        assert_eq!(expect("settings.aa.filter"), Some("a filter: `Box` or `Tent`"));
        assert_eq!(expect("lights[2].edge_v"), Some("a vector `(x, y, z)` of three numbers"));
        assert_eq!(expect("lights[3].pattern"), Some("a pattern: `Grid`, `Random` or `Jittered`"));
        assert_eq!(expect(""), None);
    }

    #[test]
    fn excerpts_mark_what_they_leave_out() {
        assert_eq!(excerpt("6.4"), "6.4");
        assert_eq!(excerpt("(\n  1, 2)"), "(...");
        assert_eq!(excerpt(&"é".repeat(50)), format!("{}...", "é".repeat(40)));
    }

    #[test]
    fn errors_outside_any_field_name_the_scene() {
        let error = parse_scene("Scene(", "x.ron").unwrap_err();
        assert!(error.to_string().starts_with("x.ron:1:6: field `Scene`: Unexpected end"), "{error}");
    }
}
