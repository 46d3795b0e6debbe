"""Type stubs of the extension module (python/src/*.rs)."""

from os import PathLike
from typing import Literal, Optional, Sequence, Tuple, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
INVALID_ID: int
"""geom_id and prim_id of a miss (4294967295)."""

_Vec3 = Tuple[float, float, float]
_Box = Tuple[_Vec3, _Vec3]
_PerRay = Union[float, npt.ArrayLike]

class Hits(TypedDict):
    t: npt.NDArray[np.float32]
    geom_id: npt.NDArray[np.uint32]
    prim_id: npt.NDArray[np.uint32]
    inst_id: npt.NDArray[np.uint32]
    u: npt.NDArray[np.float32]
    v: npt.NDArray[np.float32]
    ng: npt.NDArray[np.float32]

class AllHits(Hits):
    offsets: npt.NDArray[np.int64]

class Aovs(TypedDict):
    depth: npt.NDArray[np.float32]
    normal: npt.NDArray[np.float32]
    albedo: npt.NDArray[np.float32]

class Roots(TypedDict):
    roots: list[float]
    count: int
    multiplicity: list[int]
    bound: list[float]
    found_by: str

_Backend = Literal["embree", "obvhs", "bvh", "rust-bvh"]

class Scene:
    """A scene and its BVH: loaded from a file, or built in code and committed."""

    def __init__(
        self, toml: Optional[str] = None, backend: _Backend = "embree", threads: Optional[int] = None
    ) -> None: ...
    @staticmethod
    def load(
        path: Union[str, PathLike[str]],
        width: Optional[int] = None,
        height: Optional[int] = None,
        backend: _Backend = "embree",
        threads: Optional[int] = None,
        pov_include: Sequence[Union[str, PathLike[str]]] = (),
    ) -> "Scene": ...
    def add_mesh(
        self, vertices: npt.ArrayLike, faces: npt.ArrayLike, material: Optional[str] = None
    ) -> int: ...
    def add_sphere(
        self, radius: float, center: _Vec3 = (0.0, 0.0, 0.0), material: Optional[str] = None
    ) -> int: ...
    def add_torus(
        self,
        major: float,
        minor: float,
        center: _Vec3 = (0.0, 0.0, 0.0),
        rotate: _Vec3 = (0.0, 0.0, 0.0),
        material: Optional[str] = None,
    ) -> int: ...
    def add_quadric(
        self,
        a: Tuple[_Vec3, _Vec3, _Vec3],
        b: _Vec3,
        c: float,
        clip: _Box,
        material: Optional[str] = None,
    ) -> int: ...
    def add_algebraic(
        self,
        expr: str,
        clip: _Box,
        constants: Optional[Sequence[Tuple[str, float]]] = None,
        material: Optional[str] = None,
    ) -> int: ...
    def commit(self) -> None: ...
    def intersect(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tnear: Optional[_PerRay] = None,
        tfar: Optional[_PerRay] = None,
    ) -> Hits: ...
    def occluded(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tnear: Optional[_PerRay] = None,
        tfar: Optional[_PerRay] = None,
    ) -> npt.NDArray[np.bool_]: ...
    def intersect_all(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tnear: Optional[_PerRay] = None,
        tfar: Optional[_PerRay] = None,
        max_hits: Optional[int] = None,
    ) -> AllHits: ...
    @overload
    def render(
        self,
        spp: Optional[int] = None,
        integrator: Optional[Literal["whitted", "path"]] = None,
        aovs: Literal[False] = False,
    ) -> npt.NDArray[np.float32]: ...
    @overload
    def render(
        self,
        spp: Optional[int] = None,
        integrator: Optional[Literal["whitted", "path"]] = None,
        aovs: Literal[True] = ...,
    ) -> Tuple[npt.NDArray[np.float32], Aovs]: ...
    @property
    def size(self) -> Tuple[int, int]: ...
    @property
    def shapes_geom_id(self) -> int: ...
    @property
    def backend(self) -> str: ...
    @property
    def warnings(self) -> list[str]: ...

def roots(
    coeffs: Sequence[float],
    interval: Optional[Tuple[float, float]] = None,
    method: Optional[str] = None,
    tolerance: Optional[float] = None,
) -> Roots: ...
