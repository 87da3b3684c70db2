"""The imports of addon/hairlod point one way (issue 17).

1. Only hairlod.blender imports Blender's modules (bpy, gpu, ...) or hairlod.blender itself: the rest
   is a plain Python library and command line that runs without Blender.
2. hairlod's modules import each other without a cycle.
3. Inside hairlod.blender every module sits in a layer (LAYERS) and imports only its own layer or lower
   ones; the registration module (hairlod/blender/__init__.py) sits on top and may import anything.

The sources are read with `ast`, not imported (bpy is absent here), and every import counts, those
inside functions too: a function-level import is for loading Blender-only or heavy optional modules
late, and one that closed a cycle or pointed up a layer would be the same tangle, only deferred.
"""

import ast
from collections import namedtuple

from conftest import REPO

PACKAGE_DIR = REPO / "addon" / "hairlod"
PACKAGE = "hairlod"
BLENDER = "hairlod.blender"
# Built, not in the source tree (beside the sources after `make build`, or the hairlod_native wheel):
# `from . import _core` imports this module, not a name of the package.
COMPILED_MODULES = {"hairlod._core"}
# Modules that exist only inside Blender (top-level names), and hairlod's own Blender side.
BLENDER_MODULES = {"bpy", "bpy_extras", "bmesh", "gpu", "gpu_extras", "mathutils", "bgl", "blf", "aud", "imbuf",
                   "idprop", "bl_math", "bl_ui", "bl_operators", "addon_utils", "freestyle"}
# The add-on's entry point: Blender calls hairlod.register() / unregister(), which import
# hairlod.blender inside those functions, so that `import hairlod` never needs bpy.
ENTRY_POINT = (PACKAGE, BLENDER, {"register", "unregister"})

# The layers of hairlod.blender, lowest first. A module imports its own layer or lower ones.
SETTINGS = 0   # property declarations, nothing Blender has to call back into
BRIDGES = 1    # Blender data <-> hairlod's data (Curves, hair meshes, hair materials, packed assets)
JOBS = 2       # work on Blender data with no UI: the LoD build, the headless pipeline (build, export)
PREVIEWS = 3   # what draws or regenerates in the viewport: draw and depsgraph handlers, GPU batches
UI = 4         # operators, panels, and the property groups whose update callbacks drive the previews
LAYER_NAMES = {SETTINGS: "settings", BRIDGES: "bridges", JOBS: "jobs", PREVIEWS: "previews", UI: "UI"}
# Every module of hairlod.blender but the registration module: a new one fails test_every_blender_module
# _has_a_layer until it is placed here.
LAYERS = {
    "hairlod.blender.strand_settings": SETTINGS,
    "hairlod.blender.lod_build_settings": SETTINGS,

    "hairlod.blender.curves": BRIDGES,
    "hairlod.blender.surface": BRIDGES,
    "hairlod.blender.hair_mesh": BRIDGES,
    "hairlod.blender.principled_hair": BRIDGES,
    "hairlod.blender.packed_asset": BRIDGES,
    "hairlod.blender.versions": BRIDGES,

    "hairlod.blender.lod_build_job": JOBS,
    "hairlod.blender.pipeline": JOBS,

    "hairlod.blender.hair_mesh_preview": PREVIEWS,
    "hairlod.blender.hair_mesh_gpu_preview": PREVIEWS,
    "hairlod.blender.preview": PREVIEWS,
    "hairlod.blender.preview.lod_preview": PREVIEWS,
    "hairlod.blender.preview.strand_batch": PREVIEWS,
    "hairlod.blender.preview.shaders": PREVIEWS,
    "hairlod.blender.preview.view_transform": PREVIEWS,
    "hairlod.blender.preview.bcsdf_textures": PREVIEWS,
    "hairlod.blender.preview.opacity_maps": PREVIEWS,
    "hairlod.blender.preview.hair_layer": PREVIEWS,
    # Reads the scene's world, but to upload it as GPU blocks and textures for the LoD preview's shaders.
    "hairlod.blender.preview.world_srbf": PREVIEWS,
    "hairlod.blender.preview.pulled_strips": PREVIEWS,
    "hairlod.blender.preview.world_occlusion_texture": PREVIEWS,

    "hairlod.blender.operators": UI,
    "hairlod.blender.hair_mesh_operators": UI,
    "hairlod.blender.hair_mesh_settings": UI,
    "hairlod.blender.lod_operator": UI,
    "hairlod.blender.lod_export": UI,
    "hairlod.blender.lod_preview_ui": UI,
    "hairlod.blender.panels": UI,
}

Import = namedtuple("Import", "importer target line function")  # function: enclosing def, None at module level


def module_name(path, root=PACKAGE_DIR):
    parts = path.relative_to(root.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def package_sources(root=PACKAGE_DIR):
    """{module name: (path, is_package)} for every .py file under `root`."""
    return {module_name(path, root): (path, path.name == "__init__.py") for path in sorted(root.rglob("*.py"))}


def imports_of(name, source, is_package, modules):
    """Every import statement of module `name` (its `source`), resolved to module names. `modules`:
    the package's modules, so that `from . import x` is module x where x is one, else the package."""
    found = []

    def add(target, node, function):
        found.append(Import(name, target, node.lineno, function))

    def visit(node, function):
        if isinstance(node, ast.Import):
            for alias in node.names:
                add(alias.name, node, function)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name if is_package else name.rpartition(".")[0]
                for _ in range(node.level - 1):
                    base = base.rpartition(".")[0]
                base = f"{base}.{node.module}" if node.module else base
            else:
                base = node.module
            for alias in node.names:
                submodule = f"{base}.{alias.name}"
                add(submodule if submodule in modules else base, node, function)
        for child in ast.iter_child_nodes(node):
            inner = node.name if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) else function
            visit(child, inner)

    visit(ast.parse(source), None)
    return found


def all_imports():
    sources = package_sources()
    modules = set(sources) | COMPILED_MODULES
    return [found for name, (path, is_package) in sources.items()
            for found in imports_of(name, path.read_text(encoding="utf-8"), is_package, modules)]


def in_package(name, package):
    return name == package or name.startswith(package + ".")


def where(found):
    scope = f" in {found.function}()" if found.function else ""
    return f"{found.importer} (line {found.line}{scope}) imports {found.target}"


def find_cycle(edges):
    """One cycle of the directed graph {node: {successor: import}} as a list of its imports, or None."""
    state = {}  # node -> 1 on the current path, 2 done
    path = []

    def visit(node):
        state[node] = 1
        for successor, found in sorted(edges.get(node, {}).items()):
            path.append(found)
            if state.get(successor) == 1:
                return path[[step.importer for step in path].index(successor):]
            if successor not in state:
                cycle = visit(successor)
                if cycle:
                    return cycle
            path.pop()
        state[node] = 2
        return None

    for node in sorted(edges):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def import_graph(imports):
    """{importer: {imported hairlod module: the first import of it}}."""
    edges = {}
    for found in imports:
        if in_package(found.target, PACKAGE) and found.target != found.importer:
            edges.setdefault(found.importer, {}).setdefault(found.target, found)
    return edges


def test_only_hairlod_blender_imports_blender():
    wrong = []
    for found in all_imports():
        if in_package(found.importer, BLENDER):
            continue
        importer, target, functions = ENTRY_POINT
        if (found.importer, found.target) == (importer, target) and found.function in functions:
            continue
        if found.target.partition(".")[0] in BLENDER_MODULES or in_package(found.target, BLENDER):
            wrong.append(where(found))
    assert not wrong, "Blender is imported outside hairlod.blender:\n" + "\n".join(dict.fromkeys(wrong))


def test_no_import_cycle():
    cycle = find_cycle(import_graph(all_imports()))
    assert cycle is None, "import cycle:\n" + "\n".join(where(found) for found in cycle)


def test_every_blender_module_has_a_layer():
    blender_modules = {name for name in package_sources() if in_package(name, BLENDER)} - {BLENDER}
    assert not blender_modules - set(LAYERS), f"modules missing from LAYERS: {sorted(blender_modules - set(LAYERS))}"
    assert not set(LAYERS) - blender_modules, f"LAYERS names no such module: {sorted(set(LAYERS) - blender_modules)}"


def test_blender_modules_import_only_their_layer_or_lower():
    wrong = []
    for found in all_imports():
        if found.importer not in LAYERS or not in_package(found.target, BLENDER):
            continue
        if found.target not in LAYERS:  # the registration module, above every layer
            wrong.append(f"{where(found)}, the registration module")
        elif LAYERS[found.target] > LAYERS[found.importer]:
            wrong.append(f"{where(found)}: {LAYER_NAMES[LAYERS[found.importer]]} -> "
                         f"{LAYER_NAMES[LAYERS[found.target]]}")
    assert not wrong, "imports up a layer:\n" + "\n".join(dict.fromkeys(wrong))


# The reader above, on made-up sources: a test that read nothing would pass everything.

def test_imports_resolve_relative_and_function_level_imports():
    modules = {"hairlod", "hairlod.lod", "hairlod._core", "hairlod.blender", "hairlod.blender.curves",
               "hairlod.blender.preview", "hairlod.blender.preview.lod_preview"}
    source = ("import bpy\nfrom .. import Strands, lod\nfrom . import curves\nfrom .._core import HairMesh\n"
              "def build():\n    from .preview import lod_preview\n    import matplotlib.pyplot\n")
    found = {(i.target, i.line, i.function) for i in imports_of("hairlod.blender.job", source, False, modules)}
    assert found == {("bpy", 1, None), ("hairlod", 2, None), ("hairlod.lod", 2, None),
                     ("hairlod.blender.curves", 3, None), ("hairlod._core", 4, None),
                     ("hairlod.blender.preview.lod_preview", 6, "build"), ("matplotlib.pyplot", 7, "build")}
    in_package_init = imports_of("hairlod.blender", "from .curves import x\nfrom .. import lod\n", True, modules)
    assert [i.target for i in in_package_init] == ["hairlod.blender.curves", "hairlod.lod"]


def test_find_cycle_reports_the_chain():
    a_b, b_c, c_a = Import("a", "b", 1, None), Import("b", "c", 2, "f"), Import("c", "a", 3, None)
    assert find_cycle({"a": {"b": a_b}, "b": {"c": b_c}}) is None
    assert find_cycle({"a": {"b": a_b}, "b": {"c": b_c}, "c": {"a": c_a}}) == [a_b, b_c, c_a]
    assert find_cycle({"x": {"b": Import("x", "b", 1, None)}, "b": {"c": b_c}, "c": {"b": Import("c", "b", 4, None)}}) \
        == [b_c, Import("c", "b", 4, None)]
