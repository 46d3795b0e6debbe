#!/usr/bin/env python3
"""Two sturmray builds against each other: render time, alternated, and
whether their images are the same bytes.

Each scene is rendered by build A, then build B, `--rounds` times over; the
table gives the median render time of each (the `seconds` of `--stats`, which
leaves out loading and writing) and B / A. Alternating keeps a shared,
noisy machine's load changes from landing on one side only. The EXRs of the
two builds are compared byte for byte in every round: a change meant only
for speed must not change an image.

    .venv/bin/python tools/ab_render.py --a /tmp/before/sturmray \\
        --b target/release/sturmray --rounds 7 \\
        /usr/share/doc/povray/examples/objects/quartic/torus.pov scenes/showcase.toml

Prints one Markdown table; exits 1 if any image differs.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def render(binary: Path, scene: Path, threads: int, spp: int | None, out: Path) -> float:
    """The render time of one run, in seconds."""
    stats = out.with_suffix(".json")
    cmd = [str(binary), "render", str(scene), "--threads", str(threads)]
    cmd += ["-o", str(out), "--stats", str(stats)]
    if spp is not None:
        cmd += ["--spp", str(spp)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.loads(stats.read_text())["seconds"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a", type=Path, required=True, help="the build before")
    parser.add_argument("--b", type=Path, required=True, help="the build after")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--spp", type=int, default=None, help="samples per pixel (default: the scene's)")
    parser.add_argument("scenes", type=Path, nargs="+")
    args = parser.parse_args()

    print(f"{args.rounds} alternated rounds, {args.threads} threads, median render seconds\n")
    print("| scene | A s | B s | B / A | same bytes |")
    print("|---|---:|---:|---:|---|")
    differs = False
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            times: dict[str, list[float]] = {"a": [], "b": []}
            same = True
            for _ in range(args.rounds):
                for side in ("a", "b"):
                    out = Path(tmp) / f"{side}.exr"
                    times[side].append(render(getattr(args, side), scene, args.threads, args.spp, out))
                same &= (Path(tmp) / "a.exr").read_bytes() == (Path(tmp) / "b.exr").read_bytes()
            a, b = statistics.median(times["a"]), statistics.median(times["b"])
            differs |= not same
            print(f"| {scene.stem} | {a:.3f} | {b:.3f} | {b / a:.3f} | {'yes' if same else 'NO'} |")
    return 1 if differs else 0


if __name__ == "__main__":
    sys.exit(main())
