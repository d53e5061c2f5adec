//! The manifest of a frames folder: what the job is (`.penumbra/job.json`) and, per finished
//! frame, what it was made from (`.penumbra/frame_0042.json`). Each file is written atomically
//! on its own, so shards on many machines share a folder without locks.
//!
//! A frame is *done* when its image and its entry exist and the entry's inputs hash equals
//! the hash of the current scene, script and options for that frame; *stale* when they exist
//! but the inputs changed; *missing* otherwise. The entry is written after the image, so a
//! run killed between the two leaves a frame that counts as missing and is rendered again.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::film::{write_atomically, OutputError};
use crate::script::FrameRange;
use crate::trace::RenderStats;

/// The folder inside a frames folder that holds the manifest.
pub const MANIFEST_DIR: &str = ".penumbra";

/// Hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// File name of frame `n` of `range`: `frame_0042.png`, with at least four digits and as many
/// as the range's last frame needs, so names sort in frame order.
pub fn frame_file_name(range: FrameRange, n: u32, extension: &str) -> String {
    let digits = frame_digits(range);
    format!("frame_{n:0digits$}.{extension}")
}

/// Digits in frame file names of `range`.
pub fn frame_digits(range: FrameRange) -> usize {
    range.last.to_string().len().max(4)
}

/// What a frames folder is for: enough to tell, later and elsewhere, whether a frame is
/// current.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobSpec {
    /// Program version that made the frames.
    pub version: String,
    /// The scene file (absolute).
    pub scene: PathBuf,
    /// The script file (absolute).
    pub script: PathBuf,
    /// The whole range (all shards).
    pub frames: FrameRange,
    /// Frames per second.
    pub fps: f64,
    /// Every option that changes the pixels, as text (sizes, samples, format, tone mapping).
    pub options: String,
    /// Image file extension.
    pub extension: String,
}

impl JobSpec {
    /// The inputs hash of frame `n`: version, scene and script contents, fps, options and the
    /// frame number.
    pub fn inputs_hash(&self, scene: &[u8], script: &[u8], n: u32) -> String {
        let mut h = Sha256::new();
        for part in
            [self.version.as_bytes(), &sha256_hex(scene).into_bytes(), &sha256_hex(script).into_bytes()]
        {
            h.update((part.len() as u64).to_le_bytes());
            h.update(part);
        }
        h.update(self.fps.to_le_bytes());
        h.update((self.options.len() as u64).to_le_bytes());
        h.update(self.options.as_bytes());
        h.update(n.to_le_bytes());
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// File name of frame `n`.
    pub fn file_name(&self, n: u32) -> String {
        frame_file_name(self.frames, n, &self.extension)
    }
}

/// What one finished frame was made from and what it cost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameEntry {
    /// Frame number.
    pub frame: u32,
    /// Image file name (in the frames folder).
    pub file: String,
    /// Inputs hash ([`JobSpec::inputs_hash`]).
    pub inputs: String,
    /// Seed of the frame's randomness.
    pub seed: u64,
    /// Render settings, as text.
    pub settings: String,
    /// Seconds of tracing.
    pub render_seconds: f64,
    /// Seconds from the start of the frame to its file renamed into place.
    pub total_seconds: f64,
    /// Rays by kind.
    pub rays: BTreeMap<String, u64>,
    /// Million rays per second of tracing.
    pub mrays_per_s: f64,
    /// Host that rendered it.
    pub host: String,
    /// Shard that rendered it (`INDEX/COUNT`).
    pub shard: String,
}

impl FrameEntry {
    /// Rays by kind of `stats` as the entry stores them.
    pub fn rays_of(stats: &RenderStats) -> BTreeMap<String, u64> {
        stats.rays.kinds().iter().map(|(k, n)| (k.to_string(), *n)).collect()
    }
}

/// Errors reading or writing a manifest.
#[derive(Debug, thiserror::Error)]
pub enum ManifestError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A manifest file is not what it should be.
    #[error("{path}: not a Penumbra manifest file ({reason})")]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// Writing failed.
    #[error(transparent)]
    Write(#[from] OutputError),
}

/// The manifest of one frames folder.
#[derive(Debug, Clone)]
pub struct Manifest {
    dir: PathBuf,
}

impl Manifest {
    /// The manifest of frames folder `dir` (created with its manifest folder if missing).
    pub fn create(dir: &Path) -> Result<Self, ManifestError> {
        let manifest = Self { dir: dir.to_path_buf() };
        let sub = manifest.dir.join(MANIFEST_DIR);
        std::fs::create_dir_all(&sub).map_err(|source| ManifestError::Io { path: sub, source })?;
        Ok(manifest)
    }

    /// The manifest of an existing frames folder (nothing is created).
    pub fn open(dir: &Path) -> Self {
        Self { dir: dir.to_path_buf() }
    }

    /// The frames folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn job_path(&self) -> PathBuf {
        self.dir.join(MANIFEST_DIR).join("job.json")
    }

    fn entry_path(&self, n: u32) -> PathBuf {
        self.dir.join(MANIFEST_DIR).join(format!("frame_{n:04}.json"))
    }

    /// Records the job (every shard writes the same).
    pub fn write_job(&self, job: &JobSpec) -> Result<(), ManifestError> {
        let bytes = serde_json::to_vec_pretty(job).expect("a job spec always encodes");
        Ok(write_atomically(&self.job_path(), &bytes)?)
    }

    /// The recorded job, or `None` if no run has recorded one.
    pub fn read_job(&self) -> Result<Option<JobSpec>, ManifestError> {
        read_json(&self.job_path())
    }

    /// Records a finished frame (after its image is in place).
    pub fn write_entry(&self, entry: &FrameEntry) -> Result<(), ManifestError> {
        let bytes = serde_json::to_vec_pretty(entry).expect("a frame entry always encodes");
        Ok(write_atomically(&self.entry_path(entry.frame), &bytes)?)
    }

    /// The entry of frame `n`, if recorded.
    pub fn read_entry(&self, n: u32) -> Result<Option<FrameEntry>, ManifestError> {
        read_json(&self.entry_path(n))
    }

    /// The state of frame `n` given its current inputs hash.
    pub fn frame_state(&self, job: &JobSpec, n: u32, inputs: &str) -> Result<FrameState, ManifestError> {
        if !self.dir.join(job.file_name(n)).is_file() {
            return Ok(FrameState::Missing);
        }
        Ok(match self.read_entry(n)? {
            None => FrameState::Missing,
            Some(entry) if entry.inputs == inputs && entry.file == job.file_name(n) => FrameState::Done,
            Some(_) => FrameState::Stale,
        })
    }

    /// Temporary files left in the folder by runs killed while writing (`.penumbra-*.tmp`).
    pub fn stray_temporaries(&self) -> Vec<String> {
        let mut found: Vec<String> = [self.dir.clone(), self.dir.join(MANIFEST_DIR)]
            .iter()
            .filter_map(|d| std::fs::read_dir(d).ok())
            .flatten()
            .filter_map(Result::ok)
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(".penumbra-") && n.ends_with(".tmp"))
            .collect();
        found.sort();
        found
    }
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<Option<T>, ManifestError> {
    match std::fs::read(path) {
        Ok(bytes) => serde_json::from_slice(&bytes)
            .map(Some)
            .map_err(|e| ManifestError::Corrupt { path: path.to_path_buf(), reason: e.to_string() }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(source) => Err(ManifestError::Io { path: path.to_path_buf(), source }),
    }
}

/// Where a frame stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FrameState {
    /// Its image and entry exist and match the current inputs.
    Done,
    /// Its image or entry is absent.
    Missing,
    /// It exists but was made from other inputs.
    Stale,
}

/// The state of every frame of a job.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Status {
    /// The frames folder.
    pub dir: PathBuf,
    /// The job's range.
    pub frames: FrameRange,
    /// Frames done.
    pub done: Vec<u32>,
    /// Frames not rendered yet.
    pub missing: Vec<u32>,
    /// Frames whose inputs changed.
    pub stale: Vec<u32>,
    /// Temporary files left by killed runs.
    pub stray_temporaries: Vec<String>,
}

/// The status of a frames folder against the current scene and script files.
pub fn status(dir: &Path) -> Result<Status, ManifestError> {
    let manifest = Manifest::open(dir);
    let job = manifest.read_job()?.ok_or_else(|| ManifestError::Corrupt {
        path: manifest.job_path(),
        reason: "no job recorded: this folder was not written by `penumbra animate`".into(),
    })?;
    let read = |path: &Path| {
        std::fs::read(path).map_err(|source| ManifestError::Io { path: path.to_path_buf(), source })
    };
    let (scene, script) = (read(&job.scene)?, read(&job.script)?);
    let mut out = Status {
        dir: dir.to_path_buf(),
        frames: job.frames,
        done: Vec::new(),
        missing: Vec::new(),
        stale: Vec::new(),
        stray_temporaries: manifest.stray_temporaries(),
    };
    for n in job.frames.iter() {
        match manifest.frame_state(&job, n, &job.inputs_hash(&scene, &script, n))? {
            FrameState::Done => out.done.push(n),
            FrameState::Missing => out.missing.push(n),
            FrameState::Stale => out.stale.push(n),
        }
    }
    Ok(out)
}

/// Frame numbers as compact ranges: `0..=3, 7, 9..=12`.
pub fn ranges(frames: &[u32]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < frames.len() {
        let mut j = i;
        while j + 1 < frames.len() && frames[j + 1] == frames[j] + 1 {
            j += 1;
        }
        parts.push(match j > i {
            true => format!("{}..={}", frames[i], frames[j]),
            false => frames[i].to_string(),
        });
        i = j + 1;
    }
    match parts.is_empty() {
        true => "none".into(),
        false => parts.join(", "),
    }
}

#[cfg(test)]
mod tests {
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
        }
    }

    #[test]
    fn inputs_hash_changes_with_every_input() {
        let dir = Path::new("/x");
        let base = job(dir).inputs_hash(b"scene", b"script", 1);
        assert_eq!(base, job(dir).inputs_hash(b"scene", b"script", 1));
        assert_ne!(base, job(dir).inputs_hash(b"scene!", b"script", 1));
        assert_ne!(base, job(dir).inputs_hash(b"scene", b"script!", 1));
        assert_ne!(base, job(dir).inputs_hash(b"scene", b"script", 2));
        assert_ne!(base, JobSpec { fps: 30.0, ..job(dir) }.inputs_hash(b"scene", b"script", 1));
        assert_ne!(
            base,
            JobSpec { options: "width 9".into(), ..job(dir) }.inputs_hash(b"scene", b"script", 1)
        );
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
        let entry = |n: u32, inputs: String| FrameEntry {
            frame: n,
            file: j.file_name(n),
            inputs,
            seed: 1,
            settings: String::new(),
            render_seconds: 0.1,
            total_seconds: 0.2,
            rays: BTreeMap::new(),
            mrays_per_s: 1.0,
            host: "h".into(),
            shard: "0/1".into(),
        };
        for n in [0, 1, 2] {
            std::fs::write(dir.join(j.file_name(n)), "png").unwrap();
        }
        m.write_entry(&entry(0, j.inputs_hash(b"scene", b"script", 0))).unwrap();
        m.write_entry(&entry(1, j.inputs_hash(b"old scene", b"script", 1))).unwrap();
        // Frame 2 has an image but no entry (killed between the two writes); 3 has nothing.
        let s = status(dir).unwrap();
        assert_eq!((s.done, s.stale, s.missing), (vec![0], vec![1], vec![2, 3]));
        assert!(s.stray_temporaries.is_empty());
    }

    #[test]
    fn frame_lists_print_as_ranges() {
        assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10]), "0..=3, 7, 9..=10");
        assert_eq!(ranges(&[]), "none");
        assert_eq!(frame_file_name(FrameRange::new(0, 119), 7, "png"), "frame_0007.png");
        assert_eq!(frame_file_name(FrameRange::new(0, 123456), 7, "exr"), "frame_000007.exr");
    }
}
