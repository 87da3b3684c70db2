"""The mesh a hair Curves object is attached to (Curves.surface and surface_uv_map, as Blender's hair
tools attach it), read as arrays for hairlod.surface_attachment: what moves the hair's strands exactly
as Blender's Deform Curves on Surface node moves them on an animated head."""

import numpy as np

from .. import surface_attachment

UV_ATTRIBUTE = "surface_uv_coordinate"   # Blender's per-curve UV coordinate on the surface
REST_ATTRIBUTE = "rest_position"         # the surface's rest positions, which the node reads


def attachment(obj):
    """(surface object, UV map name) of a hair Curves object attached to a mesh, else None."""
    data = getattr(obj, "data", None)
    surface = getattr(data, "surface", None)
    uv_map = getattr(data, "surface_uv_map", "")
    if obj.type != 'CURVES' or surface is None or surface.type != 'MESH' or not uv_map:
        return None
    return surface, uv_map


def _corner_normals(mesh):
    """float32 [corners, 3]: Blender's corner normals (smooth, flat, auto smooth or custom alike)."""
    normals = np.empty(len(mesh.loops) * 3, np.float32)
    if hasattr(mesh, "corner_normals"):  # Blender 4.1 and later
        mesh.corner_normals.foreach_get("vector", normals)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", normals)
    return normals.reshape(-1, 3)


def _floats(collection, name, width):
    values = np.empty(len(collection) * width, np.float32)
    collection.foreach_get(name, values)
    return values.reshape(-1, width)


class SurfaceMesh:
    """The arrays of one pose of a mesh: positions [V, 3] and corner normals [C, 3], its matrix into the
    hair's object space, and with `topology` its corner_verts [C], triangles [T, 3] (the corners of
    Blender's loop triangles, in Blender's order, which fixes each root's reference edge) and the
    corner UVs [C, 2] of `uv_map`. `rest`: positions from the mesh's rest_position attribute where it
    has one (what the node measures the reference tangents on)."""

    def __init__(self, surface, hair, topology=False, uv_map=None, rest=False):
        # A copy of the mesh: with the modifiers of an evaluated object, the object's own data of an
        # original one. Its normals can then be computed without touching the user's mesh.
        mesh = surface.to_mesh()
        try:
            attribute = mesh.attributes.get(REST_ATTRIBUTE) if rest else None
            if attribute is not None and attribute.domain == 'POINT' and attribute.data_type == 'FLOAT_VECTOR':
                self.positions = _floats(attribute.data, "vector", 3)
            else:
                self.positions = _floats(mesh.vertices, "co", 3)
            self.corner_normals = _corner_normals(mesh)
            if topology:
                if hasattr(mesh, "calc_loop_triangles"):
                    mesh.calc_loop_triangles()
                self.corner_verts = np.empty(len(mesh.loops), np.int32)
                mesh.loops.foreach_get("vertex_index", self.corner_verts)
                self.triangles = np.empty(len(mesh.loop_triangles) * 3, np.int32)
                mesh.loop_triangles.foreach_get("loops", self.triangles)
                self.triangles = self.triangles.reshape(-1, 3)
                layer = mesh.uv_layers.get(uv_map)
                if layer is None:
                    raise ValueError(f"the surface '{surface.name}' has no UV map '{uv_map}'")
                self.corner_uvs = _floats(layer.data, "uv", 2)
        finally:
            surface.to_mesh_clear()
        self.surface_to_curves = np.array(hair.matrix_world.inverted() @ surface.matrix_world, np.float32)


def changes_topology(obj, depsgraph):
    """Whether the modifiers of the mesh `obj` is attached to change its vertex or corner counts (a
    Subdivision Surface); None when `obj` is not attached."""
    attached = attachment(obj)
    if attached is None:
        return None
    surface = attached[0]
    evaluated = surface.evaluated_get(depsgraph).data
    return len(evaluated.vertices) != len(surface.data.vertices) or len(evaluated.loops) != len(surface.data.loops)


def follow(obj, depsgraph, order=None, evaluated=False):
    """A hairlod.surface_attachment.SurfaceFollow of `obj`'s curves (in `order`, indices of curves; all
    by default) on the mesh they are attached to; None when the hair is not attached. Its reference
    pose is the original mesh, where Blender's node takes its reference frames; with `evaluated`,
    the mesh its modifiers make in `depsgraph` (for modifiers that change the mesh, such as a
    Subdivision Surface: the node finds each root on that mesh, and the frames on the original mesh
    then cancel out between two poses; the curves must be as the node placed them at this pose).
    Raises ValueError naming what is missing (the UV map, the curves' UV coordinates)."""
    attached = attachment(obj)
    if attached is None:
        return None
    surface, uv_map = attached
    hair = obj.evaluated_get(depsgraph)
    uv = hair.data.attributes.get(UV_ATTRIBUTE)
    if uv is None or uv.domain != 'CURVE':
        raise ValueError(f"'{obj.name}' is attached to '{surface.name}' but its curves have no {UV_ATTRIBUTE}")
    root_uvs = _floats(uv.data, "vector", 2)
    if order is not None:
        root_uvs = root_uvs[np.asarray(order, np.int64)]
    if evaluated:
        rest = SurfaceMesh(surface.evaluated_get(depsgraph), hair, topology=True, uv_map=uv_map)
    else:
        rest = SurfaceMesh(surface.original, hair, topology=True, uv_map=uv_map, rest=True)
    return surface_attachment.SurfaceFollow(root_uvs, rest.corner_uvs, rest.triangles, rest.corner_verts,
                                            rest.positions, rest.corner_normals, rest.surface_to_curves)


def posed_transforms(binding, obj, depsgraph, out=None):
    """float32 [N, 3, 4]: the curves' transforms from the reference pose of their surface to its pose
    in `depsgraph` (SurfaceFollow.transforms, written into `out` when given). Raises ValueError when
    the hair is no longer attached or the surface's mesh has other vertex or corner counts than when
    it was bound."""
    attached = attachment(obj)
    if attached is None:
        raise ValueError(f"'{obj.name}' is no longer attached to a mesh")
    surface = attached[0]
    posed = SurfaceMesh(surface.evaluated_get(depsgraph), obj.evaluated_get(depsgraph))
    if len(posed.positions) != binding.vertex_count or len(posed.corner_normals) != binding.corner_count:
        raise ValueError(f"the surface '{surface.name}' has {len(posed.positions)} vertices now, "
                         f"{binding.vertex_count} when the hair was bound to it")
    return binding.transforms(posed.positions, posed.corner_normals, posed.surface_to_curves, out)
