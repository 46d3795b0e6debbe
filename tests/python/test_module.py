"""The `sturmray` extension module (python/, docs/python.md): every function
of its API against known answers, the CLI's answers and its own backends.

Built into .venv by `make test` (`maturin develop --profile dev`).
"""

from __future__ import annotations

import json
import signal
import subprocess
import threading

import numpy as np
import pytest
from conftest import REPO, SCENES, at_t, run_sturmray

import sturmray

MISS = sturmray.INVALID_ID
BACKENDS = ["embree", "obvhs", "bvh"]


def square_scene(backend: str = "embree") -> sturmray.Scene:
    """A unit square of two triangles sharing the diagonal (0,0)-(1,1) at
    z = 0, a sphere of radius 0.25 at z = 2 and a torus (R 1, r 0.25, about z) at z = 5."""
    scene = sturmray.Scene(backend=backend)
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float64)
    assert scene.add_mesh(v, np.array([[0, 1, 2], [0, 2, 3]])) == 0
    assert scene.add_sphere(0.25, center=(0.5, 0.5, 2.0)) == 0
    assert scene.add_torus(1.0, 0.25, center=(0.0, 0.0, 5.0)) == 1
    scene.commit()
    return scene


# Up the z axis: through the square's diagonal (both triangles at t = 1), the
# sphere (t = 2.75, 3.25), then the torus's hole; the second ray misses the
# sphere but crosses the torus tube twice; the third misses everything.
ORIGINS = np.array([[0.5, 0.5, -1], [0.25, 0.75, -1], [3, 3, -1]], np.float32)
DIRS = np.array([[0, 0, 1], [0, 0, 1], [0, 0, 1]], np.float32)


@pytest.mark.parametrize("backend", BACKENDS)
def test_intersect_nearest_hits(backend):
    hits = square_scene(backend).intersect(ORIGINS, DIRS)
    assert at_t(hits["t"][:2], 1.0).all(), hits["t"][:2]
    assert hits["t"][2] == np.inf
    assert hits["geom_id"].tolist() == [0, 0, MISS]
    assert hits["prim_id"][1] == 1  # (0.25, 0.75) is in triangle 1
    assert hits["ng"].shape == (3, 3)
    assert abs(hits["ng"][0, 2]) > 0 and hits["ng"][0, :2].tolist() == [0, 0]


@pytest.mark.parametrize("backend", BACKENDS)
def test_intersect_all_reports_shared_edges_and_every_crossing(backend):
    scene = square_scene(backend)
    hits = scene.intersect_all(ORIGINS, DIRS)
    assert hits["offsets"].tolist() == [0, 4, 7, 7]
    first = slice(0, 4)
    # Both triangles at the shared diagonal, then the sphere's two crossings.
    assert at_t(hits["t"][first], [1.0, 1.0, 2.75, 3.25]).all(), hits["t"][first]
    assert hits["geom_id"][first].tolist() == [0, 0, 1, 1]
    assert hits["prim_id"][first].tolist() == [0, 1, 0, 0]
    # Ray 1: triangle 1, then the torus tube twice (prim 1 of the shapes).
    torus = hits["t"][5:7]
    r = np.hypot(0.25, 0.75)
    half = np.sqrt(0.25**2 - (r - 1.0) ** 2)
    np.testing.assert_allclose(torus, [6 - half, 6 + half], rtol=1e-6)
    assert hits["prim_id"][4:7].tolist() == [1, 1, 1]
    # max_hits keeps the nearest.
    capped = scene.intersect_all(ORIGINS, DIRS, max_hits=1)
    assert capped["offsets"].tolist() == [0, 1, 2, 2]
    assert at_t(capped["t"], 1.0).all(), capped["t"]


@pytest.mark.parametrize("backend", BACKENDS)
def test_occluded_and_ray_intervals(backend):
    scene = square_scene(backend)
    assert scene.occluded(ORIGINS, DIRS).tolist() == [True, True, False]
    # tfar before the square: nothing; tnear past the square: the sphere.
    assert scene.occluded(ORIGINS, DIRS, tfar=0.5).tolist() == [False, False, False]
    hits = scene.intersect(ORIGINS, DIRS, tnear=np.array([1.5, 0, 0]))
    assert hits["t"][0] == 2.75 and hits["geom_id"][0] == 1


def test_backends_agree_on_a_loaded_scene():
    """The three backends give the same nearest hits on the knot mesh (a
    shared-edge tie may pick either triangle: compared by t)."""
    rng = np.random.default_rng(3)
    n = 2000
    origins = rng.uniform(-3, 3, (n, 3)).astype(np.float32)
    dirs = (rng.uniform(-0.5, 0.5, (n, 3)) - origins).astype(np.float32)
    t = [
        sturmray.Scene.load(SCENES / "knot.toml", backend=b).intersect(origins, dirs)["t"]
        for b in BACKENDS
    ]
    assert np.isfinite(t[0]).sum() > n // 10
    for other in t[1:]:
        np.testing.assert_allclose(other, t[0], rtol=1e-5)


INSTANCED = """
[camera]
eye = [0, 0, -10]
look_at = [0, 0, 0]
fov = 40
width = 8
height = 8
[[lights]]
type = "point"
position = [0, 0, -10]
intensity = [1, 1, 1]
[materials.grey]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[[prototypes.ball.objects]]
type = "sphere"
radius = 1.0
material = "grey"
[[objects]]
type = "instance"
prototype = "ball"
transform = { translate = [-3, 0, 0] }
[[objects]]
type = "instance"
prototype = "ball"
transform = { translate = [3, 0, 0], scale = 2.0 }
"""


@pytest.mark.parametrize("backend", BACKENDS)
def test_instances_report_their_index(backend, tmp_path):
    # A unit sphere placed twice: at x = -3, and at x = 3 scaled by 2.
    (tmp_path / "inst.toml").write_text(INSTANCED)
    scene = sturmray.Scene.load(tmp_path / "inst.toml", backend=backend)
    origins = np.array([[-3, 0, -10], [3, 0, -10], [0, 0, -10]], np.float32)
    dirs = np.array([[0, 0, 1]] * 3, np.float32)
    hits = scene.intersect(origins, dirs)
    assert hits["inst_id"].tolist() == [0, 1, MISS]
    np.testing.assert_allclose(hits["t"][:2], [9.0, 8.0], rtol=1e-6)
    # The normals in world space: facing the ray.
    np.testing.assert_allclose(hits["ng"][:2, 2] / np.linalg.norm(hits["ng"][:2], axis=1), [-1, -1], atol=1e-6)
    every = scene.intersect_all(origins, dirs)
    assert every["offsets"].tolist() == [0, 2, 4, 4]
    assert every["inst_id"].tolist() == [0, 0, 1, 1]
    np.testing.assert_allclose(every["t"], [9.0, 11.0, 8.0, 12.0], rtol=1e-6)


def test_cli_trace_gives_the_same_hits(sturmray_bin, tmp_path):
    rng = np.random.default_rng(5)
    rays = np.hstack([rng.uniform(-3, 3, (500, 3)), rng.normal(size=(500, 3))]).astype(np.float32)
    np.save(tmp_path / "rays.npy", rays)
    run_sturmray(sturmray_bin, "trace", SCENES / "knot.toml", "--rays", tmp_path / "rays.npy", "--out", tmp_path / "h.npy")
    cli = np.load(tmp_path / "h.npy")
    mine = sturmray.Scene.load(SCENES / "knot.toml").intersect(rays[:, :3], rays[:, 3:])
    for key in ["t", "geom_id", "prim_id", "inst_id", "u", "v", "ng"]:
        np.testing.assert_array_equal(mine[key], cli[key])


def test_roots_answers_as_the_cli(run_stdin):
    queries = [
        {"coeffs": [-2, 0, 1]},
        {"coeffs": [1, -3, 3, -1], "interval": [0, 2], "method": "exact"},
        {"coeffs": [0.5, -1.5, 0, 1], "method": "sturm-bisect", "tolerance": 1e-6},
    ]
    text = run_stdin("roots", "\n".join(json.dumps(q) for q in queries))
    for q, line in zip(queries, text.splitlines()):
        cli = json.loads(line)
        mine = sturmray.roots(q["coeffs"], q.get("interval"), q.get("method"), q.get("tolerance"))
        for key in ["roots", "count", "multiplicity", "bound"]:
            assert mine[key] == cli[key], (q, key)
    assert sturmray.roots([1, -3, 3, -1], (0, 2))["multiplicity"] == [3]


def test_errors_are_python_exceptions_with_the_cli_message():
    with pytest.raises(ValueError, match="the polynomial is identically zero"):
        sturmray.roots([0, 0])
    with pytest.raises(ValueError, match=r"objects\[0\].radius: expected a number > 0"):
        scene = sturmray.Scene()
        scene.add_sphere(-1.0)
        scene.commit()
    with pytest.raises(ValueError, match=r"meshes\[0\]: vertex index 7 out of range: 3 vertices"):
        scene = sturmray.Scene()
        scene.add_mesh(np.zeros((3, 3)), [[0, 1, 7]])
        scene.commit()
    with pytest.raises(OSError, match="missing.toml"):
        sturmray.Scene.load(REPO / "missing.toml")
    scene = square_scene()
    with pytest.raises(ValueError, match="ray 0 .0-based row.: "):
        scene.intersect([[0, 0, 0]], [[0, 0, 0]])
    with pytest.raises(ValueError, match=r"origins: expected an \(N, 3\) array"):
        scene.intersect(np.zeros((2, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="not committed"):
        sturmray.Scene().intersect(ORIGINS, DIRS)


def test_quadric_and_algebraic_shapes():
    scene = sturmray.Scene()
    # The cylinder x^2 + y^2 = 1 and the sphere x^2+y^2+z^2 = r^2 (r from a constant).
    identity_xy = ((1, 0, 0), (0, 1, 0), (0, 0, 0))
    scene.add_quadric(identity_xy, (0, 0, 0), -1.0, clip=((-2, -2, -1), (2, 2, 1)))
    scene.add_algebraic("x^2 + y^2 + (z - 10)^2 - r^2", ((-3, -3, 7), (3, 3, 13)), [("r", 2.0)])
    scene.commit()
    hits = scene.intersect_all([[-5, 0, 0], [0, 0, 0]], [[1, 0, 0], [0, 0, 1]])
    np.testing.assert_allclose(hits["t"], [4, 6, 8, 12], rtol=1e-6)
    assert hits["prim_id"].tolist() == [0, 0, 1, 1]


def test_render_matches_the_scene_size_and_gives_aovs():
    scene = sturmray.Scene.load(SCENES / "knot.toml", width=32, height=24)
    assert scene.size == (32, 24)
    image, aovs = scene.render(spp=1, aovs=True)
    assert image.shape == (24, 32, 3) and image.dtype == np.float32
    assert aovs["depth"].shape == (24, 32) and aovs["normal"].shape == (24, 32, 3)
    assert image.max() > 0 and np.isfinite(image).all()
    again = scene.render(spp=1)
    np.testing.assert_array_equal(image, again)  # deterministic
    with pytest.raises(ValueError, match="integrator"):
        scene.render(integrator="nope")


@pytest.fixture
def python_sigint():
    """Python's own SIGINT handler, as an interactive session has it. A
    process started in the background by a non-interactive shell (a CI job
    under `nohup ... &`) inherits SIGINT ignored, and Python then installs
    no handler: the signal would never reach the render, and the test
    would wait out all 4096 samples."""
    kept = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, kept)


def test_ctrl_c_interrupts_a_render(python_sigint):
    """A SIGINT during a long render raises KeyboardInterrupt promptly."""
    scene = sturmray.Scene.load(SCENES / "knot.toml", width=320, height=240)
    timer = threading.Timer(0.5, signal.raise_signal, (signal.SIGINT,))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        scene.render(spp=4096)
    timer.join()


@pytest.fixture
def run_stdin(sturmray_bin):
    def run(*args, text: str):
        return subprocess.run(
            [str(sturmray_bin), *map(str, args)], input=text, capture_output=True, text=True,
            check=True, timeout=60,
        ).stdout

    return lambda *args: run(*args[:-1], text=args[-1])
