#!/usr/bin/env python3
"""Peak memory of large scenes: generates them under scenes/generated/ (ignored
by git), renders each at 64x48 with one sample under `/usr/bin/time -v`, and
prints the peak resident set size, with bytes per triangle for the meshes
(whole process, and the slope between 1M and 5M triangles). Fails if a
render fails or needs more than the limit.

Usage: memory_report.py STURMRAY_BINARY [--limit-gib 24]
Standard library only.
"""

import argparse
import math
import os
import re
import subprocess
import sys

OUT = os.path.join("scenes", "generated")

CAMERA = """[camera]
eye = [{ex}, {ey}, {ez}]
look_at = [{lx}, {ly}, 0]
up = [0, 0, 1]
fov = 50
width = 64
height = 48
[render]
spp = 1
[[lights]]
type = "directional"
direction = [-1, -1, -2]
irradiance = [2, 2, 2]
"""


def write_grid(path, cols, rows):
    """A wavy height field of cols x rows quads: 2 * cols * rows triangles."""
    with open(path, "w") as f:
        for j in range(rows + 1):
            y = j / 100
            f.write("".join(
                f"v {i / 100:.2f} {y:.2f} {0.05 * math.sin(i / 7) * math.cos(j / 5):.4f}\n"
                for i in range(cols + 1)
            ))
        w = cols + 1
        for j in range(rows):
            f.write("".join(
                f"f {j * w + i + 1} {j * w + i + 2} {(j + 1) * w + i + 2} {(j + 1) * w + i + 1}\n"
                for i in range(cols)
            ))


def mesh_scene(name, cols, rows):
    obj = os.path.join(OUT, f"{name}.obj")
    if not os.path.exists(obj):
        write_grid(obj + ".tmp", cols, rows)
        os.replace(obj + ".tmp", obj)
    toml = os.path.join(OUT, f"{name}.toml")
    with open(toml, "w") as f:
        cx, cy = cols / 200, rows / 200
        f.write(CAMERA.format(ex=cx, ey=-cy, ez=2 * cy, lx=cx, ly=cy))
        f.write(f'[[objects]]\ntype = "mesh"\nfile = "{name}.obj"\n')
    return toml


def shapes_scene(name, count):
    """count analytic shapes on a square grid, cycling through four types."""
    side = math.ceil(math.sqrt(count))
    kinds = [
        'type = "sphere"\nradius = 0.4',
        'type = "torus"\nmajor = 0.3\nminor = 0.1',
        'type = "ellipsoid"\nradii = [0.4, 0.3, 0.2]',
        'type = "cylinder"\nradius = 0.3',
    ]
    toml = os.path.join(OUT, f"{name}.toml")
    with open(toml, "w") as f:
        f.write(CAMERA.format(ex=side / 2, ey=-side / 2, ez=side, lx=side / 2, ly=side / 2))
        for k in range(count):
            x, y = k % side, k // side
            f.write(f"[[objects]]\n{kinds[k % 4]}\n"
                    f"transform = {{ translate = [{x}, {y}, 0] }}\n")
    return toml


def peak_rss(binary, scene):
    """Peak resident set size in bytes of rendering `scene`, and seconds."""
    out = os.path.join("out", "memory", os.path.basename(scene).replace(".toml", ".exr"))
    run = subprocess.run(
        ["/usr/bin/time", "-v", binary, "render", scene, "-o", out],
        capture_output=True, text=True,
    )
    if run.returncode != 0:
        sys.exit(f"render of {scene} failed:\n{run.stderr}")
    kib = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time.*: (.+)", run.stderr).group(1)
    return kib * 1024, wall


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("--limit-gib", type=float, default=24)
    args = parser.parse_args()
    os.makedirs(OUT, exist_ok=True)
    # 2 * 1000 * 500 = 1M and 2 * 2000 * 1250 = 5M triangles.
    cases = [
        ("mesh_1m", mesh_scene("mesh_1m", 1000, 500), 1_000_000),
        ("mesh_5m", mesh_scene("mesh_5m", 2000, 1250), 5_000_000),
        ("shapes_100k", shapes_scene("shapes_100k", 100_000), 0),
    ]
    gib = 1 << 30
    peaks = {}
    failed = False
    print(f"{'scene':<12} {'peak RSS':>10} {'wall':>9}  per item")
    for name, scene, triangles in cases:
        rss, wall = peak_rss(args.binary, scene)
        peaks[name] = rss
        per = f"{rss / triangles:.0f} B/triangle" if triangles else f"{rss / 100_000:.0f} B/shape"
        print(f"{name:<12} {rss / gib:>8.2f} GiB {wall:>9}  {per}")
        failed |= rss > args.limit_gib * gib
    slope = (peaks["mesh_5m"] - peaks["mesh_1m"]) / 4_000_000
    print(f"marginal cost between 1M and 5M triangles: {slope:.0f} bytes per triangle")
    if failed:
        sys.exit(f"a render needed more than {args.limit_gib} GiB")


if __name__ == "__main__":
    main()
