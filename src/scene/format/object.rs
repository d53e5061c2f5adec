//! The scene file's objects: shapes and their placement.

use super::*;

/// One renderable object.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    /// Unique name (scripts address objects by it). Default: the shape kind and index, e.g. `sphere_3`.
    #[serde(default)]
    pub name: Option<String>,
    /// Geometry in object space.
    pub shape: ShapeDesc,
    /// Name of a material defined in `materials`.
    pub material: String,
    /// Placement in the world. Default: identity.
    #[serde(default)]
    pub transform: TransformDesc,
}

/// Geometry of an object, in object space.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeDesc {
    /// A sphere; `radius` > 0.
    Sphere {
        /// Centre.
        centre: DVec3,
        /// Radius, > 0.
        radius: f32,
    },
    /// An infinite plane through `point` with the given (non-zero) normal.
    Plane {
        /// Any point on the plane.
        point: DVec3,
        /// Normal; need not be unit length, must be non-zero.
        normal: Vec3,
    },
    /// A single triangle; must have non-zero area.
    Triangle {
        /// The three corners, counter-clockwise seen from the front.
        vertices: [DVec3; 3],
    },
    /// A convex planar polygon of at least three vertices, in order around its boundary.
    Polygon {
        /// The corners in order.
        vertices: Vec<DVec3>,
    },
    /// An axis-aligned box (in object space; a rotation in `transform` orients it).
    #[serde(rename = "Box")]
    Cuboid {
        /// Minimum corner.
        min: DVec3,
        /// Maximum corner; strictly greater than `min` on every axis.
        max: DVec3,
    },
    /// A triangle mesh from a Wavefront OBJ file, placed by the object's `transform`. Every
    /// object naming the same file (and `smooth` and `materials`) shares one copy of it and one
    /// grid.
    Mesh {
        /// The OBJ file, relative to the scene file.
        file: String,
        /// Phong shading with interpolated vertex normals (the file's, or computed weighted by
        /// area and angle); `false` shows flat facets. Default `true`.
        #[serde(default = "default_true")]
        smooth: bool,
        /// `Object`: the object's `material` everywhere; `FromFile`: each face's material from
        /// the file's `.mtl` libraries (`mtllib`, `usemtl`), a scene material of the same name
        /// taking the place of the library's. Default `Object`.
        #[serde(default)]
        materials: MeshMaterials,
    },
}

/// Where a mesh's materials come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
pub enum MeshMaterials {
    /// The object's `material`, on every face.
    #[default]
    Object,
    /// The OBJ's `.mtl` libraries, face by face (faces before any `usemtl` take the object's
    /// `material`); a scene material named like a library material replaces it.
    FromFile,
}

impl ShapeDesc {
    /// For a mesh, the key its asset is loaded under: file, `smooth`, and whether its faces
    /// carry the file's materials.
    pub fn mesh_key(&self) -> Option<(&str, bool, bool)> {
        match self {
            ShapeDesc::Mesh { file, smooth, materials } => {
                Some((file, *smooth, *materials == MeshMaterials::FromFile))
            }
            _ => None,
        }
    }
}

fn default_true() -> bool {
    true
}

impl ShapeDesc {
    /// Lower-case kind name, used for default object names (`sphere`, `plane`, ...).
    pub fn kind(&self) -> &'static str {
        match self {
            ShapeDesc::Sphere { .. } => "sphere",
            ShapeDesc::Plane { .. } => "plane",
            ShapeDesc::Triangle { .. } => "triangle",
            ShapeDesc::Polygon { .. } => "polygon",
            ShapeDesc::Cuboid { .. } => "box",
            ShapeDesc::Mesh { .. } => "mesh",
        }
    }
}

/// Object-to-world placement: scale, then rotate (X, then Y, then Z, in degrees), then translate.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TransformDesc {
    /// Translation.
    pub translate: DVec3,
    /// Rotation in degrees about X, then Y, then Z.
    pub rotate_deg: Vec3,
    /// Per-axis scale, each non-zero; spheres require a uniform scale.
    pub scale: Vec3,
}

impl Default for TransformDesc {
    fn default() -> Self {
        Self { translate: DVec3::ZERO, rotate_deg: Vec3::ZERO, scale: Vec3::ONE }
    }
}
