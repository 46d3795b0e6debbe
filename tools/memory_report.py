#!/usr/bin/env python3
"""Peak memory of large scenes: generates them under scenes/generated/ (ignored
by git), renders each at 64x48 with one sample under `/usr/bin/time -v`, and
prints the peak resident set size, with bytes per triangle for the meshes
(whole process, and the slope between 1M and 5M triangles). Fails if a
render fails or needs more than the limit.

With --instances it measures instancing instead: 1,000 instances of the
1M-triangle mesh against one copy and against 10 copies written out as mesh
objects (1,000 flattened copies would need about 100 times the 10), and
1,000 instances of a 10k-triangle mesh against its 1,000 copies flattened.

Usage: memory_report.py STURMRAY_BINARY [--limit-gib 24] [--instances] [--backend B]
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


def placed_scene(name, mesh, cols, rows, copies, instanced):
    """`copies` of the cols x rows grid `mesh`.obj side by side, as instances
    of one prototype or as mesh objects of their own."""
    side = math.ceil(math.sqrt(copies))
    w, h = cols / 100 + 0.5, rows / 100 + 0.5
    toml = os.path.join(OUT, f"{name}.toml")
    with open(toml, "w") as f:
        cx, cy = side * w / 2, side * h / 2
        f.write(CAMERA.format(ex=cx, ey=-cy, ez=2 * cy, lx=cx, ly=cy))
        if instanced:
            f.write(f'[[prototypes.grid.objects]]\ntype = "mesh"\nfile = "{mesh}.obj"\n')
        for k in range(copies):
            what = 'type = "instance"\nprototype = "grid"' if instanced else \
                f'type = "mesh"\nfile = "{mesh}.obj"'
            f.write(f"[[objects]]\n{what}\n"
                    f"transform = {{ translate = [{k % side * w}, {k // side * h}, 0] }}\n")
    return toml


def instance_cases():
    """(name, scene, triangles placed) of the --instances study."""
    mesh_scene("mesh_1m", 1000, 500)
    mesh_scene("mesh_10k", 100, 50)
    return [
        ("mesh_1m", os.path.join(OUT, "mesh_1m.toml"), 1_000_000),
        ("inst_1000x1m", placed_scene("inst_1000x1m", "mesh_1m", 1000, 500, 1000, True),
         1_000_000_000),
        ("flat_10x1m", placed_scene("flat_10x1m", "mesh_1m", 1000, 500, 10, False), 10_000_000),
        ("inst_1000x10k", placed_scene("inst_1000x10k", "mesh_10k", 100, 50, 1000, True),
         10_000_000),
        ("flat_1000x10k", placed_scene("flat_1000x10k", "mesh_10k", 100, 50, 1000, False),
         10_000_000),
    ]


def peak_rss(binary, scene, backend="embree"):
    """Peak resident set size in bytes of rendering `scene`, and seconds."""
    out = os.path.join("out", "memory", os.path.basename(scene).replace(".toml", ".exr"))
    run = subprocess.run(
        ["/usr/bin/time", "-v", binary, "render", scene, "-o", out, "--backend", backend],
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
    parser.add_argument("--instances", action="store_true")
    parser.add_argument("--backend", default="embree")
    args = parser.parse_args()
    os.makedirs(OUT, exist_ok=True)
    if args.instances:
        gib = 1 << 30
        print(f"{'scene':<14} {'peak RSS':>10} {'wall':>9}  triangles placed")
        for name, scene, placed in instance_cases():
            rss, wall = peak_rss(args.binary, scene, args.backend)
            print(f"{name:<14} {rss / gib:>8.3f} GiB {wall:>9}  {placed:,}")
        return
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
