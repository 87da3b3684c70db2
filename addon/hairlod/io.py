"""Hair files: read and write Strands.

Formats are chosen by extension (case-insensitive):

======  ===========================================  ============
.hair   Cem Yuksel's HAIR (thickness, transparency,   read, write
        colour)
.data   USC-HairSalon                                 read, write
.bin    CT2Hair                                       read
.ply    PLY hair (vertex + strand nsegs), ascii or    read
        binary
.tfx    AMD TressFX                                   read
======  ===========================================  ============

Bad files raise ValueError (``hairlod.HairlodError``) with a message that names the file and the
problem; writing goes to a temporary file renamed when complete, so no partial file is left.
"""

import os

from . import _core, atomic_output
from ._core import Strands

READ_FORMATS = dict(_core.hair_read_formats())
WRITE_FORMATS = dict(_core.hair_write_formats())

__all__ = ["READ_FORMATS", "WRITE_FORMATS", "read", "write"]


def _checked(path):
    """The path as a string; ValueError for one no file system accepts (the bindings would raise
    TypeError)."""
    path = os.fspath(path)
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if "\0" in path:
        raise ValueError(f"{path!r}: a path cannot contain a NUL character")
    return path


def read(path, *, default_radius=None) -> Strands:
    """Reads a hair file into Strands.

    ``default_radius`` is used by formats that store no thickness (.data, .bin, .ply, .tfx); when
    None it is 1e-4 times the diagonal of the strands' bounding box.
    """
    return _core.read_hair_file(_checked(path), default_radius)


def write(path, strands: Strands) -> None:
    """Writes Strands to a .hair or .data file (atomically: the C++ writer renames a finished
    temporary file, named as atomic_output names them, over `path`)."""
    path = _checked(path)
    atomic_output.begin_writing(path)
    with atomic_output.installing():
        _core.write_hair_file(path, strands)
        atomic_output.completed(path)
