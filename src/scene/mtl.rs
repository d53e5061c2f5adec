//! Wavefront MTL material libraries: the `.mtl` files an OBJ names with `mtllib`, parsed with
//! line numbers into [`ObjMaterial`]s, and the per-triangle material indices its `usemtl`
//! records give (for [`load_obj_with_materials`](super::obj::load_obj_with_materials)).
//!
//! [`parse_mtl`] reads one library. Every problem is an [`MtlError`] naming the file and its
//! 1-based line, the `.mtl` for a bad statement and the OBJ for a bad `mtllib` or `usemtl`:
//!
//! ```text
//! scenes/room.mtl:7: Kd needs three numbers, got "0.5 x"
//! scenes/room.obj:12: usemtl `paint` names no material in room.mtl
//! ```
//!
//! Statements read (keywords in any letter case; the rest of the line holds the arguments):
//! - `newmtl name` starts a material; the name is the rest of the line (it may hold spaces),
//!   must not be empty and must be new across every library of the OBJ;
//! - `Kd r g b`, `Ks r g b`: three finite numbers; `Ns`, `d`, `Ni`: one finite number; `Tr t`
//!   sets `d = 1 − t` (of `d` and `Tr` the later wins, as does a repeated statement);
//! - `map_Kd [options] file`, `map_bump` / `bump [options] file`: the file is the rest of the
//!   line after the options, kept as written (relative to the `.mtl`'s folder unless
//!   absolute). Options: `-bm mult` (kept for bump maps, checked and dropped on `map_Kd`), and,
//!   checked and skipped, `-blendu`, `-blendv`, `-cc`, `-clamp` with `on` or `off`; `-boost`,
//!   `-texres` with a number; `-mm base gain`; `-o`, `-s`, `-t` with one to three numbers;
//!   `-imfchan` and `-type` with one word. Any other `-option` is an error, since where its
//!   arguments end and the file name starts cannot be told;
//! - `Ka`, `Ke`, `illum` and `map_Ks` are recognised and ignored.
//!
//! Blank lines and lines starting with `#` are skipped, and so are unknown statements (many
//! exporters write extras). A recognised statement before the first `newmtl`, wrong arguments
//! and non-finite numbers are errors.
//!
//! The OBJ side: every word after `mtllib` names a library relative to the OBJ's folder (several
//! per line and several lines allowed; one named twice is read once). `usemtl name` (the rest of
//! the line) selects a material for the faces that follow; naming one no library defines is an
//! error. Faces before any `usemtl`, or after one without a name, get a default material named
//! `""` ([`ObjMaterial::default`]) appended after the libraries' materials. `materials` holds every
//! material of the libraries in file order, so a material's index does not depend on its use.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::geom::mesh::ObjMaterial;
use crate::math::Vec3;
use crate::scene::error::{escaped_path, one_line, shown, MAX_LINE_CHARS};

/// A `.mtl` file as read, for the caller to hash for provenance.
#[derive(Debug, Clone, PartialEq)]
pub struct MtlFile {
    /// The path it was read from (the OBJ's folder joined with the `mtllib` name).
    pub path: PathBuf,
    /// Its bytes.
    pub bytes: Vec<u8>,
}

/// A problem in a `.mtl` file, or in the `mtllib` or `usemtl` record of an OBJ, at a line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}:{line}: {}", escaped_path(path), one_line(rule, MAX_LINE_CHARS))]
pub struct MtlError {
    /// The file the problem is in (the `.mtl` as resolved, or the OBJ as given).
    pub path: PathBuf,
    /// 1-based line of the offending statement.
    pub line: usize,
    /// What is wrong, e.g. `Kd needs three numbers, got "0.5 x"`.
    pub rule: String,
}

/// An OBJ `mtllib` record: its line and the library names on it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MtlLib {
    /// 1-based line in the OBJ.
    pub line: usize,
    /// The names as written, split on whitespace.
    pub names: Vec<String>,
}

/// An OBJ `usemtl` record: its line, the name, and the first triangle it applies to.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct UseMtl {
    /// 1-based line in the OBJ.
    pub line: usize,
    /// The material name (the rest of the line, trimmed; empty selects the default).
    pub name: String,
    /// Index of the first triangle (after triangulation) that follows the record.
    pub first_triangle: usize,
}

/// What [`assign_materials`] gives a mesh: its materials, per-triangle indices into them, and
/// the files read.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct MaterialAssignment {
    /// Every material of the libraries, then the default `""` one if a face uses it.
    pub materials: Vec<ObjMaterial>,
    /// Per triangle, an index into `materials`; empty (as is `materials`) when no face has one.
    pub face_material: Vec<u32>,
    /// Every `.mtl` file read, in `mtllib` order.
    pub files: Vec<MtlFile>,
}

/// Parses the text of a `.mtl` file (see the [module docs](self) for the rules); `path` names
/// it in errors and in each material's `file`.
///
/// # Examples
/// ```
/// # use penumbra::scene::mtl::parse_mtl;
/// # use penumbra::math::Vec3;
/// let text = "newmtl red\nKd 0.8 0.1 0.1\nTr 0.25\nmap_bump -bm 0.5 bumps.png\n";
/// let red = &parse_mtl(text, "room.mtl".as_ref())?[0];
/// assert_eq!((red.name.as_str(), red.kd, red.d), ("red", Some(Vec3::new(0.8, 0.1, 0.1)), Some(0.75)));
/// assert_eq!(red.bump_multiplier, Some(0.5));
///
/// let err = parse_mtl("newmtl a\nKd 0.5 x\n", "room.mtl".as_ref()).unwrap_err();
/// assert_eq!(err.to_string(), r#"room.mtl:2: Kd needs three numbers, got "0.5 x""#);
/// # Ok::<(), penumbra::scene::mtl::MtlError>(())
/// ```
pub fn parse_mtl(text: &str, path: &Path) -> Result<Vec<ObjMaterial>, MtlError> {
    let mut materials: Vec<ObjMaterial> = Vec::new();
    let mut defined: HashMap<String, usize> = HashMap::new();
    for (i, line) in text.lines().enumerate() {
        let at = |rule: String| MtlError { path: path.to_path_buf(), line: i + 1, rule };
        let (keyword, args) = split_word(line);
        let kind = keyword.to_ascii_lowercase();
        let known = matches!(
            kind.as_str(),
            "newmtl"
                | "kd"
                | "ks"
                | "ns"
                | "d"
                | "tr"
                | "ni"
                | "map_kd"
                | "map_bump"
                | "bump"
                | "ka"
                | "ke"
                | "illum"
                | "map_ks"
        );
        if !known {
            // Blank lines, comments and statements we do not read.
            continue;
        }
        let keyword = shown(keyword);
        if kind == "newmtl" {
            if args.is_empty() {
                return Err(at("newmtl needs a material name".into()));
            }
            if let Some(first) = defined.insert(args.to_owned(), i + 1) {
                return Err(at(format!("newmtl `{}` repeats the name defined on line {first}", shown(args))));
            }
            let file = path.to_path_buf();
            materials.push(ObjMaterial {
                name: args.to_owned(),
                file,
                line: i + 1,
                ..ObjMaterial::default()
            });
            continue;
        }
        let Some(material) = materials.last_mut() else {
            return Err(at(format!("{keyword} comes before any newmtl")));
        };
        match kind.as_str() {
            "kd" => material.kd = Some(colour(&keyword, args).map_err(at)?),
            "ks" => material.ks = Some(colour(&keyword, args).map_err(at)?),
            "ns" => material.ns = Some(scalar(&keyword, args).map_err(at)?),
            "d" => material.d = Some(scalar(&keyword, args).map_err(at)?),
            "tr" => material.d = Some(1.0 - scalar(&keyword, args).map_err(at)?),
            "ni" => material.ni = Some(scalar(&keyword, args).map_err(at)?),
            "map_kd" => material.map_kd = Some(texture(&keyword, args).map_err(at)?.0),
            "map_bump" | "bump" => {
                let (file, multiplier) = texture(&keyword, args).map_err(at)?;
                material.map_bump = Some(file);
                material.bump_multiplier = multiplier;
            }
            // Ka, Ke, illum, map_Ks: recognised, not used.
            _ => {}
        }
    }
    Ok(materials)
}

/// Reads every library `libraries` name (relative to the folder of `obj`, the OBJ's path as
/// given) and resolves the `usemtl` runs `uses` into per-triangle indices for a mesh of
/// `triangles` triangles (see the [module docs](self) for the rules).
pub(crate) fn assign_materials(
    obj: &Path,
    libraries: &[MtlLib],
    uses: &[UseMtl],
    triangles: usize,
) -> Result<MaterialAssignment, MtlError> {
    let at = |line: usize, rule: String| MtlError { path: obj.to_path_buf(), line, rule };
    let folder = obj.parent().unwrap_or(Path::new(""));

    // Read every library once, in mtllib order; names must be unique across them.
    let mut out = MaterialAssignment::default();
    let mut index_of: HashMap<String, usize> = HashMap::new();
    let mut read_names: Vec<&str> = Vec::new();
    for library in libraries {
        for name in &library.names {
            let path = folder.join(name);
            if out.files.iter().any(|f| f.path == path) {
                continue;
            }
            let bytes = std::fs::read(&path).map_err(|e| {
                at(library.line, format!("cannot read material library {}: {e}", escaped_path(&path)))
            })?;
            for material in parse_mtl(&String::from_utf8_lossy(&bytes), &path)? {
                if let Some(&k) = index_of.get(&material.name) {
                    let first = &out.materials[k];
                    return Err(MtlError {
                        rule: format!(
                            "newmtl `{}` is already defined at {}:{}",
                            shown(&material.name),
                            escaped_path(&first.file),
                            first.line
                        ),
                        path: material.file,
                        line: material.line,
                    });
                }
                index_of.insert(material.name.clone(), out.materials.len());
                out.materials.push(material);
            }
            read_names.push(name);
            out.files.push(MtlFile { path, bytes });
        }
    }
    if out.materials.len() >= u32::MAX as usize {
        let line = libraries.last().map_or(1, |l| l.line);
        return Err(at(line, format!("{} materials do not fit 32-bit indices", out.materials.len())));
    }

    // Resolve the usemtl runs; `NONE` marks faces without a material until the default exists.
    const NONE: u32 = u32::MAX;
    let mut face_material = vec![NONE; triangles];
    for (k, record) in uses.iter().enumerate() {
        let index = if record.name.is_empty() {
            NONE
        } else {
            match index_of.get(&record.name) {
                // Checked above: every index fits in u32.
                Some(&i) => i as u32,
                None if read_names.is_empty() => {
                    return Err(at(
                        record.line,
                        format!(
                            "usemtl `{}` names no material: the OBJ names no material library (mtllib)",
                            shown(&record.name)
                        ),
                    ))
                }
                None => {
                    let files: Vec<String> = read_names.iter().map(|n| shown(n)).collect();
                    return Err(at(
                        record.line,
                        format!("usemtl `{}` names no material in {}", shown(&record.name), files.join(", ")),
                    ));
                }
            }
        };
        let end = uses.get(k + 1).map_or(triangles, |next| next.first_triangle).min(triangles);
        face_material[record.first_triangle.min(end)..end].fill(index);
    }
    if face_material.iter().all(|&m| m == NONE) {
        out.materials.clear();
        return Ok(out);
    }
    if face_material.contains(&NONE) {
        // Fits: fewer than u32::MAX materials came from the libraries.
        let default = out.materials.len() as u32;
        out.materials.push(ObjMaterial::default());
        face_material.iter_mut().filter(|m| **m == NONE).for_each(|m| *m = default);
    }
    out.face_material = face_material;
    Ok(out)
}

/// The first whitespace-separated word of `text` and the rest, both trimmed.
fn split_word(text: &str) -> (&str, &str) {
    let text = text.trim();
    let end = text.find(char::is_whitespace).unwrap_or(text.len());
    (&text[..end], text[end..].trim_start())
}

/// The numbers of `args` when there are exactly `n`, all finite; otherwise the rule broken.
fn numbers(keyword: &str, args: &str, n: usize, what: &str) -> Result<Vec<f32>, String> {
    let values: Option<Vec<f32>> = args.split_whitespace().map(|w| w.parse().ok()).collect();
    match values {
        Some(values) if values.len() == n => {
            if values.iter().all(|x| x.is_finite()) {
                Ok(values)
            } else {
                Err(format!("{keyword} needs finite numbers, got \"{}\"", shown(args)))
            }
        }
        _ => Err(format!("{keyword} needs {what}, got \"{}\"", shown(args))),
    }
}

/// A `Kd`/`Ks` colour: three finite numbers.
fn colour(keyword: &str, args: &str) -> Result<Vec3, String> {
    let v = numbers(keyword, args, 3, "three numbers")?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// An `Ns`/`d`/`Tr`/`Ni` value: one finite number.
fn scalar(keyword: &str, args: &str) -> Result<f32, String> {
    Ok(numbers(keyword, args, 1, "one number")?[0])
}

/// A texture statement's file name and `-bm` multiplier, after its options.
fn texture(keyword: &str, args: &str) -> Result<(PathBuf, Option<f32>), String> {
    let mut rest = args;
    let mut multiplier = None;
    while rest.starts_with('-') {
        let (option, after) = split_word(rest);
        rest = after;
        let shown_option = shown(option);
        // The next word as a finite number, consumed.
        let number = |rest: &mut &str| -> Result<f32, String> {
            let (word, after) = split_word(rest);
            match word.parse::<f32>() {
                Ok(x) if x.is_finite() => {
                    *rest = after;
                    Ok(x)
                }
                _ => Err(format!("{keyword} option {shown_option} needs a number, got \"{}\"", shown(word))),
            }
        };
        match option.to_ascii_lowercase().as_str() {
            "-bm" => multiplier = Some(number(&mut rest)?),
            "-boost" | "-texres" => {
                number(&mut rest)?;
            }
            "-mm" => {
                number(&mut rest)?;
                number(&mut rest)?;
            }
            "-o" | "-s" | "-t" => {
                number(&mut rest)?;
                for _ in 0..2 {
                    if split_word(rest).0.parse::<f32>().is_err() {
                        break;
                    }
                    number(&mut rest)?;
                }
            }
            "-blendu" | "-blendv" | "-cc" | "-clamp" => {
                let (word, after) = split_word(rest);
                if !matches!(word.to_ascii_lowercase().as_str(), "on" | "off") {
                    return Err(format!(
                        "{keyword} option {shown_option} needs on or off, got \"{}\"",
                        shown(word)
                    ));
                }
                rest = after;
            }
            "-imfchan" | "-type" => {
                let (word, after) = split_word(rest);
                if word.is_empty() {
                    return Err(format!("{keyword} option {shown_option} needs a value"));
                }
                rest = after;
            }
            _ => {
                return Err(format!(
                    "{keyword} has an unknown option {shown_option}; known: -bm -blendu -blendv -boost -cc \
                     -clamp -imfchan -mm -o -s -t -texres -type"
                ))
            }
        }
    }
    if rest.is_empty() {
        return Err(format!("{keyword} needs a file name, got \"{}\"", shown(args)));
    }
    Ok((PathBuf::from(rest), multiplier))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MTL: &str = "room.mtl";

    fn parse(text: &str) -> Vec<ObjMaterial> {
        match parse_mtl(text, Path::new(MTL)) {
            Ok(materials) => materials,
            Err(e) => panic!("{e}"),
        }
    }

    /// The error for `text`, whose whole message must be `room.mtl:{line}: {rule}`.
    fn assert_invalid(text: &str, line: usize, rule: &str) {
        let err = parse_mtl(text, Path::new(MTL)).expect_err(text);
        assert_eq!(err.to_string(), format!("{MTL}:{line}: {rule}"), "for {text:?}");
        assert_eq!((err.path.as_path(), err.line), (Path::new(MTL), line));
    }

    #[test]
    fn every_statement_is_read_exactly() {
        let text = "# exported\n\
                    \n\
                    newmtl wood floor\n\
                    Ka 0.1 0.1 0.1\n\
                    Kd 0.5 0.25 0.125\n\
                    Ks 1 0.5 0\n\
                    Ke 0 0 0\n\
                    Ns 96.0784\n\
                    Ni 1.45\n\
                    d 0.75\n\
                    illum 2\n\
                    map_Kd textures/wood floor.png\n\
                    map_Ks spec.png\n\
                    map_bump -bm 0.5 bump.png\n\
                    vendor_extra 1 2 3\n\
                    \tnewmtl glass \r\n\
                    Tr 0.25\r\n\
                    MAP_KD -o 0.5 0.5 -s 2 -clamp on -blendu off -mm 0 1 -imfchan l -type cube_top /abs/g.png\n\
                    bump -boost 2 -texres 512 b.png\n\
                    newmtl transparent again\n\
                    d 0.2\n\
                    Tr 0.5\n";
        let materials = parse(text);
        let expected = vec![
            ObjMaterial {
                name: "wood floor".into(),
                kd: Some(Vec3::new(0.5, 0.25, 0.125)),
                ks: Some(Vec3::new(1.0, 0.5, 0.0)),
                ns: Some(96.0784),
                d: Some(0.75),
                ni: Some(1.45),
                map_kd: Some("textures/wood floor.png".into()),
                map_bump: Some("bump.png".into()),
                bump_multiplier: Some(0.5),
                file: MTL.into(),
                line: 3,
            },
            ObjMaterial {
                name: "glass".into(),
                d: Some(0.75),
                map_kd: Some("/abs/g.png".into()),
                map_bump: Some("b.png".into()),
                file: MTL.into(),
                line: 16,
                ..ObjMaterial::default()
            },
            ObjMaterial {
                name: "transparent again".into(),
                // The later of `d` and `Tr` wins.
                d: Some(0.5),
                file: MTL.into(),
                line: 20,
                ..ObjMaterial::default()
            },
        ];
        assert_eq!(materials, expected);
        assert!(parse("").is_empty());
        assert!(parse("# nothing\nfoo 1\n").is_empty(), "unknown statements are ignored anywhere");
    }

    #[test]
    fn bad_statements_name_the_file_and_line() {
        assert_invalid("newmtl a\nKd 1 1 1\n\n\n\n\nKd 0.5 x\n", 7, r#"Kd needs three numbers, got "0.5 x""#);
        assert_invalid("newmtl a\nKd 0.5 0.5\n", 2, r#"Kd needs three numbers, got "0.5 0.5""#);
        assert_invalid("newmtl a\nks 1 1 1 1\n", 2, r#"ks needs three numbers, got "1 1 1 1""#);
        assert_invalid("newmtl a\nKd 1 nan 1\n", 2, r#"Kd needs finite numbers, got "1 nan 1""#);
        assert_invalid("newmtl a\nNs 1e39\n", 2, r#"Ns needs finite numbers, got "1e39""#);
        assert_invalid("newmtl a\nd\n", 2, r#"d needs one number, got """#);
        assert_invalid("newmtl a\nTr 0.5 0.5\n", 2, r#"Tr needs one number, got "0.5 0.5""#);
        assert_invalid("newmtl a\nNi inf\n", 2, r#"Ni needs finite numbers, got "inf""#);
        assert_invalid("# header\nKd 1 1 1\nnewmtl a\n", 2, "Kd comes before any newmtl");
        assert_invalid("illum 2\n", 1, "illum comes before any newmtl");
        assert_invalid(
            "newmtl a\nKd 1 1 1\nnewmtl b\nnewmtl a\n",
            4,
            "newmtl `a` repeats the name defined on line 1",
        );
        assert_invalid("newmtl \n", 1, "newmtl needs a material name");
        assert_invalid("newmtl a\nmap_Kd\n", 2, r#"map_Kd needs a file name, got """#);
        assert_invalid("newmtl a\nmap_bump -bm 2\n", 2, r#"map_bump needs a file name, got "-bm 2""#);
        assert_invalid("newmtl a\nbump -bm x b.png\n", 2, r#"bump option -bm needs a number, got "x""#);
        assert_invalid(
            "newmtl a\nmap_Kd -clamp maybe a.png\n",
            2,
            r#"map_Kd option -clamp needs on or off, got "maybe""#,
        );
        assert_invalid(
            "newmtl a\nmap_Kd -halo a.png\n",
            2,
            "map_Kd has an unknown option -halo; known: -bm -blendu -blendv -boost -cc -clamp -imfchan -mm -o -s -t \
             -texres -type",
        );
    }

    /// Writes `files` (name, text) into a fresh folder.
    fn folder(files: &[(&str, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for (name, text) in files {
            std::fs::write(dir.path().join(name), text).unwrap();
        }
        dir
    }

    fn uses(runs: &[(usize, &str, usize)]) -> Vec<UseMtl> {
        runs.iter()
            .map(|&(line, name, first_triangle)| UseMtl { line, name: name.into(), first_triangle })
            .collect()
    }

    #[test]
    fn usemtl_runs_become_indices_with_a_default_for_faces_without_one() {
        let dir = folder(&[("a.mtl", "newmtl red\nnewmtl green\n"), ("b.mtl", "newmtl blue\n")]);
        let obj = dir.path().join("m.obj");
        let libraries = [
            MtlLib { line: 1, names: vec!["a.mtl".into()] },
            MtlLib { line: 2, names: vec!["b.mtl".into(), "a.mtl".into()] },
        ];
        // Triangles 0..2 have no material, 2..5 blue, 5..6 red, 6..7 none again, 7.. green.
        let runs = uses(&[(5, "blue", 2), (9, "red", 5), (11, "", 6), (12, "green", 7)]);
        let out = assign_materials(&obj, &libraries, &runs, 8).unwrap();
        let names: Vec<&str> = out.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["red", "green", "blue", ""]);
        assert_eq!(out.face_material, [3, 3, 2, 2, 2, 0, 3, 1]);
        assert_eq!(out.materials[2].file, dir.path().join("b.mtl"));
        assert_eq!(out.materials[3], ObjMaterial::default());
        // a.mtl is read once.
        let files: Vec<&Path> = out.files.iter().map(|f| f.path.as_path()).collect();
        assert_eq!(files, [dir.path().join("a.mtl"), dir.path().join("b.mtl")]);
        assert_eq!(out.files[1].bytes, b"newmtl blue\n");

        // Every face has a material: no default.
        let all = assign_materials(&obj, &libraries, &uses(&[(3, "green", 0)]), 4).unwrap();
        assert_eq!(all.face_material, [1; 4]);
        assert_eq!(all.materials.len(), 3);
        // No face uses one: both empty, the files are still listed.
        let none = assign_materials(&obj, &libraries, &uses(&[(3, "", 0)]), 4).unwrap();
        assert!(none.face_material.is_empty() && none.materials.is_empty());
        assert_eq!(none.files.len(), 2);
    }

    #[test]
    fn obj_usemtl_runs_give_per_triangle_indices() {
        let dir = folder(&[
            ("room.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n"),
            ("extra.mtl", "# more\nnewmtl green\n"),
        ]);
        let obj = dir.path().join("scene.obj");
        let text = "mtllib room.mtl\nmtllib extra.mtl room.mtl\n\
                    v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n\
                    f 1 2 5\n\
                    usemtl red\nf 1 2 3 4\n\
                    g second\nusemtl blue\nf 1 2 3 4 5\n\
                    o third\nusemtl red\nf 3 4 5\n\
                    usemtl\nf 2 3 4\n";
        std::fs::write(&obj, text).unwrap();
        let (mesh, files) = crate::scene::obj::load_obj_with_materials(&obj, true).unwrap();
        let names: Vec<&str> = mesh.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["red", "blue", "green", ""]);
        // Triangle 0 has none, 1-2 the red quad, 3-5 the blue pentagon, 6 red, 7 none again.
        assert_eq!(mesh.face_material, [3, 0, 0, 1, 1, 1, 0, 3]);
        assert_eq!(mesh.triangle_count(), 8);
        // The indices follow the triangles: check the first and the last two faces' corners.
        let corners = |t: usize| mesh.indices[t].map(|i| mesh.positions[i as usize]);
        assert_eq!(corners(0), [Vec3::ZERO, Vec3::X, Vec3::Z]);
        assert_eq!(corners(6), [Vec3::new(1.0, 1.0, 0.0), Vec3::Y, Vec3::Z]);
        assert_eq!(corners(7), [Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]);
        let red = &mesh.materials[0];
        assert_eq!(
            (red.kd, red.file.as_path(), red.line),
            (Some(Vec3::X), dir.path().join("room.mtl").as_path(), 1)
        );
        let paths: Vec<&Path> = files.iter().map(|f| f.path.as_path()).collect();
        assert_eq!(paths, [dir.path().join("room.mtl"), dir.path().join("extra.mtl")]);
        assert_eq!(files[1].bytes, b"# more\nnewmtl green\n");

        // load_obj ignores the materials.
        let plain = crate::scene::obj::load_obj(&obj, true).unwrap();
        assert!(plain.face_material.is_empty() && plain.materials.is_empty());
        assert_eq!((plain.indices, plain.positions), (mesh.indices, mesh.positions));
    }

    #[test]
    fn obj_material_errors_have_exact_file_and_line() {
        let dir = folder(&[("room.mtl", "newmtl wall\nKd 1 1 1\n\n# trim\nnewmtl trim\nNs 10\nKd 0.5 x\n")]);
        let obj = dir.path().join("scene.obj");
        let load = |text: &str| {
            std::fs::write(&obj, text).unwrap();
            match crate::scene::obj::load_obj_with_materials(&obj, false) {
                Err(e @ crate::scene::obj::ObjError::Invalid { .. }) => e.to_string(),
                other => panic!("{other:?}"),
            }
        };
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        let (shown_obj, room) = (obj.display().to_string(), dir.path().join("room.mtl"));
        assert_eq!(
            load(&format!("mtllib room.mtl\n{tri}f 1 2 3\n")),
            format!(r#"{}:7: Kd needs three numbers, got "0.5 x""#, room.display())
        );
        std::fs::write(&room, "newmtl wall\n").unwrap();
        assert_eq!(
            load(&format!("mtllib room.mtl\n{tri}f 1 2 3\nusemtl wall\nf 1 2 3\nusemtl paint\nf 1 2 3\n")),
            format!("{shown_obj}:8: usemtl `paint` names no material in room.mtl")
        );
        let gone = dir.path().join("gone.mtl");
        let err = load(&format!("{tri}mtllib room.mtl\nmtllib gone.mtl\nf 1 2 3\n"));
        assert!(
            err.starts_with(&format!("{shown_obj}:5: cannot read material library {}: ", gone.display())),
            "{err}"
        );
        std::fs::write(&room, "newmtl wall\nKd 1 1 1\nnewmtl wall\n").unwrap();
        assert_eq!(
            load(&format!("mtllib room.mtl\n{tri}f 1 2 3\n")),
            format!("{}:3: newmtl `wall` repeats the name defined on line 1", room.display())
        );
        std::fs::write(&room, "Kd 1 1 1\nnewmtl wall\n").unwrap();
        assert_eq!(
            load(&format!("mtllib room.mtl\n{tri}f 1 2 3\n")),
            format!("{}:1: Kd comes before any newmtl", room.display())
        );
    }

    #[test]
    fn bad_obj_records_name_the_obj_line() {
        let dir = folder(&[("room.mtl", "newmtl wall\n"), ("trim.mtl", "newmtl wall\n")]);
        let obj = dir.path().join("scene.obj");
        let shown_obj = obj.display();
        let room = [MtlLib { line: 1, names: vec!["room.mtl".into()] }];
        let err = assign_materials(&obj, &room, &uses(&[(12, "paint", 0)]), 1).unwrap_err();
        assert_eq!(err.to_string(), format!("{shown_obj}:12: usemtl `paint` names no material in room.mtl"));
        let err = assign_materials(&obj, &[], &uses(&[(3, "paint", 0)]), 1).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "{shown_obj}:3: usemtl `paint` names no material: the OBJ names no material library (mtllib)"
            )
        );
        let missing = [MtlLib { line: 4, names: vec!["room.mtl".into(), "gone.mtl".into()] }];
        let err = assign_materials(&obj, &missing, &[], 1).unwrap_err();
        let gone = dir.path().join("gone.mtl");
        assert!(
            err.to_string()
                .starts_with(&format!("{shown_obj}:4: cannot read material library {}: ", gone.display())),
            "{err}"
        );
        // The same name in two libraries.
        let both = [MtlLib { line: 1, names: vec!["room.mtl".into(), "trim.mtl".into()] }];
        let err = assign_materials(&obj, &both, &[], 1).unwrap_err();
        let (room, trim) = (dir.path().join("room.mtl"), dir.path().join("trim.mtl"));
        assert_eq!(
            err.to_string(),
            format!("{}:1: newmtl `wall` is already defined at {}:1", trim.display(), room.display())
        );
    }
}
