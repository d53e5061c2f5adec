#!/usr/bin/env python3
"""Side-by-side comparison of Penumbra with POV-Ray 3.7 and Embree, run by hand (not in CI).

For each anchor scene (ANCHORS.md) it writes a POV-Ray twin from Penumbra's own RON file (same
geometry, camera, lights, materials, recursion depth and samples: see povtwin.py), renders both
interleaved (Penumbra, POV-Ray, Penumbra, POV-Ray, ...) `--reps` times on `--threads` threads,
checks that both programs' own statistics report matching rays by kind (check.py), and takes
medians. On the mesh scenes it also traces the scene's camera rays and one shadow ray per hit
with Embree's single-ray API (embree_bench.py) beside Penumbra's figures for the same rays;
with `--layout-bench`, Penumbra's bare packets (`cargo bench --bench layout`) and Embree run in
alternating rounds, and each round's ratio pairs the two runs made side by side.

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
import statistics
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
        help="also run `cargo bench --bench layout` for Penumbra's bare packet throughput, in "
        "rounds alternating with Embree's (see --pair-rounds)",
    )
    parser.add_argument(
        "--pair-rounds",
        type=int,
        default=5,
        help="with --layout-bench: rounds of the layout bench and Embree in turn; each round's "
        "ratio pairs runs minutes apart, and the table gives the median and range (default 5)",
    )
    parser.add_argument(
        "--no-install", action="store_true", help="fail instead of installing POV-Ray or embreex"
    )
    args = parser.parse_args(argv)
    args.scenes = [s.strip() for s in args.scenes.split(",") if s.strip()]
    unknown = [s for s in args.scenes if s not in SCENES]
    if unknown:
        parser.error("unknown scene(s): %s" % ", ".join(unknown))
    if args.reps < 1 or args.threads < 1 or args.pair_rounds < 1:
        parser.error("--reps, --threads and --pair-rounds must be at least 1")
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


def embree_rounds(cases, args):
    """Embree on every mesh scene's rays, and with `--layout-bench` Penumbra's layout bench, in
    alternating rounds (bench, then Embree on each mesh, `--pair-rounds` times): the machine's
    speed drifts by 10-20 % over minutes, so a ratio of throughputs is only fair between runs
    made side by side. Without the bench, Embree runs once per mesh. Returns each mesh's Embree
    runs and the bench's rows, round by round."""
    meshes = [c for c in cases if c.camera_only_path]
    rounds = args.pair_rounds if args.layout_bench else 1
    embree = {c.name: [] for c in meshes}
    layout = []
    for r in range(rounds):
        if args.layout_bench:
            print("compare: cargo bench --bench layout, round %d/%d" % (r + 1, rounds), file=sys.stderr)
            layout.append(run_layout_bench(REPO, args.threads))
        for case in meshes:
            print("compare: %s Embree, round %d/%d" % (case.name, r + 1, rounds), file=sys.stderr)
            embree[case.name].append(
                run_embree(
                    sys.executable,
                    os.path.join(HERE, "embree_bench.py"),
                    case.ron_path,
                    args.models,
                    args.threads,
                    args.embree_reps,
                    os.path.join(case.dir, "embree-%d.json" % (r + 1)),
                )
            )
    return embree, layout


def embree_summary(runs):
    """Embree's figures over its rounds: the first round's description, each kind's median time
    and throughput over the rounds (with every round's throughput), the median build time."""
    summary = dict(runs[0].extra)
    for kind in ("camera", "shadow"):
        figures = dict(summary[kind])
        figures["median_s"] = statistics.median(r.extra[kind]["median_s"] for r in runs)
        figures["rounds_mrays_per_s"] = [r.extra[kind]["mrays_per_s"] for r in runs]
        figures["mrays_per_s"] = statistics.median(figures["rounds_mrays_per_s"])
        summary[kind] = figures
    summary["build_s"] = statistics.median(r.extra["build_s"] for r in runs)
    summary["rounds"] = len(runs)
    return summary


def compare_embree(case, result, embree_runs, layout_rounds):
    """Embree on the mesh scene's camera and shadow rays, beside Penumbra's figures for them:
    its whole renders, and (with the layout bench) its bare packets, each round's ratio taken
    between the bench and the Embree run that followed it."""
    embree = embree_summary(embree_runs)
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
    vs = {
        "embree": embree,
        "embree_whole_s": statistics.median(r.whole_s for r in embree_runs),
        "render": render,
    }
    rows = [rounds[case.name] for rounds in layout_rounds if case.name in rounds]
    if rows and len(rows) == len(embree_runs):
        bench = {key: statistics.median(row[key] for row in rows) for key in rows[0]}
        bench["rounds"] = rows
        for kind in ("camera", "shadow"):
            ratios = [row[kind] / run.extra[kind]["mrays_per_s"] for row, run in zip(rows, embree_runs)]
            bench[kind + "_vs_embree"] = {
                "rounds": ratios,
                "median": statistics.median(ratios),
                "min": min(ratios),
                "max": max(ratios),
            }
        vs["layout_bench"] = bench
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
    # The same model name covers several generations (an "Intel(R) Xeon(R) Processor" on a
    # virtual machine), whose SIMD levels and caches behave differently: record which one.
    fields = dict(line.split(":", 1) for line in lscpu if ":" in line)
    detail = ", ".join(
        "%s %s" % (label, fields[key].strip())
        for key, label in (
            ("CPU family", "family"),
            ("Model", "model"),
            ("Stepping", "stepping"),
            ("L2 cache", "L2"),
            ("L3 cache", "L3"),
        )
        if key in fields
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
        "cpu_detail": detail,
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
    results = [compare_renderers(case, args, binary, include_dir) for case in cases]
    embree_runs, layout_rounds = embree_rounds(cases, args)
    for case, result in zip(cases, results):
        if case.camera_only_path:
            compare_embree(case, result, embree_runs[case.name], layout_rounds)
    env["loadavg_end"] = os.getloadavg()

    print("## POV-Ray 3.7 and Penumbra, %d threads, medians of %d\n" % (args.threads, args.reps))
    print(
        "%s, %s (%s%d cores), load average %.2f at the start and %.2f at the end; Penumbra %s, binary sha256 %s…\n"
        % (
            env["date"],
            env["cpu"],
            env["cpu_detail"] + "; " if env["cpu_detail"] else "",
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
