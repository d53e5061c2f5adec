//! Times OBJ loading: `cargo run --release --example obj_load_time -- FILE.obj...`
//! (default `scenes/bunny_res3.obj`).
//!
//! For each file it prints the best of five runs of: reading the bytes, tobj alone
//! (`load_obj_buf` with the options `parse_obj` uses), `parse_obj` without normals (own checks +
//! tobj + merge), `vertex_normals` alone, and `load_obj` with smooth normals (everything).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use penumbra::geom::mesh::vertex_normals;
use penumbra::scene::obj::{load_obj, parse_obj};

/// The fastest of five runs of `f`, and its last result.
fn best_of_five<T>(mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut best = Duration::MAX;
    let mut last = None;
    for _ in 0..5 {
        let start = Instant::now();
        let value = f();
        best = best.min(start.elapsed());
        last = Some(value);
    }
    // Five runs always leave a value.
    (best, last.expect("ran at least once"))
}

fn ms(d: Duration) -> String {
    format!("{:8.1} ms", d.as_secs_f64() * 1e3)
}

fn main() -> anyhow::Result<()> {
    let mut files: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    if files.is_empty() {
        files.push("scenes/bunny_res3.obj".into());
    }
    println!("threads: {}", rayon::current_num_threads());
    for path in &files {
        let (read, bytes) = best_of_five(|| std::fs::read(path));
        let text = String::from_utf8(bytes?)?;
        let options = penumbra::scene::obj::load_options();
        let (tobj_only, models) = best_of_five(|| {
            tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        });
        let tobj_tris: usize = models?.0.iter().map(|m| m.mesh.indices.len() / 3).sum();
        let (flat, mesh) = best_of_five(|| parse_obj(&text, path, false));
        let mesh = mesh?;
        let (normals, _) = best_of_five(|| vertex_normals(&mesh.positions, &mesh.indices));
        let (total, smooth) = best_of_five(|| load_obj(path, true));
        let smooth = smooth?;
        assert_eq!(tobj_tris, smooth.triangle_count());
        println!("{}", path.display());
        println!(
            "  {} triangles, {} vertices, {:.1} MB of arrays; {:.1} MB of text",
            smooth.triangle_count(),
            smooth.positions.len(),
            smooth.memory_bytes() as f64 / 1e6,
            text.len() as f64 / 1e6
        );
        println!("  read bytes          {}", ms(read));
        println!("  tobj alone          {}", ms(tobj_only));
        println!("  parse_obj, flat     {}  (own checks + tobj + merge)", ms(flat));
        println!("  vertex_normals      {}", ms(normals));
        println!("  load_obj, smooth    {}  (read + parse + normals)", ms(total));
    }
    Ok(())
}
