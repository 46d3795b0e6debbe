"""Cross-check `sturmray trace` against embreex (Embree 4 from PyPI).

The OBJ is read here, in Python, by the design's `trace` contract (ARCHITECTURE.md,
"Contracts users and tests rely on"):
objects are the `o`/`g` sections that have at least one face, in file order
(faces before the first `o`/`g` form an object of their own); a polygon
v0..vn-1 is fanned into (v0,v1,v2), (v0,v2,v3), ...; indices are 1-based,
negative ones count back from the last vertex defined so far; face references
may be v, v/t, v//n or v/t/n; degenerate triangles are kept. Each object
becomes one embreex TriangleMesh, attached in file order, so embreex's geomID
and primID mean the same as sturmray's geom_id and prim_id. Both are mapped to
a global triangle index through per-object offsets before comparing.

Only hits are compared: embreex reports a miss as primID -1 with tfar left at
its input (1e37 by default) and leaves u, v, Ng from an earlier ray.

`pytest -s` prints the agreement figures.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from conftest import SCENES, SturmrayError

from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

MISS = np.uint32(0xFFFFFFFF)

# Agreement thresholds (from the design's Tests section).
MIN_HIT_MISS_AGREEMENT = 0.9999
MIN_PRIM_AGREEMENT = 0.999
T_REL_TOL = 1e-5

# A hit on which the two tracers pick different triangles must lie on the edge
# (or vertex) those triangles share. Barycentrics are computed in f32 from
# vertex coordinates taken relative to the ray origin, so their absolute error
# is about k * 2^-24 * L / h, with L the distance from the origin to the hit
# (< 5 in these scenes), h the height of the triangle (>= 0.0098 in knot.obj,
# the smallest here) and k a small count of rounding steps: 2^-24 * L / h is
# ~3e-5, so even k = 10 stays below 3e-4. EDGE_EPS = 1e-3 lies above that and
# still fails a wrong triangle: a point uniformly inside a triangle has
# min(u, v, 1-u-v) < 1e-3 with probability ~0.6% only.
EDGE_EPS = 1e-3

# Point reconstructed from (prim_id, u, v) versus origin + t * direction: both
# are f32 evaluations of the same point, good to a few ulps of the scale
# s = max|origin| + t, except that where a ray meets a plane at a grazing
# angle both the barycentrics and t are ill-conditioned by 1 / |cos| (cos of
# the angle between the ray and the triangle's normal). So the test is
# |p_bary - p_ray| * |cos| <= POINT_REL_TOL * s. Measured: <= 1e-6 * s (~15
# ulps, Cornell aimed rays); 4e-6 is ~67 ulps. A wrong triangle, or u and v
# swapped, is off by a fraction of a triangle (>= 1e-3 here).
POINT_REL_TOL = 4e-6


# --------------------------------------------------------------------------- OBJ


@dataclass
class ObjMesh:
    vertices: np.ndarray  # (V, 3) float32, every `v` of the file
    objects: list[tuple[str, np.ndarray]]  # (name, (T, 3) int64 indices into vertices)

    @property
    def offsets(self) -> np.ndarray:
        """offsets[g] = global index of object g's first triangle; offsets[-1] = total."""
        return np.concatenate([[0], np.cumsum([len(t) for _, t in self.objects])]).astype(
            np.int64
        )

    @property
    def triangles(self) -> np.ndarray:
        """(T, 3) vertex indices of all triangles in global order."""
        return np.concatenate([t for _, t in self.objects])


def read_obj(path: Path) -> ObjMesh:
    vertices: list[list[float]] = []
    objects: list[tuple[str, np.ndarray]] = []
    name, tris = path.stem, []

    def finish(next_name: str):
        nonlocal name, tris
        if tris:
            objects.append((name, np.array(tris, dtype=np.int64)))
        name, tris = next_name, []

    for lineno, line in enumerate(path.read_text().splitlines(), 1):
        words = line.split()
        if not words:
            continue
        key = words[0]
        if key == "v":
            vertices.append([float(w) for w in words[1:4]])
        elif key in ("o", "g"):
            finish(line.strip()[len(key) :].strip())
        elif key == "f":
            count = len(vertices)
            refs = []
            for word in words[1:]:
                i = int(word.split("/")[0])
                g = i - 1 if i > 0 else count + i
                if i == 0 or not 0 <= g < count:
                    raise ValueError(f"{path}:{lineno}: vertex index {i} out of range")
                refs.append(g)
            if len(refs) < 3:
                raise ValueError(f"{path}:{lineno}: face with {len(refs)} vertices")
            for k in range(1, len(refs) - 1):
                tris.append((refs[0], refs[k], refs[k + 1]))
    finish("")
    return ObjMesh(np.array(vertices, dtype=np.float32).reshape(-1, 3), objects)


# ------------------------------------------------------------------------ tracing


def trace_sturmray(sturmray, scene: Path, rays: np.ndarray, tmp_path: Path) -> np.ndarray:
    assert rays.dtype == np.float32 and rays.ndim == 2 and rays.shape[1] in (6, 8)
    ray_file = tmp_path / f"rays_{len(rays)}_{rays.shape[1]}.npy"
    hit_file = tmp_path / f"hits_{len(rays)}_{rays.shape[1]}.npy"
    np.save(ray_file, rays)
    hit_file.unlink(missing_ok=True)  # never read a stale answer
    sturmray("trace", scene, "--rays", ray_file, "--out", hit_file)
    hits = np.load(hit_file)
    assert hits.shape == (len(rays),), hits.shape
    expected = {
        "t": (np.float32, ()),
        "geom_id": (np.uint32, ()),
        "prim_id": (np.uint32, ()),
        "inst_id": (np.uint32, ()),
        "u": (np.float32, ()),
        "v": (np.float32, ()),
        "ng": (np.float32, (3,)),
    }
    assert list(hits.dtype.names) == list(expected), hits.dtype
    for field, (dtype, shape) in expected.items():
        sub = hits.dtype[field]
        assert sub.base == np.dtype(dtype) and sub.shape == shape, (field, sub)
    # These scenes have no instances: every record says so.
    assert (hits["inst_id"] == np.iinfo(np.uint32).max).all()
    return hits


def trace_embreex(mesh: ObjMesh, rays: np.ndarray) -> dict[str, np.ndarray]:
    scene = rtcs.EmbreeScene(robust=True)  # robust is also 4.4.0.post1's default
    # Keep the meshes alive until the scene has been traced.
    keep = [TriangleMesh(scene, mesh.vertices, tris) for _, tris in mesh.objects]
    org = np.ascontiguousarray(rays[:, 0:3])
    direction = np.ascontiguousarray(rays[:, 3:6])
    if rays.shape[1] == 8:
        # embreex always uses tnear = 0; only tfar can be passed.
        assert np.all(rays[:, 6] == 0.0)
        tfar = np.ascontiguousarray(rays[:, 7]).copy()  # embreex writes into it
        out = scene.run(org, direction, dists=tfar, output=1)
    else:
        out = scene.run(org, direction, output=1)
    del keep
    return out


# ------------------------------------------------------------------- comparison


def compare(label: str, mesh: ObjMesh, rays: np.ndarray, ours: np.ndarray, ref: dict) -> dict:
    n = len(rays)
    n_tris = len(mesh.triangles)
    offsets = mesh.offsets

    # Miss encoding of sturmray.
    s_hit = ours["prim_id"] != MISS
    assert np.array_equal(s_hit, ours["geom_id"] != MISS), "geom_id/prim_id miss mismatch"
    assert np.all(np.isinf(ours["t"][~s_hit]) & (ours["t"][~s_hit] > 0)), "miss with finite t"
    assert np.all(np.isfinite(ours["t"][s_hit])), "hit with non-finite t"
    e_hit = ref["primID"] != -1

    hit_miss_agree = np.count_nonzero(s_hit == e_hit) / n
    both = s_hit & e_hit
    n_both = int(np.count_nonzero(both))

    # Global triangle index.
    s_geom = ours["geom_id"][both].astype(np.int64)
    s_prim = ours["prim_id"][both].astype(np.int64)
    assert np.all(s_geom < len(mesh.objects)), "geom_id out of range"
    s_global = offsets[s_geom] + s_prim
    assert np.all(s_prim < (offsets[s_geom + 1] - offsets[s_geom])), "prim_id out of range"
    e_geom = ref["geomID"][both].astype(np.int64)
    e_global = offsets[e_geom] + ref["primID"][both].astype(np.int64)
    same = s_global == e_global
    prim_agree = np.count_nonzero(same) / max(n_both, 1)

    t_s = ours["t"][both].astype(np.float64)
    t_e = ref["tfar"][both].astype(np.float64)
    t_rel = np.abs(t_s - t_e) / np.abs(t_e)

    su, sv = ours["u"][both], ours["v"][both]
    near_edge = np.minimum(np.minimum(su, sv), 1.0 - su - sv) < EDGE_EPS
    print(
        f"\n[{label}] rays {n}, triangles {n_tris}, objects {len(mesh.objects)}: "
        f"hits sturmray {int(s_hit.sum())} embreex {int(e_hit.sum())}; "
        f"hit/miss agree {hit_miss_agree:.6%} ({int((s_hit != e_hit).sum())} differ); "
        f"same triangle {prim_agree:.6%} of {n_both} common hits "
        f"({int((~same).sum())} differ); max rel t diff (same triangle) "
        f"{t_rel[same].max() if same.any() else 0:.3g}; "
        f"{int(near_edge.sum())} common hits within {EDGE_EPS} of an edge"
    )

    assert hit_miss_agree >= MIN_HIT_MISS_AGREEMENT, (
        f"{label}: hit/miss agreement {hit_miss_agree:.6%} < {MIN_HIT_MISS_AGREEMENT:%}"
    )
    assert n_both > 0.05 * n, f"{label}: only {n_both} common hits; the ray set is too weak"
    assert prim_agree >= MIN_PRIM_AGREEMENT, (
        f"{label}: triangle agreement {prim_agree:.6%} < {MIN_PRIM_AGREEMENT:%}"
    )

    # Same triangle: same t, and the same geometry id (implied, but say so).
    assert np.array_equal(s_geom[same], e_geom[same])
    worst = int(np.argmax(np.where(same, t_rel, -1))) if same.any() else 0
    assert t_rel[same].max(initial=0) <= T_REL_TOL, (
        f"{label}: t differs by {t_rel[worst]:.3g} relative on a common triangle: "
        f"sturmray {t_s[worst]!r} embreex {t_e[worst]!r}"
    )

    # Different triangle: must be an edge or vertex hit at the same distance.
    if not same.all():
        diff = ~same
        assert t_rel[diff].max() <= T_REL_TOL, (
            f"{label}: different triangles at different t: rel diff {t_rel[diff].max():.3g}"
        )
        for u, v, who in (
            (ours["u"][both][diff], ours["v"][both][diff], "sturmray"),
            (ref["u"][both][diff], ref["v"][both][diff], "embreex"),
        ):
            m = np.minimum(np.minimum(u, v), 1.0 - u - v)
            assert m.max() < EDGE_EPS, (
                f"{label}: {who} hit a different triangle away from any edge: "
                f"min barycentric {m.max():.3g} >= {EDGE_EPS}"
            )

    # sturmray's (triangle, u, v) must name the point origin + t * direction, and
    # its ng must be the triangle's geometric normal (Embree: (v1-v0) x (v2-v0)).
    tri = mesh.vertices[mesh.triangles[s_global]].astype(np.float64)  # (H, 3, 3)
    u = ours["u"][both].astype(np.float64)[:, None]
    v = ours["v"][both].astype(np.float64)[:, None]
    p_bary = (1 - u - v) * tri[:, 0] + u * tri[:, 1] + v * tri[:, 2]
    r = rays[both].astype(np.float64)
    p_ray = r[:, 0:3] + t_s[:, None] * r[:, 3:6]
    geo_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    geo_len = np.linalg.norm(geo_n, axis=1)
    cos_ray = np.abs(np.einsum("ij,ij->i", geo_n, r[:, 3:6])) / (
        geo_len * np.linalg.norm(r[:, 3:6], axis=1)
    )
    scale = np.abs(r[:, 0:3]).max(axis=1) + t_s * np.linalg.norm(r[:, 3:6], axis=1)
    err = np.linalg.norm(p_bary - p_ray, axis=1) * cos_ray / scale
    worst = int(np.argmax(err))
    assert err[worst] <= POINT_REL_TOL, (
        f"{label}: (prim_id, u, v) names a point away from o + t d: "
        f"|diff| * |cos| / scale = {err[worst]:.3g} at ray {np.flatnonzero(both)[worst]}"
    )
    assert np.all((u >= -1e-6) & (v >= -1e-6) & (u + v <= 1 + 1e-6)), "u, v outside triangle"
    ng = ours["ng"][both].astype(np.float64)
    cos = np.einsum("ij,ij->i", ng, geo_n) / (
        np.linalg.norm(ng, axis=1) * geo_len
    )
    # f32 cross products of small triangles: direction good to ~1e-6.
    assert cos.min() >= 1 - 1e-5, f"{label}: ng is not the triangle's normal (cos {cos.min()})"

    return {
        "rays": n,
        "hit_miss_agree": hit_miss_agree,
        "prim_agree": prim_agree,
        "common_hits": n_both,
    }


# -------------------------------------------------------------------- ray sets


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def random_rays(rng, lo, hi, n: int, margin: float = 0.25) -> np.ndarray:
    """Origins uniform in the bounding box grown by `margin` of its size on
    each side; directions uniform on the sphere."""
    size = hi - lo
    org = rng.uniform(lo - margin * size, hi + margin * size, (n, 3))
    return np.concatenate([org, unit(rng.normal(size=(n, 3)))], axis=1).astype(np.float32)


def aimed_rays(rng, mesh: ObjMesh, n: int, with_tfar: bool) -> np.ndarray:
    """Rays from random points in a box around the mesh aimed at its surface:
    a third at random interior points, a third at vertices and a third at
    points on edges, where the two tracers are most likely to part ways.
    With `with_tfar`, (N, 8) rays: tnear 0, and half of them get a finite tfar
    that ends before or around the aimed point."""
    tris = mesh.triangles
    v = mesh.vertices.astype(np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    size = hi - lo
    pick = tris[rng.integers(0, len(tris), n)]
    a, b, c = v[pick[:, 0]], v[pick[:, 1]], v[pick[:, 2]]
    kind = rng.integers(0, 3, n)
    r1, r2 = rng.uniform(size=(2, n, 1))
    flip = (r1 + r2) > 1
    r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
    interior = a + r1 * (b - a) + r2 * (c - a)
    edge = a + r1 * (b - a)
    target = np.where((kind == 0)[:, None], interior, np.where((kind == 1)[:, None], a, edge))
    org = rng.uniform(lo - 0.5 * size, hi + 0.5 * size, (n, 3))
    d = unit(target - org)
    rays = np.concatenate([org, d], axis=1)
    if with_tfar:
        dist = np.linalg.norm(target - org, axis=1)
        tfar = np.where(rng.uniform(size=n) < 0.5, np.inf, dist * rng.uniform(0.3, 1.2, n))
        rays = np.concatenate([rays, np.zeros((n, 1)), tfar[:, None]], axis=1)
    return rays.astype(np.float32)


def camera_rays(eye, look_at, fov_deg: float, width: int, height: int) -> np.ndarray:
    """A pinhole camera grid through pixel centres (row 0 at the top)."""
    eye, look_at = np.asarray(eye, float), np.asarray(look_at, float)
    fwd = unit((look_at - eye)[None])[0]
    right = unit(np.cross(fwd, [0.0, 1.0, 0.0])[None])[0]
    up = np.cross(right, fwd)
    half_h = np.tan(np.radians(fov_deg) / 2)
    half_w = half_h * width / height
    x = ((np.arange(width) + 0.5) / width * 2 - 1) * half_w
    y = (1 - (np.arange(height) + 0.5) / height * 2) * half_h
    xx, yy = np.meshgrid(x, y)
    d = unit(fwd + xx.reshape(-1, 1) * right + yy.reshape(-1, 1) * up)
    org = np.broadcast_to(eye, d.shape)
    return np.concatenate([org, d], axis=1).astype(np.float32)


# ----------------------------------------------------------------------- tests

KNOT = SCENES / "meshes" / "knot.obj"
CORNELL = SCENES / "cornell" / "cornell.obj"


def _require(path: Path):
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `python3 tools/make_scenes.py`", pytrace=False)


def check_scene(sturmray, tmp_path, obj: Path, camera: dict, n_random: int, n_aimed: int, seed):
    _require(obj)
    mesh = read_obj(obj)
    rng = np.random.default_rng(seed)
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    sets = {
        "random": random_rays(rng, lo, hi, n_random),
        "aimed+tfar": aimed_rays(rng, mesh, n_aimed, with_tfar=True),
        "camera": camera_rays(**camera),
    }
    results = {}
    for name, rays in sets.items():
        ours = trace_sturmray(sturmray, obj, rays, tmp_path)
        ref = trace_embreex(mesh, rays)
        results[name] = compare(f"{obj.name} {name}", mesh, rays, ours, ref)
    return mesh, results


def test_knot_matches_embreex(sturmray, tmp_path):
    mesh, _ = check_scene(
        sturmray,
        tmp_path,
        KNOT,
        camera=dict(eye=(0.4, 0.9, 3.2), look_at=(0, 0.09, 0), fov_deg=42, width=256, height=256),
        n_random=150_000,
        n_aimed=100_000,
        seed=20240611,
    )
    # The file is the 70k-triangle knot in one object (scenes/README.md).
    assert [len(t) for _, t in mesh.objects] == [70_000]


def test_cornell_matches_embreex(sturmray, tmp_path):
    mesh, results = check_scene(
        sturmray,
        tmp_path,
        CORNELL,
        # The original Cornell camera (scenes/cornell.toml).
        camera=dict(
            eye=(0.278, 0.273, -0.8),
            look_at=(0.278, 0.273, 0.0),
            fov_deg=39.3077,
            width=256,
            height=256,
        ),
        n_random=100_000,
        n_aimed=50_000,
        seed=7,
    )
    # 8 objects of quads: 1+1+1+1+1+5+5+1 quads, 2 triangles each.
    assert [len(t) for _, t in mesh.objects] == [2, 2, 2, 2, 2, 10, 10, 2]


# A small OBJ that exercises every rule of the contract. Triangles lie apart in
# the plane z = 0 (some in z = 1, above and offset), so a ray straight down
# through a triangle's centroid hits that triangle and no other.
TRICKY_OBJ = """\
# faces before any o/g line form an object of their own
mtllib tricky.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vn 0 0 1
f 1 2 3 4
o empty_object_is_dropped
g group_with_faces
v 2 0 0
v 3 0 0
v 3.5 0.5 0
v 3 1 0
v 2 1 0
usemtl red
f -5/1 -4/1 -3/1 -2/1 -1/1
usemtl blue
v 2 2 0
v 3 2 0
v 2 3 0
f 10//1 11//1 12//1
v 4 0 0
v 5 0 0
v 4 1 0
f 13 13 14
f -3/1/1 -2/1/1 -1/1/1
o last
v 6 0 1
v 7 0 1
v 7 1 1
v 6 1 1
f 16 17 18 19
g
"""
TRICKY_MTL = """\
newmtl red
Kd 0.8 0.1 0.1
newmtl blue
Kd 0.1 0.1 0.8
"""
# (geom_id, prim_id) of each triangle in file order, by the contract.
TRICKY_EXPECTED = [
    (0, 0), (0, 1),  # quad 1 2 3 4
    (1, 0), (1, 1), (1, 2),  # pentagon, fanned; usemtl does not split the object
    (1, 3),  # triangle 10 11 12, after a usemtl change
    (1, 4),  # degenerate 13 13 14: kept, never hit
    (1, 5),  # triangle 13 14 15 (negative indices)
    (2, 0), (2, 1),  # quad in z = 1
]
TRICKY_DEGENERATE = {6}


def test_obj_contract_small(sturmray, tmp_path):
    obj = tmp_path / "tricky.obj"
    obj.write_text(TRICKY_OBJ)
    (tmp_path / "tricky.mtl").write_text(TRICKY_MTL)
    mesh = read_obj(obj)
    assert [len(t) for _, t in mesh.objects] == [2, 6, 2]
    tris = mesh.triangles
    centroids = mesh.vertices[tris].astype(np.float64).mean(axis=1)
    keep = [i for i in range(len(tris)) if i not in TRICKY_DEGENERATE]
    # Rays straight down through each centroid, and a second set tilted a little.
    org = centroids[keep] + [0.0, 0.0, 2.0]
    rays = np.concatenate(
        [
            np.concatenate([org, np.tile([0.0, 0.0, -1.0], (len(keep), 1))], axis=1),
            np.concatenate([org, unit(np.tile([0.01, 0.02, -1.0], (len(keep), 1)))], axis=1),
        ]
    ).astype(np.float32)
    ours = trace_sturmray(sturmray, obj, rays, tmp_path)
    ref = trace_embreex(mesh, rays)
    want = np.array([TRICKY_EXPECTED[i] for i in keep] * 2, dtype=np.int64)
    got = np.stack([ours["geom_id"], ours["prim_id"]], axis=1).astype(np.int64)
    bad = np.flatnonzero((got != want).any(axis=1))
    assert bad.size == 0, (
        "sturmray's (geom_id, prim_id) differ from the contract at rays "
        f"{bad.tolist()}: got {got[bad].tolist()}, want {want[bad].tolist()}"
    )
    emb = np.stack([ref["geomID"], ref["primID"]], axis=1).astype(np.int64)
    assert np.array_equal(emb, want), "the Python OBJ reader disagrees with the contract"
    compare("tricky.obj", mesh, rays, ours, ref)


def test_tnear_tfar_bound_the_hit(sturmray, tmp_path):
    """(N, 8) rays: tfar just short of the closest hit gives a miss, and tnear
    1 mm past it gives the next hit, which must be the hit embreex finds from
    an origin moved to origin + tnear * direction (embreex has no tnear)."""
    _require(CORNELL)
    mesh = read_obj(CORNELL)
    rng = np.random.default_rng(99)
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    rays = np.concatenate(
        [
            camera_rays((0.278, 0.273, -0.8), (0.278, 0.273, 0.0), 39.3077, 128, 128),
            random_rays(rng, lo, hi, 50_000, margin=0.0),  # from inside the box
        ]
    )
    first = trace_embreex(mesh, rays)
    hit = first["primID"] != -1
    rays, t1 = rays[hit], first["tfar"][hit].astype(np.float64)
    n = len(rays)
    assert n > 50_000
    org, d = rays[:, 0:3].astype(np.float64), rays[:, 3:6].astype(np.float64)

    # tfar = t1 (1 - 1e-4): nothing is closer than the closest hit.
    short = np.concatenate([rays, np.zeros((n, 1)), (t1 * (1 - 1e-4))[:, None]], axis=1)
    ours = trace_sturmray(sturmray, CORNELL, short.astype(np.float32), tmp_path)
    missed = np.count_nonzero(ours["prim_id"] == MISS) / n
    print(f"\n[tfar short of the hit] {n} rays: {missed:.6%} miss")
    assert missed >= MIN_HIT_MISS_AGREEMENT

    # tnear = t1 + 1e-3: the next surface along the ray. Absolute, not relative
    # to t1: the moved origin is rounded to f32 (~1e-7 here), and a step
    # smaller than that from a wall the origin nearly touches would leave
    # embreex's moved origin in front of the wall it is meant to be past.
    tnear = (t1 + 1e-3).astype(np.float32)
    past = np.concatenate([rays, tnear[:, None], np.full((n, 1), np.inf)], axis=1)
    ours = trace_sturmray(sturmray, CORNELL, past.astype(np.float32), tmp_path)
    s_hit = ours["prim_id"] != MISS
    assert np.all(ours["t"][s_hit] >= tnear[s_hit]), "a hit before tnear"
    moved = np.concatenate([org + tnear[:, None].astype(np.float64) * d, d], axis=1)
    ref = trace_embreex(mesh, moved.astype(np.float32))
    e_hit = ref["primID"] != -1
    agree = np.count_nonzero(s_hit == e_hit) / n
    both = s_hit & e_hit
    off = mesh.offsets
    s_g = off[ours["geom_id"][both].astype(np.int64)] + ours["prim_id"][both].astype(np.int64)
    e_g = off[ref["geomID"][both].astype(np.int64)] + ref["primID"][both].astype(np.int64)
    same = s_g == e_g
    # Moving the origin rounds it (~1 f32 ulp of |origin| < 1.5 here), which
    # shifts the distance by up to ~1e-7 absolute: allow 1e-5 relative + 1e-6.
    t_s = ours["t"][both].astype(np.float64)
    t_e = tnear[both].astype(np.float64) + ref["tfar"][both].astype(np.float64)
    t_err = np.abs(t_s - t_e) - 1e-6
    print(
        f"[tnear past the hit] hit/miss agree {agree:.6%}, same triangle "
        f"{np.count_nonzero(same) / max(both.sum(), 1):.6%} of {int(both.sum())}"
    )
    assert agree >= MIN_HIT_MISS_AGREEMENT
    assert np.count_nonzero(same) / both.sum() >= MIN_PRIM_AGREEMENT
    assert np.all(t_err[same] <= T_REL_TOL * t_e[same]), "next-hit distance differs"


@pytest.mark.parametrize(
    "rays, why",
    [
        (np.array([[np.nan, 0, 0, 0, 1, 0]], np.float32), "NaN origin"),
        (np.array([[0.2, 0.2, 0.2, 0, 0, 0]], np.float32), "zero direction"),
        (np.zeros((3, 7), np.float32), "7 columns"),
        (np.array([[0.2, 0.2, 0.2, 0, 1, 0, -1, 1]], np.float32), "negative tnear"),
    ],
    ids=["nan-origin", "zero-direction", "7-columns", "negative-tnear"],
)
def test_trace_bad_rays_exit_2(sturmray, tmp_path, rays, why):
    """Bad input is exit status 2 with a message naming the file, never a panic."""
    _require(CORNELL)
    ray_file = tmp_path / "bad_rays.npy"
    np.save(ray_file, rays)
    with pytest.raises(SturmrayError) as err:
        sturmray("trace", CORNELL, "--rays", ray_file, "--out", tmp_path / "hits.npy")
    assert err.value.returncode == 2, (why, err.value)
    assert "bad_rays.npy" in err.value.stderr, (why, err.value.stderr)
    assert "panicked" not in err.value.stderr
