#!/usr/bin/env python3
"""Issue 18's speed check: `Scene.intersect` on 1M random rays through a
1M-triangle mesh against the CLI's `sturmray trace` and embreex's `run`, all
on one thread, in one run; prints one Markdown table (Mrays/s and ratios).

The CLI's figure is the trace time it reports itself ("N rays traced in X
s": after the .npy is read and the BVH built, before the hits are written),
so file I/O is not counted against it. The module's is the whole call,
numpy arrays in and out: the binding's costs are what this measures.
The three run in turn, --rounds times; each gets its best round. Exits 1 if
the module reaches less than 90% of the CLI's rate or does not beat
embreex. Run by `make python-speed` on release builds.

`--profile module` (or `embreex`) instead traces 100k rays through an
82k-triangle icosphere with only that engine, once, for callgrind:
    valgrind --tool=callgrind python tools/python_speed.py --profile module
then `callgrind_annotate --inclusive=yes` gives each layer's instructions.
"""

from __future__ import annotations

import argparse
import os
import re
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

TRACED = re.compile(r"\((\d+) rays traced in ([0-9.]+) s")


def timed(run) -> float:
    start = time.perf_counter()
    run()
    return time.perf_counter() - start


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sturmray", type=Path, help="the CLI binary (release)")
    parser.add_argument("--rays", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--profile", choices=["module", "embreex"],
                        help="one small run of one engine, for callgrind")
    args = parser.parse_args()
    if args.profile is None and args.sturmray is None:
        parser.error("--sturmray is required for the table")

    # Icospheres of 1,310,720 triangles (82k for --profile).
    mesh = trimesh.creation.icosphere(subdivisions=6 if args.profile else 8)
    rays = 100_000 if args.profile else args.rays
    vertices = mesh.vertices.astype(np.float32)
    faces = mesh.faces.astype(np.uint32)
    rng = np.random.default_rng(1)
    origins = rng.uniform(-3, 3, (rays, 3)).astype(np.float32)
    dirs = (rng.uniform(-0.6, 0.6, (rays, 3)) - origins).astype(np.float32)

    if args.profile != "embreex":
        scene = sturmray.Scene(threads=1)
        scene.add_mesh(vertices, faces)
        scene.commit()
    if args.profile != "module":
        embree = rtcs.EmbreeScene(robust=True)
        keep = TriangleMesh(embree, vertices, faces.astype(np.int32))  # noqa: F841
        # embreex traces on the calling thread; its BVH build may use more.
    if args.profile == "module":
        scene.intersect(origins, dirs)
        return 0
    if args.profile == "embreex":
        embree.run(origins, dirs, output=1)
        return 0

    seconds: dict[str, list[float]] = {"sturmray trace (CLI)": [], "Scene.intersect": [], "embreex run": []}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        with open(tmp / "mesh.obj", "w") as f:
            np.savetxt(f, vertices, fmt="v %.9g %.9g %.9g")
            np.savetxt(f, faces + 1, fmt="f %d %d %d")
        np.save(tmp / "rays.npy", np.hstack([origins, dirs]))
        env = dict(os.environ, RAYON_NUM_THREADS="1")

        def cli() -> float:
            done = subprocess.run(
                [str(args.sturmray), "trace", str(tmp / "mesh.obj"), "--rays", str(tmp / "rays.npy"),
                 "--out", str(tmp / "hits.npy")],
                check=True, env=env, capture_output=True, text=True,
            )
            found = TRACED.search(done.stderr)
            if found is None or int(found[1]) != args.rays:
                sys.exit(f"sturmray trace did not report its trace time: {done.stderr!r}")
            return float(found[2])

        for _ in range(args.rounds):
            seconds["sturmray trace (CLI)"].append(cli())
            seconds["Scene.intersect"].append(timed(lambda: scene.intersect(origins, dirs)))
            seconds["embreex run"].append(timed(lambda: embree.run(origins, dirs, output=1)))
        cli_t = np.load(tmp / "hits.npy")["t"]

    # The three do the same work: the same rays hit, at the same distances.
    ours = scene.intersect(origins, dirs)["t"]
    theirs = embree.run(origins, dirs, output=1)
    embreex_t = np.where(theirs["primID"] == -1, np.inf, theirs["tfar"])
    for name, t in [("the CLI", cli_t), ("embreex", embreex_t)]:
        same = np.isfinite(ours) == np.isfinite(t)
        if same.mean() < 0.9999 or not np.allclose(ours[same & np.isfinite(t)], t[same & np.isfinite(t)], rtol=1e-4):
            sys.exit(f"Scene.intersect and {name} disagree on these rays")

    rate = {name: args.rays / min(s) / 1e6 for name, s in seconds.items()}
    cli_rate = rate["sturmray trace (CLI)"]
    print(f"| {args.rays:,} rays, {len(faces):,} triangles, 1 thread, best of {args.rounds} "
          f"| Mrays/s | vs CLI |")
    print("| --- | ---: | ---: |")
    for name, r in rate.items():
        print(f"| {name} | {r:.2f} | {r / cli_rate:.2f} |")
    ok = rate["Scene.intersect"] >= 0.9 * cli_rate and rate["Scene.intersect"] > rate["embreex run"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
