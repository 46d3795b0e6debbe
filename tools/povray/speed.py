#!/usr/bin/env python3
"""POV-Ray 3.7 against sturmray in time, on the objects/quartic samples (issue 20, §5).

Each scene is rendered at the same size with the same thread count and no
anti-aliasing by both, one run of each in turn (POV-Ray, sturmray, POV-Ray,
...) for --rounds rounds, so a change in the machine's load falls on both.
Two times are reported for each:

  * render: the renderer's own count of its rendering. POV-Ray's "Trace
    Time" (its statistics; parsing and bounding are counted apart, and these
    scenes have no photons or radiosity), sturmray's `seconds` from --stats
    (the render loop, after parsing and building the BVH);
  * wall: the whole process, start to exit, as a user waits for it.

The table gives the median of the rounds and the ratios POV-Ray / sturmray
(above 1: sturmray is faster). A POV-Ray render of 1x1 pixels is timed as
well: its wall time is what the POV-Ray process costs beyond rendering
(start-up, and the wait before it exits).

    .venv/bin/python tools/povray/speed.py --sturmray target/release/sturmray
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare import EXAMPLES, INCLUDES, Renderers  # noqa: E402

TRACE_TIME = re.compile(r"Trace Time:.*?\(([0-9.]+) seconds\)", re.DOTALL)


def timed(command: list[str], cwd: Path) -> tuple[float, subprocess.CompletedProcess]:
    start = time.perf_counter()
    proc = subprocess.run(command, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or ["no message"]
        raise SystemExit(f"{command[0]} failed (exit {proc.returncode}): {tail[0]}\n{command}")
    return wall, proc


def time_povray(renderers: Renderers, scene: Path, work: Path) -> tuple[float, float]:
    """(render, wall) seconds of one POV-Ray run."""
    wall, proc = timed(renderers.povray_command(scene, scene, "speed.png"), work)
    found = TRACE_TIME.search(proc.stderr)
    if found is None:
        raise SystemExit(f"no 'Trace Time' in POV-Ray's statistics for {scene}")
    return float(found.group(1)), wall


def time_sturmray(renderers: Renderers, scene: Path, work: Path) -> tuple[float, float]:
    """(render, wall) seconds of one sturmray run."""
    stats = work / "speed.json"
    command = renderers.sturmray_command(scene, scene, work / "speed.exr")
    wall, _ = timed(command + ["--stats", str(stats)], work)
    return float(json.loads(stats.read_text())["seconds"]), wall


def machine() -> str:
    """The CPU the ratios were measured on. They depend on it: Dr.Jit picks
    its LLVM variants' vector width from the CPU's features (8 lanes with
    AVX2, 16 with AVX-512), and the renderers' own speeds differ by CPU."""
    try:
        info = Path("/proc/cpuinfo").read_text()
    except OSError:
        return f"machine: unknown CPU, {os.cpu_count()} logical CPUs"
    lines = info.splitlines()
    model = next((line.split(":", 1)[1].strip() for line in lines if line.startswith("model name")), "unknown")
    flags = next((set(line.split(":", 1)[1].split()) for line in lines if line.startswith("flags")), set())
    widest = next((name for flag, name in (("avx512f", "AVX-512"), ("avx2", "AVX2"), ("avx", "AVX"))
                   if flag in flags), "SSE")
    return f"machine: {model}, {os.cpu_count()} logical CPUs, widest SIMD {widest}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sturmray", type=Path, required=True, help="the sturmray binary")
    parser.add_argument("--width", type=int, default=800)
    parser.add_argument("--height", type=int, default=600)
    parser.add_argument("--threads", type=int, default=2, help="threads of both renderers")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--povray", default="povray", help="the POV-Ray 3.7 binary")
    parser.add_argument("--examples", type=Path, default=EXAMPLES)
    parser.add_argument("--includes", type=Path, default=INCLUDES)
    args = parser.parse_args(argv)
    if not args.sturmray.is_file():
        parser.error(f"--sturmray {args.sturmray}: no such file (cargo build --release)")
    scenes = sorted((args.examples / "quartic").glob("*.pov"))
    if not scenes:
        parser.error(f"no scenes under {args.examples / 'quartic'} (install povray-examples)")
    renderers = Renderers(
        args.sturmray.resolve(), args.width, args.height, args.threads, args.povray, args.includes
    )
    tiny = Renderers(renderers.sturmray, 1, 1, args.threads, args.povray, args.includes)
    rows, overhead = [], []
    with tempfile.TemporaryDirectory(prefix="povray-speed-") as tmp:
        work = Path(tmp)  # POV-Ray may write only here or in /tmp (povray.conf)
        for scene in scenes:
            pov, sturm = [], []
            for _ in range(args.rounds):
                pov.append(time_povray(renderers, scene, work))
                sturm.append(time_sturmray(renderers, scene, work))
            overhead.append(time_povray(tiny, scene, work)[1])
            row = [statistics.median([t[i] for t in runs]) for runs in (pov, sturm) for i in (0, 1)]
            rows.append((scene.stem, *row))
            print(f"{scene.stem}: done", file=sys.stderr)
    print(
        f"{args.width}×{args.height}, {args.threads} threads each, no anti-aliasing, "
        f"median of {args.rounds} alternated runs; {machine()}\n"
    )
    print(
        "| scene | POV-Ray render s | POV-Ray wall s | sturmray render s | sturmray wall s "
        "| render ratio | wall ratio |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    ratios = []
    for name, pov_render, pov_wall, sturm_render, sturm_wall in rows:
        ratio = (pov_render / sturm_render, pov_wall / sturm_wall)
        ratios.append(ratio)
        print(
            f"| {name} | {pov_render:.3f} | {pov_wall:.3f} | {sturm_render:.3f} "
            f"| {sturm_wall:.3f} | {ratio[0]:.2f}× | {ratio[1]:.2f}× |"
        )
    means = [statistics.geometric_mean(r[i] for r in ratios) for i in (0, 1)]
    print(f"| geometric mean | | | | | {means[0]:.2f}× | {means[1]:.2f}× |")
    print(
        f"\nA POV-Ray run of 1×1 pixels takes {statistics.median(overhead):.3f} s wall "
        "(median over the scenes): its start-up and exit, which every POV-Ray wall time "
        "above includes."
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
