//! Tests of `src/scene/mtl.rs`.

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
