//! Tests of `src/batch/manifest.rs`.

use super::*;

fn job(dir: &Path) -> JobSpec {
    JobSpec {
        version: "test".into(),
        scene: dir.join("s.ron"),
        script: dir.join("s.rhai"),
        frames: FrameRange::new(0, 3),
        fps: 24.0,
        options: "width 8".into(),
        extension: "png".into(),
        inputs: Vec::new(),
    }
}

/// A finished frame `n` of `job` with inputs hash `inputs`, made from `files`.
fn entry(job: &JobSpec, n: u32, inputs: String, files: Vec<InputFile>) -> FrameEntry {
    FrameEntry {
        frame: n,
        file: job.file_name(n),
        inputs,
        seed: 1,
        settings: String::new(),
        render_seconds: 0.1,
        total_seconds: 0.2,
        rays: BTreeMap::new(),
        mrays_per_s: 1.0,
        host: "h".into(),
        simd: "scalar".into(),
        shard: "0/1".into(),
        files,
    }
}

fn inputs(scene: &[u8], script: &[u8], meshes: &[&[u8]]) -> Inputs {
    let file = |role, name: &str, bytes: &[u8]| InputFile {
        role,
        name: name.into(),
        path: None,
        sha256: sha256_hex(bytes),
    };
    let mut files = vec![file(InputRole::Scene, "s.ron", scene), file(InputRole::Script, "s.rhai", script)];
    files.extend(meshes.iter().enumerate().map(|(i, m)| file(InputRole::Mesh, &format!("m{i}.obj"), m)));
    Inputs { files }
}

#[test]
fn inputs_hash_changes_with_every_input() {
    let dir = Path::new("/x");
    let i = inputs(b"scene", b"script", &[b"mesh"]);
    let base = job(dir).inputs_hash(&i, 1);
    assert_eq!(base, job(dir).inputs_hash(&inputs(b"scene", b"script", &[b"mesh"]), 1));
    assert_ne!(base, job(dir).inputs_hash(&inputs(b"scene!", b"script", &[b"mesh"]), 1));
    assert_ne!(base, job(dir).inputs_hash(&inputs(b"scene", b"script!", &[b"mesh"]), 1));
    assert_ne!(base, job(dir).inputs_hash(&inputs(b"scene", b"script", &[b"mesh!"]), 1));
    assert_ne!(base, job(dir).inputs_hash(&inputs(b"scene", b"script", &[b"mesh", b"m"]), 1));
    assert_ne!(base, job(dir).inputs_hash(&i, 2));
    assert_ne!(base, JobSpec { fps: 30.0, ..job(dir) }.inputs_hash(&i, 1));
    assert_ne!(base, JobSpec { options: "width 9".into(), ..job(dir) }.inputs_hash(&i, 1));
}

#[test]
fn status_tells_done_missing_and_stale() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("s.ron"), "scene").unwrap();
    std::fs::write(dir.join("s.rhai"), "script").unwrap();
    let m = Manifest::create(dir).unwrap();
    let j = job(dir);
    m.write_job(&j).unwrap();
    let entry = |n: u32, inputs: String| entry(&j, n, inputs, Vec::new());
    for n in [0, 1, 2] {
        std::fs::write(dir.join(j.file_name(n)), "png").unwrap();
    }
    m.write_entry(&entry(0, j.inputs_hash(&inputs(b"scene", b"script", &[]), 0))).unwrap();
    m.write_entry(&entry(1, j.inputs_hash(&inputs(b"old scene", b"script", &[]), 1))).unwrap();
    // Frame 2 has an image but no entry (killed between the two writes); 3 has nothing.
    let s = status(dir).unwrap();
    assert_eq!((s.done, s.stale, s.missing), (vec![0], vec![1], vec![2, 3]));
    assert!(s.stray_temporaries.is_empty());
}

#[test]
fn status_names_the_input_that_changed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (name, text) in [("s.ron", "scene"), ("s.rhai", "script"), ("a.obj", "a"), ("b.obj", "b")] {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let file = |role, name: &str| InputFile::read(role, name, &dir.join(name)).unwrap();
    let recorded = Inputs {
        files: vec![
            file(InputRole::Scene, "s.ron"),
            file(InputRole::Script, "s.rhai"),
            file(InputRole::Mesh, "a.obj"),
            file(InputRole::Mesh, "b.obj"),
        ],
    };
    let m = Manifest::create(dir).unwrap();
    let j = JobSpec { inputs: recorded.files.clone(), ..job(dir) };
    m.write_job(&j).unwrap();
    for n in 0..4 {
        std::fs::write(dir.join(j.file_name(n)), "png").unwrap();
        m.write_entry(&entry(&j, n, j.inputs_hash(&recorded, n), recorded.files.clone())).unwrap();
    }
    assert_eq!(status(dir).unwrap().done, vec![0, 1, 2, 3]);
    std::fs::write(dir.join("b.obj"), "b, stretched").unwrap();
    let s = status(dir).unwrap();
    assert_eq!((s.done.len(), s.stale), (0, vec![0, 1, 2, 3]));
    assert_eq!(s.changed, vec!["mesh b.obj".to_string()]);
    std::fs::remove_file(dir.join("a.obj")).unwrap();
    let error = status(dir).unwrap_err().to_string();
    assert!(error.contains("a.obj"), "{error}");
}

#[test]
fn status_of_a_missing_folder_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let error = status(&tmp.path().join("nope")).unwrap_err().to_string();
    assert!(error.ends_with("nope: no such folder"), "{error}");
}

#[test]
fn a_frame_is_claimed_by_one_run_at_a_time() {
    let tmp = tempfile::tempdir().unwrap();
    let m = Manifest::create(tmp.path()).unwrap();
    let first = m.claim(7).unwrap();
    assert!(first.is_some());
    assert!(m.claim(7).unwrap().is_none(), "a second claim while the first holds");
    assert!(m.claim(8).unwrap().is_some(), "other frames are free");
    drop(first);
    assert!(m.claim(7).unwrap().is_some(), "free again once released");
}

#[test]
fn a_lone_run_removes_stray_temporaries_and_a_second_run_leaves_them() {
    let tmp = tempfile::tempdir().unwrap();
    let m = Manifest::create(tmp.path()).unwrap();
    std::fs::write(tmp.path().join(".penumbra-abc.tmp"), "partial").unwrap();
    std::fs::write(tmp.path().join(MANIFEST_DIR).join(".penumbra-def.tmp"), "partial").unwrap();
    let first = m.join_runs().unwrap();
    assert_eq!(first.removed, vec![".penumbra-abc.tmp".to_string(), ".penumbra-def.tmp".into()]);
    assert!(m.stray_temporaries().is_empty());
    // While a run is active, a temporary may be its write in progress: left alone.
    std::fs::write(tmp.path().join(".penumbra-ghi.tmp"), "in progress").unwrap();
    let second = m.join_runs().unwrap();
    assert!(second.removed.is_empty());
    assert_eq!(m.stray_temporaries(), vec![".penumbra-ghi.tmp".to_string()]);
    drop((first, second));
    assert_eq!(m.join_runs().unwrap().removed, vec![".penumbra-ghi.tmp".to_string()]);
}

#[test]
fn frame_lists_print_as_ranges() {
    assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10]), "0..=3, 7, 9..=10");
    assert_eq!(ranges(&[]), "none");
    assert_eq!(frame_file_name(FrameRange::new(0, 119), 7, "png"), "frame_0007.png");
    assert_eq!(frame_file_name(FrameRange::new(0, 123456), 7, "exr"), "frame_000007.exr");
}
