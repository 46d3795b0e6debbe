"""The Cornell box of `make peers`, one description for both renderers.

sturmray renders scenes/cornell/cornell.obj path traced, lit only by the
box's own emissive panel, every surface Lambertian (the tall block's glossy
coat in cornell.mtl is dropped: the issue asks for diffuse BSDFs). The TOML
is written here for each run (its seed differs per run, so no two renders
share samples), and Mitsuba's scene dict is built from the same values and
the same OBJ, split at run time into one OBJ per `o` object (Mitsuba loads
one shape per file) in a temporary folder: the geometry is never copied
into the repository.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
OBJ = REPO / "scenes" / "cornell" / "cornell.obj"
MTL = OBJ.with_suffix(".mtl")

EYE = (0.278, 0.273, -0.8)
LOOK_AT = (0.278, 0.273, 0.0)
UP = (0.0, 1.0, 0.0)
FOV = 39.3077  # vertical, degrees (as scenes/cornell.toml)
SIZE = 256
# sturmray's path tracer shades vertices 0..=max_depth (the camera hit is 0)
# with next-event estimation at each, so its longest paths have max_depth + 2
# segments; Mitsuba's max_depth counts segments (1: emitters seen directly).
STURMRAY_MAX_DEPTH = 5
MITSUBA_MAX_DEPTH = STURMRAY_MAX_DEPTH + 2
# Every material Lambertian with its MTL Kd: the plastic's Ks is dropped.
DIFFUSE_ONLY = ("white_plastic",)


@dataclass(frozen=True)
class Material:
    kd: tuple[float, float, float]
    ke: tuple[float, float, float]


def materials() -> dict[str, Material]:
    """cornell.mtl's Kd and Ke per material."""
    found, name, values = {}, None, {}
    for line in [*MTL.read_text().splitlines(), "newmtl"]:
        words = line.split()
        if not words or words[0].startswith("#"):
            continue
        if words[0] == "newmtl":
            if name is not None:
                found[name] = Material(values["Kd"], values.get("Ke", (0.0, 0.0, 0.0)))
            name, values = (words[1] if len(words) > 1 else None), {}
        elif words[0] in ("Kd", "Ke"):
            values[words[0]] = tuple(float(v) for v in words[1:4])
    return found


def sturmray_toml(seed: int) -> str:
    """sturmray's scene, with an absolute path to the OBJ."""
    plastic = materials()["white_plastic"].kd
    overrides = "".join(
        f'\n[materials.{name}]\ntype = "diffuse"\nalbedo = {list(plastic)}\n'
        for name in DIFFUSE_ONLY
    )
    return (
        "background = [0.0, 0.0, 0.0]\n\n[camera]\n"
        f"eye = {list(EYE)}\nlook_at = {list(LOOK_AT)}\nup = {list(UP)}\n"
        f"fov = {FOV}\nwidth = {SIZE}\nheight = {SIZE}\n\n[render]\n"
        f'spp = 1\nmax_depth = {STURMRAY_MAX_DEPTH}\nseed = {seed}\nintegrator = "path"\n'
        f'filter = "box"\n{overrides}\n[[objects]]\ntype = "mesh"\nfile = "{OBJ}"\n'
    )


def read_obj() -> tuple[list[list[str]], dict[str, dict]]:
    """cornell.obj's vertices (as written) and its objects: name -> faces
    (1-based vertex indices) and material."""
    vertices, objects, current = [], {}, None
    for line in OBJ.read_text().splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            vertices.append(words[1:4])
        elif words[0] == "o":
            current = objects.setdefault(words[1], {"faces": [], "material": None})
        elif words[0] == "usemtl":
            current["material"] = words[1]
        elif words[0] == "f":
            current["faces"].append([int(w.split("/")[0]) for w in words[1:]])
    return vertices, objects


def split_obj(folder: Path) -> dict[str, tuple[Path, str]]:
    """One OBJ per `o` object of cornell.obj in `folder`: name -> (file, material)."""
    vertices, objects = read_obj()
    out = {}
    for name, obj in objects.items():
        used = sorted({i for face in obj["faces"] for i in face})
        index = {old: new for new, old in enumerate(used, start=1)}
        lines = [f"v {' '.join(vertices[i - 1])}" for i in used]
        lines += ["f " + " ".join(str(index[i]) for i in face) for face in obj["faces"]]
        path = folder / f"{name}.obj"
        path.write_text("\n".join(lines) + "\n")
        out[name] = (path, obj["material"])
    return out


def mitsuba_scene(mi, parts: dict[str, tuple[Path, str]], sampler: str, spp: int) -> dict:
    """Mitsuba's scene dict: the same camera, box filter, depth and materials."""
    mats = materials()
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": MITSUBA_MAX_DEPTH},
        "sensor": {
            "type": "perspective",
            "fov": FOV,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=EYE, target=LOOK_AT, up=UP),
            "film": {
                "type": "hdrfilm",
                "width": SIZE,
                "height": SIZE,
                "pixel_format": "rgb",
                "rfilter": {"type": "box"},
            },
            "sampler": {"type": sampler, "sample_count": spp},
        },
    }
    for name, (path, material) in parts.items():
        m = mats[material]
        shape = {
            "type": "obj",
            "filename": str(path),
            "face_normals": True,
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(m.kd)}},
        }
        if max(m.ke) > 0:
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": list(m.ke)}}
        scene[name] = shape
    return scene


def away_from_light(margin: int = SIZE // 8) -> np.ndarray:
    """True on pixels more than `margin` pixels from the light panel's image
    (its corners projected through the camera, as a box)."""
    vertices, objects = read_obj()
    light = {i for face in objects["light"]["faces"] for i in face}
    corners = np.array([[float(w) for w in vertices[i - 1]] for i in sorted(light)])
    eye, forward = np.array(EYE), np.array(LOOK_AT) - np.array(EYE)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, UP)  # image x grows along forward × up
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    scale = np.tan(np.radians(FOV) / 2)
    d = corners - eye
    x = SIZE / 2 * (1 + (d @ right) / (d @ forward) / scale)
    y = SIZE / 2 * (1 - (d @ up) / (d @ forward) / scale)
    mask = np.ones((SIZE, SIZE), dtype=bool)
    x0, x1 = int(max(x.min() - margin, 0)), int(min(x.max() + margin + 1, SIZE))
    y0, y1 = int(max(y.min() - margin, 0)), int(min(y.max() + margin + 1, SIZE))
    mask[y0:y1, x0:x1] = False
    return mask
