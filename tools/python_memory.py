#!/usr/bin/env python3
"""What `Scene.add_mesh` and `commit` add to the peak resident memory for a
1,310,720-triangle mesh (docs/python.md, "Meshes are copied"): the peak RSS
(VmHWM) is reset before each step (/proc/self/clear_refs) and read after it.
glibc's mmap threshold is fixed (the script re-runs itself with
MALLOC_MMAP_THRESHOLD_ set), so freed arrays go back to the system and the
figures are the scene's own. Run by `make python-speed`.
"""

from __future__ import annotations

import gc
import os
import sys

import numpy as np
import trimesh

import sturmray

THRESHOLD = "MALLOC_MMAP_THRESHOLD_"


def peak_mib() -> float:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmHWM in /proc/self/status")


def reset_peak() -> None:
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def main() -> None:
    if THRESHOLD not in os.environ:
        os.execve(sys.executable, [sys.executable, *sys.argv], {**os.environ, THRESHOLD: "65536"})
    mesh = trimesh.creation.icosphere(subdivisions=8)
    vertices = np.ascontiguousarray(mesh.vertices, np.float32)
    faces = np.ascontiguousarray(mesh.faces, np.uint32)
    del mesh
    gc.collect()
    reset_peak()
    before = peak_mib()
    scene = sturmray.Scene(threads=1)
    scene.add_mesh(vertices, faces)
    added = peak_mib()
    reset_peak()
    scene.commit()
    committed = peak_mib()
    print(f"{len(faces):,} triangles, arrays {(vertices.nbytes + faces.nbytes) / 2**20:.1f} MiB: "
          f"add_mesh +{added - before:.1f} MiB, commit peak +{committed - added:.1f} MiB "
          f"(peak RSS {before:.1f} -> {added:.1f} -> {committed:.1f} MiB)")


if __name__ == "__main__":
    main()
