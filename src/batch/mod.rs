//! Batch frame sequences: shards of a frame range for job arrays (Slurm, Kubernetes Indexed
//! Jobs) and the manifest that makes runs resumable and idempotent.
//!
//! A frame is named by its number and written atomically (a synced temporary file renamed into
//! place), then recorded in the manifest with the hash of everything it was made from. A run
//! renders only the frames of its shard that are not done; frames are bit-identical whichever
//! shard, machine or run makes them, because every random number is keyed by frame and pixel
//! and the script's timeline is always replayed from frame 0.

pub mod manifest;
pub mod shard;

pub use manifest::{
    frame_file_name, status, FrameEntry, FrameState, JobSpec, Manifest, ManifestError, Status,
};
pub use shard::{Shard, Split};
