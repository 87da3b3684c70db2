"""Hair meshes: strands generated from a low-poly cage of layers (hair-meshes-realtime.txt).

A hair mesh is a root layer of polygons (the scalp faces) extruded into layers that share its
topology; each root face and its extrusions form a bundle. ``generate_strands`` grows strands in
the bundles (blue-noise roots, centripetal Catmull-Rom curves through the layers), styles them in
seam-free styling frames, and applies strand and vertex level of detail.

Files are JSON (``docs/hairmesh-format.md``); ``read`` / ``write`` handle them, strictly: a bad file
raises ValueError naming the file, the key and the problem.
"""

import math
import os
from dataclasses import dataclass, field

import numpy as np

from . import atomic_output, memory_budget, strict_json
from ._core import Clump, Curl, Frizz, HairMesh, StrandGenerator, Trim, Twist, Wave, detail_level

FORMAT_NAME = "hairlod.hairmesh"
FORMAT_VERSION = 1

# Styling operation name in files and dicts -> class and its parameters (all floats).
STYLING_OPERATIONS = {
    "curl": (Curl, ("radius", "frequency", "randomness")),
    "wave": (Wave, ("amplitude", "frequency", "randomness")),
    "twist": (Twist, ("rate",)),
    "clump": (Clump, ("amount", "profile")),
    "frizz": (Frizz, ("amplitude", "frequency")),
    "trim": (Trim, ("amount",)),
}

# Strand radius when neither the caller nor the file gives one, as a fraction of the bounding-box
# diagonal of the hair mesh.
DEFAULT_RADIUS_FRACTION = 5e-4

__all__ = [
    "Clump", "Curl", "Frizz", "HairMesh", "HairMeshFile", "StrandGenerator", "Trim", "Twist", "Wave",
    "default_radius", "detail_level", "extrude_faces", "generate_strands", "hair_mesh_from_dict", "hair_mesh_to_dict", "read",
    "resolve_inputs", "strand_generator", "styling_from_dicts", "styling_to_dicts", "write",
]


@dataclass
class HairMeshFile:
    """A hair mesh with the styling and strand radius stored next to it."""

    mesh: HairMesh
    styling: list = field(default_factory=list)
    strand_radius: float | None = None


def styling_from_dicts(items, where="styling"):
    """Styling operation objects from dicts like ``{"op": "curl", "radius": 0.2, "frequency": 3}``.

    Operation objects (``hairlod.hairmesh.Curl(...)``) pass through unchanged. Unknown operations
    or parameters raise ValueError naming ``where`` and the list index.
    """
    if items is None:
        return []
    if not isinstance(items, (list, tuple)):
        raise ValueError(f"{where}: must be a list of operations")
    operations = []
    for index, item in enumerate(items):
        if isinstance(item, tuple(kind for kind, _ in STYLING_OPERATIONS.values())):
            operations.append(item)
            continue
        if not isinstance(item, dict) or "op" not in item:
            raise ValueError(f"{where}[{index}]: must be an object with an 'op' key")
        name = item["op"]
        if not isinstance(name, str) or name not in STYLING_OPERATIONS:
            raise ValueError(f"{where}[{index}]: unknown operation {name!r} (known: {', '.join(STYLING_OPERATIONS)})")
        kind, parameters = STYLING_OPERATIONS[name]
        values = {}
        for key, value in item.items():
            if key == "op":
                continue
            if key not in parameters:
                raise ValueError(f"{where}[{index}] ({name}): unknown parameter {key!r} (known: {', '.join(parameters)})")
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{where}[{index}] ({name}): {key} must be a finite number")
            values[key] = float(value)
        operations.append(kind(**values))
    return operations


def styling_to_dicts(operations):
    """The inverse of ``styling_from_dicts``."""
    result = []
    for operation in operations:
        for name, (kind, parameters) in STYLING_OPERATIONS.items():
            if isinstance(operation, kind):
                result.append({"op": name, **{key: _shortest(getattr(operation, key)) for key in parameters}})
                break
        else:
            raise ValueError(f"not a styling operation: {operation!r}")
    return result


def _number_array(value, where, dtype, shape_rank):
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{where}: must be a {'nested ' if shape_rank > 1 else ''}list of numbers") from None
    if array.ndim != shape_rank:
        raise ValueError(f"{where}: expected {shape_rank} levels of nesting, got {array.ndim}")
    limit = np.finfo(dtype).max
    if not np.all(np.abs(array) <= limit):
        raise ValueError(f"{where}: numbers must be finite and within +-{limit:.3g} ({np.dtype(dtype).name})")
    return array.astype(dtype)


def hair_mesh_from_dict(data, where="hair mesh"):
    """HairMeshFile from the JSON object of the file format (strict: unknown keys are errors)."""
    if not isinstance(data, dict):
        raise ValueError(f"{where}: must be a JSON object")
    known = {"format", "version", "layers", "faces", "uv", "w", "styling", "strand_radius"}
    unknown = sorted(set(data) - known)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}")
    if data.get("format") != FORMAT_NAME:
        raise ValueError(f"{where}: 'format' must be {FORMAT_NAME!r}")
    if data.get("version") != FORMAT_VERSION:
        raise ValueError(f"{where}: unsupported version {data.get('version')!r} (this reader knows {FORMAT_VERSION})")
    for key in ("layers", "faces"):
        if key not in data:
            raise ValueError(f"{where}: missing {key!r}")
    layers = _number_array(data["layers"], f"{where}: layers", np.float32, 3)
    if layers.shape[2] != 3:
        raise ValueError(f"{where}: layers must hold [x, y, z] points")
    faces = data["faces"]
    if not isinstance(faces, list) or not all(isinstance(face, list) for face in faces):
        raise ValueError(f"{where}: faces must be a list of vertex index lists")
    sizes = np.array([len(face) for face in faces], dtype=np.int32)
    flat = [index for face in faces for index in face]
    if not all(isinstance(index, int) and not isinstance(index, bool) for index in flat):
        raise ValueError(f"{where}: faces must hold integer vertex indices")
    if flat and not (0 <= min(flat) and max(flat) < layers.shape[1]):
        raise ValueError(f"{where}: faces: vertex index {min(flat) if min(flat) < 0 else max(flat)} is outside "
                         f"0..{layers.shape[1] - 1} (the vertices of a layer)")
    uv = None
    if data.get("uv") is not None:
        corners = data["uv"]
        if not isinstance(corners, list) or not all(isinstance(face, list) for face in corners) or \
                [len(face) for face in corners] != list(sizes):
            raise ValueError(f"{where}: uv must hold one [u, v] per face corner, shaped like faces")
        uv = _number_array([pair for face in corners for pair in face], f"{where}: uv", np.float32, 2)
        if uv.shape[1] != 2:
            raise ValueError(f"{where}: uv must hold [u, v] pairs")
    w = None
    if data.get("w") is not None:
        w = _number_array(data["w"], f"{where}: w", np.float32, 2)
    radius = data.get("strand_radius")
    if radius is not None and (isinstance(radius, bool) or not isinstance(radius, (int, float)) or not radius >= 0):
        raise ValueError(f"{where}: strand_radius must be a number >= 0")
    try:
        mesh = HairMesh(layers, sizes, np.array(flat, dtype=np.int32), uv, w)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    styling = styling_from_dicts(data.get("styling"), f"{where}: styling")
    return HairMeshFile(mesh, styling, None if radius is None else float(radius))


def _shortest(array):
    """Nested lists of the shortest decimals that read back as the same float32 values."""
    values = np.asarray(array, dtype=np.float32)
    if values.ndim == 0:
        return float(str(values))
    return [_shortest(item) for item in values]


def hair_mesh_to_dict(mesh, styling=(), strand_radius=None):
    """The JSON object of the file format. Faces are written after splitting (triangles and quads)."""
    sizes = mesh.face_sizes
    starts = np.concatenate([[0], np.cumsum(sizes)])
    vertices = mesh.face_vertices.tolist()
    data = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "layers": _shortest(mesh.layers),
        "faces": [vertices[starts[f]:starts[f + 1]] for f in range(len(sizes))],
    }
    if mesh.uv is not None:
        uv = _shortest(mesh.uv)
        data["uv"] = [uv[starts[f]:starts[f + 1]] for f in range(len(sizes))]
    if mesh.w is not None:
        data["w"] = _shortest(mesh.w)
    if styling:
        data["styling"] = styling_to_dicts(styling_from_dicts(list(styling)))
    if strand_radius is not None:
        data["strand_radius"] = float(strand_radius)
    return data


def read(path) -> HairMeshFile:
    """Reads a hair mesh JSON file."""
    path = os.fspath(path)
    return hair_mesh_from_dict(strict_json.load(path), where=path)


def write(path, mesh, styling=(), strand_radius=None):
    """Writes a hair mesh JSON file atomically (temporary file renamed when complete)."""
    path = os.fspath(path)
    text = strict_json.dumps(hair_mesh_to_dict(mesh, styling, strand_radius), separators=(",", ":"))
    with atomic_output.replacing_file(path) as temporary:
        with open(temporary, "w", encoding="utf-8") as stream:
            stream.write(text)


def default_radius(mesh):
    """DEFAULT_RADIUS_FRACTION of the bounding-box diagonal of the hair mesh."""
    points = mesh.layers.reshape(-1, 3)
    return float(DEFAULT_RADIUS_FRACTION * np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def resolve_inputs(hair_mesh, styling=(), radius=None):
    """(HairMesh, styling operations, radius): a HairMeshFile's styling and strand radius are the
    defaults for those not given; the radius falls back to default_radius."""
    if isinstance(hair_mesh, HairMeshFile):
        if not styling:
            styling = hair_mesh.styling
        if radius is None:
            radius = hair_mesh.strand_radius
        hair_mesh = hair_mesh.mesh
    if not isinstance(hair_mesh, HairMesh):
        raise ValueError("hair_mesh must be a HairMesh or a HairMeshFile")
    if radius is None:
        radius = default_radius(hair_mesh)
    return hair_mesh, styling_from_dicts(list(styling)), float(radius)


# Bytes per generated vertex (points, radius, tangent, uvw: 40) and per strand (offsets, bundle,
# root sample sets), with the copies the bindings make when they hand arrays to Python.
GENERATED_VERTEX_BYTES = 2 * 40
GENERATED_STRAND_BYTES = 2 * 16 + 256


def check_generate_budget(count, vertices):
    """Raises MemoryBudgetError (a ValueError) when `count` strands of `vertices` vertices would not fit
    the memory budget; called before anything is allocated."""
    count, vertices = int(count), int(vertices)
    memory_budget.check(count * (vertices * GENERATED_VERTEX_BYTES + GENERATED_STRAND_BYTES),
                        f"{count} strands of {vertices} vertices (--count, --vertices)")


def require_finite(strands):
    """Raises ValueError when generated strands are not finite (styling parameters too large for float32)."""
    if not np.all(np.isfinite(strands.points)):
        raise ValueError("the styling produced coordinates that are not finite (reduce its parameters)")


def strand_generator(hair_mesh, count=10000, seed=0, subdivision=0, reuse=None):
    """A StrandGenerator for the (optionally subdivided) mesh: it holds the styling frames and the
    blue-noise root sample sets, the part of the work that styling and LoD changes do not redo.
    ``reuse``: the generator of an earlier state of the same hair mesh (an interactive edit); its
    root sample sets are taken when they are exactly the ones needed, so the result is the same."""
    if int(seed) < 0 or int(count) < 0:
        raise ValueError(f"seed and count must be >= 0, got seed {seed} and count {count}")
    mesh = hair_mesh.subdivided(int(subdivision)) if subdivision else hair_mesh
    return StrandGenerator(mesh, int(count), int(seed), reuse=reuse)


def generate_strands(hair_mesh, count=10000, vertices=17, styling=(), seed=0, lod=1.0, subdivision=0, radius=None,
                     lod_transition=0.5):
    """Strands grown from a hair mesh.

    hair_mesh       HairMesh or HairMeshFile (whose styling and strand radius are the defaults)
    count           strands at full LoD, distributed over the bundles by root face area
    vertices        vertices per strand at full LoD: 2^e + 1 (2, 3, 5, 9, 17, 33, 65, ...)
    styling         list of operations (Curl(...), ... or dicts {"op": "curl", ...}), applied in order
    seed            every random choice (roots, per-strand styling, LoD increments) follows from it
    lod             level of detail L in (0, 1] (Bhokare 2024 Eq. 7), or a pair (strand L, vertex L)
    subdivision     OpenSubdiv refinement level 0-3 of the hair mesh before generating
    radius          strand radius at full LoD (default: the file's, else 5e-4 of the mesh diagonal)
    lod_transition  vertex LoD morphing window lambda in (0, 1] (Bhokare 2024 Eq. 10)

    Returns Strands with point attributes 'tangent' [N, 3] and 'uvw' [N, 3] and the curve attribute
    'bundle' (index of the root face of the, possibly subdivided, hair mesh).
    """
    check_generate_budget(count, vertices)
    mesh, operations, radius = resolve_inputs(hair_mesh, styling, radius)
    strand_lod, vertex_lod = (lod, lod) if np.isscalar(lod) else lod
    generator = strand_generator(mesh, count, seed, subdivision)
    strands = generator.generate(vertices=int(vertices), styling=operations, strand_lod=float(strand_lod),
                                 vertex_lod=float(vertex_lod), lod_transition=float(lod_transition), radius=radius)
    require_finite(strands)
    return strands


def extrude_faces(positions, loop_vertices, loop_starts, loop_totals, face_normals, face_areas, selected, layers,
                  length, taper=0.0, loop_uv=None):
    """A HairMesh grown from mesh faces (New Hair Mesh from Faces): the selected faces (all of them when
    none is) are the root layer, extruded `layers` times along the area-weighted smooth normals of the
    selected faces to `length`, each layer shrunk by `taper` towards its centre relative to the one
    below. Arrays as a mesh stores them: vertex positions [V, 3], per-loop vertex indices [L], per-face
    loop_starts / loop_totals / normals [F, 3] / areas / selected flags, and optional per-loop UVs [L, 2]."""
    positions = np.asarray(positions, np.float32).reshape(-1, 3)
    loop_vertices = np.asarray(loop_vertices, np.int64)
    loop_starts, loop_totals = np.asarray(loop_starts, np.int64), np.asarray(loop_totals, np.int64)
    face_normals = np.asarray(face_normals, np.float64).reshape(-1, 3)
    face_areas = np.asarray(face_areas, np.float64)
    selected = np.array(selected, bool)
    if len(loop_starts) == 0:
        raise ValueError("the mesh has no faces to extrude")
    if not (len(loop_totals) == len(face_normals) == len(face_areas) == len(selected) == len(loop_starts)):
        raise ValueError("loop_starts, loop_totals, face_normals, face_areas and selected need one entry per face")
    if isinstance(layers, bool) or int(layers) != layers or layers < 1:
        raise ValueError(f"layers must be an integer >= 1, got {layers!r}")
    if not (np.isfinite(length) and length >= 0.0) or not (0.0 <= taper < 1.0):
        raise ValueError(f"length must be finite and >= 0 and taper in [0, 1), got {length!r}, {taper!r}")
    if not selected.any():
        selected[:] = True
    sizes = loop_totals[selected]
    first_in_output = np.cumsum(sizes) - sizes
    loops = np.repeat(loop_starts[selected] - first_in_output, sizes) + np.arange(int(sizes.sum()))
    used, root_of_loop = np.unique(loop_vertices[loops], return_inverse=True)
    # Smooth normals of the selected faces only, area-weighted, so that unselected neighbours do not
    # bend the extrusion at the selection's border.
    normals = np.zeros((len(used), 3), np.float64)
    np.add.at(normals, root_of_loop, np.repeat(face_normals[selected] * face_areas[selected, None], sizes, axis=0))
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
    step = np.arange(int(layers) + 1)[:, None, None]
    offset_layers = positions[used][None] + normals[None] * (float(length) * step / int(layers))
    centres = offset_layers.mean(axis=1, keepdims=True)
    grown = centres + (offset_layers - centres) * (1.0 - float(taper)) ** step
    uv = None if loop_uv is None else np.asarray(loop_uv, np.float32).reshape(-1, 2)[loops]
    return HairMesh(grown.astype(np.float32), sizes.astype(np.int32), root_of_loop.astype(np.int32).ravel(), uv)
