//! Arbitrary output variables: per-pixel data besides colour, for compositing, denoising and
//! seeing where render time went. Each buffer exists only when it was asked for.

use serde::Serialize;

use crate::math::Vec3;

/// Which AOVs to produce.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct AovSet {
    /// Camera-space depth of the first hit (distance along the view direction).
    pub depth: bool,
    /// Unit shading normal at the first hit (facing the camera ray).
    pub normal: bool,
    /// Diffuse colour `kd` at the first hit.
    pub albedo: bool,
    /// Object id at the first hit (0 = background; see [`Aovs::object_names`]).
    pub object: bool,
    /// Rays traced for the pixel, all kinds.
    pub cost: bool,
}

impl AovSet {
    /// True when no AOV is wanted.
    pub fn is_empty(&self) -> bool {
        !(self.depth || self.normal || self.albedo || self.object || self.cost)
    }

    /// Parses a comma-separated list such as `depth,normal,cost` (names: depth, normal, albedo,
    /// object, cost).
    pub fn parse(list: &str) -> Result<Self, String> {
        let mut set = AovSet::default();
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match name {
                "depth" => set.depth = true,
                "normal" => set.normal = true,
                "albedo" => set.albedo = true,
                "object" => set.object = true,
                "cost" => set.cost = true,
                other => {
                    return Err(format!(
                        "unknown AOV `{other}`; expected depth, normal, albedo, object or cost"
                    ))
                }
            }
        }
        Ok(set)
    }
}

/// AOV buffers of a frame, row-major like the film; `None` for those not asked for. First-hit
/// AOVs come from the pixel's first camera sample; background pixels hold depth `+∞`, normal
/// and albedo zero, object 0.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Aovs {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Camera-space depth.
    pub depth: Option<Vec<f32>>,
    /// Shading normal.
    pub normal: Option<Vec<Vec3>>,
    /// Diffuse colour.
    pub albedo: Option<Vec<Vec3>>,
    /// Object id: 0 for background, `i + 1` for `object_names[i]`.
    pub object: Option<Vec<u32>>,
    /// Rays traced per pixel.
    pub cost: Option<Vec<u32>>,
    /// Legend of object ids: the scene name of object `id - 1`.
    pub object_names: Vec<String>,
}

impl Aovs {
    /// Empty buffers of the requested kinds for a `width × height` image.
    pub fn new(set: AovSet, width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            depth: set.depth.then(|| vec![f32::INFINITY; n]),
            normal: set.normal.then(|| vec![Vec3::ZERO; n]),
            albedo: set.albedo.then(|| vec![Vec3::ZERO; n]),
            object: set.object.then(|| vec![0; n]),
            cost: set.cost.then(|| vec![0; n]),
            object_names: Vec::new(),
        }
    }

    /// Bytes held by the buffers.
    pub fn memory_bytes(&self) -> usize {
        let len = |n: Option<usize>, size: usize| n.unwrap_or(0) * size;
        len(self.depth.as_ref().map(Vec::len), 4)
            + len(self.normal.as_ref().map(Vec::len), 12)
            + len(self.albedo.as_ref().map(Vec::len), 12)
            + len(self.object.as_ref().map(Vec::len), 4)
            + len(self.cost.as_ref().map(Vec::len), 4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aov_lists_parse_and_unknown_names_are_rejected() {
        let set = AovSet::parse("depth, cost").unwrap();
        assert!(set.depth && set.cost && !set.normal && !set.albedo && !set.object);
        assert!(AovSet::parse("").unwrap().is_empty());
        assert!(AovSet::parse("depth,colour").unwrap_err().contains("colour"));
    }

    #[test]
    fn only_requested_buffers_take_memory() {
        assert_eq!(Aovs::new(AovSet::default(), 10, 10).memory_bytes(), 0);
        let set = AovSet { depth: true, normal: true, ..Default::default() };
        assert_eq!(Aovs::new(set, 10, 10).memory_bytes(), 100 * 16);
    }
}
