#!/usr/bin/env python3
"""Issue 18's speed check: `Scene.intersect` on 1M random rays through a
1M-triangle mesh against the CLI's `sturmray trace` and embreex's `run`, all
on one thread, in one run; prints one Markdown table (Mrays/s and ratios).

The CLI's trace time is the process time with the rays minus the process
time with one ray (loading the mesh and building the BVH cancel out). Best of
--rounds for each. Exits 1 if the module reaches less than 90% of the CLI's
rate or does not beat embreex. Run by `make python-speed` on release builds.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

import sturmray


def best(rounds: int, run) -> float:
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sturmray", required=True, type=Path, help="the CLI binary (release)")
    parser.add_argument("--rays", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()

    mesh = trimesh.creation.icosphere(subdivisions=8)  # 1,310,720 triangles
    vertices = mesh.vertices.astype(np.float32)
    faces = mesh.faces.astype(np.uint32)
    rng = np.random.default_rng(1)
    origins = rng.uniform(-3, 3, (args.rays, 3)).astype(np.float32)
    dirs = (rng.uniform(-0.6, 0.6, (args.rays, 3)) - origins).astype(np.float32)

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        with open(tmp / "mesh.obj", "w") as f:
            np.savetxt(f, vertices, fmt="v %.9g %.9g %.9g")
            np.savetxt(f, faces + 1, fmt="f %d %d %d")
        np.save(tmp / "rays.npy", np.hstack([origins, dirs]))
        np.save(tmp / "one.npy", np.hstack([origins[:1], dirs[:1]]))
        env = dict(os.environ, RAYON_NUM_THREADS="1")

        def cli(rays: str):
            subprocess.run(
                [str(args.sturmray), "trace", str(tmp / "mesh.obj"), "--rays", str(tmp / rays),
                 "--out", str(tmp / "hits.npy")],
                check=True, env=env, capture_output=True,
            )

        cli_s = best(args.rounds, lambda: cli("rays.npy")) - best(args.rounds, lambda: cli("one.npy"))

    scene = sturmray.Scene(threads=1)
    scene.add_mesh(vertices, faces)
    scene.commit()
    module_s = best(args.rounds, lambda: scene.intersect(origins, dirs))

    embree = rtcs.EmbreeScene(robust=True)
    keep = TriangleMesh(embree, vertices, faces.astype(np.int32))  # noqa: F841
    embreex_s = best(args.rounds, lambda: embree.run(origins, dirs, output=1))

    rate = {name: args.rays / s / 1e6 for name, s in
            [("sturmray trace (CLI)", cli_s), ("Scene.intersect", module_s), ("embreex run", embreex_s)]}
    cli_rate = rate["sturmray trace (CLI)"]
    print(f"| {args.rays:,} rays, {len(faces):,} triangles, 1 thread | Mrays/s | vs CLI |")
    print("| --- | ---: | ---: |")
    for name, r in rate.items():
        print(f"| {name} | {r:.2f} | {r / cli_rate:.2f} |")
    ok = rate["Scene.intersect"] >= 0.9 * cli_rate and rate["Scene.intersect"] > rate["embreex run"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
