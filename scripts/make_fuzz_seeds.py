#!/usr/bin/env python3
"""Writes seed corpora for the libFuzzer targets into fuzz-corpus/<target>/ (git-ignored).

Seeds are small synthetic files of each format plus the hairutil test files from ../shared/data
when that folder exists. Usage: scripts/make_fuzz_seeds.py [repo root]
"""

import pathlib
import shutil
import struct
import sys


def cyhair(counts, flags=0b11111, info=b"seed"):
    points = sum(counts)
    header = b"HAIR" + struct.pack("<IIII ff 3f", len(counts), points, flags, counts[0] - 1,
                                   1.0, 0.0, 1.0, 1.0, 1.0)
    body = b""
    if flags & 1:
        body += b"".join(struct.pack("<H", c - 1) for c in counts)
    body += b"".join(struct.pack("<3f", i, -i, 0.5 * i) for i in range(points))
    for bit, floats in ((4, 1), (8, 1), (16, 3)):
        if flags & bit:
            body += struct.pack(f"<{floats * points}f", *[0.25] * (floats * points))
    return header + info.ljust(88, b"\0") + body


def strand_list(counts, floats_per_point):
    out = struct.pack("<i", len(counts))
    for n in counts:
        out += struct.pack("<i", n)
        out += b"".join(struct.pack(f"<{floats_per_point}f", *([float(i)] * floats_per_point))
                        for i in range(n))
    return out


def ply(fmt, endian="<"):
    header = (f"ply\nformat {fmt} 1.0\ncomment seed\nelement vertex 5\nproperty float x\n"
              "property double y\nproperty short z\nproperty uchar red\nproperty uchar green\n"
              "property uchar blue\nproperty float thickness\nproperty list uchar int extra\n"
              "element strand 2\nproperty ushort nsegs\nelement edge 1\nproperty int vertex1\n"
              "property int vertex2\nend_header\n").encode()
    rows = [(i, 0.5 * i, -i, 10 * i, 20, 30, 0.1, [i, i + 1] if i % 2 else []) for i in range(5)]
    if fmt == "ascii":
        body = "".join(" ".join(map(str, r[:7])) + " " + " ".join(map(str, [len(r[7])] + r[7])) + "\n"
                       for r in rows) + "1\n2\n0 1\n"
        return header + body.encode()
    body = b""
    for x, y, z, red, green, blue, thickness, extra in rows:
        body += struct.pack(endian + "fdhBBBfB", x, y, z, red, green, blue, thickness, len(extra))
        body += struct.pack(endian + f"{len(extra)}i", *extra)
    body += struct.pack(endian + "HH", 1, 2) + struct.pack(endian + "ii", 0, 1)
    return header + body


def tfx(strands, vertices, position_offset=160):
    header = struct.pack("<fIIIIIII", 4.0, strands, vertices, position_offset, 0, 0, 0, 0)
    header = header.ljust(position_offset, b"\0")
    return header + b"".join(struct.pack("<4f", i, -i, 2 * i, 1.0)
                             for i in range(strands * vertices))


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    corpus = root / "fuzz-corpus"
    shared = root.parent / "shared" / "data" / "hairutil"
    seeds = {
        "cyhair": {"all_arrays.hair": cyhair([2, 3, 4]), "uniform.hair": cyhair([3, 3], 0b10),
                   "thickness.hair": cyhair([2, 5], 0b111), "empty.hair": cyhair([1], 0b10)[:128]},
        "usc_data": {"small.data": strand_list([2, 0, 3, 1], 3), "empty.data": strand_list([], 3)},
        "ct2hair_bin": {"small.bin": strand_list([3, 1, 2], 7)},
        "ply_hair": {"ascii.ply": ply("ascii"), "le.ply": ply("binary_little_endian"),
                     "be.ply": ply("binary_big_endian", ">")},
        "tfx": {"small.tfx": tfx(2, 3), "offset.tfx": tfx(1, 4, 192)},
    }
    shared_files = {"cyhair": ["Bangs_100.hair"], "usc_data": ["Bangs_100.data"],
                    "ct2hair_bin": ["Bangs_20.bin"],
                    "ply_hair": ["Bangs_100_ascii.ply", "Bangs_100_binary.ply", "Curly_100.ply"]}
    for target, files in seeds.items():
        directory = corpus / target
        directory.mkdir(parents=True, exist_ok=True)
        for name, data in files.items():
            (directory / ("seed_" + name)).write_bytes(data)
        for name in shared_files.get(target, []):
            if (shared / name).exists():
                shutil.copyfile(shared / name, directory / ("seed_" + name))
        print(f"{directory}: {len(list(directory.iterdir()))} files")


if __name__ == "__main__":
    main()
