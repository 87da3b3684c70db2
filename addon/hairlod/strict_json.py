"""Strict, bounded JSON in and out.

Every JSON file hairlod reads (hair meshes, LoD manifests, cameras, BCSDF parameters, packed
headers) goes through load() / loads(), which turn every way a file can be bad into one ValueError
naming the file: not UTF-8, not JSON, nested deeper than MAX_DEPTH, an integer of more than
MAX_INTEGER_DIGITS digits, a number that overflows a double, NaN or Infinity (not JSON). Everything
hairlod writes goes through dumps() / dump(), which refuse non-finite numbers instead of writing
the non-standard `Infinity` / `NaN` that strict readers reject.
"""

import json
import math
import os
import stat

__all__ = ["MAX_DEPTH", "MAX_FILE_BYTES", "MAX_INTEGER_DIGITS", "dump", "dumps", "load", "loads"]

# Deeper than any file hairlod writes (a manifest is 5 levels deep), far below Python's recursion limit.
MAX_DEPTH = 64
# int64 has 19 digits: larger integers are never valid counts or indices.
MAX_INTEGER_DIGITS = 19
# Far above the largest file hairlod writes (a 100k-vertex hair mesh is about 10 MB).
MAX_FILE_BYTES = 1 << 30


class _Refused(Exception):
    pass


def _integer(text):
    if len(text.lstrip("-")) > MAX_INTEGER_DIGITS:
        raise _Refused(f"integer {text[:24]}{'...' if len(text) > 24 else ''} is too large")
    return int(text)


def _number(text):
    value = float(text)
    if not math.isfinite(value):
        raise _Refused(f"number {text[:24]} is out of range")
    return value


def _constant(text):
    raise _Refused(f"{text} is not a JSON number")


def _nesting_depth(text):
    """Deepest bracket nesting of JSON text, skipping strings (linear, no recursion)."""
    depth = deepest = 0
    in_string = escaped = False
    for character in text:
        if in_string:
            if escaped:
                escaped = False
            elif character == "\\":
                escaped = True
            elif character == '"':
                in_string = False
        elif character == '"':
            in_string = True
        elif character in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif character in "]}":
            depth -= 1
    return deepest


def loads(text, where):
    """Parses JSON text; ValueError("{where}: ...") for anything not strict, bounded JSON."""
    if isinstance(text, (bytes, bytearray)):
        try:
            text = bytes(text).decode("utf-8")
        except UnicodeDecodeError:
            raise ValueError(f"{where}: not UTF-8 text") from None
    # The bracket scan runs in Python: only text with that many brackets at all is scanned.
    if text.count("[") + text.count("{") > MAX_DEPTH and _nesting_depth(text) > MAX_DEPTH:
        raise ValueError(f"{where}: JSON nested more than {MAX_DEPTH} levels deep")
    try:
        return json.loads(text, parse_int=_integer, parse_float=_number, parse_constant=_constant)
    except _Refused as error:
        raise ValueError(f"{where}: {error}") from None
    except json.JSONDecodeError as error:
        raise ValueError(f"{where}: not valid JSON ({error.msg} at line {error.lineno} column {error.colno})") from None
    except (RecursionError, ValueError) as error:
        raise ValueError(f"{where}: not valid JSON ({error})") from None


def load(path, what=None):
    """Reads and parses a JSON file; ValueError naming `path` (and `what` it is) on any problem,
    including an unreadable file, one that is not a regular file (a FIFO or /dev/zero would never
    end) and one larger than MAX_FILE_BYTES."""
    where = f"{path} ({what})" if what else str(path)
    try:
        # O_NONBLOCK: opening a FIFO would otherwise wait for a writer (no effect on regular files).
        with os.fdopen(os.open(path, os.O_RDONLY | os.O_NONBLOCK), "rb") as stream:
            if not stat.S_ISREG(os.fstat(stream.fileno()).st_mode):
                raise ValueError(f"{where}: not a regular file")
            data = stream.read(MAX_FILE_BYTES + 1)
    except OSError as error:
        raise ValueError(f"{where}: cannot read ({error.strerror or error})") from None
    if len(data) > MAX_FILE_BYTES:
        raise ValueError(f"{where}: larger than {MAX_FILE_BYTES >> 20} MB, more than any JSON file hairlod reads")
    return loads(data, where)


def dumps(value, **options):
    """json.dumps that refuses NaN and Infinity (ValueError) instead of writing non-standard JSON."""
    return json.dumps(value, allow_nan=False, **options)


def dump(value, stream, **options):
    json.dump(value, stream, allow_nan=False, **options)
