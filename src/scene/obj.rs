//! Wavefront OBJ import: one file becomes one [`MeshData`] triangle mesh in object space.
//!
//! [`load_obj`] reads a file, [`parse_obj`] parses text already in memory. Every object and
//! group is merged into one mesh, polygons are triangulated as fans, and points (`p`, one-vertex
//! faces are an error though) and lines (`l`) are ignored. With `smooth`, per-vertex normals
//! come from the file's `vn` records when every face vertex names one, otherwise from
//! [`vertex_normals`]; without it `normals` is empty (flat facets). Texture coordinates fill
//! `uvs` when every face vertex names a `vt` (`v/vt`, `v/vt/vn`), and are left empty when none
//! does. Materials are ignored, except by [`load_obj_with_materials`], which also reads the
//! `.mtl` libraries the file names (rules in [`mtl`](super::mtl)).
//!
//! Parsing is done by [`tobj`] after an own pass over the text that checks every record tobj
//! would read, so that every problem is reported with the 1-based line it is on (tobj's errors
//! carry no position), and so that input tobj silently misreads is rejected or fixed first:
//!
//! ```text
//! scenes/bad.obj:12: face index 9 is out of range: only 8 vertices (`v`) come before this line
//! ```
//!
//! The rules: `v` takes three finite numbers within ±1e18 (`rules::MAX_COORDINATE`),
//! optionally followed by a weight `w` (tobj divides by it; the result obeys the same rule) or
//! by an `r g b` colour (dropped); `vn` takes three finite numbers and `vt` one to three finite
//! numbers (`u [v [w]]`: v defaults to 0, w is dropped); a face `f` takes at least three
//! vertices `v`, `v/vt`, `v//vn` or `v/vt/vn`, whose indices are 1-based, or negative to count
//! back from the last record read so far (`-1` is the last), and must refer to a record that
//! comes before the face; `0` is never an index. Either every face vertex names a `vt` or none
//! does: otherwise the error is at the first face with a vertex that names none. A file with no
//! face at all is an error ("contains no triangles").

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use crate::geom::mesh::{vertex_normals, MeshData};
use crate::math::{Vec2, Vec3};
use crate::scene::error::{escaped_path, one_line, shown, MAX_LINE_CHARS};
use crate::scene::mtl::{assign_materials, MtlError, MtlFile, MtlLib, UseMtl};
use crate::scene::rules::{coordinate_rule, MAX_COORDINATE};

/// Why an OBJ mesh could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file could not be read.
    #[error("{}: cannot read mesh: {source}", escaped_path(path))]
    Io {
        /// The path as given.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The text is malformed or holds no triangles.
    #[error("{}:{line}: {}", escaped_path(path), one_line(rule, MAX_LINE_CHARS))]
    Invalid {
        /// The path as given (for [`parse_obj`], whatever names the text).
        path: PathBuf,
        /// 1-based line of the offending record; for a mesh without triangles, the last line.
        line: usize,
        /// What is wrong, e.g. `face index 0 is invalid: OBJ indices start at 1`.
        rule: String,
    },
}

impl From<MtlError> for ObjError {
    /// A `.mtl`, `mtllib` or `usemtl` problem, as [`ObjError::Invalid`] at its file and line.
    fn from(e: MtlError) -> Self {
        ObjError::Invalid { path: e.path, line: e.line, rule: e.rule }
    }
}

/// Loads a Wavefront OBJ file as one triangle mesh (see the [module docs](self) for the rules).
///
/// Bytes that are not UTF-8 are replaced (they can only matter in comments and names: anywhere
/// else they make a malformed number).
///
/// # Examples
/// ```
/// # use penumbra::scene::obj::load_obj;
/// let bunny = load_obj("scenes/bunny_res3.obj".as_ref(), true)?;
/// assert_eq!(bunny.triangle_count(), 4500);
/// assert_eq!(bunny.normals.len(), bunny.positions.len());
/// # Ok::<(), penumbra::scene::obj::ObjError>(())
/// ```
pub fn load_obj(path: &Path, smooth: bool) -> Result<MeshData, ObjError> {
    let bytes = std::fs::read(path).map_err(|source| ObjError::Io { path: path.to_path_buf(), source })?;
    parse_obj(&String::from_utf8_lossy(&bytes), path, smooth)
}

/// Parses OBJ text already in memory as one triangle mesh; `path` only names it in errors.
///
/// # Examples
/// ```
/// # use penumbra::scene::obj::parse_obj;
/// let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
/// let quad = parse_obj(text, "quad.obj".as_ref(), false)?;
/// assert_eq!(quad.indices, vec![[0, 1, 2], [0, 2, 3]]);
/// assert!(quad.normals.is_empty());
///
/// let err = parse_obj("v 0 0 0\nf 1 2 3\n", "bad.obj".as_ref(), false).unwrap_err();
/// assert!(err.to_string().starts_with("bad.obj:2: face index 2 is out of range"));
/// # Ok::<(), penumbra::scene::obj::ObjError>(())
/// ```
pub fn parse_obj(text: &str, path: &Path, smooth: bool) -> Result<MeshData, ObjError> {
    parse_scanned(text, path, smooth).map(|(mesh, _)| mesh)
}

/// Loads an OBJ file like [`load_obj`], with the materials of the `.mtl` libraries it names
/// (see [`mtl`](super::mtl) for the rules) in `materials` and `face_material`, and every `.mtl`
/// file read. Faces before any `usemtl` get a default material named `""`; a mesh that selects
/// no material has both vectors empty.
///
/// # Examples
/// ```
/// # use penumbra::scene::obj::load_obj_with_materials;
/// # let dir = tempfile::tempdir()?;
/// # std::fs::write(dir.path().join("room.mtl"), "newmtl wall\nKd 0.8 0.8 0.7\n")?;
/// # let obj = "mtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wall\nf 1 2 3\n";
/// # std::fs::write(dir.path().join("room.obj"), obj)?;
/// let (mesh, files) = load_obj_with_materials(&dir.path().join("room.obj"), false)?;
/// assert_eq!(mesh.materials[0].name, "wall");
/// assert_eq!(mesh.face_material, vec![0]);
/// assert_eq!(files[0].path, dir.path().join("room.mtl"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_obj_with_materials(path: &Path, smooth: bool) -> Result<(MeshData, Vec<MtlFile>), ObjError> {
    let bytes = std::fs::read(path).map_err(|source| ObjError::Io { path: path.to_path_buf(), source })?;
    let (mut mesh, scan) = parse_scanned(&String::from_utf8_lossy(&bytes), path, smooth)?;
    let assigned = assign_materials(path, &scan.libraries, &scan.uses, mesh.triangle_count())?;
    mesh.materials = assigned.materials;
    mesh.face_material = assigned.face_material;
    Ok((mesh, assigned.files))
}

/// [`parse_obj`], also giving what the scan learned (for the materials).
fn parse_scanned(text: &str, path: &Path, smooth: bool) -> Result<(MeshData, Scan), ObjError> {
    let invalid = |line: usize, rule: String| ObjError::Invalid { path: path.to_path_buf(), line, rule };

    // Check every record with its line number before tobj sees the text.
    let scan = scan(text).map_err(|e| invalid(e.line, e.rule))?;
    let last_line = scan.lines.max(1);
    if scan.triangles == 0 {
        return Err(invalid(last_line, "contains no triangles (no `f` record)".into()));
    }
    let source = if scan.needs_cleaning { Cow::Owned(clean(text)) } else { Cow::Borrowed(text) };

    // Parse: one tobj model per object, group or material run.
    let options = load_options();
    let (models, _materials) =
        tobj::load_obj_buf(&mut source.as_bytes(), &options, |_| Err(tobj::LoadError::OpenFileFailed))
            // The scan accepts only what tobj reads without error, so this is not expected.
            .map_err(|e| invalid(last_line, format!("the OBJ reader (tobj) rejected the file: {e}")))?;

    // Merge the models into one mesh.
    let vertex_count: usize = models.iter().map(|m| m.mesh.positions.len() / 3).sum();
    if u32::try_from(vertex_count).is_err() {
        return Err(invalid(last_line, format!("{vertex_count} vertices do not fit 32-bit indices")));
    }
    let mut mesh = MeshData {
        positions: Vec::with_capacity(vertex_count),
        indices: Vec::with_capacity(scan.triangles),
        ..MeshData::default()
    };
    let mut file_normals = Vec::new();
    let mut all_have_normals = scan.every_face_vertex_has_normal;
    for model in &models {
        // Checked above: the running vertex count fits in u32.
        let offset = mesh.positions.len() as u32;
        let m = &model.mesh;
        mesh.positions.extend(m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])));
        mesh.indices.extend(m.indices.chunks_exact(3).map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]));
        all_have_normals &= m.normals.len() == m.positions.len();
        if smooth && all_have_normals {
            file_normals.extend(m.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2])));
        }
        if scan.texcoords {
            // The scan saw a `vt` at every face vertex, so tobj gave every vertex one.
            if m.texcoords.len() / 2 != m.positions.len() / 3 {
                return Err(invalid(last_line, "the OBJ reader (tobj) lost texture coordinates".into()));
            }
            mesh.uvs.extend(m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], t[1])));
        }
    }
    mesh.update_bounds();

    // Shading normals: the file's, unit length, or computed.
    if smooth {
        mesh.normals = if all_have_normals {
            let mut computed: Option<Vec<Vec3>> = None;
            let mut normals = file_normals;
            for (i, n) in normals.iter_mut().enumerate() {
                if let Some(unit) = n.try_normalize() {
                    *n = unit;
                } else {
                    // A zero `vn`: use the computed normal for that vertex.
                    *n = computed.get_or_insert_with(|| vertex_normals(&mesh.positions, &mesh.indices))[i];
                }
            }
            normals
        } else {
            vertex_normals(&mesh.positions, &mesh.indices)
        };
    }
    Ok((mesh, scan))
}

/// A problem found by [`scan`]: 1-based line and rule.
#[derive(Debug)]
struct ScanError {
    line: usize,
    rule: String,
}

/// What [`scan`] learned about text it accepted.
#[derive(Debug, Default)]
struct Scan {
    /// Number of lines.
    lines: usize,
    /// Triangles after fan triangulation.
    triangles: usize,
    /// True when every face vertex names a normal (`v//vn` or `v/vt/vn`).
    every_face_vertex_has_normal: bool,
    /// True when some record must be cleaned before tobj reads it (see [`clean`]).
    needs_cleaning: bool,
    /// True when every face vertex names a texture coordinate (and there is a face).
    texcoords: bool,
    /// The `mtllib` records, in file order.
    libraries: Vec<MtlLib>,
    /// The `usemtl` records, in file order.
    uses: Vec<UseMtl>,
}

/// Records counted so far, for resolving and checking face indices.
#[derive(Debug, Default)]
struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
}

/// Checks every record tobj reads, in file order, and counts triangles.
///
/// Lines split like tobj's (`\n`, with a trailing `\r` dropped), words on whitespace.
fn scan(text: &str) -> Result<Scan, ScanError> {
    let mut scan = Scan { every_face_vertex_has_normal: true, ..Scan::default() };
    let mut counts = Counts::default();
    // The lines of the first face with and without a `vt` at some vertex.
    let (mut with_vt, mut without_vt) = (None, None);
    for (i, line) in text.lines().enumerate() {
        let at = |rule: String| ScanError { line: i + 1, rule };
        scan.lines = i + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut p = [0.0; 3];
                for (axis, c) in p.iter_mut().enumerate() {
                    let word =
                        words.next().ok_or_else(|| at(format!("`v` needs 3 coordinates, got {axis}")))?;
                    *c = number(word, "v").map_err(at)?;
                    if !c.is_finite() {
                        return Err(at(format!("non-finite coordinate `{word}` in `v` record")));
                    }
                    if c.abs() > MAX_COORDINATE {
                        return Err(at(format!("coordinate `{word}` in `v` record {}", coordinate_rule())));
                    }
                }
                let extra: Vec<&str> = words.collect();
                match extra.len() {
                    0 => {}
                    1 => {
                        let w = number(extra[0], "v").map_err(at)?;
                        if w == 0.0
                            || !p.iter().all(|c| (c / w).is_finite() && (c / w).abs() <= MAX_COORDINATE)
                        {
                            return Err(at(format!(
                                "`v` weight w = {} makes the position non-finite or beyond ±{MAX_COORDINATE:e}",
                                extra[0]
                            )));
                        }
                    }
                    // An `r g b` colour: dropped by `clean`, so its words need not be numbers.
                    3 => scan.needs_cleaning = true,
                    n => {
                        return Err(at(format!(
                            "`v` takes x y z, then optionally w or r g b; got {} values",
                            3 + n
                        )))
                    }
                }
                counts.v += 1;
            }
            Some("vt") => {
                let values: Vec<&str> = words.collect();
                if !(1..=3).contains(&values.len()) {
                    return Err(at(format!(
                        "`vt` takes u, then optionally v and w; got {} values",
                        values.len()
                    )));
                }
                for word in &values {
                    if !number(word, "vt").map_err(at)?.is_finite() {
                        return Err(at(format!("non-finite component `{word}` in `vt` record")));
                    }
                }
                // tobj needs u and v: `clean` adds v = 0.
                scan.needs_cleaning |= values.len() == 1;
                counts.vt += 1;
            }
            Some("vn") => {
                for k in 0..3 {
                    let word = words.next().ok_or_else(|| at(format!("`vn` needs 3 numbers, got {k}")))?;
                    if !number(word, "vn").map_err(at)?.is_finite() {
                        return Err(at(format!("non-finite component `{word}` in `vn` record")));
                    }
                }
                counts.vn += 1;
            }
            Some("f") => {
                let mut corners = 0;
                for word in words {
                    let (has_texcoord, has_normal) = face_vertex(word, &counts).map_err(at)?;
                    scan.every_face_vertex_has_normal &= has_normal;
                    if has_texcoord { &mut with_vt } else { &mut without_vt }.get_or_insert(i + 1);
                    corners += 1;
                }
                if corners < 3 {
                    return Err(at(format!("face has {corners} vertices; a face needs at least 3")));
                }
                scan.triangles += corners - 2;
                match (with_vt, without_vt) {
                    (Some(with), Some(without)) if with == without => {
                        return Err(at("face has vertices with and without a texture coordinate (`vt`); \
                                       give every face vertex a `vt` or none"
                            .into()))
                    }
                    (Some(with), Some(without)) => {
                        return Err(ScanError {
                            line: without,
                            rule: format!(
                                "face has vertices without a texture coordinate (`vt`) but the face on \
                                 line {with} has them; give every face vertex a `vt` or none"
                            ),
                        })
                    }
                    _ => {}
                }
            }
            // tobj reads `l` like `f` (so a three-point line would become a triangle) and fails on
            // a `usemtl` without a name: `clean` blanks such lines, they mean nothing to us.
            Some("l") => scan.needs_cleaning = true,
            Some("usemtl") => {
                scan.needs_cleaning |= usemtl_name(line).is_empty();
                // The name as the materials read it: the rest of the line after the keyword.
                let name = line.trim_start().strip_prefix("usemtl").map_or("", str::trim).to_owned();
                scan.uses.push(UseMtl { line: i + 1, name, first_triangle: scan.triangles });
            }
            Some("mtllib") => {
                scan.libraries.push(MtlLib { line: i + 1, names: words.map(str::to_owned).collect() })
            }
            _ => {}
        }
    }
    scan.texcoords = with_vt.is_some();
    Ok(scan)
}

/// A number in a record of kind `record`, or the rule it breaks.
fn number(word: &str, record: &str) -> Result<f32, String> {
    word.parse().map_err(|_| format!("malformed number `{}` in `{record}` record", shown(word)))
}

/// Checks one face vertex `v[/vt][/vn]`; whether it names a texture coordinate and a normal.
fn face_vertex(word: &str, counts: &Counts) -> Result<(bool, bool), String> {
    let mut parts = word.split('/');
    let kinds = [
        ("face index", "vertices (`v`)", counts.v),
        ("face texture coordinate index", "texture coordinates (`vt`)", counts.vt),
        ("face normal index", "normals (`vn`)", counts.vn),
    ];
    let mut named = [false; 3];
    for (k, (label, records, count)) in kinds.into_iter().enumerate() {
        let Some(part) = parts.next() else { break };
        if part.is_empty() {
            if k == 0 {
                return Err(format!("face vertex `{}` has no position index", shown(word)));
            }
            continue;
        }
        let index: isize = part
            .parse()
            .map_err(|_| format!("malformed face index `{}` in `{}`", shown(part), shown(word)))?;
        if index == 0 {
            return Err(format!(
                "{label} 0 is invalid: OBJ indices start at 1 (negative ones count back from the last record)"
            ));
        }
        if index.unsigned_abs() > count {
            return Err(format!(
                "{label} {index} is out of range: only {count} {records} come before this line"
            ));
        }
        named[k] = true;
    }
    if parts.any(|extra| !extra.is_empty()) {
        return Err(format!("face vertex `{}` has more than 3 indices (v/vt/vn)", shown(word)));
    }
    Ok((named[1], named[2]))
}

/// The material name of a `usemtl` line exactly as tobj finds it: after the first space.
fn usemtl_name(line: &str) -> &str {
    line.split_once(' ').map_or("", |(_, name)| name.trim())
}

/// The text with records tobj would misread made harmless, line for line (so tobj's line
/// structure, and any line number, stays the same): `l` lines and nameless `usemtl` lines
/// become empty, `v` records lose their `r g b` colour (tobj fails when only some vertices
/// have one), and `vt u` becomes `vt u 0` (tobj needs two numbers).
fn clean(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("l") => {}
            Some("usemtl") if usemtl_name(line).is_empty() => {}
            Some("v") => {
                let values: Vec<&str> = words.collect();
                if values.len() == 6 {
                    out.push_str("v ");
                    out.push_str(&values[..3].join(" "));
                } else {
                    out.push_str(line);
                }
            }
            Some("vt") => {
                let values: Vec<&str> = words.collect();
                if let [u] = values[..] {
                    out.push_str("vt ");
                    out.push_str(u);
                    out.push_str(" 0");
                } else {
                    out.push_str(line);
                }
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out
}

/// The `tobj` options the loader uses: one index per vertex (file normals line up with
/// positions), polygons triangulated, points and lines ignored.
pub fn load_options() -> tobj::LoadOptions {
    #[allow(clippy::needless_update, reason = "tobj's `merging` and `reordering` features add fields")]
    tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests;
