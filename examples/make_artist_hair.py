"""Makes a hairstyle the way artists make one in Blender: guide curves on a head, children by Geometry Nodes.

    blender -b --factory-startup --python examples/make_artist_hair.py -- --out FILE.hair
        [--children 60000] [--guides 300] [--seed 0] [--blend FILE.blend]

In a fresh scene it builds a head (a UV sphere of radius about 0.1 m, slightly elongated, whose
upper-back faces carry a boolean face attribute "scalp"), a hair Curves object of guide curves
rooted on the scalp (spread by farthest-point sampling, grown along the normal, combed back and
down under gravity, kept out of the head, with a per-guide wave) and a Geometry Nodes modifier on
it that interpolates the children: roots distributed on the scalp faces, each child blending the
shapes of three nearby guides by inverse distance, clumping towards the nearest guide at the tips,
spreading by a per-child random offset and pushed out of the head. The evaluated children go
through the project's bridge (hairlod.blender.curves.curves_to_strands) into a .hair file. Prints
one line: strands, points, seconds. The functions are importable (tests/blender/test_artist_hair.py).
"""

import argparse
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "addon"))

from hairlod import Strands, io  # noqa: E402
from hairlod.blender.curves import curves_to_strands, new_geometry_node_tree, strands_to_curves  # noqa: E402

# Semi-axes of the head (x: ear to ear, y: back of the head, the face looks along -y, z: up), metres.
HEAD_AXES = np.array([0.09, 0.1, 0.11])
HEAD_SEGMENTS, HEAD_RINGS = 64, 32
SCALP_ATTRIBUTE = "scalp"
GUIDE_POINTS = 20
GUIDE_LENGTH = (0.15, 0.3)
HAIR_RADIUS = 3e-5
# Hair keeps this much clear of the head, as a fraction of the head's size (about 2 mm).
CLEARANCE = 1.02
# How strongly guides are pulled onto the head where they rest on it (0: not at all).
HUG = 0.6
# Children: shortest length as a fraction of the blended guides', tip pull towards the nearest
# guide (0 none, 1 onto it), per-child random tip offset (metres) and the inverse-distance
# softening length (metres) that keeps the weights finite at a guide's root.
CHILD_MIN_LENGTH = 0.8
CHILD_CLUMP = 0.45
CHILD_SPREAD = 0.008
WEIGHT_SOFTENING = 0.002
# Children interpolate between this many guides: the nearest of each residue class of the guide index.
NEIGHBOURS = 3


def on_scalp(direction):
    """Whether unit directions from the head's centre ([..., 3]) point at the scalp: above a
    hairline that runs from the forehead over the ears down to the nape."""
    return direction[..., 2] > 0.05 - 0.45 * direction[..., 1]


def uv_sphere(segments, rings):
    """Unit UV sphere: vertices [V, 3] and faces (pole triangles, quads), wound outwards, in a
    fixed order (bmesh.ops.create_uvsphere orders its faces differently from run to run)."""
    theta = np.pi * np.arange(1, rings)[:, None] / rings
    phi = 2.0 * np.pi * np.arange(segments)[None, :] / segments
    ring_vertices = np.stack(np.broadcast_arrays(np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi),
                                                 np.cos(theta)), axis=-1).reshape(-1, 3)
    vertices = np.concatenate([[[0.0, 0.0, 1.0]], ring_vertices, [[0.0, 0.0, -1.0]]])
    bottom = len(vertices) - 1

    def ring(r, s):
        return 1 + (r - 1) * segments + s % segments

    faces = [(0, ring(1, s), ring(1, s + 1)) for s in range(segments)]
    faces += [(ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1))
              for r in range(1, rings - 1) for s in range(segments)]
    faces += [(ring(rings - 1, s), bottom, ring(rings - 1, s + 1)) for s in range(segments)]
    return vertices, faces


def build_head(name="Head"):
    """A UV sphere scaled to HEAD_AXES, with the boolean face attribute SCALP_ATTRIBUTE."""
    vertices, faces = uv_sphere(HEAD_SEGMENTS, HEAD_RINGS)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata((vertices * HEAD_AXES).tolist(), [], faces)
    centres = np.empty(len(mesh.polygons) * 3)
    mesh.polygons.foreach_get("center", centres)
    directions = centres.reshape(-1, 3) / HEAD_AXES
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    scalp = mesh.attributes.new(SCALP_ATTRIBUTE, 'BOOLEAN', 'FACE')
    scalp.data.foreach_set("value", on_scalp(directions))
    head = bpy.data.objects.new(name, mesh)
    bpy.context.collection.objects.link(head)
    return head


def scalp_triangles(mesh):
    """Corners ([T, 3, 3]) of the mesh's triangles that belong to scalp faces."""
    mesh.calc_loop_triangles()
    corners = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("vertices", corners)
    faces = np.empty(len(mesh.loop_triangles), np.int32)
    mesh.loop_triangles.foreach_get("polygon_index", faces)
    scalp = np.empty(len(mesh.polygons), bool)
    mesh.attributes[SCALP_ATTRIBUTE].data.foreach_get("value", scalp)
    vertices = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", vertices)
    return vertices.reshape(-1, 3)[corners.reshape(-1, 3)[scalp[faces]]]


def scalp_area(mesh):
    triangles = scalp_triangles(mesh)
    return 0.5 * np.linalg.norm(np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]),
                                axis=1).sum()


def guide_roots(mesh, count, rng):
    """``count`` points on the scalp faces, spread out: farthest-point sampling of area-weighted
    random candidates."""
    triangles = scalp_triangles(mesh)
    areas = np.linalg.norm(np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]), axis=1)
    candidate_count = 8 * count
    picked = rng.choice(len(triangles), candidate_count, p=areas / areas.sum())
    u, v = rng.random((2, candidate_count, 1))
    flip = (u + v) > 1.0
    u, v = np.where(flip, 1.0 - u, u), np.where(flip, 1.0 - v, v)
    corners = triangles[picked]
    candidates = corners[:, 0] + u * (corners[:, 1] - corners[:, 0]) + v * (corners[:, 2] - corners[:, 0])
    chosen = [0]
    distance = np.linalg.norm(candidates - candidates[0], axis=1)
    for _ in range(count - 1):
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(candidates - candidates[chosen[-1]], axis=1))
    return candidates[chosen]


def push_out_of_head(points):
    """Points moved radially (in the head's normalised space) to at least CLEARANCE."""
    reach = np.linalg.norm(points / HEAD_AXES, axis=-1, keepdims=True)
    return points * np.maximum(1.0, CLEARANCE / reach)


def groom_guides(head, count, seed):
    """Guide strands ([count] curves of GUIDE_POINTS points) groomed on the head's scalp.

    Each guide lifts off the scalp a little along the head's normal and is combed back along the
    scalp (away from the face, parted outwards at the sides); further out gravity takes over, so
    it falls down the back and the sides, sliding over the head where it would go inside. Per
    guide: length, lift, how soon gravity wins, a random tilt of the comb and a wave across the
    strand that grows towards the tip.
    """
    rng = np.random.default_rng(seed)
    roots = guide_roots(head.data, count, rng)
    normals = roots / HEAD_AXES**2
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    step = rng.uniform(*GUIDE_LENGTH, (count, 1)) / (GUIDE_POINTS - 1)
    comb = np.array([0.0, 1.0, -0.6]) + 0.5 * roots / HEAD_AXES * [1.0, 0.0, 0.0]
    comb += 0.25 * rng.normal(size=(count, 3))
    comb -= np.sum(comb * normals, axis=1, keepdims=True) * normals
    comb /= np.linalg.norm(comb, axis=1, keepdims=True)
    gravity = np.array([0.0, 0.15, -1.0]) / np.hypot(0.15, 1.0)
    lift = rng.uniform(0.2, 0.5, (count, 1))
    fall = rng.uniform(0.5, 0.9, (count, 1))
    points = [roots]
    for segment in range(GUIDE_POINTS - 1):
        t = segment / (GUIDE_POINTS - 2)
        direction = (1.0 - t**fall) * comb + t**fall * gravity + lift * (1.0 - t) * normals
        # Above the head's widest part hair rests on it: a pull towards the head's surface.
        here = points[-1]
        inwards = here / HEAD_AXES**2
        inwards /= -np.linalg.norm(inwards, axis=1, keepdims=True)
        resting = np.clip((here[:, 2:] / HEAD_AXES[2] + 0.1) / 0.4, 0.0, 1.0)
        direction += HUG * min(1.0, 4.0 * t) * resting * inwards
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        points.append(push_out_of_head(points[-1] + step * direction))
    points = np.stack(points, axis=1)

    t = np.linspace(0.0, 1.0, GUIDE_POINTS)[None, :, None]
    across = np.cross(comb, normals)
    across /= np.linalg.norm(across, axis=1, keepdims=True)
    amplitude = rng.uniform(0.002, 0.008, (count, 1, 1))
    waves = rng.uniform(1.0, 3.0, (count, 1, 1))
    phase = rng.uniform(0.0, 2.0 * np.pi, (count, 1, 1))
    points = points + across[:, None, :] * amplitude * t * np.sin(2.0 * np.pi * waves * t + phase)
    points[:, 1:] = push_out_of_head(points[:, 1:])

    radius = np.tile(HAIR_RADIUS * (1.0 - 0.5 * t.ravel()), count).astype(np.float32)
    return Strands.from_counts(points.reshape(-1, 3).astype(np.float32), np.full(count, GUIDE_POINTS), radius)


class _NodeGraph:
    """Adds nodes to a Geometry Nodes tree; inputs are sockets (linked) or constants (set)."""

    def __init__(self, tree):
        self.tree = tree

    def node(self, kind, inputs=(), **properties):
        node = self.tree.nodes.new(kind)
        for name, value in properties.items():
            setattr(node, name, value)
        for key, value in inputs:
            # Nodes of Blender 3.x keep one socket per data type under one name; the enabled one counts.
            socket = node.inputs[key] if isinstance(key, int) else _enabled(node.inputs, key)
            if isinstance(value, bpy.types.NodeSocket):
                self.tree.links.new(value, socket)
            else:
                socket.default_value = value
        return node

    def output(self, node, name):
        return _enabled(node.outputs, name)

    def math(self, operation, *values):
        return self.node('ShaderNodeMath', enumerate(values), operation=operation).outputs[0]

    def vector_math(self, operation, *values):
        node = self.node('ShaderNodeVectorMath', enumerate(values), operation=operation)
        return node.outputs["Value" if operation in ('LENGTH', 'DOT_PRODUCT', 'DISTANCE') else "Vector"]

    def scale(self, vector, factor):
        return self.node('ShaderNodeVectorMath', [(0, vector), (3, factor)], operation='SCALE').outputs["Vector"]

    def sample(self, geometry, value, index, data_type='FLOAT_VECTOR'):
        """Sample Index: ``value`` (a field on the points of ``geometry``) at point ``index``."""
        node = self.node('GeometryNodeSampleIndex', [("Geometry", geometry), ("Value", value), ("Index", index)],
                         data_type=data_type, domain='POINT')
        return self.output(node, "Value")

    def random(self, data_type, low, high, identifier, seed):
        node = self.node('FunctionNodeRandomValue', [("Min", low), ("Max", high), ("ID", identifier), ("Seed", seed)],
                         data_type=data_type)
        return self.output(node, "Value")


def _enabled(sockets, name):
    return next(socket for socket in sockets if socket.name == name and socket.enabled)


def children_node_tree(head, children, seed):
    """The Geometry Nodes tree that turns guide curves (its input, all of one point count P) into
    ``children`` child curves of P points on the scalp of ``head``; the guides are not output.

    Child roots: Distribute Points on Faces over the head's scalp faces (a few more than needed),
    thinned to exactly ``children`` by keeping every (M / children)-th point in index order (the
    points come face by face, so this keeps the same share of every face). Per child: the nearest
    guide root of each residue class of the guide index modulo NEIGHBOURS (Sample Nearest on
    Points made from the guide roots), weights 1 / (d^2 + s^2). Per child point j: child root +
    length factor * sum of weight * (guide point j - guide root), pulled towards the nearest
    guide by CHILD_CLUMP * t and offset by a per-child random vector * CHILD_SPREAD * t (t = j /
    (P - 1)), then moved out of the head; radius from the guides. Curves are Catmull-Rom.
    """
    graph = _NodeGraph(new_geometry_node_tree("ArtistHairChildren"))
    nodes = graph.tree.nodes
    guides = nodes.new('NodeGroupInput').outputs["Geometry"]
    position = nodes.new('GeometryNodeInputPosition').outputs[0]
    index = nodes.new('GeometryNodeInputIndex').outputs[0]

    guide_sizes = graph.node('GeometryNodeAttributeDomainSize', [("Geometry", guides)], component='CURVE')
    guide_count = graph.output(guide_sizes, "Spline Count")
    points_per_curve = graph.math('DIVIDE', graph.output(guide_sizes, "Point Count"), guide_count)
    root_positions = graph.node('GeometryNodePoints', [
        ("Count", guide_count),
        ("Position", graph.sample(guides, position, graph.math('MULTIPLY', index, points_per_curve)))]).outputs[0]
    residue_classes = []
    for residue in range(NEIGHBOURS):
        other_class = graph.math('GREATER_THAN', graph.math('ABSOLUTE', graph.math(
            'SUBTRACT', graph.math('MODULO', index, NEIGHBOURS), residue)), 0.5)
        residue_classes.append(graph.node('GeometryNodeDeleteGeometry', [("Geometry", root_positions),
                                                                         ("Selection", other_class)],
                                          domain='POINT').outputs[0])

    head_geometry = graph.node('GeometryNodeObjectInfo', [("Object", head)]).outputs["Geometry"]
    scalp = graph.output(graph.node('GeometryNodeInputNamedAttribute', [("Name", SCALP_ATTRIBUTE)],
                                    data_type='BOOLEAN'), "Attribute")
    density = (1.25 * children + 64) / scalp_area(head.data)
    candidates = graph.node('GeometryNodeDistributePointsOnFaces', [
        ("Mesh", head_geometry), ("Selection", scalp), ("Density", density), ("Seed", seed)]).outputs["Points"]
    candidate_count = graph.output(graph.node('GeometryNodeAttributeDomainSize', [("Geometry", candidates)],
                                              component='POINTCLOUD'), "Point Count")
    # floor((i + 1) r) - floor(i r) is 1 for exactly floor(M r) = children of the M points.
    ratio = graph.math('DIVIDE', children + 0.5, candidate_count)
    kept = graph.math('SUBTRACT', graph.math('FLOOR', graph.math('MULTIPLY', graph.math('ADD', index, 1.0), ratio)),
                      graph.math('FLOOR', graph.math('MULTIPLY', index, ratio)))
    child_roots = graph.node('GeometryNodeDeleteGeometry', [("Geometry", candidates),
                                                           ("Selection", graph.math('LESS_THAN', kept, 0.5))],
                             domain='POINT').outputs[0]

    # Fields on the child roots: neighbour guide indices, their weights, the clump offset.
    neighbours, weights, neighbour_roots = [], [], []
    for residue, residue_class in enumerate(residue_classes):
        nearest = graph.node('GeometryNodeSampleNearest', [("Geometry", residue_class),
                                                          ("Sample Position", position)]).outputs["Index"]
        guide = graph.math('MULTIPLY_ADD', nearest, NEIGHBOURS, residue)
        guide_root = graph.sample(root_positions, position, guide)
        distance = graph.vector_math('DISTANCE', position, guide_root)
        weights.append(graph.math('DIVIDE', 1.0, graph.math('MULTIPLY_ADD', distance, distance,
                                                            WEIGHT_SOFTENING ** 2)))
        neighbours.append(guide)
        neighbour_roots.append(guide_root)
    weight_vector = graph.node('ShaderNodeCombineXYZ', enumerate(weights)).outputs[0]
    normalised = graph.scale(weight_vector, graph.math('DIVIDE', 1.0, graph.vector_math(
        'DOT_PRODUCT', weight_vector, (1.0, 1.0, 1.0))))
    # The nearest guide's root, as weights ^ 4 (inverse distance ^ 8) select it.
    sharp = graph.vector_math('MULTIPLY', graph.vector_math('MULTIPLY', weight_vector, weight_vector),
                              graph.vector_math('MULTIPLY', weight_vector, weight_vector))
    sharp = graph.scale(sharp, graph.math('DIVIDE', 1.0, graph.vector_math('DOT_PRODUCT', sharp, (1.0, 1.0, 1.0))))
    sharp_parts = graph.node('ShaderNodeSeparateXYZ', [(0, sharp)]).outputs
    nearest_root = graph.scale(neighbour_roots[0], sharp_parts[0])
    for part, root in zip(sharp_parts[1:], neighbour_roots[1:]):
        nearest_root = graph.vector_math('ADD', nearest_root, graph.scale(root, part))
    clump_offset = graph.vector_math('SUBTRACT', nearest_root, position)
    neighbour_vector = graph.node('ShaderNodeCombineXYZ', enumerate(neighbours)).outputs[0]

    # The children: one curve of P points per child root, realised.
    template = graph.node('GeometryNodeResampleCurve', [
        ("Curve", graph.node('GeometryNodeCurvePrimitiveLine').outputs[0]),
        ("Count", points_per_curve)]).outputs[0]
    instances = graph.node('GeometryNodeInstanceOnPoints', [("Points", child_roots), ("Instance", template)])
    curves = graph.node('GeometryNodeRealizeInstances', [("Geometry", instances.outputs[0])]).outputs[0]

    # Fields on the child points: child c = floor(i / P), point j = i - c P of it.
    child = graph.math('FLOOR', graph.math('DIVIDE', index, points_per_curve))
    point = graph.math('SUBTRACT', index, graph.math('MULTIPLY', child, points_per_curve))
    t = graph.math('DIVIDE', point, graph.math('SUBTRACT', points_per_curve, 1.0))
    child_root = graph.sample(child_roots, position, child)
    child_weights, child_guides = (
        graph.node('ShaderNodeSeparateXYZ', [(0, graph.sample(child_roots, per_child, child))]).outputs
        for per_child in (normalised, neighbour_vector))
    shape = None
    for guide, weight in zip(child_guides, child_weights):
        first = graph.math('MULTIPLY', guide, points_per_curve)
        relative = graph.vector_math('SUBTRACT', graph.sample(guides, position, graph.math('ADD', first, point)),
                                     graph.sample(guides, position, first))
        term = graph.scale(relative, weight)
        shape = term if shape is None else graph.vector_math('ADD', shape, term)
    length_factor = graph.random('FLOAT', CHILD_MIN_LENGTH, 1.0, child, seed)
    spread = graph.random('FLOAT_VECTOR', (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0), child, seed + 1)
    offset = graph.vector_math('ADD', graph.scale(graph.sample(child_roots, clump_offset, child),
                                                  graph.math('MULTIPLY', t, CHILD_CLUMP)),
                               graph.scale(spread, graph.math('MULTIPLY', t, CHILD_SPREAD)))
    placed = graph.vector_math('ADD', graph.vector_math('ADD', child_root, graph.scale(shape, length_factor)), offset)
    curves = graph.node('GeometryNodeSetPosition', [("Geometry", curves), ("Position", placed)]).outputs[0]

    # Out of the head: scale radially to CLEARANCE where the normalised reach is less (not the roots).
    reach = graph.vector_math('LENGTH', graph.vector_math('DIVIDE', position, tuple(HEAD_AXES)))
    pushed = graph.scale(position, graph.math('MAXIMUM', graph.math('DIVIDE', CLEARANCE, reach), 1.0))
    curves = graph.node('GeometryNodeSetPosition', [("Geometry", curves), ("Selection", graph.math(
        'GREATER_THAN', point, 0.5)), ("Position", pushed)]).outputs[0]

    radius_attribute = graph.output(graph.node('GeometryNodeInputNamedAttribute', [("Name", "radius")],
                                               data_type='FLOAT'), "Attribute")
    radius = graph.sample(guides, radius_attribute, graph.math('MULTIPLY_ADD', child_guides[0], points_per_curve,
                                                               point), data_type='FLOAT')
    curves = graph.node('GeometryNodeSetCurveRadius', [("Curve", curves), ("Radius", radius)]).outputs[0]
    curves = graph.node('GeometryNodeCurveSplineType', [("Curve", curves)], spline_type='CATMULL_ROM').outputs[0]
    graph.tree.links.new(curves, nodes.new('NodeGroupOutput').inputs["Geometry"])
    return graph.tree


def make_artist_hair(children=60000, guides=300, seed=0):
    """Head and hair objects in the current scene: (head, hair), the hair's evaluated data being
    the children."""
    head = build_head()
    hair = strands_to_curves(groom_guides(head, guides, seed), "ArtistHair")
    hair.data.surface = head
    modifier = hair.modifiers.new("Children", 'NODES')
    modifier.node_group = children_node_tree(head, children, seed)
    return head, hair


def generate(children=60000, guides=300, seed=0):
    """Replaces the scene by an empty one holding the head and the hair: (head, hair, children),
    the children being the hair's evaluated curves read through the bridge."""
    bpy.ops.wm.read_homefile(use_empty=True)
    head, hair = make_artist_hair(children, guides, seed)
    strands = curves_to_strands(hair, evaluated=True)
    if len(strands) != children:
        raise RuntimeError(f"Geometry Nodes made {len(strands)} children, expected {children} "
                           "(the scalp distribution gave too few candidate roots)")
    return head, hair, strands


def parse_args():
    parser = argparse.ArgumentParser(prog="make_artist_hair.py")
    parser.add_argument("--out", required=True, help="hair file to write (.hair)")
    parser.add_argument("--children", type=int, default=60000)
    parser.add_argument("--guides", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--blend", help="also save the scene to this .blend")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    if args.children < 1 or args.guides < NEIGHBOURS:
        parser.error(f"--children must be at least 1 and --guides at least {NEIGHBOURS}")
    return args


def main():
    args = parse_args()
    start = time.perf_counter()
    _, _, strands = generate(args.children, args.guides, args.seed)
    io.write(args.out, strands)
    if args.blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.blend))
    print(f"{args.out}: {len(strands)} strands, {strands.point_count} points, "
          f"{time.perf_counter() - start:.2f} s")


if __name__ == "__main__":
    main()
