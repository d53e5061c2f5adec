"""Embree's single-ray throughput on a Penumbra mesh scene, through embreex.

The rays are the ones benches/harness/rays.rs traces for Penumbra's `layout` bench: one camera
ray through each pixel centre with Penumbra's pinhole camera (vertical `fov_deg`, `look_at`,
`up`), and one shadow ray from each camera hit towards the scene's first point light. The
geometry is the scene's meshes placed by their transforms, plus each plane as a square of
half-size 1e6 (Embree has no infinite plane; rays that would meet the plane farther out miss).

embreex's `EmbreeScene.run` loops over the rays in C without the GIL, calling
`rtcIntersect1` (closest hit) or `rtcOccluded1` (any hit) once per ray: Embree's single-ray
API, not its packet or stream API. The scene is built with Embree's robust flag (embreex's
default). T threads each run a share of the rays (64 chunks handed out in turn); Embree's own
BVH build uses every core (embreex cannot limit its device's threads).

Run: python3 embree_bench.py SCENE.ron --models DIR --threads 2 --reps 5 --json out.json
"""

import argparse
import json
import math
import os
import statistics
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mesh as meshes  # noqa: E402
import ron  # noqa: E402

PLANE_HALF_SIZE = 1e6
CHUNKS = 64
# Shadow rays start this far (relative to the hit point's magnitude, at least 1) off the
# surface along its normal, and stop this fraction short of the light.
SPAWN_OFFSET = 1e-4
SHADOW_EPSILON = 1e-4


def camera_rays(camera):
    """Origins and unit directions (float32) through every pixel centre, row by row."""
    width, height = camera["width"], camera["height"]
    position = np.array(camera["position"], dtype=np.float64)
    forward = np.array(camera["look_at"], dtype=np.float64) - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.array(camera.get("up", (0.0, 1.0, 0.0)), dtype=np.float64))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half_h = math.tan(math.radians(camera["fov_deg"]) / 2.0)
    half_w = half_h * width / height
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    sx = (2.0 * px.ravel() / width - 1.0) * half_w
    sy = (1.0 - 2.0 * py.ravel() / height) * half_h
    directions = forward + sx[:, None] * right + sy[:, None] * up
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    origins = np.repeat(position[None, :], len(directions), axis=0)
    return origins.astype(np.float32), directions.astype(np.float32)


def plane_quad(point, normal):
    """Two triangles covering a square of the plane around `point`."""
    n = np.array(normal, dtype=np.float64)
    n /= np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(n, helper)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    p = np.array(point, dtype=np.float64)
    h = PLANE_HALF_SIZE
    corners = np.array([p - h * u - h * v, p + h * u - h * v, p + h * u + h * v, p - h * u + h * v])
    return corners, np.array([[0, 1, 2], [0, 2, 3]])


def world_geometry(scene, models):
    """All meshes (placed) and planes of the scene as one triangle soup; the mesh triangle count."""
    vertex_blocks, index_blocks, base, mesh_triangles = [], [], 0, 0
    for obj in scene["objects"]:
        shape = obj["shape"]
        if shape.name == "Mesh":
            vertices, triangles = meshes.load_obj(os.path.join(models, os.path.basename(shape["file"])))
            vertices = meshes.place(vertices, obj.get("transform"))
            mesh_triangles += len(triangles)
        elif shape.name == "Plane":
            vertices, triangles = plane_quad(shape["point"], shape["normal"])
        else:
            raise SystemExit(f"embree_bench: shape {shape.name} is not supported (meshes and planes only)")
        vertex_blocks.append(vertices)
        index_blocks.append(triangles + base)
        base += len(vertices)
    vertices = np.concatenate(vertex_blocks).astype(np.float32)
    indices = np.concatenate(index_blocks).astype(np.int32)
    return vertices, indices, mesh_triangles


def point_light(scene):
    for light in scene.get("lights", []):
        if light.name == "Point":
            return np.array(light["position"], dtype=np.float64)
    raise SystemExit("embree_bench: the scene has no point light")


def in_parallel(pool, embree, origins, directions, query, dists=None, output=None):
    """Runs `embree.run` over `CHUNKS` slices of the rays on the pool's threads; results in order."""
    bounds = np.linspace(0, len(origins), CHUNKS + 1).astype(int)

    def chunk(k):
        lo, hi = bounds[k], bounds[k + 1]
        d = None if dists is None else np.ascontiguousarray(dists[lo:hi])
        return embree.run(origins[lo:hi], directions[lo:hi], dists=d, query=query, output=output)

    return list(pool.map(chunk, range(CHUNKS)))


def shadow_rays(origins, directions, hits, light):
    """One shadow ray per camera hit: from just off the hit (on the side the ray came from)
    towards `light`, stopping just short of it."""
    tfar = np.concatenate([h["tfar"] for h in hits])
    prim = np.concatenate([h["primID"] for h in hits])
    normal = np.concatenate([h["Ng"] for h in hits]).astype(np.float64)
    hit = prim >= 0
    d = directions[hit].astype(np.float64)
    p = origins[hit].astype(np.float64) + d * tfar[hit, None]
    n = normal[hit] / np.linalg.norm(normal[hit], axis=1)[:, None]
    n *= np.where(np.einsum("ij,ij->i", n, d) < 0.0, 1.0, -1.0)[:, None]
    offset = SPAWN_OFFSET * np.maximum(1.0, np.abs(p).max(axis=1))
    start = p + n * offset[:, None]
    to = light - start
    dist = np.linalg.norm(to, axis=1)
    return (
        start.astype(np.float32),
        (to / dist[:, None]).astype(np.float32),
        (dist * (1.0 - SHADOW_EPSILON)).astype(np.float32),
    )


def median_time(reps, f):
    times = []
    for _ in range(reps):
        started = time.perf_counter()
        f()
        times.append(time.perf_counter() - started)
    return statistics.median(times), times


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="Penumbra RON scene with meshes and a point light")
    parser.add_argument("--models", required=True, help="folder holding the scene's OBJ files")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--json", required=True, help="where to write the figures")
    args = parser.parse_args()

    scene = ron.load(args.scene)
    vertices, indices, mesh_triangles = world_geometry(scene, args.models)
    origins, directions = camera_rays(scene["camera"])
    light = point_light(scene)

    embree = rtcore_scene.EmbreeScene()
    TriangleMesh(embree, vertices, indices)
    started = time.perf_counter()
    embree.run(origins[:1], directions[:1])  # the first query commits (builds) the scene
    build_s = time.perf_counter() - started

    with ThreadPoolExecutor(max_workers=args.threads) as pool:
        hits = in_parallel(pool, embree, origins, directions, "INTERSECT", output=True)
        s_origins, s_directions, s_dists = shadow_rays(origins, directions, hits, light)
        camera_s, camera_all = median_time(
            args.reps, lambda: in_parallel(pool, embree, origins, directions, "INTERSECT", output=True)
        )
        shadow_s, shadow_all = median_time(
            args.reps, lambda: in_parallel(pool, embree, s_origins, s_directions, "OCCLUDED", dists=s_dists)
        )
        occluded = sum(
            int((r == 0).sum())
            for r in in_parallel(pool, embree, s_origins, s_directions, "OCCLUDED", dists=s_dists)
        )

    report = {
        "api": "embreex EmbreeScene.run: rtcIntersect1 / rtcOccluded1 per ray in a C loop without the GIL",
        "robust": True,
        "threads": args.threads,
        "mesh_triangles": mesh_triangles,
        "build_s": build_s,
        "camera": {
            "rays": len(origins),
            "hits": len(s_origins),
            "median_s": camera_s,
            "all_s": camera_all,
            "mrays_per_s": len(origins) / camera_s / 1e6,
        },
        "shadow": {
            "rays": len(s_origins),
            "occluded": occluded,
            "median_s": shadow_s,
            "all_s": shadow_all,
            "mrays_per_s": len(s_origins) / shadow_s / 1e6,
        },
    }
    with open(args.json, "w", encoding="utf-8") as f:
        json.dump(report, f, indent=2)


if __name__ == "__main__":
    main()
