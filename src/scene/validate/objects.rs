//! The rules of `objects[i]`: the shape (spheres, planes, boxes, polygons, meshes), its
//! transform and its material reference.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec3};

use super::*;

pub(super) fn object(path: &FieldPath, object: &ObjectDesc, materials: &[MaterialDesc]) -> Check {
    shape(&path.clone().field("shape"), &object.shape)?;
    if !materials.iter().any(|m| m.name == object.material) {
        const LISTED: usize = 24;
        let defined: Vec<String> =
            materials.iter().take(LISTED).map(|m| format!("`{}`", shown(&m.name))).collect();
        let more = match materials.len().saturating_sub(LISTED) {
            0 => String::new(),
            n => format!(" and {n} more"),
        };
        let defined = match defined.is_empty() {
            true => "no materials are defined".to_owned(),
            false => format!("defined: {}{more}", defined.join(", ")),
        };
        let rule = format!("material `{}` is not defined; {defined}", shown(&object.material));
        return fail(path, "material", rule);
    }
    transform(&path.clone().field("transform"), &object.transform, &object.shape)
}

fn transform(path: &FieldPath, transform: &TransformDesc, shape: &ShapeDesc) -> Check {
    position(path, "translate", transform.translate)?;
    finite_vec(path, "rotate_deg", transform.rotate_deg)?;
    coordinate_vec(path, "scale", transform.scale)?;
    if let Some((i, _)) = first_component(transform.scale, |s| s == 0.0) {
        return fail(path, "scale", format!("must be non-zero on every axis, got {} = 0", AXES[i]));
    }
    let magnitudes = transform.scale.abs();
    let spread = magnitudes.max_element() - magnitudes.min_element();
    if matches!(shape, ShapeDesc::Sphere { .. })
        && spread > UNIFORM_SCALE_TOLERANCE * magnitudes.max_element()
    {
        let rule = format!(
            "must be uniform for a sphere (|x| = |y| = |z|, within a relative {UNIFORM_SCALE_TOLERANCE}), got {}",
            vec(transform.scale)
        );
        return fail(path, "scale", rule);
    }
    Ok(())
}

fn shape(path: &FieldPath, shape: &ShapeDesc) -> Check {
    match shape {
        ShapeDesc::Sphere { centre, radius } => {
            position(path, "centre", *centre)?;
            coordinate(path, "radius", *radius)?;
            if *radius <= 0.0 {
                return fail(path, "radius", format!("must be > 0, got {radius}"));
            }
        }
        ShapeDesc::Plane { point, normal } => {
            position(path, "point", *point)?;
            finite_vec(path, "normal", *normal)?;
            if *normal == Vec3::ZERO {
                return fail(path, "normal", "must be non-zero, got (0, 0, 0)".into());
            }
        }
        ShapeDesc::Triangle { vertices } => {
            let path = path.clone().field("vertices");
            for (i, v) in vertices.iter().enumerate() {
                position(&path, i, *v)?;
            }
            let [a, b, c] = *vertices;
            let longest = (b - a).length().max((c - b).length()).max((a - c).length());
            if longest == 0.0 || (b - a).cross(c - a).length() <= DEGENERATE_TOLERANCE * longest * longest {
                let rule = "must span a non-zero area: the three vertices are collinear or coincide";
                return Err(Violation { path, rule: rule.into() });
            }
        }
        ShapeDesc::Polygon { vertices } => polygon(&path.clone().field("vertices"), vertices)?,
        ShapeDesc::Mesh { file, .. } => {
            if file.trim().is_empty() {
                return fail(path, "file", "must name an OBJ file, got an empty string".into());
            }
        }
        ShapeDesc::Cuboid { min, max } => {
            position(path, "min", *min)?;
            position(path, "max", *max)?;
            if let Some((axis, _)) = first_dcomponent(*max - *min, |d| d <= 0.0) {
                let (hi, lo) = (max[axis], min[axis]);
                let rule = format!(
                    "must be greater than `min` on every axis; on {}, max {hi} is not greater than min {lo}",
                    AXES[axis]
                );
                return fail(path, "max", rule);
            }
        }
    }
    Ok(())
}

/// A convex, planar, non-degenerate polygon visiting each corner once.
pub(super) fn polygon(path: &FieldPath, vertices: &[DVec3]) -> Check {
    if vertices.len() < 3 {
        let rule = format!("a polygon must have at least 3 vertices, got {}", vertices.len());
        return Err(Violation { path: path.clone(), rule });
    }
    for (i, v) in vertices.iter().enumerate() {
        position(path, i, *v)?;
    }
    let v = vertices;
    let n = v.len();
    let (lo, hi) = v.iter().fold((v[0], v[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let size = (hi - lo).length();
    for i in 0..n {
        if (v[(i + 1) % n] - v[i]).length() <= DEGENERATE_TOLERANCE * size {
            let previous = if i + 1 == n { "the last vertex" } else { "the previous vertex" };
            let rule = format!("repeats {previous}; consecutive vertices must differ");
            return Err(Violation { path: path.clone().index((i + 1) % n), rule });
        }
    }
    // Newell's method: twice the area times the unit normal, oriented by the winding.
    let newell: DVec3 = (0..n).map(|i| v[i].cross(v[(i + 1) % n])).sum();
    if newell.length() <= DEGENERATE_TOLERANCE * size * size {
        // Zero signed area: either the vertices are collinear, or a self-crossing outline
        // (a bow-tie) cancels its own area. Tell them apart by the widest triangle on v[0].
        let far = v.iter().copied().max_by(|a, b| (*a - v[0]).length().total_cmp(&(*b - v[0]).length()));
        let far = far.unwrap_or(v[0]) - v[0];
        let spread = v.iter().map(|p| (*p - v[0]).cross(far).length()).fold(0.0, f64::max);
        let rule = if spread <= DEGENERATE_TOLERANCE * size * size {
            "must span a non-zero area: the vertices are collinear or coincide"
        } else {
            "makes the polygon non-convex: the boundary crosses itself, so its area cancels out"
        };
        return Err(Violation { path: path.clone(), rule: rule.into() });
    }
    let normal = newell.normalize();
    let centroid = v.iter().sum::<DVec3>() / n as f64;
    for (i, p) in v.iter().enumerate() {
        let distance = (*p - centroid).dot(normal).abs();
        if distance > PLANARITY_TOLERANCE * size {
            let rule = format!(
                "must lie in the plane of the polygon: it is {} away (allowed: {PLANARITY_TOLERANCE} of the polygon's size {})",
                distance as f32, size as f32
            );
            return Err(Violation { path: path.clone().index(i), rule });
        }
    }
    let mut total_turn = 0.0;
    for i in 0..n {
        let incoming = v[i] - v[(i + n - 1) % n];
        let outgoing = v[(i + 1) % n] - v[i];
        let sine = incoming.cross(outgoing).dot(normal);
        let turn = sine.atan2(incoming.dot(outgoing));
        if !(-DEGENERATE_TOLERANCE..=PI - DEGENERATE_TOLERANCE).contains(&turn) {
            let rule = "makes the polygon non-convex: the boundary turns the other way (or folds back) here";
            return Err(Violation { path: path.clone().index(i), rule: rule.into() });
        }
        total_turn += turn;
    }
    if total_turn > TAU * (1.0 + 1e-6) {
        let rule = format!(
            "must go once around a convex outline, but the boundary winds {:.0} times (it crosses itself)",
            total_turn / TAU
        );
        return Err(Violation { path: path.clone(), rule });
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Rule helpers
