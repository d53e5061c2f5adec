//! Vectors and scalar animation helpers for scripts: the `vec3` type, its operators and
//! geometry functions, and `lerp`, `clamp`, `smoothstep`, easing curves and angle conversion.
//!
//! The Rhai surface:
//! ```text
//! vec3(x, y, z)   vec3(s)          v.x  v.y  v.z  (get and set)
//! a + b   a - b   -a   a * b   a / b   (componentwise)   v * s   s * v   v / s
//! a == b  a != b  to_string(v)  to_debug(v)   ->  "vec3(1, 0.5, -2)"
//! dot(a, b)  cross(a, b)  length(v)  normalize(v)  distance(a, b)  min(a, b)  max(a, b)
//! lerp(a, b, t)  (numbers or vec3s)   clamp(x, lo, hi)   smoothstep(e0, e1, x)
//! ease_in(t)  ease_out(t)  ease_in_out(t)  ease(name, t)   radians(deg)  degrees(rad)
//! ```
//! Every numeric parameter takes an integer or a float. Results are always finite: an input
//! that would make a vector or number infinite or NaN is a runtime error instead.

use glam::DVec3;
use rhai::{Dynamic, Engine, INT};

use super::convert::{error, finite, type_name, ScriptResult};

/// The names `ease(name, t)` accepts, in the order error messages list them.
pub const EASE_NAMES: [&str; 6] = ["linear", "in", "out", "in_out", "smooth", "sine"];

/// Registers `vec3`, its operators and functions, and the scalar helpers into `engine`.
///
/// # Examples
/// ```
/// # use penumbra::script::api::math;
/// let mut engine = rhai::Engine::new();
/// math::register(&mut engine);
/// let d: f64 = engine.eval("dot(vec3(1, 2, 3), vec3(4, -5, 6))").unwrap();
/// assert_eq!(d, 12.0);
/// ```
pub fn register(engine: &mut Engine) {
    register_vec3(engine);
    register_scalars(engine);
}

/// `v` written as a script literal: `vec3(1, 0.5, -2)`.
fn format_vec3(v: DVec3) -> String {
    format!("vec3({}, {}, {})", v.x, v.y, v.z)
}

/// `v` if all its components are finite, else an error naming the operation `op`.
fn checked(v: DVec3, op: &str) -> ScriptResult<DVec3> {
    match v.is_finite() {
        true => Ok(v),
        false => error(format!("{op} gives a non-finite vector {}", format_vec3(v))),
    }
}

/// `x` if it is finite, else an error naming the operation `op`.
fn checked_float(x: f64, op: &str) -> ScriptResult<f64> {
    match x.is_finite() {
        true => Ok(x),
        false => error(format!("{op} gives a non-finite number {x}")),
    }
}

fn register_vec3(engine: &mut Engine) {
    // Type, constructors and components.
    engine
        .register_type_with_name::<DVec3>("vec3")
        .register_fn("vec3", |x: Dynamic, y: Dynamic, z: Dynamic| -> ScriptResult<DVec3> {
            Ok(DVec3::new(finite(&x, "vec3 x")?, finite(&y, "vec3 y")?, finite(&z, "vec3 z")?))
        })
        .register_fn("vec3", |s: Dynamic| finite(&s, "vec3 value").map(DVec3::splat))
        .register_get("x", |v: &mut DVec3| v.x)
        .register_get("y", |v: &mut DVec3| v.y)
        .register_get("z", |v: &mut DVec3| v.z)
        .register_set("x", |v: &mut DVec3, x: Dynamic| -> ScriptResult<()> {
            v.x = finite(&x, "vec3 x")?;
            Ok(())
        })
        .register_set("y", |v: &mut DVec3, y: Dynamic| -> ScriptResult<()> {
            v.y = finite(&y, "vec3 y")?;
            Ok(())
        })
        .register_set("z", |v: &mut DVec3, z: Dynamic| -> ScriptResult<()> {
            v.z = finite(&z, "vec3 z")?;
            Ok(())
        })
        .register_fn("to_string", |v: &mut DVec3| format_vec3(*v))
        .register_fn("to_debug", |v: &mut DVec3| format_vec3(*v));

    // Operators. Numbers on either side take `Dynamic` so integers and floats both work.
    engine
        .register_fn("+", |a: DVec3, b: DVec3| checked(a + b, "vec3 +"))
        .register_fn("-", |a: DVec3, b: DVec3| checked(a - b, "vec3 -"))
        .register_fn("-", |a: DVec3| -a)
        .register_fn("*", |a: DVec3, b: DVec3| checked(a * b, "vec3 *"))
        .register_fn("*", |a: DVec3, s: Dynamic| {
            checked(a * finite(&s, "the factor in vec3 * number")?, "vec3 *")
        })
        .register_fn("*", |s: Dynamic, a: DVec3| {
            checked(finite(&s, "the factor in number * vec3")? * a, "vec3 *")
        })
        .register_fn("/", |a: DVec3, b: DVec3| {
            if b.cmpeq(DVec3::ZERO).any() {
                return error(format!(
                    "vec3 / vec3: division by zero, the divisor {} has a zero component",
                    format_vec3(b)
                ));
            }
            checked(a / b, "vec3 /")
        })
        .register_fn("/", |a: DVec3, s: Dynamic| {
            let s = finite(&s, "the divisor in vec3 / number")?;
            if s == 0.0 {
                return error("vec3 / number: division by zero");
            }
            checked(a / s, "vec3 /")
        })
        .register_fn("==", |a: DVec3, b: DVec3| a == b)
        .register_fn("!=", |a: DVec3, b: DVec3| a != b);

    // Geometry.
    engine
        .register_fn("dot", |a: DVec3, b: DVec3| checked_float(a.dot(b), "dot"))
        .register_fn("cross", |a: DVec3, b: DVec3| checked(a.cross(b), "cross"))
        .register_fn("length", |v: DVec3| checked_float(v.length(), "length"))
        .register_fn("distance", |a: DVec3, b: DVec3| checked_float(a.distance(b), "distance"))
        .register_fn("normalize", |v: DVec3| {
            let length = v.length();
            if length == 0.0 || !length.is_finite() {
                return error("normalize: the zero vector has no direction");
            }
            checked(v / length, "normalize")
        })
        .register_fn("min", |a: DVec3, b: DVec3| a.min(b))
        .register_fn("max", |a: DVec3, b: DVec3| a.max(b))
        .register_fn("lerp", |a: DVec3, b: DVec3, t: Dynamic| {
            checked(a.lerp(b, finite(&t, "lerp t")?), "lerp")
        });
}

fn register_scalars(engine: &mut Engine) {
    engine
        .register_fn("lerp", |a: Dynamic, b: Dynamic, t: Dynamic| {
            if a.is::<DVec3>() || b.is::<DVec3>() {
                return error(format!(
                    "lerp needs two numbers or two vec3s, got {} and {}",
                    type_name(&a),
                    type_name(&b)
                ));
            }
            let (a, b) = (finite(&a, "lerp a")?, finite(&b, "lerp b")?);
            let t = finite(&t, "lerp t")?;
            checked_float(lerp(a, b, t), "lerp")
        })
        .register_fn("clamp", clamp)
        .register_fn("smoothstep", |e0: Dynamic, e1: Dynamic, x: Dynamic| {
            let e0 = finite(&e0, "smoothstep e0")?;
            let e1 = finite(&e1, "smoothstep e1")?;
            let x = finite(&x, "smoothstep x")?;
            checked_float(smoothstep(e0, e1, x), "smoothstep")
        })
        .register_fn("ease_in", |t: Dynamic| finite(&t, "ease_in t").map(ease_in))
        .register_fn("ease_out", |t: Dynamic| finite(&t, "ease_out t").map(ease_out))
        .register_fn("ease_in_out", |t: Dynamic| finite(&t, "ease_in_out t").map(ease_in_out))
        .register_fn("ease", |name: Dynamic, t: Dynamic| {
            let Some(name) = name.read_lock::<rhai::ImmutableString>() else {
                return error(format!(
                    "ease name must be a string, one of {}; got {}",
                    EASE_NAMES.join(", "),
                    type_name(&name)
                ));
            };
            let t = finite(&t, "ease t")?;
            match ease(&name, t) {
                Some(value) => Ok(value),
                None => error(format!(
                    "ease: unknown easing \"{}\"; expected one of {}",
                    name.as_str(),
                    EASE_NAMES.join(", ")
                )),
            }
        })
        .register_fn("radians", |deg: Dynamic| {
            checked_float(finite(&deg, "radians deg")?.to_radians(), "radians")
        })
        .register_fn("degrees", |rad: Dynamic| {
            checked_float(finite(&rad, "degrees rad")?.to_degrees(), "degrees")
        });
}

/// `clamp(x, lo, hi)`: an integer when all three are integers, else a float.
fn clamp(x: Dynamic, lo: Dynamic, hi: Dynamic) -> ScriptResult<Dynamic> {
    if let (Ok(x), Ok(lo), Ok(hi)) = (x.as_int(), lo.as_int(), hi.as_int()) {
        if lo > hi {
            return error(format!("clamp: lo ({lo}) must not be greater than hi ({hi})"));
        }
        return Ok(Dynamic::from_int(INT::clamp(x, lo, hi)));
    }
    let x = finite(&x, "clamp x")?;
    let (lo, hi) = (finite(&lo, "clamp lo")?, finite(&hi, "clamp hi")?);
    if lo > hi {
        return error(format!("clamp: lo ({lo}) must not be greater than hi ({hi})"));
    }
    // Cannot panic: lo and hi are finite and lo <= hi.
    Ok(Dynamic::from_float(x.clamp(lo, hi)))
}

/// `a` at `t = 0` and `b` at `t = 1` exactly, extrapolating outside [0, 1].
pub fn lerp(a: f64, b: f64, t: f64) -> f64 {
    (1.0 - t) * a + t * b
}

/// Hermite `3t² − 2t³` of `t = (x − e0) / (e1 − e0)` clamped to [0, 1]; a step at e0 if e0 == e1.
pub fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    if e0 == e1 {
        return if x < e0 { 0.0 } else { 1.0 };
    }
    let t = unit((x - e0) / (e1 - e0));
    t * t * (3.0 - 2.0 * t)
}

/// `t` clamped to [0, 1], with NaN taken as 0.
fn unit(t: f64) -> f64 {
    if t.is_nan() {
        0.0
    } else {
        t.clamp(0.0, 1.0)
    }
}

/// Cubic ease-in `t³`, with `t` clamped to [0, 1].
pub fn ease_in(t: f64) -> f64 {
    let t = unit(t);
    t * t * t
}

/// Cubic ease-out `1 − (1 − t)³`, with `t` clamped to [0, 1].
pub fn ease_out(t: f64) -> f64 {
    let s = 1.0 - unit(t);
    1.0 - s * s * s
}

/// Cubic ease-in-out: `4t³` up to the midpoint, then the mirror image; `t` clamped to [0, 1].
pub fn ease_in_out(t: f64) -> f64 {
    let t = unit(t);
    if t < 0.5 {
        4.0 * t * t * t
    } else {
        let s = 2.0 - 2.0 * t;
        1.0 - s * s * s / 2.0
    }
}

/// The easing curve called `name` (one of [`EASE_NAMES`]) at `t` clamped to [0, 1].
pub fn ease(name: &str, t: f64) -> Option<f64> {
    let t = unit(t);
    match name {
        "linear" => Some(t),
        "in" => Some(ease_in(t)),
        "out" => Some(ease_out(t)),
        "in_out" => Some(ease_in_out(t)),
        "smooth" => Some(smoothstep(0.0, 1.0, t)),
        // `libm`, not the system's `cos`: the same bits on every CPU (`script::engine`).
        "sine" => Some((1.0 - libm::cos(std::f64::consts::PI * t)) / 2.0),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::script::api::testing::{eval, eval_err};
    use rhai::FLOAT;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn vector_arithmetic_is_componentwise() {
        let a = "let a = vec3(1, 2, 3); let b = vec3(4, -5, 0.5);";
        assert_eq!(eval::<DVec3>(&format!("{a} a + b")), v(5.0, -3.0, 3.5));
        assert_eq!(eval::<DVec3>(&format!("{a} a - b")), v(-3.0, 7.0, 2.5));
        assert_eq!(eval::<DVec3>(&format!("{a} -a")), v(-1.0, -2.0, -3.0));
        assert_eq!(eval::<DVec3>(&format!("{a} a * b")), v(4.0, -10.0, 1.5));
        assert_eq!(eval::<DVec3>(&format!("{a} b / a")), v(4.0, -2.5, 0.5 / 3.0));
        assert_eq!(eval::<DVec3>(&format!("{a} a * 2")), v(2.0, 4.0, 6.0));
        assert_eq!(eval::<DVec3>(&format!("{a} 0.5 * a")), v(0.5, 1.0, 1.5));
        assert_eq!(eval::<DVec3>(&format!("{a} a / 4")), v(0.25, 0.5, 0.75));
        assert_eq!(eval::<DVec3>(&format!("{a} a += b; a")), v(5.0, -3.0, 3.5));
        assert_eq!(eval::<DVec3>(&format!("{a} a *= 3; a")), v(3.0, 6.0, 9.0));
        assert!(eval::<bool>(&format!("{a} a == vec3(1.0, 2, 3.0)")));
        assert!(eval::<bool>(&format!("{a} a != b")));
        assert!(!eval::<bool>(&format!("{a} a != vec3(1, 2, 3)")));
    }

    #[test]
    fn dot_cross_length_against_hand_computed_values() {
        assert_eq!(eval::<FLOAT>("dot(vec3(1, 2, 3), vec3(4, -5, 6))"), 12.0);
        assert_eq!(eval::<FLOAT>("vec3(1, 2, 3).dot(vec3(4, -5, 6))"), 12.0);
        assert_eq!(eval::<DVec3>("cross(vec3(1, 0, 0), vec3(0, 1, 0))"), DVec3::Z);
        assert_eq!(eval::<DVec3>("vec3(1, 2, 3).cross(vec3(4, 5, 6))"), v(-3.0, 6.0, -3.0));
        assert_eq!(eval::<FLOAT>("length(vec3(3, 4, 12))"), 13.0);
        assert_eq!(eval::<FLOAT>("vec3(1, 1, 1).distance(vec3(4, 5, 1))"), 5.0);
        assert_eq!(eval::<DVec3>("normalize(vec3(0, 3, -4))"), v(0.0, 0.6, -0.8));
        assert_eq!(eval::<DVec3>("min(vec3(1, 5, -2), vec3(3, 4, -1))"), v(1.0, 4.0, -2.0));
        assert_eq!(eval::<DVec3>("vec3(1, 5, -2).max(vec3(3, 4, -1))"), v(3.0, 5.0, -1.0));
    }

    #[test]
    fn builtin_numeric_min_and_max_still_work() {
        assert_eq!(eval::<INT>("min(3, 2)"), 2);
        assert_eq!(eval::<FLOAT>("max(1.5, 2.5)"), 2.5);
        // Operators registered with `Dynamic` operands leave number arithmetic alone.
        assert_eq!(eval::<INT>("2 * 3 - -1"), 7);
        assert_eq!(eval::<FLOAT>("1.5 * 2 / 4"), 0.75);
    }

    #[test]
    fn normalize_of_the_zero_vector_is_an_error() {
        let e = eval_err("normalize(vec3(0, 0, 0))");
        assert!(e.contains("normalize: the zero vector has no direction"), "{e}");
        let e = eval_err("vec3(0).normalize()");
        assert!(e.contains("no direction"), "{e}");
    }

    #[test]
    fn integers_and_floats_mix() {
        assert_eq!(eval::<DVec3>("vec3(1, 2.5, -3)"), v(1.0, 2.5, -3.0));
        assert_eq!(eval::<DVec3>("vec3(2)"), DVec3::splat(2.0));
        assert_eq!(eval::<DVec3>("let p = vec3(0); p.x = 2; p.y = 1.5; p.z -= 1; p"), v(2.0, 1.5, -1.0));
        assert_eq!(eval::<FLOAT>("let p = vec3(1, 2, 3); p.y + p.z"), 5.0);
        assert_eq!(eval::<FLOAT>("lerp(0, 10, 0.25)"), 2.5);
        assert_eq!(eval::<FLOAT>("lerp(2, 4.0, 1)"), 4.0);
        assert_eq!(eval::<FLOAT>("radians(180)"), std::f64::consts::PI);
        assert!((eval::<FLOAT>("degrees(PI() / 2)") - 90.0).abs() < 1e-12);
    }

    #[test]
    fn bad_inputs_are_errors_saying_what_was_expected() {
        let cases = [
            ("vec3(\"a\", 1, 2)", "vec3 x must be a number, got string"),
            ("vec3(1, 2, vec3(0))", "vec3 z must be a number, got vec3"),
            ("vec3(1e308 * 10.0)", "vec3 value must be a finite number, got inf"),
            ("let p = vec3(0); p.y = true; p", "vec3 y must be a number, got bool"),
            ("vec3(1) * \"x\"", "must be a number, got string"),
            ("vec3(1) / 0", "division by zero"),
            ("vec3(1) / vec3(1, 0, 1)", "division by zero"),
            ("vec3(1e308) * 10", "non-finite vector"),
            ("lerp(vec3(0), 1, 0.5)", "lerp needs two numbers or two vec3s, got vec3 and i64"),
            ("lerp(0, 1, \"t\")", "lerp t must be a number, got string"),
            ("clamp(1, 3, 2)", "clamp: lo (3) must not be greater than hi (2)"),
            ("ease(3, 0.5)", "ease name must be a string"),
        ];
        for (script, expected) in cases {
            let e = eval_err(script);
            assert!(e.contains(expected), "{script}: {e}");
        }
    }

    #[test]
    fn to_string_writes_a_vec3_literal() {
        assert_eq!(eval::<String>("vec3(1, 0.5, -2).to_string()"), "vec3(1, 0.5, -2)");
        assert_eq!(eval::<String>("`at ${vec3(0, 1, 2)}`"), "at vec3(0, 1, 2)");
        assert_eq!(eval::<String>("\"p = \" + vec3(3)"), "p = vec3(3, 3, 3)");
        assert_eq!(eval::<String>("to_debug(vec3(1.5, 0, 0))"), "vec3(1.5, 0, 0)");
    }

    #[test]
    fn lerp_and_smoothstep_endpoints_and_midpoints() {
        assert_eq!(eval::<FLOAT>("lerp(3, 7, 0)"), 3.0);
        assert_eq!(eval::<FLOAT>("lerp(3, 7, 1)"), 7.0);
        assert_eq!(eval::<FLOAT>("lerp(3, 7, 0.5)"), 5.0);
        assert_eq!(eval::<FLOAT>("lerp(3, 7, 2)"), 11.0);
        assert_eq!(eval::<DVec3>("lerp(vec3(0), vec3(2, 4, 6), 0.5)"), v(1.0, 2.0, 3.0));
        assert_eq!(eval::<DVec3>("vec3(1).lerp(vec3(5), 1)"), DVec3::splat(5.0));
        assert_eq!(eval::<FLOAT>("smoothstep(0, 10, 0)"), 0.0);
        assert_eq!(eval::<FLOAT>("smoothstep(0, 10, 10)"), 1.0);
        assert_eq!(eval::<FLOAT>("smoothstep(0, 10, 5)"), 0.5);
        assert_eq!(eval::<FLOAT>("smoothstep(0, 4, 1)"), 0.15625);
        assert_eq!(eval::<FLOAT>("smoothstep(0, 10, -3)"), 0.0);
        assert_eq!(eval::<FLOAT>("smoothstep(0, 10, 30)"), 1.0);
        assert_eq!(eval::<FLOAT>("smoothstep(2, 2, 1.9)"), 0.0);
        assert_eq!(eval::<FLOAT>("smoothstep(2, 2, 2)"), 1.0);
    }

    #[test]
    fn clamp_keeps_integers_integral() {
        assert_eq!(eval::<INT>("clamp(5, 0, 3)"), 3);
        assert_eq!(eval::<INT>("clamp(-5, 0, 3)"), 0);
        assert_eq!(eval::<FLOAT>("clamp(0.25, 0, 1)"), 0.25);
        assert_eq!(eval::<FLOAT>("clamp(2, 0, 1.5)"), 1.5);
    }

    #[test]
    fn easings_run_from_zero_to_one_monotonically() {
        for name in EASE_NAMES {
            assert_eq!(eval::<FLOAT>(&format!("ease(\"{name}\", 0)")), 0.0, "{name}");
            assert_eq!(eval::<FLOAT>(&format!("ease(\"{name}\", 1)")), 1.0, "{name}");
            assert_eq!(eval::<FLOAT>(&format!("ease(\"{name}\", -2)")), 0.0, "{name}");
            assert_eq!(eval::<FLOAT>(&format!("ease(\"{name}\", 7)")), 1.0, "{name}");
            let mut previous = 0.0;
            for i in 0..=1000 {
                let value = ease(name, f64::from(i) / 1000.0).unwrap_or(f64::NAN);
                assert!(value >= previous, "{name} decreases at {i}");
                previous = value;
            }
        }
        for (f, half) in [("ease_in", 0.125), ("ease_out", 0.875), ("ease_in_out", 0.5)] {
            assert_eq!(eval::<FLOAT>(&format!("{f}(0)")), 0.0, "{f}");
            assert_eq!(eval::<FLOAT>(&format!("{f}(1)")), 1.0, "{f}");
            assert_eq!(eval::<FLOAT>(&format!("{f}(0.5)")), half, "{f}");
        }
        assert!((eval::<FLOAT>("ease(\"sine\", 0.5)") - 0.5).abs() < 1e-15);
        assert_eq!(eval::<FLOAT>("ease(\"in\", 0.5)"), 0.125);
    }

    #[test]
    fn an_unknown_easing_lists_the_valid_names() {
        let e = eval_err("ease(\"bounce\", 0.5)");
        assert!(e.contains("unknown easing \"bounce\""), "{e}");
        assert!(e.contains("linear, in, out, in_out, smooth, sine"), "{e}");
    }
}
