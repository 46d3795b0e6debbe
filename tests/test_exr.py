"""Known-answer render read back with the reference OpenEXR implementation.

Scene: a 2 x 2 quad in the plane z = 0 facing a pinhole camera at (0, 0, 4),
diffuse albedo a, lit straight on by a directional light of irradiance E, on a
coloured background. With one sample per pixel through the pixel centre:

  quad pixels:        RGB = a * E / pi * cos(0), Z = distance eye -> plane,
                      normal = (0, 0, 1), albedo = a
  background pixels:  RGB = background, Z = inf, normal = 0, albedo = 0

Plus: the channel list and pixel types, `exrheader` (Debian's openexr tools)
accepts the file, and the same render twice, or with 1 and 2 threads, gives
byte-identical files.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import OpenEXR
import pytest
from conftest import SCENES

ALBEDO = np.array([0.5, 0.25, 0.125])
IRRADIANCE = np.array([2.0, 2.0, 2.0])
BACKGROUND = np.array([0.1, 0.2, 0.3])
EYE_Z = 4.0
FOV = 40.0
WIDTH, HEIGHT = 32, 24
HALF = 1.0  # the quad spans [-HALF, HALF]^2

CHANNELS = [
    "B", "G", "R", "Z",
    "albedo.B", "albedo.G", "albedo.R",
    "normal.X", "normal.Y", "normal.Z",
]  # fmt: skip  (EXR stores channels sorted by name)

# Radiance and depth are computed in f32 by the renderer (Embree rays, f32
# shading); 1e-5 relative is ~80 f32 ulps, far below any real shading error
# (a wrong cos, a missing 1/pi, a shadowed pixel are all > 1e-2).
REL_TOL = 1e-5

QUAD_OBJ = f"""\
o quad
v {-HALF} {-HALF} 0
v {HALF} {-HALF} 0
v {HALF} {HALF} 0
v {-HALF} {HALF} 0
f 1 2 3 4
"""


def toml_list(values) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def quad_scene_toml(obj_name: str, light_dir=(0.0, 0.0, -1.0)) -> str:
    return f"""\
background = {toml_list(BACKGROUND)}

[camera]
eye = [0.0, 0.0, {EYE_Z!r}]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = {FOV!r}
width = {WIDTH}
height = {HEIGHT}

[render]
spp = 1
max_depth = 5
seed = 0

[materials.quad]
type = "diffuse"
albedo = {toml_list(ALBEDO)}

[[objects]]
type = "mesh"
file = "{obj_name}"
material = "quad"

[[lights]]
type = "directional"
direction = {toml_list(light_dir)}
irradiance = {toml_list(IRRADIANCE)}
"""


def write_quad_scene(tmp_path: Path, reverse_winding=False, light_dir=(0.0, 0.0, -1.0)) -> Path:
    obj = QUAD_OBJ.replace("f 1 2 3 4", "f 1 4 3 2") if reverse_winding else QUAD_OBJ
    (tmp_path / "quad.obj").write_text(obj)
    scene = tmp_path / "quad.toml"
    scene.write_text(quad_scene_toml("quad.obj", light_dir))
    return scene


@pytest.fixture
def quad_scene(tmp_path) -> Path:
    return write_quad_scene(tmp_path)


def read_exr(path: Path) -> dict[str, np.ndarray]:
    """Every channel by its own name, as (height, width) arrays; checks that
    the file's pixel type is 32-bit float (not half, not uint)."""
    with OpenEXR.File(str(path), separate_channels=True) as f:
        channels = f.channels()
        for name, ch in channels.items():
            assert ch.type() == OpenEXR.FLOAT, f"channel {name} is {ch.type()}, not FLOAT"
        return {name: ch.pixels.copy() for name, ch in channels.items()}


def camera_rays() -> np.ndarray:
    """Unit directions (H, W, 3) of the pinhole camera's pixel-centre rays, in
    f64: eye on +z looking at the origin, up +y, so right = +x; vertical fov;
    image row 0 at the top."""
    half_h = math.tan(math.radians(FOV) / 2)
    half_w = half_h * WIDTH / HEIGHT
    x = ((np.arange(WIDTH) + 0.5) / WIDTH * 2 - 1) * half_w
    y = (1 - (np.arange(HEIGHT) + 0.5) / HEIGHT * 2) * half_h
    xx, yy = np.meshgrid(x, y)
    d = np.stack([xx, yy, -np.ones_like(xx)], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


# (winding, light direction, cos of the angle between the light and the normal)
CASES = {
    # The brief's case: light straight onto the quad, cos 0 = 1.
    "head-on": (False, (0.0, 0.0, -1.0), 1.0),
    # Wound clockwise as seen from the camera: the geometric normal points
    # away, and the normal facing the camera, (0, 0, 1), is what shades.
    "reversed-winding": (True, (0.0, 0.0, -1.0), 1.0),
    # Oblique and not of unit length: cos = 4/5 once normalised.
    "oblique": (False, (0.0, -3.0, -4.0), 0.8),
    # From behind the quad: max(0, n . -dir) = 0, so black (the background is
    # seen only by rays that miss; it lights nothing in this renderer).
    "from-behind": (False, (0.0, 0.0, 1.0), 0.0),
}


@pytest.mark.parametrize("case", list(CASES))
def test_known_answer_quad(sturmray, tmp_path, case):
    reverse, light_dir, cos_light = CASES[case]
    quad_scene = write_quad_scene(tmp_path, reverse, light_dir)
    out = tmp_path / "quad.exr"
    stats = tmp_path / "stats.json"
    sturmray("render", quad_scene, "-o", out, "--spp", "1", "--stats", stats)
    assert out.is_file()
    png = out.with_suffix(".png")
    assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", "no PNG beside the EXR"

    # Header: one part, the contract's channels, all 32-bit float, no
    # timestamp-like attributes (equal renders must give equal files).
    with OpenEXR.File(str(out)) as f:
        assert len(f.parts) == 1
        header = f.header()
        names = [c.name for c in header["channels"]]
        assert names == CHANNELS, names
        for c in header["channels"]:
            assert (c.xSampling, c.ySampling) == (1, 1), c.name
        lo, hi = header["dataWindow"]
        assert tuple(lo) == (0, 0) and tuple(hi) == (WIDTH - 1, HEIGHT - 1)
        for key in ("capDate", "utcOffset"):
            assert key not in header, f"header carries {key}"
        # The PyPI binding groups R,G,B and albedo.R,G,B; normal.X/Y/Z stay apart.
        grouped = f.channels()
        assert set(grouped) == {"RGB", "Z", "albedo", "normal.X", "normal.Y", "normal.Z"}
        assert grouped["RGB"].pixels.shape == (HEIGHT, WIDTH, 3)

    ch = read_exr(out)
    assert sorted(ch) == sorted(CHANNELS)
    for name, px in ch.items():
        assert px.dtype == np.float32 and px.shape == (HEIGHT, WIDTH), (name, px.dtype, px.shape)

    # Which pixels see the quad: intersect each pixel-centre ray with z = 0.
    d = camera_rays()
    t_plane = EYE_Z / -d[..., 2]  # distance along the unit ray = 4 / cos(theta)
    px_x = t_plane * d[..., 0]
    px_y = t_plane * d[..., 1]
    margin = np.minimum(np.abs(np.abs(px_x) - HALF), np.abs(np.abs(px_y) - HALF))
    # No pixel centre may fall within rounding of the quad's border, or the
    # expected classification would be a coin toss. (The nearest is ~0.03 away.)
    assert margin.min() > 1e-3
    on_quad = (np.abs(px_x) < HALF) & (np.abs(px_y) < HALF)
    n_quad = int(on_quad.sum())
    assert 0 < n_quad < WIDTH * HEIGHT // 2, n_quad  # both kinds of pixel present
    bg = ~on_quad

    rgb = np.stack([ch["R"], ch["G"], ch["B"]], axis=-1).astype(np.float64)
    albedo = np.stack([ch["albedo.R"], ch["albedo.G"], ch["albedo.B"]], axis=-1)
    normal = np.stack([ch["normal.X"], ch["normal.Y"], ch["normal.Z"]], axis=-1)
    depth = ch["Z"].astype(np.float64)

    # Quad: radiance a E / pi max(0, cos). Relative to the head-on value, so
    # the black case is held to the same absolute error.
    head_on = ALBEDO * IRRADIANCE / math.pi
    expected = head_on * max(0.0, cos_light)
    rel = np.abs(rgb[on_quad] - expected) / head_on
    assert rel.max() <= REL_TOL, (
        f"quad radiance off by {rel.max():.3g} relative: got e.g. {rgb[on_quad][rel.max(axis=1).argmax()]}"
        f", want {expected}"
    )
    # Depth: distance from the eye to the hit on the plane.
    zrel = np.abs(depth[on_quad] - t_plane[on_quad]) / t_plane[on_quad]
    assert zrel.max() <= REL_TOL, f"Z off by {zrel.max():.3g} relative"
    # The normal of an axis-aligned quad normalises to (0, 0, 1) up to rounding.
    assert np.allclose(normal[on_quad], [0, 0, 1], rtol=0, atol=1e-6), (
        "normal is not (0, 0, 1) on the quad"
    )
    assert np.array_equal(albedo[on_quad], np.broadcast_to(ALBEDO.astype(np.float32), (n_quad, 3)))

    # Background: exactly the background colour, depth inf, normal and albedo 0.
    assert np.array_equal(
        rgb[bg].astype(np.float32), np.broadcast_to(BACKGROUND.astype(np.float32), (int(bg.sum()), 3))
    ), "background pixels are not exactly the background colour"
    assert np.all(np.isposinf(depth[bg])), "background depth is not +inf"
    assert np.all(normal[bg] == 0) and np.all(albedo[bg] == 0)

    # --stats: one camera ray per pixel; one shadow ray per lit quad pixel
    # (none where the light is behind); nothing else spawns.
    s = json.loads(stats.read_text())
    assert s["rays"]["camera"] == WIDTH * HEIGHT
    if cos_light > 0:
        assert s["rays"]["shadow"] == n_quad
    else:
        assert s["rays"]["shadow"] <= n_quad
    for kind in ("reflection", "refraction", "diffuse", "photon"):
        assert s["rays"].get(kind, 0) == 0, (kind, s["rays"])

    print(
        f"\n[exr {case}] {n_quad} quad pixels: max rel radiance error {rel.max():.3g}, "
        f"max rel Z error {zrel.max():.3g}; {int(bg.sum())} background pixels exact"
    )


def test_exrheader_accepts_file(sturmray, quad_scene, tmp_path):
    exrheader = shutil.which("exrheader")
    if exrheader is None:
        pytest.fail(
            "exrheader not found: it comes with the Debian package `openexr`, "
            "which `make setup` installs",
            pytrace=False,
        )
    out = tmp_path / "quad.exr"
    sturmray("render", quad_scene, "-o", out)
    proc = subprocess.run([exrheader, str(out)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, f"exrheader failed ({proc.returncode}):\n{proc.stderr}"
    for name in CHANNELS:
        assert f"{name}, 32-bit floating-point" in proc.stdout, (name, proc.stdout)


def cornell_small(tmp_path: Path) -> Path:
    """The Cornell box (8 objects, MTL materials, plastic, point light) at
    48 x 48: a determinism test needs more than one kind of pixel."""
    obj = SCENES / "cornell" / "cornell.obj"
    if not obj.is_file():
        pytest.fail(f"{obj} is missing: run `python3 tools/make_scenes.py`", pytrace=False)
    scene = tmp_path / "cornell_small.toml"
    scene.write_text(
        f"""\
background = [0.05, 0.05, 0.08]

[camera]
eye = [0.278, 0.273, -0.8]
look_at = [0.278, 0.273, 0.0]
up = [0.0, 1.0, 0.0]
fov = 39.3077
width = 48
height = 40

[render]
spp = 4
max_depth = 5
seed = 3

[[objects]]
type = "mesh"
file = {json.dumps(str(obj))}

[[lights]]
type = "point"
position = [0.278, 0.54, 0.2795]
intensity = [0.5, 0.42, 0.32]
"""
    )
    return scene


@pytest.mark.parametrize("which", ["quad", "cornell"])
def test_render_is_byte_identical(sturmray, quad_scene, tmp_path, which):
    scene = quad_scene if which == "quad" else cornell_small(tmp_path)
    # The quad at 4 spp so samples are jittered (seeded per pixel and sample).
    spp = ["--spp", "4"] if which == "quad" else []
    outs = {}
    for label, threads in (("a", None), ("b", None), ("t1", "1"), ("t2", "2")):
        out = tmp_path / f"{which}_{label}.exr"
        args = ["render", scene, "-o", out, *spp]
        if threads:
            args += ["--threads", threads]
        sturmray(*args)
        outs[label] = out.read_bytes()
    assert outs["a"] == outs["b"], "two identical renders gave different EXR files"
    assert outs["t1"] == outs["t2"], "--threads 1 and --threads 2 gave different EXR files"
    assert outs["a"] == outs["t1"], "default thread count and --threads 1 differ"
    # Not a constant image: the test would pass vacuously on an all-black render.
    ch = read_exr(tmp_path / f"{which}_a.exr")
    assert np.ptp(ch["R"]) > 0.01 and np.isfinite(ch["R"]).all()
