#!/usr/bin/env python3
"""What the sampler buys: the error of path-traced renders against a
high-spp reference at several sample counts, for the `sobol` and
`independent` samplers (issue 15).

Each scene is rendered at --width pixels wide (the height by its aspect
ratio), with adaptive sampling off so that every pixel takes the sample count
asked for, and otherwise as shipped:

  * the reference: --reference-spp samples per pixel, independent sampler, as
    two halves of different seeds merged by `sturmray merge`. Half the RMSE
    between the two halves is the reference's own noise (each half has twice
    its variance), printed as the floor: every RMSE below includes it, added
    in quadrature, since the renders measured are independent of it.
  * the renders measured: each sampler at each --spp, --seeds times with
    seeds 1, 2, ... (other than the reference's); the RMSE is the root of the
    mean squared error over the seeds, over every pixel and R, G, B channel
    of linear radiance, with the range of the MSE ratio seed by seed. Seconds
    are sturmray's own (`--stats`), the median over the seeds.

Prints one Markdown table, for docs/integrators.md. With --work DIR the
files stay in DIR and a reference already there is reused (a run with more
seeds then costs only the new renders); delete them after changing a scene
or the renderer.

    .venv/bin/python tools/sampler_study.py --sturmray target/release/sturmray
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
from pathlib import Path

import numpy as np
import OpenEXR

ROOT = Path(__file__).resolve().parent.parent
SCENES = ["cornell_path.toml", "path.toml", "metals.toml", "glass_torus.toml"]
SAMPLERS = ["sobol", "independent"]
REFERENCE_SEEDS = (1000, 1001)


def variant(scene: Path, seed: int, into: Path) -> Path:
    """A copy of `scene` in `into` with this seed, no adaptive sampling, and
    mesh paths made absolute (the copy lives elsewhere)."""
    text = scene.read_text()
    text = re.sub(r"(?m)^\s*(seed|adaptive)\s*=.*\n", "", text)
    text = re.sub(r"(?m)^\[render\]\s*\n", f"[render]\nseed = {seed}\n", text, count=1)
    if f"seed = {seed}" not in text:
        raise SystemExit(f"{scene}: no [render] table to set the seed in")
    text = re.sub(
        r'(?m)^(\s*file\s*=\s*)"([^"]+)"',
        lambda m: f'{m.group(1)}"{(scene.parent / m.group(2)).resolve()}"',
        text,
    )
    path = into / f"{scene.stem}-seed{seed}.toml"
    path.write_text(text)
    return path


def run(command: list[str]) -> None:
    proc = subprocess.run(command, capture_output=True, text=True)
    if proc.returncode != 0:
        tail = proc.stderr.strip().splitlines()[-1:] or ["no message"]
        raise SystemExit(f"failed (exit {proc.returncode}): {tail[0]}\n{' '.join(command)}")


def read_rgb(path: Path) -> np.ndarray:
    with OpenEXR.File(str(path), separate_channels=True) as f:
        channels = f.channels()
        return np.stack([channels[c].pixels.astype(np.float64) for c in "RGB"], axis=-1)


def rmse(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean((a - b) ** 2)))


class Study:
    def __init__(self, args: argparse.Namespace, work: Path):
        self.args = args
        self.work = work

    def render(self, scene: Path, seed: int, spp: int, sampler: str, out: Path,
               extra: list[str] = ()) -> float:
        """Renders and returns sturmray's seconds."""
        stats = out.with_suffix(".json")
        run([str(self.args.sturmray), "render", str(variant(scene, seed, self.work)),
             "-o", str(out), "--width", str(self.args.width), "--spp", str(spp),
             "--sampler", sampler, "--threads", str(self.args.threads),
             "--stats", str(stats), *extra])
        return float(json.loads(stats.read_text())["seconds"])

    def reference(self, scene: Path) -> tuple[np.ndarray, float]:
        """The merged reference image and its own RMSE (the floor)."""
        name = f"{scene.stem}-{self.args.width}w-ref{self.args.reference_spp}"
        halves = [self.work / f"{name}-{seed}.exr" for seed in REFERENCE_SEEDS]
        merged = self.work / f"{name}.exr"
        if not merged.exists():
            for seed, out in zip(REFERENCE_SEEDS, halves):
                # One tile of one is the whole image, with the film state `merge` reads.
                whole = ["--tile", "0/1"]
                self.render(scene, seed, self.args.reference_spp // 2, "independent", out, whole)
            run([str(self.args.sturmray), "merge", str(merged), *map(str, halves)])
        a, b = (read_rgb(h) for h in halves)
        return read_rgb(merged), rmse(a, b) / 2

    def scene(self, scene: Path) -> list[str]:
        reference, floor = self.reference(scene)
        h, w, _ = reference.shape
        rows = []
        for spp in self.args.spp:
            squares = {sampler: [] for sampler in SAMPLERS}
            times = {sampler: [] for sampler in SAMPLERS}
            # Seed by seed, the samplers in turn: a change in the machine's
            # load falls on both.
            for seed in range(1, self.args.seeds + 1):
                for sampler in SAMPLERS:
                    out = self.work / f"{scene.stem}-{sampler}-{spp}-{seed}.exr"
                    times[sampler].append(self.render(scene, seed, spp, sampler, out))
                    squares[sampler].append(rmse(read_rgb(out), reference) ** 2)
            seconds = {k: statistics.median(v) for k, v in times.items()}
            error = {k: float(np.sqrt(np.mean(v))) for k, v in squares.items()}
            ratio = (error["independent"] / error["sobol"]) ** 2
            # Seed by seed (both samplers take the same seeds, so the same
            # photon maps): how far the ratio moves with the seed.
            each = [i / s for i, s in zip(squares["independent"], squares["sobol"])]
            rows.append(
                f"| {scene.stem} {w}×{h} | {spp} | {error['sobol']:.4g} | "
                f"{error['independent']:.4g} | {ratio:.2f}× | {min(each):.2f}–{max(each):.2f} | "
                f"{seconds['sobol']:.2f} | {seconds['independent']:.2f} | {floor:.2g} |"
            )
            print(rows[-1], file=sys.stderr, flush=True)
        return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sturmray", type=Path, required=True)
    parser.add_argument("--scenes", nargs="+", type=Path,
                        default=[ROOT / "scenes" / s for s in SCENES])
    parser.add_argument("--spp", nargs="+", type=int, default=[4, 16, 64])
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--work", type=Path,
                        help="keep the files here and reuse a reference found here")
    args = parser.parse_args()
    if args.reference_spp < 2 or args.seeds < 1:
        parser.error("--reference-spp must be at least 2 and --seeds at least 1")
    header = [
        f"{args.width} pixels wide, adaptive sampling off; reference {args.reference_spp} spp "
        f"(independent, two merged halves); RMSE over {args.seeds} seeds, linear RGB; "
        f"seconds: median render time, {args.threads} threads",
        "",
        "| scene | spp | sobol RMSE | independent RMSE | MSE ratio (independent / sobol) "
        "| ratio per seed | sobol s | independent s | reference noise |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    rows = []
    with tempfile.TemporaryDirectory(prefix="sampler-study-") as temporary:
        work = args.work or Path(temporary)
        work.mkdir(parents=True, exist_ok=True)
        study = Study(args, work)
        for scene in args.scenes:
            rows += study.scene(scene)
    print("\n".join(header + rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
