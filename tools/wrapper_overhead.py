#!/usr/bin/env python3
"""The Rust wrapper's overhead against Embree called from C (issue #5).

Builds the C harness (benches/c_harness/c_harness.c) with `cc -O2`, lets
`sturmray bench --c-harness DIR` write the meshes and rays (a first run that
also warms up, and is not counted), then runs the C harness and sturmray
alternately for --rounds rounds, C first in even rounds and Rust first in odd
ones, on one thread each. Every run reports, per scene, ray kind (camera,
incoherent) and API (single: one call per ray; batch: the stream path), its
Mrays/s (each chunk of 4096 rays at its best of 10 passes) and a checksum of
the hits. The checksums of both sides must agree exactly, or the script
fails: the two did not do the same work.

The table gives the best Mrays/s of each side over all rounds and
overhead = C / Rust - 1 (the extra time per ray the wrapper costs), and the
median of the rounds' own overheads as a check on the noise. Standard library
only, so it runs without the .venv.
"""

import argparse
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SOURCE = ROOT / "benches" / "c_harness" / "c_harness.c"
TARGET = 0.05


def parse(output):
    """{(scene, kind, api): {"side", "mrays", "check"}} from a run's lines."""
    results = {}
    for line in output.splitlines():
        side, scene, kind, api, *fields = line.split()
        values = dict(f.split("=", 1) for f in fields)
        # tsum is printed to round-trip (C %.17g, Rust's shortest form): compare as floats.
        check = (int(values["rays"]), int(values["hits"]), float(values["tsum"]),
                 int(values["primsum"]))
        results[(scene, kind, api)] = {"side": side, "mrays": float(values["mrays"]),
                                       "check": check}
    return results


def run(command):
    done = subprocess.run(command, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}): {' '.join(map(str, command))}")
    return parse(done.stdout)


def build_harness(out):
    """Compiles the harness against the Embree sturmray builds with (EMBREE_DIR or the system's)."""
    command = ["cc", "-O2", "-std=c11", "-Wall", "-Wextra", "-Werror", str(SOURCE)]
    embree = os.environ.get("EMBREE_DIR")
    if embree:
        lib = Path(embree) / "lib"
        command += [f"-I{Path(embree) / 'include'}", f"-L{lib}", f"-Wl,-rpath,{lib}"]
    command += ["-lembree3", "-lm", "-o", str(out)]
    subprocess.run(command, check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", default="target/release/sturmray", help="a release build")
    parser.add_argument("--dir", default="out/c_harness", help="where the files go")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="100k rays, a 100k mesh")
    parser.add_argument("--scene", action="append", default=[], help="instead of the default")
    args = parser.parse_args()

    directory = ROOT / args.dir
    directory.mkdir(parents=True, exist_ok=True)
    harness = directory / "c_harness"
    build_harness(harness)
    rust_command = [args.bin, "bench", "--c-harness", str(directory)]
    rust_command += ["--quick"] * args.quick
    for scene in args.scene:
        rust_command += ["--scene", scene]

    reference = run(rust_command)
    scenes = list(dict.fromkeys(scene for scene, _, _ in reference))
    c_commands = [[str(harness), str(directory), scene] for scene in scenes]

    best = {}  # (side, key) -> best Mrays/s
    rounds = []  # per round: {key: C / Rust}
    mismatches = []
    for r in range(args.rounds):
        sides = {}
        order = ["c", "rust"] if r % 2 == 0 else ["rust", "c"]
        for side in order:
            if side == "rust":
                sides[side] = run(rust_command)
            else:
                sides[side] = {}
                for command in c_commands:
                    sides[side].update(run(command))
        for key, expected in reference.items():
            for side in ("c", "rust"):
                got = sides[side][key]
                if got["check"] != expected["check"]:
                    mismatches.append(f"{side} {' '.join(key)}: {got['check']} != {expected['check']}")
                best[side, key] = max(best.get((side, key), 0.0), got["mrays"])
        rounds.append({key: sides["c"][key]["mrays"] / sides["rust"][key]["mrays"]
                       for key in reference})
        print(f"round {r + 1}/{args.rounds} done", file=sys.stderr)
    if mismatches:
        sys.exit("the C harness and sturmray disagree on the hits:\n" + "\n".join(mismatches))

    print(f"{args.rounds} rounds (C and Rust alternating), one thread, each chunk of 4096 rays "
          f"at its best of 10 passes per run; hit checksums equal on every run")
    print(f"{'scene':<14} {'rays':<11} {'api':<7} {'C Mrays/s':>10} {'Rust Mrays/s':>13} "
          f"{'overhead':>9} {'median':>8}")
    worst = 0.0
    for key in reference:
        c, rust = best["c", key], best["rust", key]
        overhead = c / rust - 1
        median = statistics.median(ratios[key] for ratios in rounds) - 1
        worst = max(worst, overhead)
        scene, kind, api = key
        print(f"{scene:<14} {kind:<11} {api:<7} {c:>10.3f} {rust:>13.3f} "
              f"{overhead:>+8.1%} {median:>+8.1%}")
    verdict = "within" if worst <= TARGET else "over"
    print(f"largest overhead (best of each side): {worst:+.1%}, {verdict} the {TARGET:.0%} target")


if __name__ == "__main__":
    main()
