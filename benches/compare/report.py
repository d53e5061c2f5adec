"""The Markdown tables the harness prints (docs/compare.md explains each column)."""

import statistics

KINDS = ("camera", "lens", "shadow", "area_shadow", "reflection", "refraction")


def median(values):
    return statistics.median(values)


def mrays(rays, seconds):
    return rays / seconds / 1e6 if seconds > 0 else float("nan")


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def spread(summary):
    """(slowest − fastest) / median trace time of a program's runs, in percent."""
    times = [r["trace_s"] for r in summary["runs"]]
    return 100.0 * (max(times) - min(times)) / summary["trace_s"]


def fastest(summary):
    """The fastest trace time of a program's runs: the one least disturbed by whatever else the
    machine was doing (on a shared machine the median moves with the load, the minimum less)."""
    return min(r["trace_s"] for r in summary["runs"])


def round_ratios(numerators, denominators):
    """Each round's ratio of two programs' (or variants') times, sorted: the two ran one right
    after the other, so drift in the machine's speed over the minutes of a run moves both alike,
    and the median of these reads steadier than the ratio of the medians when the spread is
    large."""
    return sorted(a / b for a, b in zip(numerators, denominators))


def paired(pov, pen):
    """POV-Ray's trace time over Penumbra's, round by round ([`round_ratios`]): the median and
    the range."""
    ratios = round_ratios([r["trace_s"] for r in pov["runs"]], [r["trace_s"] for r in pen["runs"]])
    return "%.2f× (%.2f–%.2f)" % (median(ratios), ratios[0], ratios[-1])


def renderer_table(results):
    """POV-Ray against Penumbra, one row per scene: medians of trace and whole-process time."""
    rows = []
    for r in results:
        pov, pen = r["povray"], r["penumbra"]
        rows.append(
            [
                r["scene"],
                "%.3f" % pov["trace_s"],
                "%.3f" % pen["trace_s"],
                "%.2f×" % (pov["trace_s"] / pen["trace_s"]),
                paired(pov, pen),
                "%.2f×" % (fastest(pov) / fastest(pen)),
                "%.0f %% / %.0f %%" % (spread(pov), spread(pen)),
                "%.2f" % pov["whole_s"],
                "%.2f" % pen["whole_s"],
                "%.2f×" % (pov["whole_s"] / pen["whole_s"]),
                "%.2f" % pov["mrays_per_s"],
                "%.2f" % pen["mrays_per_s"],
                "match" if r["rays_match"] else "**MISMATCH**",
            ]
        )
    return table(
        [
            "scene",
            "POV-Ray trace s",
            "Penumbra trace s",
            "trace ratio",
            "paired rounds' ratio (range)",
            "fastest runs' ratio",
            "trace spread POV-Ray / Penumbra",
            "POV-Ray whole s",
            "Penumbra whole s",
            "whole ratio",
            "POV-Ray Mrays/s",
            "Penumbra Mrays/s",
            "ray counts",
        ],
        rows,
    )


def rays_table(results):
    """Rays by kind as each program's own statistics report them."""
    rows = []
    for r in results:
        for program in ("penumbra", "povray"):
            rays = r[program]["rays"]
            rows.append([r["scene"], program] + [rays.get(k, 0) for k in KINDS] + [sum(rays.values())])
    return table(["scene", "program"] + list(KINDS) + ["total"], rows)


def warnings(results):
    """One line per kind whose counts disagree beyond the stated tolerance."""
    lines = []
    for r in results:
        for c in r["checks"]:
            if not c["ok"]:
                lines.append("WARNING %s: %s" % (r["scene"], c["text"]))
    return lines


def embree_table(results):
    """Embree single-ray throughput against Penumbra's on the same mesh scene's rays. With the
    layout bench, its ratio is the median of the rounds' ratios (each the bench against the
    Embree run beside it), with their range."""
    with_bench = any("layout_bench" in r.get("embree_vs", {}) for r in results)
    header = [
        "mesh",
        "rays",
        "count",
        "Embree trace s",
        "Embree Mrays/s",
        "Penumbra render Mrays/s",
        "Penumbra / Embree",
    ]
    if with_bench:
        header += ["Penumbra layout bench Mrays/s", "Penumbra / Embree, median of rounds (range)"]
    rows = []
    for r in results:
        vs = r.get("embree_vs")
        if not vs:
            continue
        for kind in ("camera", "shadow"):
            e = vs["embree"][kind]
            render = vs["render"][kind]
            row = [r["scene"], kind, e["rays"], "%.4f" % e["median_s"], "%.2f" % e["mrays_per_s"]]
            if render["mrays_per_s"] is None:
                row += ["below noise: %s" % render["why"], "–"]
            else:
                row += ["%.2f" % render["mrays_per_s"], "%.2f×" % (render["mrays_per_s"] / e["mrays_per_s"])]
            if with_bench:
                bench = vs.get("layout_bench", {})
                paired = bench.get(kind + "_vs_embree")
                row += (
                    [
                        "%.2f" % bench[kind],
                        "%.2f× (%.2f–%.2f)" % (paired["median"], paired["min"], paired["max"]),
                    ]
                    if paired
                    else ["not in the bench", "–"]
                )
            rows.append(row)
    return table(header, rows) if rows else ""


def embree_notes(results):
    lines = []
    for r in results:
        vs = r.get("embree_vs")
        if vs:
            e = vs["embree"]
            lines.append(
                "%s: Embree BVH build %.1f ms (%d mesh triangles + ground quad), whole process %.2f s%s"
                % (
                    r["scene"],
                    1e3 * e["build_s"],
                    e["mesh_triangles"],
                    vs["embree_whole_s"],
                    " (medians of %d rounds)" % e["rounds"] if e.get("rounds", 1) > 1 else "",
                )
            )
            bench = vs.get("layout_bench", {})
            if "camera_vs_aos" in bench:
                lines.append(
                    "%s: layout bench, SoA packets / AoS scalar single rays: camera %.2f×, shadow %.2f×"
                    % (r["scene"], bench["camera_vs_aos"], bench["shadow_vs_aos"])
                )
    return lines
