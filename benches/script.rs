//! Question: what does a script cost per frame, next to the frame it animates?
//!
//! The default scene at 320×240. Per frame, an animation runs the script's `frame(t)` (after
//! its top level) and updates the World (applies the writes, derives bounds, rebuilds the
//! grid if something moved, takes the snapshot). Two scripts: `moving` orbits the camera,
//! moves a ball, follows it with `focus_on` and changes a material (a grid rebuild every
//! frame); `still` writes the same values every frame (no rebuild). The table gives each
//! one's median overhead as a fraction of the median render of one frame.
//!
//! Run: `cargo bench --bench script` (criterion, then the table);
//! `cargo bench --bench script -- zzz` prints only the table.

mod harness;

use std::hint::black_box;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use penumbra::scene::{self, SceneDesc};
use penumbra::script::{Animation, Limits, Script};
use penumbra::trace::render;

const SIZE: (u32, u32) = (320, 240);

const MOVING: &str = r#"
const ORBIT = 9.0;
fn frame(t) {
    camera.position = vec3(ORBIT_X(t), 2.5, -global::ORBIT * cos(0.5 * t));
    camera.look_at = vec3(0, 0.8, 0);
    let ball = entity("red_ball");
    ball.position = vec3(0.5 * sin(2.0 * t), 0.3 * abs(sin(3.0 * t)), 0);
    camera.focus_on("red_ball");
    let gold = entity("gold_box");
    gold.kd = lerp(vec3(0.7, 0.5, 0.15), vec3(0.9, 0.8, 0.3), 0.5 + 0.5 * sin(t));
}
fn ORBIT_X(t) { global::ORBIT * sin(0.5 * t) }
"#;

const STILL: &str = r#"
fn frame(t) {
    camera.look_at = vec3(0, 0.8, 0);
    let ball = entity("red_ball");
    ball.position = vec3(0, 0, 0);
    let gold = entity("gold_box");
    gold.kd = vec3(0.7, 0.5, 0.15);
}
"#;

fn desc() -> SceneDesc {
    let mut d = scene::default_scene();
    (d.camera.width, d.camera.height) = SIZE;
    d
}

fn animation(source: &str) -> Animation {
    let script = Script::from_source("bench.rhai", source, Limits::default()).expect("bench script compiles");
    Animation::new(&desc(), &script, 24.0).expect("bench script runs")
}

fn bench_script(c: &mut Criterion) {
    let mut group = c.benchmark_group("script");
    for (name, source) in [("moving", MOVING), ("still", STILL)] {
        let mut anim = animation(source);
        let mut frame = 0;
        group.bench_function(BenchmarkId::new("frame_overhead", name), |b| {
            b.iter(|| {
                frame += 1;
                black_box(anim.step_to(frame).expect("frame runs"))
            })
        });
    }
    let mut anim = animation(MOVING);
    let snapshot = anim.step_to(0).expect("frame runs");
    let settings = anim.world().world().render_settings();
    group.bench_function(BenchmarkId::new("render", "320x240"), |b| {
        b.iter(|| black_box(render(&snapshot, &settings)))
    });
    group.finish();
}

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn print_table() {
    const FRAMES: u32 = 101;
    let mut anim = animation(MOVING);
    let renders: Vec<f64> = (0..9)
        .map(|n| {
            let snapshot = anim.step_to(n).expect("frame runs");
            let settings = anim.world().world().render_settings();
            let t = Instant::now();
            black_box(render(&snapshot, &settings));
            t.elapsed().as_secs_f64()
        })
        .collect();
    let render_s = median(renders);
    println!(
        "\nscript overhead per frame, default scene at {}x{}, {} threads (medians of {FRAMES} frames; render: median of 9)",
        SIZE.0,
        SIZE.1,
        rayon::current_num_threads()
    );
    println!(
        "{:>8} {:>11} {:>11} {:>11} {:>9} {:>10}",
        "script", "script µs", "update µs", "total µs", "rebuilds", "of frame"
    );
    for (name, source) in [("moving", MOVING), ("still", STILL)] {
        let mut anim = animation(source);
        anim.step_to(0).expect("frame runs");
        let before = anim.world().world().grid_rebuilds();
        let (mut script, mut update, mut total) = (Vec::new(), Vec::new(), Vec::new());
        for n in 1..=FRAMES {
            let t = Instant::now();
            black_box(anim.step_to(n).expect("frame runs"));
            total.push(t.elapsed().as_secs_f64());
            let (s, u) = anim.last_timing();
            script.push(s);
            update.push(u);
        }
        let rebuilds = anim.world().world().grid_rebuilds() - before;
        let total_s = median(total);
        println!(
            "{name:>8} {:>11.1} {:>11.1} {:>11.1} {rebuilds:>9} {:>9.2}%",
            median(script) * 1e6,
            median(update) * 1e6,
            total_s * 1e6,
            100.0 * total_s / render_s
        );
    }
    println!("{:>8} {:>35.1} ms", "render", render_s * 1e3);
}

fn main() {
    harness::run(20, bench_script, print_table);
}
