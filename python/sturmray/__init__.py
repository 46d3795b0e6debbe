"""sturmray from Python: scenes of triangle meshes and exact analytic
surfaces, traced and rendered in-process, numpy arrays in and out.

    import sturmray
    scene = sturmray.Scene.load("scenes/knot.toml")
    hits = scene.intersect(origins, directions)   # dict of numpy arrays

See docs/python.md. ``sturmray.trimesh.RayMeshIntersector`` is a ray engine
for trimesh.
"""

from ._sturmray import INVALID_ID, Scene, __version__, roots

__all__ = ["INVALID_ID", "Scene", "roots", "__version__"]
