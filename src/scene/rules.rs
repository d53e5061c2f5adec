//! The numeric limits of the scene format, and the rule texts that name them: one small
//! table that the field checks ([`super::validate`]), the cross-field checks
//! ([`super::limits`]) and the OBJ and `.mtl` importers read (`validate` re-exports it), so none
//! of them borrows a number from another.

/// Largest accepted image width or height, in pixels.
pub const MAX_IMAGE_SIZE: u32 = 16384;
/// Largest accepted `settings.max_depth`.
pub const MAX_DEPTH: u32 = 64;
/// Relative tolerance for degeneracy: a triangle or polygon is degenerate when its height is
/// below this fraction of its size; `up` is parallel to the view when the sine of the angle
/// between them is below it.
pub const DEGENERATE_TOLERANCE: f64 = 1e-6;
/// Relative tolerance for polygon planarity: each vertex may be this fraction of the
/// polygon's size away from its plane.
pub const PLANARITY_TOLERANCE: f64 = 1e-5;
/// Relative tolerance for a sphere's uniform scale.
pub const UNIFORM_SCALE_TOLERANCE: f32 = 1e-5;
/// Largest accepted sample count of any distribution effect (anti-aliasing, lens, glossy
/// rays, area lights).
pub const MAX_SAMPLES: u32 = 4096;
/// Largest accepted `settings.adaptive.max_depth`.
pub const MAX_ADAPTIVE_DEPTH: u32 = 6;
/// Largest accepted `settings.max_secondary_rays` (2^24): the budget still bounds a camera
/// sample's work to seconds, not the hours of an unbounded tree.
pub const MAX_SECONDARY_RAYS: u32 = 1 << 24;
/// Largest accepted magnitude of any coordinate, radius or scale component. Intersection
/// tests square distances in 32-bit floats (largest ≈ 3.4e38), so a value beyond about 1.8e19
/// overflows; the limit leaves a margin for sums. It also bounds what fields make together:
/// an object's world-space bounds and the lens (see [`super::limits`]).
pub const MAX_COORDINATE: f32 = 1e18;

/// Largest accepted Phong exponent. `R·V` can round to a few ulps above 1 in 32-bit floats,
/// and `(1 + 5e-7)^1e4` is still below 1.01, so a highlight stays at most `ks`; at 1e9 the
/// same rounding overflows to +inf.
pub const MAX_SHININESS: f32 = 1e4;

/// The rule a material's `shininess` obeys (see [`MAX_SHININESS`]).
pub fn shininess_rule() -> String {
    format!(
        "must be at most {MAX_SHININESS:e} (a larger Phong exponent turns rounding into infinite highlights)"
    )
}

/// Largest exposure magnitude in stops.
pub const MAX_EXPOSURE: f32 = 30.0;

/// Largest `settings.noise.max_samples` (and `min_samples`).
pub const MAX_NOISE_SAMPLES: u32 = 65536;

/// The rule every coordinate, radius and scale obeys (see [`MAX_COORDINATE`]).
pub fn coordinate_rule() -> String {
    format!("must lie within ±{MAX_COORDINATE:e} (distances are squared in 32-bit floats)")
}
