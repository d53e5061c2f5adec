//! Keyframe paths: centripetal Catmull–Rom splines through `vec3` control points,
//! reparameterised by arc length so that `p.at(u)` moves at constant speed.
//!
//! The Rhai surface:
//! ```text
//! catmull_rom(points)  catmull_rom(points, closed)   ->  path   (points: an array of vec3)
//! p.at(u)  p.tangent(u)     u in [0, 1]: clamped on an open path, wrapped on a closed one
//! p.length  length(p)  p.points  len(p)  p.len()  to_string(p)
//! ```
//! Each segment is evaluated with the Barry–Goldman pyramid at alpha = 0.5 (knot intervals
//! are square roots of chord lengths), which rules out cusps and self-intersections within a
//! segment. An open path's end segments use reflected phantom points. A segment whose knot
//! intervals degenerate (coincident consecutive points) is a straight line instead.
//! Construction tabulates cumulative chord lengths at [`SAMPLES`] steps per segment;
//! `at` inverts that table by binary search and linear interpolation.

use std::fmt;

use glam::DVec3;
use rhai::{Array, Dynamic, Engine, INT};

use super::convert::{error, finite, type_name, ScriptResult};

/// Arc-length samples per segment.
pub const SAMPLES: usize = 64;

/// A smooth path through control points, traversed at constant speed as `u` runs over [0, 1].
///
/// # Examples
/// ```
/// # use penumbra::script::api::path::Path;
/// # use glam::DVec3;
/// let points = vec![DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::new(2.0, 0.0, 0.0)];
/// let path = Path::new(points, false).unwrap();
/// assert_eq!(path.at(0.0), DVec3::ZERO);
/// assert_eq!(path.at(1.0), DVec3::new(2.0, 0.0, 0.0));
/// ```
#[derive(Clone, Debug)]
pub struct Path {
    points: Vec<DVec3>,
    closed: bool,
    segments: Vec<Segment>,
    /// Cumulative chord length; entry `i * SAMPLES + j` lies at segment `i`, `tau = j / SAMPLES`.
    arc: Vec<f64>,
}

/// One Catmull–Rom segment from `p[1]` to `p[2]`, with neighbours `p[0]` and `p[3]`.
#[derive(Clone, Copy, Debug)]
struct Segment {
    p: [DVec3; 4],
    /// Knot intervals `|p[k+1] − p[k]|^½`.
    d: [f64; 3],
    /// Some knot interval is zero: the segment is the straight line `p[1]`–`p[2]`.
    linear: bool,
}

/// `a + (b − a) w`: `a` at 0 and `b` at 1, extended linearly beyond.
fn mix(a: DVec3, b: DVec3, w: f64) -> DVec3 {
    a + (b - a) * w
}

impl Segment {
    fn new(p: [DVec3; 4]) -> Segment {
        let d = [p[0].distance(p[1]).sqrt(), p[1].distance(p[2]).sqrt(), p[2].distance(p[3]).sqrt()];
        let linear = !d.iter().all(|&d| d > 0.0 && d.is_finite());
        Segment { p, d, linear }
    }

    /// Position and its derivative with respect to `tau` in [0, 1].
    fn eval(&self, tau: f64) -> (DVec3, DVec3) {
        let [p0, p1, p2, p3] = self.p;
        if self.linear {
            return (mix(p1, p2, tau), p2 - p1);
        }
        // Knots relative to t1 = 0, so that every denominator is a sum of positive intervals.
        let [d0, d1, d2] = self.d;
        let (t0, t1, t2, t3) = (-d0, 0.0, d1, d1 + d2);
        let t = tau * d1;

        // First level: the three chords, extended linearly in t.
        let a1 = mix(p0, p1, (t - t0) / d0);
        let a2 = mix(p1, p2, (t - t1) / d1);
        let a3 = mix(p2, p3, (t - t2) / d2);
        let (da1, da2, da3) = ((p1 - p0) / d0, (p2 - p1) / d1, (p3 - p2) / d2);

        // Second level.
        let b1 = mix(a1, a2, (t - t0) / (t2 - t0));
        let b2 = mix(a2, a3, (t - t1) / (t3 - t1));
        let db1 = mix(da1, da2, (t - t0) / (t2 - t0)) + (a2 - a1) / (t2 - t0);
        let db2 = mix(da2, da3, (t - t1) / (t3 - t1)) + (a3 - a2) / (t3 - t1);

        // Apex.
        let c = mix(b1, b2, (t - t1) / d1);
        let dc = mix(db1, db2, (t - t1) / d1) + (b2 - b1) / d1;
        (c, dc * d1)
    }

    /// Position at `tau`, exactly `p[1]` at 0 and `p[2]` at 1.
    fn position(&self, tau: f64) -> DVec3 {
        if tau <= 0.0 {
            self.p[1]
        } else if tau >= 1.0 {
            self.p[2]
        } else {
            self.eval(tau).0
        }
    }
}

impl Path {
    /// A path through `points` (at least 2, finite, not all equal), closed into a loop if asked.
    pub fn new(points: Vec<DVec3>, closed: bool) -> Result<Path, String> {
        let n = points.len();
        if n < 2 {
            return Err(format!("a path needs at least 2 points, got {n}"));
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(format!("point {i} is not finite: {}", points[i]));
        }

        // Segments, with reflected phantom points past the ends of an open path.
        let point = |i: isize| -> DVec3 {
            let last = n as isize - 1;
            match i {
                _ if closed => points[i.rem_euclid(n as isize) as usize],
                -1 => 2.0 * points[0] - points[1],
                _ if i > last => 2.0 * points[n - 1] - points[n - 2],
                _ => points[i as usize],
            }
        };
        let count = if closed { n } else { n - 1 };
        let segments: Vec<Segment> = (0..count as isize)
            .map(|i| Segment::new([point(i - 1), point(i), point(i + 1), point(i + 2)]))
            .collect();

        // Arc-length table: cumulative chord lengths over SAMPLES steps per segment.
        let mut arc = Vec::with_capacity(count * SAMPLES + 1);
        arc.push(0.0);
        let mut length = 0.0;
        for segment in &segments {
            let mut previous = segment.p[1];
            for j in 1..=SAMPLES {
                let q = segment.position(j as f64 / SAMPLES as f64);
                length += q.distance(previous);
                arc.push(length);
                previous = q;
            }
        }
        if !length.is_finite() {
            return Err("the points are too far apart: the path's length is not finite".into());
        }
        if length == 0.0 {
            return Err(format!("a path needs 2 distinct points, but all {n} coincide"));
        }
        Ok(Path { points, closed, segments, arc })
    }

    /// The position at `u` along the path by arc length; exactly the first point at `u = 0`.
    ///
    /// An open path clamps `u` to [0, 1] and ends exactly at its last point; a closed path
    /// wraps `u`, so `at(1) == at(0)`. NaN counts as 0.
    pub fn at(&self, u: f64) -> DVec3 {
        let u = self.wrap(u);
        if u <= 0.0 {
            return self.points[0];
        }
        if u >= 1.0 {
            return self.points[self.points.len() - 1];
        }
        let (segment, tau) = self.locate(u);
        self.segments[segment].position(tau)
    }

    /// The unit direction of travel at `u` (wrapped or clamped as in [`Path::at`]).
    pub fn tangent(&self, u: f64) -> DVec3 {
        let (segment, tau) = self.locate(self.wrap(u));
        let direction = self.segments[segment].eval(tau).1.normalize_or_zero();
        if direction != DVec3::ZERO {
            return direction;
        }
        // A segment shrunk to a point: difference the neighbouring positions along the arc.
        const H: f64 = 1e-6;
        (self.at(u + H) - self.at(u - H)).normalize_or_zero()
    }

    /// The total arc length.
    pub fn length(&self) -> f64 {
        self.arc[self.arc.len() - 1]
    }

    /// The control points the path passes through.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// Whether the path loops back from its last point to its first.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// `u` clamped (open) or wrapped (closed) into [0, 1]; NaN and, when closed, ±∞ become 0.
    fn wrap(&self, u: f64) -> f64 {
        if !self.closed {
            return if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        }
        if !u.is_finite() {
            return 0.0;
        }
        // rem_euclid rounds up to 1.0 for tiny negative u.
        let w = u.rem_euclid(1.0);
        if w < 1.0 {
            w
        } else {
            0.0
        }
    }

    /// The segment and its local parameter at arc-length fraction `u` in [0, 1].
    fn locate(&self, u: f64) -> (usize, f64) {
        let s = u * self.length();
        // The last entry at or below s; runs of equal entries (zero-length stretches) are
        // skipped, so the interval [k, k + 1] has positive width unless s is the very end.
        let k = self.arc.partition_point(|&c| c <= s).saturating_sub(1).min(self.arc.len() - 2);
        let (c0, c1) = (self.arc[k], self.arc[k + 1]);
        let f = if c1 > c0 { ((s - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 0.0 };
        (k / SAMPLES, ((k % SAMPLES) as f64 + f) / SAMPLES as f64)
    }
}

impl fmt::Display for Path {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = if self.closed { "closed" } else { "open" };
        let n = self.points.len();
        write!(f, "path({n} points, {kind}, length {})", self.length())
    }
}

/// A path from a script array of `vec3`, with errors naming the offending element.
fn from_script(points: Dynamic, closed: bool) -> ScriptResult<Path> {
    let name = type_name(&points);
    let Ok(array) = points.into_array() else {
        return error(format!("catmull_rom points must be an array of vec3, got {name}"));
    };
    let mut vectors = Vec::with_capacity(array.len());
    for (i, element) in array.iter().enumerate() {
        match element.read_lock::<DVec3>() {
            Some(v) => vectors.push(*v),
            None => {
                let got = type_name(element);
                return error(format!("catmull_rom point {i} must be a vec3, got {got}"));
            }
        }
    }
    Path::new(vectors, closed).or_else(|e| error(format!("catmull_rom: {e}")))
}

/// Registers the `path` type, `catmull_rom` and the path methods into `engine`.
///
/// # Examples
/// ```
/// # use penumbra::script::api::{math, path};
/// let mut engine = rhai::Engine::new();
/// math::register(&mut engine);
/// path::register(&mut engine);
/// let length: f64 = engine.eval("catmull_rom([vec3(0), vec3(3, 4, 0)]).length").unwrap();
/// assert_eq!(length, 5.0);
/// ```
pub fn register(engine: &mut Engine) {
    engine
        .register_type_with_name::<Path>("path")
        .register_fn("catmull_rom", |points: Dynamic| from_script(points, false))
        .register_fn("catmull_rom", |points: Dynamic, closed: Dynamic| {
            let Ok(closed) = closed.as_bool() else {
                let got = type_name(&closed);
                return error(format!("catmull_rom closed must be true or false, got {got}"));
            };
            from_script(points, closed)
        })
        .register_fn("at", |p: &mut Path, u: Dynamic| finite(&u, "path at u").map(|u| p.at(u)))
        .register_fn("tangent", |p: &mut Path, u: Dynamic| finite(&u, "path tangent u").map(|u| p.tangent(u)))
        .register_get("length", |p: &mut Path| p.length())
        .register_fn("length", |p: &mut Path| p.length())
        .register_get("points", |p: &mut Path| p.points.iter().copied().map(Dynamic::from).collect::<Array>())
        .register_fn("len", |p: &mut Path| p.points.len() as INT)
        .register_fn("to_string", |p: &mut Path| p.to_string())
        .register_fn("to_debug", |p: &mut Path| p.to_string());
}

#[cfg(test)]
mod tests;
