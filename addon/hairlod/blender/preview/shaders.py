"""Loads the GLSL sources of shaders/ and builds GPU shaders from create-info descriptions."""

import os

_SHADER_DIR = os.path.join(os.path.dirname(__file__), "shaders")


def glsl_source(*names):
    """The text of shaders/<name> for each name, concatenated in order (libraries before main)."""
    parts = []
    for name in names:
        with open(os.path.join(_SHADER_DIR, name), encoding="utf-8") as f:
            parts.append(f.read())
    return "\n".join(parts)
