"""Strands <-> Blender hair Curves (hairlod.blender.curves)."""

import bpy
import numpy as np
import pytest

from hairlod import Strands
from hairlod.blender.curves import curves_to_strands, new_geometry_node_tree, strands_to_curves


def random_strands(curve_count=200, seed=7):
    rng = np.random.default_rng(seed)
    counts = rng.integers(2, 20, curve_count)
    point_count = int(counts.sum())
    strands = Strands.from_counts((rng.random((point_count, 3), dtype=np.float32) - 0.5) * 10, counts,
                                  rng.random(point_count, dtype=np.float32) * 0.01)
    strands.set_attribute("weight", rng.random(point_count, dtype=np.float32))
    strands.set_attribute("uv", rng.random((point_count, 2), dtype=np.float32))
    strands.set_attribute("rest", rng.random((point_count, 3), dtype=np.float32))
    strands.set_attribute("tint", rng.random((curve_count, 4), dtype=np.float32), domain="curve")
    strands.set_attribute("cluster", rng.random(curve_count, dtype=np.float32), domain="curve")
    return strands


def assert_same_strands(actual, expected):
    np.testing.assert_array_equal(actual.offsets, expected.offsets)
    np.testing.assert_array_equal(actual.points, expected.points)
    np.testing.assert_array_equal(actual.radius, expected.radius)
    assert sorted(actual.attribute_names()) == sorted(expected.attribute_names())
    for name in expected.attribute_names():
        assert actual.attribute_domain(name) == expected.attribute_domain(name), name
        np.testing.assert_array_equal(actual.attribute(name), expected.attribute(name), err_msg=name)


def datablock_counts():
    return {kind: len(getattr(bpy.data, kind))
            for kind in ("objects", "meshes", "node_groups", "hair_curves", "collections")}


def add_nodes_modifier(obj, build):
    """A Geometry Nodes modifier whose tree is input -> build(tree, geometry socket) -> output."""
    tree = new_geometry_node_tree("test_nodes")
    group_input = tree.nodes.new('NodeGroupInput')
    group_output = tree.nodes.new('NodeGroupOutput')
    tree.links.new(build(tree, group_input.outputs["Geometry"]), group_output.inputs["Geometry"])
    obj.modifiers.new("test_nodes", 'NODES').node_group = tree


def test_round_trip_is_exact(empty_scene):
    strands = random_strands()
    obj = strands_to_curves(strands, "round_trip")
    assert obj.type == 'CURVES' and obj.name == "round_trip" and obj.data.name == "round_trip"
    assert len(obj.data.curves) == len(strands) and len(obj.data.points) == strands.point_count
    assert_same_strands(curves_to_strands(obj, evaluated=False), strands)
    assert_same_strands(curves_to_strands(obj), strands)


def test_new_curves_are_catmull_rom_and_typed_like_the_attributes(empty_scene):
    obj = strands_to_curves(random_strands(20), "types")
    attributes = obj.data.attributes
    assert "curve_type" not in attributes  # absent means Catmull-Rom
    assert not [a.name for a in attributes if a.name.startswith(".")]
    found = {a.name: (a.domain, a.data_type) for a in attributes}
    assert found["radius"] == ('POINT', 'FLOAT')
    assert found["weight"] == ('POINT', 'FLOAT')
    assert found["uv"] == ('POINT', 'FLOAT2')
    assert found["rest"] == ('POINT', 'FLOAT_VECTOR')
    assert found["tint"] == ('CURVE', 'FLOAT_COLOR')
    assert found["cluster"] == ('CURVE', 'FLOAT')


def test_order_is_kept_at_scale(empty_scene):
    rng = np.random.default_rng(3)
    counts = rng.integers(2, 40, 20_000)
    point_count = int(counts.sum())
    strands = Strands.from_counts(rng.random((point_count, 3), dtype=np.float32), counts,
                                  rng.random(point_count, dtype=np.float32))
    assert_same_strands(curves_to_strands(strands_to_curves(strands, "large"), evaluated=False), strands)


def test_temporary_datablocks_are_removed(empty_scene):
    before = datablock_counts()
    strands_to_curves(random_strands(50), "clean")
    after = datablock_counts()
    assert after == {**before, "objects": before["objects"] + 1, "hair_curves": before["hair_curves"] + 1}


def test_links_to_given_or_active_collection(empty_scene):
    target = bpy.data.collections.new("target")
    empty_scene.collection.children.link(target)
    given = strands_to_curves(random_strands(5), "given", target)
    assert [c.name for c in given.users_collection] == ["target"]
    active = strands_to_curves(random_strands(5), "active")
    assert list(active.users_collection) == [bpy.context.collection]


def test_reads_evaluated_geometry_nodes_output(empty_scene):
    strands = random_strands(30)
    obj = strands_to_curves(strands, "evaluated")

    def resample_and_lift(tree, geometry):
        resample = tree.nodes.new('GeometryNodeResampleCurve')
        resample.inputs["Count"].default_value = 4
        lift = tree.nodes.new('GeometryNodeSetPosition')
        lift.inputs["Offset"].default_value = (0.0, 0.0, 1.0)
        tree.links.new(geometry, resample.inputs["Curve"])
        tree.links.new(resample.outputs["Curve"], lift.inputs["Geometry"])
        return lift.outputs["Geometry"]

    add_nodes_modifier(obj, resample_and_lift)
    evaluated = curves_to_strands(obj)
    assert len(evaluated) == len(strands)
    np.testing.assert_array_equal(np.diff(evaluated.offsets), 4)
    # Resampling keeps the end points; Set Position lifts them by 1 in z.
    first_points = strands.points[strands.offsets[:-1]]
    np.testing.assert_allclose(evaluated.points[evaluated.offsets[:-1]], first_points + [0, 0, 1], atol=1e-5)
    assert "weight" in evaluated.attribute_names()
    assert_same_strands(curves_to_strands(obj, evaluated=False), strands)

    # An explicit depsgraph gives the same result.
    explicit = curves_to_strands(obj, depsgraph=bpy.context.evaluated_depsgraph_get())
    np.testing.assert_array_equal(explicit.points, evaluated.points)


def test_missing_radius_reads_as_blender_default(empty_scene):
    obj = strands_to_curves(random_strands(10), "no_radius")
    obj.data.attributes.remove(obj.data.attributes["radius"])
    strands = curves_to_strands(obj, evaluated=False)
    np.testing.assert_array_equal(strands.radius, 0.0)


def test_rejects_objects_that_are_not_hair_curves(empty_scene):
    mesh_obj = bpy.data.objects.new("Mesh Object", bpy.data.meshes.new("mesh"))
    with pytest.raises(TypeError, match="'Mesh Object' \\(MESH\\)"):
        curves_to_strands(mesh_obj)
    with pytest.raises(TypeError, match="nothing"):
        curves_to_strands(None)


def test_rejects_curves_with_fewer_than_two_points(empty_scene):
    obj = strands_to_curves(random_strands(10), "short")
    def resample_to_one(tree, geometry):
        resample = tree.nodes.new('GeometryNodeResampleCurve')
        resample.inputs["Count"].default_value = 1
        tree.links.new(geometry, resample.inputs["Curve"])
        return resample.outputs["Curve"]
    add_nodes_modifier(obj, resample_to_one)
    with pytest.raises(ValueError, match="curve 0 has 1 point"):
        curves_to_strands(obj)


def test_rejects_empty_curves(empty_scene):
    obj = bpy.data.objects.new("empty", bpy.data.hair_curves.new("empty"))
    empty_scene.collection.objects.link(obj)
    with pytest.raises(ValueError, match="no curves"):
        curves_to_strands(obj)


@pytest.mark.parametrize("name, components, message", [
    ("too_wide", 5, "'too_wide' has 5 components"),
    ("radius", 1, "'radius' clashes"),
])
def test_failed_conversion_leaves_nothing_behind(empty_scene, name, components, message):
    strands = random_strands(10)
    shape = (strands.point_count, components) if components > 1 else strands.point_count
    strands.set_attribute(name, np.zeros(shape, np.float32))
    before = datablock_counts()
    with pytest.raises(ValueError, match=message):
        strands_to_curves(strands, "failed")
    assert datablock_counts() == before


def test_rewrite_keeps_the_object_and_needs_the_same_sizes(empty_scene):
    from hairlod.blender.curves import rewrite_strand_data

    original = random_strands(50, seed=1)
    obj = strands_to_curves(original, "rewritten")
    moved = random_strands(50, seed=1)
    moved = Strands(moved.points + 1, moved.offsets, moved.radius * 2)
    for name in original.attribute_names():
        moved.set_attribute(name, original.attribute(name) * 3, original.attribute_domain(name))
    assert rewrite_strand_data(obj, moved)
    assert_same_strands(curves_to_strands(obj, evaluated=False), moved)

    assert not rewrite_strand_data(obj, random_strands(50, seed=2))  # other curve sizes
    assert not rewrite_strand_data(obj, Strands(moved.points, moved.offsets, moved.radius))  # fewer attributes
    assert_same_strands(curves_to_strands(obj, evaluated=False), moved)
