"""Build Hair LoD (hairlod.build_lod) on a hair Curves object, headless."""

import math

import bpy
import numpy as np
import pytest

from hairlod import Strands
from hairlod.blender.curves import curves_to_strands, strands_to_curves
from hairlod.blender.lod_operator import COLLECTION_NAME

pytestmark = pytest.mark.usefixtures("addon")


def hanging_hair(curves=600, points=8, seed=3):
    rng = np.random.default_rng(seed)
    azimuth, polar = rng.uniform(0, 2 * math.pi, curves), rng.uniform(0, 1.4, curves)
    roots = np.stack([np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)], axis=1)
    t = np.linspace(0, 1, points)
    positions = roots[:, None, :] * (1 + 0.2 * t[None, :, None]) - np.array([0, 0, 1.0]) * t[None, :, None]
    return Strands.from_counts(positions.astype(np.float32).reshape(-1, 3), np.full(curves, points),
                               np.full(curves * points, 0.002, np.float32))


@pytest.fixture
def hair_object():
    obj = strands_to_curves(hanging_hair(), "Hair")
    bpy.context.view_layer.objects.active = obj
    yield obj
    collection = bpy.data.collections.get(COLLECTION_NAME)
    if collection is not None:
        for child in list(collection.objects):
            bpy.data.objects.remove(child)
        bpy.data.collections.remove(collection)
    bpy.data.objects.remove(obj)


def test_build_lod_creates_one_curves_object_per_level(hair_object):
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    collection = bpy.data.collections[COLLECTION_NAME]
    objects = sorted(collection.objects, key=lambda o: o.name)
    assert [o.name for o in objects] == [f"Hair LoD L{level}" for level in range(len(objects))]
    assert 1 <= len(objects) <= 3
    for level, obj in enumerate(objects):
        strands = curves_to_strands(obj)
        attributes = set(strands.attribute_names())
        assert {"major_radius", "minor_radius", "major_axis", "minor_axis", "n_total", "density", "cluster",
                "level"} <= attributes
        assert strands.attribute("n_total").sum() == 600
        assert np.all(strands.attribute("level") == level)
        assert np.allclose(strands.radius, strands.attribute("major_radius"))
        assert np.all(strands.attribute("major_radius") >= strands.attribute("minor_radius"))
        assert np.all(np.diff(strands.offsets) == 6)


def test_build_lod_needs_hair_curves():
    bpy.ops.object.select_all(action='DESELECT')
    bpy.context.view_layer.objects.active = None
    assert not bpy.ops.hairlod.build_lod.poll()
    with pytest.raises(RuntimeError):
        bpy.ops.hairlod.build_lod()


def test_failed_build_leaves_nothing_behind(hair_object):
    hair_object.data.attributes["position"].data.foreach_set("vector", np.full(600 * 8 * 3, np.nan, np.float32))
    objects_before = len(bpy.data.objects)
    with pytest.raises(RuntimeError, match="Cannot build"):
        bpy.ops.hairlod.build_lod(guides=4, levels=3, control_points=4)
    assert len(bpy.data.objects) == objects_before
    assert COLLECTION_NAME not in bpy.data.collections
