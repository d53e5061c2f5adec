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
use super::runtime::{Script, ScriptedWorld};
use super::state::Clock;
use crate::scene::SceneDesc;
use crate::store::{PrimitiveStore, SoaStore};
use crate::trace::TraceScene;

/// An inclusive range of frame numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FrameRange {
    /// First frame.
    pub first: u32,
    /// Last frame (inclusive).
    pub last: u32,
}

impl FrameRange {
    /// Number of frames.
    pub fn len(&self) -> u32 {
        self.last - self.first + 1
    }

    /// Never empty: a range holds at least its first frame.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The frame numbers in order.
    pub fn iter(&self) -> std::ops::RangeInclusive<u32> {
        self.first..=self.last
    }
}

impl fmt::Display for FrameRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..={}", self.first, self.last)
    }
}

/// Largest frame number accepted (six digits of file names).
pub const MAX_FRAME: u32 = 999_999;

impl FromStr for FrameRange {
    type Err = String;

    /// `A..=B` (inclusive), `A..B` (exclusive) or a single frame `A`.
    fn from_str(s: &str) -> Result<Self, String> {
        let number = |t: &str| {
            t.trim().parse::<u32>().ok().filter(|n| *n <= MAX_FRAME).ok_or_else(|| {
                format!("`{t}` is not a frame number in 0..={MAX_FRAME} (expected A..=B, A..B or A)")
            })
        };
        let (first, last) = if let Some((a, b)) = s.split_once("..=") {
            (number(a)?, number(b)?)
        } else if let Some((a, b)) = s.split_once("..") {
            let (a, b) = (number(a)?, number(b)?);
            if b <= a {
                return Err(format!("`{s}` is empty: the end of A..B is exclusive"));
            }
            (a, b - 1)
        } else {
            let a = number(s)?;
            (a, a)
        };
        match first <= last {
            true => Ok(Self { first, last }),
            false => Err(format!("`{s}` is empty: the first frame comes after the last")),
        }
    }
}

/// A scripted scene stepped frame by frame.
pub struct Animation<S: PrimitiveStore + 'static = SoaStore> {
    world: ScriptedWorld<S>,
    fps: f64,
    /// The next frame whose `frame(t)` has not run.
    next: u32,
    /// Seconds of the last `step_to`: running the script, then updating the World.
    timing: (f64, f64),
}

impl<S: PrimitiveStore + 'static> Animation<S> {
    /// Spawns `desc`, attaches `script` (which must define `fn frame(t)`) and runs `setup()`.
    pub fn new(desc: &SceneDesc, script: &Script, fps: f64) -> Result<Self, ScriptError> {
        script.require("frame", 1, "`animate` calls once per frame with the time in seconds")?;
        let mut world = ScriptedWorld::from_scene(desc, script);
        world.setup()?;
        Ok(Self { world, fps, next: 0, timing: (0.0, 0.0) })
    }

    /// Runs the script up to `frame` (each frame not yet run, in order, with output shown only
    /// for `frame` itself), applies its writes and returns the frame's snapshot. Frames must be
    /// asked for in increasing order.
    pub fn step_to(&mut self, frame: u32) -> Result<Arc<TraceScene<S>>, ScriptError> {
        assert!(frame + 1 >= self.next, "frames run in order: frame {frame} asked for after {}", self.next);
        let started = Instant::now();
        while self.next <= frame {
            self.world.mute_output(self.next < frame);
            let ran = self.world.frame(Clock::at(self.next, self.fps));
            self.world.mute_output(false);
            ran?;
            self.next += 1;
        }
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
        assert_eq!("0..=119".parse::<FrameRange>().unwrap(), FrameRange { first: 0, last: 119 });
        assert_eq!("10..20".parse::<FrameRange>().unwrap(), FrameRange { first: 10, last: 19 });
        assert_eq!("7".parse::<FrameRange>().unwrap(), FrameRange { first: 7, last: 7 });
        assert_eq!("0..=119".parse::<FrameRange>().unwrap().len(), 120);
        for bad in ["5..=2", "3..3", "a..=4", "-1..=3", "", "1..=9999999"] {
            assert!(bad.parse::<FrameRange>().is_err(), "{bad}");
        }
    }
}
