"""Bridge between Blender hair ``Curves`` objects and ``hairlod.Strands``.

Data moves with ``foreach_get`` / ``foreach_set`` on contiguous numpy arrays; no Python loop
touches individual points or curves.
"""

import bpy
import numpy as np

# Taken from the core, not from the hairlod package: hairlod.register() imports hairlod.blender, so
# that would be an import cycle (tests/python/test_import_layers.py).
from .._core import Strands

# Strands attribute domain <-> Blender attribute domain.
_DOMAIN_TO_BLENDER = {"point": "POINT", "curve": "CURVE"}
_DOMAIN_FROM_BLENDER = {blender: ours for ours, blender in _DOMAIN_TO_BLENDER.items()}

# Float attribute types by component count, and the name of their foreach property.
_FLOAT_TYPES = {1: ("FLOAT", "value"), 2: ("FLOAT2", "vector"), 3: ("FLOAT_VECTOR", "vector"),
                4: ("FLOAT_COLOR", "color")}
_COMPONENTS_BY_TYPE = {data_type: (components, prop)
                       for components, (data_type, prop) in _FLOAT_TYPES.items()}

# Attributes that have their own Strands field.
_BUILTIN_ATTRIBUTES = {"position", "radius"}


def _position_data(curves):
    """The points' positions of a Curves data-block: `position_data` (Blender 3.3+), several times
    faster through foreach_get / foreach_set than the "position" attribute's data (1.7M points in
    Blender 3.4: 4 ms against 20 ms), else that attribute."""
    data = getattr(curves, "position_data", None)
    return data if data is not None else curves.attributes["position"].data


def curves_to_strands(obj, evaluated=True, depsgraph=None) -> Strands:
    """Strands from a hair Curves object.

    With ``evaluated`` the object's evaluated data (Geometry Nodes output) is read, using
    ``depsgraph`` or the context's evaluated depsgraph. Float point and curve attributes become
    Strands attributes; a missing ``radius`` attribute gives radius 0 (Blender 3.x's default).
    Raises TypeError for objects that are not hair Curves, ValueError for unusable curves.
    """
    if obj is None or obj.type != 'CURVES':
        kind = "nothing" if obj is None else f"'{obj.name}' ({obj.type})"
        raise TypeError(f"expected a hair Curves object, got {kind}")
    if evaluated:
        depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
        obj = obj.evaluated_get(depsgraph)
    curves = obj.data
    point_count, curve_count = len(curves.points), len(curves.curves)
    if curve_count == 0:
        raise ValueError(f"'{obj.name}' has no curves")

    offsets = np.empty(curve_count + 1, np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    counts = np.diff(offsets)
    if counts.min() < 2:
        short = int(np.argmax(counts < 2))
        raise ValueError(f"'{obj.name}': curve {short} has {counts[short]} point(s); "
                         "hair strands need at least 2")

    points = np.empty((point_count, 3), np.float32)
    _position_data(curves).foreach_get("vector", points.ravel())
    radius_attribute = curves.attributes.get("radius")
    radius = None
    if radius_attribute is not None:
        radius = np.empty(point_count, np.float32)
        radius_attribute.data.foreach_get("value", radius)
    strands = Strands(points, offsets.astype(np.int64), radius)

    for attribute in curves.attributes:
        name = attribute.name
        domain = _DOMAIN_FROM_BLENDER.get(attribute.domain)
        # Names starting with "." are Blender's internal attributes (selection and the like).
        if (name in _BUILTIN_ATTRIBUTES or name.startswith(".") or domain is None
                or attribute.data_type not in _COMPONENTS_BY_TYPE):
            continue
        components, prop = _COMPONENTS_BY_TYPE[attribute.data_type]
        rows = point_count if domain == "point" else curve_count
        values = np.empty((rows, components) if components > 1 else rows, np.float32)
        attribute.data.foreach_get(prop, values.ravel())
        strands.set_attribute(name, values, domain)
    return strands


def evaluated_curve_subset(obj, curve_indices, depsgraph, expected_curves=None) -> Strands:
    """Strands of the curves ``curve_indices`` (in that order) of the hair Curves object ``obj`` as
    ``depsgraph`` evaluates it, positions only (radius 0): what following an animation reads each
    frame. Raises ValueError when the evaluated curves are not ``expected_curves`` many (the
    topology changed since the indices were taken) or an index is out of range."""
    curves = obj.evaluated_get(depsgraph).data
    curve_count = len(curves.curves)
    if expected_curves is not None and curve_count != expected_curves:
        raise ValueError(f"'{obj.name}' has {curve_count} curves now, {expected_curves} when the LoD was built")
    indices = np.asarray(curve_indices, dtype=np.int64)
    if indices.size and (indices.min() < 0 or indices.max() >= curve_count):
        raise ValueError(f"'{obj.name}' has {curve_count} curves, a curve index asks for {int(indices.max())}")
    # Only these curves are read, one foreach_get per curve slice: a loop over the few hundred guides,
    # not over strands or points. Reading every position instead (position_data.foreach_get, then a
    # gather) took 10-54 ms for 100k strands of 17 points on a Geometry Nodes output in Blender 3.4,
    # the slices of 256 guides 0.5 ms (the same values).
    slices = [curves.curves[int(index)] for index in indices]
    counts = np.fromiter((curve.points_length for curve in slices), np.int64, count=len(slices))
    offsets = np.zeros(len(slices) + 1, np.int64)
    np.cumsum(counts, out=offsets[1:])
    points = np.empty((int(offsets[-1]), 3), np.float32)
    for curve, start, end in zip(slices, offsets[:-1], offsets[1:]):
        curve.points.foreach_get("position", points[start:end].ravel())
    return Strands(points, offsets, None)


def strands_to_curves(strands: Strands, name, collection=None):
    """A new hair Curves object named ``name`` holding ``strands``, linked to ``collection``
    (the context's collection when None). Curves are Catmull-Rom; Strands attributes become
    Blender attributes (1-4 float components). Nothing is left behind when it fails.
    """
    collection = collection or bpy.context.collection
    curves = bpy.data.hair_curves.new(name)
    obj = bpy.data.objects.new(name, curves)
    try:
        collection.objects.link(obj)
        counts = np.diff(strands.offsets)
        if bpy.app.version >= (4, 0, 0):
            curves.add_curves(counts.tolist())
        else:
            _build_topology_with_geometry_nodes(obj, counts)
            curves = obj.data
        _position_data(curves).foreach_set("vector", strands.points.ravel())
        # A "radius" that does not exist yet silently drops foreach_set writes: create it first.
        radius = curves.attributes.get("radius") or curves.attributes.new("radius", 'FLOAT', 'POINT')
        radius.data.foreach_set("value", np.ascontiguousarray(strands.radius))
        for attribute_name in strands.attribute_names():
            _write_attribute(curves, attribute_name, strands)
        curves.update_tag()
    except BaseException:
        data = obj.data
        bpy.data.objects.remove(obj)
        bpy.data.hair_curves.remove(data)
        raise
    return obj


def rewrite_strand_data(obj, strands: Strands):
    """Overwrites positions, radius and attributes of a Curves object made by ``strands_to_curves``
    with those of ``strands``, which must have the same curve sizes and the same attribute names,
    types and domains (Blender's own attributes aside). Unlike building new curves, this works in any
    mode and is cheap. Returns False, changing nothing, when the layouts differ."""
    curves = obj.data
    if len(curves.curves) != len(strands) or len(curves.points) != strands.point_count:
        return False
    offsets = np.empty(len(curves.curves) + 1, np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    if not np.array_equal(offsets, strands.offsets) or "radius" not in curves.attributes:
        return False
    attributes = {name: _attribute_layout(strands, name) for name in strands.attribute_names()}
    existing = {attribute.name: (attribute.data_type, attribute.domain) for attribute in curves.attributes
                if attribute.name not in _BUILTIN_ATTRIBUTES and not attribute.name.startswith(".")}
    if existing != {name: (data_type, domain) for name, (data_type, domain, _, _) in attributes.items()}:
        return False
    _position_data(curves).foreach_set("vector", strands.points.ravel())
    curves.attributes["radius"].data.foreach_set("value", np.ascontiguousarray(strands.radius))
    for name, (_, _, prop, values) in attributes.items():
        curves.attributes[name].data.foreach_set(prop, values)
    curves.update_tag()
    return True


def replace_generated_curves(source, strands, name, collection):
    """Writes ``strands`` into a new Curves object named ``name`` placed like ``source``. An earlier
    Curves object of that name passes on its materials and collections and is deleted; without one
    the new object goes to ``collection``. Another kind of object of that name is left alone (the
    new one gets a numbered name)."""
    previous = bpy.data.objects.get(name)
    if previous is not None and previous.type != 'CURVES':
        previous = None
    if previous is not None and previous.users_collection:
        collection = previous.users_collection[0]
    obj = strands_to_curves(strands, name, collection)
    obj.matrix_world = source.matrix_world
    if previous is None:
        return obj
    for material in previous.data.materials:
        obj.data.materials.append(material)
    for other in previous.users_collection:
        if obj.name not in other.objects:
            other.objects.link(obj)
    name, data_name = previous.name, previous.data.name
    old_data = previous.data
    bpy.data.objects.remove(previous)
    if old_data.users == 0:
        bpy.data.hair_curves.remove(old_data)
    obj.name, obj.data.name = name, data_name
    return obj


def _attribute_layout(strands, name):
    """(Blender data type, domain, foreach property, flat float32 values) of a Strands attribute."""
    values = strands.attribute(name)
    components = values.shape[1] if values.ndim == 2 else 1
    if components not in _FLOAT_TYPES:
        raise ValueError(f"attribute '{name}' has {components} components; Blender takes 1 to 4")
    data_type, prop = _FLOAT_TYPES[components]
    domain = _DOMAIN_TO_BLENDER[strands.attribute_domain(name)]
    return data_type, domain, prop, np.ascontiguousarray(values, np.float32).ravel()


def _write_attribute(curves, name, strands):
    data_type, domain, prop, values = _attribute_layout(strands, name)
    if name in curves.attributes:
        raise ValueError(f"attribute '{name}' clashes with a Blender attribute of the same name")
    curves.attributes.new(name, data_type, domain).data.foreach_set(prop, values)


def new_geometry_node_tree(name):
    """A new Geometry Nodes tree with one geometry input and one geometry output, both named
    "Geometry" (Blender 4.0 moved them from ``inputs`` / ``outputs`` to ``interface``)."""
    tree = bpy.data.node_groups.new(name, 'GeometryNodeTree')
    if bpy.app.version >= (4, 0, 0):
        tree.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
        tree.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    else:
        tree.inputs.new('NodeSocketGeometry', "Geometry")
        tree.outputs.new('NodeSocketGeometry', "Geometry")
    return tree


_COUNT_ATTRIBUTE = "hairlod_point_count"


def _build_topology_with_geometry_nodes(obj, counts):
    """Gives the (empty) Curves of ``obj`` one curve per entry of ``counts`` (Blender < 4.0).

    These versions cannot resize Curves from Python, so Geometry Nodes build the topology: a
    temporary mesh of one isolated edge per curve, carrying the curve's point count, goes through
    "Mesh to Curve" (one 2-point curve per edge, in edge order) and "Resample Curve" with that
    count. The modifier's evaluated result is copied into the object: one evaluation, where
    bpy.ops.object.modifier_apply would evaluate the view layer twice more (and an edge chain per
    curve through Mesh to Curve alone costs about 10x more). The caller writes the positions.
    """
    curve_count = len(counts)
    mesh = bpy.data.meshes.new("hairlod_edges")
    mesh_obj = node_group = None
    try:
        mesh.vertices.add(2 * curve_count)
        mesh.edges.add(curve_count)
        mesh.edges.foreach_set("vertices", np.arange(2 * curve_count, dtype=np.int32))
        count_attribute = mesh.attributes.new(_COUNT_ATTRIBUTE, 'INT', 'POINT')
        count_attribute.data.foreach_set("value", np.repeat(counts, 2).astype(np.int32))
        mesh_obj = bpy.data.objects.new("hairlod_edges", mesh)
        node_group = _topology_node_group(mesh_obj)
        modifier = obj.modifiers.new("hairlod_topology", 'NODES')
        modifier.node_group = node_group
        depsgraph = bpy.context.evaluated_depsgraph_get()
        topology = obj.evaluated_get(depsgraph).data.copy()
        obj.modifiers.remove(modifier)
    finally:
        if mesh_obj is not None:
            bpy.data.objects.remove(mesh_obj)
        bpy.data.meshes.remove(mesh)
        if node_group is not None:
            bpy.data.node_groups.remove(node_group)

    empty = obj.data
    obj.data = topology
    bpy.data.hair_curves.remove(empty)
    topology.name = obj.name
    offsets = np.empty(len(topology.curves) + 1, np.int32)
    topology.curve_offset_data.foreach_get("value", offsets)
    if len(topology.curves) != curve_count or not np.array_equal(np.diff(offsets), counts):
        raise RuntimeError("Geometry Nodes built a different strand topology: "
                           f"{len(topology.curves)} curves / {len(topology.points)} points, "
                           f"expected {curve_count} / {int(counts.sum())}")
    # Without curve_type the curves are Catmull-Rom; the others are mesh leftovers or defaults.
    for leftover in (_COUNT_ATTRIBUTE, "curve_type", "cyclic", ".select_vert", ".select_edge"):
        attribute = topology.attributes.get(leftover)
        if attribute is not None:
            topology.attributes.remove(attribute)


def _topology_node_group(mesh_obj):
    """Object Info (the edge mesh) -> Mesh to Curve -> Resample Curve (count per curve)."""
    node_group = bpy.data.node_groups.new("hairlod_topology", 'GeometryNodeTree')
    node_group.outputs.new('NodeSocketGeometry', "Geometry")
    nodes, links = node_group.nodes, node_group.links
    object_info = nodes.new('GeometryNodeObjectInfo')
    object_info.inputs["Object"].default_value = mesh_obj
    mesh_to_curve = nodes.new('GeometryNodeMeshToCurve')
    resample = nodes.new('GeometryNodeResampleCurve')
    resample.mode = 'COUNT'
    point_count = nodes.new('GeometryNodeInputNamedAttribute')
    point_count.data_type = 'INT'
    point_count.inputs["Name"].default_value = _COUNT_ATTRIBUTE
    output = nodes.new('NodeGroupOutput')
    links.new(object_info.outputs["Geometry"], mesh_to_curve.inputs["Mesh"])
    links.new(mesh_to_curve.outputs["Curve"], resample.inputs["Curve"])
    # The node has one "Attribute" output per data type; only the INT one is enabled.
    links.new(next(socket for socket in point_count.outputs if socket.enabled), resample.inputs["Count"])
    links.new(resample.outputs["Curve"], output.inputs["Geometry"])
    return node_group
