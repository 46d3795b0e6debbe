"""The noise of renders against a reference: for each image, its samples per
pixel (the `sturmray.spp` attribute) and the RMSE of its RGB against the
reference's, one line each:

    noise.py REFERENCE IMAGE...   ->   IMAGE spp RMSE

tools/farm/test_cluster.sh uses it to check that parts rendered with other
seeds add up to an image as noisy as one render with all their samples.
"""

from __future__ import annotations

import sys

import numpy as np
import OpenEXR


def read(path: str) -> tuple[str, np.ndarray]:
    with OpenEXR.File(path) as f:
        spp = f.header().get("sturmray.spp", "?")
        rgb = f.channels()["RGB"].pixels.astype(np.float64)
    return str(spp), rgb


def main() -> None:
    if len(sys.argv) < 3:
        sys.exit("usage: noise.py REFERENCE IMAGE...")
    _, reference = read(sys.argv[1])
    for path in sys.argv[2:]:
        spp, rgb = read(path)
        if rgb.shape != reference.shape:
            sys.exit(f"{path}: {rgb.shape} pixels, the reference has {reference.shape}")
        print(path, spp, np.sqrt(np.mean((rgb - reference) ** 2)))


if __name__ == "__main__":
    main()
