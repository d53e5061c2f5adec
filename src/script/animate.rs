//! Animation: a script's timeline from frame 0, stepped to the frames being rendered.
//!
//! Frame `n` is always the World after `setup()` and `frame(t)` for every frame `0..=n` in
//! order (frames before the first rendered one run the script only: no grid, no render), so
//! frame `n` is the same image whether the range starts at 0 or at `n`, on one machine or
//! split across many.
//!
//! The script's `print` and `debug` output is shown for `setup()` and for each frame that is
//! rendered, and dropped for the frames run only to reach a later one, so a `print` in
//! `frame(t)` shows once per rendered frame however the range starts or steps.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

use super::error::ScriptError;
use super::lent::Clock;
use super::runtime::{Script, ScriptedWorld};
use crate::camera::Shutter;
use crate::scene::SceneDesc;
use crate::store::{PrimitiveStore, SoaStore};
use crate::trace::TraceScene;

/// Frame numbers from `first` to `last` (inclusive), every `step`-th: `0..=12:4` is 0, 4, 8
/// and 12; `0..=119:5` stops at 115.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FrameRange {
    /// First frame.
    pub first: u32,
    /// Last frame allowed (inclusive); the last frame rendered is the last step at or before it.
    pub last: u32,
    /// Distance between rendered frames, at least 1 (manifests written before steps existed
    /// have none: 1).
    #[serde(default = "one")]
    pub step: u32,
}

fn one() -> u32 {
    1
}

impl FrameRange {
    /// Every frame from `first` to `last` (inclusive).
    pub const fn new(first: u32, last: u32) -> Self {
        Self { first, last, step: 1 }
    }

    /// Number of frames.
    pub fn len(&self) -> u32 {
        (self.last - self.first) / self.step.max(1) + 1
    }

    /// Never empty: a range holds at least its first frame.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The `k`-th frame number (0-based), for `k < len()`.
    pub fn nth(&self, k: u32) -> u32 {
        debug_assert!(k < self.len(), "frame {k} of a range of {}", self.len());
        self.first + k * self.step.max(1)
    }

    /// The frame numbers in order.
    pub fn iter(&self) -> std::iter::StepBy<std::ops::RangeInclusive<u32>> {
        (self.first..=self.last).step_by(self.step.max(1) as usize)
    }
}

impl fmt::Display for FrameRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..={}", self.first, self.last)?;
        match self.step {
            0 | 1 => Ok(()),
            step => write!(f, ":{step}"),
        }
    }
}

/// Largest frame number accepted (six digits of file names).
pub const MAX_FRAME: u32 = 999_999;

impl FromStr for FrameRange {
    type Err = String;

    /// `A..=B` (inclusive), `A..B` (exclusive) or a single frame `A`; a range may end with
    /// `:S` to take every S-th frame (`0..=119:5`).
    fn from_str(s: &str) -> Result<Self, String> {
        let number = |t: &str| {
            t.trim().parse::<u32>().ok().filter(|n| *n <= MAX_FRAME).ok_or_else(|| {
                format!("`{t}` is not a frame number in 0..={MAX_FRAME} (expected A..=B, A..B or A, then optionally :STEP)")
            })
        };
        let (range, step) = match s.rsplit_once(':') {
            Some((range, step)) => {
                let step = step.trim().parse::<u32>().ok().filter(|n| *n >= 1).ok_or_else(|| {
                    format!("`{s}`: the step after `:` must be a whole number >= 1, got `{step}`")
                })?;
                if !range.contains("..") {
                    return Err(format!("`{s}`: a step needs a range, e.g. `{range}..=120:{step}`"));
                }
                (range, step)
            }
            None => (s, 1),
        };
        let (first, last) = if let Some((a, b)) = range.split_once("..=") {
            (number(a)?, number(b)?)
        } else if let Some((a, b)) = range.split_once("..") {
            let (a, b) = (number(a)?, number(b)?);
            if b <= a {
                return Err(format!("`{s}` is empty: the end of A..B is exclusive"));
            }
            (a, b - 1)
        } else {
            let a = number(range)?;
            (a, a)
        };
        match first <= last {
            true => Ok(Self { first, last, step }),
            false => Err(format!("`{s}` is empty: the first frame comes after the last")),
        }
    }
}

/// A scripted scene stepped frame by frame.
pub struct Animation<S: PrimitiveStore + 'static = SoaStore> {
    world: ScriptedWorld<S>,
    fps: f64,
    /// The scene's shutter (motion blur), if any.
    shutter: Option<Shutter>,
    /// The pose at the last stepped frame's shutter close.
    close: Option<super::shutter::ClosePose>,
    /// The next frame whose `frame(t)` has not run.
    next: u32,
    /// Seconds of the last `step_to`: running the script, then updating the World.
    timing: (f64, f64),
    /// Whether the script's `print` output is dropped on every frame (reports).
    muted: bool,
}

impl<S: PrimitiveStore + 'static> Animation<S> {
    /// Spawns `desc`, attaches `script` (which must define `fn frame(t)`) and runs `setup()`.
    pub fn new(desc: &SceneDesc, script: &Script, fps: f64) -> Result<Self, ScriptError> {
        Self::with_output(desc, script, fps, true)
    }

    /// [`Self::new`], with the script's `print` and `debug` output shown (as `animate` does,
    /// once per rendered frame) or dropped throughout, `setup()` included (`report`, which
    /// steps the same script once per configuration).
    pub fn with_output(
        desc: &SceneDesc,
        script: &Script,
        fps: f64,
        shown: bool,
    ) -> Result<Self, ScriptError> {
        script.require("frame", 1, "`animate` calls once per frame with the time in seconds")?;
        let mut world = ScriptedWorld::from_scene(desc, script);
        world.mute_output(!shown);
        world.setup()?;
        let shutter = desc.camera.shutter.and_then(|(open, close)| Shutter::new(open, close).ok());
        Ok(Self { world, fps, shutter, close: None, next: 0, timing: (0.0, 0.0), muted: !shown })
    }

    /// Runs the script up to `frame` (each frame not yet run, in order, with output shown only
    /// for `frame` itself), applies its writes and returns the frame's snapshot. Frames must be
    /// asked for in increasing order.
    ///
    /// With a shutter, every frame of the timeline runs at its shutter's opening, and `frame`
    /// is also evaluated at its closing ([`super::shutter`]): what moved between the two is
    /// blurred.
    pub fn step_to(&mut self, frame: u32) -> Result<Arc<TraceScene<S>>, ScriptError> {
        assert!(frame + 1 >= self.next, "frames run in order: frame {frame} asked for after {}", self.next);
        let started = Instant::now();
        while self.next <= frame {
            let n = self.next;
            if let (true, Some(shutter)) = (n == frame, self.shutter) {
                self.close = Some(self.world.evaluate_at(Clock::at_offset(n, shutter.close, self.fps))?);
            }
            self.world.mute_output(self.muted || n < frame);
            let open = self.shutter.map_or(0.0, |s| s.open);
            let ran = self.world.frame(Clock::at_offset(n, open, self.fps));
            self.world.mute_output(self.muted);
            ran?;
            self.next += 1;
        }
        self.world.set_shutter_pose(self.close.clone());
        let script = started.elapsed().as_secs_f64();
        let snapshot = self.world.update();
        self.timing = (script, started.elapsed().as_secs_f64() - script);
        Ok(snapshot)
    }

    /// Seconds the last [`Self::step_to`] spent running the script and updating the World
    /// (which includes any grid rebuild and the snapshot).
    pub fn last_timing(&self) -> (f64, f64) {
        self.timing
    }

    /// The scripted World (render settings, grid rebuild count, stage timings).
    pub fn world(&self) -> &ScriptedWorld<S> {
        &self.world
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_parse_inclusive_exclusive_and_single() {
        assert_eq!("0..=119".parse::<FrameRange>().unwrap(), FrameRange::new(0, 119));
        assert_eq!("10..20".parse::<FrameRange>().unwrap(), FrameRange::new(10, 19));
        assert_eq!("7".parse::<FrameRange>().unwrap(), FrameRange::new(7, 7));
        assert_eq!("0..=119".parse::<FrameRange>().unwrap().len(), 120);
        for bad in ["5..=2", "3..3", "a..=4", "-1..=3", "", "1..=9999999"] {
            assert!(bad.parse::<FrameRange>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_step_takes_every_nth_frame_up_to_the_end() {
        let stepped = |s: &str| s.parse::<FrameRange>().unwrap().iter().collect::<Vec<_>>();
        assert_eq!(stepped("0..=12:4"), [0, 4, 8, 12]);
        assert_eq!(stepped("0..12:4"), [0, 4, 8]);
        assert_eq!(stepped("3..=10:3"), [3, 6, 9]);
        assert_eq!(stepped("5..=5:7"), [5]);
        let r: FrameRange = "0..=119:5".parse().unwrap();
        assert_eq!((r.len(), r.nth(0), r.nth(23)), (24, 0, 115));
        assert_eq!(r.iter().count(), r.len() as usize);
        assert_eq!(r.to_string(), "0..=119:5");
        assert_eq!(r.to_string().parse::<FrameRange>().unwrap(), r);
        assert_eq!("2..=9:1".parse::<FrameRange>().unwrap().to_string(), "2..=9");
        for (bad, says) in [
            ("0..=12:0", "must be a whole number >= 1, got `0`"),
            ("0..=12:", "must be a whole number >= 1"),
            ("0..=12:-2", "must be a whole number >= 1"),
            ("4:2", "a step needs a range"),
        ] {
            let e = bad.parse::<FrameRange>().unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn manifests_without_a_step_read_as_every_frame() {
        let old: FrameRange = serde_json::from_str(r#"{"first": 2, "last": 9}"#).unwrap();
        assert_eq!(old, FrameRange::new(2, 9));
        let stepped = FrameRange { first: 0, last: 12, step: 4 };
        let json = serde_json::to_string(&stepped).unwrap();
        assert_eq!(serde_json::from_str::<FrameRange>(&json).unwrap(), stepped);
    }
}
