"""Triangle meshes for the twins: OBJ reading, Penumbra's smooth normals, object placement.

Needs numpy (installed with embreex). Positions stay in object space; `place` applies a RON
`transform` (scale, then rotate about X, Y, Z in degrees, then translate) the way Penumbra does.
"""

import math

import numpy as np


def load_obj(path):
    """Vertices (n×3 float64) and triangles (m×3 int64, 0-based) of an OBJ file.

    Reads `v` and `f` records; polygons are fan-triangulated and `f a/b/c` and negative
    (relative) indices are understood, as Penumbra's importer does. Other records are ignored.
    """
    vertex_text = []
    faces = []
    plain = True  # every face so far is "f i j k" with positive plain indices
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith("v "):
                vertex_text.append(line[2:])
            elif line.startswith("f "):
                parts = line.split()[1:]
                if plain and len(parts) == 3 and all(p.isdigit() for p in parts):
                    faces.append(line[2:])
                    continue
                if plain:
                    faces = [list(map(int, t.split())) for t in faces]
                    plain = False
                faces.extend(_fan(parts, len(vertex_text)))
    numbers = np.array(" ".join(vertex_text).split(), dtype=np.float64)
    if len(numbers) == 3 * len(vertex_text):
        vertices = numbers.reshape(-1, 3)
    else:  # some `v` records carry a weight w: divide by it, as tobj does
        rows = [[float(x) for x in v.split()] for v in vertex_text]
        vertices = np.array([r[:3] if len(r) < 4 else [x / r[3] for x in r[:3]] for r in rows])
    if plain:
        triangles = np.array(" ".join(faces).split(), dtype=np.int64).reshape(-1, 3) - 1
    else:
        triangles = np.array(faces, dtype=np.int64).reshape(-1, 3) - 1
    return vertices, triangles


def _fan(parts, vertex_count):
    """1-based triangles of one polygon record `parts`, relative indices resolved."""
    ids = []
    for p in parts:
        i = int(p.split("/")[0])
        ids.append(i if i > 0 else vertex_count + 1 + i)
    return [[ids[0], ids[k], ids[k + 1]] for k in range(1, len(ids) - 1)]


def vertex_normals(vertices, triangles):
    """Unit per-vertex normals: face normals weighted by area and by the corner angle, summed.

    Penumbra's rule (`geom::mesh::vertex_normals`), without its welding of coincident
    vertices (the scanned models share their vertices) and with (0, 1, 0) where no face counts.
    """
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    ab, ac, bc = b - a, c - a, c - b
    cross = np.cross(ab, ac)
    twice_area = np.linalg.norm(cross, axis=1)
    area_normal = cross * 0.5
    angles = (
        np.arctan2(twice_area, np.einsum("ij,ij->i", ab, ac)),
        np.arctan2(twice_area, -np.einsum("ij,ij->i", ab, bc)),
        np.arctan2(twice_area, np.einsum("ij,ij->i", ac, bc)),
    )
    sums = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(sums, triangles[:, k], area_normal * angles[k][:, None])
    length = np.linalg.norm(sums, axis=1)
    normals = np.tile([0.0, 1.0, 0.0], (len(vertices), 1))
    ok = length > 0.0
    normals[ok] = sums[ok] / length[ok, None]
    return normals


def rotation(rotate_deg):
    """The 3×3 matrix of rotating about X, then Y, then Z by `rotate_deg` degrees."""
    rx, ry, rz = (math.radians(d) for d in rotate_deg)
    x = np.array([[1, 0, 0], [0, math.cos(rx), -math.sin(rx)], [0, math.sin(rx), math.cos(rx)]])
    y = np.array([[math.cos(ry), 0, math.sin(ry)], [0, 1, 0], [-math.sin(ry), 0, math.cos(ry)]])
    z = np.array([[math.cos(rz), -math.sin(rz), 0], [math.sin(rz), math.cos(rz), 0], [0, 0, 1]])
    return z @ y @ x


def place(vertices, transform):
    """World positions of object-space `vertices` under a RON `transform` (a ron.Struct or None)."""
    if transform is None:
        return vertices.copy()
    scale = np.array(transform.get("scale", (1.0, 1.0, 1.0)), dtype=np.float64)
    rotate = transform.get("rotate_deg", (0.0, 0.0, 0.0))
    translate = np.array(transform.get("translate", (0.0, 0.0, 0.0)), dtype=np.float64)
    return (vertices * scale) @ rotation(rotate).T + translate
