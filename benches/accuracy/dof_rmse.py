#!/usr/bin/env python3
"""Depth-of-field error against a high-sample reference, fixed and adaptive (README, "Depth
of field"): renders scenes/effects_dof.ron with 1024 lens samples once as the reference, then
the default render, 64 lens samples and two adaptive settings, and prints each one's 8-bit
RMSE, rays and trace time.

    python3 benches/accuracy/dof_rmse.py [--binary target/release/penumbra] [--out DIR]
        [--reference REF.png]

Pass the same --reference to compare two builds against one reference. Needs numpy and
pillow (`pip install numpy pillow`).
"""
import argparse
import json
import os
import subprocess

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "scenes", "effects_dof.ron")
VARIANTS = [
    ("default", []),
    ("lens64", ["--samples", "lens=64"]),
    ("adaptive_0.05_3", ["--adaptive", "0.05:3"]),
    ("adaptive_0.02_4", ["--adaptive", "0.02:4"]),
]


def render(binary, out, name, args):
    path, stats = os.path.join(out, f"{name}.png"), os.path.join(out, f"{name}.json")
    cmd = [binary, "render", SCENE, "-o", path, "--stats", stats, "--threads", "2", "--quiet"]
    subprocess.run(cmd + args, check=True, stdout=subprocess.DEVNULL)
    with open(stats) as f:
        return path, json.load(f)


def pixels(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "penumbra"))
    parser.add_argument("--out", default="dof-rmse")
    parser.add_argument("--reference", help="a reference PNG made earlier (default: render one)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    reference = args.reference or render(args.binary, args.out, "reference", ["--samples", "lens=1024"])[0]
    truth = pixels(reference)
    for name, extra in VARIANTS:
        path, stats = render(args.binary, args.out, name, extra)
        rmse = np.sqrt(np.mean((pixels(path) - truth) ** 2))
        rays = sum(v for v in stats["rays"].values() if isinstance(v, int))
        print(f"{name:18} RMSE {rmse:5.2f}/255  rays {rays / 1e6:6.2f} M  "
              f"lens {stats['rays']['lens'] / 1e6:6.2f} M  trace {stats['times']['trace']:.3f} s")


if __name__ == "__main__":
    main()
