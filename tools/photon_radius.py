#!/usr/bin/env python3
"""What the photon pass costs on a scene with a large floor (issue 15).

`scenes/glass_floor.toml`: a glass ball of radius 0.5 one unit above a diffuse
floor 2000 units wide, lit by a point light above it, rendered by the Whitted
integrator at 400x300 with the default settings (4 samples a pixel, 200,000
photons, the default gather radius), with and without the photon pass
(`--photons 0`), and, for comparison, with the radius the old default gave
(1/200 of the scene's bounding-box diagonal, 14.1 units). One run of each in
turn, for --rounds rounds, so a change in the machine's load falls on all of
them.

Two times are reported for each: `render`, sturmray's own `seconds` from
--stats (the photon pass and the render loop, after loading and building the
BVH), and `wall`, the whole process. The table gives the median of the rounds
and the median of each round's ratio to its run without photons; the script
fails if the default's render ratio is above 1.2 (issue 15's limit). Standard
library only, so it runs without the .venv:

    python3 tools/photon_radius.py --bin target/release/sturmray
"""

from __future__ import annotations

import argparse
import json
import platform
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "scenes" / "glass_floor.toml"
LIMIT = 1.2
# The scene's box: the floor's clip box, y from -0.1, to the ball's top at 1.5.
OLD_RADIUS = (2 * 2000.0**2 + 1.6**2) ** 0.5 / 200
REPORT = re.compile(r"photon map: .*")


def variants(work: Path) -> dict[str, tuple[Path, list[str]]]:
    """name -> (scene, extra flags); the old default's scene is written to `work`."""
    old = work / "old_radius.toml"
    text = SCENE.read_text()
    if "\n[render]\n" not in text:
        sys.exit(f"{SCENE} has no [render] table to add the old radius to")
    old.write_text(text.replace("\n[render]\n",
                                f"\n[render]\nphotons = {{ radius = {OLD_RADIUS:.4f} }}\n"))
    return {
        "no photon pass": (SCENE, ["--photons", "0"]),
        "default radius": (SCENE, []),
        f"old default, radius {OLD_RADIUS:.1f}": (old, []),
    }


def run(binary: Path, work: Path, name: str, scene: Path, flags: list[str], threads: int):
    """(render seconds, wall seconds, the photon report line or "") of one run."""
    stats = work / f"{name}.json"
    command = [str(binary), "render", str(scene), "-o", str(work / f"{name}.exr"),
               "--threads", str(threads), "--stats", str(stats), *flags]
    start = time.perf_counter()
    proc = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"failed (exit {proc.returncode}): {' '.join(command)}\n{proc.stderr}")
    report = REPORT.search(proc.stderr)
    seconds = json.loads(stats.read_text())["seconds"]
    return seconds, wall, report.group(0) if report else ""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", default="target/release/sturmray", help="a release build")
    parser.add_argument("--dir", default="out/photon_radius", help="where the files go")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()

    work = ROOT / args.dir
    work.mkdir(parents=True, exist_ok=True)
    scenes = {name: (path, flags, f"run{i}")
              for i, (name, (path, flags)) in enumerate(variants(work).items())}

    times: dict[str, list[tuple[float, float]]] = {name: [] for name in scenes}
    reports: dict[str, str] = {}
    for _ in range(args.rounds):
        for name, (path, flags, stem) in scenes.items():
            seconds, wall, report = run(ROOT / args.bin, work, stem, path, flags, args.threads)
            times[name].append((seconds, wall))
            reports[name] = report

    base = [t for t, _ in times["no photon pass"]]
    base_wall = [w for _, w in times["no photon pass"]]
    print(f"400x300, 4 spp, Whitted, {args.threads} threads, median of {args.rounds} "
          f"alternated runs; {platform.machine()}")
    print()
    print("| photon pass | render s | wall s | render ratio | wall ratio | photon map |")
    print("|---|---:|---:|---:|---:|---|")
    ratios = {}
    for name, runs in times.items():
        render = statistics.median(t for t, _ in runs)
        wall = statistics.median(w for _, w in runs)
        # Each round's own ratio, so a slow moment weighs on both runs of it.
        ratio = statistics.median(t / b for (t, _), b in zip(runs, base))
        wall_ratio = statistics.median(w / b for (_, w), b in zip(runs, base_wall))
        ratios[name] = ratio
        report = reports[name].removeprefix("photon map: ") or "none"
        print(f"| {name} | {render:.3f} | {wall:.3f} | {ratio:.2f}x | {wall_ratio:.2f}x | "
              f"{report} |")
    ratio = ratios["default radius"]
    verdict = "within" if ratio <= LIMIT else "above"
    print(f"\nthe default radius: {ratio:.2f}x the render without photons, {verdict} {LIMIT}x")
    if ratio > LIMIT:
        sys.exit(1)


if __name__ == "__main__":
    main()
