"""Hair for the Blender tests and benchmarks: hanging test strands; an LoD previewed on an empty; a
Geometry Nodes modifier that turns a hair object by
keyframed angles, and hair attached to an armature-animated head the way artists animate hair in
Blender (a UV-sphere head deformed by a two-bone rig, neck and head, and a hair Curves object on its
surface, Curves.surface, surface_uv_map and each curve's surface_uv_coordinate, moved by a Geometry
Nodes modifier with the Deform Curves on Surface node), and many strands on a head that a keyframed
twist deforms. Shared by tests/blender, tests/ui and scripts/bench_preview_animation.py."""

import math

import bpy
import numpy as np

from hairlod import Strands
from hairlod.blender.curves import new_geometry_node_tree, strands_to_curves


def hanging_hair(curves=600, points=8, seed=3):
    """Strands hanging from the upper part of a unit sphere, radius 0.002, deterministic for `seed`."""
    rng = np.random.default_rng(seed)
    azimuth, polar = rng.uniform(0, 2 * math.pi, curves), rng.uniform(0, 1.4, curves)
    roots = np.stack([np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)], axis=1)
    t = np.linspace(0, 1, points)
    positions = roots[:, None, :] * (1 + 0.2 * t[None, :, None]) - np.array([0, 0, 1.0]) * t[None, :, None]
    return Strands.from_counts(positions.astype(np.float32).reshape(-1, 3), np.full(curves, points),
                               np.full(curves * points, 0.002, np.float32))


def preview_on_an_empty(asset):
    """An empty scene but for an empty object that shows `asset` in the LoD preview:
    (holder, its preview settings, its LodPreview)."""
    from hairlod.blender.preview import lod_preview

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    holder = bpy.data.objects.new("hair LoD", None)
    bpy.context.scene.collection.objects.link(holder)
    lod_preview.attach(holder, asset)
    return holder, holder.hairlod_lod_preview, lod_preview.preview_of(holder)


def action_fcurves(action):
    """The F-curves of an action: on the action itself up to Blender 4.x, in its layers' strips'
    channel bags (one per slot) since Blender 5 took the action's own list away."""
    if hasattr(action, "fcurves"):
        return list(action.fcurves)
    return [curve for layer in action.layers for strip in layer.strips for bag in strip.channelbags
            for curve in bag.fcurves]


def node_input(node, name):
    """The input socket `name` that `node` uses for its current type: Blender 4.x and older keep one
    socket per data type under the same name (the others disabled), Blender 5 only the current one."""
    return next(socket for socket in node.inputs if socket.name == name and getattr(socket, "enabled", True))


def add_keyframed_rotation(obj, keys, name="Turn"):
    """A Geometry Nodes modifier on `obj` whose Transform node rotates the geometry by Euler angles
    keyed at frames: keys ((frame, (x, y, z)), ...), interpolated linearly between them."""
    tree = new_geometry_node_tree(name)
    group_in, group_out = tree.nodes.new('NodeGroupInput'), tree.nodes.new('NodeGroupOutput')
    transform = tree.nodes.new('GeometryNodeTransform')
    tree.links.new(group_in.outputs[0], transform.inputs["Geometry"])
    tree.links.new(transform.outputs["Geometry"], group_out.inputs[0])
    rotation = transform.inputs["Rotation"]
    for frame, angles in keys:
        rotation.default_value = angles
        rotation.keyframe_insert("default_value", frame=frame)
    for curve in action_fcurves(tree.animation_data.action):
        for key in curve.keyframe_points:
            key.interpolation = 'LINEAR'
    obj.modifiers.new(name, 'NODES').node_group = tree
    return tree


def _mesh_arrays(mesh):
    """(loop triangles' corners [T, 3], each corner's vertex [C], positions [V, 3], corner UVs [C, 2])."""
    mesh.calc_loop_triangles()
    loops = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    vertex_of_loop = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", vertex_of_loop)
    positions = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", positions)
    uv = np.empty(len(mesh.loops) * 2, np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    return loops.reshape(-1, 3), vertex_of_loop, positions.reshape(-1, 3), uv.reshape(-1, 2)


def _triangles(mesh):
    """(centroids [T, 3], normals [T, 3], uv centroids [T, 2], bool [T]: the triangle is a polygon of
    its own, not part of a quad) of the mesh's loop triangles."""
    loops, vertex_of_loop, positions, uv = _mesh_arrays(mesh)
    count = len(loops)
    polygon_sizes = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("loop_total", polygon_sizes)
    polygon_of_triangle = np.empty(count, np.int32)
    mesh.loop_triangles.foreach_get("polygon_index", polygon_of_triangle)
    # Blender 3.4 numbers a new UV sphere's loops in a different order from run to run (the same
    # triangles, reordered): order them by their vertices so the hair grown on them is the same.
    vertices = np.sort(vertex_of_loop[loops].reshape(count, 3), axis=1)
    order = np.lexsort(vertices.T[::-1])
    loops = loops.reshape(count, 3)[order].ravel()
    corners = positions[vertex_of_loop[loops]].reshape(count, 3, 3)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return (corners.mean(axis=1), normals, uv[loops].reshape(count, 3, 2).mean(axis=1),
            polygon_sizes[polygon_of_triangle[order]] == 3)


def surface_strands(head_mesh, points=12, length=0.9, seed=4):
    """Strands rooted at the centroids of the head's upper triangles (one per triangle of its quads,
    away from the UV seam), growing out along the normal and falling: (Strands, uv [C, 2])."""
    centroids, normals, uv, pole_fan = _triangles(head_mesh)
    # Where a UV coordinate names one triangle: away from the seam (u near 0 or 1) and the pole's fan
    # of triangles, whose centroids a Subdivision Surface makes vertices of its mesh (Blender 5 then
    # turns such a root with another of the triangles meeting there than Blender 4 did).
    keep = (centroids[:, 2] > 0.15) & (uv[:, 0] > 0.02) & (uv[:, 0] < 0.98) & ~pole_fan
    roots, out, uv = centroids[keep], normals[keep], uv[keep]
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, points)[None, :, None]
    wave = 0.02 * np.sin(8.0 * t + rng.uniform(0, 2 * math.pi, (len(roots), 1, 1)))
    positions = roots[:, None, :] + length * (0.25 * t * out[:, None, :] + np.array([0.0, 0.0, -1.0]) * t ** 2) + wave
    count = len(roots)
    strands = Strands.from_counts(positions.astype(np.float32).reshape(-1, 3), np.full(count, points),
                                  np.full(count * points, 0.002, np.float32))
    return strands, uv


def build_scene(rigid, subdivisions=48):
    """(hair object, rig object) in the current scene. `rigid`: every head vertex follows the head
    bone (a head turn moves the surface rigidly); else the weights fall from the crown to the ears
    (turning the head bone bends and squashes the scalp)."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=subdivisions, ring_count=subdivisions // 2, radius=1.0)
    head = bpy.context.active_object
    head.name = "Head"
    rig_data = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", rig_data)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    neck = rig_data.edit_bones.new("neck")
    neck.head, neck.tail = (0.0, 0.0, -2.0), (0.0, 0.0, -0.8)
    skull = rig_data.edit_bones.new("head")
    skull.head, skull.tail, skull.parent = (0.0, 0.0, -0.8), (0.0, 0.0, 1.2), neck
    bpy.ops.object.mode_set(mode='OBJECT')
    z = np.array([v.co.z for v in head.data.vertices])
    skull_weight = np.ones_like(z) if rigid else np.clip(z, 0.0, 1.0) ** 2
    neck_group, skull_group = head.vertex_groups.new(name="neck"), head.vertex_groups.new(name="head")
    for index, weight in enumerate(skull_weight):
        skull_group.add([index], float(weight), 'REPLACE')
        neck_group.add([index], float(1.0 - weight), 'REPLACE')
    head.modifiers.new("Armature", 'ARMATURE').object = rig
    strands, uv = surface_strands(head.data)
    hair = strands_to_curves(strands, "Hair")
    attribute = hair.data.attributes.new("surface_uv_coordinate", 'FLOAT2', 'CURVE')
    attribute.data.foreach_set("vector", uv.astype(np.float32).ravel())
    _attach(hair, head)
    bpy.context.view_layer.objects.active = hair
    return hair, rig


def _attach(hair, head):
    """Attaches `hair` to the mesh object `head` as Blender's hair tools do: the surface and its UV map,
    the surface's rest positions, and a Geometry Nodes modifier with Deform Curves on Surface."""
    # Deform Curves on Surface reads the surface's rest positions (to find the same tangents on the
    # original and the deformed mesh) from this attribute, which the deformation leaves as it is.
    rest = head.data.attributes.new("rest_position", 'FLOAT_VECTOR', 'POINT')
    positions = np.empty(len(head.data.vertices) * 3, np.float32)
    head.data.vertices.foreach_get("co", positions)
    rest.data.foreach_set("vector", positions)
    hair.data.surface = head
    hair.data.surface_uv_map = head.data.uv_layers.active.name
    tree = new_geometry_node_tree("Deform on Head")
    group_in, group_out = tree.nodes.new('NodeGroupInput'), tree.nodes.new('NodeGroupOutput')
    deform = tree.nodes.new('GeometryNodeDeformCurvesOnSurface')
    tree.links.new(group_in.outputs[0], deform.inputs[0])
    tree.links.new(deform.outputs[0], group_out.inputs[0])
    hair.modifiers.new("Deform on Head", 'NODES').node_group = tree


def twisted_head_hair(count, frames, angle=0.8, points=16, seed=1):
    """(hair, head): `count` strands of `points` rooted at random points of the upper half of a smooth
    UV-sphere head (16,128 triangles, radius 1), attached to it (Deform Curves on Surface), and a Simple
    Deform modifier twisting the head about z from 0 at frame 1 to `angle` at frame `frames` (the
    crown turns, the neck stays: every triangle turns its own way). Leaves the scene at frame 1."""
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=1.0)
    head = bpy.context.active_object
    head.name = "Head"
    for polygon in head.data.polygons:
        polygon.use_smooth = True
    triangles, corner_verts, positions, uv = _mesh_arrays(head.data)
    # Upper triangles away from the UV seam (where a UV coordinate names one triangle).
    corner_uv = uv[triangles]
    upper = np.nonzero((positions[corner_verts[triangles]].mean(axis=1)[:, 2] > 0.1) &
                       (corner_uv[:, :, 0].min(axis=1) > 0.01) & (corner_uv[:, :, 0].max(axis=1) < 0.99))[0]
    rng = np.random.default_rng(seed)
    chosen = rng.choice(upper, count)
    weights = rng.dirichlet((1.0, 1.0, 1.0), count)
    root_uv = np.einsum("nk,nkj->nj", weights, uv[triangles[chosen]])
    roots = np.einsum("nk,nkj->nj", weights, positions[corner_verts[triangles[chosen]]])
    t = np.linspace(0.0, 1.0, points)[None, :, None]
    out = roots / np.linalg.norm(roots, axis=1, keepdims=True)
    strands = roots[:, None, :] + 0.4 * t * out[:, None, :] - np.array([0.0, 0.0, 0.9]) * t ** 2
    hair = strands_to_curves(Strands.from_counts(strands.astype(np.float32).reshape(-1, 3), np.full(count, points),
                                                 np.full(count * points, 0.002, np.float32)), "Hair")
    attribute = hair.data.attributes.new("surface_uv_coordinate", 'FLOAT2', 'CURVE')
    attribute.data.foreach_set("vector", root_uv.astype(np.float32).ravel())
    _attach(hair, head)
    twist = head.modifiers.new("Twist", 'SIMPLE_DEFORM')
    twist.deform_method, twist.deform_axis = 'TWIST', 'Z'
    for frame, value in ((1, 0.0), (frames, angle)):
        twist.angle = value
        twist.keyframe_insert("angle", frame=frame)
    scene.frame_set(1)
    return hair, head


def turn_head(rig, angle):
    """Turns the head bone about its local x axis (a nod) and updates the scene."""
    bone = rig.pose.bones["head"]
    bone.rotation_mode = 'XYZ'
    bone.rotation_euler = (angle, 0.0, 0.3 * angle)
    bpy.context.view_layer.update()
