"""`sturmray trace` on analytic shapes mixed with a mesh, against closed-form
geometry computed here in float64 with numpy.

Contract (ARCHITECTURE.md, .npy rays and hits): the analytic shapes are one geometry whose
geom_id is the number of meshes, and prim_id is the shape's index in the
scene's list of shapes; `ng` is the normal from the surface's gradient.
On an instance, `inst_id` is the instance's index and geom_id and prim_id
are the prototype's own (its meshes first, its shapes one geometry after
them); elsewhere inst_id is 4294967295.
"""

from __future__ import annotations

import json
import subprocess

import numpy as np

SCENE = """
[[objects]]
type = "mesh"
file = "quad.obj"

[[objects]]
type = "sphere"
radius = 0.75
transform = { translate = [-1, 0, 0] }

[[objects]]
type = "torus"
major = 0.6
minor = 0.2
transform = { translate = [1, 0, 0] }
"""

# A quad far behind everything (z = -5), so every ray has a backstop: geom 0.
QUAD = "v -50 -50 -5\nv 50 -50 -5\nv 50 50 -5\nv -50 50 -5\nf 1 2 3 4\n"


def sphere_t(o, d, c, r):
    """Nearest positive root of |o + t d - c|^2 = r^2, inf on a miss. d is the
    float32 direction, not exactly unit: near a silhouette, leaving out d·d
    moves the root by 1e-5."""
    oc = o - c
    a = np.einsum("ij,ij->i", d, d)
    b = np.einsum("ij,ij->i", oc, d)
    disc = b * b - a * (np.einsum("ij,ij->i", oc, oc) - r * r)
    t = (-b - np.sqrt(np.where(disc >= 0, disc, np.nan))) / a
    return np.where(disc >= 0, t, np.inf)


def torus_t(o, d, c, big, small):
    """Nearest positive root of the torus quartic around axis z, via numpy.roots."""
    out = np.full(len(o), np.inf)
    for i, (oi, di) in enumerate(zip(o - c, d)):
        a = di @ di
        b = 2 * oi @ di
        cc = oi @ oi + big**2 - small**2
        e = di[0] ** 2 + di[1] ** 2
        f = 2 * (oi[0] * di[0] + oi[1] * di[1])
        g = oi[0] ** 2 + oi[1] ** 2
        k = 4 * big**2
        coeffs = [a * a, 2 * a * b, b * b + 2 * a * cc - k * e, 2 * b * cc - k * f, cc * cc - k * g]
        roots = np.roots(coeffs)
        real = roots[np.abs(roots.imag) < 1e-9].real
        real = real[real > 1e-9]
        if len(real):
            out[i] = real.min()
    return out


def trace_random_rays(sturmray, tmp_path, text, seed, n, target_z):
    """Traces `n` rays from random points of z = 3 towards random points
    around the shapes with z in `target_z` through the scene `text` (with
    the quad behind); returns the hits and the rays as sturmray reads them
    (float32 values), in float64, for the references."""
    (tmp_path / "quad.obj").write_text(QUAD)
    scene = tmp_path / "s.toml"
    scene.write_text(text)
    rng = np.random.default_rng(seed)
    origin = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-1.2, 1.2, n), np.full(n, 3.0)])
    target = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-1.2, 1.2, n), rng.uniform(*target_z, n)])
    d = target - origin
    d /= np.linalg.norm(d, axis=1)[:, None]
    rays = np.hstack([origin, d]).astype(np.float32)
    np.save(tmp_path / "rays.npy", rays)
    sturmray("trace", scene, "--rays", tmp_path / "rays.npy", "--out", tmp_path / "hits.npy")
    hits = np.load(tmp_path / "hits.npy")
    return hits, rays[:, :3].astype(np.float64), rays[:, 3:].astype(np.float64)


def test_trace_hits_analytic_shapes(sturmray, tmp_path):
    # Rays towards the z = 0 plane around both shapes.
    hits, o64, d64 = trace_random_rays(sturmray, tmp_path, SCENE, 7, 4000, (-0.3, 0.3))
    ts = sphere_t(o64, d64, np.array([-1.0, 0, 0]), 0.75)
    tt = torus_t(o64, d64, np.array([1.0, 0, 0]), 0.6, 0.2)
    nearest = np.minimum(ts, tt)
    analytic = np.isfinite(nearest)

    shapes_geom = 1  # one mesh, so the shapes are geometry 1
    ours = hits["geom_id"] == shapes_geom
    # Rays that graze a silhouette can go either way in float32; count, don't hide.
    agree = ours == analytic
    assert agree.mean() > 0.999, f"hit/miss agreement {agree.mean():.5f}"
    assert analytic.sum() > 1000 and (~analytic).sum() > 1000
    both = ours & analytic
    expected_prim = np.where(ts <= tt, 0, 1)
    assert (hits["prim_id"][both] == expected_prim[both]).mean() > 0.999
    rel = np.abs(hits["t"][both] - nearest[both]) / nearest[both]
    # float32 t of a float64 root: a few ulps.
    assert rel.max() < 1e-6, f"max relative t error {rel.max():.3g}"
    # v bounds the error of the float64 root, before t is rounded to
    # float32: positive, and small against t (a tolerance of 1e-12 times
    # the distance, plus the root's uncertainty).
    v = hits["v"][both].astype(np.float64)
    assert (v > 0).all() and (v < 1e-6 * nearest[both]).all(), f"v from {v.min():.3g} to {v.max():.3g}"
    # u names the CSG leaf: these are plain shapes.
    assert (hits["u"][both] == 0).all()
    # Misses of both shapes land on the quad behind (geom 0).
    assert (hits["geom_id"][~analytic & ~ours] == 0).all()
    # Sphere normals point from the centre through the hit point.
    sphere_hits = both & (expected_prim == 0)
    p = o64[sphere_hits] + hits["t"][sphere_hits, None] * d64[sphere_hits]
    radial = (p - np.array([-1.0, 0, 0])) / 0.75
    ng = hits["ng"][sphere_hits]
    ng = ng / np.linalg.norm(ng, axis=1)[:, None]
    assert np.abs(ng - radial).max() < 1e-4


INSTANCED = """
[[objects]]
type = "mesh"
file = "quad.obj"

[[prototypes.pair.objects]]
type = "sphere"
radius = 0.75
transform = { translate = [-1, 0, 0] }

[[prototypes.pair.objects]]
type = "torus"
major = 0.6
minor = 0.2
transform = { translate = [1, 0, 0] }

[[objects]]
type = "instance"
prototype = "pair"

[[objects]]
type = "instance"
prototype = "pair"
transform = { translate = [0, 0, -3] }
"""

MISS = 4294967295


def test_trace_reports_instances(sturmray, tmp_path):
    """The sphere and torus of one prototype placed twice (the second 3 behind
    the first), in front of a quad: inst_id names the copy hit, geom_id and
    prim_id the prototype's shape, t agrees with the closed forms."""
    # Rays towards the z = -3 plane: through both copies' gaps.
    hits, o64, d64 = trace_random_rays(sturmray, tmp_path, INSTANCED, 11, 3000, (-3.0, -3.0))
    assert hits.dtype["inst_id"] == np.uint32
    # Each (instance, shape) pair's t, in the order inst_id * 2 + prim_id.
    candidates = []
    for z in (0.0, -3.0):
        candidates.append(sphere_t(o64, d64, np.array([-1.0, 0, z]), 0.75))
        candidates.append(torus_t(o64, d64, np.array([1.0, 0, z]), 0.6, 0.2))
    candidates = np.stack(candidates)
    nearest = candidates.min(axis=0)
    which = candidates.argmin(axis=0)
    analytic = np.isfinite(nearest)
    ours = hits["inst_id"] != MISS
    agree = ours == analytic
    assert agree.mean() > 0.999, f"hit/miss agreement {agree.mean():.5f}"
    assert (which[analytic] >= 2).sum() > 100, "the second copy is hit through the first's gaps"
    both = ours & analytic
    assert (hits["inst_id"][both] == which[both] // 2).mean() > 0.999
    # The prototype has no meshes: its shapes are its geometry 0.
    assert (hits["geom_id"][both] == 0).all()
    assert (hits["prim_id"][both] == which[both] % 2).mean() > 0.999
    rel = np.abs(hits["t"][both] - nearest[both]) / nearest[both]
    assert rel.max() < 1e-6, f"max relative t error {rel.max():.3g}"
    # The quad is the scene's own geometry 0: no instance.
    quad = ~analytic & ~ours
    assert quad.sum() > 100 and (hits["geom_id"][quad] == 0).all()
    assert (hits["inst_id"][quad] == MISS).all()


def test_roots_tool_answers_json_lines(sturmray_bin):
    lines = [
        {"coeffs": [0, 0, -1, 0, 1], "interval": [-2, 2]},
        {"coeffs": [-6, 11, -6, 1], "interval": [0, 10], "method": "sturm-illinois"},
        {"coeffs": [1, -3, 3, -1], "interval": [0, 2], "method": "exact"},
    ]
    text = "\n".join(json.dumps(x) for x in lines) + "\nnot json\n"
    proc = subprocess.run([str(sturmray_bin), "roots", "--sturm"], input=text, capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr  # one bad line
    out = [json.loads(x) for x in proc.stdout.splitlines()]
    assert out[0]["count"] == 3 and np.allclose(out[0]["roots"], [-1, 0, 1], atol=1e-9)
    assert out[0]["sturm"]["variations_a"] == 3 and out[0]["sturm"]["variations_b"] == 0
    assert np.allclose(out[1]["roots"], [1, 2, 3], atol=1e-9)
    assert out[2]["roots"] == [1.0]
    assert out[3] == {"error": out[3]["error"], "line": 4}
