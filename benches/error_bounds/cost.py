#!/usr/bin/env python3
"""What the hit-point error bounds cost in trace time: this commit against itself without them.

Issue 17 asks that the error bounds cost at most 5 % of trace time. They are spread over every
shape (each shape's bound on its hit point's rounding, the reprojection onto the surface, offsets
from the bound, the sphere's conservative root test and its near-tangent check), so the cost is
measured against a counterfactual build: `no_bounds.patch` (beside this script) takes them out
and starts secondary rays the way the engine did before them, 1/8192 of the point's largest
coordinate along the normal. Its images are wrong in the hard cases; it exists to be timed.

Both binaries are built from HEAD in a temporary git worktree (uncommitted changes are not
included), into `target/error-bounds/` (kept, so later runs rebuild only the engine), then
each scene is rendered by both:

- **instructions** (deterministic): `valgrind --tool=callgrind`, one thread, inclusive
  instructions of `trace::render::render_observed`, the whole trace stage. Valgrind does not
  emulate AVX-512, so the engine runs its AVX2 level there;
- **wall clock** (`--wall N`, noisy on shared machines): N interleaved repetitions (A B A B) of
  the `times.trace` that `--stats` reports, medians.

The rays traced by kind are printed for both, so a difference in work (offsets change a few
secondary rays) is visible.

Usage: python3 benches/error_bounds/cost.py [--width 120] [--wall 5 --wall-width 480 --threads 2]
       [SCENE ...]
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TARGET = os.path.join(ROOT, "target", "error-bounds")
DEFAULT_SCENES = ["spheres", "default", "effects_aa", "effects_glossy", "effects_soft_shadows", "showcase",
                  "bunny"]


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw)


def build_both():
    """Builds HEAD and HEAD without error bounds; returns the two binaries' paths."""
    os.makedirs(TARGET, exist_ok=True)
    bins = {}
    with tempfile.TemporaryDirectory() as tmp:
        tree = os.path.join(tmp, "tree")
        run(["git", "-C", ROOT, "worktree", "add", "--detach", tree, "HEAD"])
        try:
            for name in ("bounds", "no-bounds"):
                if name == "no-bounds":
                    run(["git", "-C", tree, "apply", os.path.join(HERE, "no_bounds.patch")])
                print(f"building {name} ...", file=sys.stderr)
                env = dict(os.environ, CARGO_TARGET_DIR=TARGET)
                run(["cargo", "build", "--release", "--quiet", "--bin", "penumbra"], cwd=tree, env=env)
                bins[name] = os.path.join(TARGET, f"penumbra-{name}")
                shutil.copy2(os.path.join(TARGET, "release", "penumbra"), bins[name])
        finally:
            run(["git", "-C", ROOT, "worktree", "remove", "--force", tree])
    return bins


def render(binary, scene, out_dir, width, threads, wrap=()):
    stats = os.path.join(out_dir, "stats.json")
    run(list(wrap) + [binary, "render", os.path.join(ROOT, "scenes", f"{scene}.ron"),
                      "-o", os.path.join(out_dir, "frame.png"), "--quiet", "--threads", str(threads),
                      "--width", str(width), "--stats", stats])
    with open(stats) as f:
        return json.load(f)


def trace_instructions(binary, scene, out_dir, width):
    """Inclusive instructions of render_observed, and the rays traced."""
    profile = os.path.join(out_dir, "callgrind.out")
    stats = render(binary, scene, out_dir, width, 1,
                   wrap=("valgrind", "--tool=callgrind", f"--callgrind-out-file={profile}"))
    text = run(["callgrind_annotate", "--inclusive=yes", "--auto=no", "--threshold=100", profile]).stdout
    # The function's inclusive count is the largest of the lines naming it (callgrind_annotate
    # also lists it once per source file of the code inlined into it).
    counts = [int(line.split()[0].replace(",", "")) for line in text.split("\n")
              if line.rstrip().endswith("render::render_observed")
              or "render::render_observed [" in line]
    if not counts:
        sys.exit("cost.py: no render_observed in the profile")
    return max(counts), sum(stats["rays"].values())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scenes", nargs="*", default=DEFAULT_SCENES)
    parser.add_argument("--width", type=int, default=120, help="image width under callgrind")
    parser.add_argument("--wall", type=int, default=0, help="wall-clock repetitions (0: none)")
    parser.add_argument("--wall-width", type=int, default=480)
    parser.add_argument("--threads", type=int, default=2, help="threads for the wall-clock runs")
    args = parser.parse_args()
    for tool in ("valgrind", "callgrind_annotate", "git", "cargo"):
        if shutil.which(tool) is None:
            sys.exit(f"cost.py: needs {tool}")
    bins = build_both()
    head = run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"]).stdout.strip()
    print(f"Error bounds' cost at {head}: trace stage with bounds / without (no_bounds.patch)\n")
    header = "| scene | trace Ir with | trace Ir without | **Ir ratio** | rays with | rays without |"
    rule = "|---|---:|---:|---:|---:|---:|"
    if args.wall:
        header += f" wall ratio ({args.wall} reps, {args.threads} threads, width {args.wall_width}) |"
        rule += "---:|"
    print(header)
    print(rule)
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            (ir_a, rays_a), (ir_b, rays_b) = (trace_instructions(bins[n], scene, tmp, args.width)
                                              for n in ("bounds", "no-bounds"))
            row = f"| {scene} | {ir_a:,} | {ir_b:,} | **{ir_a / ir_b:.3f}** | {rays_a:,} | {rays_b:,} |"
            if args.wall:
                times = {"bounds": [], "no-bounds": []}
                for _ in range(args.wall):
                    for name in times:
                        stats = render(bins[name], scene, tmp, args.wall_width, args.threads)
                        times[name].append(stats["times"]["trace"])
                row += f" {statistics.median(times['bounds']) / statistics.median(times['no-bounds']):.3f} |"
            print(row, flush=True)


if __name__ == "__main__":
    main()
