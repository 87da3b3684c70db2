"""Bridge between Blender Mesh objects and ``hairlod.HairMesh``.

In Blender a hair mesh is an ordinary Mesh whose vertices carry two integer point attributes:
``hair_layer`` (0 for the root layer) and ``hair_root`` (the mesh index of the vertex's root-layer
vertex). The faces whose vertices all lie on the root layer are the root faces; every other face
(the sides of the cage) only helps the artist see and edit it. An optional float point attribute
``hair_w`` holds the styling coordinate w, and the active UV map gives the root faces' uv.
Data moves with ``foreach_get`` / ``foreach_set`` on numpy arrays; no Python loop touches vertices.
"""

import bpy
import numpy as np

# Taken from hairlod.hairmesh, not from the hairlod package: hairlod.register() imports hairlod.blender,
# so that would be an import cycle (tests/python/test_import_layers.py).
from ..hairmesh import HairMesh

LAYER_ATTRIBUTE = "hair_layer"
ROOT_ATTRIBUTE = "hair_root"
W_ATTRIBUTE = "hair_w"


def is_hair_mesh_object(obj):
    """True for a Mesh object with the hair-mesh vertex attributes (not a full validation)."""
    if obj is None or obj.type != 'MESH':
        return False
    attributes = obj.data.attributes
    return LAYER_ATTRIBUTE in attributes and ROOT_ATTRIBUTE in attributes


def hair_mesh_from_object(obj) -> HairMesh:
    """The HairMesh of a hair-mesh object, in the object's local coordinates.

    Reads the edit-mode mesh when the object is being edited. Raises TypeError for objects that
    are not meshes and ValueError, naming the object, for meshes that are not valid hair meshes.
    """
    if obj is None or obj.type != 'MESH':
        kind = "nothing" if obj is None else f"'{obj.name}' ({obj.type})"
        raise TypeError(f"expected a hair-mesh Mesh object, got {kind}")
    if obj.mode != 'EDIT':
        return _hair_mesh_from_mesh(obj.data, obj.name)
    # In edit mode a mesh's attribute arrays read as empty, and neither to_mesh() nor the evaluated
    # mesh is up to date: write the edit mesh back and read a copy, which is not in edit mode.
    obj.update_from_editmode()
    copy = obj.data.copy()
    try:
        return _hair_mesh_from_mesh(copy, obj.name)
    finally:
        bpy.data.meshes.remove(copy)


def _hair_mesh_from_mesh(mesh, name):
    vertex_count = len(mesh.vertices)
    layer = _read_int_attribute(mesh, name, LAYER_ATTRIBUTE)
    root = _read_int_attribute(mesh, name, ROOT_ATTRIBUTE)

    if layer.min() < 0:
        raise ValueError(f"'{name}': {LAYER_ATTRIBUTE} is negative at vertex {int(np.argmin(layer))}")
    layer_count = int(layer.max()) + 1
    if layer_count < 2:
        raise ValueError(f"'{name}': all vertices are on the root layer; a hair mesh needs at least one more layer")
    bad_root = (root < 0) | (root >= vertex_count)
    bad_root[~bad_root] = layer[root[~bad_root]] != 0
    if bad_root.any():
        vertex = int(np.argmax(bad_root))
        raise ValueError(f"'{name}': vertex {vertex} has {ROOT_ATTRIBUTE} {int(root[vertex])}, "
                         "which is not a root-layer vertex")
    root_vertices = np.flatnonzero(layer == 0)
    if (root[root_vertices] != root_vertices).any():
        vertex = int(root_vertices[np.argmax(root[root_vertices] != root_vertices)])
        raise ValueError(f"'{name}': root-layer vertex {vertex} has {ROOT_ATTRIBUTE} {int(root[vertex])}, "
                         "not its own index")
    roots_per_layer = len(root_vertices)
    layer_sizes = np.bincount(layer, minlength=layer_count)
    if (layer_sizes != roots_per_layer).any():
        wrong = int(np.argmax(layer_sizes != roots_per_layer))
        raise ValueError(f"'{name}': layer {wrong} has {layer_sizes[wrong]} vertices, "
                         f"the root layer has {roots_per_layer}")

    # Hair-mesh vertex index of each root: its rank among the root-layer vertices.
    rank = np.full(vertex_count, -1, np.int64)
    rank[root_vertices] = np.arange(roots_per_layer)
    slot = layer * roots_per_layer + rank[root]
    uses = np.bincount(slot, minlength=layer_count * roots_per_layer)
    if (uses != 1).any():
        twice = int(np.argmax(uses > 1))
        raise ValueError(f"'{name}': layer {twice // roots_per_layer} has two vertices for root vertex "
                         f"{int(root_vertices[twice % roots_per_layer])}")

    positions = np.empty((vertex_count, 3), np.float32)
    mesh.vertices.foreach_get("co", positions.ravel())
    layers = np.empty_like(positions)
    layers[slot] = positions

    loop_vertices = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertices)
    loop_starts = np.empty(len(mesh.polygons), np.int32)
    loop_totals = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("loop_start", loop_starts)
    mesh.polygons.foreach_get("loop_total", loop_totals)
    off_root = (layer[loop_vertices] != 0).astype(np.int32)
    order = np.argsort(loop_starts, kind="stable")
    is_root_face = np.zeros(len(loop_starts), bool)
    if len(order):
        is_root_face[order] = np.add.reduceat(off_root, loop_starts[order]) == 0
    if not is_root_face.any():
        raise ValueError(f"'{name}': no face has all its vertices on the root layer")
    root_sizes = loop_totals[is_root_face]
    root_loop_count = int(root_sizes.sum())
    # Loop indices of the root faces in face order: each face's start plus 0 .. size - 1.
    first_in_output = np.cumsum(root_sizes) - root_sizes
    root_loops = np.repeat(loop_starts[is_root_face] - first_in_output, root_sizes) + np.arange(root_loop_count)

    uv = None
    if mesh.uv_layers.active is not None:
        loop_uv = np.empty((len(mesh.loops), 2), np.float32)
        mesh.uv_layers.active.data.foreach_get("uv", loop_uv.ravel())
        uv = loop_uv[root_loops]
    w = None
    if W_ATTRIBUTE in mesh.attributes:
        values = np.empty(vertex_count, np.float32)
        mesh.attributes[W_ATTRIBUTE].data.foreach_get("value", values)
        w = np.empty_like(values)
        w[slot] = values
        w = w.reshape(layer_count, roots_per_layer)

    try:
        return HairMesh(layers.reshape(layer_count, roots_per_layer, 3), root_sizes,
                        rank[loop_vertices[root_loops]].astype(np.int32), uv, w)
    except ValueError as error:
        raise ValueError(f"'{name}': {error}") from None


def object_from_hair_mesh(hair_mesh: HairMesh, name, collection=None):
    """A new hair-mesh object named ``name`` in ``collection`` (the context's when None): every
    layer's vertices, the root faces, and side quads between consecutive layers along every root
    edge, so that the cage shows each bundle. Vertices are ordered layer by layer."""
    layer_count, roots_per_layer = hair_mesh.layer_count, hair_mesh.vertex_count
    face_sizes = hair_mesh.face_sizes.astype(np.int32)
    face_vertices = hair_mesh.face_vertices.astype(np.int32)

    # Each root edge once, as (lower, higher) vertex index.
    face_starts = np.concatenate([[0], np.cumsum(face_sizes)[:-1]]).astype(np.int32)
    following = np.arange(1, len(face_vertices) + 1)
    following[np.cumsum(face_sizes) - 1] = face_starts
    edges = np.unique(np.sort(np.stack([face_vertices, face_vertices[following]], axis=1), axis=1), axis=0)
    lower = np.arange(layer_count - 1)[:, None] * roots_per_layer
    upper = lower + roots_per_layer
    a, b = edges[:, 0][None, :], edges[:, 1][None, :]
    side_quads = np.stack([a + lower, b + lower, b + upper, a + upper], axis=-1).reshape(-1, 4)

    polygon_sizes = np.concatenate([face_sizes, np.full(len(side_quads), 4, np.int32)])
    loop_vertices = np.concatenate([face_vertices, side_quads.ravel()]).astype(np.int32)

    mesh = bpy.data.meshes.new(name)
    obj = bpy.data.objects.new(name, mesh)
    try:
        (collection or bpy.context.collection).objects.link(obj)
        mesh.vertices.add(layer_count * roots_per_layer)
        mesh.vertices.foreach_set("co", np.ascontiguousarray(hair_mesh.layers, np.float32).ravel())
        mesh.loops.add(len(loop_vertices))
        mesh.loops.foreach_set("vertex_index", loop_vertices)
        mesh.polygons.add(len(polygon_sizes))
        mesh.polygons.foreach_set("loop_start", np.concatenate([[0], np.cumsum(polygon_sizes)[:-1]]).astype(np.int32))
        # Blender 4 derives the sizes from the starts and makes loop_total read-only.
        if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:
            mesh.polygons.foreach_set("loop_total", polygon_sizes)
        mesh.update(calc_edges=True)

        layer_index = np.repeat(np.arange(layer_count, dtype=np.int32), roots_per_layer)
        _write_attribute(mesh, LAYER_ATTRIBUTE, 'INT', layer_index)
        _write_attribute(mesh, ROOT_ATTRIBUTE, 'INT', np.tile(np.arange(roots_per_layer, dtype=np.int32), layer_count))
        if hair_mesh.w is not None:
            _write_attribute(mesh, W_ATTRIBUTE, 'FLOAT', hair_mesh.w.ravel())
        if hair_mesh.uv is not None:
            loop_uv = np.zeros((len(loop_vertices), 2), np.float32)
            loop_uv[:len(face_vertices)] = hair_mesh.uv
            mesh.uv_layers.new(name="UVMap").data.foreach_set("uv", loop_uv.ravel())
    except BaseException:
        bpy.data.objects.remove(obj)
        bpy.data.meshes.remove(mesh)
        raise
    return obj


def _read_int_attribute(mesh, object_name, name):
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != 'POINT' or attribute.data_type != 'INT':
        raise ValueError(f"'{object_name}' has no integer vertex attribute '{name}': "
                         "it is not a hair mesh (make one with New Hair Mesh from Faces)")
    values = np.empty(len(mesh.vertices), np.int32)
    attribute.data.foreach_get("value", values)
    return values.astype(np.int64)


def _write_attribute(mesh, name, data_type, values):
    attribute = mesh.attributes.new(name, data_type, 'POINT')
    attribute.data.foreach_set("value", np.ascontiguousarray(values, np.float32 if data_type == 'FLOAT' else np.int32))
