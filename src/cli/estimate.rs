//! What a render will cost before it starts: memory (film, per-tile results, AOVs, the scene's
//! meshes and grids, the encoder's copies and output) and work (camera samples, rays at
//! least), checked against what the machine has or `--max-memory`.
//!
//! The render holds the film (fixed and adaptive renders write their tiles into it in place;
//! noise-driven renders also hold every tile's results until the film is assembled), then the
//! film, the AOVs, the encoder's copies of every channel and the encoded file while it writes;
//! the peak is the larger of the two, plus the scene. Refusing a render that cannot fit (exit
//! 2, with the estimate) replaces an abort on a failed allocation hours later, and the largest
//! block is reserved once before rendering (exit 1 if even that fails).

use penumbra::film::{AovSet, OutputFormat};
use penumbra::scene::{LightDesc, SceneDesc};

use super::bad_input;

const GIB: f64 = (1u64 << 30) as f64;

/// Bytes a render needs at its peak, by part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MemoryEstimate {
    /// Film (linear RGB, f32).
    pub film: u64,
    /// Per-tile results held until the film is assembled (colour and cost): noise-driven
    /// renders only; fixed and adaptive renders write their tiles into the film in place.
    pub tiles: u64,
    /// AOV buffers.
    pub aovs: u64,
    /// The encoder's copies of every channel and the encoded bytes.
    pub encode: u64,
    /// Meshes (data, grids, laid-out triangles) and the top-level grid.
    pub scene: u64,
}

impl MemoryEstimate {
    /// The estimate for `desc` rendered with AOVs `aovs` into `format`.
    pub fn of(desc: &SceneDesc, aovs: AovSet, format: OutputFormat) -> Self {
        let n = u64::from(desc.camera.width) * u64::from(desc.camera.height);
        let aov_bytes = aov_bytes_per_pixel(aovs);
        let cost = if aovs.cost { 4 } else { 0 };
        let channel_bytes = |half: bool| {
            let colour = if half { 2 } else { 4 };
            let mut per_pixel = 3 * colour;
            per_pixel += if aovs.depth { 4 } else { 0 };
            per_pixel += if aovs.normal { 3 * colour } else { 0 };
            per_pixel += if aovs.albedo { 3 * colour } else { 0 };
            per_pixel += if aovs.object { 4 } else { 0 };
            per_pixel += cost;
            per_pixel
        };
        // EXR: a copy of every channel plus the file in memory (at most the raw size, with the
        // format's block overhead). PNG: the tone-mapped film, one 8- or 16-bit image at a time
        // and its file (measured: 31 B a pixel at 4096² for png8, against 31 estimated).
        let encode_per_pixel = match format {
            OutputFormat::ExrHalf => 2 * channel_bytes(true) + 1,
            OutputFormat::ExrFloat => 2 * channel_bytes(false) + 1,
            OutputFormat::Png8 => 12 + 2 * 3 + 1 + aov_png_bytes_per_pixel(aovs),
            OutputFormat::Png16 => 12 + 2 * 6 + 1 + aov_png_bytes_per_pixel(aovs),
        };
        let triangles: u64 = desc.assets.meshes.assets().iter().map(|a| a.data.triangle_count() as u64).sum();
        let meshes: u64 = desc.assets.meshes.assets().iter().map(|a| a.memory_bytes() as u64).sum();
        let objects = desc.objects.len() as u64;
        // Decoded images, each once however many textures share it.
        let mut rasters: Vec<&std::sync::Arc<penumbra::texture::Raster>> = Vec::new();
        for t in desc.assets.texture_table.iter() {
            if let penumbra::texture::Texture::Image { raster, .. } = t {
                if !rasters.iter().any(|seen| std::sync::Arc::ptr_eq(seen, raster)) {
                    rasters.push(raster);
                }
            }
        }
        let textures: u64 = rasters.iter().map(|r| r.memory_bytes() as u64).sum();
        Self {
            film: 12 * n,
            // Colour and cost per pixel, and the allocator's share of many small tile buffers
            // (8 B a pixel, measured at 2048² and 4096²).
            tiles: if desc.settings.noise.is_some() { (12 + cost + 8) * n } else { 0 },
            aovs: aov_bytes * n,
            encode: encode_per_pixel * n,
            // Triangles laid out for the store (≈ 48 B each), the top-level grid and tables, and
            // the process itself (code, threads, the World: 9 MiB measured at 64×48), and the
            // decoded texture images.
            scene: meshes + 48 * triangles + 256 * objects + textures + (8 << 20),
        }
    }

    /// The peak: the larger of rendering (tiles + film + cost) and writing (film + AOVs +
    /// encoding), plus the scene.
    pub fn peak(&self) -> u64 {
        let rendering = self.tiles + self.film + self.aovs;
        let writing = self.film + self.aovs + self.encode;
        rendering.max(writing) + self.scene
    }

    /// `about 33.3 GiB (film 3.0 GiB, AOVs 8.0 GiB, encoding 22.2 GiB, scene 8.0 MiB)`, with
    /// `tiles …` after the film where the render holds per-tile results (noise-driven renders).
    pub fn describe(&self) -> String {
        let tiles = match self.tiles {
            0 => String::new(),
            bytes => format!(", tiles {}", size(bytes)),
        };
        format!(
            "about {} (film {}{tiles}, AOVs {}, encoding {}, scene {})",
            size(self.peak()),
            size(self.film),
            size(self.aovs),
            size(self.encode),
            size(self.scene)
        )
    }
}

/// Bytes per pixel of the AOV buffers of `set`.
fn aov_bytes_per_pixel(set: AovSet) -> u64 {
    [(set.depth, 4), (set.normal, 12), (set.albedo, 12), (set.object, 4), (set.cost, 4)]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, b)| b)
        .sum()
}

/// Bytes per pixel of the false-colour PNGs written beside a PNG image: all of them are made
/// before they are written (8-bit RGB and its file each), and depth and cost are sorted once
/// for their scale.
fn aov_png_bytes_per_pixel(set: AovSet) -> u64 {
    let images =
        [set.depth, set.normal, set.albedo, set.object, set.cost].iter().filter(|on| **on).count() as u64;
    6 * images + if set.depth { 4 } else { 0 } + if set.cost { 4 } else { 0 }
}

/// A byte count in GiB (or MiB below 1 GiB) with one decimal.
pub fn size(bytes: u64) -> String {
    match bytes as f64 >= GIB {
        true => format!("{:.1} GiB", bytes as f64 / GIB),
        false => format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64),
    }
}

/// Parses `--max-memory`: a byte count with an optional unit (`K`, `M`, `G`, `T`, with or
/// without `iB`/`B`, powers of 1024), e.g. `512M`, `8G`, `1.5GiB`.
pub fn parse_size(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let digits = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (number, unit) = t.split_at(digits);
    let scale: u64 = match unit.trim().to_ascii_uppercase().as_str() {
        "" | "B" => 1,
        "K" | "KB" | "KIB" => 1 << 10,
        "M" | "MB" | "MIB" => 1 << 20,
        "G" | "GB" | "GIB" => 1 << 30,
        "T" | "TB" | "TIB" => 1 << 40,
        _ => return Err(format!("expected a size such as 512M, 8G or 1.5GiB, got `{s}`")),
    };
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v * (scale as f64) < u64::MAX as f64 => {
            Ok((v * scale as f64) as u64)
        }
        _ => Err(format!("expected a size > 0 such as 512M, 8G or 1.5GiB, got `{s}`")),
    }
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
pub fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// The machine's available memory (Linux `MemAvailable`), if known.
pub fn machine_memory() -> Option<u64> {
    mem_available(&std::fs::read_to_string("/proc/meminfo").ok()?)
}

/// This process's peak resident memory so far (Linux `VmHWM`), in bytes, if known.
pub fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<u64>().ok()? * 1024)
}

/// Refuses (exit 2, with the estimate) a render that needs more than `max_memory` or, without
/// it, more than the machine has available; then reserves the peak once (exit 1 if the system
/// cannot give it), so no allocation fails half-way.
pub fn check_memory(estimate: &MemoryEstimate, max_memory: Option<u64>) -> anyhow::Result<()> {
    let (limit, what) = match max_memory {
        Some(limit) => (Some(limit), "--max-memory allows".to_owned()),
        None => (machine_memory(), "this machine has available".to_owned()),
    };
    if let Some(limit) = limit {
        if estimate.peak() > limit {
            return Err(bad_input(format!(
                "the render needs {} but {what} {}; lower --width/--height, drop AOVs, write \
                 exr-half or PNG, or raise --max-memory",
                estimate.describe(),
                size(limit)
            )));
        }
    }
    let mut probe: Vec<u8> = Vec::new();
    let peak = usize::try_from(estimate.peak()).unwrap_or(usize::MAX);
    probe.try_reserve_exact(peak).map_err(|_| {
        anyhow::anyhow!("cannot reserve memory for the render: it needs {}", estimate.describe())
    })?;
    Ok(())
}

/// The work a frame asks for: camera samples (pixels × AA × lens samples, the most adaptive
/// sampling may take) and, with lights, the shadow rays they bring at least.
pub fn work(desc: &SceneDesc) -> String {
    let pixels = u64::from(desc.camera.width) * u64::from(desc.camera.height);
    let aa = u64::from(match &desc.settings.adaptive {
        // Depth d subdivides a pixel into at most 4^d cells, (2^d + 1)^2 corners.
        Some(a) => (2u32.pow(a.max_depth) + 1).pow(2),
        None => desc.settings.aa.samples.max(1),
    });
    let lens = if desc.camera.aperture > 0.0 { u64::from(desc.camera.lens.samples.max(1)) } else { 1 };
    let samples = pixels.saturating_mul(aa).saturating_mul(lens);
    let shadow: u64 = desc
        .lights
        .iter()
        .map(|l| match l {
            LightDesc::Rect { samples, .. } | LightDesc::Disk { samples, .. } => u64::from((*samples).max(1)),
            _ => 1,
        })
        .sum();
    let mut text = format!("{} camera samples", count(samples));
    if shadow > 0 {
        text += &format!(", at least {} rays", count(samples.saturating_mul(1 + shadow)));
    }
    text
}

/// `1.1e12`, or the plain number below a million.
fn count(n: u64) -> String {
    match n < 1_000_000 {
        true => n.to_string(),
        false => format!("{:.1e}", n as f64),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(width: u32, height: u32) -> SceneDesc {
        let mut desc = penumbra::scene::default_scene();
        desc.camera.width = width;
        desc.camera.height = height;
        desc
    }

    #[test]
    fn the_issue_s_oversized_request_is_far_over_24_gib() {
        let all = AovSet::parse("depth,normal,albedo,object,cost").unwrap();
        let e = MemoryEstimate::of(&scene(16384, 16384), all, OutputFormat::ExrFloat);
        let n = 16384u64 * 16384;
        assert_eq!(e.film, 12 * n);
        assert_eq!(e.aovs, 36 * n);
        // Copies of 3·4 + 4 + 3·4 + 3·4 + 4 + 4 = 48 B a pixel, and the file.
        assert_eq!(e.encode, (2 * 48 + 1) * n);
        assert!(e.peak() > 24 << 30, "{}", e.describe());
        let small = MemoryEstimate::of(&scene(64, 48), AovSet::default(), OutputFormat::Png8);
        assert!(small.peak() < 16 << 20, "{}", small.describe());
        assert!(check_memory(&e, Some(1 << 30))
            .unwrap_err()
            .to_string()
            .contains("--max-memory allows 1.0 GiB"));
        check_memory(&small, Some(1 << 30)).unwrap();
        let png = MemoryEstimate::of(&scene(100, 10), AovSet::default(), OutputFormat::Png8);
        assert_eq!(png.encode, (12 + 3 + 3 + 1) * 1000, "tone-mapped copy, 8-bit image, file");
    }

    #[test]
    fn only_noise_driven_renders_hold_tile_results() {
        let fixed = MemoryEstimate::of(&scene(100, 10), AovSet::default(), OutputFormat::Png8);
        assert_eq!(fixed.tiles, 0, "fixed renders write tiles into the film");
        assert!(!fixed.describe().contains("tiles"), "{}", fixed.describe());
        let mut desc = scene(100, 10);
        desc.settings.noise = Some(penumbra::sample::noise::NoiseSettings::default());
        let cost = AovSet::parse("cost").unwrap();
        let noisy = MemoryEstimate::of(&desc, cost, OutputFormat::Png8);
        assert_eq!(noisy.tiles, (12 + 4 + 8) * 1000, "colour, cost and the allocator's share");
        assert!(noisy.describe().contains("(film 0.0 MiB, tiles 0.0 MiB, AOVs"), "{}", noisy.describe());
        assert!(noisy.peak() > fixed.peak());
    }

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("8G"), Ok(8 << 30));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("1000"), Ok(1000));
        for bad in ["", "G", "-1G", "0", "5X", "nanG"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        assert_eq!(size(3 << 29), "1.5 GiB");
        assert_eq!(size(3 << 19), "1.5 MiB");
    }

    #[test]
    fn available_memory_is_read_from_meminfo() {
        let text = "MemTotal:       24576000 kB\nMemFree:         1000 kB\nMemAvailable:   20000000 kB\n";
        assert_eq!(mem_available(text), Some(20_000_000 * 1024));
        assert_eq!(mem_available("MemTotal: 1 kB\n"), None);
    }

    #[test]
    fn work_counts_camera_samples_and_shadow_rays() {
        let mut desc = scene(100, 100);
        desc.settings.adaptive = None;
        desc.settings.aa.samples = 4;
        desc.camera.aperture = 0.0;
        let lights = desc.lights.len() as u64;
        let text = work(&desc);
        assert!(text.starts_with("40000 camera samples"), "{text}");
        if lights > 0 {
            assert!(text.contains("at least"), "{text}");
        }
        desc.camera.width = 16384;
        desc.camera.height = 16384;
        desc.settings.aa.samples = 4096;
        assert!(work(&desc).starts_with("1.1e12 camera samples"), "{}", work(&desc));
    }
}
