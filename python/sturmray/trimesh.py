"""A ray engine for trimesh on sturmray's Embree path.

    import sturmray.trimesh
    mesh.ray = sturmray.trimesh.RayMeshIntersector(mesh)

Every query of trimesh's ray interface (``mesh.ray.intersects_*``,
``mesh.contains``) then traces through sturmray. It answers as trimesh's own
``trimesh.ray.ray_triangle.RayMeshIntersector`` does, including every hit at
a shared edge with ``multiple_hits=True``: one hit per location, as
trimesh's own gives (``Scene.intersect_all`` keeps both triangles), never a
location dropped, as engines that re-cast rays past each hit may.
"""

from __future__ import annotations

from typing import Any, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._sturmray import INVALID_ID, Scene

__all__ = ["RayMeshIntersector"]


def _rays(origins: npt.ArrayLike, directions: npt.ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
    o = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    d = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    if len(o) != len(d):
        raise ValueError(f"ray_directions: expected {len(o)} rows, as ray_origins has, found {len(d)}")
    return o, d


class RayMeshIntersector:
    """trimesh's ray-intersector interface, traced by sturmray.

    The mesh is copied once (as float32 vertices, which is what Embree
    traces); a mesh changed afterwards needs a new intersector.
    ``backend`` is "embree" (default), "obvhs", "bvh" or "rust-bvh".
    """

    def __init__(self, mesh: Any, backend: str = "embree") -> None:
        self.mesh = mesh
        self._backend = backend
        self._scene = Scene(backend=backend)
        self._scene.add_mesh(mesh.vertices, mesh.faces)
        self._scene.commit()

    def intersects_id(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool = True,
        max_hits: Union[int, None] = None,
        return_locations: bool = False,
        **kwargs: Any,
    ):
        """Triangles hit by each ray: ``(index_tri, index_ray)``, plus the
        (h, 3) ``locations`` with ``return_locations``. With
        ``multiple_hits`` every hit of every ray (nearest first, at most
        ``max_hits`` a ray if given), else the nearest only."""
        o, d = _rays(ray_origins, ray_directions)
        if multiple_hits:
            hits = self._scene.intersect_all(o, d, max_hits=max_hits)
            index_ray = np.repeat(np.arange(len(o), dtype=np.int64), np.diff(hits["offsets"]))
            t = hits["t"]
            index_tri = hits["prim_id"].astype(np.int64)
            # One hit per location, as trimesh's own intersector reports: the
            # triangles that share an edge a ray crosses give one hit (the
            # lowest index). Scene.intersect_all keeps them all.
            keep = np.ones(len(t), dtype=bool)
            keep[1:] = (t[1:] != t[:-1]) | (index_ray[1:] != index_ray[:-1])
            index_ray, t, index_tri = index_ray[keep], t[keep], index_tri[keep]
        else:
            hits = self._scene.intersect(o, d)
            hit = hits["geom_id"] != INVALID_ID
            index_ray = np.nonzero(hit)[0].astype(np.int64)
            t = hits["t"][hit]
            index_tri = hits["prim_id"][hit].astype(np.int64)
        if return_locations:
            locations = o[index_ray] + t[:, None].astype(np.float64) * d[index_ray]
            return index_tri, index_ray, locations
        return index_tri, index_ray

    def intersects_location(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool = True,
        **kwargs: Any,
    ):
        """Where rays hit: ``(locations, index_ray, index_tri)``."""
        index_tri, index_ray, locations = self.intersects_id(
            ray_origins, ray_directions, multiple_hits=multiple_hits, return_locations=True, **kwargs
        )
        return locations, index_ray, index_tri

    def intersects_first(self, ray_origins: npt.ArrayLike, ray_directions: npt.ArrayLike, **kwargs: Any):
        """The nearest triangle each ray hits, -1 for a miss."""
        o, d = _rays(ray_origins, ray_directions)
        hits = self._scene.intersect(o, d)
        first = hits["prim_id"].astype(np.int64)
        first[hits["geom_id"] == INVALID_ID] = -1
        return first

    def intersects_any(self, ray_origins: npt.ArrayLike, ray_directions: npt.ArrayLike, **kwargs: Any):
        """Whether each ray hits anything (an occlusion query)."""
        o, d = _rays(ray_origins, ray_directions)
        return self._scene.occluded(o, d)

    def contains_points(self, points: npt.ArrayLike):
        """Whether each point is inside the (watertight) mesh, by trimesh's
        own ray-parity test run on this engine."""
        from trimesh.ray.ray_util import contains_points

        return contains_points(self, points)

    def __getstate__(self):
        return {"mesh": self.mesh, "backend": self._backend}

    def __setstate__(self, state) -> None:
        self.__init__(state["mesh"], state["backend"])

    def __copy__(self, *args: Any) -> "RayMeshIntersector":
        return RayMeshIntersector(self.mesh, self._backend)

    def __deepcopy__(self, *args: Any) -> "RayMeshIntersector":
        return self.__copy__()
