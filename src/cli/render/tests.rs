//! Tests of `src/cli/render.rs` and its modules.

use penumbra::simd::SimdLevel;

use super::frame_args::simd_refusal;
use super::*;

#[test]
fn a_level_the_cpu_lacks_is_refused_naming_the_option_and_the_levels_it_has() {
    let without_avx512 = |l: SimdLevel| l != SimdLevel::Avx512;
    assert_eq!(simd_refusal(SimdLevel::Avx2, without_avx512), None);
    assert_eq!(
        simd_refusal(SimdLevel::Avx512, without_avx512).as_deref(),
        Some(
            "--simd avx512: this CPU does not support AVX-512 F/BW/CD/DQ/VL (x86-64-v4); \
                 available: auto, scalar, baseline, avx2"
        )
    );
    let baseline_only = |l: SimdLevel| !matches!(l, SimdLevel::Avx2 | SimdLevel::Avx512);
    let message = simd_refusal(SimdLevel::Avx2, baseline_only).unwrap();
    assert!(message.starts_with("--simd avx2: this CPU does not support AVX2"), "{message}");
    assert!(message.ends_with("available: auto, scalar, baseline"), "{message}");
    // What this CPU has always passes.
    for level in SimdLevel::ALL.into_iter().filter(|l| l.available()) {
        assert!(check_simd(level).is_ok(), "{level}");
    }
}

#[test]
fn the_simd_level_is_no_part_of_the_fingerprint_and_reaches_the_settings() {
    use clap::Parser;
    let parse = |extra: &[&str]| {
        let argv = [&["penumbra", "animate", "s.ron", "f.rhai", "--frames", "0"][..], extra].concat();
        match super::super::Cli::parse_from(argv).command {
            Some(super::super::Command::Animate(args)) => args.frame,
            other => panic!("not an animation: {other:?}"),
        }
    };
    let (auto, scalar) = (parse(&[]), parse(&["--simd", "scalar"]));
    assert_eq!(auto.simd, SimdLevel::Auto);
    assert_eq!(scalar.simd, SimdLevel::Scalar);
    assert_eq!(auto.fingerprint(), scalar.fingerprint());
    assert!(!auto.fingerprint().contains("simd"), "{}", auto.fingerprint());
    assert_ne!(auto.fingerprint(), parse(&["--width", "9"]).fingerprint());
    assert_eq!(scalar.settings(RenderSettings::default()).simd, SimdLevel::Scalar);
    assert_eq!(parse(&["--simd", "AVX2"]).simd, SimdLevel::Avx2);
}
