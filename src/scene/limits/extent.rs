//! The world-space extent rule: an object's placed bounds ([`Extent`] under a [`Placement`])
//! and an area light's corners lie within ±[`MAX_COORDINATE`].

use glam::{DQuat, DVec3};

use super::{beyond, violation};
use crate::scene::error::number as num;
use crate::scene::format::{LightDesc, ObjectDesc, ShapeDesc, TransformDesc};
use crate::scene::mesh::MeshLibrary;
use crate::scene::rules::MAX_COORDINATE;
use crate::scene::validate::Violation;
use crate::world::components::Transform;

/// Where a shape lies in object space, as the extent rule sees it.
#[derive(Debug, Clone, PartialEq)]
pub enum Extent {
    /// A sphere: under a uniform scale its world bounds are the moved centre ± radius × |scale|.
    Ball {
        /// Centre.
        centre: DVec3,
        /// Radius.
        radius: f64,
    },
    /// These points' world images bound the shape (vertices, or a box's eight corners).
    Points(Vec<DVec3>),
    /// An infinite plane: only its point is placed.
    Plane(DVec3),
}

impl Extent {
    /// The extent of `shape`; a mesh's is its bounds' corners (`None` if it is not loaded).
    pub fn of(shape: &ShapeDesc, meshes: &MeshLibrary) -> Option<Self> {
        Some(match shape {
            ShapeDesc::Sphere { centre, radius } => {
                Self::Ball { centre: *centre, radius: f64::from(*radius) }
            }
            ShapeDesc::Plane { point, .. } => Self::Plane(*point),
            ShapeDesc::Triangle { vertices } => Self::Points(vertices.to_vec()),
            ShapeDesc::Polygon { vertices } => Self::Points(vertices.clone()),
            ShapeDesc::Cuboid { min, max } => Self::corners(*min, *max),
            ShapeDesc::Mesh { .. } => {
                let (_, asset) = meshes.get_key(shape.mesh_key()?)?;
                let b = asset.data.bounds;
                Self::corners(b.min.as_dvec3(), b.max.as_dvec3())
            }
        })
    }

    /// The eight corners of the box `min..max`.
    pub fn corners(min: DVec3, max: DVec3) -> Self {
        let pick = |i: usize| {
            DVec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        Self::Points((0..8).map(pick).collect())
    }

    /// World-space bounds under `placement` (scale, then rotate X, Y, Z, then translate).
    pub fn world_bounds(&self, placement: &Placement) -> (DVec3, DVec3) {
        let rotation = placement.rotation;
        let place = |p: DVec3| rotation * (placement.scale * p) + placement.translate;
        match self {
            Self::Ball { centre, radius } => {
                let c = place(*centre);
                let r = DVec3::splat(radius * placement.scale.abs().max_element());
                (c - r, c + r)
            }
            Self::Points(points) => points
                .iter()
                .map(|p| place(*p))
                .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
                    (lo.min(p), hi.max(p))
                }),
            Self::Plane(point) => (place(*point), place(*point)),
        }
    }
}

/// An object's placement in 64-bit floats: as a scene transform ([`TransformDesc`]) or the
/// World's [`Transform`] gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Translation.
    pub translate: DVec3,
    /// Rotation.
    pub rotation: DQuat,
    /// Per-axis scale.
    pub scale: DVec3,
}

impl Placement {
    /// The placement a scene transform describes (its rotation about X, then Y, then Z).
    pub fn of(t: &TransformDesc) -> Self {
        let r = t.rotate_deg.as_dvec3() * (std::f64::consts::PI / 180.0);
        let rotation =
            DQuat::from_rotation_z(r.z) * DQuat::from_rotation_y(r.y) * DQuat::from_rotation_x(r.x);
        Self { translate: t.translate, rotation, scale: t.scale.as_dvec3() }
    }

    /// The placement of a World transform.
    pub fn of_transform(t: &Transform) -> Self {
        Self { translate: t.translation, rotation: t.rotation.as_dquat(), scale: t.scale.as_dvec3() }
    }
}

/// The rule every object's placed bounds obey.
pub fn extent_rule() -> String {
    format!(
        "an object's world-space bounds (its shape × scale, rotated, then translated) must lie within \
         ±{MAX_COORDINATE:e}"
    )
}

/// Which part of an object puts it beyond the limit, and the first coordinate beyond it;
/// `None` when its placed bounds lie within ±[`MAX_COORDINATE`].
///
/// The part is `translate` when the object fits before it is moved, `scale` when the scale
/// enlarges it (|scale| > 1 on some axis), else `shape` (the shape alone is too large).
pub fn extent_excess(extent: &Extent, placement: &Placement) -> Option<(&'static str, &'static str, f64)> {
    let (lo, hi) = extent.world_bounds(placement);
    let (axis, value) = beyond(lo).or_else(|| beyond(hi))?;
    let unmoved = Placement { translate: DVec3::ZERO, ..*placement };
    let (ulo, uhi) = extent.world_bounds(&unmoved);
    let part = if beyond(ulo).is_none() && beyond(uhi).is_none() {
        "translate"
    } else if placement.scale.abs().max_element() > 1.0 {
        "scale"
    } else {
        "shape"
    };
    Some((part, axis, value))
}

/// A short account of how the shape reaches that far: `radius 1e17 × scale 1000`.
fn extent_account(object: &ObjectDesc) -> String {
    let t = &object.transform;
    let scale = t.scale.abs().max_element();
    match &object.shape {
        ShapeDesc::Sphere { radius, .. } => {
            format!("radius {} × scale {}", num(f64::from(*radius)), num(f64::from(scale)))
        }
        ShapeDesc::Plane { .. } => "the plane's point × transform".to_owned(),
        ShapeDesc::Triangle { .. } | ShapeDesc::Polygon { .. } => "its vertices × transform".to_owned(),
        ShapeDesc::Cuboid { .. } => "its box corners × transform".to_owned(),
        ShapeDesc::Mesh { .. } => "its mesh bounds × transform".to_owned(),
    }
}

/// The extent rule for one object, with a path relative to it.
pub fn object_violation(object: &ObjectDesc, meshes: &MeshLibrary) -> Option<Violation> {
    let extent = Extent::of(&object.shape, meshes)?;
    let (part, axis, value) = extent_excess(&extent, &Placement::of(&object.transform))?;
    let path = match (part, &object.shape) {
        ("translate", _) => "transform.translate",
        ("scale", _) => "transform.scale",
        (_, ShapeDesc::Sphere { .. }) => "shape.radius",
        (_, ShapeDesc::Mesh { .. }) => "shape.file",
        (_, ShapeDesc::Cuboid { .. }) => "shape.max",
        (_, ShapeDesc::Plane { .. }) => "shape.point",
        _ => "shape.vertices",
    };
    let rule =
        format!("{}: {} puts the object at {axis} = {}", extent_rule(), extent_account(object), num(value));
    Some(violation(path, rule))
}

/// The extent rule for an area light (its corners, or its centre ± radius); the path is
/// relative to the light.
pub fn light_extent_violation(light: &LightDesc) -> Option<Violation> {
    match *light {
        LightDesc::Rect { corner, edge_u, edge_v, .. } => {
            let (c, u, v) = (corner, edge_u.as_dvec3(), edge_v.as_dvec3());
            for (field, p) in [("edge_u", c + u), ("edge_v", c + v), ("edge_v", c + u + v)] {
                if let Some((axis, value)) = beyond(p) {
                    let rule = format!(
                        "the light's corners (`corner` + `edge_u` + `edge_v`) must lie within \
                         ±{MAX_COORDINATE:e}, but one is at {axis} = {}",
                        num(value)
                    );
                    return Some(violation(field, rule));
                }
            }
            None
        }
        LightDesc::Disk { centre, radius, .. } => {
            let reach = centre.abs() + DVec3::splat(f64::from(radius));
            let (axis, value) = beyond(reach)?;
            let rule = format!(
                "the disk (`centre` ± `radius`) must lie within ±{MAX_COORDINATE:e}, but it reaches \
                 |{axis}| = {}",
                num(value)
            );
            Some(violation("radius", rule))
        }
        LightDesc::Point { .. } | LightDesc::Spot { .. } | LightDesc::Directional { .. } => None,
    }
}
