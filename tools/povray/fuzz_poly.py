#!/usr/bin/env python3
"""Random algebraic surfaces of the hard kinds, drawn by POV-Ray 3.7 and
sturmray, with every disagreement settled by an exact root count.

Each seed writes one `poly` (degree 3 to 12) clipped by a ball, placed by a
random rotation and shift substituted into its coefficients, so the file
holds exactly the polynomial both renderers read. The kinds are the hard
cases of the solver: thin tori, thin shells (clustered roots), products of
two surfaces less a little (near double roots where they meet), squares
less a little (near-tangent sheets), Goursat and Steiner-like surfaces,
dense random polynomials and products of high degree. Every surface has
ambient light only on a black background, so a pixel's hit is any colour.
Both renderers draw it at --width x --height without anti-aliasing, through
the pixel centres of a camera without look_at.

On each pixel where the two disagree, `compare.ExactSurfaces` counts the
roots of F(o + t d) in the ball in rational arithmetic (Python's Fraction,
not sturmray's own exact solver). A seed fails if sturmray misses a pixel
the count proves hit, or hits one it proves empty; pixels POV-Ray alone gets
wrong are counted apart, as are those the count leaves open (a root within
1e-9 of the ball). The script exits 1 if any seed fails or does not render.

    .venv/bin/python tools/povray/fuzz_poly.py --sturmray target/release/sturmray --seeds 0:100
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare import ExactSurfaces  # noqa: E402
from fuzz_csg import arguments, draw_both, run_seeds  # noqa: E402

HEADER = """#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0, 0, {z!r}> angle {angle!r} right x*image_width/image_height }}
background {{ rgb 0 }}
#default {{ texture {{ pigment {{ rgb 1 }} finish {{ ambient 1 diffuse 0 }} }} }}
"""

# A polynomial is a dict {(i, j, k): coefficient of x^i y^j z^k}.


def add(*polys, scales=None):
    out: dict = {}
    for p, s in zip(polys, scales or [1.0] * len(polys)):
        for e, c in p.items():
            out[e] = out.get(e, 0.0) + s * c
    return out


def mul(p, q):
    out: dict = {}
    for (a, b, c), u in p.items():
        for (d, e, f), v in q.items():
            key = (a + d, b + e, c + f)
            out[key] = out.get(key, 0.0) + u * v
    return out


def const(c):
    return {(0, 0, 0): c}


def degree(p) -> int:
    return max(sum(e) for e, c in p.items() if c != 0)


def substitute(p, rows, shift):
    """p at the point M x + s: each of x, y, z becomes a linear polynomial."""
    linear = [{(1, 0, 0): r[0], (0, 1, 0): r[1], (0, 0, 1): r[2], (0, 0, 0): t} for r, t in zip(rows, shift)]
    out: dict = {}
    powers = [[const(1.0)] for _ in range(3)]
    for (i, j, k), c in p.items():
        term = const(c)
        for axis, n in enumerate((i, j, k)):
            while len(powers[axis]) <= n:
                powers[axis].append(mul(powers[axis][-1], linear[axis]))
            term = mul(term, powers[axis][n])
        out = add(out, term)
    return out


def r2():
    return {(2, 0, 0): 1.0, (0, 2, 0): 1.0, (0, 0, 2): 1.0}


def ellipsoid(r: random.Random):
    centre = [r.uniform(-0.6, 0.6) for _ in range(3)]
    axes = [r.uniform(0.5, 1.3) for _ in range(3)]
    rows = [[1 / a if m == n else 0.0 for m in range(3)] for n, a in enumerate(axes)]
    return substitute(add(r2(), const(-1.0)), rows, [-c / a for c, a in zip(centre, axes)])


def torus(major: float, minor: float):
    """(x² + y² + z² + R² − r²)² − 4R²(x² + z²), about y as POV-Ray's."""
    square = add(r2(), const(major * major - minor * minor))
    return add(mul(square, square), {(2, 0, 0): 1.0, (0, 0, 2): 1.0}, scales=[1.0, -4 * major * major])


def random_rotation(r: random.Random):
    q = np.array([r.gauss(0, 1) for _ in range(4)])
    w, x, y, z = q / np.linalg.norm(q)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]


def surface(r: random.Random) -> tuple[str, dict]:
    kind = r.choice(
        ["thin torus", "shell", "product", "square", "goursat", "steiner", "dense", "two tori", "high degree"]
    )
    if kind == "thin torus":
        major = r.uniform(0.5, 1.2)
        p = torus(major, major * 10 ** r.uniform(-2.5, -0.7))
    elif kind == "shell":
        p = add(mul(ellipsoid(r), ellipsoid(r)), const(-(10 ** r.uniform(-10, -1))))
    elif kind == "product":
        p = add(mul(ellipsoid(r), torus(r.uniform(0.6, 1.1), r.uniform(0.15, 0.4))), const(-(10 ** r.uniform(-5, -1))))
    elif kind == "square":
        e = ellipsoid(r)
        p = add(mul(e, e), const(-(10 ** r.uniform(-12, -3))))
    elif kind == "goursat":
        a, b, c = r.uniform(-1.5, 0.5), r.uniform(-2.0, 2.0), r.uniform(-1.5, 1.0)
        fourth = {(4, 0, 0): 1.0, (0, 4, 0): 1.0, (0, 0, 4): 1.0}
        p = add(fourth, mul(r2(), r2()), r2(), const(1.0), scales=[1.0, a, b, c])
    elif kind == "steiner":
        s = {(2, 2, 0): 1.0, (0, 2, 2): 1.0, (2, 0, 2): 1.0, (1, 1, 1): r.uniform(0.5, 2.0)}
        p = add(s, const(r.uniform(-0.05, 0.05)))
    elif kind == "dense":
        n = r.choice([3, 4, 5, 6])
        p = {
            (i, j, k): r.uniform(-1, 1)
            for i in range(n + 1)
            for j in range(n + 1 - i)
            for k in range(n + 1 - i - j)
        }
        if n % 2 == 0:
            # An even-degree leading sum of squares keeps most of it bounded.
            lead = r2()
            for _ in range(n // 2 - 1):
                lead = mul(lead, r2())
            p = add(p, lead, scales=[1.0, r.uniform(1.0, 4.0)])
    elif kind == "two tori":
        a = torus(r.uniform(0.6, 1.1), r.uniform(0.1, 0.35))
        b = substitute(torus(r.uniform(0.6, 1.1), r.uniform(0.1, 0.35)), random_rotation(r), [0.0, 0.0, 0.0])
        p = add(mul(a, b), const(-(10 ** r.uniform(-4, -1))))
    else:
        factors = [ellipsoid(r) for _ in range(r.randint(2, 4))]
        if r.random() < 0.5:
            factors.append(torus(r.uniform(0.6, 1.1), r.uniform(0.1, 0.4)))
        p = const(1.0)
        for f in factors:
            p = mul(p, f)
        p = add(p, const(-(10 ** r.uniform(-4, -1))))
    scale = r.uniform(0.8, 1.3)
    rotation = np.array(random_rotation(r)) / scale
    shift = -rotation @ np.array([r.uniform(-0.4, 0.4) for _ in range(3)])
    p = substitute(p, rotation.tolist(), shift.tolist())
    big = max(abs(c) for c in p.values())
    return kind, {e: c / big for e, c in p.items() if c != 0 and abs(c / big) > 1e-14}


def poly_text(p: dict) -> str:
    n = max(degree(p), 3)
    order = [
        (i, j, k) for i in range(n, -1, -1) for j in range(n - i, -1, -1) for k in range(n - i - j, -1, -1)
    ]
    return f"poly {{ {n}, <" + ", ".join(repr(float(p.get(e, 0.0))) for e in order) + ">"


def scene(seed: int) -> tuple[str, str, ExactSurfaces]:
    r = random.Random(seed)
    kind, p = surface(r)
    centre = tuple(r.uniform(-0.3, 0.3) for _ in range(3))
    radius = r.uniform(1.3, 2.0)
    sturm = " sturm" if r.random() < 0.5 or degree(p) > 4 else ""
    ball = f"sphere {{ <{centre[0]!r}, {centre[1]!r}, {centre[2]!r}>, {radius!r} }}"
    # One scene in four is seen from far off through a narrow lens: Q is
    # formed far from the surface, where its terms cancel.
    distance = 10 ** r.uniform(1.5, 4) if r.random() < 0.25 else 6.0
    angle = math.degrees(2 * math.atan(1.6 / distance))
    text = HEADER.format(z=-distance, angle=angle) + f"{poly_text(p)}{sturm}\n  clipped_by {{ {ball} }}\n}}\n"
    exact = ExactSurfaces(
        location=(0.0, 0.0, -distance),
        angle=angle,
        terms=p,
        placements=((np.eye(3), (0.0, 0.0, 0.0)),),
        reason=kind,
        ball=(centre, radius),
    )
    return kind, text, exact


def compare(seed: int, args, work: Path) -> tuple[str, bool]:
    kind, text, exact = scene(seed)
    drawn = draw_both(seed, text, args, work)
    if isinstance(drawn, str):
        return f"{seed} ({kind}): {drawn}", False
    theirs, ours = drawn
    disputed = [(int(x), int(y)) for y, x in zip(*np.nonzero(theirs != ours))]
    # The exact count takes up to a second a pixel at degree 8 and up: past
    # --settle pixels, an even sample of them is settled.
    stride = max(1, -(-len(disputed) // args.settle))
    disputed = disputed[::stride]
    truth = exact.hits(args.width, args.height, disputed)
    wrong = [px for px in disputed if truth[px] is not None and truth[px] != ours[px[1], px[0]]]
    open_ = sum(1 for px in disputed if truth[px] is None)
    pov_wrong = len(disputed) - len(wrong) - open_
    missed = sum(1 for x, y in wrong if truth[x, y])
    sampled = f" (1 in {stride} settled)" if stride > 1 else ""
    line = (
        f"{seed} ({kind}, degree {degree(exact.terms)}): {int((theirs != ours).sum())} disputed pixels{sampled}; "
        f"of those settled, sturmray wrong on {len(wrong)} ({missed} missed, {len(wrong) - missed} false), "
        f"POV-Ray wrong on {pov_wrong}, {open_} left open"
    )
    if wrong:
        line += f"; first: {wrong[:4]}"
    return line, not wrong


def main(argv=None) -> int:
    parser = arguments(__doc__)
    parser.add_argument("--settle", type=int, default=300, help="most disputed pixels a seed settles exactly")
    return run_seeds(
        parser.parse_args(argv), compare, "sturmray wrong", "with sturmray right on every settled pixel"
    )


if __name__ == "__main__":
    sys.exit(main())
