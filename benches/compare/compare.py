#!/usr/bin/env python3
"""Side-by-side comparison of Penumbra with POV-Ray 3.7 and Embree, run by hand (not in CI).

For each anchor scene (ANCHORS.md) it writes a POV-Ray twin from Penumbra's own RON file (same
geometry, camera, lights, materials, recursion depth and samples: see povtwin.py), renders both
interleaved (Penumbra, POV-Ray, Penumbra, POV-Ray, ...) `--reps` times on `--threads` threads,
checks that both programs' own statistics report matching rays by kind (check.py), and takes
medians. On the mesh scenes it also traces the scene's camera rays and one shadow ray per hit
with Embree's single-ray API (embree_bench.py) beside Penumbra's figures for the same rays.

Prints Markdown tables and writes everything measured to OUT/compare.json. POV-Ray and embreex
are installed when missing (install.py). docs/compare.md says how to read the output.

    python3 benches/compare/compare.py --reps 3 --threads 2 --scenes spheres,effects_aa,bunny
"""

import argparse
import datetime
import hashlib
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DEFAULT_BINARY = os.path.join(REPO, "target", "release", "penumbra")
sys.path.insert(0, HERE)

import install  # noqa: E402
import many  # noqa: E402
import report  # noqa: E402
import ron  # noqa: E402
from check import check_rays  # noqa: E402
from runners import run_embree, run_layout_bench, run_penumbra, run_povray  # noqa: E402

# The anchor scenes: a RON file of the repository, or None for one the harness generates.
SCENES = {
    "spheres": "scenes/spheres.ron",
    "effects_aa": "scenes/anchor_effects_aa.ron",
    "effects_dof": "scenes/anchor_effects_dof.ron",
    "bunny": "scenes/anchor_mesh_bunny.ron",
    "dragon": "scenes/anchor_mesh_dragon.ron",
    "many": None,
}


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--reps", type=int, default=3, help="runs of each program per scene (medians; default 3)"
    )
    parser.add_argument("--threads", type=int, default=2, help="worker threads of every program (default 2)")
    parser.add_argument(
        "--scenes", default=",".join(SCENES), help="comma-separated, of: " + ", ".join(SCENES)
    )
    parser.add_argument(
        "--models",
        default=os.path.join(REPO, "..", "shared", "models"),
        help="folder with bunny.obj and dragon.obj (default ../shared/models); mesh scenes are skipped without it",
    )
    parser.add_argument(
        "--out",
        default=os.path.join(tempfile.gettempdir(), "penumbra-compare"),
        help="folder for twins, images, statistics and compare.json (default: TMP/penumbra-compare)",
    )
    parser.add_argument(
        "--penumbra",
        default=DEFAULT_BINARY,
        help="Penumbra binary (default target/release/penumbra, brought up to date with the "
        "working tree by `cargo build --release` first)",
    )
    parser.add_argument(
        "--embree-reps", type=int, default=5, help="timed passes per ray kind in Embree (default 5)"
    )
    parser.add_argument(
        "--layout-bench",
        action="store_true",
        help="also run `cargo bench --bench layout` for Penumbra's bare packet throughput",
    )
    parser.add_argument(
        "--no-install", action="store_true", help="fail instead of installing POV-Ray or embreex"
    )
    args = parser.parse_args(argv)
    args.scenes = [s.strip() for s in args.scenes.split(",") if s.strip()]
    unknown = [s for s in args.scenes if s not in SCENES]
    if unknown:
        parser.error("unknown scene(s): %s" % ", ".join(unknown))
    if args.reps < 1 or args.threads < 1:
        parser.error("--reps and --threads must be at least 1")
    return args


@dataclass
class Case:
    """One scene made ready for both programs."""

    name: str
    dir: str
    ron_path: str
    pov_path: str
    pov_options: list
    notes: list
    antialiased: bool
    transmissive: bool
    camera_only_path: str | None  # meshes only: the scene without lights or recursion


def prepare(name, args, include_dir):
    """Writes the scene's RON (mesh paths made absolute) and its POV-Ray twin; None when its
    meshes are not in --models."""
    import povtwin  # needs numpy, which install.ensure_embreex has made importable

    source = SCENES[name]
    scene = many.scene() if source is None else ron.load(os.path.join(REPO, source))
    folder = os.path.join(args.out, name)
    os.makedirs(folder, exist_ok=True)
    has_mesh = False
    for obj in scene["objects"]:
        shape = obj["shape"]
        if shape.name == "Mesh":
            path = os.path.abspath(os.path.join(args.models, os.path.basename(shape["file"])))
            if not os.path.exists(path):
                print("compare: %s not found; skipping %s" % (path, name), file=sys.stderr)
                return None
            shape.fields["file"] = path
            has_mesh = True
    ron_path = os.path.join(folder, "scene.ron")
    with open(ron_path, "w", encoding="utf-8") as f:
        f.write(ron.dumps(scene) + "\n")
    twin = povtwin.write_twin(scene, folder, include_dir)
    pov_path = os.path.join(folder, "scene.pov")
    with open(pov_path, "w", encoding="utf-8") as f:
        f.write(twin.sdl)
    camera_only_path = None
    if has_mesh:
        scene.fields["lights"] = []
        scene.fields.setdefault("settings", ron.Struct(None)).fields["max_depth"] = 0
        camera_only_path = os.path.join(folder, "camera_only.ron")
        with open(camera_only_path, "w", encoding="utf-8") as f:
            f.write(ron.dumps(scene) + "\n")
    return Case(
        name=name,
        dir=folder,
        ron_path=ron_path,
        pov_path=pov_path,
        pov_options=twin.options,
        notes=twin.notes,
        antialiased=any(o.startswith("+A") for o in twin.options),
        transmissive=any(m.get("kt", 0.0) > 0 for m in scene["materials"]),
        camera_only_path=camera_only_path,
    )


def summary(runs):
    """Medians of a program's runs, and its rays (the first run's: every run reports the same)."""
    trace = report.median([r.trace_s for r in runs])
    return {
        "trace_s": trace,
        "whole_s": report.median([r.whole_s for r in runs]),
        "rays": runs[0].rays,
        "mrays_per_s": report.mrays(runs[0].total_rays, trace),
        "runs": [
            {"trace_s": r.trace_s, "whole_s": r.whole_s, "rays": r.rays, "extra": r.extra} for r in runs
        ],
    }


def compare_renderers(case, args, binary, include_dir):
    """A B A B: Penumbra then POV-Ray, `reps` times; medians and the ray-count check. Mesh
    scenes add Penumbra's camera-only render to each round (A B C A B C) for compare_embree."""
    pen_runs, pov_runs, camera_runs = [], [], []
    for rep in range(args.reps):
        print("compare: %s rep %d/%d" % (case.name, rep + 1, args.reps), file=sys.stderr)
        pen_runs.append(
            run_penumbra(
                binary,
                case.ron_path,
                os.path.join(case.dir, "penumbra.png"),
                os.path.join(case.dir, "penumbra-stats.json"),
                args.threads,
            )
        )
        pov_runs.append(
            run_povray(
                case.pov_path,
                os.path.join(case.dir, "povray.png"),
                case.pov_options,
                args.threads,
                include_dir,
            )
        )
        if case.camera_only_path:
            camera_runs.append(
                run_penumbra(
                    binary,
                    case.camera_only_path,
                    os.path.join(case.dir, "camera-only.png"),
                    os.path.join(case.dir, "camera-only-stats.json"),
                    args.threads,
                )
            )
    checks = check_rays(pen_runs[0], pov_runs[0], case.antialiased, case.transmissive)
    return {
        "scene": case.name,
        "penumbra": summary(pen_runs),
        "povray": summary(pov_runs),
        "pov_options": case.pov_options,
        "twin_notes": case.notes,
        "checks": [
            {
                "kind": c.kind,
                "penumbra": c.penumbra,
                "povray": c.povray,
                "low": c.low,
                "high": c.high,
                "ok": c.ok,
                "text": c.describe(),
            }
            for c in checks
        ],
        "rays_match": all(c.ok for c in checks),
        "penumbra_camera_only": summary(camera_runs) if camera_runs else None,
    }


def compare_embree(case, result, args, layout_rows):
    """Embree on the mesh scene's camera and shadow rays, beside Penumbra's figures for them."""
    print("compare: %s Embree" % case.name, file=sys.stderr)
    embree = run_embree(
        sys.executable,
        os.path.join(HERE, "embree_bench.py"),
        case.ron_path,
        args.models,
        args.threads,
        args.embree_reps,
        os.path.join(case.dir, "embree.json"),
    )
    camera_only = result["penumbra_camera_only"]
    camera_trace = camera_only["trace_s"]
    camera_rays = camera_only["rays"].get("camera", 0)
    shadow_rays = result["penumbra"]["rays"].get("shadow", 0)
    # The shadow rays' share of the full render: its trace time less the camera-only one's,
    # trusted only when that difference exceeds the spread of either set of runs.
    full_times = [r["trace_s"] for r in result["penumbra"]["runs"]]
    camera_times = [r["trace_s"] for r in camera_only["runs"]]
    spread = max(max(full_times) - min(full_times), max(camera_times) - min(camera_times))
    shadow_time = result["penumbra"]["trace_s"] - camera_trace
    render = {
        "camera": {
            "rays": camera_rays,
            "trace_s": camera_trace,
            "mrays_per_s": camera_rays / camera_trace / 1e6,
        },
        "shadow": {
            "rays": shadow_rays,
            "trace_s": shadow_time,
            "spread_s": spread,
            "mrays_per_s": None,
            "why": "",
        },
    }
    if shadow_time > spread:
        render["shadow"]["mrays_per_s"] = shadow_rays / shadow_time / 1e6
    else:
        render["shadow"]["why"] = "full %.3f s − camera-only %.3f s within the runs' spread %.3f s" % (
            result["penumbra"]["trace_s"],
            camera_trace,
            spread,
        )
    vs = {"embree": embree.extra, "embree_whole_s": embree.whole_s, "render": render}
    if layout_rows is not None and case.name in layout_rows:
        vs["layout_bench"] = layout_rows[case.name]
    result["embree_vs"] = vs


def penumbra_binary(args):
    """A private copy of the binary, so a rebuild during the run cannot change what is measured.
    The default binary is built first (a no-op when it is current): target/release/penumbra may
    be left over from an experiment since reverted, or be `cargo bench`'s build of the same
    sources, and the run would measure that under the working tree's name."""
    if args.penumbra == DEFAULT_BINARY:
        print("compare: cargo build --release --bin penumbra", file=sys.stderr)
        subprocess.run(["cargo", "build", "--release", "--bin", "penumbra"], cwd=REPO, check=True)
    elif not os.path.exists(args.penumbra):
        raise SystemExit("compare: no Penumbra binary at %s" % args.penumbra)
    copy = os.path.join(args.out, "penumbra")
    shutil.copy2(args.penumbra, copy)
    with open(copy, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()[:16]
    return copy, digest


def environment(args, digest):
    def output(command):
        try:
            done = subprocess.run(command, capture_output=True, text=True, cwd=REPO)
            return (done.stdout + done.stderr).strip()
        except OSError:
            return ""

    lscpu = output(["lscpu"]).splitlines()
    cpu = next(
        (line.split(":", 1)[1].strip() for line in lscpu if line.startswith("Model name")),
        platform.processor(),
    )
    pov = next(
        (line for line in output(["povray", "--version"]).splitlines() if line.startswith("POV-Ray")), ""
    )
    dirty = output(["git", "status", "--porcelain", "--untracked-files=no"])
    try:
        from importlib.metadata import version

        embreex = version("embreex")
    except Exception:  # noqa: BLE001 - the version is informative only
        embreex = "unknown"
    mtime = os.path.getmtime(args.penumbra)
    modified = datetime.datetime.fromtimestamp(mtime, datetime.timezone.utc).isoformat(timespec="seconds")
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpu": cpu,
        "cores": os.cpu_count(),
        "threads": args.threads,
        "reps": args.reps,
        "povray": pov,
        "embreex": embreex,
        "penumbra_commit": output(["git", "rev-parse", "--short", "HEAD"])
        + (" + uncommitted changes" if dirty else ""),
        "penumbra_binary": {"path": args.penumbra, "sha256_16": digest, "modified": modified},
        "loadavg_start": os.getloadavg(),
        "command": " ".join([os.path.relpath(sys.argv[0], REPO)] + sys.argv[1:]),
    }


def main(argv):
    args = parse_args(argv)
    install.ensure_povray(not args.no_install)
    install.ensure_embreex(not args.no_install, [os.path.abspath(__file__)] + argv)
    args.out = os.path.abspath(args.out)
    args.models = os.path.abspath(args.models)
    include_dir = os.path.join(args.out, "inc")
    os.makedirs(include_dir, exist_ok=True)
    binary, digest = penumbra_binary(args)
    env = environment(args, digest)

    cases = [c for c in (prepare(name, args, include_dir) for name in args.scenes) if c is not None]
    layout_rows = None
    if args.layout_bench and any(c.camera_only_path for c in cases):
        print("compare: cargo bench --bench layout", file=sys.stderr)
        layout_rows = run_layout_bench(REPO, args.threads)
    results = []
    for case in cases:
        result = compare_renderers(case, args, binary, include_dir)
        if case.camera_only_path:
            compare_embree(case, result, args, layout_rows)
        results.append(result)
    env["loadavg_end"] = os.getloadavg()

    print("## POV-Ray 3.7 and Penumbra, %d threads, medians of %d\n" % (args.threads, args.reps))
    print(
        "%s, %s (%d cores), load average %.2f at the start and %.2f at the end; Penumbra %s, binary sha256 %s…\n"
        % (
            env["date"],
            env["cpu"],
            env["cores"],
            env["loadavg_start"][0],
            env["loadavg_end"][0],
            env["penumbra_commit"],
            digest,
        )
    )
    print(report.renderer_table(results))
    print("\n## Rays by kind, from each program's own statistics\n")
    print(report.rays_table(results))
    for line in report.warnings(results):
        print("\n" + line)
    for r in results:
        for note in r["twin_notes"]:
            print("\nnote %s: %s" % (r["scene"], note))
    embree = report.embree_table(results)
    if embree:
        print(
            "\n## Embree %s (single-ray API) and Penumbra on the mesh scenes' rays, %d threads\n"
            % (env["embreex"], args.threads)
        )
        print(embree)
        print()
        for line in report.embree_notes(results):
            print("- " + line)
    path = os.path.join(args.out, "compare.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump({"environment": env, "scenes": results}, f, indent=2)
    print("\nwrote %s" % path)


if __name__ == "__main__":
    main(sys.argv[1:])
