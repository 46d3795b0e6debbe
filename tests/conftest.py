"""Shared fixtures for the Python cross-checks of sturmray.

The tests run the CLI binary named by the environment variable STURMRAY_BIN
(the Makefile points it at the dev build, target/debug/sturmray). Without it
they use <repo>/target/debug/sturmray. A missing binary is a failure, never a
skip: a cross-check that silently does not run checks nothing.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "scenes"

# Generous: the slowest call (trace of ~200k rays against 70k triangles, or a
# small render) takes well under a second; this only stops a hung process.
DEFAULT_TIMEOUT_S = 120


def _find_binary() -> Path:
    env = os.environ.get("STURMRAY_BIN")
    if env:
        path = Path(env)
        if not path.is_absolute():
            # The Makefile may pass a path relative to the repo root; pytest may
            # run from elsewhere. Accept either the cwd or the repo root.
            path = path if path.exists() else REPO / path
        if not path.is_file():
            pytest.fail(
                f"STURMRAY_BIN={env!r} does not name an existing file "
                f"(looked at {path}); build it with `cargo build` in {REPO}",
                pytrace=False,
            )
        return path.resolve()
    path = REPO / "target" / "debug" / "sturmray"
    if not path.is_file():
        pytest.fail(
            f"sturmray binary not found: STURMRAY_BIN is unset and {path} does not "
            f"exist. Run `cargo build` in {REPO} (or `make test`), or set STURMRAY_BIN.",
            pytrace=False,
        )
    return path


@pytest.fixture(scope="session")
def sturmray_bin() -> Path:
    """Absolute path of the sturmray binary under test."""
    return _find_binary()


class SturmrayError(AssertionError):
    """sturmray exited with a nonzero status (message carries its stderr)."""

    def __init__(self, args: list[str], returncode: int, stdout: str, stderr: str):
        self.returncode = returncode
        self.stdout = stdout
        self.stderr = stderr
        super().__init__(
            f"sturmray exited with status {returncode}\n"
            f"command: {' '.join(map(str, args))}\n"
            f"--- stderr ---\n{stderr.strip()}\n"
            f"--- stdout ---\n{stdout.strip()}"
        )


def run_sturmray(
    binary: Path, *args: str | os.PathLike, timeout: float = DEFAULT_TIMEOUT_S
) -> subprocess.CompletedProcess:
    """Runs `sturmray ARGS...`; raises SturmrayError with stderr on a nonzero exit."""
    cmd = [str(binary), *map(str, args)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise SturmrayError(cmd, proc.returncode, proc.stdout, proc.stderr)
    return proc


@pytest.fixture(scope="session")
def sturmray(sturmray_bin):
    """`sturmray("render", scene, "-o", out)`: runs the CLI, raises on failure."""

    def run(*args, timeout: float = DEFAULT_TIMEOUT_S):
        return run_sturmray(sturmray_bin, *args, timeout=timeout)

    return run


def at_t(t, expected) -> np.ndarray:
    """Whether each float32 `t` is `expected` to within an ulp. Embree picks
    its kernels by the CPU at run time, and its t is not always the correctly
    rounded one: Embree 3.13.5 on an AMD EPYC with AVX2 and no AVX-512 gives
    0.99999994 for these tests' t = 1 (one ulp below), where other machines
    give 1 (as tests/maps.rs's `at` and src/accel/rust_bvh/tests.rs's
    `at_one`)."""
    t = np.asarray(t, np.float32)
    return np.abs(t - np.float32(expected)) <= np.abs(np.float32(expected)) * np.finfo(np.float32).eps
