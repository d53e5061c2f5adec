//! A hit as shading sees it: the surface seen from the side its ray arrives on, with the
//! normals and spawn point every shading step shares.

use crate::math::Vec3;
use crate::store::SurfacePoint;

/// The normals a hit is shaded with, turned towards the incoming direction `dir`: whether the
/// ray arrives on the front (geometric) side, the geometric normal on the arrival side, and the
/// shading normal on that side (the geometric one where the interpolated normal would face
/// away from the viewer, which can happen at grazing angles on a smooth mesh).
#[inline]
pub fn facing_normals(sp: &crate::store::SurfacePoint, dir: Vec3) -> (bool, Vec3, Vec3) {
    let entering = sp.normal.dot(dir) < 0.0;
    let n = if entering { sp.normal } else { -sp.normal };
    let ns = match if entering { sp.shading } else { -sp.shading } {
        s if s.dot(dir) < 0.0 => s,
        _ => n,
    };
    (entering, n, ns)
}

/// A hit as shading sees it from the side its ray arrives on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingPoint {
    /// The surface at the hit.
    pub sp: SurfacePoint,
    /// Whether the ray arrives on the front (geometric) side.
    pub entering: bool,
    /// The unit geometric normal on the arrival side: it decides offsets and sides.
    pub n: Vec3,
    /// The unit shading normal on the arrival side, unless it would face away from the viewer
    /// (possible at grazing angles on a smooth mesh), where `n` takes over.
    pub ns: Vec3,
    /// Where rays leaving on the arrival side start: just beyond the hit point's error bound
    /// along `n` (the front of a smooth mesh from its lifted point: no shadow terminator).
    pub above: Vec3,
}

impl ShadingPoint {
    /// The surface `sp` seen by a ray travelling along `dir`.
    #[inline(always)]
    pub fn new(sp: SurfacePoint, dir: Vec3) -> Self {
        let (entering, n, ns) = facing_normals(&sp, dir);
        Self { sp, entering, n, ns, above: sp.spawn(n) }
    }
}
