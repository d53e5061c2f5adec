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
mod tests;
