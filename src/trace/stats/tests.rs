//! Tests of `src/trace/stats.rs`.

use super::*;

#[test]
fn the_json_carries_every_field_and_the_throughput_of_the_trace_time() {
    let mut stats = RenderStats::default();
    stats.rays.camera = 3_000_000;
    stats.rays.shadow = 1_000_000;
    stats.times.trace = 2.0;
    let json = serde_json::to_value(&stats).unwrap();
    assert_eq!(json["mrays_per_s"].as_f64(), Some(2.0));
    assert_eq!(json["rays"]["camera"], 3_000_000);
    let keys: Vec<&str> = json.as_object().unwrap().keys().map(String::as_str).collect();
    for key in
        ["width", "rays", "adaptive", "effects", "times", "grid", "traversal", "aov_bytes", "ray_budget"]
    {
        assert!(keys.contains(&key), "{key} missing from {keys:?}");
    }
}

#[test]
fn the_budget_tally_counts_cut_samples_and_keeps_the_largest_tree() {
    let mut a = BudgetTally::default();
    a.record(10, 0);
    a.record(1024, 7);
    let mut b = BudgetTally::default();
    b.record(1024, 1);
    b.record(3, 0);
    a.add(&b);
    assert_eq!(a, BudgetTally { cut_samples: 2, refused_rays: 8, max_per_sample: 1024 });
    let stats = RenderStats { ray_budget: BudgetStats::new(1024, &a), ..Default::default() };
    let line =
        "ray budget 1024 secondary rays per camera sample: 2 samples cut, 8 rays refused, at most 1024";
    assert!(stats.summary().contains(line), "{}", stats.summary());
    let json = serde_json::to_value(&stats).unwrap();
    assert_eq!(json["ray_budget"]["cut_samples"], 2);
    assert_eq!(json["ray_budget"]["max_secondary_rays"], 1024);
}

#[test]
fn the_level_that_traced_is_in_the_summary_and_the_json() {
    let stats = RenderStats { threads: 2, simd: crate::simd::SimdLevel::Avx2, ..Default::default() };
    assert!(stats.summary().contains("2 threads, simd avx2,"), "{}", stats.summary());
    assert_eq!(serde_json::to_value(&stats).unwrap()["simd"], "avx2");
}

#[test]
fn no_trace_time_is_zero_throughput_not_nan() {
    let json = serde_json::to_value(RenderStats::default()).unwrap();
    assert_eq!(json["mrays_per_s"].as_f64(), Some(0.0));
}

#[test]
fn a_packets_tally_recorded_at_once_equals_its_lanes_recorded_one_by_one() {
    use crate::store::TraversalCost;
    let costs = [(0, 0), (3, 7), (31, 32), (33, 1000), (70_000, 5)];
    let (mut one_by_one, mut at_once) = (TraversalTally::default(), TraversalTally::default());
    for (k, &(cells, tests)) in costs.iter().enumerate() {
        let cost = TraversalCost { cells, tests };
        let lanes = k as u64 * 5 + 1;
        (0..lanes).for_each(|_| one_by_one.record(cost));
        at_once.record_many(cost, lanes);
    }
    assert_eq!(at_once, one_by_one);
    assert_eq!(at_once.rays, 1 + 6 + 11 + 16 + 21);
    assert_eq!(at_once.summary(), one_by_one.summary());
}
