"""8-bit RGB / RGBA PNG files from numpy arrays, with the standard library only (zlib): the CLI's
and the pipeline's images need no imaging package, which Blender's own Python does not ship.

Layout from the PNG specification (ISO/IEC 15948, W3C PNG 2nd edition): signature, IHDR, one IDAT
of filter-0 scanlines, IEND; every chunk closed by the CRC-32 of its type and data.
"""

import struct
import zlib

import numpy as np

__all__ = ["encode_png"]

_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_COLOUR_TYPES = {3: 2, 4: 6}  # channels -> PNG colour type (2 truecolour, 6 truecolour with alpha)


def _chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def encode_png(pixels):
    """The PNG file of `pixels`, uint8 [height, width, 3 or 4], rows top to bottom."""
    pixels = np.asarray(pixels)
    if pixels.dtype != np.uint8 or pixels.ndim != 3 or pixels.shape[2] not in _COLOUR_TYPES:
        raise ValueError(f"PNG pixels must be uint8 [height, width, 3 or 4], not {pixels.dtype} {pixels.shape}")
    height, width, channels = pixels.shape
    if height == 0 or width == 0:
        raise ValueError(f"PNG image is empty ({width} x {height})")
    # Each scanline starts with its filter type: 0 (none); zlib does the compressing.
    scanlines = np.zeros((height, 1 + width * channels), np.uint8)
    scanlines[:, 1:] = pixels.reshape(height, width * channels)
    header = struct.pack(">IIBBBBB", width, height, 8, _COLOUR_TYPES[channels], 0, 0, 0)
    return (_SIGNATURE + _chunk(b"IHDR", header) + _chunk(b"IDAT", zlib.compress(scanlines.tobytes(), 6))
            + _chunk(b"IEND", b""))
