"""The preview's GLSL names nothing that Blender 5 defines away: its shader sources start with
`#define constant`, `device`, `thread`, `threadgroup` and `static` (empty: Metal's address spaces and
storage), so a variable or struct member of one of those names stops compiling there, and the whole
preview with it (a uniform block member named `constant` did, in Blender 5.2). Checked on the .glsl
files and on the GLSL the Python modules of the preview hold in strings."""

import pathlib
import re

PREVIEW = pathlib.Path(__file__).resolve().parents[2] / "addon" / "hairlod" / "blender" / "preview"
DEFINED_AWAY = ("constant", "device", "thread", "threadgroup", "static")


def code_of(glsl):
    """GLSL without its comments."""
    return re.sub(r"//[^\n]*", "", re.sub(r"/\*.*?\*/", "", glsl, flags=re.S))


def embedded_glsl(python):
    """The triple-quoted strings of a Python module that hold GLSL (a struct, a function or a #define)."""
    strings = re.findall(r'f?"""(.*?)"""', python, flags=re.S)
    return [s for s in strings if re.search(r"\bstruct\b|\bvoid\b|#define|\bvec[234]\b", s)]


def names_defined_away(glsl):
    return sorted({word for word in re.findall(r"\b[A-Za-z_]\w*\b", code_of(glsl)) if word in DEFINED_AWAY})


def test_the_checks_find_such_a_name():
    assert names_defined_away("struct HairWorld { vec4 constant; };") == ["constant"]
    assert names_defined_away("/* constant */ float x; // static\n") == []
    assert embedded_glsl('X = """\nstruct A {\n  vec4 device;\n};\n"""\nY = """not glsl"""') == ["\nstruct A {\n  vec4 device;\n};\n"]


def test_the_preview_glsl_names_nothing_blender_5_defines_away():
    sources = {path.name: path.read_text() for path in (PREVIEW / "shaders").glob("*.glsl")}
    assert len(sources) > 10
    for path in PREVIEW.glob("*.py"):
        for k, glsl in enumerate(embedded_glsl(path.read_text())):
            sources[f"{path.name} string {k}"] = glsl
    assert any("struct HairWorld" in glsl for glsl in sources.values())  # world_srbf.WORLD_BLOCK among them
    found = {name: names_defined_away(glsl) for name, glsl in sources.items()}
    assert {name: words for name, words in found.items() if words} == {}
