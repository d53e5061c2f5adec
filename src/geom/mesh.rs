//! Indexed triangle meshes in object space: the [`MeshData`] arrays a file loader fills
//! (see `scene::obj`), the [`ObjMaterial`]s an OBJ's `.mtl` libraries define, smooth
//! per-vertex normals for meshes that come without any ([`vertex_normals`]), and a watertight
//! [`icosphere`] for tests and benchmarks.
//!
//! Indices are `u32` triples into `positions`, counter-clockwise seen from the front, so the
//! right-hand normal `(v1 − v0) × (v2 − v0)` points out of the surface.

use std::collections::HashMap;

use std::path::PathBuf;

use crate::math::{Aabb, Vec2, Vec3};

/// The normal [`vertex_normals`] gives a vertex that no usable (non-degenerate, finite) face
/// touches: +Y, an arbitrary but finite unit vector.
pub const FALLBACK_NORMAL: Vec3 = Vec3::Y;

/// The most subdivisions [`icosphere`] performs (20 · 4^10 ≈ 21 million triangles).
pub const MAX_ICOSPHERE_SUBDIVISIONS: u32 = 10;

/// An indexed triangle mesh in object space, as loaded from a file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit per-vertex shading normals, same indexing as `positions`; empty for flat facets.
    pub normals: Vec<Vec3>,
    /// Triangles as indices into `positions` (counter-clockwise seen from the front).
    pub indices: Vec<[u32; 3]>,
    /// Bounds of the positions used by faces.
    pub bounds: Aabb,
    /// Per-vertex texture coordinates `(u, v)` as the file gives them (OBJ `vt`, v up), same
    /// indexing as `positions`; empty when the mesh has none.
    pub uvs: Vec<Vec2>,
    /// Per triangle, an index into `materials`; empty when the mesh uses no materials.
    pub face_material: Vec<u32>,
    /// The materials `face_material` indexes; empty when the mesh uses no materials.
    pub materials: Vec<ObjMaterial>,
}

/// A material read from an OBJ's `.mtl` library, as the file gives it (unset statements are None).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObjMaterial {
    /// The `newmtl` name (`""` for the default material of faces without a `usemtl`).
    pub name: String,
    /// `Kd`: diffuse colour.
    pub kd: Option<Vec3>,
    /// `Ks`: specular colour.
    pub ks: Option<Vec3>,
    /// `Ns`: specular exponent.
    pub ns: Option<f32>,
    /// `d` (dissolve, 1 = opaque); `Tr` is read as 1 − Tr.
    pub d: Option<f32>,
    /// `Ni`: index of refraction.
    pub ni: Option<f32>,
    /// `map_Kd`, as written in the .mtl (relative to the .mtl's folder unless absolute).
    pub map_kd: Option<PathBuf>,
    /// `map_bump` / `bump`, as written (relative to the .mtl's folder unless absolute).
    pub map_bump: Option<PathBuf>,
    /// The `-bm` multiplier of `map_bump` / `bump` (None when absent).
    pub bump_multiplier: Option<f32>,
    /// The .mtl file it came from (as resolved: the OBJ's folder joined with the `mtllib` name);
    /// empty for the default material.
    pub file: PathBuf,
    /// 1-based line of its `newmtl` in `file`; 0 for the default material.
    pub line: usize,
}

impl MeshData {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Bytes held by the arrays (their lengths, not their capacities; for `materials` the
    /// structs only, not the names and paths they point to).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(self.positions.as_slice())
            + std::mem::size_of_val(self.normals.as_slice())
            + std::mem::size_of_val(self.indices.as_slice())
            + std::mem::size_of_val(self.uvs.as_slice())
            + std::mem::size_of_val(self.face_material.as_slice())
            + std::mem::size_of_val(self.materials.as_slice())
    }

    /// Recomputes `bounds` from the positions that faces use; [`Aabb::EMPTY`] without faces.
    /// Indices past the end of `positions` are skipped.
    pub fn update_bounds(&mut self) {
        let positions = &self.positions;
        self.bounds = Aabb::from_points(
            self.indices.iter().flatten().filter_map(|&i| positions.get(i as usize).copied()),
        );
    }
}

/// Smooth per-vertex normals: each face's unit normal weighted by its area and by its angle at
/// the vertex, summed over the faces around the vertex and normalised.
///
/// Vertices at exactly the same position (`-0.0` and `0.0` count as equal) are welded for the
/// sum, so a mesh made of unwelded patches (the Utah teapot) shades without seams: welded
/// vertices get identical normals. Zero-area faces, faces with non-finite corners and faces with
/// an index past the end of `positions` contribute nothing. A vertex that no usable face touches
/// gets [`FALLBACK_NORMAL`]. Every returned normal is finite and unit length. The result is
/// deterministic (serial sums in face order).
///
/// # Examples
/// ```
/// # use penumbra::geom::mesh::vertex_normals;
/// # use penumbra::math::Vec3;
/// let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
/// let normals = vertex_normals(&positions, &[[0, 1, 2]]);
/// assert_eq!(normals, vec![Vec3::Z; 3]);
/// ```
pub fn vertex_normals(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    // Area × angle weighted face normals, accumulated per (unwelded) vertex.
    let mut sums = vec![Vec3::ZERO; positions.len()];
    for &[i0, i1, i2] in indices {
        let (Some(&a), Some(&b), Some(&c)) =
            (positions.get(i0 as usize), positions.get(i1 as usize), positions.get(i2 as usize))
        else {
            continue;
        };
        let (ab, ac, bc) = (b - a, c - a, c - b);
        // |cross| is twice the area, and it is also |u × v| for the edge pair at every corner,
        // so each corner angle is atan2(|cross|, u · v): accurate for thin and obtuse corners.
        let cross = ab.cross(ac);
        let twice_area = cross.length();
        if !(twice_area > 0.0 && twice_area.is_finite()) {
            continue;
        }
        // unit normal × area = cross / 2.
        let area_normal = cross * 0.5;
        let angle_a = twice_area.atan2(ab.dot(ac));
        let angle_b = twice_area.atan2(-ab.dot(bc));
        let angle_c = twice_area.atan2(ac.dot(bc));
        sums[i0 as usize] += area_normal * angle_a;
        sums[i1 as usize] += area_normal * angle_b;
        sums[i2 as usize] += area_normal * angle_c;
    }

    // Weld: sort vertices by position and give every run of equal positions its summed normal.
    let mut order: Vec<([u32; 3], u32)> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // `+ 0.0` turns -0.0 into 0.0 so the two weld; i fits in u32 for any index-addressable mesh.
            let key = [(p.x + 0.0).to_bits(), (p.y + 0.0).to_bits(), (p.z + 0.0).to_bits()];
            (key, i as u32)
        })
        .collect();
    order.sort_unstable();
    let mut normals = vec![FALLBACK_NORMAL; positions.len()];
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        let sum: Vec3 = run.iter().map(|&(_, i)| sums[i as usize]).sum();
        let n = sum.normalize_or(FALLBACK_NORMAL);
        for &(_, i) in run {
            normals[i as usize] = n;
        }
    }
    normals
}

/// A closed, watertight sphere mesh: a subdivided icosahedron with `20 · 4^subdivisions`
/// triangles, centred at `centre` with radius `radius`.
///
/// Vertices are shared (every edge is used by exactly two triangles, once in each direction),
/// faces wind counter-clockwise seen from outside and the normals are the exact sphere normals
/// at the vertices; it has no texture coordinates or materials. `subdivisions` above
/// [`MAX_ICOSPHERE_SUBDIVISIONS`] are clamped to it.
///
/// # Examples
/// ```
/// # use penumbra::geom::mesh::icosphere;
/// # use penumbra::math::Vec3;
/// let sphere = icosphere(Vec3::ZERO, 2.0, 2);
/// assert_eq!(sphere.triangle_count(), 320);
/// assert_eq!(sphere.positions.len(), 162);
/// ```
pub fn icosphere(centre: Vec3, radius: f32, subdivisions: u32) -> MeshData {
    // Icosahedron: the three golden rectangles, faces counter-clockwise from outside.
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut dirs: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .into_iter()
    .map(|p| Vec3::from_array(p).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];

    // Subdivide: split every triangle into four through its edge midpoints, one shared midpoint
    // vertex per edge (looked up by the sorted index pair), projected onto the unit sphere.
    for _ in 0..subdivisions.min(MAX_ICOSPHERE_SUBDIVISIONS) {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 3 / 2);
        let mut midpoint = |a: u32, b: u32, dirs: &mut Vec<Vec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let m = (dirs[a as usize] + dirs[b as usize]).normalize();
                dirs.push(m);
                // At most 10 · 4^10 + 2 ≈ 10.5 million vertices: fits in u32.
                (dirs.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = midpoint(a, b, &mut dirs);
            let bc = midpoint(b, c, &mut dirs);
            let ca = midpoint(c, a, &mut dirs);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }

    let positions = dirs.iter().map(|&d| centre + d * radius).collect();
    let mut mesh = MeshData { positions, normals: dirs, indices: faces, ..MeshData::default() };
    mesh.update_bounds();
    mesh
}

#[cfg(test)]
mod tests {
    use std::f32::consts::FRAC_PI_2;

    use super::*;

    fn assert_unit_and_finite(normals: &[Vec3]) {
        for n in normals {
            assert!(n.is_finite(), "non-finite normal {n}");
            assert!((n.length() - 1.0).abs() < 1e-5, "normal {n} is not unit length");
        }
    }

    #[test]
    fn cube_corner_normals_are_the_area_times_angle_weighted_sum() {
        // Three faces of a box corner at the origin seen from outside (-x, -y, -z), with
        // different areas (1.5, 3, 1) so the weighting matters.
        let positions =
            [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 3.0)];
        let (o, a, b, c) = (0, 1, 2, 3);
        let indices = [[o, b, a], [o, c, b], [o, a, c]];
        let normals = vertex_normals(&positions, &indices);
        assert_unit_and_finite(&normals);

        // At the corner all angles are 90°: the areas alone decide.
        let at_o = (Vec3::NEG_Z * 1.0 + Vec3::NEG_X * 1.5 + Vec3::NEG_Y * 3.0) * FRAC_PI_2;
        assert!(normals[o as usize].abs_diff_eq(at_o.normalize(), 1e-6), "{}", normals[o as usize]);

        // At A = (2,0,0): face OBA (area 1, normal -z) has angle atan(1/2) there, face OAC
        // (area 3, normal -y) has angle atan(3/2).
        let at_a = Vec3::NEG_Z * 1.0 * 0.5f32.atan() + Vec3::NEG_Y * 3.0 * 1.5f32.atan();
        assert!(normals[a as usize].abs_diff_eq(at_a.normalize(), 1e-6), "{}", normals[a as usize]);
        // Area-only or angle-only weighting would give something else.
        assert!(!normals[a as usize].abs_diff_eq(Vec3::new(0.0, -3.0, -1.0).normalize(), 1e-3));
        assert!(!normals[a as usize]
            .abs_diff_eq(Vec3::new(0.0, -1.5f32.atan(), -0.5f32.atan()).normalize(), 1e-3));

        // At C = (0,0,3): face OCB (area 1.5, normal -x) has angle atan(1/3), face OAC (area 3,
        // normal -y) has angle atan(2/3).
        let at_c = Vec3::NEG_X * 1.5 * (1.0f32 / 3.0).atan() + Vec3::NEG_Y * 3.0 * (2.0f32 / 3.0).atan();
        assert!(normals[c as usize].abs_diff_eq(at_c.normalize(), 1e-6), "{}", normals[c as usize]);
    }

    #[test]
    fn coincident_unwelded_vertices_get_identical_normals() {
        // Two triangles meeting at a crease along x = 0, with their own copies of the shared edge.
        let positions = [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            // Second patch: same edge as vertices 1 and 2 (one with -0.0), then its own apex.
            Vec3::new(-0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let indices = [[0, 1, 2], [3, 5, 4]];
        let normals = vertex_normals(&positions, &indices);
        assert_unit_and_finite(&normals);
        assert_eq!(normals[1], normals[3]);
        assert_eq!(normals[2], normals[4]);
        // The welded edge normal lies between the two face normals.
        let n0 = (positions[1] - positions[0]).cross(positions[2] - positions[0]).normalize();
        let n1 = (positions[5] - positions[3]).cross(positions[4] - positions[3]).normalize();
        assert!(normals[1].dot(n0) > 0.5 && normals[1].dot(n1) > 0.5);
        assert!(normals[1].dot(n0) < 0.9999 && normals[1].dot(n1) < 0.9999);
    }

    #[test]
    fn degenerate_faces_give_finite_normals() {
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(2.0, 0.0, 0.0), // collinear with the first two
            Vec3::new(5.0, 5.0, 5.0), // only in a face with repeated indices
            Vec3::new(9.0, 9.0, 9.0), // in no face at all
            Vec3::Y,
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
        ];
        let indices = [[0, 1, 2], [3, 3, 3], [0, 1, 5], [0, 6, 1], [7, 1, 5], [0, 1, 99]];
        let normals = vertex_normals(&positions, &indices);
        assert_eq!(normals.len(), positions.len());
        assert_unit_and_finite(&normals);
        // The one usable face decides vertices 0, 1 and 5; the others fall back.
        assert_eq!(normals[0], Vec3::Z);
        assert_eq!(normals[5], Vec3::Z);
        assert_eq!(normals[2], FALLBACK_NORMAL);
        assert_eq!(normals[3], FALLBACK_NORMAL);
        assert_eq!(normals[4], FALLBACK_NORMAL);
        assert!(vertex_normals(&[], &[]).is_empty());
    }

    #[test]
    fn icosphere_is_closed_outward_and_on_the_sphere() {
        let centre = Vec3::new(1.0, -2.0, 3.0);
        for s in 0..4 {
            let mesh = icosphere(centre, 2.5, s);
            assert_eq!(mesh.triangle_count(), 20 * 4usize.pow(s));
            // Euler: V - E + F = 2 with E = 3F/2.
            assert_eq!(mesh.positions.len(), 2 + mesh.triangle_count() / 2);
            assert_eq!(mesh.normals.len(), mesh.positions.len());
            assert!(mesh.uvs.is_empty() && mesh.face_material.is_empty() && mesh.materials.is_empty());
            assert_unit_and_finite(&mesh.normals);
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                assert!(((*p - centre).length() - 2.5).abs() < 1e-5);
                assert!((*p - centre).normalize().abs_diff_eq(*n, 1e-5));
            }
            // Watertight: every directed edge appears once and its reverse once.
            let mut edges = HashMap::new();
            for &[a, b, c] in &mesh.indices {
                for e in [(a, b), (b, c), (c, a)] {
                    *edges.entry(e).or_insert(0) += 1;
                }
            }
            assert!(edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)));
            // Counter-clockwise from outside: every face normal points away from the centre.
            let mut volume = 0.0;
            for &[a, b, c] in &mesh.indices {
                let [pa, pb, pc] = [a, b, c].map(|i| mesh.positions[i as usize] - centre);
                let n = (pb - pa).cross(pc - pa);
                assert!(n.dot(pa + pb + pc) > 0.0);
                volume += pa.dot(pb.cross(pc)) / 6.0;
            }
            let sphere = 4.0 / 3.0 * std::f32::consts::PI * 2.5f32.powi(3);
            assert!(volume > 0.0 && volume <= sphere);
            // Every vertex is used, and all lie within the sphere's box.
            assert_eq!(mesh.bounds, Aabb::from_points(mesh.positions.iter().copied()));
            assert!(mesh.bounds.min.cmpge(centre - 2.5 - 1e-5).all());
            assert!(mesh.bounds.max.cmple(centre + 2.5 + 1e-5).all());
        }
    }

    #[test]
    fn icosphere_vertex_normals_approach_the_sphere_normals() {
        let mesh = icosphere(Vec3::ZERO, 1.0, 3);
        let smooth = vertex_normals(&mesh.positions, &mesh.indices);
        for (n, exact) in smooth.iter().zip(&mesh.normals) {
            assert!(n.dot(*exact) > 0.999, "{n} vs {exact}");
        }
    }

    #[test]
    fn accounting_and_bounds() {
        let mut mesh = MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::splat(100.0)],
            normals: vec![],
            indices: vec![[0, 1, 2]],
            bounds: Aabb::EMPTY,
            uvs: vec![],
            face_material: vec![],
            materials: vec![],
        };
        assert_eq!(mesh.triangle_count(), 1);
        assert_eq!(mesh.memory_bytes(), 4 * 12 + 12);
        // Texture coordinates, face materials and material structs count too.
        mesh.uvs = vec![Vec2::ZERO; 4];
        mesh.face_material = vec![0];
        mesh.materials = vec![ObjMaterial::default()];
        let material = std::mem::size_of::<ObjMaterial>();
        assert_eq!(mesh.memory_bytes(), 4 * 12 + 12 + 4 * 8 + 4 + material);
        mesh.update_bounds();
        // The unused vertex at (100, 100, 100) is not in the bounds.
        assert_eq!(mesh.bounds, Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
        mesh.indices.clear();
        mesh.update_bounds();
        assert!(mesh.bounds.is_empty());
    }
}
