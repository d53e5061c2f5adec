"""ANCHORS.md's "many" scene as a RON file: 100,000 random spheres of radius 0.02–0.06 in an
8×8×8 box over a ground plane, one point light, 640×480, 1 sample per pixel.

The repository has no RON of it (benches/layout.rs builds it in code from the `rand` crate),
so the harness writes one from Python's seeded generator: the same file feeds Penumbra and,
through povtwin, POV-Ray. Layout, camera and light follow benches/layout.rs; materials and
background follow the mesh scenes (Material::default() in the bench: grey, no highlight).
"""

import random

import ron
from ron import Ident, Struct

SEED = 100_000
COUNT = 100_000
BOX_MIN = (-4.0, 0.1, -4.0)
BOX_MAX = (4.0, 8.1, 4.0)


def scene():
    """The scene as ron values (deterministic: the same every call)."""
    rng = random.Random(SEED)
    spheres = []
    for _ in range(COUNT):
        centre = tuple(round(rng.uniform(lo, hi), 6) for lo, hi in zip(BOX_MIN, BOX_MAX))
        radius = round(rng.uniform(0.02, 0.06), 6)
        spheres.append(
            Struct(
                None, {"shape": Struct("Sphere", {"centre": centre, "radius": radius}), "material": "ball"}
            )
        )
    ground = Struct(
        None,
        {
            "name": "ground",
            "shape": Struct("Plane", {"point": (0.0, 0.0, 0.0), "normal": (0.0, 1.0, 0.0)}),
            "material": "ground",
        },
    )
    return Struct(
        "Scene",
        {
            "camera": Struct(
                None,
                {
                    "position": (0.0, 4.0, -11.0),
                    "look_at": (0.0, 4.0, 0.0),
                    "up": (0.0, 1.0, 0.0),
                    "fov_deg": 45.0,
                    "width": 640,
                    "height": 480,
                },
            ),
            "settings": Struct(
                None,
                {
                    "max_depth": 1,
                    "background": (0.6, 0.7, 0.85),
                    "ambient": (0.1, 0.1, 0.1),
                    "seed": 1,
                    "aa": Struct(None, {"samples": 1, "pattern": Ident("Jittered")}),
                },
            ),
            "materials": [
                Struct(None, {"name": "ground", "kd": (0.5, 0.5, 0.5), "ks": 0.0}),
                Struct(None, {"name": "ball", "kd": (0.75, 0.62, 0.5), "ks": 0.4, "shininess": 50.0}),
            ],
            "lights": [
                Struct("Point", {"position": (6.0, 14.0, -10.0), "colour": (1.0, 1.0, 1.0), "intensity": 1.0})
            ],
            "objects": [ground] + spheres,
        },
    )


def write(path):
    """Writes the scene's RON to `path`."""
    with open(path, "w", encoding="utf-8") as f:
        f.write('// ANCHORS.md\'s "many" scene, written by benches/compare/many.py (seed %d).\n' % SEED)
        f.write(ron.dumps(scene()))
        f.write("\n")
