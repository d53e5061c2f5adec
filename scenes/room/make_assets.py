#!/usr/bin/env python3
"""Makes the assets of scenes/room.ron: two small PNG textures and a table with a lamp as an OBJ
with its .mtl library. Standard library only; run from anywhere, writes beside this file.
The outputs are committed, so this is only needed to change them."""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(path, width, height, pixel):
    """Writes an 8-bit sRGB RGB PNG whose pixel (x, y), y down, is pixel(x, y) -> (r, g, b) in 0..255."""
    rows = b"".join(
        b"\x00" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(rows, 9)))
        f.write(chunk(b"IEND", b""))


def hash01(i, j):
    """A deterministic value in [0, 1) per integer lattice point."""
    h = (i * 374761393 + j * 668265263) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return (h ^ (h >> 16)) / 2**32


def wood(x, y, size=256):
    """Rings around an off-centre axis, wobbled, in warm browns."""
    u, v = x / size, y / size
    r = math.hypot((u - 0.3) * 6.0, (v - 1.7) * 1.2)
    r += 0.15 * math.sin(u * 9.0 + 2.0 * math.sin(v * 5.0))
    ring = 0.5 + 0.5 * math.sin(r * 18.0)
    grain = 0.08 * hash01(x, y // 3)
    t = 0.65 * ring + grain
    return tuple(int(255 * max(0.0, min(1.0, a + (b - a) * t))) for a, b in zip((0.55, 0.33, 0.17), (0.33, 0.18, 0.08)))


def tiles(x, y, size=256):
    """Four tiles with grout, each tile's shade varied a little."""
    n = 4
    tile = size // n
    gx, gy = x % tile, y % tile
    if gx < 4 or gy < 4:
        return (110, 105, 100)
    s = 0.85 + 0.15 * hash01(x // tile, y // tile)
    speck = 0.05 * hash01(x, y)
    base = (0.86, 0.83, 0.78) if (x // tile + y // tile) % 2 == 0 else (0.62, 0.66, 0.72)
    return tuple(int(255 * min(1.0, c * s + speck)) for c in base)


def box(lo, hi):
    """The 6 faces of an axis-aligned box as quads (corner lists, counter-clockwise seen from outside),
    each with texture coordinates spanning its two longest... simply (0,0)-(1,1) scaled by size."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return [
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # top (+y)
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # bottom
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # +z
        [(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)],  # -z
        [(x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)],  # +x
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # -x
    ]


def cone(centre_x, centre_y, r_bottom, r_top, height, segments=24):
    """An open truncated cone (a lamp shade) around a vertical axis, as quads with (u, v) around and up."""
    quads = []
    for k in range(segments):
        a0, a1 = 2 * math.pi * k / segments, 2 * math.pi * (k + 1) / segments
        p = lambda r, a, y: (centre_x + r * math.cos(a), y, -r * math.sin(a))
        quads.append([p(r_bottom, a0, centre_y), p(r_bottom, a1, centre_y), p(r_top, a1, centre_y + height), p(r_top, a0, centre_y + height)])
    return quads


def write_obj():
    parts = []  # (material, quads, uv_scale)
    parts.append(("wood", box((-1.0, 0.70, -0.6), (1.0, 0.76, 0.6)), 1.0))
    for sx in (-1, 1):
        for sz in (-1, 1):
            x, z = 0.9 * sx, 0.5 * sz
            parts.append(("steel", box((x - 0.04, 0.0, z - 0.04), (x + 0.04, 0.70, z + 0.04)), 1.0))
    # A lamp: a thin stand and a shade, on the table's left side.
    parts.append(("steel", box((-0.72, 0.76, -0.02), (-0.68, 1.20, 0.02)), 1.0))
    parts.append(("shade", cone(-0.7, 1.08, 0.22, 0.12, 0.22), 1.0))
    lines = ["# A small table with a lamp for scenes/room.ron (made by make_assets.py).", "mtllib table.mtl"]
    v, vt = [], []
    faces = []
    for material, quads, _ in parts:
        faces.append(f"usemtl {material}")
        for q in quads:
            idx = []
            for corner, uv in zip(q, [(0, 0), (1, 0), (1, 1), (0, 1)]):
                v.append(corner)
                vt.append(uv)
                idx.append(len(v))
            faces.append("f " + " ".join(f"{i}/{i}" for i in idx))
    lines += [f"v {x:.4f} {y:.4f} {z:.4f}" for x, y, z in v]
    lines += [f"vt {a} {b}" for a, b in vt]
    lines += faces
    with open(os.path.join(HERE, "table.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(HERE, "table.mtl"), "w") as f:
        f.write(
            "# Materials of table.obj. The scene overrides `shade` with a glowing one.\n"
            "newmtl wood\nKd 1.0 1.0 1.0\nKs 0.25 0.25 0.25\nNs 40\nmap_Kd wood.png\nmap_bump -bm 0.5 wood.png\n\n"
            "newmtl steel\nKd 0.25 0.26 0.28\nKs 0.8 0.8 0.8\nNs 200\n\n"
            "newmtl shade\nKd 0.9 0.85 0.7\nKs 0.0 0.0 0.0\nd 0.9\nNi 1.0\n"
        )


if __name__ == "__main__":
    png(os.path.join(HERE, "wood.png"), 256, 256, wood)
    png(os.path.join(HERE, "tiles.png"), 256, 256, tiles)
    write_obj()
