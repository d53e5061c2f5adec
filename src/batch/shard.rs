//! Shards: which frames of a range one machine renders. Every shard of a split gets a
//! disjoint set and together they cover the range exactly once.

use std::fmt;
use std::str::FromStr;

use crate::script::FrameRange;

/// How a range is split among shards.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Split {
    /// Shard i gets the i-th block of consecutive frames; block sizes differ by at most one,
    /// the first blocks being the larger. Best when a frame's script state is costly to reach
    /// (each shard steps the script from frame 0 to its first frame).
    #[default]
    Contiguous,
    /// Shard i gets frames `first + i`, `first + i + count`, …: balanced when cost varies
    /// along the range.
    Interleaved,
}

impl FromStr for Split {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "contiguous" => Ok(Split::Contiguous),
            "interleaved" => Ok(Split::Interleaved),
            other => Err(format!("unknown split `{other}`; expected contiguous or interleaved")),
        }
    }
}

impl fmt::Display for Split {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Split::Contiguous => "contiguous",
            Split::Interleaved => "interleaved",
        })
    }
}

/// Shard `index` of `count` (0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, in `0..count`.
    pub index: u32,
    /// How many shards there are, ≥ 1.
    pub count: u32,
}

impl Shard {
    /// The whole range on one machine.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`, or an error saying what is wrong.
    pub fn new(index: u32, count: u32) -> Result<Self, String> {
        match (count, index < count) {
            (0, _) => Err("the shard count must be at least 1".into()),
            (_, false) => {
                Err(format!("shard index {index} is out of range for {count} shards (0..={})", count - 1))
            }
            _ => Ok(Self { index, count }),
        }
    }

    /// This shard's frames of `range` (of its stepped list, for `0..=12:4`), in increasing
    /// order (possibly none, when there are more shards than frames).
    pub fn frames(&self, range: FrameRange, split: Split) -> Vec<u32> {
        let (n, i, len) = (self.count as u64, self.index as u64, range.len() as u64);
        match split {
            Split::Contiguous => {
                let (base, extra) = (len / n, len % n);
                let start = i * base + i.min(extra);
                let size = base + u64::from(i < extra);
                (start..start + size).map(|k| range.nth(k as u32)).collect()
            }
            Split::Interleaved => (i..len).step_by(n as usize).map(|k| range.nth(k as u32)).collect(),
        }
    }

    /// The shard a job scheduler assigned, from environment variables read through `var`:
    /// Slurm's `SLURM_ARRAY_TASK_ID` (index = id − `SLURM_ARRAY_TASK_MIN`, default 0; count =
    /// `SLURM_ARRAY_TASK_MAX` − min + 1, or `SLURM_ARRAY_TASK_COUNT`), else Kubernetes'
    /// `JOB_COMPLETION_INDEX` with the count from `count` (a flag) or `PENUMBRA_SHARD_COUNT`.
    /// `None` when neither scheduler set anything.
    pub fn from_env(
        var: impl Fn(&str) -> Option<String>,
        count: Option<u32>,
    ) -> Result<Option<Self>, String> {
        let number = |name: &str| -> Result<Option<u32>, String> {
            match var(name) {
                None => Ok(None),
                Some(v) => v
                    .trim()
                    .parse::<u32>()
                    .map(Some)
                    .map_err(|_| format!("{name}={v:?} is not a whole number")),
            }
        };
        if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
            let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let total = match (number("SLURM_ARRAY_TASK_MAX")?, number("SLURM_ARRAY_TASK_COUNT")?, count) {
                (Some(max), _, _) if max >= min => max - min + 1,
                (Some(max), _, _) => return Err(format!("SLURM_ARRAY_TASK_MAX={max} is below SLURM_ARRAY_TASK_MIN={min}")),
                (None, Some(n), _) | (None, None, Some(n)) => n,
                (None, None, None) => {
                    return Err("SLURM_ARRAY_TASK_ID is set but neither SLURM_ARRAY_TASK_MAX nor SLURM_ARRAY_TASK_COUNT is".into())
                }
            };
            let index = id
                .checked_sub(min)
                .ok_or_else(|| format!("SLURM_ARRAY_TASK_ID={id} is below SLURM_ARRAY_TASK_MIN={min}"))?;
            // Arrays with steps (`--array=0-7:2`) would leave gaps: their ids are not 0..count.
            return Shard::new(index, total).map(Some).map_err(|e| format!("from SLURM_ARRAY_TASK_*: {e}"));
        }
        if let Some(index) = number("JOB_COMPLETION_INDEX")? {
            let total = match count {
                Some(n) => n,
                None => number("PENUMBRA_SHARD_COUNT")?.ok_or(
                    "JOB_COMPLETION_INDEX is set but the shard count is not: pass --shard-count N or set PENUMBRA_SHARD_COUNT (the Job's completions)",
                )?,
            };
            return Shard::new(index, total).map(Some).map_err(|e| format!("from JOB_COMPLETION_INDEX: {e}"));
        }
        Ok(None)
    }
}

impl FromStr for Shard {
    type Err = String;

    /// `INDEX/COUNT`, e.g. `2/4`.
    fn from_str(s: &str) -> Result<Self, String> {
        let (i, n) =
            s.split_once('/').ok_or_else(|| format!("expected INDEX/COUNT such as 2/4, got `{s}`"))?;
        let parse =
            |t: &str| t.trim().parse::<u32>().map_err(|_| format!("`{t}` in `{s}` is not a whole number"));
        Shard::new(parse(i)?, parse(n)?)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn range(first: u32, last: u32) -> FrameRange {
        FrameRange::new(first, last)
    }

    #[test]
    fn every_split_covers_the_range_exactly_once() {
        for (first, last) in [(0, 0), (0, 7), (3, 12), (10, 109), (5, 6)] {
            for count in [1, 2, 3, 7, 16] {
                for split in [Split::Contiguous, Split::Interleaved] {
                    let mut all: Vec<u32> = (0..count)
                        .flat_map(|i| Shard::new(i, count).unwrap().frames(range(first, last), split))
                        .collect();
                    all.sort_unstable();
                    assert_eq!(
                        all,
                        (first..=last).collect::<Vec<_>>(),
                        "{first}..={last} in {count} {split}"
                    );
                }
            }
        }
    }

    #[test]
    fn contiguous_blocks_differ_by_at_most_one_frame_first_ones_larger() {
        let sizes: Vec<usize> =
            (0..3).map(|i| Shard::new(i, 3).unwrap().frames(range(0, 9), Split::Contiguous).len()).collect();
        assert_eq!(sizes, [4, 3, 3]);
        assert_eq!(Shard::new(1, 3).unwrap().frames(range(0, 9), Split::Contiguous), [4, 5, 6]);
        assert_eq!(Shard::new(1, 3).unwrap().frames(range(0, 9), Split::Interleaved), [1, 4, 7]);
    }

    #[test]
    fn a_stepped_range_is_split_as_its_list_of_frames() {
        let stepped = FrameRange { first: 0, last: 12, step: 4 };
        let shard = |i, split| Shard::new(i, 2).unwrap().frames(stepped, split);
        assert_eq!((shard(0, Split::Contiguous), shard(1, Split::Contiguous)), (vec![0, 4], vec![8, 12]));
        assert_eq!((shard(0, Split::Interleaved), shard(1, Split::Interleaved)), (vec![0, 8], vec![4, 12]));
        assert_eq!(
            Shard::new(2, 3).unwrap().frames(FrameRange { first: 3, last: 20, step: 5 }, Split::Contiguous),
            [18]
        );
    }

    #[test]
    fn shards_parse_and_reject_bad_input() {
        assert_eq!("2/4".parse::<Shard>().unwrap(), Shard { index: 2, count: 4 });
        for bad in ["4/4", "1/0", "x/2", "3", "-1/2"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let map: HashMap<String, String> =
            pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        move |k| map.get(k).cloned()
    }

    #[test]
    fn slurm_and_kubernetes_environments_name_the_shard() {
        let slurm = env(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "5"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
        ]);
        assert_eq!(Shard::from_env(slurm, None).unwrap(), Some(Shard { index: 2, count: 4 }));
        let slurm = env(&[("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_COUNT", "3")]);
        assert_eq!(Shard::from_env(slurm, None).unwrap(), Some(Shard { index: 1, count: 3 }));
        let k8s = env(&[("JOB_COMPLETION_INDEX", "3"), ("PENUMBRA_SHARD_COUNT", "4")]);
        assert_eq!(Shard::from_env(k8s, None).unwrap(), Some(Shard { index: 3, count: 4 }));
        let k8s = env(&[("JOB_COMPLETION_INDEX", "0")]);
        assert_eq!(Shard::from_env(&k8s, Some(2)).unwrap(), Some(Shard { index: 0, count: 2 }));
        assert!(Shard::from_env(&k8s, None).unwrap_err().contains("--shard-count"));
        assert_eq!(Shard::from_env(env(&[]), None).unwrap(), None);
        assert!(Shard::from_env(env(&[("SLURM_ARRAY_TASK_ID", "x")]), None).is_err());
        assert!(Shard::from_env(env(&[("SLURM_ARRAY_TASK_ID", "9"), ("SLURM_ARRAY_TASK_MAX", "3")]), None)
            .is_err());
    }
}
