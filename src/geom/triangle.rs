//! Triangle given by its three vertices, intersected with the watertight test of Woop, Benthin
//! and Wald (2013).
//!
//! The ray is turned once into a [`WatertightRay`]: the axis where its direction is largest
//! becomes z, and a shear maps the direction onto +z. Each vertex is then sheared relative to
//! the ray origin and the three 2D edge functions `U`, `V`, `W` decide the hit. Two triangles
//! sharing an edge compute that edge's function from the same two sheared vertices in opposite
//! order, so one gets exactly the negation of the other: no ray slips between them. A ray that
//! meets an edge or a vertex exactly (a function is exactly 0, also after the f64 re-check the
//! paper prescribes) is given to exactly one of the triangles around it by a tie-break that
//! treats the ray as nudged by an infinitesimal fixed offset in the sheared plane.

use crate::math::{gamma, Aabb, Ray, Vec3};

/// A triangle hit: ray parameter and barycentrics of `v1` and `v2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter.
    pub t: f32,
    /// Barycentric weight of `v1`.
    pub u: f32,
    /// Barycentric weight of `v2`.
    pub v: f32,
}

/// A ray prepared for watertight triangle tests: axis permutation and shear constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WatertightRay {
    /// Ray origin.
    pub origin: Vec3,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl WatertightRay {
    /// Prepares `ray` (any non-zero direction; it need not be unit length).
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let a = ray.dir.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        // The next two axes in cyclic order, `(kz + 1) % 3` and `(kz + 2) % 3`, without a
        // division.
        let (mut kx, mut ky) = [(1, 2), (2, 0), (0, 1)][kz];
        // Keep the winding: a negative z axis swaps the other two.
        if ray.dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let dz = ray.dir[kz];
        Self { origin: ray.origin, kx, ky, kz, sx: ray.dir[kx] / dz, sy: ray.dir[ky] / dz, sz: 1.0 / dz }
    }

    /// The axis permutation `[kx, ky, kz]`: `kz` the direction's largest axis.
    #[inline]
    pub fn permutation(&self) -> [usize; 3] {
        [self.kx, self.ky, self.kz]
    }

    /// The shear constants `(s_x, s_y, s_z)`: `d_kx/d_kz`, `d_ky/d_kz`, `1/d_kz`.
    #[inline]
    pub fn shear_constants(&self) -> (f32, f32, f32) {
        (self.sx, self.sy, self.sz)
    }

    /// A vertex relative to the origin, sheared: `(x, y)` in the ray's plane, `z` along it.
    #[inline]
    fn shear(&self, p: Vec3) -> (f32, f32, f32) {
        let a = p - self.origin;
        (a[self.kx] - self.sx * a[self.kz], a[self.ky] - self.sy * a[self.kz], self.sz * a[self.kz])
    }
}

/// The bounds of the triangle `v0 v1 v2`.
#[inline]
pub fn bounds(v0: Vec3, v1: Vec3, v2: Vec3) -> Aabb {
    Aabb::from_points([v0, v1, v2])
}

/// Watertight intersection within `(t_min, t_max)`; both faces are hit; a degenerate
/// (zero-area) triangle is never hit.
#[inline]
pub fn intersect(
    v0: Vec3,
    v1: Vec3,
    v2: Vec3,
    ray: &WatertightRay,
    t_min: f32,
    t_max: f32,
) -> Option<TriangleHit> {
    let (ax, ay, az) = ray.shear(v0);
    let (bx, by, bz) = ray.shear(v1);
    let (cx, cy, cz) = ray.shear(v2);
    // Edge functions: U for edge v1→v2 (weight of v0), V for v2→v0, W for v0→v1.
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // Exactly on an edge in f32: decide in f64, where these products are exact.
        let (ax, ay, bx, by, cx, cy) = (ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64);
        u = (cx * by - cy * bx) as f32;
        v = (ax * cy - ay * cx) as f32;
        w = (bx * ay - by * ax) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    // Points exactly on an edge belong to one side only (see the module docs).
    let positive = det > 0.0;
    if (u == 0.0 && !owns_edge(cx, cy, bx, by, positive))
        || (v == 0.0 && !owns_edge(ax, ay, cx, cy, positive))
        || (w == 0.0 && !owns_edge(bx, by, ax, ay, positive))
    {
        return None;
    }
    let t = (u * az + v * bz + w * cz) / det;
    if !(t > t_min && t < t_max) {
        return None;
    }
    Some(TriangleHit { t, u: v / det, v: w / det })
}

/// The hit point at barycentrics `(u, v)` of `v1`, `v2`, interpolated from the vertices (which,
/// unlike `origin + t·dir`, does not carry the error of `t`), and a conservative bound on its
/// distance from the triangle's plane along the unit normal `n`, as [`intersect`] will see a
/// ray starting there: pbrt-v4's `γ(7)·(|b0·v0| + |b1·v1| + |b2·v2|)` per axis, projected on
/// `|n|`, for the point, plus [`TEST_ERROR`] times the vertices' distance from it, for the test.
#[inline]
pub fn surface_point(v0: Vec3, v1: Vec3, v2: Vec3, u: f32, v: f32, n: Vec3) -> (Vec3, f32) {
    let b0 = 1.0 - u - v;
    let point = v0 * b0 + v1 * u + v2 * v;
    let error = ((v0 * b0).abs() + (v1 * u).abs() + (v2 * v).abs()) * gamma(7);
    (point, error.dot(n.abs()) + TEST_ERROR * reach(v0, v1, v2, point))
}

/// How far the test's own rounding can put a ray origin from the triangle's plane, per unit of
/// the vertices' distance from it. The watertight test works on the vertices relative to the
/// origin; pbrt-v4's bound on the error of its `t` (section 6.8.7) is, times the cosine between
/// the ray and the normal, at most about γ(40) of that distance, whatever the direction: an
/// origin farther out than this from the plane gets the sign of `t` right.
pub const TEST_ERROR: f32 = gamma(48);

/// A bound on the distance from `p` to the farthest vertex (√3 times the largest coordinate
/// difference: no square root).
#[inline]
pub fn reach(v0: Vec3, v1: Vec3, v2: Vec3, p: Vec3) -> f32 {
    (v0 - p).abs().max((v1 - p).abs()).max((v2 - p).abs()).max_element() * 1.7321
}

/// Whether a ray exactly on the edge whose function is `f.x * g.y - f.y * g.x` counts as
/// inside: true when nudging the ray by `(1, δ)` (δ → 0⁺) in the sheared plane moves it to the
/// inside. The function's gradient with respect to the ray position is `(f.y - g.y, g.x - f.x)`;
/// the two triangles on an edge see it with swapped `f`, `g` and agree on which one owns it.
#[inline]
fn owns_edge(fx: f32, fy: f32, gx: f32, gy: f32, positive: bool) -> bool {
    let (dx, dy) = (fy - gy, gx - fx);
    let towards = if dx != 0.0 { dx > 0.0 } else { dy > 0.0 };
    towards == positive
}

/// Unit geometric normal (`(v1 - v0) × (v2 - v0)`, counter-clockwise front). Zero-area
/// triangles, which are never hit, give `+Y` rather than NaN.
#[inline]
pub fn normal(v0: Vec3, v1: Vec3, v2: Vec3) -> Vec3 {
    (v1 - v0).cross(v2 - v0).try_normalize().unwrap_or(Vec3::Y)
}

/// True when the triangle overlaps the box: separating-axis test of Akenine-Möller
/// (box axes, triangle normal and the nine edge cross products). Exact, not a bounds test.
pub fn overlaps_box(v0: Vec3, v1: Vec3, v2: Vec3, cell: &Aabb) -> bool {
    let centre = (cell.min + cell.max) * 0.5;
    let half = (cell.max - cell.min) * 0.5;
    let a = v0 - centre;
    let b = v1 - centre;
    let c = v2 - centre;
    // The three box axes first: triangle bounds against the box (the cheapest rejection).
    let lo = a.min(b).min(c);
    let hi = a.max(b).max(c);
    if lo.cmpgt(half).any() || hi.cmplt(-half).any() {
        return false;
    }
    // The triangle's plane.
    let n = (b - a).cross(c - a);
    if n.dot(a).abs() > half.dot(n.abs()) {
        return false;
    }
    // The nine axes edge × box-axis.
    for edge in [b - a, c - b, a - c] {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let l = axis.cross(edge);
            let (pa, pb, pc) = (a.dot(l), b.dot(l), c.dot(l));
            let r = half.dot(l.abs());
            if pa.min(pb).min(pc) > r || pa.max(pb).max(pc) < -r {
                return false;
            }
        }
    }
    true
}

/// Up to `N` triangles in lane arrays, their coordinates in one ray's permuted axes: the input of
/// [`nearest_in_block`], where one ray meets many triangles at once (a grid cell's).
#[derive(Debug, Clone, Copy)]
pub struct TriangleBlock<const N: usize> {
    /// `p[vertex][axis][lane]`, axes in the order `kx, ky, kz`.
    p: [[[f32; N]; 3]; 3],
    /// Lanes holding a triangle.
    len: usize,
}

impl<const N: usize> TriangleBlock<N> {
    /// Gathers the `len ≤ N` triangles `vertices(0..len)` for `ray`.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn gather(ray: &WatertightRay, len: usize, vertices: impl Fn(usize) -> [Vec3; 3]) -> Self {
        debug_assert!(len <= N);
        let mut p = [[[0.0f32; N]; 3]; 3];
        let perm = ray.permutation();
        for i in 0..len {
            let tri = vertices(i);
            for (j, v) in tri.iter().enumerate() {
                for (c, &axis) in perm.iter().enumerate() {
                    p[j][c][i] = v[axis];
                }
            }
        }
        Self { p, len }
    }
}

/// The nearest hit within `(t_min, t_max)` among a block's triangles and its lane: what testing
/// them one by one in lane order with [`intersect`], each hit lowering the bound, finds (the
/// first of equally near ones). All lanes run the scalar test's operations lane-wise; a lane
/// with an edge function exactly 0 is decided by [`intersect`] itself.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
pub fn nearest_in_block<const N: usize>(
    block: &TriangleBlock<N>,
    ray: &WatertightRay,
    t_min: f32,
    t_max: f32,
    vertices: impl Fn(usize) -> [Vec3; 3],
) -> Option<(usize, TriangleHit)> {
    let o = ray.permutation().map(|axis| ray.origin[axis]);
    let (sx, sy, sz) = ray.shear_constants();
    let mut hit = [false; N];
    let mut exact = [false; N];
    let mut t_hit = [0.0f32; N];
    let mut det_hit = [0.0f32; N];
    let mut vw = [[0.0f32; N]; 2];
    let p = &block.p;
    for i in 0..N {
        // The scalar kernel's shear: `a = p − o`, then `(a_x − s_x·a_z, a_y − s_y·a_z, s_z·a_z)`.
        let shear = |j: usize| {
            let (ax, ay, az) = (p[j][0][i] - o[0], p[j][1][i] - o[1], p[j][2][i] - o[2]);
            (ax - sx * az, ay - sy * az, sz * az)
        };
        let (ax, ay, az) = shear(0);
        let (bx, by, bz) = shear(1);
        let (cx, cy, cz) = shear(2);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let e = bx * ay - by * ax;
        let live = i < block.len;
        exact[i] = live & ((u == 0.0) | (v == 0.0) | (e == 0.0));
        let outside = ((u < 0.0) | (v < 0.0) | (e < 0.0)) & ((u > 0.0) | (v > 0.0) | (e > 0.0));
        let det = u + v + e;
        let t = (u * az + v * bz + e * cz) / det;
        hit[i] = live & !exact[i] & !outside & (det != 0.0) & (t > t_min) & (t < t_max);
        t_hit[i] = t;
        det_hit[i] = det;
        vw[0][i] = v;
        vw[1][i] = e;
    }
    let mut best: Option<(usize, TriangleHit)> = None;
    let mut bound = t_max;
    for i in 0..block.len {
        if hit[i] {
            if t_hit[i] < bound {
                let det = det_hit[i];
                bound = t_hit[i];
                best = Some((i, TriangleHit { t: t_hit[i], u: vw[0][i] / det, v: vw[1][i] / det }));
            }
        } else if exact[i] {
            let [v0, v1, v2] = vertices(i);
            if let Some(h) = intersect(v0, v1, v2, ray, t_min, bound) {
                bound = h.t;
                best = Some((i, h));
            }
        }
    }
    best
}

/// Coordinate `k` (0, 1 or 2) of `v` by selection, not indexing, so that a lane-wise loop keeps
/// its lanes in vector registers.
#[inline(always)]
fn select(v: [f32; 3], k: u32) -> f32 {
    if k == 0 {
        v[0]
    } else if k == 1 {
        v[1]
    } else {
        v[2]
    }
}

/// A packet prepared for watertight triangle tests: each lane's axis permutation, origin in
/// its permuted axes and shear constants, and the permutation all live lanes share when they
/// do (the common case, which needs no per-lane selection of vertex coordinates).
#[derive(Debug, Clone, Copy)]
pub struct WatertightPacket<const N: usize> {
    /// The shared permutation `(kx, ky, kz)`, when there is one.
    common: Option<[usize; 3]>,
    /// Each lane's permutation, axis by axis (`0`, `1` or `2`).
    perm: [[u32; N]; 3],
    /// Origins in each lane's permuted axes.
    o: [[f32; N]; 3],
    sx: [f32; N],
    sy: [f32; N],
    sz: [f32; N],
}

impl<const N: usize> WatertightPacket<N> {
    /// The axis permutation all live lanes share, if they do (the kernel then reads the
    /// vertices' coordinates once for all lanes).
    pub fn common_permutation(&self) -> Option<[usize; 3]> {
        self.common
    }

    /// Prepares the `live` lanes of `packet`: lane for lane what [`WatertightRay::new`] gives
    /// (the same comparisons, NaN included, and the same divisions), worked out without a
    /// branch per lane so that the lanes share vector instructions; dead lanes get zeros.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn new(packet: &crate::math::RayPacket<N>, live: &[bool; N]) -> Self {
        let mut p = Self {
            common: None,
            perm: [[0; N]; 3],
            o: [[0.0; N]; 3],
            sx: [0.0; N],
            sy: [0.0; N],
            sz: [0.0; N],
        };
        let pick = select;
        // A lane's permutation is fixed by `kz` and the sign of `d_kz`: `2·kz + negative`.
        let mut code = [0u32; N];
        for i in 0..N {
            let d = [packet.dir[0][i], packet.dir[1][i], packet.dir[2][i]];
            let o = [packet.origin[0][i], packet.origin[1][i], packet.origin[2][i]];
            let a = d.map(f32::abs);
            // `WatertightRay::new`'s comparison chain as arithmetic on its two outcomes.
            let x_largest = (a[0] >= a[1]) & (a[0] >= a[2]);
            let y_over_z = a[1] >= a[2];
            let kz = u32::from(!x_largest) * (1 + u32::from(!y_over_z));
            let dz = pick(d, kz);
            let negative = dz < 0.0;
            // The next two axes in cyclic order, swapped when the z axis points backwards.
            let k1 = if kz == 2 { 0 } else { kz + 1 };
            let k2 = if k1 == 2 { 0 } else { k1 + 1 };
            let (kx, ky) = if negative { (k2, k1) } else { (k1, k2) };
            let (sx, sy, sz) = (pick(d, kx) / dz, pick(d, ky) / dz, 1.0 / dz);
            let on = live[i];
            let keep = |x: f32| if on { x } else { 0.0 };
            for (c, k) in [kx, ky, kz].into_iter().enumerate() {
                p.perm[c][i] = if on { k } else { 0 };
                p.o[c][i] = keep(pick(o, k));
            }
            (p.sx[i], p.sy[i], p.sz[i]) = (keep(sx), keep(sy), keep(sz));
            code[i] = 2 * kz + u32::from(negative);
        }
        if let Some(first) = live.iter().position(|&l| l) {
            let mut shared = true;
            for i in 0..N {
                shared &= !live[i] | (code[i] == code[first]);
            }
            if shared {
                p.common = Some([0, 1, 2].map(|c| p.perm[c][first] as usize));
            }
        }
        p
    }

    /// Lane `i`'s prepared ray, the scalar kernel's input for edge cases: rebuilt from the
    /// lane's permutation, permuted origin and shear constants, the very values
    /// [`WatertightRay::new`] gave (kept as lane arrays, not as sixteen copies of the ray,
    /// which a packet would build and copy for its rare edge hits).
    #[inline]
    fn ray(&self, i: usize) -> WatertightRay {
        let [kx, ky, kz] = [0, 1, 2].map(|c| self.perm[c][i] as usize);
        let mut origin = Vec3::ZERO;
        (origin[kx], origin[ky], origin[kz]) = (self.o[0][i], self.o[1][i], self.o[2][i]);
        WatertightRay { origin, kx, ky, kz, sx: self.sx[i], sy: self.sy[i], sz: self.sz[i] }
    }
}

/// Tests triangle `[v0, v1, v2]` against the `live` lanes, each within `(t_min, bound)`; a
/// lane it hits nearer gets `record(lane, hit)` and its bound moves. Bit for bit
/// [`intersect`] on every lane: lanes that share a permutation read the permuted
/// vertices once, lanes that do not each select their own coordinates.
#[inline(always)]
pub fn triangle_lanes<const N: usize>(
    [v0, v1, v2]: [Vec3; 3],
    w: &WatertightPacket<N>,
    live: &[bool; N],
    t_min: &[f32; N],
    bound: &mut [f32; N],
    record: impl FnMut(usize, TriangleHit),
) {
    match w.common {
        Some([kx, ky, kz]) => {
            // Arrays, not `Vec3` indexing (a `match` per coordinate).
            let p = [v0, v1, v2].map(|v| {
                let a = v.to_array();
                [a[kx], a[ky], a[kz]]
            });
            lanes_with([v0, v1, v2], w, live, t_min, bound, record, |j, _| p[j])
        }
        None => {
            let v = [v0, v1, v2];
            let pick = |a: Vec3, k: u32| select(a.to_array(), k);
            lanes_with(v, w, live, t_min, bound, record, |j, i| {
                [pick(v[j], w.perm[0][i]), pick(v[j], w.perm[1][i]), pick(v[j], w.perm[2][i])]
            })
        }
    }
}

/// [`triangle_lanes`] with vertex `j` in lane `i`'s permuted axes given by `permuted(j, i)`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
fn lanes_with<const N: usize>(
    [v0, v1, v2]: [Vec3; 3],
    w: &WatertightPacket<N>,
    live: &[bool; N],
    t_min: &[f32; N],
    bound: &mut [f32; N],
    mut record: impl FnMut(usize, TriangleHit),
    permuted: impl Fn(usize, usize) -> [f32; 3],
) {
    const { assert!(N <= 64, "lane masks are 64 bits") };
    // First the edge functions: most tests end here, with no lane inside the triangle, before
    // the division and before any per-lane branch.
    let mut uve = [[0.0f32; N]; 3];
    let mut z = [[0.0f32; N]; 3];
    let mut inside = 0u64;
    let mut exact = 0u64;
    for i in 0..N {
        // The scalar kernel's shear: `a = p − o`, then `(a_x − s_x·a_z, a_y − s_y·a_z, s_z·a_z)`.
        let shear = |q: [f32; 3]| {
            let (ax, ay, az) = (q[0] - w.o[0][i], q[1] - w.o[1][i], q[2] - w.o[2][i]);
            (ax - w.sx[i] * az, ay - w.sy[i] * az, w.sz[i] * az)
        };
        let (ax, ay, az) = shear(permuted(0, i));
        let (bx, by, bz) = shear(permuted(1, i));
        let (cx, cy, cz) = shear(permuted(2, i));
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let e = bx * ay - by * ax;
        let on_edge = live[i] & ((u == 0.0) | (v == 0.0) | (e == 0.0));
        let outside = ((u < 0.0) | (v < 0.0) | (e < 0.0)) & ((u > 0.0) | (v > 0.0) | (e > 0.0));
        inside |= u64::from(live[i] & !on_edge & !outside) << i;
        exact |= u64::from(on_edge) << i;
        (uve[0][i], uve[1][i], uve[2][i]) = (u, v, e);
        (z[0][i], z[1][i], z[2][i]) = (az, bz, cz);
    }
    if inside | exact == 0 {
        return;
    }
    let mut hit = 0u64;
    let mut t_hit = [0.0f32; N];
    let mut det_hit = [0.0f32; N];
    for i in 0..N {
        let (u, v, e) = (uve[0][i], uve[1][i], uve[2][i]);
        let det = u + v + e;
        let t = (u * z[0][i] + v * z[1][i] + e * z[2][i]) / det;
        let good = (inside >> i) & 1 == 1;
        hit |= u64::from(good & (det != 0.0) & (t > t_min[i]) & (t < bound[i])) << i;
        t_hit[i] = t;
        det_hit[i] = det;
    }
    // Lanes in increasing order, as the scalar loop would take them.
    let mut todo = hit | exact;
    while todo != 0 {
        let i = todo.trailing_zeros() as usize;
        todo &= todo - 1;
        if (hit >> i) & 1 == 1 {
            let det = det_hit[i];
            bound[i] = t_hit[i];
            record(i, TriangleHit { t: t_hit[i], u: uve[1][i] / det, v: uve[2][i] / det });
        } else {
            // On an edge in f32 (only live lanes are): the scalar kernel's f64 re-check and
            // tie-break decide.
            if let Some(h) = intersect(v0, v1, v2, &w.ray(i), t_min[i], bound[i]) {
                bound[i] = h.t;
                record(i, h);
            }
        }
    }
}

#[cfg(test)]
mod tests;
