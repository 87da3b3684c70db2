"""The memory a single command may plan to use, checked before anything large is allocated.

Commands estimate the bytes their arguments and input imply (strands x vertices, control points,
table sizes) and call check() first, so an argument such as `generate --count 100000000` is refused
at once with a message naming it, instead of running for minutes while memory grows.

The budget is DEFAULT_FRACTION of physical memory; the environment variable HAIRLOD_MEMORY_BUDGET
sets it in bytes, with an optional K, M, G or T suffix (powers of 1024), e.g. HAIRLOD_MEMORY_BUDGET=64G.
"""

import os

__all__ = ["DEFAULT_FRACTION", "ENVIRONMENT_VARIABLE", "MemoryBudgetError", "budget_bytes", "check", "format_bytes"]

DEFAULT_FRACTION = 0.5
ENVIRONMENT_VARIABLE = "HAIRLOD_MEMORY_BUDGET"
_SUFFIXES = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}


class MemoryBudgetError(ValueError):
    """A request larger than the memory budget (a ValueError: bad input)."""


def _physical_bytes():
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 8 << 30  # unknown: assume a small machine


def budget_bytes():
    """The budget in bytes: HAIRLOD_MEMORY_BUDGET when set, else DEFAULT_FRACTION of physical memory."""
    text = os.environ.get(ENVIRONMENT_VARIABLE, "").strip().upper().removesuffix("B")
    if not text:
        return int(DEFAULT_FRACTION * _physical_bytes())
    number, suffix = (text[:-1], text[-1]) if text[-1] in _SUFFIXES else (text, "")
    try:
        value = float(number) * _SUFFIXES[suffix]
    except ValueError:
        value = float("nan")
    if not value > 0 or value == float("inf"):
        raise MemoryBudgetError(f"{ENVIRONMENT_VARIABLE}={os.environ[ENVIRONMENT_VARIABLE]!r}: expected a size in "
                                "bytes such as 8000000000, 512M or 16G")
    return int(value)


def format_bytes(count):
    for unit, size in (("TB", 1 << 40), ("GB", 1 << 30), ("MB", 1 << 20), ("KB", 1 << 10)):
        if count >= size:
            return f"{count / size:.1f} {unit}"
    return f"{int(count)} bytes"


def check(estimated_bytes, what):
    """Raises MemoryBudgetError("{what} needs about N GB, more than the budget ...") when the
    estimate exceeds the budget."""
    budget = budget_bytes()
    if estimated_bytes > budget:
        raise MemoryBudgetError(f"{what} needs about {format_bytes(estimated_bytes)}, more than the memory budget "
                                f"of {format_bytes(budget)} (set {ENVIRONMENT_VARIABLE} to change it)")
