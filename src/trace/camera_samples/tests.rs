//! Tests of `src/trace/camera_samples.rs`.

use super::*;

#[test]
fn times_keep_to_their_strata_by_pattern() {
    let n = 8;
    for k in 0..n {
        let (lo, hi) = (k as f32 / n as f32, (k + 1) as f32 / n as f32);
        for u in [0.0, 0.3, 1.0f32.next_down()] {
            let t = stratum_time(Pattern::Jittered, k, n, u);
            assert!((lo..hi).contains(&t), "jittered time {t} of stratum {k} at u = {u}");
        }
        assert_eq!(stratum_time(Pattern::Grid, k, n, 0.9), (k as f32 + 0.5) / n as f32);
        assert_eq!(stratum_time(Pattern::Random, k, n, 0.9), 0.9, "random ignores the stratum");
    }
    // The last stratum's end is pulled back inside it.
    assert!(stratum_time(Pattern::Jittered, 2, 3, 1.0f32.next_down()) < 1.0);
}
