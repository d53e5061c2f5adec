"""Running each program once and reading its own statistics.

Every runner returns a `Run`: the wall-clock time of the whole process (start-up, parsing,
acceleration build, trace, image write: what a user waits for), the trace time the program
reports itself, and its rays by kind in Penumbra's names.
"""

import json
import os
import re
import subprocess
import time
from dataclasses import dataclass, field


@dataclass
class Run:
    """One run of one program."""

    whole_s: float
    trace_s: float
    rays: dict  # kind -> count, Penumbra's kinds (camera, shadow, reflection, refraction, ...)
    extra: dict = field(default_factory=dict)  # program-specific figures, kept in the JSON

    @property
    def total_rays(self):
        return sum(self.rays.values())


class RunError(RuntimeError):
    """A program failed or printed no statistics."""


def timed(command, cwd=None, env=None):
    """Runs `command`; returns (wall seconds, stdout, stderr). Raises RunError on failure."""
    started = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - started
    if done.returncode != 0:
        tail = (done.stderr or done.stdout).strip().splitlines()[-15:]
        raise RunError("%s exited %d:\n%s" % (os.path.basename(command[0]), done.returncode, "\n".join(tail)))
    return wall, done.stdout, done.stderr


def run_penumbra(binary, scene, image, stats, threads):
    """Renders `scene` with Penumbra; its statistics come from `--stats`."""
    wall, _, _ = timed(
        [binary, "render", scene, "-o", image, "--stats", stats, "--threads", str(threads), "--quiet"]
    )
    with open(stats, encoding="utf-8") as f:
        report = json.load(f)
    rays = {kind: n for kind, n in report["rays"].items() if n}
    times = report["times"]
    return Run(
        whole_s=wall,
        trace_s=times["trace"],
        rays=rays,
        extra={"times": times, "mrays_per_s": report.get("mrays_per_s")},
    )


POV_FIELDS = {
    "pixels": r"Pixels:\s+(\d+)",
    "samples": r"Samples:\s+(\d+)",
    "rays": r"Rays:\s+(\d+)\s+Saved",
    "shadow_tests": r"Shadow Ray Tests:\s+(\d+)",
    "shadow_succeeded": r"Shadow Ray Tests:\s+\d+\s+Succeeded:\s+(\d+)",
    "reflected": r"Reflected Rays:\s+(\d+)",
    "total_internal": r"Total Internal:\s+(\d+)",
    "refracted": r"Refracted Rays:\s+(\d+)",
    "transmitted": r"Transmitted Rays:\s+(\d+)",
}
POV_TIMES = {
    "parse_s": r"Parse Time:.*\((\d+\.\d+) seconds\)",
    "bounding_s": r"Bounding Time:.*\((\d+\.\d+) seconds\)",
    "trace_s": r"Trace Time:.*\((\d+\.\d+) seconds\)",
}


def parse_pov_stats(text):
    """POV-Ray's render statistics (printed on standard error) as a dict of numbers; a line
    POV-Ray leaves out (it prints only non-zero reflection and refraction counts) reads 0."""
    stats = {}
    for key, pattern in {**POV_FIELDS, **POV_TIMES}.items():
        found = re.search(pattern, text)
        stats[key] = (float(found.group(1)) if key.endswith("_s") else int(found.group(1))) if found else 0
    if not re.search(POV_TIMES["trace_s"], text) or not re.search(POV_FIELDS["rays"], text):
        raise RunError("POV-Ray printed no render statistics")
    return stats


def pov_rays(stats):
    """POV-Ray's counts in Penumbra's kinds. POV-Ray counts a total internal reflection as a
    reflected ray (and under "Total Internal"); Penumbra counts it as refraction. "Rays" holds
    every traced ray but shadow rays, so the camera's are what is left of it."""
    reflection = stats["reflected"] - stats["total_internal"]
    refraction = stats["refracted"] + stats["total_internal"] + stats["transmitted"]
    camera = stats["rays"] - stats["reflected"] - stats["refracted"] - stats["transmitted"]
    rays = {
        "camera": camera,
        "shadow": stats["shadow_tests"],
        "reflection": reflection,
        "refraction": refraction,
    }
    return {kind: n for kind, n in rays.items() if n}


def run_povray(pov_file, image, options, threads, include_dir):
    """Renders `pov_file` with POV-Ray; its statistics come from its own report."""
    command = [
        "povray",
        "+I" + pov_file,
        "+O" + image,
        "+FN",
        "-D",
        "-P",
        "+WT%d" % threads,
        "+L" + include_dir,
    ]
    wall, stdout, stderr = timed(command + options, cwd=os.path.dirname(pov_file))
    stats = parse_pov_stats(stderr + stdout)
    return Run(whole_s=wall, trace_s=stats["trace_s"], rays=pov_rays(stats), extra={"stats": stats})


def run_embree(python, script, scene, models, threads, reps, output):
    """Runs embree_bench.py in its own process; its figures come from the JSON it writes."""
    command = [
        python,
        script,
        scene,
        "--models",
        models,
        "--threads",
        str(threads),
        "--reps",
        str(reps),
        "--json",
        output,
    ]
    wall, _, _ = timed(command)
    with open(output, encoding="utf-8") as f:
        report = json.load(f)
    trace = report["camera"]["median_s"] + report["shadow"]["median_s"]
    rays = {"camera": report["camera"]["rays"], "shadow": report["shadow"]["rays"]}
    return Run(whole_s=wall, trace_s=trace, rays=rays, extra=report)


# scene, then camera rays (packets, SoA, AoS Mrays/s, two ratios), then shadow rays (the same).
LAYOUT_ROW = re.compile(r"^(\w+)" + r"\s+([\d.]+)" * 14 + r"\s*$")


def run_layout_bench(repo, threads):
    """Penumbra's own bare throughput: `cargo bench --bench layout`'s table (criterion's groups
    filtered out), as {scene: {"camera": Mrays/s, "shadow": Mrays/s}} for SoA packets at the
    best SIMD level (what the renderer uses by default), with the single-ray SoA figures (with
    the single-ray SIMD kernels, as the renderer traces single rays) beside them as
    "camera_single" and "shadow_single", and the packets' ratio to AoS scalar single rays as
    "camera_vs_aos" and "shadow_vs_aos" (the issue's layout target)."""
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    _, stdout, _ = timed(
        ["cargo", "bench", "--bench", "layout", "--", "no_criterion_group_matches_this"], cwd=repo, env=env
    )
    rows = {}
    for line in stdout.splitlines():
        found = LAYOUT_ROW.match(line.strip())
        if found:
            rows[found.group(1)] = {
                "camera": float(found.group(2)),
                "camera_single": float(found.group(3)),
                "camera_vs_aos": float(found.group(6)),
                "shadow": float(found.group(9)),
                "shadow_single": float(found.group(10)),
                "shadow_vs_aos": float(found.group(13)),
            }
    if not rows:
        raise RunError("cargo bench --bench layout printed no table")
    return rows
