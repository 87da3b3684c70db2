"""hairlod.png: PNG files written with zlib only, read back by an independent decoder."""

import struct
import zlib

import numpy as np
import pytest

from hairlod import png


def decode(data):
    """Minimal reader for what encode_png writes (8-bit, filter 0), checking every CRC."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    at, chunks = 8, {}
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + length]
        (crc,) = struct.unpack(">I", data[at + 8 + length:at + 12 + length])
        assert crc == zlib.crc32(kind + body), kind
        chunks[kind] = chunks.get(kind, b"") + body
        at += 12 + length
    width, height, depth, colour, _, _, _ = struct.unpack(">IIBBBBB", chunks[b"IHDR"])
    channels = {2: 3, 6: 4}[colour]
    assert depth == 8 and b"IEND" in chunks
    rows = np.frombuffer(zlib.decompress(chunks[b"IDAT"]), np.uint8).reshape(height, 1 + width * channels)
    assert np.all(rows[:, 0] == 0)
    return rows[:, 1:].reshape(height, width, channels)


@pytest.mark.parametrize("channels", [3, 4])
def test_round_trip(channels):
    pixels = np.random.default_rng(5).integers(0, 256, (7, 13, channels), dtype=np.uint8)
    np.testing.assert_array_equal(decode(png.encode_png(pixels)), pixels)


def test_matplotlib_reads_it_the_same(tmp_path):
    image = pytest.importorskip("matplotlib.image")
    pixels = np.random.default_rng(6).integers(0, 256, (5, 9, 3), dtype=np.uint8)
    path = tmp_path / "x.png"
    path.write_bytes(png.encode_png(pixels))
    np.testing.assert_array_equal(np.round(image.imread(str(path)) * 255).astype(np.uint8), pixels)


@pytest.mark.parametrize("bad", [np.zeros((4, 4, 3), np.float32), np.zeros((4, 4), np.uint8),
                                 np.zeros((4, 4, 2), np.uint8), np.zeros((0, 4, 3), np.uint8)])
def test_rejects_what_it_cannot_write(bad):
    with pytest.raises(ValueError, match="PNG"):
        png.encode_png(bad)
