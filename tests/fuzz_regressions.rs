//! Bad input never crashes: each fuzz target's body (`tests/fuzz_entries`, the code the targets
//! in `fuzz/` run; see docs/fuzzing.md) on its seeds, on every input that ever crashed it
//! (`fuzz/regressions/<target>/`) and on a handful of nasty inputs. Each must be accepted or
//! refused with a message naming its file.

use crate::fuzz_entries;

use std::path::{Path, PathBuf};

/// A target's seeds, as `fuzz/run.sh` gives them to the fuzzer: the shipped files
/// (`scenes/*.ron`, `scenes/*.obj` or `scripts/*.rhai`), the hand-written `fuzz/seeds/<target>/`
/// and every input that ever crashed the target, `fuzz/regressions/<target>/`.
fn seeds(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (shipped, extension) = match target {
        "scene" | "render" => ("scenes", "ron"),
        "obj" => ("scenes", "obj"),
        "script" => ("scripts", "rhai"),
        other => panic!("no fuzz target `{other}`"),
    };
    let files_in = |dir: PathBuf, only: Option<&str>| -> Vec<PathBuf> {
        let Ok(entries) = std::fs::read_dir(&dir) else { return Vec::new() };
        entries
            .map(|entry| entry.expect("directory entry").path())
            .filter(|path| {
                path.is_file() && only.is_none_or(|ext| path.extension().is_some_and(|e| e == ext))
            })
            .collect()
    };
    let mut files = files_in(root.join(shipped), Some(extension));
    assert!(!files.is_empty(), "no {shipped}/*.{extension}");
    files.extend(files_in(root.join("fuzz/seeds").join(target), None));
    files.extend(files_in(root.join("fuzz/regressions").join(target), None));
    files.sort();
    files.into_iter().map(|path| (path.clone(), std::fs::read(&path).expect("read seed"))).collect()
}

/// Inputs no target should choke on: empty, NUL bytes, invalid UTF-8, huge numbers, deep
/// nesting of each bracket kind, and a long line.
fn nasty() -> Vec<Vec<u8>> {
    let deep =
        |open: &str, close: &str| format!("{}{}", open.repeat(10_000), close.repeat(10_000)).into_bytes();
    vec![
        Vec::new(),
        vec![0; 64],
        b"\0Scene(\0)\0".to_vec(),
        vec![0xff, 0xfe, 0xc3, 0x28, 0xe2, 0x82],
        b"1e999999 -1e999999 NaN inf -inf 18446744073709551616 -9223372036854775809".to_vec(),
        deep("(", ")"),
        deep("[", "]"),
        deep("{", "}"),
        deep("Scene(camera:(", ")"),
        "x".repeat(100_000).into_bytes(),
    ]
}

#[test]
fn scene_seeds_regressions_and_nasty_inputs_never_panic() {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for (path, bytes) in seeds("scene") {
        // A shipped scene is refused only for its meshes (they resolve against an empty folder).
        if let Err(message) = fuzz_entries::scene(&bytes) {
            assert!(!path.starts_with(&shipped) || message.contains(".obj"), "{}: {message}", path.display());
        }
    }
    for bytes in nasty() {
        fuzz_entries::scene(&bytes).expect_err("nasty input is not a scene");
    }
}

#[test]
fn render_seeds_regressions_and_nasty_inputs_give_finite_films() {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut rendered = 0;
    for (path, bytes) in seeds("render") {
        match fuzz_entries::render(&bytes) {
            Ok(()) => rendered += 1,
            Err(message) => {
                assert!(
                    !path.starts_with(&shipped) || message.contains(".obj"),
                    "{}: {message}",
                    path.display()
                )
            }
        }
    }
    assert!(rendered >= 10, "only {rendered} seeds rendered");
    for bytes in nasty() {
        fuzz_entries::render(&bytes).expect_err("nasty input is not a scene");
    }
}

#[test]
fn obj_seeds_regressions_and_nasty_inputs_never_panic() {
    for (path, bytes) in seeds("obj") {
        let accepted = fuzz_entries::obj(&bytes);
        assert!(accepted.is_ok(), "{}: {accepted:?}", path.display());
    }
    for bytes in nasty() {
        fuzz_entries::obj(&bytes).expect_err("nasty input is not a mesh");
    }
}

#[test]
fn script_seeds_regressions_and_nasty_inputs_never_panic() {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts");
    for (path, bytes) in seeds("script") {
        let result = fuzz_entries::script(&bytes);
        // The shipped animation scripts written for the fuzzer's stage (`scenes/flythrough.ron`)
        // run on it (sweep scripts have no frame(t); `motion.rhai` has a stage of its own).
        let text = String::from_utf8_lossy(&bytes);
        if path.starts_with(&shipped)
            && text.contains("fn frame(t)")
            && text.contains("scenes/flythrough.ron")
        {
            assert!(result.is_ok(), "{}: {result:?}", path.display());
        }
    }
    let mut inputs = nasty();
    inputs.extend(
        [
            "fn frame(t) { loop {} }",
            "fn frame(t) { frame(t) }",
            "fn frame(t) { let s = \"x\"; loop { s += s; } }",
            "fn frame(t) { camera.fov = 1e300; camera.position = vec3(0.0/0.0, 1.0, 1.0); }",
            "fn frame(t) { settings.samples = -1; settings.max_depth = 9223372036854775807; }",
            "fn frame(t) { let s = entity(\"subject\"); s.position = vec3(1e38 * 10.0, 0.0, 0.0); }",
        ]
        .map(|s| s.as_bytes().to_vec()),
    );
    for bytes in inputs {
        let refused = fuzz_entries::script(&bytes);
        assert!(refused.is_err(), "{}: accepted", String::from_utf8_lossy(&bytes));
    }
}
