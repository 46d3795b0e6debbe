#!/usr/bin/env python3
"""What smooth normals and textures cost over flat shading (issue 16 §6).

Renders the showcase (scenes/showcase.toml: the 70,000-triangle knot in the
Cornell box, a plastic material, flat-shaded) and the same scene with the
knot given per-vertex normals (vn, the area-weighted mean of the faces'
normals), texture coordinates (vt) and a plastic MTL material whose map_Kd is
scenes/asset/vase.png, alternately for --rounds rounds (flat first in even
rounds, smooth first in odd ones), with the release binary. Each render's
time is its own (`--stats`: the render, not the loading). The figure is the
median of the rounds' ratios smooth / flat, with the best of each side as a
check. The smooth knot and its scene are written under scenes/generated/
(ignored by git). Standard library only.

    cargo build --release && python3 tools/shading_cost.py
"""

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "scenes" / "generated" / "shading"


def smooth_knot():
    """knot.obj with vn and vt per vertex, and an MTL with map_Kd."""
    verts, faces = [], []
    for line in (ROOT / "scenes/meshes/knot.obj").read_text().splitlines():
        if line.startswith("v "):
            verts.append(tuple(map(float, line.split()[1:4])))
        elif line.startswith("f "):
            faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    normals = [[0.0, 0.0, 0.0] for _ in verts]
    for f in faces:
        for k in range(1, len(f) - 1):
            a, b, c = verts[f[0]], verts[f[k]], verts[f[k + 1]]
            e1 = [b[i] - a[i] for i in range(3)]
            e2 = [c[i] - a[i] for i in range(3)]
            n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0])
            for v in (f[0], f[k], f[k + 1]):
                for i in range(3):
                    normals[v][i] += n[i]
    out = ["mtllib knot.mtl\n", "usemtl painted\n"]
    for (x, y, z), n in zip(verts, normals):
        length = math.sqrt(sum(c * c for c in n)) or 1.0
        out.append("v %r %r %r\n" % (x, y, z))
        out.append("vn %r %r %r\n" % tuple(c / length for c in n))
        out.append("vt %r %r\n" % (math.atan2(y, x) / math.pi + 1.0, 2.0 * z + 0.5))
    out.extend("f %s\n" % " ".join("%d/%d/%d" % (v + 1, v + 1, v + 1) for v in f) for f in faces)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "knot.obj").write_text("".join(out))
    (OUT / "knot.mtl").write_text(
        "newmtl painted\nKd 0.15 0.3 0.75\nKs 0.06 0.06 0.06\nNs 200\n"
        "map_Kd ../../asset/vase.png\n")
    showcase = (ROOT / "scenes/showcase.toml").read_text()
    scene = (showcase.replace('"cornell/cornell.obj"', '"../../cornell/cornell.obj"')
             .replace('file = "meshes/knot.obj"\nmaterial = "knot_blue"\n', 'file = "knot.obj"\n'))
    assert scene.count('file = "knot.obj"') == 1, "showcase.toml changed: update this tool"
    (OUT / "showcase_smooth.toml").write_text(scene)
    return OUT / "showcase_smooth.toml"


def render_seconds(binary, scene, threads):
    with tempfile.TemporaryDirectory() as tmp:
        stats = Path(tmp) / "stats.json"
        subprocess.run([str(binary), "render", str(scene), "-o", str(Path(tmp) / "x.exr"),
                        "--stats", str(stats), "--threads", str(threads)],
                       check=True, capture_output=True)
        return json.loads(stats.read_text())["seconds"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--binary", default=str(ROOT / "target/release/sturmray"))
    args = parser.parse_args()
    smooth = smooth_knot()
    flat = ROOT / "scenes/showcase.toml"
    render_seconds(args.binary, flat, args.threads)  # warm-up, not counted
    times = {"flat": [], "smooth": []}
    for r in range(args.rounds):
        order = [("flat", flat), ("smooth", smooth)]
        for name, scene in order if r % 2 == 0 else order[::-1]:
            times[name].append(render_seconds(args.binary, scene, args.threads))
    ratios = [s / f for f, s in zip(times["flat"], times["smooth"])]
    print("flat   (showcase.toml)       best %.3f s  %s" % (min(times["flat"]), times["flat"]))
    print("smooth (vn, vt, map_Kd)      best %.3f s  %s" % (min(times["smooth"]), times["smooth"]))
    print("smooth / flat: median %.3f over %d rounds (best / best %.3f)"
          % (statistics.median(ratios), args.rounds, min(times["smooth"]) / min(times["flat"])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
