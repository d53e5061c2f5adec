//! `penumbra report`: every output file from a tiny scene, error falling as samples rise,
//! a default sweep that covers only the effects a scene uses, and an HTML page that loads in
//! headless Chromium with its plots and no console error.

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// A small scene with hard edges (so anti-aliasing matters) and, optionally, an area light.
fn scene(area_light: bool) -> String {
    let light = match area_light {
        true => "Rect(corner: (-1, 4, -1), edge_u: (2, 0, 0), edge_v: (0, 0, 2), samples: 4)",
        false => "Point(position: (-2, 4, -3), intensity: 0.9)",
    };
    format!(
        r#"Scene(
    camera: (position: (0, 1.2, -5), look_at: (0, 0.6, 0), fov_deg: 40, width: 40, height: 30),
    settings: (max_depth: 2, background: (0.1, 0.12, 0.2), ambient: (0.1, 0.1, 0.1), seed: 9),
    materials: [(name: "white", kd: (0.8, 0.8, 0.8)), (name: "red", kd: (0.8, 0.1, 0.1))],
    lights: [{light}],
    objects: [
        (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "white"),
        (name: "ball", shape: Sphere(centre: (0, 0.6, 0), radius: 0.6), material: "red"),
        (name: "box", shape: Box(min: (0.8, 0, -0.5), max: (1.6, 1.2, 0.3)), material: "white"),
    ],
)"#
    )
}

fn report(dir: &Path, area_light: bool, extra: &[&str]) -> PathBuf {
    std::fs::write(dir.join("scene.ron"), scene(area_light)).unwrap();
    let out = Command::new(BIN)
        .current_dir(dir)
        .args(["report", "scene.ron", "-o", "report", "--runs", "1", "--quiet"])
        .args(extra)
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    dir.join("report")
}

/// (axis, label, rmse, ssim) of every row of results.csv.
fn rows(report: &Path) -> Vec<(String, String, f64, f64)> {
    let text = std::fs::read_to_string(report.join("results.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col =
        |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let (axis, label, rmse, ssim) = (col("axis"), col("label"), col("rmse"), col("ssim"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[axis].to_owned(), f[label].to_owned(), f[rmse].parse().unwrap(), f[ssim].parse().unwrap())
        })
        .collect()
}

#[test]
fn a_sweep_writes_every_output_and_error_falls_as_samples_rise() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("sweep.ron"),
        "Sweep(axes: [Aa(samples: [1, 4, 16, 64]), AreaLight(samples: [1, 4, 16, 64])], reference: (aa: 256, area_light: 256))",
    )
    .unwrap();
    let dir = report(tmp.path(), true, &["--sweep", "sweep.ron"]);
    for file in [
        "results.csv",
        "results.json",
        "index.html",
        "reference.png",
        "error_vs_time.png",
        "error_vs_time.svg",
        "rays_vs_error.png",
        "rays_vs_error.svg",
        "effect_costs.png",
        "effect_costs.svg",
        "estimate_vs_error.png",
        "estimate_vs_error.svg",
    ] {
        assert!(dir.join(file).is_file(), "{file} is missing");
    }
    let rows = rows(&dir);
    assert_eq!(rows.len(), 8);
    for axis in ["aa", "area_light"] {
        let errors: Vec<f64> = rows.iter().filter(|r| r.0 == axis).map(|r| r.2).collect();
        assert!(errors.windows(2).all(|w| w[1] < w[0]), "{axis}: RMSE must fall as samples rise: {errors:?}");
        let ssims: Vec<f64> = rows.iter().filter(|r| r.0 == axis).map(|r| r.3).collect();
        assert!(ssims.first() < ssims.last() && ssims.iter().all(|s| *s <= 1.0), "{axis}: {ssims:?}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("results.json")).unwrap()).unwrap();
    let points = json["points"].as_array().unwrap();
    assert_eq!(points.len(), 8);
    for p in points {
        assert!(
            dir.join(p["image"].as_str().unwrap()).is_file()
                && dir.join(p["heatmap"].as_str().unwrap()).is_file()
        );
    }
}

#[test]
fn the_default_sweep_of_a_scene_without_area_lights_has_no_area_light_axis() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = report(tmp.path(), false, &["--width", "16", "--height", "12"]);
    let axes: std::collections::BTreeSet<String> = rows(&dir).into_iter().map(|r| r.0).collect();
    assert_eq!(axes.into_iter().collect::<Vec<_>>(), ["aa", "adaptive", "noise"]);
    let tmp = tempfile::tempdir().unwrap();
    let dir = report(tmp.path(), true, &["--width", "16", "--height", "12"]);
    assert!(rows(&dir).iter().any(|r| r.0 == "area_light"), "with an area light, its axis is swept");
}

/// A scene whose ball is thrown across the view while the shutter is open all frame, by
/// `move.rhai` (written beside it).
fn moving(dir: &Path) {
    let text = scene(false).replace("width: 40, height: 30)", "width: 40, height: 30, shutter: (0.0, 1.0))");
    std::fs::write(dir.join("scene.ron"), text).unwrap();
    let script = "fn frame(t) { let e = entity(\"ball\"); e.position = vec3(-1.5 + 3.0 * t, 0.6, 0); }";
    std::fs::write(dir.join("move.rhai"), script).unwrap();
}

#[test]
fn a_scripted_report_sweeps_the_shutter_samples_and_prices_motion_blur() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    moving(dir);
    std::fs::write(
        dir.join("sweep.ron"),
        "Sweep(axes: [Time(samples: [1, 4, 16])], reference: (aa: 16, time: 16))",
    )
    .unwrap();
    let run = |args: &[&str]| {
        let out = penumbra(
            dir,
            &[&["report", "scene.ron", "--runs", "1", "--quiet", "--width", "24"], args].concat(),
        );
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    };
    run(&["-o", "report", "--sweep", "sweep.ron", "--script", "move.rhai", "--frame", "0", "--fps", "1"]);
    let rows = rows(&dir.join("report"));
    let labels: Vec<&str> = rows.iter().map(|r| r.1.as_str()).collect();
    assert_eq!(labels, ["time 1", "time 4", "time 16"]);
    assert!(
        rows[0].2 > 1.5 * rows[1].2 && rows[1].2 > 1.5 * rows[2].2,
        "error does not fall with time samples: {rows:?}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report/results.json")).unwrap()).unwrap();
    assert_eq!(json["script"], "move.rhai, frame 0 at 1 fps");
    assert_eq!(json["reference"]["description"], "aa 16 jittered, time 16");
    // The first time-sampled point traces 4 times the primary rays of the first.
    let camera = |i: usize| json["points"][i]["rays"]["camera"].as_u64().unwrap();
    assert_eq!((camera(0), camera(1)), (24 * 18, 4 * 24 * 18));
    // The cost of motion blur: the scene as is against the same scene with no shutter.
    let costs = json["costs"].as_array().unwrap();
    assert!(
        costs.iter().any(|c| c["effect"] == "time" && c["seconds_off"].as_f64().unwrap() > 0.0),
        "{costs:?}"
    );
    assert!(std::fs::read_to_string(dir.join("report/index.html"))
        .unwrap()
        .contains("move.rhai, frame 0 at 1 fps"));

    // The default sweep has a time axis only where something moves.
    let axes = |out: &str| -> Vec<String> {
        let mut axes: Vec<String> = self::rows(&dir.join(out)).into_iter().map(|r| r.0).collect();
        axes.dedup();
        axes
    };
    run(&["-o", "posed", "--height", "12", "--script", "move.rhai"]);
    assert_eq!(axes("posed"), ["aa", "adaptive", "noise", "time"]);
    run(&["-o", "still", "--height", "12"]);
    assert_eq!(axes("still"), ["aa", "adaptive", "noise"]);
    let out = penumbra(dir, &["report", "scene.ron", "--frame", "3"]);
    assert_eq!(out.status.code(), Some(2), "--frame needs --script");
}

#[test]
fn a_reference_read_from_a_file_equal_to_a_variant_gives_zero_error() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("scene.ron"), scene(false)).unwrap();
    std::fs::write(dir.join("sweep.ron"), "Sweep(axes: [Aa(samples: [4, 16])])").unwrap();
    // The reference is the 16-sample render itself: that point must have RMSE 0, PSNR ∞, SSIM 1.
    let rendered = Command::new(BIN)
        .current_dir(dir)
        .args(["render", "scene.ron", "-o", "ref.exr", "--format", "exr-float", "--samples", "aa=16"])
        .output()
        .unwrap();
    assert!(rendered.status.success(), "{}", String::from_utf8_lossy(&rendered.stderr));
    let out = report(dir, false, &["--sweep", "sweep.ron", "--reference", "ref.exr"]);
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let row = text.lines().find(|l| l.contains("aa 16")).unwrap();
    assert!(row.contains(",0.000000e0,,inf,1.000000,"), "{row}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["points"][1]["psnr"], "inf");
}

/// Runs `penumbra ARGS` in `dir`.
fn penumbra(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(BIN).current_dir(dir).args(args).output().expect("the binary runs")
}

/// The `aa 16 jittered` row's RMSE of a report against `reference` made from the 16-sample render.
fn rmse_of_aa16(dir: &Path, reference: &str) -> f64 {
    let out = report(dir, false, &["--sweep", "sweep.ron", "--reference", reference]);
    rows(&out).into_iter().find(|r| r.1 == "aa 16 jittered").expect("an aa 16 row").2
}

#[test]
fn png_references_of_8_and_16_bits_are_read_as_linear() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("scene.ron"), scene(false)).unwrap();
    std::fs::write(dir.join("sweep.ron"), "Sweep(axes: [Aa(samples: [4, 16])])").unwrap();
    for (file, format) in [("ref8.png", "png8"), ("ref16.png", "png16"), ("ref.exr", "exr-float")] {
        let out =
            penumbra(dir, &["render", "scene.ron", "-o", file, "--format", format, "--samples", "aa=16"]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    assert_eq!(rmse_of_aa16(dir, "ref.exr"), 0.0);
    // Quantisation only: half a code value of sRGB is at most ~1.5e-3 in linear light (8 bits).
    let rmse8 = rmse_of_aa16(dir, "ref8.png");
    assert!(rmse8 < 2e-3, "8-bit PNG reference: RMSE {rmse8}");
    let rmse16 = rmse_of_aa16(dir, "ref16.png");
    assert!(rmse16 < 2e-5, "16-bit PNG reference: RMSE {rmse16}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report/results.json")).unwrap()).unwrap();
    assert!(json["reference"]["description"]
        .as_str()
        .unwrap()
        .contains("16-bit PNG, sRGB decoded to linear"));

    // A filmic PNG cannot be undone: refused plainly, with exit 2 and one message.
    let out = penumbra(dir, &["render", "scene.ron", "-o", "aces.png", "--tonemap", "aces"]);
    assert!(out.status.success());
    let out = penumbra(dir, &["report", "scene.ron", "--reference", "aces.png", "-o", "r2", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("aces.png: this PNG was tone-mapped with Aces"), "{stderr}");
    // Neither PNG nor EXR: said plainly, once.
    std::fs::write(dir.join("x.png"), "not an image").unwrap();
    let out = penumbra(dir, &["report", "scene.ron", "--reference", "x.png", "-o", "r3", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("x.png: not a PNG or EXR file") && !stderr.contains("EXR error"), "{stderr}");
}

#[test]
fn a_reference_from_another_scene_is_refused_unless_forced() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("scene.ron"), scene(false)).unwrap();
    std::fs::write(dir.join("other.ron"), scene(true)).unwrap();
    std::fs::write(dir.join("sweep.ron"), "Sweep(axes: [Aa(samples: [1])])").unwrap();
    let out = penumbra(dir, &["render", "other.ron", "-o", "other.exr", "--format", "exr-float"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let args =
        ["report", "scene.ron", "--sweep", "sweep.ron", "--reference", "other.exr", "-o", "r", "--quiet"];
    let out = penumbra(dir, &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("other.exr: the reference was made from scene other.ron (sha256 ")
            && stderr.contains("not from scene.ron (sha256 ")
            && stderr.contains("--force"),
        "{stderr}"
    );
    assert!(!dir.join("r/results.csv").exists(), "nothing is measured against the wrong scene");

    let out = penumbra(dir, &[&args[..], &["--force"]].concat());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("warning: other.exr: the reference was made from scene other.ron"), "{stderr}");
    assert!(dir.join("r/results.csv").is_file());

    // A PNG with no Penumbra metadata: used, with a warning that its scene cannot be checked.
    let out = penumbra(dir, &["render", "scene.ron", "-o", "plain.png"]);
    assert!(out.status.success());
    image::open(dir.join("plain.png")).unwrap().save(dir.join("stripped.png")).unwrap();
    let out = penumbra(
        dir,
        &[
            "report",
            "scene.ron",
            "--sweep",
            "sweep.ron",
            "--reference",
            "stripped.png",
            "-o",
            "r4",
            "--quiet",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("stripped.png: no Penumbra metadata") && stderr.contains("cannot be checked"),
        "{stderr}"
    );
}

#[test]
fn configurations_render_once_per_round_in_interleaved_rounds() {
    use penumbra::report::run::{effects_of, render_count, run, Options};
    use penumbra::report::sweep::SweepDesc;
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("scene.ron");
    std::fs::write(&path, scene(true)).unwrap();
    let mut desc = penumbra::scene::load_scene(&path).unwrap();
    (desc.camera.width, desc.camera.height) = (12, 9);
    // `aa 4` twice, and `area_light 4` is the scene's own light setting, as is the scene as is
    // that the area light's cost is measured against.
    let sweep =
        SweepDesc::parse("Sweep(axes: [Aa(samples: [4, 4]), AreaLight(samples: [4, 16])])", "sweep.ron")
            .unwrap();
    let options = Options { runs: 3, ..Options::default() };
    let labels = std::sync::Mutex::new(Vec::new());
    let progress = |label: &str| labels.lock().unwrap().push(label.to_owned());
    let report = run(&desc, "scene.ron", &sweep, &options, tmp.path(), &progress).unwrap();
    let labels = labels.into_inner().unwrap();
    // Distinct configurations: aa 4, area_light 4 (= the scene as is), area_light 16, area_light off.
    let round = ["aa 4 jittered", "area_light 4", "area_light 16", "area_light off"];
    let expected: Vec<&str> =
        std::iter::once("reference").chain(round.iter().copied().cycle().take(12)).collect();
    assert_eq!(labels, expected);
    let effects = effects_of(&desc, None).unwrap();
    assert_eq!(render_count(&desc, &effects, &sweep, &options), labels.len());
    // Both `aa 4` rows report the one configuration: same time, rays and error, 3 rounds each.
    let (a, b) = (&report.points[0], &report.points[1]);
    assert_eq!((&a.label, &b.label), (&"aa 4 jittered".to_owned(), &"aa 4 jittered".to_owned()));
    assert_eq!((a.config, a.seconds, a.rays, a.rmse), (b.config, b.seconds, b.rays, b.rmse));
    assert_eq!((a.runs, a.times.len()), (3, 3));
    assert_eq!(report.costs.len(), 1);
    assert_eq!(report.costs[0].seconds_on, report.points[2].seconds, "the scene as is is area_light 4");
}

#[test]
fn effects_have_one_name_in_the_command_line_and_the_report() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("sweep.ron"), "Sweep(axes: [Aa(samples: [1]), AreaLight(samples: [1, 2]), Glossy(samples: [1]), Lens(samples: [1]), Time(samples: [1])])").unwrap();
    let out = report(dir, true, &["--sweep", "sweep.ron", "--width", "8", "--height", "6"]);
    let rows = rows(&out);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).unwrap()).unwrap();
    let mut names: Vec<String> = rows.iter().map(|r| r.0.clone()).collect();
    names.extend(json["costs"].as_array().unwrap().iter().map(|c| c["effect"].as_str().unwrap().to_owned()));
    assert!(names.contains(&"area_light".to_owned()), "{names:?}");
    for (axis, label, _, _) in &rows {
        assert!(label.starts_with(&format!("{axis} ")), "label `{label}` does not name its axis `{axis}`");
    }
    // Every name the report prints is what `render --samples` and `--pattern` take.
    for name in &names {
        for (flag, value) in [("--samples", "2"), ("--pattern", "grid")] {
            let arg = format!("{name}={value}");
            let r = penumbra(dir, &["render", "scene.ron", "-o", "x.png", "--width", "8", flag, &arg]);
            assert!(r.status.success(), "{flag} {arg}: {}", String::from_utf8_lossy(&r.stderr));
        }
    }
    let r = penumbra(dir, &["render", "scene.ron", "-o", "x.png", "--samples", "bogus=2"]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("expected aa, lens, area_light, glossy or time"));
    // The older spelling still works.
    let r = penumbra(dir, &["render", "scene.ron", "-o", "x.png", "--width", "8", "--samples", "shadow=2"]);
    assert!(r.status.success());
}

#[test]
fn the_page_loads_in_headless_chromium_with_its_plots_and_no_console_error() {
    let Some(chromium) = ["chromium", "chromium-browser", "google-chrome"].iter().find_map(|name| {
        let found = Command::new("which").arg(name).output().ok()?;
        found.status.success().then(|| String::from_utf8_lossy(&found.stdout).trim().to_owned())
    }) else {
        eprintln!(
            "SKIPPED: no Chromium on this machine (install the Debian package `chromium`; .ci/run does)"
        );
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = report(tmp.path(), false, &["--width", "16", "--height", "12"]);
    // A checker page loads the report in a frame and lists every image that failed to load.
    std::fs::write(
        dir.join("check.html"),
        r#"<!doctype html><html><body><iframe id="r" src="index.html" width="1200" height="30000"></iframe>
<pre id="result">pending</pre>
<script>
// `window` load comes after the frame and its in-view images (the frame is tall enough that
// every lazy image is in view); any image still loading is polled with timers, which run in
// the virtual time that --dump-dom waits for (a promise such as decode() would not hold it).
window.addEventListener('load', () => {
  const images = Array.from(document.getElementById('r').contentDocument.images);
  images.forEach(i => { i.loading = 'eager'; });
  const report = () => {
    const broken = images.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.getAttribute('src'));
    const plots = images.filter(i => /error_vs_time|rays_vs_error|effect_costs|estimate_vs_error/.test(i.getAttribute('src') || ''));
    document.getElementById('result').textContent =
      'IMAGES=' + images.length + ' PLOTS=' + plots.length + ' BROKEN=' + JSON.stringify(broken);
  };
  let polls = 0;
  const poll = () => {
    polls += 1;
    if (images.every(i => i.complete) || polls > 300) { report(); } else { setTimeout(poll, 20); }
  };
  poll();
});
</script></body></html>"#,
    )
    .unwrap();
    let out = Command::new(&chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--allow-file-access-from-files",
            "--enable-logging=stderr",
            "--v=0",
            "--virtual-time-budget=10000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", tmp.path().join("profile").display()))
        .arg(format!("file://{}", dir.join("check.html").display()))
        .output()
        .expect("chromium runs");
    let dom = String::from_utf8_lossy(&out.stdout);
    let log = String::from_utf8_lossy(&out.stderr);
    let result = dom.split("<pre id=\"result\">").nth(1).and_then(|r| r.split("</pre>").next()).unwrap_or("");
    assert!(result.contains("BROKEN=[]"), "images failed to load: {result}\n{log}");
    let plots: usize = result
        .split("PLOTS=")
        .nth(1)
        .and_then(|p| p.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(plots >= 4, "the four plots are shown: {result}");
    let console_errors: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("CONSOLE") && (l.contains("rror") || l.contains("Failed to load")))
        .collect();
    assert!(console_errors.is_empty(), "console errors: {console_errors:?}");
}
