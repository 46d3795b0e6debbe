#!/usr/bin/env python3
"""sturmray against its peers (issue 15): POV-Ray 3.7 and Mitsuba 3, one table of ratios.

POV-Ray: Debian's objects/quartic samples at 800×600, no anti-aliasing, the
timing of tools/povray/speed.py (render times, alternated runs) and the hit
masks of tools/povray/compare.py (pixels POV-Ray hits and sturmray misses).

Mitsuba: the Cornell box of tools/peers/cornell.py at 256×256, box filter,
path traced at equal depth, 2 threads each. Each renderer gets a reference
(--reference-spp; Mitsuba's is the mean of independent 256-spp renders, one
wavefront of 256×256×4096 lanes does not fit in memory) and a sweep of spp;
RMSE against the renderer's own reference over the whole image and away
from the light; per-sample time; time to equal RMSE from a log-log line of
RMSE against time. The two references' means must agree within 0.1% per
channel (reported, and the exit status is 1 if not). Runs alternate:
sturmray, Mitsuba llvm_ad_rgb, Mitsuba scalar_rgb at each spp and round.
Mitsuba's times are of `mi.render` and the copy to numpy that waits for it;
each llvm_ad_rgb render is preceded by an untimed warm-up render at the same
spp, so the JIT's compilation is not counted. sturmray's are its --stats
`seconds` (the render loop, after loading and the BVH).

Run inside .venv-peers with DRJIT_LIBLLVM_PATH set (`make peers` does both).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "povray"))
sys.path.insert(0, str(HERE))
import cornell  # noqa: E402
from compare import Renderers, run as compare_run  # noqa: E402
from speed import machine, time_povray, time_sturmray  # noqa: E402

SAMPLERS = ("independent", "stratified", "multijitter", "orthogonal", "ldsampler")
MEAN_LIMIT = 0.001  # the issue's: image means within 0.1%
MITSUBA_PASS = 256  # spp of one Mitsuba reference pass


def povray_part(args, work: Path) -> list[tuple]:
    """(scene, sturmray render s / POV-Ray trace s, pixels POV-Ray hits and sturmray misses)."""
    renderers = Renderers(args.sturmray.resolve(), 800, 600, args.threads)
    scenes = sorted((args.examples / "quartic").glob("*.pov"))
    masks = {r.name: r.pov_only for r in compare_run(renderers, scenes, work, jobs=1)}
    rows = []
    for scene in scenes:
        pov, sturm = [], []
        for _ in range(args.rounds):
            pov.append(time_povray(renderers, scene, work)[0])
            sturm.append(time_sturmray(renderers, scene, work)[0])
        rows.append((scene.stem, statistics.median(sturm) / statistics.median(pov), masks[scene.stem]))
        print(f"povray {scene.stem}: done", file=sys.stderr)
    return rows


class Mitsuba:
    """One Mitsuba variant with the Cornell box loaded per sampler."""

    def __init__(self, mi, dr, variant: str, parts, threads: int):
        self.mi, self.dr, self.variant, self.parts = mi, dr, variant, parts
        mi.set_variant(variant)
        dr.set_thread_count(threads)
        self.scenes = {}
        self.seed = 1000

    def render(self, sampler: str, spp: int, timed: bool = True) -> tuple[np.ndarray, float]:
        mi = self.mi
        mi.set_variant(self.variant)
        if sampler not in self.scenes:
            self.scenes[sampler] = mi.load_dict(cornell.mitsuba_scene(mi, self.parts, sampler, spp))
        scene = self.scenes[sampler]
        if timed and self.variant.startswith("llvm"):
            np.array(mi.render(scene, spp=spp, seed=0))  # warm-up: the JIT compiles here
        self.seed += 1
        start = time.perf_counter()
        image = np.array(mi.render(scene, spp=spp, seed=self.seed), dtype=np.float64)
        return image, time.perf_counter() - start


def sturmray(args, work: Path, spp: int, seed: int) -> tuple[np.ndarray, float]:
    from mitsuba import Bitmap  # reads sturmray's EXR (beauty R, G, B come first)

    toml, exr, stats = work / f"cornell-{seed}.toml", work / f"cornell-{seed}.exr", work / "s.json"
    toml.write_text(cornell.sturmray_toml(seed))
    command = [str(args.sturmray), "render", str(toml), "--spp", str(spp), "--threads"]
    subprocess.run(command + [str(args.threads), "-o", str(exr), "--stats", str(stats)],
                   check=True, capture_output=True)
    image = np.array(Bitmap(str(exr)), dtype=np.float64)[..., :3]
    return image, float(json.loads(stats.read_text())["seconds"])


def rmse(image: np.ndarray, reference: np.ndarray, mask: np.ndarray) -> float:
    return float(np.sqrt(((image - reference)[mask] ** 2).mean()))


def time_to(points: list[tuple[float, float]], target: float) -> float:
    """The time at which the log-log least-squares line through (time, RMSE) reaches target."""
    t, e = np.log([p[0] for p in points]), np.log([p[1] for p in points])
    slope, intercept = np.polyfit(t, e, 1)
    return math.exp((math.log(target) - intercept) / slope)


def mitsuba_part(args, work: Path) -> tuple[list[tuple], list[str], bool]:
    import drjit as dr
    import mitsuba as mi

    parts = cornell.split_obj(work)
    llvm = Mitsuba(mi, dr, "llvm_ad_rgb", parts, args.threads)
    scalar = Mitsuba(mi, dr, "scalar_rgb", parts, args.threads)
    notes = []
    # References, then Mitsuba's best sampler: the least RMSE² × time at 64 spp.
    s_ref, s_ref_time = sturmray(args, work, args.reference_spp, seed=1)
    passes = max(1, args.reference_spp // MITSUBA_PASS)
    m_ref = sum(llvm.render("independent", MITSUBA_PASS, timed=False)[0] for _ in range(passes)) / passes
    notes.append(f"references: sturmray {args.reference_spp} spp in {s_ref_time:.1f} s; "
                 f"Mitsuba llvm_ad_rgb {passes} × {MITSUBA_PASS} spp")
    whole, away = np.ones(s_ref.shape[:2], dtype=bool), cornell.away_from_light()
    ratio = s_ref.mean(axis=(0, 1)) / m_ref.mean(axis=(0, 1))
    agree = bool(np.all(np.abs(ratio - 1) <= MEAN_LIMIT))
    notes.append("reference means sturmray / Mitsuba (R, G, B): "
                 + ", ".join(f"{r:.4f}" for r in ratio)
                 + (" (within 0.1%)" if agree else " (NOT within 0.1%)"))
    ratio_away = s_ref[away].mean(axis=0) / m_ref[away].mean(axis=0)
    notes.append("the same away from the light: " + ", ".join(f"{r:.4f}" for r in ratio_away))
    scores = {}
    for sampler in SAMPLERS:
        image, seconds = llvm.render(sampler, 64)
        scores[sampler] = rmse(image, m_ref, whole) ** 2 * seconds
    best = min(scores, key=scores.get)
    notes.append(f"Mitsuba's best sampler (least RMSE² × time at 64 spp): {best}")
    runs = {name: {spp: [] for spp in args.spp} for name in ("sturmray", "llvm", "scalar")}
    for _ in range(args.rounds):
        for spp in args.spp:
            runs["sturmray"][spp].append(sturmray(args, work, spp, seed=100 + len(runs["sturmray"][spp])))
            runs["llvm"][spp].append(llvm.render(best, spp))
            runs["scalar"][spp].append(scalar.render(best, spp))
            print(f"mitsuba spp {spp}: done", file=sys.stderr)
    refs = {"sturmray": s_ref, "llvm": m_ref, "scalar": m_ref}
    curves = {}  # name -> mask name -> [(median time, median RMSE)]
    for name, by_spp in runs.items():
        for label, mask in (("whole", whole), ("away", away)):
            curves.setdefault(name, {})[label] = [
                (statistics.median(t for _, t in rs),
                 statistics.median(rmse(i, refs[name], mask) for i, _ in rs))
                for rs in by_spp.values()
            ]
    rows = []
    for label in ("whole", "away"):
        target = curves["sturmray"][label][len(args.spp) // 2][1]
        for other in ("llvm", "scalar"):
            r = time_to(curves["sturmray"][label], target) / time_to(curves[other][label], target)
            rows.append((f"time to equal RMSE ({label}), vs {other}", r, 1.0 if other == "llvm" else None))
    top = args.spp[-1]
    for other in ("llvm", "scalar"):
        r = curves["sturmray"]["whole"][-1][0] / curves[other]["whole"][-1][0]
        rows.append((f"time per sample at {top} spp, vs {other}", r, 1.0 if other == "llvm" else None))
    for name, c in curves.items():
        notes.append(f"{name}: (s, RMSE whole) " + ", ".join(f"({t:.3f}, {e:.4f})" for t, e in c["whole"]))
    return rows, notes, agree


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sturmray", type=Path, required=True)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--spp", type=int, nargs="+", default=[4, 16, 64, 256])
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--examples", type=Path, default=Path("/usr/share/doc/povray/examples/objects"))
    parser.add_argument("--skip-povray", action="store_true")
    parser.add_argument("--skip-mitsuba", action="store_true")
    parser.add_argument("--markdown", type=Path, default=Path("out/peers.md"))
    args = parser.parse_args(argv)
    lines = ["| comparison | ratio (sturmray / peer) | target | met |", "|---|---:|---:|---|"]
    notes, ok = [], True
    with tempfile.TemporaryDirectory(prefix="peers-") as tmp:
        work = Path(tmp)  # POV-Ray may write only here or in /tmp (povray.conf)
        if not args.skip_povray:
            rows = povray_part(args, work)
            for name, ratio, missed in rows:
                met = ratio <= 0.5 and missed == 0
                lines.append(f"| POV-Ray quartic/{name}: render time; {missed} pixels POV-Ray hits, "
                             f"sturmray misses | {ratio:.2f} | ≤ 0.50, 0 pixels | {'yes' if met else 'no'} |")
            mean = statistics.geometric_mean(r for _, r, _ in rows)
            lines.append(f"| POV-Ray quartic: geometric mean of render time | {mean:.2f} | ≤ 0.50 "
                         f"| {'yes' if mean <= 0.5 else 'no'} |")
        if not args.skip_mitsuba:
            rows, notes, ok = mitsuba_part(args, work)
            for name, ratio, target in rows:
                met = "–" if target is None else ("yes" if ratio <= target else "no")
                lines.append(f"| Mitsuba Cornell box: {name} | {ratio:.2f} | "
                             f"{'–' if target is None else f'≤ {target:.2f}'} | {met} |")
    notes.append(machine())
    text = "\n".join(lines) + "\n\n" + "".join(f"- {n}\n" for n in notes)
    print(text)
    args.markdown.parent.mkdir(parents=True, exist_ok=True)
    args.markdown.write_text(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
