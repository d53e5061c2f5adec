"""Interleaved A/B renders: Penumbra binaries or SIMD levels against the first, on the same scenes.

    python3 benches/compare/ab.py --reps 11 --width 640 --threads 2 \
        SCENE.ron[,SCENE.ron...] BIN[:LEVEL][@THREADS] BIN[:LEVEL][@THREADS] ...

Each round renders every scene once with every variant, the variants' order reversed in every
other round, and reads `times.trace` from `--stats`. A variant is a binary, optionally with a
`--simd` level after a colon and a thread count after an at sign, which overrides `--threads`
(`target/release/penumbra:avx2`, `target/release/penumbra@1`: the ratio of `BIN@1` to `BIN@2`
is the two-thread scaling). Per scene and variant it prints
the median trace time, its ratio to the first variant's median, the median of each round's
ratio to the first variant (the two ran within seconds of each other, so a slow stretch of the
machine moves both) with the middle half of the rounds, and a hash of the PNG. Every render of
a scene must write the same image, whatever the variant: one that does not is named and the
script exits with status 1 after its tables. Run by hand, not in CI; the harness's twins (`compare.py --out DIR`,
`DIR/SCENE/scene.ron`) are the usual scenes.
"""

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile

import report


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--reps", type=int, default=11, help="rounds (default 11)")
    p.add_argument("--width", type=int, help="image width (default: the scene's)")
    p.add_argument("--threads", type=int, default=2, help="worker threads (default 2)")
    p.add_argument("scenes", help="comma-separated scene files")
    p.add_argument("variants", nargs="+", help="BIN[:LEVEL][@THREADS]; ratios are against the first")
    args = p.parse_args(argv)
    if args.reps < 1:
        p.error("--reps must be at least 1")
    return args


def render(variant, scene, args, out):
    variant, _, threads = variant.partition("@")
    binary, _, level = variant.partition(":")
    png, stats = os.path.join(out, "image.png"), os.path.join(out, "stats.json")
    threads = threads or str(args.threads)
    command = [binary, "render", scene, "--threads", threads, "--quiet", "-o", png, "--stats", stats]
    if args.width:
        command += ["--width", str(args.width)]
    if level:
        command += ["--simd", level]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    with open(stats) as f:
        trace = json.load(f)["times"]["trace"]
    with open(png, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()[:12]
    return trace, digest


def main(argv):
    args = parse_args(argv)
    scenes = args.scenes.split(",")
    differ = []
    with tempfile.TemporaryDirectory() as out:
        for scene in scenes:
            times = {v: [] for v in args.variants}
            digests = {}
            want = None
            for rep in range(args.reps):
                order = args.variants if rep % 2 == 0 else args.variants[::-1]
                for variant in order:
                    trace, digests[variant] = render(variant, scene, args, out)
                    want = want or digests[variant]
                    if digests[variant] != want:
                        differ.append("%s, round %d, %s" % (scene, rep + 1, variant))
                    times[variant].append(trace)
            first = args.variants[0]
            base = statistics.median(times[first])
            print("== %s (%d rounds)" % (scene, args.reps))
            for variant in args.variants:
                ratios = report.round_ratios(times[variant], times[first])
                quarter = len(ratios) // 4
                median = statistics.median(times[variant])
                print(
                    "  %-40s %9.1f ms  %6.3f×  paired %6.3f× (%.3f–%.3f)  png %s"
                    % (
                        variant,
                        median * 1e3,
                        median / base,
                        statistics.median(ratios),
                        ratios[quarter],
                        ratios[len(ratios) - 1 - quarter],
                        digests[variant],
                    )
                )
    if differ:
        print("ab: these renders wrote another image than the scene's first:", file=sys.stderr)
        for line in differ:
            print("  " + line, file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main(sys.argv[1:])
