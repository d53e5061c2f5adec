//! The manifest of a frames folder: what the job is (`.penumbra/job.json`) and, per finished
//! frame, what it was made from (`.penumbra/frame_0042.json`). Each file is written atomically
//! on its own, so shards on many machines share a folder.
//!
//! A frame is *done* when its image and its entry exist and the entry's inputs hash equals
//! the hash of the current inputs (scene, script, every mesh file) and options for that frame;
//! *stale* when they exist but the inputs changed (the entry lists each input's hash, so
//! [`status`] names the files that changed); *missing* otherwise. The entry is written after
//! the image, so a run killed between the two leaves a frame that counts as missing and is
//! rendered again.
//!
//! Runs that overlap on one folder (two `animate` processes, or shards whose ranges overlap)
//! coordinate through advisory locks (`flock` on Unix) in `.penumbra/`: each run holds
//! `run.lock` shared while it works, and a frame is rendered only by the run that holds its
//! `locks/frame_0042.lock`; the other skips it. The kernel drops a killed process's locks. A
//! run that finds no other run active (it gets `run.lock` exclusively) first removes the
//! temporary files earlier, killed runs left behind. On a network file system the locks work
//! where it supports `flock` (NFSv4, Lustre mounted with `flock`); without it overlapping runs
//! may render a frame twice, but every write stays atomic, so the folder is never corrupt.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::film::{write_atomically, OutputError};
use crate::scene::inputs::{InputFile, InputRole, Inputs};
use crate::script::FrameRange;
use crate::trace::RenderStats;

/// The folder inside a frames folder that holds the manifest.
pub const MANIFEST_DIR: &str = ".penumbra";

pub use crate::scene::inputs::sha256_hex;

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
    /// Every input file (scene, script, meshes) with its absolute path and its hash when the
    /// job was last started; [`status`] reads them again from there. Empty in folders written
    /// before inputs were recorded (then the scene and script above are the inputs).
    #[serde(default)]
    pub inputs: Vec<InputFile>,
}

impl JobSpec {
    /// The inputs hash of frame `n`: version, the contents of every input file
    /// ([`Inputs::fingerprint`]), fps, options and the frame number.
    pub fn inputs_hash(&self, inputs: &Inputs, n: u32) -> String {
        let mut h = Sha256::new();
        for part in [self.version.as_bytes(), inputs.fingerprint().as_bytes()] {
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
    /// The SIMD level that traced it, resolved (`scalar`, `baseline`, `avx2`, `avx512`; empty in
    /// entries written before it was recorded). Informational, like the host: every level gives
    /// the same pixels, so it is no part of the inputs hash.
    #[serde(default)]
    pub simd: String,
    /// Shard that rendered it (`INDEX/COUNT`).
    pub shard: String,
    /// The input files it was made from, with their hashes (empty in entries written before
    /// inputs were recorded).
    #[serde(default)]
    pub files: Vec<InputFile>,
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
    /// The frames folder does not exist.
    #[error("{}: no such folder", path.display())]
    NoFolder {
        /// The folder.
        path: PathBuf,
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

    /// Joins the runs working on this folder: holds `run.lock` shared until the returned lock
    /// is dropped. When no other run is active it first removes the temporary files killed runs
    /// left (the lock's `removed` lists them).
    pub fn join_runs(&self) -> Result<RunLock, ManifestError> {
        let path = self.dir.join(MANIFEST_DIR).join("run.lock");
        let io = |source| ManifestError::Io { path: path.clone(), source };
        let file =
            std::fs::OpenOptions::new().create(true).truncate(false).write(true).open(&path).map_err(io)?;
        let mut removed = Vec::new();
        match file.try_lock() {
            Ok(()) => {
                // Alone: every temporary file here belongs to a run that is gone.
                for name in self.stray_temporaries() {
                    let at = [self.dir.join(&name), self.dir.join(MANIFEST_DIR).join(&name)];
                    if at.iter().any(|p| std::fs::remove_file(p).is_ok()) {
                        removed.push(name);
                    }
                }
                file.lock_shared().map_err(io)?;
            }
            Err(std::fs::TryLockError::WouldBlock) => file.lock_shared().map_err(io)?,
            Err(std::fs::TryLockError::Error(e)) => return Err(io(e)),
        }
        Ok(RunLock { _file: file, removed })
    }

    /// Claims frame `n` for this run: `Some` while no other run renders it (the claim lasts
    /// until dropped), `None` when another run holds it.
    pub fn claim(&self, n: u32) -> Result<Option<FrameClaim>, ManifestError> {
        let dir = self.dir.join(MANIFEST_DIR).join("locks");
        std::fs::create_dir_all(&dir).map_err(|source| ManifestError::Io { path: dir.clone(), source })?;
        let path = dir.join(format!("frame_{n:04}.lock"));
        let io = |source| ManifestError::Io { path: path.clone(), source };
        let file =
            std::fs::OpenOptions::new().create(true).truncate(false).write(true).open(&path).map_err(io)?;
        match file.try_lock() {
            Ok(()) => Ok(Some(FrameClaim { _file: file })),
            Err(std::fs::TryLockError::WouldBlock) => Ok(None),
            Err(std::fs::TryLockError::Error(e)) => Err(io(e)),
        }
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

/// A run's share of a frames folder ([`Manifest::join_runs`]); released when dropped.
#[derive(Debug)]
pub struct RunLock {
    _file: std::fs::File,
    /// Temporary files of killed runs removed on joining (empty when another run was active).
    pub removed: Vec<String>,
}

/// A run's exclusive claim on one frame ([`Manifest::claim`]); released when dropped.
#[derive(Debug)]
pub struct FrameClaim {
    _file: std::fs::File,
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
    /// The inputs (`role name`, e.g. `mesh bunny.obj`) whose contents differ from what stale
    /// frames were made from; empty when only the options or the program version changed (or
    /// the frames predate per-file records).
    pub changed: Vec<String>,
    /// Temporary files left by killed runs.
    pub stray_temporaries: Vec<String>,
}

/// The current inputs of `job`: each recorded input file read again at its path (for folders
/// that predate per-file records, the scene and the script).
pub fn current_inputs(job: &JobSpec) -> Result<Inputs, ManifestError> {
    let recorded = match job.inputs.is_empty() {
        false => job.inputs.clone(),
        true => [(InputRole::Scene, &job.scene), (InputRole::Script, &job.script)]
            .into_iter()
            .map(|(role, path)| InputFile {
                role,
                name: path.display().to_string(),
                path: Some(path.clone()),
                sha256: String::new(),
            })
            .collect(),
    };
    let mut files = Vec::with_capacity(recorded.len());
    for file in recorded {
        let path = file.path.clone().unwrap_or_else(|| PathBuf::from(&file.name));
        let bytes =
            std::fs::read(&path).map_err(|source| ManifestError::Io { path: path.clone(), source })?;
        files.push(InputFile { sha256: sha256_hex(&bytes), ..file });
    }
    Ok(Inputs { files })
}

/// The status of a frames folder against the current input files.
pub fn status(dir: &Path) -> Result<Status, ManifestError> {
    if !dir.is_dir() {
        return Err(ManifestError::NoFolder { path: dir.to_path_buf() });
    }
    let manifest = Manifest::open(dir);
    let job = manifest.read_job()?.ok_or_else(|| ManifestError::Corrupt {
        path: manifest.job_path(),
        reason: "no job recorded: this folder was not written by `penumbra animate`".into(),
    })?;
    let inputs = current_inputs(&job)?;
    let mut out = Status {
        dir: dir.to_path_buf(),
        frames: job.frames,
        done: Vec::new(),
        missing: Vec::new(),
        stale: Vec::new(),
        changed: Vec::new(),
        stray_temporaries: manifest.stray_temporaries(),
    };
    for n in job.frames.iter() {
        match manifest.frame_state(&job, n, &job.inputs_hash(&inputs, n))? {
            FrameState::Done => out.done.push(n),
            FrameState::Missing => out.missing.push(n),
            FrameState::Stale => {
                out.stale.push(n);
                let made_from = manifest.read_entry(n)?.map(|e| e.files).unwrap_or_default();
                for now in &inputs.files {
                    let label = now.label();
                    let then = made_from.iter().find(|f| f.role == now.role && f.name == now.name);
                    let differs = match then {
                        Some(then) => then.sha256 != now.sha256,
                        // Not among the frame's inputs: a mesh the scene did not name then.
                        None => !made_from.is_empty(),
                    };
                    if differs && !out.changed.contains(&label) {
                        out.changed.push(label);
                    }
                }
            }
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
mod tests;
