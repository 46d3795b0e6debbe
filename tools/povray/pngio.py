"""8-bit RGB PNG reading and writing with the standard library and numpy.

The comparison reads the PNGs both renderers write (POV-Ray's through
libpng, sturmray's through the `png` crate) and writes side-by-side images.
Pillow would do it, but the Python cross-checks pin only numpy, pytest and
their dependencies; a PNG of 8-bit RGB is small enough to decode here:
zlib, then the five row filters of the PNG specification (section 9).
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np

SIGNATURE = b"\x89PNG\r\n\x1a\n"
# Colour type -> channels per pixel, for the 8-bit types we accept:
# 2 is RGB, 6 is RGBA (its alpha is dropped: neither renderer is asked for one).
CHANNELS = {2: 3, 6: 4}


def read_png(path: Path) -> np.ndarray:
    """The image as an (height, width, 3) uint8 array, row 0 at the top."""
    data = Path(path).read_bytes()
    if not data.startswith(SIGNATURE):
        raise ValueError(f"{path}: not a PNG file")
    pos, header, idat = len(SIGNATURE), None, []
    while pos + 8 <= len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if len(body) != length:
            raise ValueError(f"{path}: chunk {kind!r} is cut short")
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + length  # length, type, body, CRC
    if header is None:
        raise ValueError(f"{path}: no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in CHANNELS or interlace != 0:
        raise ValueError(
            f"{path}: only 8-bit RGB or RGBA without interlacing is read "
            f"(found depth {depth}, colour type {colour}, interlace {interlace})"
        )
    bpp = CHANNELS[colour]
    stride = width * bpp
    raw = zlib.decompress(b"".join(idat))
    if len(raw) != height * (stride + 1):
        expected = height * (stride + 1)
        raise ValueError(f"{path}: {len(raw)} bytes of pixel data, expected {expected}")
    rows = np.frombuffer(raw, dtype=np.uint8).reshape(height, stride + 1)
    image = np.zeros((height, stride), dtype=np.uint8)
    prior = np.zeros(stride, dtype=np.uint8)
    for y in range(height):
        image[y] = unfilter(int(rows[y, 0]), rows[y, 1:], prior, bpp, path)
        prior = image[y]
    return image.reshape(height, width, bpp)[:, :, :3]


def unfilter(kind: int, line: np.ndarray, prior: np.ndarray, bpp: int, path) -> np.ndarray:
    """One row's bytes with its filter undone (PNG specification, 9.2)."""
    if kind == 0:
        return line
    if kind == 1:  # Sub: a running sum along the row, per channel, mod 256
        sums = np.cumsum(line.reshape(-1, bpp).astype(np.uint32), axis=0)
        return (sums % 256).astype(np.uint8).reshape(-1)
    if kind == 2:  # Up
        return line + prior  # uint8 arithmetic wraps mod 256, as the filter does
    if kind not in (3, 4):
        raise ValueError(f"{path}: unknown row filter {kind}")
    # Average and Paeth depend on the byte just rebuilt to their left, so they
    # run byte by byte (on Python ints: numpy's per-element overhead is larger).
    x, b, out = line.tolist(), prior.tolist(), bytearray(len(line))
    for i, xi in enumerate(x):
        a = out[i - bpp] if i >= bpp else 0
        if kind == 3:
            out[i] = (xi + ((a + b[i]) >> 1)) & 0xFF
            continue
        c = b[i - bpp] if i >= bpp else 0
        p = a + b[i] - c
        pa, pb, pc = abs(p - a), abs(p - b[i]), abs(p - c)
        if pa <= pb and pa <= pc:
            predictor = a
        elif pb <= pc:
            predictor = b[i]
        else:
            predictor = c
        out[i] = (xi + predictor) & 0xFF
    return np.frombuffer(bytes(out), dtype=np.uint8)


def write_png(path: Path, image: np.ndarray) -> None:
    """Writes an (height, width, 3) uint8 array as an sRGB PNG (no row filter)."""
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(
            f"expected a (height, width, 3) uint8 image, got {image.dtype} {image.shape}"
        )
    height, width, _ = image.shape
    rows = np.zeros((height, width * 3 + 1), dtype=np.uint8)  # filter byte 0 first
    rows[:, 1:] = image.reshape(height, -1)

    def chunk(kind: bytes, body: bytes) -> bytes:
        crc = zlib.crc32(kind + body) & 0xFFFFFFFF
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", crc)

    Path(path).write_bytes(
        SIGNATURE
        + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
        + chunk(b"sRGB", b"\x00")  # perceptual intent, as sturmray's previews
        + chunk(b"IDAT", zlib.compress(rows.tobytes(), 9))
        + chunk(b"IEND", b"")
    )
