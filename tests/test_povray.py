"""sturmray against POV-Ray 3.7 on POV-Ray's own sample scenes (issue 20, §5).

The comparison itself is tools/povray/compare.py; `make povray-compare` runs
it at 800x600 for the README. Here it runs at 160x120 over every sample of
objects/quartic/ and objects/csg/ and the issue's limits are asserted: at most
0.1% of the pixels differ in their hit, and the mean colour difference is at
most 2%. The scenes exempt from a check are named with their reasons in
compare.py's tables (COLOUR_EXEMPT, OUTSIDE_SUBSET, EXTRA_HITS_ALLOWED), so
that the README's table and this test judge alike; the test checks that each
exemption names a feature its scene really uses.

The harness's own parts are checked against POV-Ray alone: the PNG reader
against POV-Ray's PPM output of the same render, the wrapper that forces the
background, the hit mask against a count worked out by hand, and the whole
pipeline with POV-Ray standing in for sturmray.

POV-Ray (Debian's povray, povray-examples, povray-includes) is installed by
`make setup`; a missing one is a failure, never a skip.
"""

from __future__ import annotations

import argparse
import re
import shutil
import struct
import subprocess
import sys
import zlib
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from conftest import REPO

sys.path.insert(0, str(REPO / "tools" / "povray"))
import compare  # noqa: E402
from pngio import read_png, write_png  # noqa: E402

WIDTH, HEIGHT = 160, 120
TORUS = compare.EXAMPLES / "quartic" / "torus.pov"


@pytest.fixture(scope="module")
def povray() -> str:
    path = shutil.which("povray")
    if path is None or not compare.sample_scenes():
        pytest.fail(
            "POV-Ray 3.7 and its samples are missing: run `make setup` "
            "(apt packages povray povray-examples povray-includes)",
            pytrace=False,
        )
    return path


def renderers(binary: Path, width: int = WIDTH, height: int = HEIGHT) -> compare.Renderers:
    return compare.Renderers(binary, width, height)


def test_the_samples_are_there(povray):
    names = [p.stem for p in compare.sample_scenes()]
    # Debian's povray-examples 3.7: 18 quartic and 4 csg samples.
    assert len(names) == 22, names
    for table in (compare.COLOUR_EXEMPT, compare.OUTSIDE_SUBSET, compare.EXTRA_HITS_ALLOWED):
        assert set(table) <= set(names), f"an exemption names no sample: {set(table) - set(names)}"


def without_comments(text: str) -> str:
    return re.sub(r"//[^\n]*", "", re.sub(r"/\*.*?\*/", "", text, flags=re.DOTALL))


@pytest.mark.parametrize(
    "name, features",
    [*compare.COLOUR_EXEMPT.items(), *compare.OUTSIDE_SUBSET.items()],
)
def test_each_exemption_names_what_its_scene_uses(povray, name, features):
    # An exemption is earned by the scene, not by a failing number: every
    # feature it names occurs in the scene's own text outside comments.
    (scene,) = [p for p in compare.sample_scenes() if p.stem == name]
    text = without_comments(scene.read_text(errors="replace"))
    for feature in features:
        assert re.search(rf"\b{feature}\b", text), f"{scene} does not use {feature}"


def test_png_reader_matches_povray_ppm(povray, tmp_path):
    # The same render written by POV-Ray as PNG (libpng, adaptive row
    # filters) and as PPM (raw bytes): the reader must give the PPM's bytes.
    common = [f"+I{TORUS}", f"+W{WIDTH}", f"+H{HEIGHT}", "-A", "-D", "-V", "File_Gamma=sRGB"]
    for kind, name in (("+FN", "t.png"), ("+FP", "t.ppm")):
        command = [povray, *common, kind, f"+O{name}"]
        subprocess.run(command, cwd=tmp_path, check=True, capture_output=True)
    ppm = (tmp_path / "t.ppm").read_bytes()
    pixels = np.frombuffer(ppm[-WIDTH * HEIGHT * 3 :], dtype=np.uint8)
    assert np.array_equal(read_png(tmp_path / "t.png"), pixels.reshape(HEIGHT, WIDTH, 3))
    # The check means something only if all four filters were used.
    assert row_filters(tmp_path / "t.png", WIDTH * 3) >= {1, 2, 3, 4}


def row_filters(png: Path, stride: int) -> set[int]:
    data, pos, idat = png.read_bytes(), 8, b""
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        if data[pos + 4 : pos + 8] == b"IDAT":
            idat += data[pos + 8 : pos + 8 + length]
        pos += 12 + length
    raw = zlib.decompress(idat)
    return set(raw[:: stride + 1])


def test_png_writer_round_trip(tmp_path):
    image = np.random.default_rng(20).integers(0, 256, size=(7, 5, 3), dtype=np.uint8)
    write_png(tmp_path / "r.png", image)
    assert np.array_equal(read_png(tmp_path / "r.png"), image)


def srgb8(c: float) -> int:
    """IEC 61966-2-1's encoding of linear c, rounded to 8 bits."""
    encoded = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
    return round(255 * encoded)


@pytest.mark.parametrize("colour", [(0.002, 0.2, 0.5), (0.01, 0.7, 0.9)])
def test_both_renderers_encode_srgb_alike(povray, sturmray, tmp_path, colour):
    # A background alone, linear in both (POV-Ray: assumed_gamma 1): POV-Ray's
    # File_Gamma=sRGB and sturmray's PNG preview give the same 8-bit values,
    # the sRGB encoding (0.002 is on its linear segment). File_Gamma=2.2
    # would give 31 for 0.01, not 25.
    expected = [srgb8(c) for c in colour]
    rgb = ", ".join(map(str, colour))
    pov = tmp_path / "bg.pov"
    pov.write_text(
        "#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n"
        f"camera {{ location <0, 0, -5> look_at 0 }}\nbackground {{ color rgb <{rgb}> }}\n"
    )
    from_povray = renderers(Path("unused"), 4, 3).run_povray(pov, pov, tmp_path, "bg-povray")
    toml = tmp_path / "bg.toml"
    toml.write_text(
        f"background = [{rgb}]\n[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\n"
        "up = [0, 1, 0]\nfov = 40\nwidth = 4\nheight = 3\n"
    )
    sturmray("render", toml, "--spp", "1", "-o", tmp_path / "bg-sturmray.exr")
    from_sturmray = read_png(tmp_path / "bg-sturmray.png")
    assert (from_povray.image == expected).all(), from_povray.image[0, 0]
    assert (from_sturmray == expected).all(), from_sturmray[0, 0]


def test_wrapper_keeps_camera_and_lights_and_its_background_wins(povray, tmp_path):
    r = renderers(Path("unused"))
    own = r.run_povray(TORUS, TORUS, tmp_path, "own")
    renders = []
    for grey in (0, 1):
        wrapper = tmp_path / f"bg{grey}.pov"
        wrapper.write_text(compare.wrapper_text(TORUS, grey))
        renders.append(r.run_povray(wrapper, TORUS, tmp_path, f"bg{grey}"))
    black, white = (x.image for x in renders)
    assert own.image is not None and black is not None and white is not None
    assert all(x.warnings == 0 for x in renders), [x.stderr for x in renders]
    hit = compare.object_mask(black, white)
    # torus.pov's own background is not black: the wrapper's later one won.
    assert not np.array_equal(own.image[~hit], black[~hit])
    assert (black[~hit] == 0).all() and (white[~hit] == 255).all()
    # The torus fills a good part of the frame, lit and seen as in the scene:
    # same camera, same lights.
    assert 0.2 < hit.mean() < 0.8
    assert np.array_equal(own.image[hit], black[hit])
    assert np.array_equal(own.image[hit], white[hit])


ORTHO_SCENE = """\
#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ orthographic location <0, 0, -10> direction z right 4*x up 3*y }}
light_source {{ <-5, 5, -10> color rgb 1 }}
background {{ color rgb <0.2, 0.4, 0.6> }}
// Opaque, but glossy: it reflects a fifth of the background.
sphere {{ 0, {radius} pigment {{ color rgb <1, 0.5, 0> }} finish {{ reflection 0.2 }} }}
// Clear: what shows through it is the background.
sphere {{ <1.5, 0.9, 0>, 0.45 pigment {{ color rgbt <1, 1, 1, 1> }} }}
"""


def pixel_centres_inside(radius: float, width: int, height: int) -> int:
    """Pixel centres of a width x height image of [-2, 2] x [-1.5, 1.5] inside
    the circle of `radius` about the origin. With pixels 0.1 wide (40 x 30),
    centres sit at odd multiples of 0.05, and x^2 + y^2 = r^2 for r = 1 or 0.8
    would need two odd squares to sum to 400 or 256, a multiple of 4, which
    no two odd squares do: no centre lies on a rim."""
    count = 0
    for j in range(height):
        for i in range(width):
            x = -2 + (i + 0.5) * 4 / width
            y = 1.5 - (j + 0.5) * 3 / height
            count += x * x + y * y < radius * radius
    return count


def ortho_mask(r: compare.Renderers, folder: Path, radius: float) -> np.ndarray:
    scene = folder / f"ortho{radius}.pov"
    scene.write_text(ORTHO_SCENE.format(radius=radius))
    images = []
    for grey in (0, 1):
        wrapper = folder / f"ortho{radius}-bg{grey}.pov"
        wrapper.write_text(compare.wrapper_text(scene, grey))
        images.append(r.run_povray(wrapper, scene, folder, f"ortho{radius}-bg{grey}").image)
    return compare.object_mask(*images)


def test_hit_mask_counts_pixel_centres(povray, tmp_path):
    # 40 x 30 pixels over a 4 x 3 orthographic view: one ray through each
    # pixel centre (POV-Ray -A), so the unit sphere covers exactly the
    # centres inside the unit circle. The glossy sphere counts as an object,
    # the clear one as background.
    r = renderers(Path("unused"), 40, 30)
    big, small = ortho_mask(r, tmp_path, 1.0), ortho_mask(r, tmp_path, 0.8)
    assert big.sum() == pixel_centres_inside(1.0, 40, 30)
    assert small.sum() == pixel_centres_inside(0.8, 40, 30)
    ring = pixel_centres_inside(1.0, 40, 30) - pixel_centres_inside(0.8, 40, 30)
    assert compare.hit_differences(big, small) == (ring, 0)
    assert compare.hit_differences(small, big) == (0, ring)


def test_colour_difference_by_hand():
    a = np.full((2, 3, 3), 100, dtype=np.uint8)
    b = a.copy()
    b[0, :, 0] = 110  # the top row's red, 10 levels up
    per_channel, overall = compare.colour_difference(a, b)
    # 3 of 6 pixels differ by 10/255 in one of three channels.
    assert np.allclose(per_channel, [10 / 255 / 2, 0, 0])
    assert overall == pytest.approx(10 / 255 / 6)
    top = np.zeros((2, 3), dtype=bool)
    top[0] = True
    per_channel, overall = compare.colour_difference(a, b, top)
    assert np.allclose(per_channel, [10 / 255, 0, 0])
    assert compare.colour_difference(a, b, np.zeros((2, 3), dtype=bool)) is None


def test_a_render_past_its_time_fails_alone(tmp_path):
    renderers = compare.Renderers(Path("sturmray"), WIDTH, HEIGHT, timeout=0.2)
    render = renderers.run(["sleep", "5"], tmp_path, tmp_path / "never.png")
    assert render.image is None
    assert render.failure() == "exit -1: error: timed out after 0.2 s"


def result(name: str, pov_only=0, sturm_only=0, colour=0.0, warnings=0) -> compare.SceneResult:
    image = np.zeros((HEIGHT, WIDTH, 3), dtype=np.uint8)
    stderr = "sturmray: warning: x\n" * warnings
    r = compare.SceneResult(
        Path(f"/samples/{name}.pov"),
        WIDTH,
        HEIGHT,
        compare.Render(0, "", image),
        compare.Render(0, stderr, image),
        pov_only,
        sturm_only,
        (np.array([colour] * 3), colour),
    )
    r.problems = compare.judge(r)
    return r


def test_judge_holds_the_issue_limits(monkeypatch):
    # 0.1% of 160 x 120 = 19.2 pixels; 2% mean colour difference.
    assert result("torus", pov_only=10, sturm_only=9).passed
    assert not result("torus", pov_only=10, sturm_only=10).passed
    assert not result("torus", pov_only=20).passed
    assert result("torus", colour=0.02).passed
    assert not result("torus", colour=0.0201).passed
    # Exempt from the colour check, never from the hit check.
    assert result("granite", colour=0.5).passed
    assert not result("granite", sturm_only=20).passed
    # Outside the subset: a warning and exit 0 are all that is asked.
    assert result("hfclip", pov_only=5000, colour=0.5, warnings=1).passed
    assert not result("hfclip", warnings=0).passed
    # Extra hits where POV-Ray misses, only for a named scene, only that way.
    monkeypatch.setitem(compare.EXTRA_HITS_ALLOWED, "torus", "a test")
    assert result("torus", sturm_only=500).passed
    assert not result("torus", pov_only=20).passed


SHIM = """\
#!{python}
# sturmray's render command played by POV-Ray, to test the harness alone.
import subprocess, sys
from pathlib import Path
args = sys.argv[2:]
scene, rest = args[0], args[1:]
opts = dict(zip(rest[::2], rest[1::2]))
libs = [rest[i + 1] for i, a in enumerate(rest) if a == "--pov-include"]
out = Path(opts["-o"]).with_suffix(".png").name  # beside the EXR, in the cwd
sys.exit(subprocess.run(
    ["{povray}", "+I" + scene, "+O" + out, "+W" + opts["--width"], "+H" + opts["--height"],
     "-A", "+FN", "-D", "-V", "File_Gamma=sRGB"] + ["+L" + d for d in libs]).returncode)
"""


def test_pipeline_with_povray_standing_in_for_sturmray(povray, tmp_path):
    shim = tmp_path / "fake-sturmray"
    shim.write_text(SHIM.format(python=sys.executable, povray=povray))
    shim.chmod(0o755)
    scenes = [p for p in compare.sample_scenes() if p.stem in ("torus", "cliptst2", "hfclip")]
    results = compare.run(renderers(shim), scenes, tmp_path, jobs=6)
    by_name = {r.name: r for r in results}
    for name in ("torus", "cliptst2"):
        r = by_name[name]
        assert (r.pov_only, r.sturm_only, r.colour[1]) == (0, 0, 0.0), name
        assert r.passed, r.problems
    # POV-Ray does not warn about height_field, so as sturmray it fails there.
    assert by_name["hfclip"].problems == ["sturmray gave no warning for height_field"]
    out = tmp_path / "out"
    compare.write_outputs(results, out, {"torus"})
    table = (out / "compare.md").read_text()
    assert table.count("\n") == 2 + len(scenes)
    picture = read_png(out / "torus.png")
    assert picture.shape == (HEIGHT, 2 * WIDTH + 8, 3)
    assert np.array_equal(picture[:, :WIDTH], picture[:, WIDTH + 8 :])


def test_sturm_count_by_hand():
    F = Fraction
    # (t - 1)(t - 2)(t + 3) = t^3 - 7t + 6: two roots above 0.
    assert compare.sturm_count([F(6), F(-7), F(0), F(1)]) == 2
    assert compare.sturm_count([F(1), F(0), F(1)]) == 0  # t^2 + 1
    assert compare.sturm_count([F(1), F(-2), F(1)]) == 1  # (t - 1)^2: one, double
    assert compare.sturm_count([F(0), F(1)]) == 0  # t: its root is the origin, not after it
    # (t - 1e-9)(t + 1): a root just after the origin is one.
    assert compare.sturm_count([F(-1, 10**9), F(1) - F(1, 10**9), F(1)]) == 1
    # Over (lo, hi]: the root at lo is left out, the one at hi counted.
    cubic = [F(6), F(-7), F(0), F(1)]
    assert compare.sturm_count(cubic, F(0), F(3, 2)) == 1
    assert compare.sturm_count(cubic, F(1), F(2)) == 1
    assert compare.sturm_count(cubic, F(-4), F(1)) == 2
    assert compare.sturm_count(cubic, F(2), F(10)) == 0


def test_exact_surfaces_by_hand():
    # The unit sphere x^2 + y^2 + z^2 - 1 from z = -11, angle 90 on 100 x 100:
    # pixel i's ray leaves the axis by tan = 2 (i + 0.5 - 50) / 100 and meets the
    # sphere while sin <= 1/11 (tan <= 0.0913): pixels 45..54 of the middle row.
    sphere = compare.ExactSurfaces(
        (0.0, 0.0, -11.0),
        90.0,
        {(2, 0, 0): 1, (0, 2, 0): 1, (0, 0, 2): 1, (0, 0, 0): -1},
        ((np.eye(3), (0.0, 0.0, 0.0)),),
        "a test",
    )
    row = sphere.hits(100, 100, [(i, 50) for i in range(100)])
    assert [i for i in range(100) if row[i, 50] is True] == list(range(45, 55))
    assert all(row[i, 50] is False for i in range(100) if not 45 <= i < 55)
    # Clipped to a ball of radius 0.5 inside it, the sphere shows nowhere;
    # clipped to a ball of radius 2 around it, everywhere it did.
    for radius, seen in ((0.5, []), (2.0, list(range(45, 55)))):
        clipped = compare.ExactSurfaces(
            sphere.location, 90.0, sphere.terms, sphere.placements, "", ((0, 0, 0), radius)
        )
        row = clipped.hits(100, 100, [(i, 50) for i in range(100)])
        assert [i for i in range(100) if row[i, 50] is True] == seen
    # Placed: scaled by 2 and moved to x = 3, it covers other pixels.
    moved = compare.ExactSurfaces(
        (0.0, 0.0, -11.0), 90.0, sphere.terms, ((2 * np.eye(3), (3.0, 0.0, 0.0)),), ""
    )
    hits = moved.hits(100, 100, [(50, 50), (63, 50)])
    assert hits[50, 50] is False and hits[63, 50] is True


def test_settled_scenes_at_their_disputed_pixels():
    # At 800x600 POV-Ray 3.7 hits these pixels and sturmray does not; the exact
    # count finds no root there, and does find the surface on a pixel nearby
    # that both renderers hit (so the scene's model is the scene).
    for name, misses, hit in (
        ("quarcyl", [(81, 30), (70, 50), (10, 159)], (400, 300)),
        ("grafbic", [(586, 518)], (584, 518)),
    ):
        truth = compare.SETTLED_EXACTLY[name].hits(800, 600, misses + [hit])
        assert [truth[p] for p in misses] == [False] * len(misses), name
        assert truth[hit] is True, name


def test_samples_match_povray(povray, sturmray_bin, tmp_path):
    results = compare.run(renderers(sturmray_bin), compare.sample_scenes(), tmp_path, jobs=4)
    failed = [r for r in results if not r.passed]
    assert not failed, "\n" + compare.markdown_table(results)


CHECKERED = """\
#version 3.7;
global_settings { assumed_gamma 1.0 }
#include "colors.inc"
camera { location <0, 3, -6> look_at <0, 0, 0> angle 50 right x*image_width/image_height }
light_source { <10, 20, -10> color White }
plane { y, -1 pigment { checker color NavyBlue color rgb <0.9, 0.8, 0.2> scale 1.5 }
        finish { ambient 0.2 diffuse 0.8 } }
torus { 1.5, 0.4 pigment { checker Red White scale 0.3 } rotate 30*x translate y*0.5 }
sphere { <-2.6, 0, 0.5>, 0.5 pigment { rgb <0.2, 0.9, 0.3> } no_shadow }
background { color rgb 0.1 }
"""


def test_a_checkered_floor_matches_povray(povray, sturmray_bin, tmp_path):
    # POV-Ray's classic checkered floor (the samples' own are commented out):
    # a plane alone, cut by the world box, and a checker that moves with its
    # object (scaled pigment, rotated and moved torus), lit by an unfading
    # light with shadows, and a sphere with `no_shadow`. Pixels differ only where a cube's edge crosses a
    # pixel centre in the distance, where the f32 hit point of one renderer
    # and the f64 of the other fall on either side.
    scene = tmp_path / "checkered.pov"
    scene.write_text(CHECKERED)
    both = renderers(sturmray_bin)
    a = both.run_povray(scene, scene, tmp_path, "pov")
    b = both.run_sturmray(scene, scene, tmp_path, "sturm")
    assert a.image is not None and b.image is not None, (a.stderr, b.stderr)
    _, overall = compare.colour_difference(a.image, b.image)
    assert overall < 0.005, overall
    differing = (np.abs(a.image.astype(int) - b.image.astype(int)).max(axis=2) > 8).mean()
    assert differing < 0.005, differing


LIGHT_SCENES = REPO / "tests" / "pov_lights"


def both_images(r, scene, tmp_path, name, colour_limit=True):
    """POV-Ray's and sturmray's renders of `scene` (8-bit sRGB): both must
    succeed, and, with `colour_limit`, differ by at most the issue's 2%
    mean colour difference."""
    pov = r.run_povray(scene, scene, tmp_path, f"{name}-povray")
    ours = r.run_sturmray(scene, scene, tmp_path, f"{name}-sturmray")
    assert pov.image is not None, pov.failure()
    assert ours.image is not None, ours.failure()
    if colour_limit:
        _, overall = compare.colour_difference(pov.image, ours.image)
        assert overall <= compare.COLOUR_LIMIT, overall
    return pov.image, ours.image


@pytest.mark.parametrize("name", ["spotlight", "cylinder", "parallel"])
def test_beam_lights_light_what_povray_lights(povray, sturmray_bin, tmp_path, name):
    # POV-Ray's spotlight (radius, falloff, tightness; its defaults), cylinder
    # and parallel lights, written for this test: both renderers at one size
    # without anti-aliasing. The mean colour difference stays within the
    # issue's 2%, and the lit region (brighter than halfway between the
    # darkest and brightest floor) has its edge in the same place: at most
    # 0.2% of the pixels are lit in one render only.
    scene = LIGHT_SCENES / f"{name}.pov"
    pov, ours = both_images(renderers(sturmray_bin), scene, tmp_path, name)
    level = compare.linear(pov).mean(axis=2)
    middle = 0.5 * (level.min() + level.max())
    lit_pov = level > middle
    lit_ours = compare.linear(ours).mean(axis=2) > middle
    # The beam lights part of the frame, not all of it.
    assert 0.02 < lit_pov.mean() < 0.95, lit_pov.mean()
    assert (lit_pov != lit_ours).mean() <= 0.002


GAMMA_SCENE = """\
{header}
camera {{ location <0, 0.5, -4> look_at 0 angle 45 }}
light_source {{ <-3, 4, -5> color rgb 1 }}
background {{ color rgb <0.1, 0.3, 0.6> }}
sphere {{ 0, 1 pigment {{ color rgb <0.8, 0.5, 0.2> }} finish {{ ambient 0.1 diffuse 0.7 phong 0.5 }} }}
plane {{ y, -1 pigment {{ color rgb 0.5 }} }}
"""


@pytest.mark.parametrize(
    "header",
    [
        # No assumed_gamma in a scene older than 3.7: POV-Ray turns gamma
        # handling off, and what it computes goes to the file as it is.
        "#version 3.6;",
        "#version 3.6;\nglobal_settings { assumed_gamma 2.2 }",
        "#version 3.7;\nglobal_settings { assumed_gamma 1.8 }",
        "#version 3.7;\nglobal_settings { assumed_gamma srgb }",
        "#version 3.7;\nglobal_settings { assumed_gamma 1 }",
    ],
)
def test_gamma_rules_give_povrays_pixels(povray, sturmray_bin, tmp_path, header):
    # POV-Ray 3.7 lights a scene in its working gamma space (assumed_gamma)
    # and decodes only the result for the file: a lit sphere, a floor in its
    # shadow and a background, where colours reading as linear would be up
    # to 60 levels of 255 off (0.5 at gamma 2.2 shows as 128, not 188).
    # Limits: the 2% mean of issue 20 and 4 levels at the 99th percentile,
    # for the sphere's rim and the shadow's edge.
    scene = tmp_path / "gamma.pov"
    scene.write_text(GAMMA_SCENE.format(header=header))
    pov, ours = both_images(renderers(sturmray_bin, 96, 72), scene, tmp_path, "gamma")
    levels = np.abs(pov.astype(int) - ours.astype(int))
    assert np.percentile(levels, 99) <= 4, np.percentile(levels, 99)


BOX_FACES_SCENE = """\
#version 3.7;
global_settings { assumed_gamma 1.0 max_trace_level 10 }
camera { location <0, 3, -6> look_at <0, 0.5, 0> angle 50 }
light_source { <-4, 8, -3> color rgb 1 }
background { color rgb <0.9, 0.9, 1.0> }
// A box for a floor and a sphere resting on it, whose shadow falls on the
// box's top face; glass that light crosses twice, a slab and a capped
// cylinder seen through their faces and caps (untinted, and casting no
// shadow: the next test adds both).
box { <-4, -0.5, -2>, <4, 0, 6> pigment { color rgb <0.8, 0.7, 0.5> } }
sphere { <-1.8, 0.6, 0.5>, 0.6 pigment { color rgb <0.2, 0.5, 0.8> } }
box { <-0.6, 0.05, -0.5>, <0.6, 1.6, -0.3>
      pigment { color rgbf <1, 1, 1, 0.7> } finish { ambient 0 diffuse 0 reflection 0.1 }
      interior { ior 1.5 } no_shadow }
cylinder { <1.8, 0.05, 0.5>, <1.8, 1.2, 0.5>, 0.6
      pigment { color rgbt <1, 1, 1, 0.8> } finish { ambient 0 diffuse 0 }
      interior { ior 1.3 } no_shadow }
"""


def test_rays_leave_box_faces_and_caps_where_povray_s_do(povray, sturmray_bin, tmp_path):
    # A hit on a face of a box or a cylinder's cap carried the box's size
    # as its error bound, and the rays spawned from it started that far
    # off: no shadow on a box floor near what stands on it, and glass that
    # filtered light once instead of at each face (iortest.pov): then 8.3%
    # of the pixels were more than 8 levels of 255 off, under a 1.5% mean.
    # Limits: the 2% mean, and 4% of the pixels more than 8 levels off: 2.5%
    # are, the slab's top edge seen grazing and the floor seen through the
    # cylinder's bottom cap, where the two renderers' refraction depths and
    # bail-outs part.
    assert_close_to_povray(BOX_FACES_SCENE, "faces", sturmray_bin, tmp_path, far_off_limit=0.04)


def assert_close_to_povray(text, name, sturmray_bin, tmp_path, far_off_limit):
    """Renders the scene `text` with both at 160x120: within the 2% mean
    colour difference, and at most `far_off_limit` of the pixels more than 8
    levels of 255 apart."""
    scene = tmp_path / f"{name}.pov"
    scene.write_text(text)
    pov, ours = both_images(renderers(sturmray_bin, 160, 120), scene, tmp_path, name)
    far_off = (np.abs(pov.astype(int) - ours.astype(int)).max(axis=2) > 8).mean()
    assert far_off <= far_off_limit, far_off


def test_glass_is_tinted_and_its_shadows_filtered_as_povray_s(povray, sturmray_bin, tmp_path):
    # The scene above with its glass casting shadows, the cylinder's tinted:
    # POV-Ray tints the light through a surface by the pigment's filter
    # (colour x filter + transmit) and lets shadow rays through transparent
    # surfaces filtered at each. Untinted and with opaque shadows, 9.3% of
    # the pixels were more than 8 levels off; 2.5% are (limit 4%, as above).
    text = BOX_FACES_SCENE.replace(" no_shadow", "").replace(
        "rgbt <1, 1, 1, 0.8>", "rgbf <1, 0.6, 0.3, 0.8>"
    )
    assert text.count("rgbf") == 2 and "no_shadow" not in text
    assert_close_to_povray(text, "glass", sturmray_bin, tmp_path, far_off_limit=0.04)


FADE_SCENE = """\
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 4, -9> look_at <0, 0.5, 0> angle 50 }
// A point light that fades (its own colour 3 units off), a spotlight that
// fades faster, and spheres of brilliance 0.4, 1 and 4.
light_source { <0, 3, -1> color rgb 1 fade_distance 3 fade_power 2 }
light_source { <4, 6, 2> color rgb <1, 0.8, 0.6> spotlight point_at <2, 0, 1>
               radius 20 falloff 35 fade_distance 4 fade_power 1 }
background { color rgb <0.1, 0.1, 0.2> }
plane { y, 0 pigment { color rgb 0.8 } finish { ambient 0 diffuse 0.7 } }
sphere { <-2.5, 1, 1>, 1 pigment { color rgb <0.9, 0.4, 0.2> }
         finish { ambient 0 diffuse 0.8 brilliance 0.4 } }
sphere { <0, 1, 2>, 1 pigment { color rgb <0.3, 0.8, 0.3> } finish { ambient 0 diffuse 0.8 } }
sphere { <2.5, 1, 1>, 1 pigment { color rgb <0.3, 0.4, 0.9> }
         finish { ambient 0 diffuse 0.8 brilliance 4 phong 0.5 } }
"""


def test_brilliance_and_fading_lights_give_povrays_pixels(povray, sturmray_bin, tmp_path):
    # POV-Ray's `brilliance` (diffuse light times cos^brilliance, as in
    # metals.inc and golds.inc) and its lights' `fade_distance` and
    # `fade_power` (2 / (1 + (d/D)^P)), on a point light and a spotlight.
    # Read as 1 and as unfading, 89% of the pixels were more than 8 levels
    # of 255 off (14% mean colour difference); brilliance alone left 6.9%.
    # Now no pixel is more than 8 levels off at 160x120 (measured: none
    # differs at all); the limit leaves room for 19 rim pixels.
    assert_close_to_povray(FADE_SCENE, "fade", sturmray_bin, tmp_path, far_off_limit=0.001)


INTERIOR_FADE_SCENE = """\
#version 3.7;
global_settings { assumed_gamma 1.0 max_trace_level 10 }
camera { location <0, 3, -7> look_at <0, 0.8, 0> angle 50 }
light_source { <-4, 8, -5> color rgb 1 }
background { color rgb <0.9, 0.9, 1.0> }
plane { y, 0 pigment { color rgb <0.8, 0.7, 0.5> } }
// Glass that fades: by a power (glass.inc's I_Glass1), exponentially to a
// colour, and (POV-Ray's quirk) with a power of 0. The box's floor face,
// seen through its front, reflects totally inside.
sphere { <-2, 1, 0.5>, 1 pigment { color rgbf <1, 1, 1, 0.9> } finish { ambient 0 diffuse 0.1 }
         interior { ior 1.5 fade_distance 1 fade_power 2 } }
box { <-0.7, 0.01, -0.5>, <0.7, 1.8, 0.8> pigment { color rgbt <1, 1, 1, 0.9> }
      finish { ambient 0 diffuse 0 }
      interior { ior 1.3 fade_distance 0.5 fade_power 1001 fade_color <1, 0.5, 0.2> } }
sphere { <2, 1, 0.5>, 1 pigment { color rgbt <1, 1, 1, 0.9> } finish { ambient 0 diffuse 0 }
         interior { ior 1.0 fade_distance 1 fade_power 0 } }
"""


def test_glass_fades_inside_and_reflects_totally_as_povray_s(povray, sturmray_bin, tmp_path):
    # POV-Ray's interior fade (fade_distance, fade_power, fade_color) on the
    # light through the surface where a ray leaves the glass, and on shadow
    # rays; and its total internal reflection, which carries all of the
    # light (not the transmitted fraction plus the surface's reflection).
    # Without the fade, 6.0% mean colour difference and 28% of the pixels
    # more than 8 levels of 255 off; with it but the fraction under total
    # reflection, 1.6% of the pixels (the box's floor face) 10% too dark.
    # Now no pixel is more than 1 level off at 160x120 (measured); the limit
    # leaves room for 19 rim pixels.
    assert_close_to_povray(INTERIOR_FADE_SCENE, "interior-fade", sturmray_bin, tmp_path, far_off_limit=0.001)


FOG_SCENE = """\
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 2, -8> look_at <0, 1, 0> angle 60 }
light_source { <-5, 10, -6> color rgb 1 }
background { color rgb <0.2, 0.3, 0.6> }
plane { y, 0 pigment { color rgb <0.7, 0.6, 0.4> } }
sphere { <-2, 1, 2>, 1 pigment { color rgb <0.9, 0.2, 0.1> } finish { phong 0.5 } }
sphere { <1.5, 1, 8>, 1 pigment { color rgb <0.1, 0.7, 0.3> } }
sphere { <4, 2, 20>, 2 pigment { color rgb <0.2, 0.3, 0.9> } }
// Glass, whose inside is not fogged, and a mirror, whose reflection is.
sphere { <1, 1, 0>, 0.8 pigment { color rgbf <1, 1, 1, 0.9> } finish { reflection 0.2 }
         interior { ior 1.4 } }
box { <3, 0, 3>, <4, 3, 3.2> pigment { color rgb 0.2 } finish { reflection 0.8 } }
// A thin constant fog, tinted and partly filtered, and a ground fog.
fog { distance 40 color rgbf <0.8, 0.8, 0.9, 0.3> }
fog { fog_type 2 distance 6 color rgb <0.9, 0.85, 0.8> fog_offset 0.5 fog_alt 0.8 }
"""


HOLLOW_FOG_SCENE = """\
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 1, -6> look_at <0, 1.5, 0> angle 70 }
light_source { <30, 50, -40> color rgb 1 }
// The templates' sky: a hollow plane overhead, the camera inside it; a
// ground plane; a fog that fills the air, the sky's inside included.
plane { y, 30 hollow pigment { color rgb <0.3, 0.5, 1> } finish { ambient 1 diffuse 0 } }
plane { y, 0 pigment { color rgb <0.6, 0.5, 0.3> } }
sphere { <1, 1, 4>, 1 pigment { color rgb <0.9, 0.3, 0.2> } }
// A solid (not hollow) box around part of the view: no fog inside it.
box { <-20, 0.5, 25>, <20, 20, 40> pigment { color rgb <0.2, 0.7, 0.3> } }
fog { distance 40 color rgb <0.9, 0.9, 0.95> }
"""


@pytest.mark.parametrize("name", ["fog", "hollow-fog"])
def test_fog_is_povrays(povray, sturmray_bin, tmp_path, name):
    # POV-Ray's constant and ground fog (its fog_type 2, offset and
    # altitude), filtered and tinted, on every ray through the air: camera,
    # reflected and refracted rays, not a ray's way inside glass or another
    # solid, but inside a `hollow` one (the sky plane of POV-Ray's scene
    # templates). Left out, every pixel of the first scene was more than 8
    # levels of 255 off (35% mean colour difference); with the sky plane's
    # inside left unfogged, 7.9% of the second's. Now no pixel differs at
    # all at 160x120 (measured); the limit leaves room for 19 rim pixels.
    text = FOG_SCENE if name == "fog" else HOLLOW_FOG_SCENE
    assert_close_to_povray(text, name, sturmray_bin, tmp_path, far_off_limit=0.001)


IDIOM_HEADER = """\
#version 3.7;
global_settings { assumed_gamma 1.0 }
#include "shapes.inc"
#include "shapes2.inc"
camera { location <0, 3, -10> look_at 0 angle 45 right x*image_width/image_height }
light_source { <20, 30, -40> color rgb 1 }
background { color rgb 0 }
#declare T = texture { pigment { color rgb <1, 0.8, 0.6> } finish { ambient 0.3 diffuse 0.7 } }
"""

# POV-Ray idioms that sturmray once refused or drew otherwise, each written
# for this test: open tubes in CSG keep the capped solid's inside; trees
# unbounded as a whole; a bounded union's triangles; a flat box; checkers
# of textures and of `rgb a rgb b`; a camera looking straight down;
# orthographic cameras sized by right and up, and by an angle; spheres
# scattered by `rand`; objects taken from an array; colour-mapped patterns
# (gradient, radial, onion, spherical, boxed, cylindrical, planar, leopard,
# marble, wood) with their waves, frequency, phase and a declared map.
# Then POV-Ray's CSG rules that a fuzz against POV-Ray found drawn otherwise
# (random trees of its shapes at 80x60, hit masks compared): a disc in CSG
# is inside behind its plane, and its ring's box bounds what that shows; an
# inverted or subtracted clipped object is inverted within its clips; a
# part's bounded_by gates that part and bounds what its inside shows (the
# disc's ring covers the box: where a ring's box cuts what the half-space
# shows, POV-Ray's box grows with each transform, ours does not); an
# intersection of parts apart, or with a surface that cannot reach it, is
# empty, not an error. A whole CSG object's `bounded_by` of several objects
# lets a ray through only if it meets every one (POV-Ray's `Ray_In_Bound`)
# and the box of their boxes; a plane's bound is removed and only that box
# culls it (POV-Ray's `Link_To_Frame`; both in a scene of two objects and a
# light, as POV-Ray draws one object and a light without its box test). A plane's
# bound in an intersection gates the plane but does not bound the
# intersection, which takes the plane's own box (`CSG::Compute_BBox`).
# Transforms after a bound's or clip's objects move them all, and a second
# block adds its objects to the first's (`Parse_Bound_Clip`). A bound no ray
# can pass (boxes apart, an empty intersection) leaves nothing of the object;
# but with fewer than three objects in the scene, lights counted (Debian's
# `Bounding_Threshold = 3`), POV-Ray culls by no box, so a removed bound's
# box cuts nothing there (the header's light and one sphere). A part whose
# own bound no ray can pass shows no surface, but its inside still counts
# (POV-Ray's `Inside_Object` ignores bounds): an invisible cut.
IDIOMS = {
    "shut_parts": "#declare E = intersection { sphere { -3*x, 0.5 } sphere { 3*x, 0.5 } }\n"
    "intersection { sphere { 0, 1.5 } sphere { <0.8, 0, 0>, 1.5 bounded_by { E } } texture { T } translate -2*x }\n"
    "difference { box { -1, 1 } sphere { <1, 1, -1>, 1 bounded_by { E } } texture { T } rotate 20*y translate 2*x }",
    "bound_boxes_apart": "sphere { 0, 1.5 texture { T } bounded_by { box { <-2, -2, -2>, <-0.5, 2, 2> }"
    " box { <0.5, -2, -2>, <2, 2, 2> } } }\n"
    "intersection { sphere { 0, 1 } sphere { 0.5*x, 1 } texture { T } bounded_by { intersection {"
    " sphere { -2*x, 1 } sphere { 2*x, 1 } } } translate <-2, 1, 0> }\n"
    "sphere { <2, 1.5, 0>, 0.5 texture { T } }",
    "bound_box_below_threshold": "sphere { 0, 1.5 texture { T } bounded_by { box { <-2, -2, -2>, <-0.5, 2, 2> } } }",
    "bound_clip_blocks": "sphere { 0, 1.5 texture { T } clipped_by { plane { y, 0.3 } rotate 60*z }"
    " clipped_by { plane { z, 0.4 } } rotate 30*y }\n"
    "intersection { sphere { 0, 1 } sphere { <0.3, 0, 0>, 1 } texture { T }"
    " bounded_by { box { -1, 1 } translate <0.8, 0.6, 0> } bounded_by { sphere { 0, 1 } scale <1, 0.6, 1> }"
    " translate <3, 1, 0> }",
    "bounds_all": "plane { y, 0 texture { T } bounded_by { sphere { <-1, 0, 0>, 2 } sphere { <1, 0, 1>, 2 } } }\n"
    "intersection { sphere { 0, 1.5 } sphere { <0.6, 0, 0>, 1.5 } texture { T } bounded_by { sphere { <-1, 0, 0>, 1.6 }"
    " box { <-0.8, -2, -2>, <2, 0.6, 2> } } translate <0, 1.6, 1> }",
    "bounded_plane_part": "intersection { box { <-4, 0.5, -4>, <4, 3, 4> } plane { z, 0 rotate -50*x"
    " bounded_by { sphere { <-2, 2, 0>, 2 } } } texture { T } translate 2*x }",
    "disc_inside": "intersection { union { disc { <0, 0.2, 0>, <0.3, 1, -0.2>, 3.5, 0.6 } sphere { <1, 0.5, 0>, 0.8 } }"
    " box { -2, 2 } texture { T } rotate 20*y }",
    "subtracted_clipped": "difference { box { -1.5, 1.5 } sphere { <1, 1, -1>, 1.2 clipped_by { plane { y, 0.5 } } }"
    " texture { T } rotate 30*y }",
    "subtracted_merge_clipped": "difference { box { -1.5, 1.5 } merge { sphere { <1, 1, -1>, 1.2 clipped_by { plane { -x, 0.2 } } }"
    " cylinder { <-3, -1, -1>, <3, -1, -1>, 0.4 } } texture { T } rotate 30*y }",
    "inverse_clipped": "intersection { box { -1.5, 1.5 } object { sphere { 0, 1 clipped_by { box { <-2, -2, -2>, <2, 0.8, 2> } } inverse } }"
    " texture { T } rotate <20, 30, 0> }",
    "part_bounded": "intersection { union { sphere { 0, 1.5 } sphere { <1.5, 0, 0>, 1 } bounded_by { sphere { 0, 1.7 } } }"
    " box { <-3, -1, -3>, <3, 1, 3> } texture { T } rotate 20*y }",
    "empty_parts": "intersection { sphere { -3*x, 1 } sphere { 3*x, 1 } texture { T } }\n"
    "intersection { box { -1, 1 } quadric { <1, 1, 1>, <0, 0, 0>, <0, 0, 0>, -1 translate 5*x } texture { T } }\n"
    "sphere { 0, 1 texture { T } }",
    "open_cylinder": "difference { box { -2, 2 } cylinder { -3*x, 3*x, 1 open } texture { T } rotate 40*y }",
    "open_cone": "difference { box { -2, 2 } cone { <-1.5, 0, 0>, 0.2, <3, 0, 0>, 1.2 open } texture { T } rotate 40*y }",
    "open_ring": "intersection { sphere { 0, 1.5 } cylinder { -z, z, 1 open } texture { T } rotate <30, 20, 0> }",
    "channel": "difference { plane { y, 0 } box { <-1, -2, -5>, <1, 0.1, 20> } texture { T } }",
    "floor_and_ball": "merge { plane { y, -1 } sphere { 0, 1 } texture { T } }",
    "polyhedra": "union { object { Tetrahedron translate -2*x } object { Octahedron translate 2*x } texture { T } }",
    "bounded_union_triangle": "union { triangle { <-2, -1, 0>, <2, -1, 0>, <0, 2, 0> } sphere { <0, 0, -1>, 0.5 } texture { T } bounded_by { box { -3, 3 } } }",
    "flat_box": "box { <-2, -1, 0>, <2, 1.5, 0> texture { T } rotate <-30, 20, 0> }",
    "checkers": "sphere { <-1.2, 0, 0>, 1 pigment { checker rgb <1, 0, 0> rgb <0, 0, 1> scale 0.5 } finish { ambient 0.3 } }\n"
    "sphere { <1.2, 0, 0>, 1 texture { checker texture { T } texture { pigment { rgb <0.2, 0.5, 1> } finish { ambient 0.3 diffuse 0.7 } } scale 0.5 } }",
    "from_above": "camera { location <0, 12, 0> look_at 0 angle 45 right x*image_width/image_height }\n"
    "cone { -y, 1.5, y, 0.5 texture { T } translate x } box { <-3, -0.5, -1>, <-1, 0.5, 2> texture { T } }",
    "orthographic": "camera { orthographic location <1, 2, -10> up 5*y right 5*x*image_width/image_height look_at 0 }\n"
    "sphere { 0, 1 texture { T } } torus { 1.2, 0.3 rotate 60*x translate <1.5, -1, 1> texture { T } }",
    "orthographic_angle": "camera { orthographic location <3, 1, -5> angle 50 right x*image_width/image_height look_at <0, 0.5, 0> }\n"
    "sphere { 0, 1 texture { T } } box { <-2, -1.5, 1>, <-1, -0.5, 3> rotate 20*y texture { T } }",
    "random_spheres": "#declare S = seed(7);\n"
    "#for (I, 1, 12) sphere { <rand(S) * 6 - 3, rand(S) * 3 - 1, rand(S) * 4>, 0.2 + 0.3 * rand(S) texture { T } } #end",
    "array_of_objects": "#declare Things = array[3] { sphere { 0, 1 }, box { -0.8, 0.8 }, torus { 0.8, 0.3 rotate 90*x } }\n"
    "#for (I, 0, 2) object { Things[I] texture { T } translate (I - 1) * 2.5 * x } #end",
    "patterns": "plane { y, -1 pigment { gradient x color_map { [0 rgb <1, 0, 0>] [0.5 rgb <0, 1, 0>] [1 rgb <0, 0, 1>] } scale 2 } }\n"
    "sphere { <-2.2, 0, 0>, 1 pigment { onion color_map { [0 rgb <1, 0.5, 0>] [1 rgb <0, 0.3, 1>] } scale 0.4 } }\n"
    "sphere { 0, 1 pigment { radial frequency 6 color_map { [0 rgb <1, 0, 0>] [0.5 rgb 1] [1 rgb <1, 0, 0>] } rotate 30*x } }\n"
    "box { <1.2, -1, -1>, <3.2, 1, 1> pigment { boxed color_map { [0 rgb <0, 0, 1>] [1 rgb <1, 1, 0>] } translate 2.2*x } }\n"
    "sphere { <0, 2, 1>, 0.8 pigment { leopard scale 0.1 } } sphere { <2, 2, 1>, 0.8 pigment { spherical translate <2, 2, 1> } }\n"
    "sphere { <-2, 2, 1>, 0.8 pigment { cylindrical color_map { [0 rgb 0.2] [1 rgb <1, 0.8, 0.2>] } translate -2*x } }",
    "pattern_waves": "#declare M = color_map { [0.0 0.5 color rgb <1, 0, 0> color rgb <1, 1, 0>] [0.5 1.0 color rgb <0, 1, 0> color rgb <0, 0, 1>] }\n"
    "plane { y, -1 pigment { marble scale 0.5 } }\n"
    "sphere { <-2.2, 0, 0>, 1 pigment { wood scale 0.3 rotate 90*x } }\n"
    "sphere { 0, 1 pigment { gradient y sine_wave frequency 3 phase 0.3 color_map { M } } }\n"
    "sphere { <2.2, 0, 0>, 1 pigment { planar triangle_wave frequency -2 color_map { M } } }\n"
    "box { <-3, 1.2, 1>, <3, 1.8, 2> pigment { gradient x poly_wave 2 color_map { M } scale 1.5 } }",
}


@pytest.mark.parametrize("name", sorted(IDIOMS))
def test_pov_idioms_match_povray(povray, sturmray_bin, tmp_path, name):
    # The issue's limits: pixels hit by one renderer only (any colour above
    # the black background: every surface has ambient light) at most 0.1%
    # (a silhouette's pixel centre may round either way: measured, 0 on
    # nine scenes and 1 on from_above), and a mean colour difference of 2%.
    scene = tmp_path / f"{name}.pov"
    scene.write_text(IDIOM_HEADER + IDIOMS[name] + "\n")
    pov, ours = both_images(renderers(sturmray_bin), scene, tmp_path, name, colour_limit=False)
    hit_pov, hit_ours = pov.sum(axis=2) > 0, ours.sum(axis=2) > 0
    assert hit_pov.mean() > 0.01, "the scene shows nothing"
    one_only = (hit_pov != hit_ours).mean()
    assert one_only <= 0.001, ((hit_pov & ~hit_ours).sum(), (hit_ours & ~hit_pov).sum())
    _, overall = compare.colour_difference(pov, ours)
    assert overall <= compare.COLOUR_LIMIT, overall


# The hard kinds of algebraic surface (thin tori, thin shells, products and
# squares less a little, Goursat and Steiner-like surfaces, dense and
# high-degree polynomials; a quarter seen from far off through a narrow
# lens), as `make povray-fuzz` draws them: wherever the two renderers
# disagree, sturmray must be right by the exact root count (on an even
# sample of 60 disputed pixels: the count takes up to a second a pixel at
# degree 8). These seeds hold every kind, four of them seen from far off
# (5, 6, 12 and 17), where POV-Ray misses or invents most of the surface.
@pytest.mark.parametrize("seed", [0, 1, 2, 3, 5, 6, 7, 9, 12, 17])
def test_hard_polys_settled_exactly(povray, sturmray_bin, tmp_path, seed):
    import fuzz_poly

    args = argparse.Namespace(sturmray=sturmray_bin, width=80, height=60, settle=60)
    line, passed = fuzz_poly.compare(seed, args, tmp_path)
    assert passed, line
