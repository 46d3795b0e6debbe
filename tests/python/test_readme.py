"""README.md's Python example, run as written (a doctest of sorts): if the
API it shows changes, this fails rather than the README going stale."""

from __future__ import annotations

import re

import numpy as np
from conftest import REPO


def readme_example() -> str:
    """The first ```python block of README.md's "From Python" section."""
    text = (REPO / "README.md").read_text()
    section = text.split("\n## From Python\n", 1)[1].split("\n## ", 1)[0]
    found = re.search(r"```python\n(.*?)```", section, re.S)
    assert found, "README.md's From Python section has no ```python block"
    return found[1]


def test_readme_example_runs_and_hits_the_mesh_and_the_torus(monkeypatch):
    monkeypatch.chdir(REPO)  # its paths are the repository's
    names: dict = {}
    exec(compile(readme_example(), "README.md", "exec"), names)  # noqa: S102
    hits, every, scene = names["hits"], names["every"], names["scene"]
    n = len(names["o"])
    assert hits["t"].shape == (n,)
    # Rays from the box's points toward its centre: the knot (geom_id 0) and
    # the torus (the shapes' geom_id) are both hit, some rays miss.
    hit_ids = set(np.unique(hits["geom_id"]).tolist())
    assert {0, scene.shapes_geom_id} <= hit_ids
    assert np.isinf(hits["t"]).any()
    # The nearest of every hit is the nearest hit.
    first = every["offsets"][:-1]
    has = np.diff(every["offsets"]) > 0
    np.testing.assert_array_equal(every["t"][first[has]], hits["t"][has])
    # The drop-in line runs and answers as trimesh's interface does.
    mesh = names["mesh"]
    assert mesh.ray.intersects_any(names["o"][:100], -names["o"][:100]).shape == (100,)
